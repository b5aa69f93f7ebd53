"""ddg.match and ddg.apply(camera=...) round trip (build/bin/pvpython).

Compared: a picture of NegHip made by the project's render (`ddg render`, neghip_shells.json at
neghip_oblique.json's camera, ParaView's palette background) is matched
- with camera="current" (the active view set to the picture's camera first): the Match's view
  holds that camera (1e-6), camera_estimated False, psnr_after >= 35 dB and > psnr_before
  (started from neghip_cool_warm);
- with camera=a view dict that is off, refine_camera=False: the given camera comes back as is.
Then ddg.apply(m, camera=True) from another camera: the view's camera properties equal the
Match's view (1e-6), the LUT's RGBPoints equal the Match's preset (1e-6), and ParaView's
screenshot at the picture's size (orientation axes off, the background the Match estimated) is
within 30 dB of the picture, and the display's Shade is off as the picture (was on). Lighting
from a view dict sets Shade and its coefficients; bad lighting is refused before anything is
written. Bad input: ddg.match on a uniform picture raises DDGError naming it.

Usage: build/bin/pvpython TestMatch.py DDG OUTDIR
"""
import json
import math
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Common"))
from pictures import psnr, read_png  # noqa: E402

import ddg
from paraview.simple import (
    GetActiveViewOrCreate,
    GetColorTransferFunction,
    Render,
    SaveScreenshot,
    Show,
    XMLImageDataReader,
)

ddg_exe, outdir = sys.argv[1:3]
os.makedirs(outdir, exist_ok=True)
volume = ddg.data_path("Volumes/neghip.vti")
with open(ddg.data_path("Views/neghip_oblique.json")) as f:
    known = json.load(f)
known["size"] = [240, 180]
known["background"] = [0.32, 0.34, 0.43]
view_path = os.path.join(outdir, "picture_view.json")
with open(view_path, "w") as f:
    json.dump(known, f)
picture_path = os.path.join(outdir, "picture.png")
subprocess.run(
    [ddg_exe, "render", "--volume", volume, "--view", view_path, "--out", picture_path]
    + ["--tf", ddg.data_path("TransferFunctions/neghip_shells.json")],
    check=True,
)


def same_camera(a, b, tol=1e-6):
    return all(np.allclose(a[k], b[k], rtol=tol, atol=tol) for k in ("position", "focal_point"))


neghip = XMLImageDataReader(FileName=[volume])
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [480, 360]
view.OrientationAxesVisibility = 0
Show(neghip, view)
ddg.set_camera(known, view)

# the picture was taken from the current camera
m = ddg.match(
    picture_path,
    neghip,
    camera="current",
    initial=ddg.data_path("TransferFunctions/neghip_cool_warm.json"),
    iterations=300,
)
print(m)
assert not m.camera_estimated
assert same_camera(m.view["camera"], known["camera"]), m.view["camera"]
assert m.view["size"] == known["size"], m.view["size"]
assert m.psnr_after >= 35 and m.psnr_after > m.psnr_before, (m.psnr_before, m.psnr_after)
assert m.image.shape == (180, 240, 3) and m.overlay.shape == (180, 240)
assert "RGBPoints" in m.tf and "Points" in m.tf

# a given camera comes back as it is (its size becomes the picture's)
off = json.loads(json.dumps(known))
off["camera"]["position"] = [p * 1.01 for p in off["camera"]["position"]]
off["size"] = [100, 100]
given = ddg.match(picture_path, neghip, camera=off, iterations=20)
assert same_camera(given.view["camera"], off["camera"]) and given.view["size"] == [240, 180]
# no initial TF, no "before": its repr gives the found TF's figure alone, not "nan"
assert math.isnan(given.psnr_before) and "nan" not in repr(given), repr(given)
assert repr(m).startswith("Match(PSNR %.1f -> " % m.psnr_before), repr(m)

# apply with the camera, from elsewhere
view.CameraPosition = [0, 0, 300]
view.CameraFocalPoint = [31.5, 31.5, 31.5]
view.CameraViewUp = [0, 1, 0]
Render(view)
display = Show(neghip, view)
display.Shade = 1  # the match's picture is unlit: apply turns Shade off (its look)
ddg.apply(m, source=neghip, view=view, camera=True)
assert display.Shade == 0 and "lighting" not in m.view, (display.Shade, m.view.get("lighting"))
camera = {
    "position": list(view.CameraPosition),
    "focal_point": list(view.CameraFocalPoint),
    "view_up": list(view.CameraViewUp),
}
assert same_camera(camera, m.view["camera"]), camera
assert np.allclose(view.CameraViewUp, m.view["camera"]["view_up"], atol=1e-6)
lut = GetColorTransferFunction(ddg.scene.volume_array(neghip, view))
assert np.allclose(list(lut.RGBPoints), m.tf["RGBPoints"], rtol=1e-6, atol=1e-6)
with open(ddg.export(m, os.path.join(outdir, "matched.json"))) as f:  # the Match's TF as a preset
    assert json.load(f)[0]["RGBPoints"] == m.tf["RGBPoints"], "the export is not the match's TF"
view.UseColorPaletteForBackground = 0
view.Background = m.view["background"]
shot = os.path.join(outdir, "paraview.png")
SaveScreenshot(shot, view, ImageResolution=m.view["size"])
figure = psnr(read_png(shot), read_png(picture_path))
print(f"ParaView's render of the match at its camera vs the picture: PSNR {figure:.2f} dB")
assert figure >= 30, figure

# lighting from a view JSON: Shade and its coefficients; a bad one refused before any write
lit = dict(m.view, lighting={"shade": True, "specular": 0.5, "specular_power": 30})
ddg.apply(m, source=neghip, view=view, lighting=lit)
got = (display.Shade, display.Ambient, display.Diffuse, display.Specular, display.SpecularPower)
assert got == (1, 0, 1, 0.5, 30), got
before = list(lut.RGBPoints)
cool_warm = ddg.data_path("TransferFunctions/neghip_cool_warm.json")
for bad, words in (
    ({"shade": True, "specular": 2}, "must lie in [0, 1]"),
    ({"shine": 1}, "unknown"),
):
    try:
        ddg.apply(cool_warm, source=neghip, view=view, lighting=dict(m.view, lighting=bad))
        raise AssertionError("bad lighting %s was applied" % bad)
    except ddg.DDGError as e:
        print("bad lighting:", e)
        assert words in str(e), e
assert list(lut.RGBPoints) == before and display.Shade == 1, "a refused apply changed the scene"

# a bad camera: refused with the readers' reason before the TF, the lighting or the camera moves
where = list(view.CameraPosition) + [view.CameraViewAngle]
good = m.view["camera"]
for bad, words in (
    (dict(good, position=[0, 0]), "position"),
    (dict(good, view_angle="wide"), "view_angle"),
    (dict(good, view_up=list(np.subtract(good["focal_point"], good["position"]))), "degenerate"),
    ({}, "camera"),
):
    for call in (
        lambda: ddg.apply(cool_warm, source=neghip, view=view, camera={"camera": bad}),
        lambda: ddg.set_camera({"camera": bad} if bad else {}, view),
    ):
        try:
            call()
            raise AssertionError("bad camera %s was set" % bad)
        except ddg.DDGError as e:
            print("bad camera:", e)
            assert words in str(e), e
# a preset ParaView cannot draw: refused before the colour map is made separate or written
with open(cool_warm) as f:
    good_tf = json.load(f)[0]
for bad, words in (
    (dict(good_tf, Points=[0, 0, 0.5, 0, 60, 2.0, 0.5, 0]), "opacity of node 1 is 2"),
    (dict(good_tf, ColorSpace="Banana"), "Banana"),
):
    try:
        ddg.apply(bad, source=neghip, view=view, separate_color_map=True)
        raise AssertionError("bad preset %s was applied" % bad)
    except ddg.DDGError as e:
        print("bad preset:", e)
        assert words in str(e), e
assert display.UseSeparateColorMap == 0, "a refused preset made the colour map separate"
assert list(lut.RGBPoints) == before and display.Shade == 1, "a refused camera changed the TF"
assert list(view.CameraPosition) + [view.CameraViewAngle] == where, "a refused camera moved"

# counts the filter would clamp silently are refused before anything runs
for call, words in (
    (lambda: ddg.match(picture_path, neghip, iterations=-5), "iterations must be a whole number"),
    (lambda: ddg.match(picture_path, neghip, bins=1), "bins must be a whole number from 2"),
    (lambda: ddg.reconstruct(picture_path, neghip, known, iterations=0.5), "iterations"),
):
    try:
        call()
        raise AssertionError("a count out of range was run: " + words)
    except ValueError as e:
        print("bad count:", e)
        assert words in str(e), e

# a picture the match cannot use
uniform = os.path.join(outdir, "uniform.png")
ddg.save_image(np.full((60, 80, 3), 0.4), uniform)
try:
    ddg.match(uniform, neghip)
    raise AssertionError("a uniform picture was matched")
except ddg.DDGError as e:
    print("uniform picture:", e)
    assert "nothing but the background colour" in str(e), e
print("ok")
