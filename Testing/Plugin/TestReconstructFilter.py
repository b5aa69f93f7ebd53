"""DDG Reconstruct Transfer Function in pvpython: a ParaView screenshot -> TF -> applied in ParaView.

Compared: a shipped ParaView screenshot of Tooth (Data/Screenshots/tooth_dentin_enamel_oblique.png,
white background, the tooth_oblique camera; its own view file states white) is the target; the
filter's "Preset" (field data) is applied to the reader's Volume representation (LookupTable
RGBPoints, ScalarOpacityFunction Points) and ParaView renders it at the same camera over white.
ParaView's render must match the screenshot (PSNR >= 35 dB, `ddg compare`; `ddg reconstruct`
reaches ~56 dB on this case), the table must hold one row per bin, OutputFile must hold the same
preset, named for the array, "reconstruction", the file's stem and the time.

The background setting: the same screenshot with the grey view file (Data/Views/tooth_oblique.json,
the documented route) and EstimateBackground on (the default) must warn once that the border
disagrees and report white in "Background" (within 2 levels of 255); the preset is then the
screenshot's TF: ParaView's render of it over the grey view matches ParaView's render of the
preset the screenshot was made with (Data/TransferFunctions/tooth_dentin_enamel.json) over grey
(>= 35 dB). With EstimateBackground off and the view's grey as Background (what the filter did
before it had the setting) it warns too, and that comparison fails by far (< 25 dB: a white fog
box painted over the grey it assumed).

Bad input (target of the wrong size, missing target, missing view): exactly one error, empty
output, no crash.

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
view_path = os.path.join(data, "Screenshots", "tooth_dentin_enamel_oblique.json")  # its own view
with open(view_path) as f:
    view_json = json.load(f)
assert view_json["background"] == [1.0, 1.0, 1.0], "the screenshot was saved over white"

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
assert preset["Name"].startswith("DDG scalars reconstruction reconstructed_preset 20"), preset[
    "Name"
]
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

# --- the background setting: the screenshot with the grey view file (the documented route) ------
from vtkmodules.util.misc import calldata_type  # noqa: E402
from vtkmodules.util.vtkConstants import VTK_STRING  # noqa: E402
from vtkmodules.vtkCommonCore import vtkCommand  # noqa: E402

warnings = []


@calldata_type(VTK_STRING)
def on_warning(obj, event, calldata):
    warnings.append(calldata)


rec.GetClientSideObject().AddObserver(vtkCommand.WarningEvent, on_warning)
grey_view = os.path.join(data, "Views", "tooth_oblique.json")
with open(grey_view) as f:
    grey_json = json.load(f)
with open(os.path.join(data, "TransferFunctions", "tooth_dentin_enamel.json")) as f:
    truth = json.load(f)[0]
truth_png = os.path.join(outdir, "grey_view_truth.png")
paraview_render(volume, truth, grey_json, truth_png)
rec.ViewFile = grey_view
rec.OutputFile = ""


def grey_route(label, **props):
    warnings.clear()
    for key, value in props.items():
        setattr(rec, key, value)
    rec.UpdatePipeline()
    out = servermanager.Fetch(rec)
    bg = out.GetFieldData().GetArray("Background")
    background = [bg.GetValue(i) for i in range(3)]
    p = json.loads(out.GetFieldData().GetAbstractArray("Preset").GetValue(0))[0]
    png = os.path.join(outdir, f"grey_view_{label.replace(' ', '_')}.png")
    paraview_render(volume, p, grey_json, png)
    c = subprocess.run([ddg, "compare", png, truth_png], capture_output=True, text=True, check=True)
    value = float(c.stdout.split("PSNR")[1].split()[0])
    print(
        f"grey view, {label}: background {[round(v, 3) for v in background]}; over grey, "
        f"ParaView's render of the preset vs of the screenshot's preset {value:.2f} dB; "
        f"warnings {len(warnings)}"
    )
    assert len(warnings) == 1 and "border" in warnings[0], f"{label}: {warnings}"
    return background, value


background, estimated = grey_route("estimated", EstimateBackground=1)
assert all(abs(v - 1.0) <= 2 / 255 for v in background), background
assert estimated >= 35, estimated
grey = [0.329, 0.349, 0.427]
background, stated = grey_route("stated grey", EstimateBackground=0, Background=grey)
assert background == grey, background
assert stated < 25, stated
rec.EstimateBackground = 1
rec.ViewFile = view_path

# --- bad input: one error, empty output, no crash --------------------------------------------

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
