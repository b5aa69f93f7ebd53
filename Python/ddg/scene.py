"""ddg.scene: the ParaView scene: the volume and its array, views and cameras, images, applying a
transfer function to the volume's representation and the project's render of it.
"""
import base64
import contextlib
import json
import warnings

import numpy as np
from paraview import servermanager
import paraview.simple as simple
from vtkmodules.util import numpy_support
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkIOImage import vtkPNGReader, vtkPNGWriter

from .plugin import DDGError, _vtk_module

# --- the volume -----------------------------------------------------------------------------------


def _source(source):
    source = source or simple.GetActiveSource()
    if source is None:
        raise ValueError("no source given and none is active")
    return source


def _view(view):
    """``view``, or the active render view (created when there is none)."""
    return view or simple.GetActiveViewOrCreate("RenderView")


def _scene():
    """vtkSMDDGScene: the scene rules the panel uses too (the volume's array, view JSON, default
    model, writing TFs into a representation), in one place."""
    return _vtk_module("DDGScene").vtkSMDDGScene


def _display(source, view):
    """``source``'s representation in ``view`` (default: the active view), or None."""
    view = view or simple.GetActiveView()
    return servermanager.GetRepresentation(source, view) if view is not None else None


def volume_array(source, view=None):
    """The name of the volume's point array: the one the filters compute on and whose colour and
    opacity maps a TF goes into. It is the array ParaView's representation colours by, in order:

    1. when ``source`` is shown in ``view`` (default: the active view, if any) and its display
       is coloured by a point array: that array (``ColorArrayName``);
    2. else the data's active point scalars;
    3. else, only when the data has no active point scalars, its first one-component point array.

    The rule is vtkSMDDGScene's (``Plugin/Scene``), which the Design Gallery panel uses too, so a
    script and the GUI work on the same array. (ParaView itself, when a display not coloured by an
    array is switched to Volume, colours it by the first point array; ``apply`` asks this function
    first and colours by its answer.)

    Raises ValueError when the source is not a volume: not image data, or the array so chosen has
    more than one component (colour it by, or make active, a one-component array).
    """
    source.UpdatePipeline()  # the rule reads the data information
    display = _display(source, view)
    proxy = display.SMProxy if display is not None else None
    name = _scene().VolumeArray(source.SMProxy, proxy, 0)
    if not name:
        problem = _scene().VolumeProblemOf(source.SMProxy, proxy, 0)
        raise ValueError("%s %s" % (source.GetXMLLabel(), problem))
    return name


_helpers = {}  # (filter, source, connection) -> helper proxy


def _proxy(name, source, **props):
    """An unregistered helper filter on ``source`` (not in the pipeline, the active source kept)
    reading the volume's array (``volume_array``). One proxy per filter, source and connection
    is kept and reused with its properties reset, so a filter's loaded bundle and outline serve
    the next call too."""
    key = (name, source.GetGlobalIDAsString(), id(servermanager.ActiveConnection))
    proxy = _helpers.get(key)
    if proxy is None:
        proxy = _helpers[key] = getattr(servermanager.filters, name)(Input=source)
    else:
        for prop in proxy.ListProperties():
            if prop != "Input":
                proxy.GetProperty(prop).SMProperty.ResetToXMLDefaults()
    proxy.SetPropertyWithName("SelectInputScalars", ["POINTS", volume_array(source)])
    for key, value in props.items():  # XML property names
        proxy.SetPropertyWithName(key, value)
    return proxy


# --- views ----------------------------------------------------------------------------------------


def view_json(view=None, source=None, max_side=None):
    """The DDG view JSON (dict) of a render view's current camera (default: the active view):
    camera as ParaView states it, ViewSize (scaled so the longer side is at most ``max_side``),
    background and the source's Scalar Opacity Unit Distance when it is shown. A view that shows
    nothing (after OpenDataFile, before Show) gives the camera ParaView's Reset Camera would give
    ``source`` in it, since its own camera has never looked at the data. A ``str`` is read as a
    view JSON file, a ``dict`` is returned as is."""
    if isinstance(view, str):
        with open(view) as f:
            return json.load(f)
    if isinstance(view, dict):
        return view
    view = _view(view)
    text = _scene().ViewJSON(
        view.SMProxy, source.SMProxy if source is not None else None, int(max_side or 0)
    )
    if not text:
        raise ValueError("view_json: %s is not a render view" % view.GetXMLName())
    return json.loads(text)


def set_camera(view_file, view=None):
    """Sets a render view's camera (default: the active one) from a DDG view JSON file or dict
    and renders (after a first render: paraview.simple resets the camera on that one). A view
    JSON the project's readers refuse (no camera, a degenerate one, a value of the wrong type)
    raises DDGError and leaves the camera as it was."""
    text = json.dumps(view_json(view_file))
    view = _view(view)
    error = _scene().SetCamera(view.SMProxy, text, True)  # the panel's rule; refused unchanged
    if error:
        raise DDGError("set_camera: " + error)
    simple.Render(view)  # paraview.simple resets the camera on a view's first render: do it first
    _scene().SetCamera(view.SMProxy, text, False)
    simple.Render(view)
    return view


# --- images ---------------------------------------------------------------------------------------


def _png(pixels, path=None):
    """A numpy image (h, w[, c]) as PNG: written to `path`, or returned as bytes."""
    a = np.asarray(pixels)
    if a.dtype != np.uint8:
        a = np.clip(np.rint(a * 255.0), 0, 255).astype(np.uint8)
    if a.ndim == 2:
        a = a[:, :, None]
    h, w, c = a.shape
    data = vtkImageData()
    data.SetDimensions(w, h, 1)
    data.GetPointData().SetScalars(
        numpy_support.numpy_to_vtk(np.ascontiguousarray(a[::-1]).reshape(-1, c), deep=True)
    )
    writer = vtkPNGWriter()
    writer.SetInputData(data)
    if path:
        writer.SetFileName(path)
        writer.Write()
        return path
    writer.WriteToMemoryOn()
    writer.Write()
    return numpy_support.vtk_to_numpy(writer.GetResult()).tobytes()


def save_image(pixels, path):
    """Writes a numpy image (h, w, 3 or 4; uint8, or floats in [0, 1]; top row first) as PNG."""
    return _png(pixels, path)


def _image_text(image, label):
    """base64 of an image file (a path: PNG, JPEG, TIFF, BMP, GIF or WebP) or of a numpy image
    encoded as PNG; an empty file raises DDGError named as ``_errors_named`` names the call's
    (``label``)."""
    if isinstance(image, str):
        with open(image, "rb") as f:
            data = f.read()
        if not data:  # else no ImageData would reach the filter: "no ImageFile or ImageData set"
            with _errors_named(label, image):
                raise DDGError("the picture file is empty (0 bytes)")
        return base64.b64encode(data).decode()
    return base64.b64encode(_png(image)).decode()


@contextlib.contextmanager
def _errors_named(label, image=None):
    """A DDGError raised inside is prefixed with ``label`` and, when ``image`` is a file path,
    its name: "query ('a.png'): cannot read the picture: ..."."""
    try:
        yield
    except DDGError as e:
        name = "%s ('%s')" % (label, image) if isinstance(image, str) else label
        raise DDGError("%s: %s" % (name, e)) from None


def _rgb(image, array):
    """A point array of a 2D vtkImageData (bottom row first) as (h, w, 3), top row first."""
    w, h, _ = image.GetDimensions()
    a = numpy_support.vtk_to_numpy(array).reshape(h, w, -1)
    return np.ascontiguousarray(a[::-1, :, :3])


def _to_numpy(image):
    """The "Image" array of a filter's image output as (h, w, 3) uint8, top row first."""
    return _rgb(image, image.GetPointData().GetArray("Image")).astype(np.uint8)


def _read_png(path):
    """A PNG file as (h, w, 3), top row first."""
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    out = reader.GetOutput()
    return _rgb(out, out.GetPointData().GetScalars())


# --- transfer functions in the scene --------------------------------------------------------------


def apply(
    tf, display=None, source=None, view=None, camera=None, separate_color_map=None, lighting=None
):
    """Writes a TF (Design, preset dict or file, DDG 2D JSON, ParaView's 2D boxes, a ``Match`` or a
    ``CarriedLook``: its TF) into ``display``'s maps (default: the active source's display in the
    active view; shown first if needed), switches it to the Volume representation and renders. A
    Design's TF is made at the view's camera. 1D TFs go into the colour and opacity maps (2D
    rendering off); 2D TFs into ParaView's TransferFunction2D (``paraview_2d``) with
    UseTransfer2D on. ``camera``: also moves the view's camera there (a view JSON dict or file,
    e.g. a ``Match``'s ``view``; True with a ``Match``: its camera; a ``CarriedLook`` has none,
    its picture being of another volume; default: the camera stays; a view JSON the project's
    readers refuse raises DDGError before anything is written). ParaView shares one colour
    map per array name: when other shown volumes share this one, ``separate_color_map=True``
    first gives this display its own maps (ParaView's Use Separate Color Map), False recolours
    them all, and None (default) recolours them all with a warning naming them. ``lighting``:
    sets the display's Shade and its Ambient, Diffuse, Specular, SpecularPower from a view JSON's
    "lighting" (a view JSON dict or file; none: Shade off); default: a ``Match``'s or a
    ``CarriedLook``'s own (the look it matched or was carried over under), else unchanged;
    False: unchanged. Returns the display."""
    from .designs import Design  # these modules build on this one
    from .tf import CarriedLook, Match, _tf_dict, paraview_2d

    # a Match's or a CarriedLook's TF is taken out by _tf_dict; a Match adds its camera and look
    if isinstance(tf, (Match, CarriedLook)) and lighting is None:
        lighting = tf.view  # the look it matched, or was carried over under
    if isinstance(tf, Match) and camera is True:
        camera = tf.view
    elif camera is True and isinstance(tf, CarriedLook):
        raise ValueError("apply: a carried look has no camera, its picture shows another volume")
    elif camera is True:
        raise ValueError("apply: camera=True needs a Match (give a view JSON dict or file)")
    view = _view(view)
    source = _source(source)
    display = display or simple.Show(source, view)
    preset = _tf_dict(tf, view_json(view, source, 256) if isinstance(tf, Design) else None)
    paraview_boxes = "Boxes" in preset  # ParaView's own 2D TF: set as it is
    two_d = preset.get("Format") == "ddg-transfer-function-2d" or paraview_boxes
    if not two_d and "RGBPoints" not in preset:
        raise ValueError(
            "apply: a ParaView preset (RGBPoints, Points), a DDG 2D transfer function or "
            "ParaView's 2D boxes (Boxes, Range, OutputDimensions)"
        )
    if two_d and display.GetProperty("UseTransfer2D") is None:
        raise ValueError("apply: this representation has no 2D transfer function (image data has)")
    boxes = preset if paraview_boxes else paraview_2d(tf, source, view) if two_d else None
    array = volume_array(source, view)  # before the switch to Volume, which may colour by another
    scene = _scene()
    lighting = None if lighting is False else lighting
    # the lighting, the TF and the camera: each refused before anything is written
    if lighting is not None:
        lighting = json.dumps(view_json(lighting))
        error = scene.SetLighting(display.SMProxy, lighting, True)
        if error:
            raise DDGError("apply: " + error)
    error = (
        scene.Apply2D(display.SMProxy, array, json.dumps(boxes), True)
        if two_d
        else scene.Apply1D(display.SMProxy, array, json.dumps(preset), True)
    )
    if error:
        raise DDGError("apply: " + error)
    if camera is not None:
        camera = view_json(camera)
        error = scene.SetCamera(view.SMProxy, json.dumps(camera), True)
        if error:
            raise DDGError("apply: " + error)
    shared = scene.SharedColorMapUsers(display.SMProxy, array)
    if shared and separate_color_map:
        error = scene.UseSeparateColorMap(display.SMProxy, array)
        if error:
            raise DDGError("apply: " + error)
    elif shared and separate_color_map is None:
        one = "\n" not in shared
        warnings.warn(
            "apply: %s %s the colour map of '%s' and %s recoloured too (separate_color_map=True "
            "leaves %s as %s)"
            % (
                ", ".join(shared.split("\n")),
                "shares" if one else "share",
                array,
                "is" if one else "are",
                "it" if one else "them",
                "it is" if one else "they are",
            ),
            stacklevel=2,
        )
    error = (
        scene.Apply2D(display.SMProxy, array, json.dumps(boxes))
        if two_d
        else scene.Apply1D(display.SMProxy, array, json.dumps(preset))
    )
    if error:
        raise DDGError("apply: " + error)
    if lighting is not None:
        error = scene.SetLighting(display.SMProxy, lighting)
        if error:
            raise DDGError("apply: " + error)
    if camera is not None:
        set_camera(camera, view)
    simple.Render(view)
    return display


def render(source=None, tf=None, view=None):
    """The project's CPU ray cast of ``source`` with ``tf`` at ``view`` (DDG Volume Render; as
    ParaView renders it): a numpy image (h, w, 3) over the view's background."""
    from .tf import _tf_dict  # tf builds on this module

    source = _source(source)
    if tf is None:
        raise ValueError("render: give a transfer function")
    v = view_json(view, source)
    proxy = _proxy(
        "DDGVolumeRender",
        source,
        TransferFunctionJSON=json.dumps(_tf_dict(tf, v)),
        ViewJSON=json.dumps(v),
    )
    proxy.UpdatePipeline()
    image = servermanager.Fetch(proxy, idx=0)
    if image.GetNumberOfPoints() == 0:
        raise DDGError("the render failed (see the Output Messages)")
    return _to_numpy(image)
