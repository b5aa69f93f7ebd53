"""DDG Volume Render in pvpython / pvbatch: happy path and bad input.

Compared: the filter's "Image" output for Tooth (preset + view from Data/) against
`ddg render` of the same files; they run the same Core code, so the images must be identical
(PSNR reported by `ddg compare` >= 99, i.e. exact). Bad inputs (missing/malformed TF,
degenerate view, constant / vector volumes): exactly the filter's error reaches the observer,
the output is empty and nothing crashes.

Usage: pvpython TestVolumeRenderFilter.py PLUGIN DDG DATA TESTDATA OUTDIR
"""
import os
import subprocess
import sys

from paraview import servermanager
from paraview.simple import LoadPlugin, XMLImageDataReader, SaveData, UpdatePipeline
import paraview.simple as simple

plugin, ddg, data, testdata, outdir = sys.argv[1:6]
os.makedirs(outdir, exist_ok=True)
LoadPlugin(plugin, remote=False)

volume = os.path.join(data, "Volumes", "tooth.vti")
tf = os.path.join(data, "TransferFunctions", "tooth_dentin_enamel.json")
view = os.path.join(data, "Views", "tooth_oblique.json")

reader = XMLImageDataReader(FileName=[volume])
render = simple.DDGVolumeRender(Input=reader)
render.TransferFunctionFile = tf
render.ViewFile = view
render.UpdatePipeline()
info = render.GetDataInformation()
assert info.GetExtent()[1] == 399 and info.GetExtent()[3] == 319, info.GetExtent()
out = servermanager.Fetch(render)
assert out.GetPointData().GetArray("RGBA").GetNumberOfComponents() == 4
assert out.GetPointData().GetScalars().GetName() == "Image"

# Write the filter's image as PNG through VTK and compare with ddg render.
from vtkmodules.vtkIOImage import vtkPNGWriter

png = os.path.join(outdir, "filter_tooth.png")
w = vtkPNGWriter()
w.SetFileName(png)
w.SetInputData(out)
w.Write()
ref = os.path.join(outdir, "cli_tooth.png")
subprocess.run(
    [ddg, "render", "--volume", volume, "--tf", tf, "--view", view, "--out", ref],
    check=True,
    stdout=subprocess.DEVNULL,
)
cmp = subprocess.run([ddg, "compare", "--min-psnr", "99", png, ref], capture_output=True, text=True)
print("filter vs ddg render:", cmp.stdout.strip())
assert cmp.returncode == 0, cmp.stderr

# --- bad input: one error, empty output, no crash ------------------------------------------------
# vtkErrorMacro hands its text to ErrorEvent observers (instead of the output window).
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_STRING
from vtkmodules.vtkCommonCore import vtkCommand

algorithm = render.GetClientSideObject()
messages = []


@calldata_type(VTK_STRING)
def on_error(obj, event, calldata):
    messages.append(calldata)


algorithm.AddObserver(vtkCommand.ErrorEvent, on_error)


def expect_error(label, expected, **props):
    messages.clear()
    for key, value in props.items():
        setattr(render, key, value)
    render.UpdatePipeline()
    data_out = servermanager.Fetch(render)
    assert data_out.GetNumberOfPoints() == 0, f"{label}: output should be empty"
    assert len(messages) == 1, f"{label}: expected one error, got {messages}"
    assert expected in messages[0], f"{label}: '{expected}' not in '{messages[0]}'"
    print(f"{label}: {messages[0].strip().splitlines()[-1]}")


expect_error(
    "missing TF",
    "cannot read transfer function",
    TransferFunctionFile=os.path.join(testdata, "nothing.json"),
)
expect_error(
    "malformed TF",
    "not valid JSON",
    TransferFunctionFile=os.path.join(testdata, "malformed_tf.json"),
)
expect_error(
    "unsorted TF", "are not sorted", TransferFunctionFile=os.path.join(testdata, "unsorted_tf.json")
)
expect_error(
    "degenerate view",
    "degenerate camera",
    TransferFunctionFile=tf,
    ViewFile=os.path.join(testdata, "degenerate_view.json"),
)
expect_error("huge view", "out of range", ViewFile=os.path.join(testdata, "huge_size_view.json"))
expect_error(
    "zero-size view",
    "image size 0 x 32 is out of range",
    ViewFile=os.path.join(testdata, "zero_size_view.json"),
)
expect_error(
    "out-of-range TF",
    "outside [0, 1]",
    ViewFile=os.path.join(testdata, "small_view.json"),
    TransferFunctionFile=os.path.join(testdata, "out_of_range_tf.json"),
)
render.TransferFunctionFile = tf
reader.FileName = [os.path.join(testdata, "constant.vti")]
expect_error("constant volume", "volume is constant")
reader.FileName = [os.path.join(testdata, "vector.vti")]
render.Scalars = ["POINTS", "velocity"]
expect_error("vector volume", "components")

reader.FileName = [os.path.join(testdata, "empty.vti")]
render.Scalars = ["POINTS", "scalars"]
expect_error("empty volume", "input volume is empty")

# NaN voxels: rendered (as the minimum) with one warning, not an error.
warnings = []


@calldata_type(VTK_STRING)
def on_warning(obj, event, calldata):
    warnings.append(calldata)


algorithm.AddObserver(vtkCommand.WarningEvent, on_warning)
reader.FileName = [os.path.join(testdata, "nan.vti")]
messages.clear()
render.UpdatePipeline()
assert not messages, messages
assert len(warnings) == 1 and "2 NaN/infinite voxels" in warnings[0], warnings
assert servermanager.Fetch(render).GetNumberOfPoints() == 32 * 24
print("NaN volume:", warnings[0].strip().splitlines()[-1])

# and it recovers on good input
reader.FileName = [os.path.join(testdata, "small.vti")]
render.Scalars = ["POINTS", "scalars"]
messages.clear()
render.UpdatePipeline()
assert not messages, messages
assert servermanager.Fetch(render).GetNumberOfPoints() == 32 * 24
print("ok")
