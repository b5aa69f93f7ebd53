"""ParaView renders of a volume with a preset and a view JSON, shared by the parity and
round-trip tests (run with pvpython under a display)."""
from paraview.simple import (
    ColorBy,
    CreateView,
    Delete,
    GetColorTransferFunction,
    GetOpacityTransferFunction,
    Render,
    SaveScreenshot,
    Show,
    XMLImageDataReader,
)


# The view JSON's "lighting" the parity and round-trip tests use (--lighting NAME)
LIGHTINGS = {
    "off": None,
    "shade": {"shade": True},
    "shade-specular": {"shade": True, "specular": 0.5, "specular_power": 30},
}


def paraview_render(volume_path, preset, view_json, out_png, boxes_2d=None):
    """Renders with a 1D ``preset`` or, when ``boxes_2d`` is given (the TransferFunction2D
    properties of `ddg export --format paraview-2d`), with ParaView's 2D TF (UseTransfer2D)."""
    reader = XMLImageDataReader(FileName=[volume_path])
    view = CreateView("RenderView")
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = view_json.get("background", [0.329, 0.349, 0.427])
    size = view_json.get("size", [512, 512])
    view.ViewSize = size
    display = Show(reader, view)
    array = reader.PointData.keys()[0]
    ColorBy(display, ("POINTS", array))
    display.SetRepresentationType("Volume")
    # the view JSON's "lighting" (ParaView's defaults for the keys it leaves out)
    lighting = view_json.get("lighting") or {}
    display.Shade = int(bool(lighting.get("shade", False)))
    display.Ambient = lighting.get("ambient", 0.0)
    display.Diffuse = lighting.get("diffuse", 1.0)
    display.Specular = lighting.get("specular", 0.0)
    display.SpecularPower = lighting.get("specular_power", 100.0)
    lut = GetColorTransferFunction(array)
    pwf = GetOpacityTransferFunction(array)
    lut.AutomaticRescaleRangeMode = "Never"
    if boxes_2d:
        display.UseTransfer2D = 1
        display.UseGradientForTransfer2D = 1
        tf2 = display.TransferFunction2D
        tf2.Range = boxes_2d["Range"]
        tf2.OutputDimensions = boxes_2d["OutputDimensions"]
        tf2.Boxes = boxes_2d["Boxes"]
    else:
        lut.ColorSpace = preset.get("ColorSpace", "RGB")
        lut.HSVWrap = int(preset.get("HSVWrap", 0))
        lut.RGBPoints = preset["RGBPoints"]
        pwf.Points = preset["Points"]
    if view_json.get("opacity_unit_distance"):
        display.ScalarOpacityUnitDistance = view_json["opacity_unit_distance"]
    Render(view)  # the first render resets the camera: set ours afterwards
    cam = view_json["camera"]
    view.CameraPosition = cam["position"]
    view.CameraFocalPoint = cam["focal_point"]
    view.CameraViewUp = cam["view_up"]
    view.CameraViewAngle = cam.get("view_angle", 30.0)
    view.CameraParallelProjection = int(cam.get("parallel_projection", False))
    view.CameraParallelScale = cam.get("parallel_scale", 1.0)
    Render(view)
    SaveScreenshot(out_png, view, ImageResolution=size, TransparentBackground=0)
    Delete(display)
    Delete(view)
    Delete(reader)
