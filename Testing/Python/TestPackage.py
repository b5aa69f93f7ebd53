"""Every public function of the `ddg` package on Tooth and its shipped model (build/bin/pvpython),
against the `ddg` command line on the same files (the same Core code) where both exist.

Usage: build/bin/pvpython TestPackage.py DDG TESTDATA OUTDIR [--server]
With --server the session is connected to a pvserver started here (a free loopback port) and the
same checks run there (the package loads the plugin on both sides).
"""
import json
import os
import re
import subprocess
import sys
import tempfile
import time
import warnings

import numpy as np
from vtkmodules.util import numpy_support
from vtkmodules.vtkIOImage import vtkPNGReader

ddg_exe, testdata, outdir = sys.argv[1:4]
remote = "--server" in sys.argv
os.makedirs(outdir, exist_ok=True)
server = None
if remote:
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Plugin"))
    from ddgtest import start_pvserver, stop_pvserver

    server = start_pvserver()

import ddg  # noqa: E402  (loads the plugin, remotely too when connected)
from paraview.simple import (
    ColorBy,
    CreateView,
    Delete,
    GetActiveView,
    GetColorTransferFunction,
    GetDisplayProperties,  # noqa: E402
    GetOpacityTransferFunction,
    Hide,
    RenameSource,
    Render,
    SetActiveView,
    Show,
    XMLImageDataReader,
)


def cli(*args):
    return subprocess.run([ddg_exe, *args], check=True, capture_output=True, text=True).stdout


def psnr(a, b):
    return 10 * np.log10(255.0**2 / max(1e-12, np.mean((a.astype(float) - b.astype(float)) ** 2)))


volume = ddg.data_path("Volumes/tooth.vti")
model_dir = ddg.data_path("Models/tooth")
shot = ddg.data_path("Screenshots/tooth_dentin_enamel_oblique.png")
view_file = ddg.data_path("Views/tooth_oblique.json")
white = json.load(open(view_file))
white["background"] = [1.0, 1.0, 1.0]  # the shipped screenshot's background
tooth = XMLImageDataReader(FileName=[volume])
display = Show(tooth)
ddg.set_camera(view_file)
checks = []


def check(name, ok, detail=""):
    checks.append(name)
    assert ok, f"{name}: {detail}"
    print(f"ok {name} {detail}")


# a view that shows nothing has ParaView's first camera, away from the data: its view JSON gives the
# camera ParaView's Reset Camera gives with the volume shown there (a view taller than wide)
first = GetActiveView()
empty = CreateView("RenderView")
empty.ViewSize = [300, 500]
unseen = ddg.view_json(empty, tooth)["camera"]
Show(tooth, empty)
Render(empty)
empty.ResetCamera()  # paraview.simple resets on the session's first render alone; the GUI on Show
seen = ddg.view_json(empty, tooth)["camera"]
check(
    "view_json of a view showing nothing",
    all(np.allclose(unseen[k], seen[k], rtol=1e-9) for k in ("position", "focal_point", "view_up"))
    and np.isclose(unseen["parallel_scale"], seen["parallel_scale"], rtol=1e-9),
    "%s against ParaView's %s" % (unseen["position"], seen["position"]),
)
Delete(empty)
SetActiveView(first)

start = time.time()
model = ddg.load_model(model_dir, tooth)
check("load_model", model.directory == os.path.abspath(model_dir))

g = ddg.gallery(tooth, model, count=16, seed=3)
listed = os.path.join(outdir, "list.csv")
cli(
    "gallery",
    "--model",
    model_dir,
    "--volume",
    volume,
    "--count",
    "16",
    "--seed",
    "3",
    "--thumb",
    "8",
    "--side",
    "64",
    "--list",
    listed,
    "--out",
    os.path.join(outdir, "sheet.png"),
)
cli_rows = [int(line.split(",")[0]) for line in open(listed).read().split("\n")[1:] if line]
check(
    "gallery",
    g.thumbnails == cli_rows and len(g.x) == 50000 and g.sheet.ndim == 3,
    f"{len(g.x)} designs, thumbnails {g.thumbnails[:4]}..., sheet {g.sheet.shape}",
)

found = ddg.query(shot, view=view_file, thumbnail_size=64)
out = cli(
    "query",
    "--model",
    model_dir,
    "--volume",
    volume,
    "--image",
    shot,
    "--view",
    view_file,
    "--out-tf",
    os.path.join(outdir, "query_tf.json"),
)
cli_tf = json.load(open(os.path.join(outdir, "query_tf.json")))[0]
check(
    "query",
    found.neighbours == [int(m) for m in re.findall(r"design row (\d+)", out)]
    and found.transfer_function(view_file)["RGBPoints"] == cli_tf["RGBPoints"],
    f"neighbours {found.neighbours}, position {tuple(round(p, 2) for p in found.position)}",
)
thumbs = found.neighbour_thumbnails
check(
    "query's neighbour thumbnails",
    len(thumbs) == len(found.neighbours) == 5
    and all(t.shape == (64, 64, 3) and t.std() > 0 for t in thumbs)
    and len(found.neighbour_picture_psnr) == 5
    and all(5 < f < 60 for f in found.neighbour_picture_psnr),
    f"{len(thumbs)} of {[t.shape for t in thumbs][:1]}, against the picture "
    f"{[round(f, 1) for f in found.neighbour_picture_psnr]} dB",
)
plain = ddg.query(shot, view=view_file)  # by default no thumbnails (a query stays as fast)
try:
    ddg.query(shot, view=view_file, thumbnail_size=600)
    refused = False
except ddg.DDGError as e:
    refused = "thumbnail_size" in str(e)
check(
    "query without thumbnails; a thumbnail size out of range refused",
    plain.neighbours == found.neighbours
    and plain.neighbour_thumbnails == []
    and plain.neighbour_picture_psnr == []
    and refused,
    "",
)

picked = ddg.pick(g.thumbnails[0], model)
history = os.path.join(outdir, "pick.json")
ddg.export(picked, history, format="history")
cli(
    "replay",
    "--model",
    model_dir,
    "--volume",
    volume,
    "--history",
    history,
    "--view",
    view_file,
    "--out-tf",
    os.path.join(outdir, "pick_tf.json"),
)
check(
    "pick + export history",
    picked.transfer_function(view_file)["RGBPoints"]
    == json.load(open(os.path.join(outdir, "pick_tf.json")))[0]["RGBPoints"],
)

a, b = found, picked
check(
    "interpolate",
    np.allclose(ddg.interpolate(a, b, 0).latent, a.latent, atol=1e-6)
    and np.allclose(ddg.interpolate(a, b, 1).latent, b.latent, atol=1e-6)
    and not np.allclose(ddg.interpolate(a, b, 0.5).latent, a.latent, atol=1e-3),
)

edited = ddg.edit(found, cluster=0, hue=90, axes=[0.5], view=view_file)
check(
    "edit",
    not np.allclose(edited.latent, found.latent, atol=1e-4)
    and len(found.evaluate(view_file)["clusters"]) >= 1,
    f"{edited}",
)

# the grey view file with the screenshot's background stated (the same as its own view file)
tf = ddg.reconstruct(shot, view=view_file, iterations=300, background=(1.0, 1.0, 1.0))
ours = ddg.render(tooth, tf, white)
reader = vtkPNGReader()
reader.SetFileName(shot)
reader.Update()
w, h, _ = reader.GetOutput().GetDimensions()
target = numpy_support.vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars()).reshape(
    h, w, -1
)[::-1, :, :3]
check(
    "reconstruct + render",
    psnr(ours, target) > 40,
    f"our render of the TF vs. the screenshot {psnr(ours, target):.1f} dB",
)

# match (builtin and against the pvserver): the screenshot at its camera, from the query's design
m = ddg.match(shot, tooth, camera=white, initial=found, iterations=100)
check(
    "match",
    not m.camera_estimated
    and np.allclose(m.view["camera"]["position"], white["camera"]["position"])
    and "RGBPoints" in m.tf
    and m.psnr_after > m.psnr_before
    and m.image.shape == (h, w, 3),
    f"{m}",
)

cli(
    "render",
    "--volume",
    volume,
    "--tf",
    os.path.join(outdir, "query_tf.json"),
    "--view",
    view_file,
    "--out",
    os.path.join(outdir, "cli_render.png"),
)
reader.SetFileName(os.path.join(outdir, "cli_render.png"))
reader.Update()
cli_img = numpy_support.vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars()).reshape(
    h, w, -1
)[::-1, :, :3]
check("render", psnr(ddg.render(tooth, found, view_file), cli_img) > 99, "identical to ddg render")

ddg.apply(found, display)
lut = GetColorTransferFunction(tooth.PointData.keys()[0])
check(
    "apply",
    list(lut.RGBPoints)
    == found.transfer_function(ddg.view_json(GetActiveView(), tooth, 256))["RGBPoints"]
    and display.Representation == "Volume",
)

# 2D: a TF file, a 2D model's design and a 2D reconstruction into ParaView's TransferFunction2D
tf2d = ddg.data_path("TransferFunctions/tooth_2d_boundaries.json")
cli(
    "export",
    "--tf",
    tf2d,
    "--volume",
    volume,
    "--view",
    view_file,
    "--format",
    "paraview-2d",
    "--out",
    os.path.join(outdir, "tooth_2d_boxes.json"),
)
cli_boxes = json.load(open(os.path.join(outdir, "tooth_2d_boxes.json")))
boxes = ddg.paraview_2d(tf2d, tooth, view_file)
check(
    "paraview_2d",
    np.allclose(boxes["Boxes"], cli_boxes["Boxes"], rtol=1e-9, atol=1e-12)
    and boxes["Range"] == cli_boxes["Range"]
    and boxes["OutputDimensions"] == [1024, 1024],
    f"{len(boxes['Boxes']) // 8} boxes (fit RMSE {boxes['Fit']['rmse']:.4f}), as ddg export --format paraview-2d",
)


def applied_2d(disp, expected):
    tf2 = disp.TransferFunction2D
    return (
        disp.UseTransfer2D == 1
        and disp.Representation == "Volume"
        and np.allclose(list(tf2.Boxes), expected["Boxes"])
        and list(tf2.Range) == expected["Range"]
        and list(tf2.OutputDimensions) == expected["OutputDimensions"]
    )


ddg.apply(tf2d, display)
check("apply 2D file", applied_2d(display, ddg.paraview_2d(tf2d, tooth, GetActiveView())))
# ParaView's own 2D boxes are applied as they are
own_boxes = {
    "Boxes": [100, 0, 60, 20, 0.9, 0.6, 0.3, 0.7],
    "Range": [0, 255, 0, 63.75],
    "OutputDimensions": [1024, 1024],
}
ddg.apply(own_boxes, display)
check("apply ParaView boxes", applied_2d(display, own_boxes))
ddg.apply(tf2d, display)
try:
    ddg.apply(
        {
            "Format": "ddg-transfer-function-2d",
            "Version": 1,
            "ValueRange": [0, 255],
            "GradientRange": [0, 80],
            "Primitives": [],
        },
        display,
    )
    raise AssertionError("a 2D TF without primitives should raise")
except ddg.DDGError as e:
    check(
        "apply 2D bad input",
        applied_2d(display, ddg.paraview_2d(tf2d, tooth, GetActiveView())),
        f"raised '{e}', the 2D TF applied before is untouched",
    )
small_vti, small_view = os.path.join(testdata, "small.vti"), os.path.join(
    testdata, "small_view.json"
)
bundle_2d = os.path.join(outdir, "bundle_2d")
if not os.path.exists(os.path.join(bundle_2d, "outline.bin")):
    cli(
        "generate",
        "--volume",
        small_vti,
        "--spec",
        os.path.join(testdata, "spec_2d.json"),
        "--count",
        "8",
        "--size",
        "16",
        "--out",
        os.path.join(outdir, "gen_2d"),
        "--quiet",
    )
    cli(
        "train",
        "--kind",
        "decoder",
        "--volume",
        small_vti,
        "--data",
        os.path.join(outdir, "gen_2d"),
        "--eval-data",
        os.path.join(outdir, "gen_2d"),
        "--out",
        bundle_2d,
        "--max-iterations",
        "10",
        "--width",
        "4",
        "--latent",
        "8",
        "--batch",
        "4",
        "--threads",
        "1",
        "--image-weight",
        "10",
        "--image-rays",
        "64",
        "--quiet",
    )
    cli("outline", "--model", bundle_2d, "--volume", small_vti, "--count", "50")
small = XMLImageDataReader(FileName=[small_vti])
small_display = Show(small)
design_2d = ddg.query(
    os.path.join(testdata, "small_target.png"), small, small_view, ddg.load_model(bundle_2d, small)
)
ddg.apply(design_2d, small_display, small)
expected = design_2d.evaluate(ddg.view_json(GetActiveView(), small, 256))["paraview_2d"]
check(
    "apply 2D design",
    applied_2d(small_display, expected)
    and design_2d.transfer_function(small_view)["Format"] == "ddg-transfer-function-2d",
    f"{len(expected['Boxes']) // 8} boxes from the 2D model's design",
)
rec_2d = ddg.reconstruct(
    os.path.join(testdata, "small_target.png"),
    small,
    small_view,
    iterations=20,
    bins=16,
    two_d=True,
)
ddg.apply(rec_2d, small_display, small)
check(
    "apply 2D reconstruction",
    applied_2d(small_display, ddg.paraview_2d(rec_2d, small, GetActiveView())),
    f"table {rec_2d.get('Size')} as {len(small_display.TransferFunction2D.Boxes) // 8} boxes",
)
ddg.apply(found, display)
check(
    "apply 1D after 2D",
    display.UseTransfer2D == 0
    and list(lut.RGBPoints)
    == found.transfer_function(ddg.view_json(GetActiveView(), tooth, 256))["RGBPoints"],
)
Hide(small)

preset_file = ddg.export(found, os.path.join(outdir, "found.json"), view=view_file)
slicer_file = ddg.export(
    found, os.path.join(outdir, "found.vp.json"), format="slicer", view=view_file
)
check(
    "export",
    json.load(open(preset_file))[0]["RGBPoints"] == cli_tf["RGBPoints"]
    and json.load(open(preset_file))[0]["Name"].startswith("DDG tooth query found 20")
    and "volumeProperties" in json.load(open(slicer_file)),
    json.load(open(preset_file))[0]["Name"],
)

before = list(lut.RGBPoints)
frames = ddg.animate(a, b, 3)
check(
    "animate",
    len(frames) == 3 and psnr(frames[0], frames[2]) < 40 and list(lut.RGBPoints) == before,
    f"3 frames, first vs last {psnr(frames[0], frames[2]):.1f} dB, colour map restored",
)

if not remote:  # the build writes where the filter runs; here the same machine
    small = XMLImageDataReader(FileName=[os.path.join(testdata, "small.vti")])
    built = ddg.build_design_space(
        small,
        os.path.join(outdir, "built"),
        count=16,
        size=16,
        iterations=10,
        outline=20,
        overwrite=True,  # a re-run replaces its own bundle
    )
    check(
        "build_design_space",
        os.path.exists(os.path.join(built.directory, "outline.bin"))
        and len(ddg.gallery(small, built, count=4, thumbnail_size=16).x) == 20,
    )
    try:
        ddg.build_design_space(small, built.directory, count=16, size=16, iterations=10)
        raise AssertionError("a folder holding a bundle should be refused")
    except ddg.DDGError as e:
        check("build refuses a bundle's folder", "already holds a model bundle" in str(e), str(e))
    # sizes the filter would clamp silently are refused before anything runs or is written
    for call, words in (
        (lambda: ddg.build_plan(0, small), "budget_minutes must lie in [1, 100000], not 0"),
        (lambda: ddg.build_design_space(small, built.directory + "_x", budget_minutes=0), "[1,"),
        (lambda: ddg.build_design_space(small, built.directory + "_x", minutes=-3), "minutes"),
        (lambda: ddg.build_design_space(small, built.directory + "_x", count=0), "count must be"),
    ):
        try:
            call()
            raise AssertionError("a size out of range was run: " + words)
        except ValueError as e:
            check("a build's size out of range refused", words in str(e), str(e))
    check("nothing written for them", not os.path.exists(built.directory + "_x"))
    plan = ddg.build_plan(2, small, built.directory)
    check(
        "build_plan(2 min)",
        plan["count"] >= 256
        and plan["total_seconds"] <= 120
        and "already holds" in plan["output_error"],
        plan["describe"].replace("\n", "; "),
    )
    # a design-voxel cap below the volume's: planned (and built) on its block average
    plan = ddg.build_plan(2, tooth, design_voxels=200000)
    check(
        "build_plan(design_voxels=200000) on Tooth",
        plan["downsample"] == 2 and plan["design_dims"] == [52, 47, 81],
        plan["describe"].replace("\n", "; "),
    )

# an unreadable picture: one line naming the file (not the filter's property, not libpng's
# own lines)
garbage = os.path.join(testdata, "garbage.png")
truncated = os.path.join(tempfile.mkdtemp(), "truncated.png")
with open(shot, "rb") as f, open(truncated, "wb") as out:
    out.write(f.read()[:3000])
empty = os.path.join(os.path.dirname(truncated), "empty.png")
open(empty, "wb").close()
for path, reason in (
    (garbage, "the picture"),
    (truncated, "cannot read the picture: "),
    (empty, "the picture file is empty (0 bytes)"),
):
    try:
        ddg.query(path, source=tooth, view=view_file)
        raise AssertionError("an unreadable query picture should raise")
    except ddg.DDGError as e:
        text = str(e)
        check(
            "an unreadable picture raises DDGError naming it",
            text.startswith("query ('%s'): " % path)
            and reason in text
            and "\n" not in text
            and "ImageData" not in text,
            text,
        )

# a chart (lines on white) is refused; a photograph-like picture (colours to every edge) is
# answered with a warning
chart = np.full((120, 160, 3), 255, np.uint8)
chart[100:102, 20:150] = 0
chart[10:101, 20:22] = 0
for x in range(20, 150):
    y = int(55 + 35 * np.sin(x / 12.0))
    chart[y : y + 2, x] = (20, 80, 230)
try:
    ddg.query(chart, source=tooth, view=view_file)
    raise AssertionError("a chart should be refused")
except ddg.DDGError as e:
    check("a chart is refused", "lines or text" in str(e), str(e).splitlines()[0][:100])
yy, xx = np.mgrid[0:120, 0:160]
photo = np.stack(
    [127 + 100 * np.sin(0.05 * xx * (c + 1) + 0.07 * yy * (3 - c)) for c in range(3)], axis=2
).astype(np.uint8)
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    guessed = ddg.query(photo, source=tooth, view=view_file)
check(
    "a photograph is answered with a warning",
    guessed.warning is not None
    and "cannot be read as a rendered volume" in guessed.warning
    and any("cannot be read" in str(w.message) for w in caught),
    (guessed.warning or "no warning")[:100],
)
check("the shipped screenshot gets no warning", found.warning is None, str(found.warning))
# the kind check (the shipped kind network): Tooth's screenshot on Tooth is the same kind; the
# engine's screenshot on Tooth is said to be of another kind (warned), and kind=False skips it
with open(ddg.data_path("Models/kind/kind.json")) as f:
    kind_threshold = json.load(f)["threshold"]
check(
    "the query's kind check: a Tooth picture on Tooth",
    found.kind is not None
    and not found.kind_differs
    and found.kind["agreement"] >= kind_threshold == found.kind["threshold"]
    and found.kind["volume_like"] == "tooth",
    str(found.kind),
)
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    engine_on_tooth = ddg.query(
        ddg.data_path("Screenshots/engine_block_oblique.png"), source=tooth, view=view_file
    )
check(
    "the query's kind check: the engine's picture on Tooth",
    engine_on_tooth.kind_differs
    and engine_on_tooth.kind["agreement"] < kind_threshold
    and any("another kind" in str(w.message) for w in caught),
    str(engine_on_tooth.kind),
)
check(
    "kind=False: no check",
    ddg.query(shot, source=tooth, view=view_file, kind=False).kind is None,
    "",
)

# the query's design against its picture, framed alike: a finite PSNR, the better of the
# design unlit and lit (the shipped screenshot is unlit)
check(
    "query against its picture",
    found.picture_psnr is not None and 10 < found.picture_psnr < 99 and found.picture_lit is False,
    f"{found.picture_psnr:.1f} dB, design {'lit' if found.picture_lit else 'unlit'}",
)

# a second volume coloured by the same array shares ParaView's colour map: apply says so, and
# separate_color_map=True leaves it as it is
twin = XMLImageDataReader(FileName=[volume])
RenameSource("tooth twin", twin)
twin_display = Show(twin)
ColorBy(twin_display, ("POINTS", tooth.PointData.keys()[0]))
twin_display.SetRepresentationType("Volume")
ddg.apply(found, display)
twin_before = list(twin_display.LookupTable.RGBPoints)
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    ddg.apply(picked, display)
check(
    "apply warns of a shared colour map",
    any("tooth twin" in str(w.message) for w in caught)
    and list(twin_display.LookupTable.RGBPoints) != twin_before,
    str(caught[0].message) if caught else "no warning",
)
ddg.apply(found, display)
twin_before = list(twin_display.LookupTable.RGBPoints)
ddg.apply(picked, display, separate_color_map=True)
check(
    "separate colour map",
    display.UseSeparateColorMap == 1
    and display.LookupTable.SMProxy != twin_display.LookupTable.SMProxy
    and list(twin_display.LookupTable.RGBPoints) == twin_before
    and list(display.LookupTable.RGBPoints)
    == picked.transfer_function(ddg.view_json(GetActiveView(), tooth, 256))["RGBPoints"],
)
Delete(twin)

print(
    f"{len(checks)} checks passed in {time.time() - start:.1f} s ({'client/server' if remote else 'builtin'})"
)
if server:
    stop_pvserver(server)
