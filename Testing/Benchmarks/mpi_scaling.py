"""mpi_scaling.py: strong scaling of the distributed filters over ParaView's MPI ranks, with the
memory of every rank (issue 21, part 5).

The volume: the project's Bonsai (Data/Volumes/bonsai.vti, 256^3, the largest volume of the tests
and of Data/) upsampled 2x along x and y by trilinear interpolation (volume_memory.make_volume):
512 x 512 x 256 uint8, 67 MB, 4x the voxels. It is written once as uncompressed raw-appended
.vti, so that ParaView's XML reader reads only the rows of each rank's piece.

For RANKS in --ranks (default 1 2 4): `mpiexec -np RANKS pvserver` (Testing/Plugin/mpiserver.py),
the plugin loaded on the server, then on the volume read by XMLImageDataReader:
  read+render   DDG Volume Render, 1D TF (bonsai_tree.json), the Bonsai view at 800 x 640: the
                first update (the reader reads the pieces, the ranks agree on them, render);
  render        the same filter at another camera (the pieces kept: the render alone);
  reconstruct   DDG Reconstruct Transfer Function from a `ddg render` of the volume at the view
                (target), --iterations steps of 2048 rays;
  match         DDG Reconstruct Transfer Function with Match Picture on the same target, the camera
                searched near its view (EstimateCamera), --match-iterations steps;
  query         DDG Query with the target, of a design space built once for the volume (`ddg
                build --budget 1`: its bundle checked against the whole's fingerprint, the
                picture analyzed, the design's preview and other lighting rendered at the view);
  gallery       DDG Design Gallery: 16 thumbnails of 128 x 128 at the view.
  build         DDG Build Design Space (--build-count exemplars of 64 px, 200 held out,
                --build-iterations training steps, --build-outline outline designs; the design
                volume: the volume downsampled 2x per axis under the 16 Mi voxel cap): with more
                ranks every rank streams its piece to the first, every rank gets the design
                volume and the others render shares of the exemplars and outline designs; the
                training and the analyzer's passes stay on the first rank.
With one rank the filters compute as one process (no pieces: ParaView's pipeline asks for the
whole volume); with more, every rank renders its own piece (one ghost level) and the images or
the reconstruction's rays are composited sort-last (Documentation/Rendering.md).

Per stage and rank: wall seconds (the client's UpdatePipeline), the rank's peak resident set size
above its RSS before the stage (VmHWM after resetting it: /proc/PID/clear_refs 5), its piece's
points (with its ghost planes; the whole for one rank) and the peak per piece point; the rank's
RSS after loading the plugin (the process alone). Speed-ups are against one rank, in the same
run. The machine's cores are printed: with fewer cores than ranks the ranks share them.

  xvfb-run -a /usr/bin/pvpython Testing/Benchmarks/mpi_scaling.py --build build \\
      --work /tmp/mpiscale --out Documentation/Results/mpi_scaling

Writes OUT.json and OUT.md.
"""
import argparse
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DATA = os.path.join(ROOT, "Data")
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, "Testing", "Plugin"))

from mpiserver import (  # noqa: E402
    Server,
    current_rss_mb,
    peak_rss_mb,
    piece_points,
    reset_peak_rss,
    split_boxes,
)
from volume_memory import make_volume  # noqa: E402

FACTORS = (2, 2, 1)
SIZE = (800, 640)


def write_vti(volume_json, path):
    """The raw + JSON volume as uncompressed raw-appended VTK XML image data."""
    import numpy as np
    from vtkmodules.util import numpy_support
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

    if os.path.exists(path):
        return path
    meta = json.load(open(volume_json))
    nx, ny, nz = meta["dims"]
    values = np.fromfile(os.path.join(os.path.dirname(volume_json), meta["file"]), np.uint8)
    image = vtkImageData()
    image.SetDimensions(nx, ny, nz)
    image.SetSpacing(*meta["spacing"])
    image.SetOrigin(*meta["origin"])
    array = numpy_support.numpy_to_vtk(values, deep=1)
    array.SetName("scalars")
    image.GetPointData().SetScalars(array)
    writer = vtkXMLImageDataWriter()
    writer.SetFileName(path + ".part")
    writer.SetInputData(image)
    writer.SetDataModeToAppended()
    writer.EncodeAppendedDataOff()
    writer.SetCompressorTypeToNone()
    if not writer.Write():
        raise RuntimeError("could not write " + path)
    os.replace(path + ".part", path)
    return path


def views(work):
    """(view JSON text, view file) at the Bonsai view, 800 x 640, and the same camera moved."""
    view = json.load(open(os.path.join(DATA, "Views", "bonsai_oblique.json")))
    view["size"] = list(SIZE)
    path = os.path.join(work, "view.json")
    json.dump(view, open(path, "w"))
    moved = json.loads(json.dumps(view))
    f, p = moved["camera"]["focal_point"], moved["camera"]["position"]
    moved["camera"]["position"] = [f[0] + (p[2] - f[2]), p[1], f[2] - (p[0] - f[0])]  # 90 deg
    return json.dumps(view), json.dumps(moved), path


def target(build, volume_json, tf, view_path, work):
    """The reconstruction's target: `ddg render` of the volume at the view."""
    out = os.path.join(work, "target.png")
    if not os.path.exists(out):
        subprocess.run(
            [
                os.path.join(build, "bin", "ddg"),
                "render",
                "--volume",
                volume_json,
                "--tf",
                tf,
                "--view",
                view_path,
                "--out",
                out,
            ],
            check=True,
        )
    return out


def bundle(build, volume_json, work):
    """A design space for the volume (`ddg build --budget 1`, once): what DDG Query reads."""
    out = os.path.join(work, "bundle")
    if not os.path.exists(os.path.join(out, "outline.bin")):
        subprocess.run(
            [
                os.path.join(build, "bin", "ddg"),
                "build",
                "--volume",
                volume_json,
                "--out",
                out,
                "--budget",
                "1",
                "--overwrite",
                "--quiet",
            ],
            check=True,
        )
    return out


def run(ranks, args, vti, tf, view_text, moved_text, target_png, model):
    import paraview.simple as simple
    from paraview import servermanager

    plugin = os.path.join(
        args.build, "lib", "paraview-5.11", "plugins", "DesignGallery", "DesignGallery.so"
    )
    server = Server(ranks)
    result = {"ranks": ranks, "stages": {}}
    try:
        server.wait_ready()
        simple.Connect("localhost", server.port)
        simple.LoadPlugin(plugin, remote=True)
        pids = server.rank_pids()
        assert sorted(pids) == list(range(ranks)), f"ranks found: {sorted(pids)}"
        result["process_mb"] = [current_rss_mb(pids[r]) for r in range(ranks)]
        reader = simple.XMLImageDataReader(FileName=[vti])
        render = simple.DDGVolumeRender(Input=reader, TransferFunctionFile=tf, ViewJSON=view_text)
        rec = simple.DDGReconstructTransferFunction(
            Input=reader,
            TargetImageFile=target_png,
            ViewJSON=view_text,
            Iterations=args.iterations,
        )
        # Match Picture over the pieces: the camera searched near the view (EstimateCamera)
        match = simple.DDGReconstructTransferFunction(
            Input=reader,
            TargetImageFile=target_png,
            ViewJSON=view_text,
            MatchPicture=1,
            EstimateCamera=1,
            Iterations=args.match_iterations,
        )

        query = simple.DDGQuery(
            Input=reader, ModelDirectory=model, ImageFile=target_png, ViewJSON=view_text
        )
        gallery = simple.DDGDesignGallery(
            Input=reader, ModelDirectory=model, ViewJSON=view_text, Count=16, ThumbnailSize=128
        )
        build = simple.DDGBuildDesignSpace(
            Input=reader,
            OutputDirectory=os.path.join(args.work, f"built_{ranks}"),
            Overwrite=1,
            Count=args.build_count,
            Iterations=args.build_iterations,
            OutlineCount=args.build_outline,
        )

        def stage(name, proxy, change=None):
            before = {}
            for r in range(ranks):
                reset_peak_rss(pids[r])
                before[r] = current_rss_mb(pids[r])
            if change:
                change()
            start = time.time()
            proxy.UpdatePipeline()
            seconds = time.time() - start
            proxy.UpdatePropertyInformation()
            error = proxy.GetProperty("LastError").GetElement(0)
            assert not error, f"{name} on {ranks} ranks: {error}"
            peaks = [peak_rss_mb(pids[r]) - before[r] for r in range(ranks)]
            result["stages"][name] = {"seconds": seconds, "peak_above_mb": peaks}
            print(
                f"{ranks} rank(s) {name}: {seconds:.2f} s, peak above the stage's start per rank "
                + ", ".join(f"{p:.0f} MB" for p in peaks),
                flush=True,
            )

        stage("read+render", render)
        stage("render", render, lambda: setattr(render, "ViewJSON", moved_text))
        stage("reconstruct", rec)
        stage("match", match)
        stage("query", query)
        stage("gallery", gallery)
        stage("build", build)
        fetched = servermanager.Fetch(build)
        result["build_other_ranks_candidates"] = (
            fetched.GetFieldData().GetArray("OtherRanksCandidates").GetValue(0)
        )
        extent = reader.GetDataInformation().DataInformation.GetExtent()
        boxes = split_boxes(extent, ranks)
        result["piece_points"] = [piece_points(extent, box, 1 if ranks > 1 else 0) for box in boxes]
        del reader, render, rec, match, query, gallery, build
        simple.Disconnect()
        simple.Connect()
        server.process.wait(timeout=60)
    finally:
        server.stop()
    return result


def markdown(results, cores, voxels):
    base = {s: results[0]["stages"][s]["seconds"] for s in results[0]["stages"]}
    lines = [
        "# Strong scaling over MPI ranks (issue 21, part 5)",
        "",
        f"Bonsai upsampled 2x along x and y: 512 x 512 x 256 uint8 ({voxels / 1e6:.1f} M voxels, "
        f"{voxels / 2**20:.0f} MB), 800 x 640 render, reconstruction {results[0]['iterations']} "
        f"steps of 2048 rays; {cores} cores. Written by Testing/Benchmarks/mpi_scaling.py.",
        "",
        f"Match Picture: the render as the picture, the camera searched near its view, "
        f"{results[0]['match_iterations']} steps.",
        "",
        f"Build: {results[0]['build_count']} exemplars of 64 px (+200 held out), "
        f"{results[0]['build_iterations']} training steps, {results[0]['build_outline']} outline "
        "designs; candidates the other ranks rendered in brackets.",
        "",
        "| ranks | read+render s | render s | reconstruct s | match s | query s | gallery s | "
        "build s | speed-up (render, reconstruct, match, query, gallery, build) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in results:
        st = r["stages"]
        lines.append(
            f"| {r['ranks']} | {st['read+render']['seconds']:.2f} | {st['render']['seconds']:.2f} "
            f"| {st['reconstruct']['seconds']:.2f} | {st['match']['seconds']:.1f} "
            f"| {st['query']['seconds']:.2f} | {st['gallery']['seconds']:.2f} "
            f"| {st['build']['seconds']:.1f} ({r['build_other_ranks_candidates']:.0f}) "
            f"| {base['render'] / st['render']['seconds']:.2f}, "
            f"{base['reconstruct'] / st['reconstruct']['seconds']:.2f}, "
            f"{base['match'] / st['match']['seconds']:.2f}, "
            f"{base['query'] / st['query']['seconds']:.2f}, "
            f"{base['gallery'] / st['gallery']['seconds']:.2f}, "
            f"{base['build'] / st['build']['seconds']:.2f} |"
        )
    lines += [
        "",
        "Per rank: its piece's points (with ghost planes), the process after loading the plugin, "
        "and the peak resident set size above the stage's start (MB; bytes per piece point).",
        "",
        "| ranks | rank | piece points | process MB | read+render MB (B/pt) | render MB | "
        "reconstruct MB (B/pt) | match MB (B/pt) | query MB (B/pt) | gallery MB | build MB |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in results:
        st = r["stages"]
        for k in range(r["ranks"]):
            pts = r["piece_points"][k]
            rr, re_ = st["read+render"]["peak_above_mb"][k], st["reconstruct"]["peak_above_mb"][k]
            ma = st["match"]["peak_above_mb"][k]
            qu, ga = st["query"]["peak_above_mb"][k], st["gallery"]["peak_above_mb"][k]
            lines.append(
                f"| {r['ranks']} | {k} | {pts / 1e6:.1f} M | {r['process_mb'][k]:.0f} | "
                f"{rr:.0f} ({rr * 2**20 / pts:.2f}) | {st['render']['peak_above_mb'][k]:.0f} | "
                f"{re_:.0f} ({re_ * 2**20 / pts:.2f}) | {ma:.0f} ({ma * 2**20 / pts:.2f}) | "
                f"{qu:.0f} ({qu * 2**20 / pts:.2f}) | {ga:.0f} | "
                f"{st['build']['peak_above_mb'][k]:.0f} |"
            )
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--work", default="/tmp/ddg_mpi_scaling")
    parser.add_argument("--out", default=None, help="OUT.json and OUT.md (default: print only)")
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 4])
    parser.add_argument("--iterations", type=int, default=30)
    parser.add_argument("--match-iterations", type=int, default=100)
    parser.add_argument("--build-count", type=int, default=512)
    parser.add_argument("--build-iterations", type=int, default=50)
    parser.add_argument("--build-outline", type=int, default=2000)
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    volume_json = make_volume(args.work, FACTORS)
    vti = write_vti(volume_json, os.path.join(args.work, "bonsai_4x.vti"))
    tf = os.path.join(DATA, "TransferFunctions", "bonsai_tree.json")
    view_text, moved_text, view_path = views(args.work)
    target_png = target(args.build, volume_json, tf, view_path, args.work)
    model = bundle(args.build, volume_json, args.work)
    meta = json.load(open(volume_json))
    voxels = meta["dims"][0] * meta["dims"][1] * meta["dims"][2]
    results = []
    for ranks in args.ranks:
        r = run(ranks, args, vti, tf, view_text, moved_text, target_png, model)
        r["iterations"] = args.iterations
        r["match_iterations"] = args.match_iterations
        r["build_count"] = args.build_count
        r["build_iterations"] = args.build_iterations
        r["build_outline"] = args.build_outline
        results.append(r)
    md = markdown(results, os.cpu_count(), voxels)
    print(md)
    if args.out:
        json.dump(
            {"voxels": voxels, "cores": os.cpu_count(), "results": results},
            open(args.out + ".json", "w"),
            indent=1,
        )
        open(args.out + ".md", "w").write(md)
        print("wrote " + args.out + ".md")


if __name__ == "__main__":
    main()
