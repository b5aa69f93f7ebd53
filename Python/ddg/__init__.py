"""Differentiable Design Gallery for pvpython: find a volume's transfer function from pictures.

The functions follow `paraview.simple`: proxies in, proxies out, ``source=None`` means the active
source, ``view=None`` the active render view's current camera. They drive the DesignGallery
plugin's filters (DDG Query, DDG Design, DDG Design Gallery, DDG Reconstruct Transfer Function,
DDG Volume Render, DDG Build Design Space) and work the same in a builtin session and connected to
a ``pvserver`` (the plugin is loaded on both sides; images and views travel as text, so nothing
needs to be on the server's disk but the volume and the model bundle).

Importing the package loads the plugin: ``build/bin/pvpython`` and ``build/bin/pvbatch`` (written
by the build) set ``PYTHONPATH`` and ``DDG_PLUGIN``; elsewhere set ``DDG_PLUGIN`` to
``DesignGallery.so`` and put ``Python/`` on ``PYTHONPATH``.

Ten lines (the README's example)::

    import ddg
    from paraview.simple import *
    tooth = XMLImageDataReader(FileName=[ddg.data_path("Volumes/tooth.vti")])
    Show(tooth)
    ddg.set_camera(ddg.data_path("Views/tooth_oblique.json"))
    found = ddg.query(ddg.data_path("Screenshots/tooth_dentin_enamel_oblique.png"))
    print("outline position", found.position, "nearest designs", found.neighbours)
    ddg.apply(found)                  # its TF into the volume's colour and opacity maps
    ddg.export(found, "found.json")   # as a ParaView preset
    SaveScreenshot("found.png", GetActiveView())

Transfer functions are ParaView presets (``dict`` with ``RGBPoints``, ``Points``, ``ColorSpace``)
or, for 2D models, the DDG 2D TF JSON (``dict`` with ``Format`` = ``ddg-transfer-function-2d``).
Images are numpy arrays (height, width, 3) of uint8, top row first.
"""
import base64
import json
import os

import numpy as np
from paraview import servermanager
import paraview.simple as simple
from vtkmodules.util import numpy_support
from vtkmodules.vtkIOImage import vtkPNGWriter, vtkPNGReader
from vtkmodules.vtkCommonDataModel import vtkImageData

__all__ = [
    "Model",
    "Design",
    "Gallery",
    "load_model",
    "build_design_space",
    "gallery",
    "query",
    "pick",
    "reconstruct",
    "apply",
    "interpolate",
    "edit",
    "animate",
    "export",
    "render",
    "view_json",
    "set_camera",
    "save_image",
    "data_path",
    "paraview_2d",
    "DDGError",
]

_HERE = os.path.dirname(os.path.abspath(__file__))
_ROOT = os.path.dirname(os.path.dirname(_HERE))


class DDGError(RuntimeError):
    """A filter reported an error (the message is the filter's)."""


def data_path(relative=""):
    """A path in the project's Data/ directory (``DDG_DATA_DIR`` or next to the package)."""
    return os.path.join(os.environ.get("DDG_DATA_DIR", os.path.join(_ROOT, "Data")), relative)


def _plugin_file():
    path = os.environ.get("DDG_PLUGIN")
    if not path:
        path = os.path.join(
            _ROOT, "build", "lib", "paraview-5.11", "plugins", "DesignGallery", "DesignGallery.so"
        )
    if not os.path.exists(path):
        raise ImportError(
            "ddg: the DesignGallery plugin was not found at %s; build it "
            "(bash scripts/build.sh) and use build/bin/pvpython, or set DDG_PLUGIN" % path
        )
    return path


_loaded = set()


def _ensure_plugin():
    """Loads the plugin on the client and, when connected to a server, on the server."""
    connection = servermanager.ActiveConnection
    if connection is None:
        simple.Connect()
        connection = servermanager.ActiveConnection
    key = id(connection)
    if key in _loaded:
        return
    path = _plugin_file()
    if connection.IsRemote():
        simple.LoadPlugin(path, remote=True)
    simple.LoadPlugin(path, remote=False)
    _loaded.add(key)


_ensure_plugin()


# --- scene --------------------------------------------------------------------------------------


def _source(source):
    source = source or simple.GetActiveSource()
    if source is None:
        raise ValueError("no source given and none is active")
    return source


def _array(source):
    """The volume's point array (the first one-component one)."""
    data = source.PointData
    for name in data.keys():
        if data[name].GetNumberOfComponents() == 1:
            return name
    raise ValueError("%s has no one-component point array: not a volume" % source.GetXMLLabel())


def view_json(view=None, source=None, max_side=None):
    """The DDG view JSON (dict) of a render view's current camera (default: the active view):
    camera as ParaView states it, ViewSize (scaled so the longer side is at most ``max_side``),
    background and the source's Scalar Opacity Unit Distance when it is shown. A ``str`` is read
    as a view JSON file, a ``dict`` is returned as is."""
    if isinstance(view, str):
        with open(view) as f:
            return json.load(f)
    if isinstance(view, dict):
        return view
    view = view or simple.GetActiveViewOrCreate("RenderView")
    w, h = [max(1, int(v)) for v in view.ViewSize]
    scale = min(1.0, max_side / max(w, h)) if max_side else 1.0
    out = {
        "camera": {
            "position": list(view.CameraPosition),
            "focal_point": list(view.CameraFocalPoint),
            "view_up": list(view.CameraViewUp),
            "view_angle": view.CameraViewAngle,
            "parallel_projection": bool(view.CameraParallelProjection),
            "parallel_scale": view.CameraParallelScale,
        },
        "size": [max(1, round(w * scale)), max(1, round(h * scale))],
        "background": list(view.Background),
    }
    if source is not None:
        display = simple.GetDisplayProperties(source, view)
        if display is not None and hasattr(display, "ScalarOpacityUnitDistance"):
            out["opacity_unit_distance"] = display.ScalarOpacityUnitDistance
    return out


def set_camera(view_file, view=None):
    """Sets a render view's camera (default: the active one) from a DDG view JSON file or dict
    and renders (after a first render: paraview.simple resets the camera on that one)."""
    v = view_json(view_file)
    view = view or simple.GetActiveViewOrCreate("RenderView")
    simple.Render(view)  # paraview.simple resets the camera on a view's first render: do it first
    c = v["camera"]
    view.CameraPosition = c["position"]
    view.CameraFocalPoint = c["focal_point"]
    view.CameraViewUp = c["view_up"]
    view.CameraViewAngle = c.get("view_angle", 30)
    view.CameraParallelProjection = int(c.get("parallel_projection", False))
    if "parallel_scale" in c:
        view.CameraParallelScale = c["parallel_scale"]
    simple.Render(view)
    return view


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


def _image_text(image):
    """base64 of a PNG/JPEG/TIFF file (path) or of a numpy image encoded as PNG."""
    if isinstance(image, str):
        with open(image, "rb") as f:
            return base64.b64encode(f.read()).decode()
    return base64.b64encode(_png(image)).decode()


def _to_numpy(image):
    """The "Image" array of a filter's image output as (h, w, 3) uint8, top row first."""
    w, h, _ = image.GetDimensions()
    a = numpy_support.vtk_to_numpy(image.GetPointData().GetArray("Image")).reshape(h, w, -1)
    return np.ascontiguousarray(a[::-1, :, :3]).astype(np.uint8)


def _run(proxy):
    """Updates a filter; raises DDGError with its message when it failed."""
    proxy.UpdatePipeline()
    proxy.UpdatePropertyInformation()
    error = proxy.GetPropertyValue("LastError") if proxy.GetProperty("LastError") else ""
    if error:
        raise DDGError(error)


def _field_string(table, name):
    a = table.GetFieldData().GetAbstractArray(name)
    return a.GetValue(0) if a is not None else None


def _field_numbers(table, name):
    a = table.GetFieldData().GetArray(name)
    return (
        np.array([a.GetValue(i) for i in range(a.GetNumberOfValues())]) if a is not None else None
    )


def _tf_dict(tf, view=None):
    """A TF as a dict: a Design (its explicit TF at `view`), a dict, a preset list or a file."""
    if isinstance(tf, Design):
        return tf.transfer_function(view)
    if isinstance(tf, str):
        with open(tf) as f:
            tf = json.load(f)
    if isinstance(tf, list):
        tf = tf[0]
    if not isinstance(tf, dict):
        raise TypeError("a transfer function is a Design, a preset dict or a JSON file path")
    return tf


_helpers = {}  # (filter, source, connection) -> helper proxy


def _proxy(name, source, **props):
    """An unregistered helper filter on ``source`` (not in the pipeline, the active source kept).
    One proxy per filter, source and connection is kept and reused with its properties reset, so
    a filter's loaded bundle and outline serve the next call too."""
    key = (name, source.GetGlobalIDAsString(), id(servermanager.ActiveConnection))
    proxy = _helpers.get(key)
    if proxy is None:
        proxy = _helpers[key] = getattr(servermanager.filters, name)(Input=source)
    else:
        for prop in proxy.ListProperties():
            if prop != "Input":
                proxy.GetProperty(prop).SMProperty.ResetToXMLDefaults()
    proxy.SetPropertyWithName("SelectInputScalars", ["POINTS", _array(source)])
    for key, value in props.items():  # XML property names
        proxy.SetPropertyWithName(key, value)
    return proxy


# --- models -------------------------------------------------------------------------------------


class Model:
    """A model bundle (trained design space with its outline) of one volume."""

    def __init__(self, directory, source):
        self.directory = os.path.abspath(directory)
        self.source = source

    def __repr__(self):
        return "ddg.Model(%r)" % self.directory


def _default_model(source):
    """The shipped bundle named like the volume's file (Data/Models/tooth for tooth.vti)."""
    if "FileName" in source.ListProperties():
        f = source.GetPropertyValue("FileName")
        f = f[0] if isinstance(f, (list, tuple)) else str(f)
        stem = os.path.splitext(os.path.basename(f))[0].lower()
        candidate = data_path(os.path.join("Models", stem))
        if stem and os.path.exists(os.path.join(candidate, "bundle.json")):
            return Model(candidate, source)
    raise ValueError(
        "no model given and no shipped bundle for this source: pass model= "
        "(ddg.load_model) or build one (ddg.build_design_space)"
    )


def load_model(directory, source=None):
    """The model bundle in ``directory`` (a path where the filters run: the server's disk in
    client/server) for ``source`` (default: the active source). Checked when first used."""
    return Model(directory, _source(source))


def build_design_space(
    source=None,
    directory="design_space",
    minutes=5.0,
    count=2000,
    size=64,
    iterations=None,
    outline=None,
):
    """Builds a design space for a volume (DDG Build Design Space; progress in ParaView):
    ``count`` exemplars of ``size``^2 pixels, a decoder trained for ``minutes`` (or exactly
    ``iterations`` steps), its evaluation and an outline of ``outline`` designs (default: the
    filter's), written to ``directory`` (where the filters run). Returns the Model."""
    source = _source(source)
    directory = os.path.abspath(directory)
    build = _proxy(
        "DDGBuildDesignSpace",
        source,
        OutputDirectory=directory,
        Minutes=float(minutes),
        Count=int(count),
        Size=int(size),
    )
    if iterations is not None:
        build.SetPropertyWithName("Iterations", int(iterations))
    if outline is not None:
        build.SetPropertyWithName("OutlineCount", int(outline))
    build.UpdatePipeline()
    table = servermanager.Fetch(build, idx=0)
    if table.GetNumberOfRows() != 1:
        raise DDGError("the design space was not built (see the Output Messages)")
    return Model(directory, source)


def _model(model, source):
    source = _source(
        source if source is not None else (model.source if isinstance(model, Model) else None)
    )
    if model is None:
        return _default_model(source), source
    if isinstance(model, str):
        return Model(model, source), source
    return model, source


# --- designs ------------------------------------------------------------------------------------


class Design:
    """A design of a model's design space: the path that leads to it (a ddg history, the JSON
    that ``ddg replay`` reads) evaluated by DDG Design. ``position`` (outline plane), ``latent``
    (numpy), ``neighbours`` (nearest outline rows, for queries)."""

    def __init__(self, model, steps, neighbours=None):
        self.model = model
        self.steps = list(steps)
        self.neighbours = list(neighbours or [])
        self._cache = {}

    def history(self):
        """The design's history as JSON text (``export(design, path, format="history")``)."""
        return json.dumps({"format": "ddg-history", "version": 1, "steps": self.steps}, indent=1)

    def evaluate(self, view=None, fidelity=False):
        """Runs DDG Design at ``view`` (default: the active view's camera, at most 256 pixels):
        a dict with "preview" (numpy image), "latent", "position", "preset", "slicer",
        "clusters" (mean RGB and share of each colour cluster) and with ``fidelity`` "fidelity"
        (PSNR dB, SSIM, max error); 2D models add "paraview_2d" (the TransferFunction2D proxy's
        Boxes, Range and OutputDimensions fitted to the design, with the fit's errors)."""
        v = (
            view_json(view, self.model.source, 256)
            if not isinstance(view, (str, dict))
            else view_json(view)
        )
        key = (json.dumps(v, sort_keys=True), fidelity)
        if key in self._cache:
            return self._cache[key]
        proxy = _proxy(
            "DDGDesign",
            self.model.source,
            ModelDirectory=self.model.directory,
            History=self.history(),
            ViewJSON=json.dumps(v),
            ComputeFidelity=int(fidelity),
        )
        _run(proxy)
        table = servermanager.Fetch(proxy, idx=1)
        preset = _field_string(table, "Preset") or _field_string(table, "TransferFunction2D")
        clusters = [
            {
                "rgb": [table.GetValueByName(i, c).ToDouble() for c in "RGB"],
                "share": table.GetValueByName(i, "Share").ToDouble(),
            }
            for i in range(table.GetNumberOfRows())
        ]
        out = {
            "preview": _to_numpy(servermanager.Fetch(proxy, idx=0)),
            "latent": _field_numbers(table, "Latent"),
            "position": tuple(_field_numbers(table, "Position")),
            "preset": json.loads(preset),
            "slicer": _field_string(table, "Slicer"),
            "clusters": clusters,
        }
        boxes = _field_string(table, "ParaViewTransferFunction2D")
        if boxes:
            out["paraview_2d"] = json.loads(boxes)
        if fidelity:
            out["fidelity"] = tuple(_field_numbers(table, "Fidelity"))
        self._cache[key] = out
        return out

    def transfer_function(self, view=None):
        """The design's explicit TF at ``view`` as a dict (a ParaView preset for 1D models)."""
        p = self.evaluate(view)["preset"]
        return p[0] if isinstance(p, list) else p

    def preview(self, view=None):
        """The model's render of the design at ``view`` (numpy image)."""
        return self.evaluate(view)["preview"]

    @property
    def latent(self):
        return self.evaluate()["latent"]

    @property
    def position(self):
        return self.evaluate()["position"]

    def __repr__(self):
        return "ddg.Design(%s)" % " -> ".join(s["action"] for s in self.steps)


def pick(row, model=None, source=None):
    """Outline design ``row`` of the model (rows as in ``gallery()``)."""
    model, source = _model(model, source)
    return Design(model, [{"action": "pick", "row": int(row)}])


def query(image, source=None, view=None, model=None, neighbours=5):
    """Queries the model's design space with an image (a file path or a numpy image): the
    analyzer's design, placed on the outline, with its ``neighbours`` nearest outline rows.
    ``view`` is where its preview is rendered and its explicit TF made (default: the active
    view's camera). Returns a Design."""
    model, source = _model(model, source)
    v = view_json(view, source, 256)
    proxy = _proxy(
        "DDGQuery",
        source,
        ModelDirectory=model.directory,
        ViewJSON=json.dumps(v),
        ImageData=_image_text(image),
        Neighbours=int(neighbours),
    )
    _run(proxy)
    table = servermanager.Fetch(proxy, idx=1)
    rows = [int(table.GetValueByName(i, "Row").ToInt()) for i in range(table.GetNumberOfRows())]
    latent = [float(x) for x in _field_numbers(table, "Latent")]
    step = {"action": "latent", "latent": latent}
    if isinstance(image, str):
        step["image"] = os.path.basename(image)
    return Design(model, [step], rows)


def interpolate(a, b, t, c=None, d=None, v=0.0):
    """The design at ``t`` between designs ``a`` and ``b`` (t = 0: a, 1: b; with ``c`` (and
    ``d``) the barycentric (bilinear) blend at (t, v), as Core's blendLatents)."""
    anchors = [x for x in (a, b, c, d) if x is not None]
    latents = [[float(z) for z in x.latent] for x in anchors]
    return Design(a.model, [{"action": "blend", "latents": latents, "u": float(t), "v": float(v)}])


def edit(
    design,
    cluster=None,
    hue=0.0,
    saturation=1.0,
    lightness=0.0,
    visibility=1.0,
    axes=None,
    view=None,
    pick_pixel=None,
):
    """An edited design: colour cluster ``cluster`` (index into ``design.evaluate()["clusters"]``,
    or the cluster under ``pick_pixel`` = (x, y) of the preview) recoloured (hue degrees,
    saturation factor, lightness in L*) and made more (``visibility`` > 1) or less visible, then
    moved along the principal axes by ``axes`` (standard deviations per axis)."""
    steps = list(design.steps)
    if cluster is not None or pick_pixel is not None:
        step = {
            "action": "edit",
            "view": view_json(view, design.model.source, 256),
            "clusters": 4,
            "hue": float(hue),
            "saturation": float(saturation),
            "lightness": float(lightness),
            "visibility": float(visibility),
            "white": False,
        }
        if pick_pixel is not None:
            step["pick"] = [int(pick_pixel[0]), int(pick_pixel[1])]
        else:
            step["cluster"] = int(cluster)
        steps.append(step)
    if axes is not None:
        steps.append({"action": "axes", "steps": [float(s) for s in axes]})
    if len(steps) == len(design.steps):
        raise ValueError("edit: give a cluster (or pick_pixel) or axes")
    return Design(design.model, steps)


class Gallery:
    """The outline of a model: ``sheet`` (numpy image of the thumbnails, row by row), ``x``,
    ``y`` (plane position of every outline row), ``thumbnails`` (the outline row of each
    thumbnail, in sheet order) and ``box`` (the plane part shown)."""

    def __init__(self, model, sheet, x, y, thumbnails, box):
        self.model, self.sheet, self.x, self.y = model, sheet, x, y
        self.thumbnails, self.box = thumbnails, box

    def design(self, k):
        """The design of thumbnail ``k``."""
        return pick(self.thumbnails[k], self.model)


def gallery(source=None, model=None, count=32, box=None, seed=1, thumbnail_size=64, view=None):
    """The model's outline and ``count`` thumbnails covering ``box`` = (x0, y0, x1, y1) of the
    PCA plane (default: all of it), sampled with ``seed``, rendered at ``view`` (default: the
    volume's default view). Returns a Gallery."""
    model, source = _model(model, source)
    proxy = _proxy(
        "DDGDesignGallery",
        source,
        ModelDirectory=model.directory,
        Count=int(count),
        Seed=int(seed),
        ThumbnailSize=int(thumbnail_size),
        Box=list(box or [0, 0, 0, 0]),
    )
    if view is not None:
        proxy.SetPropertyWithName("ViewJSON", json.dumps(view_json(view)))
    _run(proxy)
    sheet = _to_numpy(servermanager.Fetch(proxy, idx=0))
    table = servermanager.Fetch(proxy, idx=1)
    col = lambda name: numpy_support.vtk_to_numpy(table.GetColumnByName(name))  # noqa: E731
    x, y, cells = col("X").copy(), col("Y").copy(), col("Thumbnail")
    order = np.argsort(np.where(cells >= 0, cells, np.iinfo(np.int32).max))
    thumbnails = [int(r) for r in order[: int((cells >= 0).sum())]]
    shown = tuple(_field_numbers(table, "Box"))
    return Gallery(model, sheet, x, y, thumbnails, shown)


# --- transfer functions ---------------------------------------------------------------------------


def reconstruct(
    image,
    source=None,
    view=None,
    iterations=300,
    bins=128,
    smoothness=None,
    learning_rate=None,
    two_d=False,
):
    """The TF that renders ``source`` like ``image`` (a screenshot file or numpy image of the
    volume, the view's size) at ``view`` (a view JSON file or dict, or the active view's camera:
    then the image must have the view's size): differentiable reconstruction (DDG Reconstruct
    Transfer Function), ``iterations`` Adam steps. Returns the TF dict (a ParaView preset)."""
    source = _source(source)
    v = view_json(view, source)
    proxy = _proxy(
        "DDGReconstructTransferFunction",
        source,
        TargetImageData=_image_text(image),
        ViewJSON=json.dumps(v),
        Iterations=int(iterations),
        Bins=int(bins),
        TwoD=int(two_d),
    )
    if smoothness is not None:
        proxy.SetPropertyWithName("Smoothness", float(smoothness))
    if learning_rate is not None:
        proxy.SetPropertyWithName("LearningRate", float(learning_rate))
    proxy.UpdatePipeline()
    table = servermanager.Fetch(proxy, idx=0)
    text = _field_string(table, "Preset") or _field_string(table, "TransferFunction2D")
    if not text:
        raise DDGError("the reconstruction failed (see the Output Messages)")
    p = json.loads(text)
    return p[0] if isinstance(p, list) else p


def paraview_2d(tf, source=None, view=None):
    """ParaView 5.11's TransferFunction2D for a 2D TF (Design, DDG 2D JSON dict or file) on
    ``source``: a dict of the proxy's ``Boxes`` (8 numbers per Gaussian box: lower-left x, y,
    width, height, r, g, b, a), ``Range`` and ``OutputDimensions``, fitted on the server so that
    ParaView's 2D rendering matches the project's (its axes are value and gradient magnitude in
    value units per voxel; alpha per ray sample), and ``Fit`` (rmse, initial_rmse, alpha_rmse,
    max_alpha on the fit grid). ``view`` gives the opacity unit distance."""
    source = _source(source)
    if isinstance(tf, Design):
        out = tf.evaluate(
            view_json(view, source, 256) if not isinstance(view, (str, dict)) else view
        )
        if "paraview_2d" not in out:
            raise ValueError("paraview_2d: the design is 1D (apply it as a ParaView preset)")
        return out["paraview_2d"]
    d = _tf_dict(tf)
    if d.get("Format") != "ddg-transfer-function-2d":
        raise ValueError(
            'paraview_2d: not a DDG 2D transfer function ("Format": "ddg-transfer-function-2d")'
        )
    v = view_json(view, source, 16) if not isinstance(view, (str, dict)) else view_json(view)
    v["size"] = [8, 8]  # the fit is what is wanted, not the image
    proxy = _proxy(
        "DDGVolumeRender", source, TransferFunctionJSON=json.dumps(d), ViewJSON=json.dumps(v)
    )
    proxy.UpdatePipeline()
    boxes = _field_string(servermanager.Fetch(proxy, idx=0), "ParaViewTransferFunction2D")
    if not boxes:
        raise DDGError("the 2D transfer function could not be converted (see the Output Messages)")
    return json.loads(boxes)


def apply(tf, display=None, source=None, view=None):
    """Writes a TF (Design, preset dict or file, DDG 2D JSON) into ``display``'s maps (default:
    the active source's display in the active view; shown first if needed), switches it to the
    Volume representation and renders. A Design's TF is made at the view's camera. 1D TFs go
    into the colour and opacity maps (2D rendering off); 2D TFs into ParaView's
    TransferFunction2D (``paraview_2d``) with UseTransfer2D on. Returns the display."""
    view = view or simple.GetActiveViewOrCreate("RenderView")
    source = _source(source)
    display = display or simple.Show(source, view)
    preset = _tf_dict(tf, view_json(view, source, 256) if isinstance(tf, Design) else None)
    two_d = preset.get("Format") == "ddg-transfer-function-2d"
    if not two_d and "RGBPoints" not in preset:
        raise ValueError(
            "apply: a ParaView preset (RGBPoints, Points) or a DDG 2D transfer function"
        )
    if two_d and display.GetProperty("UseTransfer2D") is None:
        raise ValueError("apply: this representation has no 2D transfer function (image data has)")
    boxes = paraview_2d(tf, source, view) if two_d else None
    display.SetRepresentationType("Volume")
    array = _array(source)
    simple.ColorBy(display, ("POINTS", array))
    lut = simple.GetColorTransferFunction(array)
    lut.AutomaticRescaleRangeMode = "Never"
    if display.GetProperty("UseTransfer2D") is not None:
        display.UseTransfer2D = int(two_d)
    if two_d:
        display.UseGradientForTransfer2D = 1
        if display.VolumeRenderingMode == "Ray Cast Only":  # the fixed-point mapper has no 2D TFs
            display.VolumeRenderingMode = "Smart"
        tf2 = display.TransferFunction2D  # the LUT's too: the Color Map Editor's 2D editor shows it
        tf2.Range = boxes["Range"]
        tf2.OutputDimensions = boxes["OutputDimensions"]
        tf2.Boxes = boxes["Boxes"]
    else:
        lut.ColorSpace = preset.get("ColorSpace", "RGB")
        lut.RGBPoints = preset["RGBPoints"]
        simple.GetOpacityTransferFunction(array).Points = preset["Points"]
    simple.Render(view)
    return display


def export(tf, path, format="paraview", view=None):
    """Writes a TF: ``format`` "paraview" (preset JSON list, importable with
    ``ImportPresets``), "slicer" (3D Slicer .vp.json; Designs only) or "history" (a Design's
    path, replayed by ``ddg replay``)."""
    if format == "history":
        if not isinstance(tf, Design):
            raise TypeError("export history: give a Design")
        text = tf.history()
    elif format == "slicer":
        if not isinstance(tf, Design):
            raise TypeError("export slicer: give a Design (or use `ddg export --format slicer`)")
        text = tf.evaluate(view)["slicer"]
        if not text:
            raise ValueError("3D Slicer's format holds 1D transfer functions only")
    elif format == "paraview":
        d = _tf_dict(tf, view)
        text = json.dumps([d] if "RGBPoints" in d else d, indent=1)
    else:
        raise ValueError("export: format is paraview, slicer or history")
    with open(path, "w") as f:
        f.write(text)
    return path


def render(source=None, tf=None, view=None):
    """The project's CPU ray cast of ``source`` with ``tf`` at ``view`` (DDG Volume Render; as
    ParaView renders it): a numpy image (h, w, 3) over the view's background."""
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


def animate(a, b, frames=30, source=None, view=None, directory=None, easing="smoothstep"):
    """ParaView renders of the designs from ``a`` to ``b``: ``frames`` blends on an eased path
    (smoothstep, linear or cosine, as ``ddg animate``) applied to the active view one after the
    other. Returns the frames as numpy images; with ``directory`` also writes frame_0000.png, ...
    The colour map is put back afterwards."""
    view = view or simple.GetActiveViewOrCreate("RenderView")
    source = _source(source)
    array = _array(source)
    lut, sof = simple.GetColorTransferFunction(array), simple.GetOpacityTransferFunction(array)
    before = (list(lut.RGBPoints), list(sof.Points))
    ease = {
        "linear": lambda t: t,
        "smoothstep": lambda t: t * t * (3 - 2 * t),
        "cosine": lambda t: (1 - np.cos(np.pi * t)) / 2,
    }[easing]
    if directory:
        os.makedirs(directory, exist_ok=True)
    images = []
    try:
        for k in range(int(frames)):
            t = ease(k / max(1, frames - 1))
            apply(interpolate(a, b, t), source=source, view=view)
            w, h = [int(s) for s in view.ViewSize]
            path = os.path.join(
                directory or os.environ.get("TMPDIR", "/tmp"),
                "frame_%04d.png" % k if directory else "ddg_frame_%d.png" % os.getpid(),
            )
            simple.SaveScreenshot(path, view, ImageResolution=[w, h])
            reader = vtkPNGReader()
            reader.SetFileName(path)
            reader.Update()
            out = reader.GetOutput()
            ow, oh, _ = out.GetDimensions()
            pixels = numpy_support.vtk_to_numpy(out.GetPointData().GetScalars()).reshape(oh, ow, -1)
            images.append(np.ascontiguousarray(pixels[::-1, :, :3]))
            if not directory:
                os.remove(path)
    finally:
        lut.RGBPoints, sof.Points = before
        simple.Render(view)
    return images
