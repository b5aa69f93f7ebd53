"""DDG Reconstruct Transfer Function in pvpython: a ParaView screenshot -> TF -> applied in ParaView.

Compared: a shipped ParaView screenshot of Tooth (Data/Screenshots/tooth_dentin_enamel_oblique.png,
white background, the tooth_oblique camera) is the target; the filter's "Preset" (field data) is
applied to the reader's Volume representation (LookupTable RGBPoints, ScalarOpacityFunction
Points) and ParaView renders it at the same camera. ParaView's render must match the screenshot
(PSNR >= 35 dB, `ddg compare`; `ddg reconstruct` reaches ~56 dB on this case), the table must
hold one row per bin, and OutputFile must hold the same preset. Bad input (target of the wrong
size, missing target, missing view): exactly one error, empty output, no crash.

Usage: pvpython TestReconstructFilter.py PLUGIN DDG DATA TESTDATA OUTDIR
"""
import json
import os
import subprocess
import sys

from paraview import servermanager
from paraview.simple import LoadPlugin, XMLImageDataReader
import paraview.simple as simple

plugin, ddg, data, testdata, outdir = sys.argv[1:6]
os.makedirs(outdir, exist_ok=True)
LoadPlugin(plugin, remote=False)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Parity"))
from pvrender import paraview_render  # noqa: E402

volume = os.path.join(data, "Volumes", "tooth.vti")
shot = os.path.join(data, "Screenshots", "tooth_dentin_enamel_oblique.png")
with open(os.path.join(data, "Views", "tooth_oblique.json")) as f:
    view_json = json.load(f)
view_json["background"] = [1.0, 1.0, 1.0]  # the screenshot's
view_path = os.path.join(outdir, "tooth_oblique_white.json")
with open(view_path, "w") as f:
    json.dump(view_json, f)

reader = XMLImageDataReader(FileName=[volume])
rec = simple.DDGReconstructTransferFunction(Input=reader)
rec.TargetImageFile = shot
rec.ViewFile = view_path
rec.Iterations = 300
rec.OutputFile = os.path.join(outdir, "reconstructed_preset.json")
rec.UpdatePipeline()
table = servermanager.Fetch(rec)
assert table.GetNumberOfRows() == 128, table.GetNumberOfRows()
for name in ("Value", "Red", "Green", "Blue", "Opacity"):
    assert table.GetColumnByName(name) is not None, name
preset_text = table.GetFieldData().GetAbstractArray("Preset").GetValue(0)
preset = json.loads(preset_text)[0]
with open(rec.OutputFile) as f:
    assert json.load(f)[0] == preset, "OutputFile differs from the Preset field"
iterations = table.GetFieldData().GetArray("Iterations").GetValue(0)

out_png = os.path.join(outdir, "reconstructed_paraview.png")
paraview_render(volume, preset, view_json, out_png)
cmp = subprocess.run([ddg, "compare", out_png, shot], capture_output=True, text=True, check=True)
psnr = float(cmp.stdout.split("PSNR")[1].split()[0])
print(
    f"reconstructed in {iterations} steps; ParaView's render with the preset vs the screenshot: "
    f"PSNR {psnr:.2f} dB"
)
assert psnr >= 35, psnr

# --- bad input: one error, empty output, no crash --------------------------------------------
from vtkmodules.util.misc import calldata_type  # noqa: E402
from vtkmodules.util.vtkConstants import VTK_STRING  # noqa: E402
from vtkmodules.vtkCommonCore import vtkCommand  # noqa: E402

messages = []


@calldata_type(VTK_STRING)
def on_error(obj, event, calldata):
    messages.append(calldata)


rec.GetClientSideObject().AddObserver(vtkCommand.ErrorEvent, on_error)


def expect_error(label, expected, **props):
    messages.clear()
    for key, value in props.items():
        setattr(rec, key, value)
    rec.UpdatePipeline()
    out = servermanager.Fetch(rec)
    assert out.GetNumberOfRows() == 0, f"{label}: output should be empty"
    assert len(messages) == 1, f"{label}: expected one error, got {messages}"
    assert expected in messages[0], f"{label}: '{expected}' not in '{messages[0]}'"
    print(f"{label}: {messages[0].strip().splitlines()[-1]}")


rec.OutputFile = ""
rec.Iterations = 5
expect_error(
    "wrong size",
    "save the screenshot at the view's size",
    TargetImageFile=os.path.join(testdata, "small_target_40x30.png"),
)
expect_error(
    "missing target", "cannot read image", TargetImageFile=os.path.join(testdata, "none.png")
)
expect_error("no view", "no ViewFile or ViewJSON set", TargetImageFile=shot, ViewFile="")
print("ok")
