"""Helpers shared by the plugin's pvpython tests."""
import json
import os

from paraview import servermanager
import paraview.simple as simple
from vtkmodules.vtkCommonCore import VTK_STRING, vtkCommand
from vtkmodules.util.misc import calldata_type


class Errors:
    """Collects the error messages a filter reports (its client-side object: builtin sessions)."""

    def __init__(self, proxy):
        self.messages = []
        self.proxy = proxy

        @calldata_type(VTK_STRING)
        def on_error(obj, event, calldata):
            self.messages.append(calldata)

        proxy.GetClientSideObject().AddObserver(vtkCommand.ErrorEvent, on_error)

    def expect(self, label, expected, port=0, **props):
        """Sets `props`, updates: exactly one error containing `expected` and an empty output."""
        self.messages.clear()
        for key, value in props.items():
            setattr(self.proxy, key, value)
        self.proxy.UpdatePipeline()
        data = servermanager.Fetch(self.proxy, idx=port)
        assert (
            data.GetNumberOfElements(0) == 0 and data.GetNumberOfElements(6) == 0
        ), f"{label}: output {port} should be empty"
        assert len(self.messages) == 1, f"{label}: expected one error, got {self.messages}"
        assert expected in self.messages[0], f"{label}: '{expected}' not in '{self.messages[0]}'"
        print(f"{label}: {self.messages[0].strip().splitlines()[-1]}")


def apply_and_render(source, preset, view_file, out_png, size=(320, 320)):
    """Shows `source` as a volume with a ParaView preset (dict) at a view JSON's camera, saves a
    screenshot and returns its size in bytes (the file is removed)."""
    display = simple.Show(source)
    display.SetRepresentationType("Volume")
    array = source.PointData.keys()[0]
    simple.ColorBy(display, ("POINTS", array))
    lut = simple.GetColorTransferFunction(array)
    lut.AutomaticRescaleRangeMode = "Never"
    lut.RGBPoints = preset["RGBPoints"]
    simple.GetOpacityTransferFunction(array).Points = preset["Points"]
    camera = json.load(open(view_file))["camera"]
    view = simple.GetActiveView()
    view.CameraPosition, view.CameraFocalPoint = camera["position"], camera["focal_point"]
    view.CameraViewUp = camera["view_up"]
    simple.SaveScreenshot(out_png, view, ImageResolution=list(size))
    assert list(lut.RGBPoints) == list(preset["RGBPoints"]), "the LUT does not hold the preset"
    bytes_ = os.path.getsize(out_png)
    os.remove(out_png)
    simple.Hide(source)
    return bytes_
