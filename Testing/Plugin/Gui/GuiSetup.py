"""Scene of a Design Gallery GUI test, run by `paraview --script` before the XML events.

Environment: DDG_GUI_CASE ("tooth": the Tooth volume as a Volume representation at
Data/Views/tooth_oblique.json's camera; "small2d": Testing/Data/small.vti (DDG_TEST_DATA) at
small_view.json's camera, for a 2D model; "constant": Testing/Data/constant.vti at the same
camera, a volume no design space can be built for; "sphere": a Sphere source, not a volume;
"tooth-twin": "tooth" and a second reader of tooth.vti ("twin.vti") shown after it as a volume
coloured by the same array, Tooth selected),
DDG_DATA_DIR, DDG_GUI_RECORD (a file that gets one JSON line per change of the volume's colour
map RGBPoints, starting with the initial one: what the panel wrote, read back from the LUT proxy;
"tooth" also writes DDG_GUI_RECORD + ".camera", one line per change of the view's
CameraPosition property;
"small2d" and "constant": per change of UseTransfer2D or the TransferFunction2D's Boxes, Range or
OutputDimensions, {"use2d": 0/1, "boxes": [...], "range": [...], "dims": [...]}).
"""
import json
import os

from paraview.simple import *

data = os.environ["DDG_DATA_DIR"]
record = os.environ["DDG_GUI_RECORD"]
view = GetActiveViewOrCreate("RenderView")
layout = GetLayout()
layout.SetSize(400, 400)
if os.environ.get("DDG_GUI_CASE") == "sphere":
    sphere = Sphere()
    Show(sphere, view)
    SetActiveSource(sphere)
    Render()
else:
    case = os.environ.get("DDG_GUI_CASE")
    small = case in ("small2d", "constant")
    path = (
        os.path.join(
            os.environ["DDG_TEST_DATA"], "constant.vti" if case == "constant" else "small.vti"
        )
        if small
        else os.path.join(data, "Volumes", "tooth.vti")
    )
    volume = XMLImageDataReader(registrationName=os.path.basename(path), FileName=[path])
    volume.UpdatePipeline()
    display = Show(volume, view)
    display.SetRepresentationType("Volume")
    array = volume.PointData.keys()[0]
    ColorBy(display, ("POINTS", array))
    view_file = (
        os.path.join(os.environ["DDG_TEST_DATA"], "small_view.json")
        if small
        else os.path.join(data, "Views", "tooth_oblique.json")
    )
    camera = json.load(open(view_file))["camera"]
    view.CameraPosition = camera["position"]
    view.CameraFocalPoint = camera["focal_point"]
    view.CameraViewUp = camera["view_up"]
    view.CameraViewAngle = camera.get("view_angle", 30)
    view.OrientationAxesVisibility = 0
    lut = GetColorTransferFunction(array)

    def write(*_):
        with open(record, "a") as f:
            if small:
                state = {
                    "use2d": display.UseTransfer2D,
                    "boxes": list(display.TransferFunction2D.Boxes),
                    "range": list(display.TransferFunction2D.Range),
                    "dims": list(display.TransferFunction2D.OutputDimensions),
                }
            else:
                state = list(lut.RGBPoints)
            f.write(json.dumps(state) + "\n")

    open(record, "w").close()
    write()
    if small:
        display.SMProxy.GetProperty("UseTransfer2D").AddObserver("ModifiedEvent", write)
        for name in ("Boxes", "Range", "OutputDimensions"):
            display.TransferFunction2D.SMProxy.GetProperty(name).AddObserver("ModifiedEvent", write)
    else:
        lut.SMProxy.GetProperty("RGBPoints").AddObserver("ModifiedEvent", write)

        def write_camera(*_):
            with open(record + ".camera", "a") as f:
                f.write(json.dumps(list(view.CameraPosition)) + "\n")

        open(record + ".camera", "w").close()
        write_camera()
        view.SMProxy.GetProperty("CameraPosition").AddObserver("ModifiedEvent", write_camera)
    if case == "tooth-twin":  # a second volume after Tooth, sharing its colour map
        twin = XMLImageDataReader(registrationName="twin.vti", FileName=[path])
        twin_display = Show(twin, view)
        twin_display.SetRepresentationType("Volume")
        ColorBy(twin_display, ("POINTS", array))
    SetActiveSource(volume)
    Render()
