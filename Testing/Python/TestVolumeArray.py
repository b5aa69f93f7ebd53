"""The volume's array (`ddg.scene.volume_array`): the package uses the array ParaView colours by,
the active point scalars as the Design Gallery panel does, not the first point array.

Compared: a copy of Tooth whose point data holds a decoy one-component array first (Tooth's values
reversed) and Tooth's values second, as the active scalars, against tooth.vti itself:
- `ddg.render` of the copy is identical to the render of tooth.vti (exact, uint8);
- `ddg.query` on the copy finds the same neighbours and TF as on tooth.vti (exact);
- `ddg.apply` colours the copy's display by the active array and writes the TF into its maps;
- once the display is coloured by the decoy, the decoy is the volume's array (the render differs
  from Tooth's by more than 10 grey levels on average); hidden, the active scalars are again;
- a volume whose active scalars have 3 components (Testing/Data/vector.vti) raises ValueError.

Usage: build/bin/pvpython TestVolumeArray.py TESTDATA OUTDIR
"""
import json
import os
import sys

import numpy as np
from vtkmodules.util import numpy_support
from vtkmodules.vtkIOXML import vtkXMLImageDataReader, vtkXMLImageDataWriter
from vtkmodules.vtkCommonDataModel import vtkImageData

import ddg
from ddg.scene import volume_array
from paraview.simple import ColorBy, GetColorTransferFunction, Hide, Show, XMLImageDataReader

testdata, outdir = sys.argv[1:3]
os.makedirs(outdir, exist_ok=True)
checks = []


def check(name, ok, detail=""):
    checks.append(name)
    assert ok, f"{name}: {detail}"
    print(f"ok {name} {detail}")


# the copy: "decoy" first, Tooth's array second and active
tooth_file = ddg.data_path("Volumes/tooth.vti")
reader = vtkXMLImageDataReader()
reader.SetFileName(tooth_file)
reader.Update()
values = reader.GetOutput().GetPointData().GetScalars()
name = values.GetName()
a = numpy_support.vtk_to_numpy(values)
decoy = numpy_support.numpy_to_vtk(
    a.max() - a + a.min(), deep=True, array_type=values.GetDataType()
)
decoy.SetName("decoy")
two = vtkImageData()
two.CopyStructure(reader.GetOutput())
two.GetPointData().AddArray(decoy)
two.GetPointData().AddArray(values)
two.GetPointData().SetActiveScalars(name)
copy_file = os.path.join(outdir, "tooth_two_arrays.vti")
writer = vtkXMLImageDataWriter()
writer.SetFileName(copy_file)
writer.SetInputData(two)
writer.Write()

tooth = XMLImageDataReader(FileName=[tooth_file])
copy = XMLImageDataReader(FileName=[copy_file])
check(
    "the copy's first point array is the decoy",
    copy.PointData.keys() == ["decoy", name],
    f"{copy.PointData.keys()}, active '{name}'",
)
check("volume_array: the active scalars", volume_array(copy) == name, name)

view_file = ddg.data_path("Views/tooth_oblique.json")
view = json.load(open(view_file))
view["size"] = [200, 160]
preset = ddg.data_path("TransferFunctions/tooth_dentin_enamel.json")
reference = ddg.render(tooth, preset, view)
check("render", np.array_equal(ddg.render(copy, preset, view), reference), "identical to Tooth's")

shot = ddg.data_path("Screenshots/tooth_dentin_enamel_oblique.png")
model = ddg.data_path("Models/tooth")
on_tooth = ddg.query(shot, tooth, view_file, ddg.load_model(model, tooth))
on_copy = ddg.query(shot, copy, view_file, ddg.load_model(model, copy))
check(
    "query",
    on_copy.neighbours == on_tooth.neighbours
    and on_copy.transfer_function(view_file) == on_tooth.transfer_function(view_file),
    f"neighbours {on_copy.neighbours}, as on Tooth",
)

display = Show(copy)
ddg.set_camera(view_file)
ddg.apply(on_copy, display, copy)
tf = on_copy.transfer_function(ddg.view_json(None, copy, 256))
check(
    "apply",
    list(display.ColorArrayName) == ["POINTS", name]
    and list(GetColorTransferFunction(name).RGBPoints) == tf["RGBPoints"],
    f"coloured by '{name}'",
)

ColorBy(display, ("POINTS", "decoy"))
difference = np.abs(ddg.render(copy, preset, view).astype(float) - reference).mean()
check(
    "a display coloured by the decoy",
    volume_array(copy) == "decoy" and difference > 10,
    f"volume_array 'decoy', render {difference:.1f} grey levels from Tooth's",
)
Hide(copy)
check("hidden: the active scalars again", volume_array(copy) == name)

vector = XMLImageDataReader(FileName=[os.path.join(testdata, "vector.vti")])
try:
    ddg.render(
        vector, os.path.join(testdata, "small_tf.json"), os.path.join(testdata, "small_view.json")
    )
    raise AssertionError("a 3-component active array should raise")
except ValueError as e:
    check("3-component active scalars raise", "3 components" in str(e), str(e))

print(f"{len(checks)} checks passed")
