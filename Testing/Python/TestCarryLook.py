"""ddg.carry_look and ddg.apply: another volume's picture carried over (build/bin/pvpython).

A picture of the iron protein (the project's render, `ddg render`, of neghip_shells.json at
neghip_oblique.json's camera over ParaView's palette background) is carried over to NegHip, an
electron density of the same kind: the CarriedLook holds 1-4 regions of NegHip's values (in
value order, colours in [0, 1]), the colour distance goes down, its image is the view's size;
ddg.apply(look.tf) writes the preset into NegHip's colour map (1e-6). With Shade on the look is
fitted lit (apply sets Shade on), shade=False fits it unlit at the same seed, and seed= changes
the fit. The shipped kind network's figure comes with the look (kind=False: none). Bad input: a uniform
picture raises DDGError naming it, and the colour map is unchanged.

Usage: build/bin/pvpython TestCarryLook.py DDG OUTDIR
"""
import json
import os
import subprocess
import sys

import numpy as np

import ddg
from paraview.simple import GetActiveViewOrCreate, GetColorTransferFunction, Render, Show
from paraview.simple import XMLImageDataReader

ddg_exe, outdir = sys.argv[1:3]
os.makedirs(outdir, exist_ok=True)
with open(ddg.data_path("Views/neghip_oblique.json")) as f:
    view = json.load(f)
view["size"] = [240, 180]
view["background"] = [0.32, 0.34, 0.43]
view_path = os.path.join(outdir, "picture_view.json")
with open(view_path, "w") as f:
    json.dump(view, f)
picture = os.path.join(outdir, "ironprot.png")
subprocess.run(
    [ddg_exe, "render", "--volume", ddg.data_path("Volumes/ironprot.vti"), "--view", view_path]
    + ["--tf", ddg.data_path("TransferFunctions/neghip_shells.json"), "--out", picture],
    check=True,
)

neghip = XMLImageDataReader(FileName=[ddg.data_path("Volumes/neghip.vti")])
render_view = GetActiveViewOrCreate("RenderView")
display = Show(neghip, render_view)
look = ddg.carry_look(picture, neghip)
print(look)
for r in look.regions:
    print(
        "  values %.1f-%.1f <- colour %s, %.0f %%" % (*r["values"], r["colour"], 100 * r["share"])
    )
assert 1 <= len(look.regions) <= 4, look.regions
assert all(r["values"][0] < r["values"][1] for r in look.regions)
assert [r["values"][0] for r in look.regions] == sorted(r["values"][0] for r in look.regions)
assert all(0 <= c <= 1 for r in look.regions for c in r["colour"])
assert look.distance_end < look.distance_start, (look.distance_start, look.distance_end)
assert look.image.shape == (256, 256, 3), look.image.shape
assert look.view["size"] == [256, 256]
# the shipped kind network checked the picture against NegHip (kind=True, the default): its
# figure, the threshold it was calibrated to, and the verdict that follows from the two
with open(ddg.data_path("Models/kind/kind.json")) as f:
    threshold = json.load(f)["threshold"]
assert look.kind is not None and 0 <= look.kind["agreement"] <= 1 + 1e-9, look.kind
assert abs(look.kind["threshold"] - threshold) < 1e-12, (look.kind, threshold)
assert look.kind_differs == (look.kind["agreement"] < threshold), look.kind
assert "kind agreement %.2f" % look.kind["agreement"] in repr(look), repr(look)
try:
    ddg.carry_look(picture, neghip, kind=outdir)
    raise AssertionError("a directory without kind.json was taken for a kind network")
except ddg.DDGError as e:
    assert "is not a kind network" in str(e), e
# from a TF of this volume (a query's design, here the look itself): the fit starts there, so
# its start is already nearer the picture than the regions' rank-matched colours were
again = ddg.carry_look(picture, neghip, initial=look, kind=False)
assert again.kind is None and not again.kind_differs, again.kind
print("from the look: %.2f -> %.2f" % (again.distance_start, again.distance_end))
assert again.distance_start < look.distance_start, (again.distance_start, look.distance_start)
assert len(again.regions) == len(look.regions)
try:
    ddg.carry_look(picture, neghip, initial={"Points": [0, 0, 0.5, 0]})
    raise AssertionError("a TF without colours started the carried look")
except ValueError as e:
    assert "initial is a 1D transfer function" in str(e), e

array = neghip.PointData.keys()[0]
lut = GetColorTransferFunction(array)
Render(render_view)  # the first render resets the camera
camera_before = render_view.CameraPosition[:]
try:  # another volume's picture: no camera to move to, and nothing written
    ddg.apply(look, source=neghip, view=render_view, camera=True)
    raise AssertionError("a carried look moved the camera")
except ValueError as e:
    print("camera=True:", e)
    assert "carried look has no camera" in str(e), e
assert list(lut.RGBPoints) != list(look.tf["RGBPoints"]), "a refused apply wrote the TF"
ddg.apply(look, source=neghip, view=render_view)  # the CarriedLook itself, as a Match is applied
assert np.allclose(list(lut.RGBPoints), look.tf["RGBPoints"], atol=1e-6), "not applied"
assert list(render_view.CameraPosition) == list(camera_before), "the camera moved"
exported = ddg.export(look, os.path.join(outdir, "carried.json"))
with open(exported) as f:
    preset = json.load(f)[0]
assert preset["RGBPoints"] == look.tf["RGBPoints"], "the export is not the carried look's TF"
assert preset["Name"].startswith("DDG "), preset["Name"]

# the lighting: the look is fitted under the one NegHip has in the view (Shade on here), unless
# shade= says otherwise; apply sets it; seed= draws other colour-distance directions
assert "lighting" not in look.view, look.view
display.Shade = 1
lit = ddg.carry_look(picture, neghip, seed=7)
unlit = ddg.carry_look(picture, neghip, shade=False, seed=7)
print(
    "lit: %.2f -> %.2f, unlit: %.2f -> %.2f"
    % (lit.distance_start, lit.distance_end, unlit.distance_start, unlit.distance_end)
)
assert lit.view.get("lighting", {}).get("shade") is True, lit.view
assert "lighting" not in unlit.view, unlit.view
# the same seed: only the lighting differs (the start's distance is measured at a fixed seed)
assert lit.tf["RGBPoints"] != unlit.tf["RGBPoints"], "Shade on gave the unlit fit"
assert abs(lit.distance_start - unlit.distance_start) > 1e-3 * unlit.distance_start
assert unlit.tf["RGBPoints"] != look.tf["RGBPoints"], "seed=7 gave seed 1's fit"
try:
    ddg.carry_look(picture, neghip, seed=-1)
    raise AssertionError("a negative seed was taken")
except ValueError as e:
    assert "seed must be a whole number" in str(e), e
display.Shade = 0
ddg.apply(lit, source=neghip, view=render_view)
assert display.Shade == 1, "apply did not set the carried look's lighting"
ddg.apply(unlit, source=neghip, view=render_view)
assert display.Shade == 0, "apply did not set the carried look's lighting"

before = list(lut.RGBPoints)
uniform = os.path.join(outdir, "uniform.png")
ddg.save_image(np.full((60, 80, 3), 0.4), uniform)
try:
    ddg.carry_look(uniform, neghip)
    raise AssertionError("a uniform picture's look was carried")
except ddg.DDGError as e:
    print("uniform picture:", e)
    assert "nothing but its background colour" in str(e), e
assert list(lut.RGBPoints) == before, "a refused carry changed the scene"
print("ok")
