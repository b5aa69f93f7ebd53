"""Scene of a Design Gallery GUI test, run by `paraview --script` before the XML events.

Environment: DDG_GUI_CASE ("tooth": the Tooth volume as a Volume representation at
Data/Views/tooth_oblique.json's camera; "sphere": a Sphere source, not a volume), DDG_DATA_DIR,
DDG_GUI_RECORD (a file that gets one JSON line per change of the volume's colour map RGBPoints,
starting with the initial one: what the panel wrote, read back from the LUT proxy).
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
    tooth = XMLImageDataReader(
        registrationName="tooth.vti", FileName=[os.path.join(data, "Volumes", "tooth.vti")]
    )
    tooth.UpdatePipeline()
    display = Show(tooth, view)
    display.SetRepresentationType("Volume")
    array = tooth.PointData.keys()[0]
    ColorBy(display, ("POINTS", array))
    camera = json.load(open(os.path.join(data, "Views", "tooth_oblique.json")))["camera"]
    view.CameraPosition = camera["position"]
    view.CameraFocalPoint = camera["focal_point"]
    view.CameraViewUp = camera["view_up"]
    view.CameraViewAngle = camera.get("view_angle", 30)
    view.OrientationAxesVisibility = 0
    lut = GetColorTransferFunction(array)

    def write(*_):
        with open(record, "a") as f:
            f.write(json.dumps(list(lut.RGBPoints)) + "\n")

    open(record, "w").close()
    write()
    lut.SMProxy.GetProperty("RGBPoints").AddObserver("ModifiedEvent", write)
    SetActiveSource(tooth)
    Render()
