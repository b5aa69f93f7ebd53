"""ParaView scene helpers shared by the suite's scripts (pvpython): a volume shown as ParaView's
Volume representation, a preset written into its colour and opacity maps, cameras from
ParaView's reset camera, screenshots read back as arrays.

The default GUI look: ParaView 5.11 draws a render view's background from the global colour
palette (``UseColorPaletteForBackground`` is 1 on a new view), whose default background is
(0.32, 0.34, 0.43): the ``BackgroundColor`` default of the ``ColorPalette`` settings proxy
(ParaView 5.11's server-manager XML, read here from the copy embedded in the installed
``libvtkRemotingApplication-pv5.11.so``; pvpython reports it as the palette's ``Background``),
measured as the 8-bit pixel (82, 87, 110) in a pvpython screenshot under Xvfb. The view's own
``Background`` property defaults to (0.329, 0.349, 0.427), but it is only drawn when the palette
is switched off: the project's view JSON default is that one, not what a user's screenshot shows.
"""
import math
import os

import numpy as np
from paraview import simple
from vtkmodules.util import numpy_support
from vtkmodules.vtkIOImage import vtkJPEGReader, vtkPNGReader

DEFAULT_PALETTE_BACKGROUND = [0.32, 0.34, 0.43]


def read_image(path):
    """An 8-bit PNG or JPEG as a numpy array (height, width, 3), top row first."""
    reader = vtkJPEGReader() if path.lower().endswith((".jpg", ".jpeg")) else vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    w, h, _ = image.GetDimensions()
    scalars = image.GetPointData().GetScalars()
    if scalars is None:
        raise ValueError("cannot read image %s" % path)
    a = numpy_support.vtk_to_numpy(scalars).reshape(h, w, -1)
    return np.ascontiguousarray(a[::-1, :, :3])


def use_default_palette():
    """Puts ParaView's default palette background back (a user's settings file may have changed
    it) and returns it."""
    palette = simple.GetSettingsProxy("ColorPalette")
    palette.Background = DEFAULT_PALETTE_BACKGROUND
    palette.BackgroundColorMode = "Single Color"
    return list(DEFAULT_PALETTE_BACKGROUND)


class VolumeScene:
    """A new render view of ``size`` (width, height) showing the volume file with ParaView's
    Volume representation (unlit: Shade 0, or ``lighting`` as the view JSON's "lighting" says;
    other properties at their defaults).

    ``gui_look``: the view as a new view in the GUI is (palette background, orientation axes);
    otherwise no orientation axes and a single background colour set with ``set_background``.
    ``view``: show it in this view (the GUI's own, whose size the window sets) instead of a new
    one of ``size``.
    """

    def __init__(self, volume_path, size, gui_look=False, lighting=None, view=None):
        self.reader = simple.XMLImageDataReader(FileName=[os.path.abspath(volume_path)])
        # ``view``: a view of the GUI's (its size is the window's; closing leaves it)
        self.own_view = view is None
        self.view = simple.CreateView("RenderView") if view is None else view
        if view is None:
            self.size = [int(size[0]), int(size[1])]
            self.view.ViewSize = self.size
        else:
            self.size = [int(x) for x in self.view.ViewSize]
        if gui_look:
            self.view.UseColorPaletteForBackground = 1
            self.view.OrientationAxesVisibility = 1
        else:
            self.view.UseColorPaletteForBackground = 0
            self.view.BackgroundColorMode = "Single Color"
            self.view.OrientationAxesVisibility = 0
        self.display = simple.Show(self.reader, self.view)
        self.array = self.reader.PointData.keys()[0]
        simple.ColorBy(self.display, ("POINTS", self.array))
        self.display.SetRepresentationType("Volume")
        lighting = lighting or {}
        self.display.Shade = int(bool(lighting.get("shade", False)))
        self.display.Ambient = lighting.get("ambient", 0.0)
        self.display.Diffuse = lighting.get("diffuse", 1.0)
        self.display.Specular = lighting.get("specular", 0.0)
        self.display.SpecularPower = lighting.get("specular_power", 100.0)
        self.lut = simple.GetColorTransferFunction(self.array)
        self.pwf = simple.GetOpacityTransferFunction(self.array)
        self.lut.AutomaticRescaleRangeMode = "Never"
        simple.Render(self.view)  # paraview.simple resets the camera on the first render

    def set_background(self, rgb):
        self.view.Background = list(rgb)

    def apply(self, preset):
        """Writes a ParaView preset (dict) into the volume's colour and opacity maps."""
        self.lut.ColorSpace = preset.get("ColorSpace", "RGB")
        self.lut.HSVWrap = int(preset.get("HSVWrap", 0))
        self.lut.RGBPoints = [float(x) for x in preset["RGBPoints"]]
        self.pwf.Points = [float(x) for x in preset["Points"]]

    def camera(self):
        return self.view.GetActiveCamera()

    def reset_camera(self):
        """ParaView's reset camera from its initial direction (looking down -z, +y up), as a new
        view shows the volume and as `ddg view` computes it."""
        self.view.CameraPosition = [0.0, 0.0, 1.0]
        self.view.CameraFocalPoint = [0.0, 0.0, 0.0]
        self.view.CameraViewUp = [0.0, 1.0, 0.0]
        self.view.CameraViewAngle = 30.0
        self.view.CameraParallelProjection = 0
        simple.ResetCamera(self.view)
        return self.camera()

    def orbit(self, azimuth, elevation):
        """From the reset camera: azimuth about the view up, then elevation (degrees)."""
        cam = self.reset_camera()
        cam.Azimuth(azimuth)
        cam.Elevation(elevation)
        cam.OrthogonalizeViewUp()
        return cam

    def pan(self, right, up):
        """Moves camera and focal point by fractions of the view height at the focal point."""
        cam = self.camera()
        direction = np.array(cam.GetDirectionOfProjection())
        view_up = np.array(cam.GetViewUp())
        side = np.cross(direction, view_up)
        if cam.GetParallelProjection():
            height = 2.0 * cam.GetParallelScale()
        else:
            height = 2.0 * cam.GetDistance() * math.tan(math.radians(cam.GetViewAngle()) / 2.0)
        shift = (right * side + up * view_up) * height
        cam.SetFocalPoint(*(np.array(cam.GetFocalPoint()) + shift))
        cam.SetPosition(*(np.array(cam.GetPosition()) + shift))

    def camera_json(self):
        """The camera as the project's view JSON states it."""
        cam = self.camera()
        return {
            "position": list(cam.GetPosition()),
            "focal_point": list(cam.GetFocalPoint()),
            "view_up": list(cam.GetViewUp()),
            "view_angle": cam.GetViewAngle(),
            "parallel_projection": bool(cam.GetParallelProjection()),
            "parallel_scale": cam.GetParallelScale(),
        }

    def screenshot(self, path, **options):
        """ParaView's File > Save Screenshot at the view's size (``options``: format options,
        e.g. Quality=85 for JPEG)."""
        simple.Render(self.view)
        simple.SaveScreenshot(path, self.view, ImageResolution=self.size, **options)

    def close(self):
        simple.Delete(self.display)
        if self.own_view:
            simple.Delete(self.view)
        simple.Delete(self.reader)
