"""DDG Build Design Space in pvpython: a bundle for a volume, then the gallery filters on it.

Compared: the filter builds a tiny design space for the small test volume (16 exemplars of 16 px,
10 iterations, 20 outline designs); the bundle must hold bundle.json and outline.bin, the output
table its held-out figures, and DDG Design Gallery must read it (20 designs, 4 thumbnails). Bad
input (no output directory, a folder that holds a bundle, a constant volume): one error, empty output, no bundle.json, and the
reason in the filter's LastError (empty again after a build that finished), which is what the
panel reads to report a failed build as failed.

Usage: pvpython TestBuildFilter.py PLUGIN DDG DATA TESTDATA OUTDIR
"""
import os
import shutil
import sys

from paraview import servermanager
from paraview.simple import LoadPlugin, XMLImageDataReader
import paraview.simple as simple

plugin, ddg, data, testdata, outdir = sys.argv[1:6]
os.makedirs(outdir, exist_ok=True)
LoadPlugin(plugin, remote=False)
bundle = os.path.join(outdir, "built_bundle")
shutil.rmtree(bundle, ignore_errors=True)

reader = XMLImageDataReader(FileName=[os.path.join(testdata, "small.vti")])
build = simple.DDGBuildDesignSpace(Input=reader)
build.OutputDirectory = bundle
build.Count = 16
build.Size = 16
build.Iterations = 10
build.OutlineCount = 20
build.UpdatePipeline()
table = servermanager.Fetch(build)
assert table.GetNumberOfRows() == 1, table.GetNumberOfRows()
psnr = table.GetColumnByName("PSNR").GetValue(0)
assert os.path.exists(os.path.join(bundle, "bundle.json")) and os.path.exists(
    os.path.join(bundle, "outline.bin")
)
print(f"built {bundle}: held-out PSNR {psnr:.2f} dB")


def last_error():
    build.UpdatePropertyInformation()
    return build.GetPropertyValue("LastError")


assert last_error() == "", last_error()

gal = simple.DDGDesignGallery(Input=reader)
gal.ModelDirectory = bundle
gal.Count = 4
gal.ThumbnailSize = 16
gal.UpdatePipeline()
designs = servermanager.Fetch(gal, idx=1)
assert designs.GetNumberOfRows() == 20, designs.GetNumberOfRows()

from vtkmodules.util.misc import calldata_type  # noqa: E402
from vtkmodules.util.vtkConstants import VTK_STRING  # noqa: E402
from vtkmodules.vtkCommonCore import vtkCommand  # noqa: E402

messages = []


@calldata_type(VTK_STRING)
def on_error(obj, event, calldata):
    messages.append(calldata)


build.GetClientSideObject().AddObserver(vtkCommand.ErrorEvent, on_error)
for label, expected, setup in (
    (
        "no output directory",
        "no OutputDirectory set",
        lambda: setattr(build, "OutputDirectory", ""),
    ),
    (
        "a folder holding a bundle",
        "already holds a model bundle",
        lambda: setattr(build, "OutputDirectory", bundle),
    ),
    (
        "constant volume",
        "the volume has one value (42) everywhere",
        lambda: (
            setattr(build, "OutputDirectory", os.path.join(outdir, "built_constant")),
            setattr(reader, "FileName", [os.path.join(testdata, "constant.vti")]),
        ),
    ),
):
    messages.clear()
    setup()
    build.UpdatePipeline()
    assert servermanager.Fetch(build).GetNumberOfRows() == 0, label
    assert len(messages) == 1 and expected in messages[0], (label, messages)
    assert expected in last_error(), (label, last_error())
    print(f"{label}: {messages[0].strip().splitlines()[-1]}")
assert not os.path.exists(os.path.join(outdir, "built_constant", "bundle.json"))
print("ok")
