"""The filters on ParaView's MPI engine: `mpiexec -np N pvserver` on a free loopback port.

DDG Volume Render, DDG Query, DDG Design Gallery and DDG Reconstruct Transfer Function (with Match
Picture too) work on pieces: every rank reads and renders its own piece of the volume (one ghost
level); the render's images are composited sort-last on the first rank; the query and the
gallery run on the first rank (the bundle checked against the whole's fingerprint, streamed to
it slab by slab) and their design renders are composited like the render's; the reconstruction
composites every step's rays on every rank and sums the ranks' TF gradients (DDGPieces.h); the
match runs in step on every rank (Core's match over pieces). DDG Build Design Space (in the
pipeline and in the background, StartBuild) streams every rank's piece (no ghost level) to the
first rank slab by slab, which assembles the design-space volume (downsampled: DesignVoxels
2^18) and the whole's fingerprint; every rank then gets that volume and the other ranks render
shares of the exemplar candidates over their TCP links to the first, which trains alone. What is compared with what: the
client fetches (servermanager.Fetch, which keeps the first rank's output) the outputs of DDG
Volume Render (1D; Shade with specular; a 2D TF), DDG Query (shipped Tooth bundle and screenshot)
and DDG Reconstruct Transfer Function (1D, 20 iterations; 2D, 10 iterations) from the server,
then computes the same in a builtin session:
- build (16 exemplars of 16 px, 10 iterations, 20 outline designs): the bundle records the
  whole's fingerprint (the shipped Tooth bundle's), the training exemplars' designs are the same
  text as the builtin's (the same design volume: its feature regions and the screen's verdicts;
  the other ranks rendered some of them: OtherRanksCandidates > 0, 0 in the builtin session),
  the held-out figures within BUILD_TOL (0.5 dB, 0.02 SSIM); the reader's points after it are the
  pieces' without ghosts: no rank read the whole volume;
- render: the same arrays, values within RENDER_TOL (1/255 + 1e-6 on the premultiplied RGBA, 1
  level on the 8-bit image; 2/255 and 2 levels for the lit 2D TF, whose lit colour is not
  clamped): each piece stops its rays at ParaView's opacity threshold (1 - 1/255) on its own,
  and compositing adds in another order;
- the reader's points over the ranks after the renders are the pieces' (the volume split as
  vtkExtentTranslator splits it, one ghost level): no rank read the whole volume;
- query and gallery (9 thumbnails): the preview and the sheet within RENDER_TOL (renders over
  pieces, as above), the designs tables identical (rows, latent, outline position, the Preset
  string) but for the picture's figure (PicturePSNR, from the preview: within 0.1 dB); after
  each the reader's points are the pieces' (no rank read the whole volume); the query's kind
  check (shipped Kind Network; its reference drawn on the first rank from the volume the ranks
  stream to it) within 1e-4 of the builtin's agreement, the same verdict;
- reconstruction: same columns, rows, field data names and steps, values within
  RECONSTRUCT_TOL (1e-3, a quarter of one 8-bit level of a table entry): each piece stops its
  rays at ParaView's opacity threshold on its own (the images of a step differ by up to 1/255
  where a ray crosses pieces), and gradients are summed in another order; after the
  reconstruction, the reader's points are still the pieces' (no rank read the whole volume);
- match (Match Picture, the camera searched near the given view, 150 steps): the camera within
  0.5 degree and 1 % in distance of the builtin's, the found TF's render (port 1) >= 30 dB from
  the builtin's and at most 2 dB below its PSNR against the picture (each piece stops its rays on
  its own: the fits' steps differ a little, and the search follows them; one process's own runs
  spread over 1 dB);
- carried look (Carry Look, Iterations 5, shipped Kind Network; 2 ranks): 5 steps, its kind check
  within 1e-4 of the builtin's, the same verdict;
- no rank logged an error.
Then the query's preset is applied to the distributed volume and rendered by both ranks. The
server must exit by itself (status 0) when the client leaves; on any failure its ranks are killed
(they run in their own process groups). A crash in the server log fails the test.

With RANKS 4 (the distributed filters' own test; no query, match or carried look, which run on 2
ranks): the builds, renders, gallery, designs and reconstructions, plus a volume with fewer
cells than ranks (two ranks get empty pieces) and a pipeline whose piece on rank 1 has no scalars
(rank 1 fails in a render, a query, Match Picture and a build, in the pipeline and in the
background: the client reads the error from the first rank, no rank hangs, a failed build leaves
no folder, the server logs that error once per filter in the pipeline and exits).

Usage: pvpython TestMPIServer.py PLUGIN DATA [RANKS]
"""
import atexit
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

from paraview import servermanager
import paraview.simple as simple
from vtkmodules.util.numpy_support import vtk_to_numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ddgtest import apply_and_render, wait_for_build  # noqa: E402
from mpiserver import Server, split_points  # noqa: E402

RECONSTRUCT_TOL = 1e-3
# a build's held-out figures (dB, SSIM): the same design volume and exemplars; the training on
# the first rank and on the builtin process may run its threads' sums in another order
BUILD_TOL = (0.5, 0.02)
RENDER_TOL = 1 / 255 + 1e-6
# 2D tables with Shade: the lit colour is not clamped to 1 (as in ParaView), so what one piece's
# early termination leaves out (transmittance < 1/255) can weigh up to the brightest lit colour
RENDER_TOL_UNCLAMPED = 2 / 255 + 1e-6
CRASH_MARKERS = (
    "SIGSEGV",
    "SIGABRT",
    "Segmentation fault",
    "signal 11",
    "exited on signal",
    "core dumped",
)

plugin, data = sys.argv[1:3]
# The kind check's references, kept in folders new to this run: the server's ranks draw the
# query's into one (its MPI path: the volume streamed to the first rank), the builtin session its
# own into another, and each carried look reads the query's from its folder (a kept reference's
# path over pieces and in one process). With none kept, both filters drew theirs on both sides.
kind_cache = tempfile.mkdtemp(prefix="ddg_mpi_kind_")
atexit.register(shutil.rmtree, kind_cache, True)
os.environ["DDG_CACHE_DIR"] = os.path.join(kind_cache, "server")
ranks = int(sys.argv[3]) if len(sys.argv) > 3 else 2
tooth_file = os.path.join(data, "Volumes", "tooth.vti")
shot = os.path.join(data, "Screenshots", "tooth_dentin_enamel_oblique.png")
view_file = os.path.join(data, "Views", "tooth_oblique.json")


# ---------------------------------------------------------------------------------------------
# the filters, and what the client receives from them


def arrays(fields):
    """{name: values} of a vtkFieldData / vtkDataSetAttributes (numpy for numeric arrays)."""
    out = {}
    for i in range(fields.GetNumberOfArrays()):
        a = fields.GetAbstractArray(i)
        if a.IsA("vtkDataArray"):
            out[a.GetName()] = vtk_to_numpy(a).copy()
        else:
            out[a.GetName()] = [
                a.GetVariantValue(k).ToString() for k in range(a.GetNumberOfValues())
            ]
    return out


def snapshot(obj):
    """What a fetched image or table holds, as plain Python / numpy values."""
    snap = {"class": obj.GetClassName(), "field": arrays(obj.GetFieldData())}
    if obj.IsA("vtkImageData"):
        snap.update(
            dims=obj.GetDimensions(),
            origin=obj.GetOrigin(),
            spacing=obj.GetSpacing(),
            points=arrays(obj.GetPointData()),
        )
    else:
        snap.update(rows=obj.GetNumberOfRows(), columns=arrays(obj.GetRowData()))
    return snap


def lit_view():
    """The Tooth view with Shade on and a specular highlight, as view JSON text."""
    with open(view_file) as f:
        view = json.load(f)
    view["lighting"] = {"shade": True, "specular": 0.5, "specular_power": 30}
    return json.dumps(view)


def run_renders(remote, tooth, out):
    """DDG Volume Render of Tooth: 1D, Shade with specular, a 2D TF (Shade on)."""
    tfs = os.path.join(data, "TransferFunctions")
    cases = (
        ("render", dict(ViewFile=view_file), "tooth_dentin_enamel.json"),
        ("render lit", dict(ViewJSON=lit_view()), "tooth_dentin_enamel.json"),
        ("render 2d", dict(ViewJSON=lit_view()), "tooth_2d_boundaries.json"),
    )
    seconds = {}
    for name, view, tf in cases:
        render = simple.DDGVolumeRender(
            Input=tooth, TransferFunctionFile=os.path.join(tfs, tf), **view
        )
        start = time.time()
        render.UpdatePipeline()
        seconds[name] = time.time() - start
        out[name + ":0"] = snapshot(servermanager.Fetch(render))
    # summed over the ranks: the pieces with their ghost planes (before Show, whose
    # representation asks for pieces without ghosts)
    out["reader points"] = reader_points(tooth, remote, 1)
    return seconds


def reader_points(tooth, remote, ghosts):
    """The reader's points summed over the ranks now (its data information gathered again: a
    downstream filter's update does not refresh it) and what its pieces with `ghosts` ghost
    levels hold (one piece in a builtin session)."""
    tooth.SMProxy.GetOutputPort(0).InvalidateDataInformation()
    whole = tooth.GetDataInformation().DataInformation.GetExtent()
    return (
        tooth.GetDataInformation().GetNumberOfPoints(),
        split_points(whole, ranks if remote else 1, ghosts if remote else 0),
    )


def run_builds(remote, tooth, out):
    """DDG Build Design Space of Tooth, tiny (16 exemplars of 16 px, 10 iterations, 20 outline
    designs) on a downsampled design volume (DesignVoxels 2^18: 103 x 94 x 161 -> 52 x 47 x 81):
    in the pipeline (UpdatePipeline, pvpython's way) and in the background (StartBuild, the
    panel's way). What each bundle records; the seconds."""
    root = tempfile.mkdtemp(prefix=f"ddg_mpi_build_{'mpi' if remote else 'builtin'}_")
    seconds = {}
    for name in ("build", "build background"):
        build = simple.DDGBuildDesignSpace(
            Input=tooth,
            OutputDirectory=os.path.join(root, name.replace(" ", "_")),
            Count=16,
            Size=16,
            Iterations=10,
            OutlineCount=20,
            DesignVoxels=1 << 18,
        )
        start = time.time()
        if name == "build":
            build.UpdatePipeline()
            out["build:0"] = snapshot(servermanager.Fetch(build))
            build.UpdatePropertyInformation()
            assert build.GetPropertyValue("LastError") == "", build.GetPropertyValue("LastError")
        else:
            build.SMProxy.InvokeCommand("StartBuild")
            wait_for_build(build, polls=3000)
            state = build.GetPropertyValue("BuildState")
            assert state == "done", (state, build.GetPropertyValue("BuildError"))
        seconds[name] = time.time() - start
        directory = build.GetPropertyValue("OutputDirectory")
        with open(os.path.join(directory, "bundle.json")) as f:
            out[name + ":bundle"] = json.load(f)
        with open(os.path.join(directory, "exemplars.json")) as f:
            out[name + ":exemplars"] = f.read()
        with open(os.path.join(directory, "outline.bin"), "rb") as f:
            out[name + ":outline"] = f.read()
        # the pieces without ghost points (the build asks for none)
        out[f"reader points after {name}"] = reader_points(tooth, remote, 0)
        simple.Delete(build)
    shutil.rmtree(root, ignore_errors=True)
    return seconds


def run_filters(remote):
    simple.LoadPlugin(plugin, remote=remote)
    out = {}
    tooth = simple.XMLImageDataReader(FileName=[tooth_file])
    seconds = run_builds(remote, tooth, out)
    seconds.update(run_renders(remote, tooth, out))
    rec = simple.DDGReconstructTransferFunction(
        Input=tooth, TargetImageFile=shot, ViewFile=view_file, Iterations=20
    )
    rec2d = simple.DDGReconstructTransferFunction(
        Input=tooth,
        TargetImageFile=shot,
        ViewFile=view_file,
        Iterations=10,
        a2Dvaluexgradientmagnitude=1,  # TwoD, named after its label
    )
    gallery = simple.DDGDesignGallery(
        Input=tooth,
        ModelDirectory=os.path.join(data, "Models", "tooth"),
        ViewFile=view_file,
        Count=9,
        ThumbnailSize=48,
    )
    with open(view_file) as f:
        view = json.load(f)

    def design_of(*steps):
        return simple.DDGDesign(
            Input=tooth,
            ModelDirectory=os.path.join(data, "Models", "tooth"),
            ViewFile=view_file,
            ComputeFidelity=1,
            History=json.dumps({"format": "ddg-history", "version": 1, "steps": list(steps)}),
        )

    design = design_of({"action": "pick", "row": 4725}, {"action": "axes", "steps": [1.0, -0.5]})
    # an edit renders the design and analyzes its recoloured image again (over the pieces)
    edited = design_of(
        {"action": "pick", "row": 4725}, {"action": "edit", "view": view, "cluster": 0, "hue": 90}
    )
    filters = [
        ("gallery", gallery, [0, 1]),
        ("design", design, [0, 1]),
        ("edited", edited, [1]),
        ("reconstruct", rec, [0]),
        ("reconstruct 2d", rec2d, [0]),
    ]
    if ranks == 2:
        # the query and its kind check over pieces (with 4 ranks, the gallery and the design
        # render over the pieces as the query's preview does; a query on 4 ranks and its builtin
        # twin were 43 s of that test in a CI run)
        query = simple.DDGQuery(
            Input=tooth,
            ModelDirectory=os.path.join(data, "Models", "tooth"),
            ImageFile=shot,
            ViewFile=view_file,
            KindNetwork=os.path.join(data, "Models", "kind"),
        )
        filters.insert(0, ("query", query, [0, 1]))
        # Match Picture over pieces: the camera searched near the given view (silhouettes,
        # colours, short fits, polish), the fit, previews and the before/after renders
        match = simple.DDGReconstructTransferFunction(
            Input=tooth,
            TargetImageFile=shot,
            ViewFile=view_file,
            MatchPicture=1,
            EstimateCamera=1,
            Iterations=150,
            PreviewEvery=50,
        )
        filters.append(("match", match, [0, 1]))
        # a short carried look: its kind check over pieces (the reference drawn from the volume
        # the ranks stream to the first) against the builtin session's
        carry = simple.DDGReconstructTransferFunction(
            Input=tooth,
            TargetImageFile=shot,
            CarryLook=1,
            Iterations=5,
            KindNetwork=os.path.join(data, "Models", "kind"),
        )
        filters.append(("carry", carry, [0]))
    for name, proxy, ports in filters:
        start = time.time()
        proxy.UpdatePipeline()
        seconds[name] = time.time() - start
        for port in ports:
            out[f"{name}:{port}"] = snapshot(servermanager.Fetch(proxy, idx=port))
        if name in ("query", "gallery", "design"):
            out[f"reader points after {name}"] = reader_points(tooth, remote, 1)
    out["reader points after reconstruct"] = reader_points(tooth, remote, 1)
    print(report_line(remote, seconds))
    return tooth, out


def report_line(remote, seconds):
    return (
        (f"{ranks} ranks" if remote else "builtin")
        + ": "
        + ", ".join(f"{k} {v:.2f} s" for k, v in seconds.items())
    )


def same(a, b):
    """Exact equality of snapshots (numpy arrays compared element by element)."""
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if hasattr(a, "dtype"):
        return hasattr(b, "dtype") and a.dtype == b.dtype and a.shape == b.shape and (a == b).all()
    return a == b


def render_difference(a, b):
    """The largest difference between two render snapshots' RGBA (and their 8-bit images', in
    levels); their arrays, field data and size must match."""
    assert a["class"] == b["class"] == "vtkImageData" and a["dims"] == b["dims"], (
        a["dims"],
        b["dims"],
    )
    assert a["points"].keys() == b["points"].keys() and a["field"].keys() == b["field"].keys()
    assert "Image" in a["points"], "render: no image"
    rgba = float(abs(a["points"]["RGBA"] - b["points"]["RGBA"]).max())
    levels = int(abs(a["points"]["Image"].astype(int) - b["points"]["Image"].astype(int)).max())
    return rgba, levels


def compare_renders(mpi, builtin):
    for key, tol in (
        ("render:0", RENDER_TOL),
        ("render lit:0", RENDER_TOL),
        ("render 2d:0", RENDER_TOL_UNCLAMPED),
    ):
        rgba, levels = render_difference(mpi[key], builtin[key])
        assert rgba <= tol and levels <= round(
            255 * tol
        ), f"{key}: {rgba} ({levels} levels) from builtin"
        print(
            f"{key[:-2]}: {ranks} ranks vs builtin, RGBA max difference {rgba:.2e}, {levels} level(s)"
        )
    points, expected = mpi["reader points"]
    assert (
        points == expected
    ), f"the ranks read {points} points; their pieces with one ghost level hold {expected}"


def compare_designs(mpi, builtin, name):
    """The query's (or the gallery's) image within RENDER_TOL, its table the same but for the
    picture's figure (within 0.1 dB), and the reader's points after it the pieces'."""
    rgba, levels = render_difference(mpi[name + ":0"], builtin[name + ":0"])
    assert rgba <= RENDER_TOL and levels <= round(
        255 * RENDER_TOL
    ), f"{name} image: {rgba} ({levels} levels) from builtin"
    a, b = dict(mpi[name + ":1"]), dict(builtin[name + ":1"])
    assert a["class"] == b["class"], (name, a["class"], b["class"])
    fa, fb = dict(a.pop("field")), dict(b.pop("field"))
    kind = [json.loads(f.pop("Kind")[0]) for f in (fa, fb) if "Kind" in f]
    assert len(kind) in (0, 2), f"{name}: the kind check in one session only"
    if kind:
        # the reference's exemplars drawn on the first rank from the assembled whole (Tooth is
        # under the design-space cap: the same volume); the network's sums may add in another
        # order over other thread counts
        km, kb = kind
        assert (
            abs(km["agreement"] - kb["agreement"]) <= 1e-4
            and km["differs"] == kb["differs"]
            and km["volume_like"] == kb["volume_like"]
        ), f"{name}: the kind check {km} against the builtin session's {kb}"
    psnr = [float(f.pop("PicturePSNR")[0]) for f in (fa, fb) if "PicturePSNR" in f]
    assert not psnr or abs(psnr[0] - psnr[1]) <= 0.1, f"{name}: the picture's figure {psnr}"
    assert same(a, b) and same(fa, fb), f"{name}:1 differs from the builtin session's"
    points, expected = mpi[f"reader points after {name}"]
    assert (
        points == expected
    ), f"after the {name} the ranks read {points} points; their pieces hold {expected}"
    figure = f", picture {psnr[0]:.3f} vs {psnr[1]:.3f} dB" if psnr else ""
    if kind:
        figure += f", kind agreement {km['agreement']:.6f} vs {kb['agreement']:.6f}"
    print(
        f"{name}: {ranks} ranks vs builtin, image RGBA max difference {rgba:.2e}, "
        f"{levels} level(s){figure}; the table the same ({a.get('rows')} rows); "
        f"the reader's points after it: the pieces' ({points})"
    )


def compare_design(mpi, builtin):
    """The design (a pick and a move along the principal axes): its preview within RENDER_TOL,
    the same latent and fields, the fidelity (the neural image against the explicit TF's ray
    cast, both over the pieces) within 0.5 dB; the reader's points after it the pieces'. The
    edited design (its image rendered over the pieces, recoloured and analyzed again): its
    latent is another than the pick's (the edit ran); how far it is from the builtin's is
    reported (an image that differs by up to 1/255 can fall into other colour clusters)."""
    rgba, levels = render_difference(mpi["design:0"], builtin["design:0"])
    assert rgba <= RENDER_TOL and levels <= round(
        255 * RENDER_TOL
    ), f"design preview: {rgba} ({levels} levels) from builtin"
    fa, fb = dict(mpi["design:1"]["field"]), dict(builtin["design:1"]["field"])
    fidelity = (float(fa.pop("Fidelity")[0]), float(fb.pop("Fidelity")[0]))
    assert abs(fidelity[0] - fidelity[1]) <= 0.5, f"design: fidelity {fidelity}"
    assert same(fa, fb), "design: the latent, TF or regions differ from the builtin session's"
    points, expected = mpi["reader points after design"]
    assert points == expected, f"after the design the ranks read {points} points, not {expected}"
    edited = mpi["edited:1"]["field"]["Latent"]
    moved = float(abs(edited - builtin["edited:1"]["field"]["Latent"]).max())
    assert (edited != fa["Latent"]).any() and "Preset" in mpi["edited:1"]["field"]
    print(
        f"design (pick + axes): {ranks} ranks vs builtin, preview RGBA max difference {rgba:.2e}, "
        f"the same latent and TF, fidelity {fidelity[0]:.2f} vs {fidelity[1]:.2f} dB; edited "
        f"(pick + edit): its latent {moved:.3f} from the builtin's at most; the reader's points "
        f"after them: the pieces' ({points})"
    )


def compare_builds(mpi, builtin):
    """The builds over the ranks against the builtin's: the bundle records the whole volume's
    fingerprint (the shipped Tooth bundle's), the training exemplars' designs are the same text
    (the design volume's feature regions and the screen's verdicts: the same design volume), the
    held-out figures within BUILD_TOL (training runs on one process either way); the reader's
    points after the build are the pieces' (no ghost level): no rank read the whole volume."""
    with open(os.path.join(data, "Models", "tooth", "bundle.json")) as f:
        tooth_fingerprint = json.load(f)["volume"]
    for name in ("build", "build background"):
        m, b = mpi[name + ":bundle"], builtin[name + ":bundle"]
        assert m["volume"] == b["volume"] == tooth_fingerprint, (m["volume"], b["volume"])
        assert mpi[name + ":exemplars"] == builtin[name + ":exemplars"], f"{name}: other exemplars"
        dpsnr = abs(m["metrics"]["psnr"] - b["metrics"]["psnr"])
        dssim = abs(m["metrics"]["ssim"] - b["metrics"]["ssim"])
        assert dpsnr <= BUILD_TOL[0] and dssim <= BUILD_TOL[1], (name, m["metrics"], b["metrics"])
        points, pieces = mpi[f"reader points after {name}"]
        assert points == pieces, f"after the {name} the reader holds {points} points, not {pieces}"
        outline = "the same" if mpi[name + ":outline"] == builtin[name + ":outline"] else "other"
        print(
            f"{ranks} ranks, {name}: the whole's fingerprint, the same exemplars, {outline} "
            f"outline latents (rendered in shares; the training's threads may sum in another "
            f"order); held-out "
            f"{m['metrics']['psnr']:.3f} dB / {m['metrics']['ssim']:.4f} vs builtin "
            f"{b['metrics']['psnr']:.3f} / {b['metrics']['ssim']:.4f}; reader points {points} "
            f"(the pieces')"
        )
    table = mpi["build:0"]["columns"]
    assert abs(float(table["PSNR"][0]) - mpi["build:bundle"]["metrics"]["psnr"]) < 1e-3, table
    elsewhere = float(mpi["build:0"]["field"]["OtherRanksCandidates"][0])
    assert elsewhere > 0, "the other ranks rendered no exemplar candidate"
    assert float(builtin["build:0"]["field"]["OtherRanksCandidates"][0]) == 0
    print(f"{ranks} ranks, build: the other ranks rendered {elsewhere:.0f} exemplar candidates")


def compare(mpi, builtin):
    compare_builds(mpi, builtin)
    compare_renders(mpi, builtin)
    compare_designs(mpi, builtin, "query")
    compare_designs(mpi, builtin, "gallery")
    compare_design(mpi, builtin)
    assert (
        mpi["query:1"]["rows"] > 0
        and "Preset" in mpi["query:1"]["field"]
        and "Kind" in mpi["query:1"]["field"]
    ), "query: no designs, preset or kind check"
    compare_match(mpi, builtin)
    compare_carry(mpi, builtin)
    return compare_reconstructions(mpi, builtin)


def image_psnr(a, b):
    """PSNR (dB) between two 8-bit images."""
    mse = float(((a.astype(float) - b.astype(float)) ** 2).mean()) / 255.0**2
    return 100.0 if mse == 0 else 10.0 * math.log10(1.0 / mse)


def compare_match(mpi, builtin):
    """The match over pieces finds the builtin session's camera and look: the camera within half a
    degree and 1 % in distance, the found TF's render at the found view as the builtin's (>= 30 dB
    between the two) and not more than 2 dB further from the picture (one process's own runs
    spread over 1 dB: 46.3-47.3 dB in 4 runs, its threads adding in varying order until the
    backward pass dealt its rays in a fixed way; the pieces still add in another order). (Carry
    Look's full fit over pieces, 70 s here, is checked over threads:
    Core.ColourDistribution.CarriesALookOverPieces; compare_carry runs 5 steps.)
    """
    m, b = mpi["match:0"]["field"], builtin["match:0"]["field"]
    orbit = max(abs(x - y) for x, y in zip(m["Orbit"], b["Orbit"]))
    zoom = abs(m["Zoom"][0] / b["Zoom"][0] - 1)
    assert (
        orbit <= 0.5 and zoom <= 0.01
    ), f"match camera: orbit {orbit} deg, zoom {zoom} from builtin"
    agree = image_psnr(mpi["match:1"]["points"]["Image"], builtin["match:1"]["points"]["Image"])
    picture = b["PicturePSNR"][1] - m["PicturePSNR"][1]  # how much worse than the builtin's
    assert (
        agree >= 30 and picture <= 2
    ), f"match look: renders at {agree:.1f} dB PSNR of each other, {picture:.2f} dB worse"
    print(
        f"match: {ranks} ranks vs builtin, camera {orbit:.3f} deg / zoom {100 * zoom:.2f} % apart, "
        f"renders at {agree:.1f} dB PSNR of each other, against the picture {m['PicturePSNR'][1]:.2f} vs "
        f"{b['PicturePSNR'][1]:.2f} dB, fit {m['FitPSNR'][0]:.2f} vs {b['FitPSNR'][0]:.2f} dB"
    )


def compare_carry(mpi, builtin):
    """The short carried look over pieces (2 ranks): its steps (Iterations caps them) and its
    kind check as the builtin session's (agreement within 1e-4, the same verdict and reading)."""
    if "carry:0" not in mpi:
        return
    m, b = mpi["carry:0"]["field"], builtin["carry:0"]["field"]
    assert m["Iterations"][0] == b["Iterations"][0] == 5, (m["Iterations"], b["Iterations"])
    km, kb = (json.loads(f["Kind"][0]) for f in (m, b))
    assert (
        abs(km["agreement"] - kb["agreement"]) <= 1e-4
        and km["differs"] == kb["differs"]
        and km["volume_like"] == kb["volume_like"]
    ), f"carried look's kind check {km} against the builtin session's {kb}"
    print(
        f"carry: {ranks} ranks vs builtin, 5 steps, kind agreement {km['agreement']:.6f} vs "
        f"{kb['agreement']:.6f} ({km['volume_like']})"
    )


def compare_reconstructions(mpi, builtin):
    """The largest differences of the 1D and 2D reconstructions' columns from the builtin's."""
    diffs = []
    for key in ("reconstruct:0", "reconstruct 2d:0"):
        m, b = mpi[key], builtin[key]
        assert m["class"] == b["class"] == "vtkTable" and m["rows"] == b["rows"] > 0, (
            key,
            m["class"],
            m["rows"],
            b["rows"],
        )
        assert m["columns"].keys() == b["columns"].keys() and m["field"].keys() == b["field"].keys()
        diff = max(
            float(abs(m["columns"][c].astype(float) - b["columns"][c].astype(float)).max())
            for c in m["columns"]
        )
        assert diff <= RECONSTRUCT_TOL, f"{key} differs from the builtin session's by {diff}"
        assert m["field"]["Iterations"] == b["field"]["Iterations"], (
            m["field"]["Iterations"],
            b["field"]["Iterations"],
        )
        diffs.append(diff)
    points, expected = mpi["reader points after reconstruct"]
    assert (
        points == expected
    ), f"after the reconstruction the ranks read {points} points; their pieces hold {expected}"
    return diffs


def crashed(log):
    return any(marker in log for marker in CRASH_MARKERS)


# ---------------------------------------------------------------------------------------------
# pieces that own nothing, and a rank that fails (RANKS 4)

FAIL_ON_RANK_1 = """
from vtkmodules.vtkParallelCore import vtkMultiProcessController
out = self.GetOutputDataObject(0)
out.ShallowCopy(self.GetInputDataObject(0, 0))
if vtkMultiProcessController.GetGlobalController().GetLocalProcessId() == 1:
    out.GetPointData().Initialize()  # this rank's piece has no point data
"""
FAILED = "rank 1: the volume has cell data only"  # tooth.vti has cell data too
MISSING_BUNDLE = "/nonexistent/ddg_bundle"


def tiny_render():
    """A 2 x 2 x 3-point volume (two cells: two of four ranks get no cell) rendered (the plugin
    is loaded)."""
    tiny = simple.Wavelet(WholeExtent=[0, 1, 0, 1, 0, 2])
    view = {
        "camera": {
            "position": [4.0, 3.0, 6.0],
            "focal_point": [0.5, 0.5, 1.0],
            "view_up": [0.0, 1.0, 0.0],
            "view_angle": 30.0,
        },
        "size": [64, 48],
        "background": [0.0, 0.0, 0.0],
    }
    render = simple.DDGVolumeRender(
        Input=tiny,
        ViewJSON=json.dumps(view),
        TransferFunctionFile=os.path.join(data, "TransferFunctions", "tooth_cool_warm.json"),
    )
    render.UpdatePipeline()
    snap = snapshot(servermanager.Fetch(render))
    assert snap["points"]["RGBA"][:, 3].max() > 0.05, "the tiny volume's image is empty"
    return snap


def failing_rank(tooth):
    """A pipeline whose piece on rank 1 has no scalars: every rank stops, the client reads the
    error from the first rank — for a render, a query and Match Picture (the match's ranks stop
    before their first exchange of the match)."""
    broken = simple.ProgrammableFilter(Input=tooth, Script=FAIL_ON_RANK_1)
    render = simple.DDGVolumeRender(
        Input=broken,
        ViewFile=view_file,
        TransferFunctionFile=os.path.join(data, "TransferFunctions", "tooth_dentin_enamel.json"),
    )
    match = simple.DDGReconstructTransferFunction(
        Input=broken, TargetImageFile=shot, MatchPicture=1, Iterations=20
    )
    query = simple.DDGQuery(
        Input=broken,
        ModelDirectory=os.path.join(data, "Models", "tooth"),
        ImageFile=shot,
        ViewFile=view_file,
    )
    # the first rank fails on its own (no such bundle) while the others serve its renders: they
    # stop too
    missing = simple.DDGQuery(
        Input=tooth, ModelDirectory=MISSING_BUNDLE, ImageFile=shot, ViewFile=view_file
    )
    missing.UpdatePipeline()
    missing.UpdatePropertyInformation()
    error = missing.GetProperty("LastError").GetElement(0)
    assert MISSING_BUNDLE in error, f"query without a bundle: LastError {error!r}"
    print(f"{ranks} ranks, query of a missing bundle: the client read: {error}")
    # a build: in the pipeline (logged like the others) and in the background (its state)
    folder = tempfile.mkdtemp(prefix="ddg_mpi_failed_build_")
    build = simple.DDGBuildDesignSpace(
        Input=broken, OutputDirectory=os.path.join(folder, "bundle"), Count=16, Size=16
    )
    background = simple.DDGBuildDesignSpace(
        Input=broken, OutputDirectory=os.path.join(folder, "background"), Count=16, Size=16
    )
    start = time.time()
    background.SMProxy.InvokeCommand("StartBuild")
    background.UpdatePropertyInformation()
    state, error = (background.GetPropertyValue(k) for k in ("BuildState", "BuildError"))
    assert state == "failed" and error.startswith(FAILED), (state, error)
    print(
        f"{ranks} ranks, build in the background: rank 1 failed, every rank stopped in "
        f"{time.time() - start:.1f} s, the client read: {error}"
    )
    for name, proxy in (("render", render), ("query", query), ("match", match), ("build", build)):
        start = time.time()
        proxy.UpdatePipeline()
        proxy.UpdatePropertyInformation()
        error = proxy.GetProperty("LastError").GetElement(0)
        assert error.startswith(FAILED), f"{name}: LastError {error!r}, expected {FAILED!r}..."
        out = servermanager.Fetch(proxy)
        empty = out.GetNumberOfPoints() if out.IsA("vtkDataSet") else out.GetNumberOfRows()
        assert empty == 0, f"a failed {name} gave an output"
        print(
            f"{ranks} ranks, {name}: rank 1 failed, every rank stopped in "
            f"{time.time() - start:.1f} s, the client read: {error}"
        )
    assert os.listdir(folder) == [], f"a failed build left {os.listdir(folder)}"
    shutil.rmtree(folder)


# ---------------------------------------------------------------------------------------------
# the test

signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))  # ctest's timeout: still stop the server
server = Server(ranks)
try:
    server.wait_ready()
    simple.Connect("localhost", server.port)
    partitions = servermanager.ActiveConnection.GetNumberOfDataPartitions()
    assert partitions == ranks, f"the server runs {partitions} processes, expected {ranks}"
    tooth, mpi = run_filters(remote=True)
    if ranks == 2:
        preset = json.loads(mpi["query:1"]["field"]["Preset"][0])[0]
        out = os.path.join(tempfile.gettempdir(), f"ddg_mpi_apply_{os.getpid()}.png")
        size = apply_and_render(tooth, preset, view_file, out)
        assert size > 5000, size
        print(
            f"2 ranks: the query's preset applied to the distributed volume and rendered ({size} bytes PNG)"
        )
    else:
        failing_rank(tooth)
        mpi["tiny"] = tiny_render()
    del tooth
    # simple.Disconnect() alone keeps the session (servermanager's proxy namespaces refer to it)
    # and so the server; a builtin session replaces it, and the server then exits by itself
    simple.Disconnect()
    simple.Connect()
    try:
        server.process.wait(timeout=30)
    except subprocess.TimeoutExpired:
        raise AssertionError("the server did not exit after the client left")
    log = server.output()
    assert not crashed(log), "pvserver crashed:\n" + log
    assert server.process.returncode == 0, (
        f"mpiexec exit status {server.process.returncode}:\n" + log
    )
    assert log.count("Exiting...") == ranks, "every rank should exit:\n" + log
    errors = [line for line in log.splitlines() if "ERR|" in line or "Error" in line]
    expected = [line for line in errors if FAILED in line]
    if ranks == 2:
        assert not errors, "the server logged errors:\n" + log
    else:  # the failing rank's error, reported once by the first rank
        # the error as vtkErrorMacro prints it: a header line ("ERR| ERROR: In ...") and the message
        others = [
            line
            for line in errors
            if FAILED not in line and MISSING_BUNDLE not in line and "ERR| ERROR: In" not in line
        ]
        assert len(expected) == 4 and not others, (
            "the server should log rank 1's error once per filter (render, query, match, build):\n"
            + log
        )
    print(
        f"{ranks} ranks: mpiexec exited with status 0 after the client left, "
        f"{len(expected)} error(s) logged (expected {0 if ranks == 2 else 4})"
    )
finally:
    server.stop()
    log = server.output()
    if crashed(log):
        print(log)
        raise SystemExit("pvserver crashed")

os.environ["DDG_CACHE_DIR"] = os.path.join(kind_cache, "builtin")
_, builtin = run_filters(remote=False)
if ranks != 2:
    compare_builds(mpi, builtin)
    compare_renders(mpi, builtin)
    compare_designs(mpi, builtin, "gallery")
    compare_design(mpi, builtin)
    diffs = compare_reconstructions(mpi, builtin)
    print(
        f"reconstruct on {ranks} pieces: max difference {diffs[0]:.1e}, 2D {diffs[1]:.1e} "
        f"(tolerance {RECONSTRUCT_TOL:g}); the reader's points after it: the pieces' "
        f"({mpi['reader points after reconstruct'][0]})"
    )
    rgba, levels = render_difference(mpi["tiny"], tiny_render())
    assert rgba <= RENDER_TOL and levels <= 1, f"tiny volume: {rgba} ({levels} levels) from builtin"
    print(
        f"tiny volume (ranks without cells): {ranks} ranks vs builtin, RGBA max difference {rgba:.2e}"
    )
    sys.exit(0)
diffs = compare(mpi, builtin)
print(
    f"as the builtin session: renders within tolerance, query preview and "
    f"{mpi['query:1']['rows']} designs with preset; reconstruct on pieces "
    f"({mpi['reconstruct:0']['rows']} bins) max difference {diffs[0]:.1e}, 2D "
    f"({mpi['reconstruct 2d:0']['rows']} entries) {diffs[1]:.1e} (tolerance {RECONSTRUCT_TOL:g}); "
    f"the reader's points after it: the pieces' ({mpi['reader points after reconstruct'][0]})"
)
