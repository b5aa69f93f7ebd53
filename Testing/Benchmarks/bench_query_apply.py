"""Query -> TF applied and rendered in ParaView, timed (issue 6's bar: <= 3 s for Tooth on 2 cores).

Steps, each timed (median of --runs after one warm-up that loads the bundle): DDG Query on the
shipped Tooth bundle with a shipped ParaView screenshot (analyzer, neighbours, preview, explicit
TF), the preset written into the volume representation's LookupTable / ScalarOpacityFunction,
and ParaView's render of it at the query's camera. Prints figures and the ratio to the bar;
asserts nothing.

Then the query as the Design Gallery panel runs it (its view at 192 pixels on the longer side, 5
nearest designs), without and with the strip of the nearest designs under the query box
(ThumbnailSize 64: their thumbnails and each one's figure against the picture), the two
alternated run by run; prints both medians and their ratio.

Run: scripts/with-xvfb.sh pvpython Testing/Benchmarks/bench_query_apply.py [--runs 5]
     (from the repository root, after the README's build)
"""
import argparse
import json
import os
import statistics
import time

from paraview import servermanager
import paraview.simple as simple

root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
parser = argparse.ArgumentParser(
    description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
)
parser.add_argument("--runs", type=int, default=5)
parser.add_argument(
    "--plugin",
    default=os.path.join(
        root, "build", "lib", "paraview-5.11", "plugins", "DesignGallery", "DesignGallery.so"
    ),
)
args = parser.parse_args()
data = os.path.join(root, "Data")
simple.LoadPlugin(args.plugin, remote=False)

reader = simple.XMLImageDataReader(FileName=[os.path.join(data, "Volumes", "tooth.vti")])
array = reader.PointData.keys()[0]
view_path = os.path.join(data, "Views", "tooth_oblique.json")
with open(view_path) as f:
    cam = json.load(f)
view = simple.CreateView("RenderView")
view.ViewSize = cam["size"]
view.OrientationAxesVisibility = 0
display = simple.Show(reader, view)
simple.ColorBy(display, ("POINTS", array))
display.SetRepresentationType("Volume")
lut = simple.GetColorTransferFunction(array)
pwf = simple.GetOpacityTransferFunction(array)
simple.Render(view)
c = cam["camera"]
view.CameraPosition, view.CameraFocalPoint, view.CameraViewUp = (
    c["position"],
    c["focal_point"],
    c["view_up"],
)
view.CameraViewAngle = c.get("view_angle", 30.0)

query = simple.DDGQuery(Input=reader)
query.ModelDirectory = os.path.join(data, "Models", "tooth")
query.ViewFile = view_path
shots = [
    os.path.join(data, "Screenshots", s)
    for s in ("tooth_dentin_enamel_oblique.png", "tooth_cool_warm_side.png")
]

t0 = time.perf_counter()
query.ImageFile = shots[1]
query.UpdatePipeline()
warm = time.perf_counter() - t0

times = {"query": [], "apply": [], "render": [], "total": []}
for r in range(args.runs):
    t0 = time.perf_counter()
    query.ImageFile = shots[r % 2]
    query.UpdatePipeline()
    table = servermanager.Fetch(query, idx=1)
    preset = json.loads(table.GetFieldData().GetAbstractArray("Preset").GetValue(0))[0]
    t1 = time.perf_counter()
    lut.RGBPoints = preset["RGBPoints"]
    pwf.Points = preset["Points"]
    t2 = time.perf_counter()
    simple.Render(view)
    t3 = time.perf_counter()
    times["query"].append(t1 - t0)
    times["apply"].append(t2 - t1)
    times["render"].append(t3 - t2)
    times["total"].append(t3 - t0)

print(
    f"query -> TF applied -> rendered in ParaView, Tooth, {args.runs} runs, median "
    f"(first query incl. loading the bundle and its outline: {warm:.2f} s)"
)
for k, v in times.items():
    print(f"  {k:7s} {statistics.median(v) * 1000:8.1f} ms")
total = statistics.median(times["total"])
print(f"  bar 3000 ms, ratio {total / 3.0:.3f}")

# --- the panel's query, without and with its nearest designs' thumbnails and figures ---
panel_view = dict(cam)
scale = 192.0 / max(cam["size"])
panel_view["size"] = [max(1, round(n * scale)) for n in cam["size"]]
query.ViewFile = ""
query.ViewJSON = json.dumps(panel_view)
query.Neighbours = 5
strip = {0: [], 64: []}
for r in range(args.runs):
    for size in (0, 64) if r % 2 == 0 else (64, 0):
        query.ThumbnailSize = size
        query.ImageFile = shots[r % 2]
        t0 = time.perf_counter()
        query.UpdatePipeline()
        servermanager.Fetch(query, idx=1)
        if size:
            servermanager.Fetch(query, idx=2)
        strip[size].append(time.perf_counter() - t0)
without, with_strip = (statistics.median(strip[k]) for k in (0, 64))
print(
    f"the panel's query ({panel_view['size'][0]} x {panel_view['size'][1]} view, 5 nearest "
    f"designs), {args.runs} runs each, alternated, median"
)
print(f"  without the strip          {without * 1000:8.1f} ms")
print(f"  with the strip (64 px)     {with_strip * 1000:8.1f} ms")
print(f"  ratio {with_strip / without:.2f} (+{(with_strip - without) * 1000:.0f} ms)")
