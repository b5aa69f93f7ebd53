"""DDG::Scene (vtkSMDDGScene, Python-wrapped as ddg_vtk.DDGScene) in pvpython on real proxies.

Compared, each with what paraview.simple itself reads from the same proxies (exactly, unless said):
- ViewJSON: the render view's camera properties after a render, its ViewSize scaled to 64 pixels
  on the longer side (rounded half away from zero), Background, the display's
  ScalarOpacityUnitDistance; the same JSON with the source in place of the display; no view: "".
- CheckVolume / VolumeProblem / VolumeArray: tooth.vti is a volume with array "scalars"; a Sphere
  and vector.vti (3-component active scalars) are not, with the panel's words; a visible
  representation coloured by another one-component array names that array (hidden: ignored), one
  coloured by a 3-component array makes it no volume.
- DefaultModelDirectory: Data/Models/tooth for tooth.vti, none for small.vti.
- Apply1D: a preset (HSV) lands in the LUT's RGBPoints and ColorSpace and the opacity function's
  Points, the LUT never rescales, the display is Volume with UseTransfer2D off; a bad preset gives
  its message and changes nothing; CurrentPreset gives back what was written.
- Apply2D: boxes land in the TransferFunction2D (Boxes, Range, OutputDimensions) with
  UseTransfer2D and UseGradientForTransfer2D on; bad boxes give their message.

Usage: pvpython TestScene.py DATA TESTDATA (PYTHONPATH with the build's python/ for ddg_vtk)
"""
import json
import math
import os
import sys

import paraview.simple as simple
from ddg_vtk import DDGScene

S = DDGScene.vtkSMDDGScene
data, testdata = sys.argv[1:3]
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


view = simple.CreateView("RenderView")
view.ViewSize = [300, 200]
tooth = simple.XMLImageDataReader(FileName=[os.path.join(data, "Volumes", "tooth.vti")])
display = simple.Show(tooth, view)
display.SetRepresentationType("Volume")
simple.Render(view)
view.CameraPosition = [300, -200, 150]
view.CameraViewUp = [0, 0, 1]
simple.Render(view)

# --- ViewJSON ---
v = json.loads(S.ViewJSON(view.SMProxy, display.SMProxy, 64))
c = v["camera"]
round_half_away = lambda x: int(math.floor(x + 0.5))  # noqa: E731 (std::lround for x > 0)
check(
    c["position"] == list(view.CameraPosition)
    and c["focal_point"] == list(view.CameraFocalPoint)
    and c["view_up"] == list(view.CameraViewUp)
    and c["view_angle"] == view.CameraViewAngle
    and c["parallel_projection"] == bool(view.CameraParallelProjection)
    and c["parallel_scale"] == view.CameraParallelScale,
    "ViewJSON camera = the view's camera %s" % c["position"],
)
w, h = view.ViewSize
check(
    v["size"] == [round_half_away(w * 64 / max(w, h)), round_half_away(h * 64 / max(w, h))],
    "ViewJSON size %s for ViewSize %s at 64" % (v["size"], [w, h]),
)
drawn = (
    list(simple.GetSettingsProxy("ColorPalette").Background)
    if view.UseColorPaletteForBackground
    else list(view.Background)
)
check(v["background"] == drawn, "ViewJSON background %s = the colour drawn" % v["background"])
check(
    v.get("opacity_unit_distance") == display.ScalarOpacityUnitDistance,
    "ViewJSON opacity_unit_distance %s" % v.get("opacity_unit_distance"),
)
check("lighting" not in v, "ViewJSON: no lighting while Shade is off")
display.Shade, display.Specular, display.SpecularPower = 1, 0.5, 30
lit = json.loads(S.ViewJSON(view.SMProxy, display.SMProxy, 64))
check(
    lit.get("lighting")
    == {"shade": True, "ambient": 0.0, "diffuse": 1.0, "specular": 0.5, "specular_power": 30.0},
    "ViewJSON lighting with Shade on: %s" % lit.get("lighting"),
)
display.Shade, display.Specular, display.SpecularPower = 0, 0.0, 100.0
check(json.loads(S.ViewJSON(view.SMProxy, tooth.SMProxy, 64)) == v, "ViewJSON with the source")
check(json.loads(S.ViewJSON(view.SMProxy, None, 0))["size"] == [w, h], "ViewJSON at full size")
check(S.ViewJSON(None, display.SMProxy, 64) == "", "ViewJSON without a view is empty")
palette, own = view.UseColorPaletteForBackground, list(view.Background)
view.UseColorPaletteForBackground = 0
view.Background = [1.0, 1.0, 1.0]
check(
    json.loads(S.ViewJSON(view.SMProxy, None, 0))["background"] == [1.0, 1.0, 1.0],
    "ViewJSON background without the palette: the view's own",
)
view.UseColorPaletteForBackground = 1
check(
    json.loads(S.ViewJSON(view.SMProxy, None, 0))["background"]
    == list(simple.GetSettingsProxy("ColorPalette").Background),
    "ViewJSON background with the palette: the palette's %s"
    % list(simple.GetSettingsProxy("ColorPalette").Background),
)
view.UseColorPaletteForBackground, view.Background = palette, own

# --- a picture's camera in a view of another shape (this view: 300 x 200) ---
saved = json.loads(S.ViewJSON(view.SMProxy, None, 0))
# the view's own camera with another angle and scale, from a picture three times as wide as high
picture = {
    "camera": dict(saved["camera"], view_angle=30.0, parallel_scale=100.0),
    "size": [600, 200],
}
half = lambda angle: math.tan(math.radians(angle) / 2)  # noqa: E731
fitted = json.loads(S.FitToView(view.SMProxy, json.dumps(picture)))
check(
    abs(half(fitted["camera"]["view_angle"]) * 1.5 - half(30.0) * 3.0) < 1e-9
    and abs(fitted["camera"]["parallel_scale"] * 1.5 - 100.0 * 3.0) < 1e-9
    and fitted["size"] == [300, 200]
    and fitted["camera"]["position"] == saved["camera"]["position"],
    "FitToView: a picture wider than the view has its width fill the view's (view angle %.4f, "
    "parallel scale %.4f)" % (fitted["camera"]["view_angle"], fitted["camera"]["parallel_scale"]),
)
for size in ([300, 200], [200, 200]):  # as wide as the view, narrower: the camera as stated
    same = json.loads(S.FitToView(view.SMProxy, json.dumps(dict(picture, size=size))))
    check(
        same["camera"] == picture["camera"],
        "FitToView: a picture %s in the view keeps its camera" % size,
    )
no_size = json.dumps({"camera": picture["camera"]})
check(S.FitToView(view.SMProxy, no_size) == no_size, "FitToView: no size, as it is")
# SetCamera sets the camera as stated: a screenshot at the picture's size shows the picture
check(S.SetCamera(view.SMProxy, json.dumps(picture), False) == "", "SetCamera of a wider picture")
check(
    view.CameraViewAngle == 30.0 and view.CameraParallelScale == 100.0,
    "SetCamera: the camera as stated (%s)" % view.CameraViewAngle,
)
check(S.SetCamera(view.SMProxy, json.dumps(saved), False) == "", "SetCamera back")
check(
    json.loads(S.ViewJSON(view.SMProxy, None, 0)) == saved,
    "SetCamera of a live view's JSON: as it was",
)

# --- the volume ---
check(
    S.CheckVolume(tooth.SMProxy, None, 0) == S.IS_VOLUME and S.VolumeProblem(S.IS_VOLUME) == "",
    "tooth.vti is a volume",
)
check(S.VolumeArray(tooth.SMProxy, None, 0) == "scalars", "tooth.vti's array")
sphere = simple.Sphere()
sphere.UpdatePipeline()
vector = simple.XMLImageDataReader(FileName=[os.path.join(testdata, "vector.vti")])
vector.UpdatePipeline()
problem = (
    "is not a volume: the Design Gallery needs image data with a one-component point array "
    "(e.g. a .vti, .raw or DICOM volume)"
)
for name, source in (("a Sphere", sphere), ("vector.vti", vector)):
    check(
        S.CheckVolume(source.SMProxy, None, 0) == S.NOT_A_VOLUME
        and S.VolumeProblem(S.NOT_A_VOLUME) == problem
        and S.VolumeArray(source.SMProxy, None, 0) == "",
        name + " is not a volume",
    )
check(S.VolumeProblem(S.NO_DATA) == "has no data yet", "no data in words")
calc = simple.Calculator(Input=tooth, Function="scalars*2", ResultArrayName="twice")
calc.UpdatePipeline()
calc_display = simple.Show(calc, view)
active = S.VolumeArray(calc.SMProxy, None, 0)  # the active scalars
other = "scalars" if active == "twice" else "twice"
simple.ColorBy(calc_display, ("POINTS", other))
check(
    active in ("scalars", "twice")
    and S.VolumeArray(calc.SMProxy, calc_display.SMProxy, 0) == other,
    "the representation's colour array %r, not the active scalars %r" % (other, active),
)
simple.Hide(calc, view)
check(
    S.VolumeArray(calc.SMProxy, calc_display.SMProxy, 0) == active,
    "a hidden display's colour array does not count",
)
simple.Show(calc, view)
vectors = simple.Calculator(Input=tooth, Function="scalars*iHat", ResultArrayName="vectors")
vectors.UpdatePipeline()
vectors_display = simple.Show(vectors, view)
simple.ColorBy(vectors_display, ("POINTS", "vectors"))
check(
    S.CheckVolume(vectors.SMProxy, vectors_display.SMProxy, 0) == S.NOT_A_VOLUME
    and S.VolumeArray(vectors.SMProxy, vectors_display.SMProxy, 0) == "",
    "a display coloured by a 3-component array: not a volume",
)
simple.Hide(vectors, view)
simple.Hide(calc, view)

# --- the default model ---
small = simple.XMLImageDataReader(FileName=[os.path.join(testdata, "small.vti")])
check(
    S.DefaultModelDirectory(tooth.SMProxy, data) == data + "/Models/tooth"
    and S.DefaultModelDirectory(small.SMProxy, data) == ""
    and S.DefaultModelDirectory(sphere.SMProxy, data) == "",
    "default model of tooth.vti, none for small.vti and a Sphere",
)

# --- 1D TF ---
simple.SetActiveSource(tooth)
preset = json.load(open(os.path.join(data, "TransferFunctions", "engine_hsv.json")))
display.SetRepresentationType("Surface")
error = S.Apply1D(display.SMProxy, "scalars", json.dumps(preset))
lut = simple.GetColorTransferFunction("scalars")
sof = simple.GetOpacityTransferFunction("scalars")
check(error == "", "Apply1D: no error %r" % error)
check(
    list(lut.RGBPoints) == preset[0]["RGBPoints"]
    and list(sof.Points) == preset[0]["Points"]
    and lut.ColorSpace == "HSV"
    and lut.AutomaticRescaleRangeMode == "Never"
    and display.Representation == "Volume"
    and display.UseTransfer2D == 0
    and display.ColorArrayName[1] == "scalars",
    "Apply1D wrote the preset (RGBPoints, Points, HSV, never rescale, Volume, 1D)",
)
back = json.loads(S.CurrentPreset(display.SMProxy))
check(
    back["RGBPoints"] == preset[0]["RGBPoints"]
    and back["Points"] == preset[0]["Points"]
    and back["ColorSpace"] == "HSV",
    "CurrentPreset gives back what was written",
)
before = (list(lut.RGBPoints), list(sof.Points), lut.ColorSpace)
good = preset[0]
for bad, says in (
    ('{"RGBPoints": [0, 1, 0]}', '"RGBPoints" must hold 4 numbers a node (x, red, green, blue)'),
    (dict(good, Points=[0, 0, 0.5, 0, 255, "1", 0.5, 0]), '"Points" must hold 4 numbers a node'),
    (dict(good, Points=[0, 0, 0.5, 0, 255, 2, 0.5, 0]), "Points: opacity of node 1 is 2"),
    (
        dict(good, RGBPoints=[9, 0, 0, 0] + good["RGBPoints"]),
        "RGBPoints are not sorted: node 1 at x = %g comes before x = 9 (x must not decrease)"
        % good["RGBPoints"][0],
    ),
    (dict(good, ColorSpace="Banana"), 'ColorSpace "Banana" is not one of ParaView\'s'),
    ("[]", "is not a ParaView preset"),
):
    error = S.Apply1D(display.SMProxy, "scalars", bad if isinstance(bad, str) else json.dumps(bad))
    check(
        says in error and (list(lut.RGBPoints), list(sof.Points), lut.ColorSpace) == before,
        "Apply1D of a bad preset: %r, the maps unchanged" % error,
    )
# ParaView's own presets say CIELAB for Lab, and three repeat an x (the later node replaces it)
x0 = good["RGBPoints"][0]
twice = dict(good, ColorSpace="CIELAB", RGBPoints=[x0, 1, 1, 1] + good["RGBPoints"])
error = S.Apply1D(display.SMProxy, "scalars", json.dumps(twice))
check(error == "" and lut.ColorSpace == "Lab", "Apply1D of CIELAB and a repeated x: %r" % error)
S.Apply1D(display.SMProxy, "scalars", json.dumps(preset))

# --- 2D TF ---
boxes = {
    "Boxes": [0, 0, 255, 60, 0, 0, 0, 0, 150, 10, 80, 20, 1, 0.9, 0.8, 0.6],
    "Range": [0, 255, 0, 60],
    "OutputDimensions": [64, 32],
}
error = S.Apply2D(display.SMProxy, "scalars", json.dumps(boxes))
tf2 = display.TransferFunction2D
check(error == "", "Apply2D: no error %r" % error)
check(
    list(tf2.Boxes) == boxes["Boxes"]
    and list(tf2.Range) == boxes["Range"]
    and list(tf2.OutputDimensions) == boxes["OutputDimensions"]
    and display.UseTransfer2D == 1
    and display.UseGradientForTransfer2D == 1,
    "Apply2D wrote the boxes (Boxes, Range, OutputDimensions, UseTransfer2D, gradient as Y)",
)
error = S.Apply2D(display.SMProxy, "scalars", '{"Boxes": [1, 2, 3]}')
check(
    error.startswith("the design's 2D transfer function has no ParaView boxes"),
    "Apply2D of bad boxes: %r" % error,
)
simple.Render(view)

# no sys.exit(0) on success: it crashed pvpython 5.11 at exit after this script's renders
if failures:
    raise SystemExit("FAILED: %d: %s" % (len(failures), "; ".join(failures)))
print("all passed")
