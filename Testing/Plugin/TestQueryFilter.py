"""DDG Query and DDG Design Gallery in pvpython, on the shipped Tooth bundle.

DDG Query: the bundle queried with a shipped ParaView screenshot.

Compared: the filter's outputs against `ddg query` on the same files (the same Core code): the
nearest designs (rows) must be identical, the preview image identical (PSNR >= 99 dB by
`ddg compare`) and the "Preset" field the same TF as --out-tf. Bad input (another volume's
bundle, a missing bundle, an unusable image): exactly one error, empty outputs, no crash.

The nearest designs' thumbnails (ThumbnailSize 32, the third output): one row of five 32-px
cells, each the very image DDG Design gives for a pick of that row at the same view, with each
one's figure against the picture (NeighbourPicturePSNR); of 70 nearest designs the first 64 get
thumbnails and figures, the rest NaN; none with ThumbnailSize 0.

DDG Design Gallery: 16 thumbnails of 32 px; the sheet's size, one row per outline design, the
thumbnail rows identical to `ddg gallery --list` (same count and seed), and a box beside the
plane giving no thumbnails without an error.

Usage: pvpython TestQueryFilter.py PLUGIN DDG DATA TESTDATA OUTDIR
"""
import json
import math
import os
import re
import subprocess
import sys

from paraview import servermanager
from paraview.simple import LoadPlugin, XMLImageDataReader
import paraview.simple as simple

plugin, ddg, data, testdata, outdir = sys.argv[1:6]
os.makedirs(outdir, exist_ok=True)
LoadPlugin(plugin, remote=False)

volume = os.path.join(data, "Volumes", "tooth.vti")
model = os.path.join(data, "Models", "tooth")
shot = os.path.join(data, "Screenshots", "tooth_dentin_enamel_oblique.png")
view = os.path.join(data, "Views", "tooth_oblique.json")

reader = XMLImageDataReader(FileName=[volume])
query = simple.DDGQuery(Input=reader)
query.ModelDirectory = model
query.ImageFile = shot
query.ViewFile = view
query.Neighbours = 5
query.UpdatePipeline()
preview = servermanager.Fetch(query, idx=0)
table = servermanager.Fetch(query, idx=1)
rows = [int(table.GetColumnByName("Row").GetValue(i)) for i in range(table.GetNumberOfRows())]
preset = json.loads(table.GetFieldData().GetAbstractArray("Preset").GetValue(0))[0]
position = table.GetFieldData().GetArray("Position")
print("filter: rows", rows, "position", position.GetValue(0), position.GetValue(1))

cli_tf = os.path.join(outdir, "query_cli_tf.json")
cli_png = os.path.join(outdir, "query_cli.png")
out = subprocess.run(
    [
        ddg,
        "query",
        "--model",
        model,
        "--volume",
        volume,
        "--image",
        shot,
        "--view",
        view,
        "--out-tf",
        cli_tf,
        "--out-preview",
        cli_png,
    ],
    check=True,
    capture_output=True,
    text=True,
).stdout
cli_rows = [int(m) for m in re.findall(r"design row (\d+)", out)]
assert rows == cli_rows, f"filter rows {rows} != ddg query rows {cli_rows}"
with open(cli_tf) as f:
    assert (
        json.load(f)[0]["RGBPoints"] == preset["RGBPoints"]
    ), "Preset differs from ddg query --out-tf"

from vtkmodules.vtkIOImage import vtkPNGWriter  # noqa: E402

png = os.path.join(outdir, "query_filter.png")
w = vtkPNGWriter()
w.SetFileName(png)
w.SetInputData(preview)
w.Write()
cmp = subprocess.run(
    [ddg, "compare", "--min-psnr", "99", png, cli_png], capture_output=True, text=True
)
print("filter preview vs ddg query preview:", cmp.stdout.strip())
assert cmp.returncode == 0, cmp.stderr

# --- the nearest designs' thumbnails -----------------------------------------------------------
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402


def image_of(data):
    w, h, _ = data.GetDimensions()
    return vtk_to_numpy(data.GetPointData().GetArray("Image")).reshape(h, w, 3)


assert servermanager.Fetch(query, idx=2).GetNumberOfPoints() == 0, "thumbnails without a size"
query.ThumbnailSize = 32
query.UpdatePipeline()
strip = image_of(servermanager.Fetch(query, idx=2))
assert strip.shape == (36, 5 * 34 + 2, 3), strip.shape
with open(view) as f:
    small = json.load(f)
small["size"] = [32, 32]
design = simple.DDGDesign(Input=reader, ModelDirectory=model, ViewJSON=json.dumps(small))
for k, row in enumerate(rows):
    design.History = json.dumps(
        {"format": "ddg-history", "version": 1, "steps": [{"action": "pick", "row": row}]}
    )
    design.UpdatePipeline()
    own = image_of(servermanager.Fetch(design, idx=0))
    cell = strip[2:34, 2 + k * 34 : 2 + k * 34 + 32]
    assert (cell == own).all(), f"thumbnail {k} (row {row}) differs from DDG Design's pick"
simple.Delete(design)
against = servermanager.Fetch(query, idx=1).GetColumnByName("NeighbourPicturePSNR")
figures = [against.GetValue(i) for i in range(against.GetNumberOfTuples())]
assert len(figures) == 5 and all(5 < f < 60 for f in figures), figures
# at most 64 thumbnails and figures; the rows beyond them NaN
query.Neighbours = 70
query.UpdatePipeline()
assert servermanager.Fetch(query, idx=2).GetDimensions()[:2] == (64 * 34 + 2, 36)
many = servermanager.Fetch(query, idx=1)
against = many.GetColumnByName("NeighbourPicturePSNR")
figures = [against.GetValue(i) for i in range(against.GetNumberOfTuples())]
assert many.GetNumberOfRows() == 70 and len(figures) == 70, (many.GetNumberOfRows(), len(figures))
assert all(5 < f < 60 for f in figures[:64]) and all(math.isnan(f) for f in figures[64:]), figures
query.Neighbours = 5
query.ThumbnailSize = 0
assert servermanager.Fetch(query, idx=1).GetColumnByName("NeighbourPicturePSNR") is None
print("neighbour thumbnails: 5 cells of 32 px, each DDG Design's pick of its row; 64 of 70")

# --- bad input -------------------------------------------------------------------------------
from vtkmodules.util.misc import calldata_type  # noqa: E402
from vtkmodules.util.vtkConstants import VTK_STRING  # noqa: E402
from vtkmodules.vtkCommonCore import vtkCommand  # noqa: E402

messages = []


@calldata_type(VTK_STRING)
def on_error(obj, event, calldata):
    messages.append(calldata)


query.GetClientSideObject().AddObserver(vtkCommand.ErrorEvent, on_error)


def expect_error(label, expected, **props):
    messages.clear()
    for key, value in props.items():
        setattr(query, key, value)
    query.UpdatePipeline()
    assert (
        servermanager.Fetch(query, idx=0).GetNumberOfPoints() == 0
    ), f"{label}: preview should be empty"
    assert len(messages) == 1, f"{label}: expected one error, got {messages}"
    assert expected in messages[0], f"{label}: '{expected}' not in '{messages[0]}'"
    print(f"{label}: {messages[0].strip().splitlines()[-1]}")


expect_error(
    "another volume's bundle",
    "trained on another volume",
    ModelDirectory=os.path.join(data, "Models", "engine"),
)
expect_error("missing bundle", "model bundle", ModelDirectory=os.path.join(outdir, "no_bundle"))
expect_error(
    "uniform image",
    "shows nothing",
    ModelDirectory=model,
    ImageFile=os.path.join(testdata, "query_uniform.png"),
)
expect_error("tiny image", "too small", ImageFile=os.path.join(testdata, "query_tiny.png"))
print("ok")

# --- DDG Design Gallery on the same bundle -----------------------------------------------------
gal = simple.DDGDesignGallery(Input=reader)
gal.ModelDirectory = model
gal.ViewFile = view
gal.Count = 16
gal.ThumbnailSize = 32
gal.UpdatePipeline()
sheet = servermanager.Fetch(gal, idx=0)
designs = servermanager.Fetch(gal, idx=1)
assert sheet.GetDimensions()[:2] == (4 * 34 + 2, 4 * 34 + 2), sheet.GetDimensions()
assert designs.GetNumberOfRows() == 50000, designs.GetNumberOfRows()
thumb = designs.GetColumnByName("Thumbnail")
cells = sorted(
    int(thumb.GetValue(i)) for i in range(designs.GetNumberOfRows()) if thumb.GetValue(i) >= 0
)
assert cells == list(range(16)), cells
# the same rows as ddg gallery --list with the same seed and count
listing = os.path.join(outdir, "gallery_rows.csv")
subprocess.run(
    [
        ddg,
        "gallery",
        "--model",
        model,
        "--volume",
        volume,
        "--count",
        "16",
        "--thumb",
        "16",
        "--side",
        "128",
        "--out",
        os.path.join(outdir, "gallery_cli.png"),
        "--list",
        listing,
    ],
    check=True,
    stdout=subprocess.DEVNULL,
)
with open(listing) as f:
    cli_rows = [int(line.split(",")[0]) for line in f.read().splitlines()[1:]]
filter_rows = [0] * 16
for i in range(designs.GetNumberOfRows()):
    if thumb.GetValue(i) >= 0:
        filter_rows[int(thumb.GetValue(i))] = i
assert filter_rows == cli_rows, (filter_rows, cli_rows)
# lit as the volume is shown: LightingJSON (the panel sends the representation's Shade)


def sheet_pixels():
    gal.UpdatePipeline()
    s = servermanager.Fetch(gal, idx=0)
    return vtk_to_numpy(s.GetPointData().GetScalars()).astype(float)


unlit = sheet_pixels()
gal.LightingJSON = json.dumps({"shade": True, "specular": 0.5, "specular_power": 30})
lit = sheet_pixels()
gal.LightingJSON = "{}"
assert abs(sheet_pixels() - unlit).max() == 0, "LightingJSON {} is not unlit"
print(f"thumbnails lit: mean change {abs(lit - unlit).mean():.2f} levels")
assert abs(lit - unlit).mean() > 1, "Shade on did not change the thumbnails"
gal.GetClientSideObject().AddObserver(vtkCommand.ErrorEvent, on_error)
messages.clear()
gal.LightingJSON = json.dumps({"shine": 1})
gal.UpdatePipeline()
assert len(messages) == 1 and "unknown lighting key" in messages[0], messages
print("bad lighting:", messages[0].strip().splitlines()[-1])
gal.LightingJSON = ""
box = designs.GetFieldData().GetArray("Box")
print(
    f"design gallery ok: 16 thumbnails over box ({box.GetValue(0):.2f}, {box.GetValue(1):.2f}, "
    f"{box.GetValue(2):.2f}, {box.GetValue(3):.2f}), rows as ddg gallery"
)
gal.Box = [1000, 1000, 1001, 1001]  # beside the plane: no thumbnails, no error
gal.UpdatePipeline()
assert max(servermanager.Fetch(gal, idx=1).GetColumnByName("Thumbnail").GetRange()) == -1
print("ok")
