"""A queried design's ParaView preset loads in ParaView and reproduces the design.

Compared: `ddg query` on the shipped Tooth bundle with a shipped screenshot writes the decoded TF
as a ParaView preset; pvpython imports it (ImportPresets), applies it to the Volume
representation's LookupTable and ScalarOpacityFunction, and renders at the query's view. The
LUT's RGBPoints and the opacity Points must equal the file's nodes (1e-9), and ParaView's render
must match the ray cast of the same preset by `ddg render` (PSNR >= 40 dB: ParaView's GPU ray
caster against ours, as in Testing/Parity).

Usage: pvpython TestQueryPresetInParaView.py DDG DATA OUTDIR
"""
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Parity"))
from pvrender import paraview_render  # noqa: E402
from paraview.simple import (  # noqa: E402
    GetColorTransferFunction,
    GetOpacityTransferFunction,
    ImportPresets,
    XMLImageDataReader,
)

ddg, data, outdir = sys.argv[1:4]
os.makedirs(outdir, exist_ok=True)
volume = os.path.join(data, "Volumes", "tooth.vti")
view_path = os.path.join(data, "Views", "tooth_oblique.json")
shot = os.path.join(data, "Screenshots", "tooth_dentin_enamel_oblique.png")
preset_path = os.path.join(outdir, "query_preset.json")
subprocess.run(
    [
        ddg,
        "query",
        "--model",
        os.path.join(data, "Models", "tooth"),
        "--volume",
        volume,
        "--image",
        shot,
        "--view",
        view_path,
        "--out-tf",
        preset_path,
    ],
    check=True,
)

with open(preset_path) as f:
    preset = json.load(f)[0]
assert preset["RGBPoints"] and preset["Points"], "empty preset"
assert ImportPresets(preset_path), "ParaView did not import the preset"
array = XMLImageDataReader(FileName=[volume]).PointData.keys()[0]
lut = GetColorTransferFunction(array)
lut.ApplyPreset(preset["Name"], False)
pwf = GetOpacityTransferFunction(array)
pwf.ApplyPreset(preset["Name"], False)
for got, want, what in (
    (lut.RGBPoints, preset["RGBPoints"], "RGBPoints"),
    (pwf.Points, preset["Points"], "Points"),
):
    got = list(got)
    assert len(got) == len(want), f"{what}: {len(got)} values, the file has {len(want)}"
    assert max(abs(a - b) for a, b in zip(got, want)) < 1e-9, f"{what} differ from the file"

with open(view_path) as f:
    view_json = json.load(f)
pv_png = os.path.join(outdir, "query_paraview.png")
ddg_png = os.path.join(outdir, "query_ddg.png")
paraview_render(volume, preset, view_json, pv_png)
subprocess.run(
    [ddg, "render", "--volume", volume, "--tf", preset_path, "--view", view_path, "--out", ddg_png],
    check=True,
    stdout=subprocess.DEVNULL,
)
out = subprocess.run(
    [ddg, "compare", pv_png, ddg_png], check=True, capture_output=True, text=True
).stdout
psnr = float(out.split("PSNR")[1].split()[0])
print(
    f"queried preset: {len(preset['RGBPoints']) // 4} colour and {len(preset['Points']) // 4} opacity nodes; "
    f"ParaView vs ddg render PSNR {psnr:.2f} dB"
)
assert psnr >= 40, f"ParaView's render of the queried preset differs from ours: {psnr:.2f} dB"
