"""ddg.designs: a volume's design space: model bundles, designs (the history that leads to one,
evaluated by DDG Design), queries with pictures, the outline gallery, blends, edits, animations.
"""
import json
import os
import warnings

import numpy as np
from paraview import servermanager
import paraview.simple as simple
from vtkmodules.util import numpy_support

from .plugin import DDGError, _field_numbers, _field_string, _first_tf, _history, _run, _tf_text
from .plugin import _kind_network, _kind_of, _vtk_module, _whole, _within, data_path
from .scene import (
    _display,
    _image_text,
    _errors_named,
    _proxy,
    _read_png,
    _scene,
    _source,
    _to_numpy,
    _view,
)
from .scene import apply, view_json
from .scene import volume_array

# --- models -------------------------------------------------------------------------------------


class Model:
    """A model bundle (trained design space with its outline) of one volume."""

    def __init__(self, directory, source):
        self.directory = os.path.abspath(directory)
        self.source = source

    def __repr__(self):
        return "ddg.Model(%r)" % self.directory


def _default_model(source):
    """The shipped bundle named like the volume's file (Data/Models/tooth for tooth.vti), by the
    panel's rule (vtkSMDDGScene::DefaultModelDirectory)."""
    directory = _scene().DefaultModelDirectory(source.SMProxy, data_path())
    if directory:
        return Model(directory, source)
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
    budget_minutes=None,
    overwrite=False,
    design_voxels=None,
):
    """Builds a design space for a volume (DDG Build Design Space; progress in ParaView):
    ``count`` exemplars of ``size``^2 pixels, a decoder trained for ``minutes`` (or exactly
    ``iterations`` steps), its evaluation and an outline of ``outline`` designs (default: the
    filter's), written to ``directory`` (where the filters run). With ``budget_minutes`` (>= 1)
    the whole build is sized to take about that long (``count``, ``minutes`` and ``outline`` are
    then ignored; ``build_plan`` shows the plan first). A directory that already holds a bundle
    is refused unless ``overwrite``. ``design_voxels``: volumes above this many voxels are
    downsampled for the design space (default: the filter's, 16 Mi). Returns the Model."""
    # the filter's ranges (the CLI's), refused here rather than clamped there
    what = "build_design_space"
    props = dict(
        Minutes=_within(minutes, what, "minutes", 0.01, 10000),
        Count=_whole(count, what, "count", 8, 1000000),
        Size=_whole(size, what, "size", 16, 512),
        BudgetMinutes=0
        if budget_minutes is None
        else _within(budget_minutes, what, "budget_minutes", 1, 100000),
    )
    if iterations is not None:
        props["Iterations"] = _whole(iterations, what, "iterations", 0, 10000000)
    if outline is not None:
        props["OutlineCount"] = _whole(outline, what, "outline", 3, 1000000)
    if design_voxels is not None:
        props["DesignVoxels"] = _whole(design_voxels, what, "design_voxels", 4096, 1 << 40)
    source = _source(source)
    directory = os.path.abspath(directory)
    build = _proxy(
        "DDGBuildDesignSpace",
        source,
        OutputDirectory=directory,
        Overwrite=int(bool(overwrite)),
        **props,
    )
    build.UpdatePipeline()
    table = servermanager.Fetch(build, idx=0)
    if table.GetNumberOfRows() != 1:
        build.UpdatePropertyInformation()
        reason = build.GetPropertyValue("LastError")
        raise DDGError("the design space was not built: " + (reason or "see the Output Messages"))
    return Model(directory, source)


def build_plan(budget_minutes, source=None, directory=None, size=64, design_voxels=None):
    """What a ``budget_minutes`` build of a volume would cost (DDG Build Design Space's
    PlanBuild, a short timed probe where the filters run): a dict with ``count``, ``heldout``,
    ``outline_count``, ``training_minutes``, the stages' estimated seconds, ``total_seconds``,
    ``disk_bytes``, ``downsample`` and ``describe`` (text); ``output_error`` when ``directory``
    would be refused; ``design_voxels`` as in build_design_space. Raises DDGError for a volume
    no design space can be built on."""
    props = dict(
        BudgetMinutes=_within(budget_minutes, "build_plan", "budget_minutes", 1, 100000),
        Size=_whole(size, "build_plan", "size", 16, 512),
    )
    if design_voxels is not None:
        props["DesignVoxels"] = _whole(design_voxels, "build_plan", "design_voxels", 4096, 1 << 40)
    source = _source(source)
    build = _proxy(
        "DDGBuildDesignSpace",
        source,
        OutputDirectory=os.path.abspath(directory) if directory else "",
        **props,
    )
    build.SMProxy.InvokeCommand("PlanBuild")
    build.UpdatePropertyInformation()
    plan = json.loads(build.GetPropertyValue("BuildPlan"))
    if "error" in plan:
        raise DDGError(plan["error"])
    return plan


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
    (numpy), ``neighbours`` (nearest outline rows, for queries), ``neighbour_thumbnails``
    (queries: their thumbnails at the query's view, numpy images, as the panel shows them) and
    ``neighbour_picture_psnr`` (queries: each of those against the picture, dB)."""

    def __init__(self, model, history, neighbours=None):
        self.model = model
        self._history = history  # a vtkDDGDesignHistory: its steps are written by Core
        self.neighbours = list(neighbours or [])
        self.neighbour_thumbnails = []  # queries: the neighbours' thumbnails (query())
        self.neighbour_picture_psnr = []  # queries: each of those against the picture (dB)
        self.picture_psnr = None  # queries: against the picture (query())
        self.picture_lit = None  # queries: whether that figure is of the design lit
        self.warning = None  # queries: why the design is a guess (a photograph), else None
        self.kind = None  # queries: the kind check (query(kind=...)), else None
        self.kind_differs = False
        self._cache = {}

    @property
    def steps(self):
        """The steps of the design's history (dicts as in the history JSON)."""
        return json.loads(self._history.GetJSON())["steps"]

    def history(self):
        """The design's history as JSON text (``export(design, path, format="history")``)."""
        return self._history.GetJSON()

    def _then(self, add, *args):
        """A new design: this one's history plus the step ``add(*args)`` builds."""
        history = _history(self._history.GetJSON())
        if getattr(history, add)(*args) is False:
            raise DDGError(history.GetError())
        return Design(self.model, history)

    def evaluate(self, view=None, fidelity=False):
        """Runs DDG Design at ``view`` (default: the active view's camera, at most 256 pixels):
        a dict with "preview" (numpy image), "latent", "position", "preset", "slicer",
        "clusters" (mean RGB and share of each colour cluster) and with ``fidelity`` "fidelity"
        (PSNR dB, SSIM, max error); 2D models add "paraview_2d" (the TransferFunction2D proxy's
        Boxes, Range and OutputDimensions fitted to the design, with the fit's errors)."""
        v = view_json(view, self.model.source, 256)
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
            "preset": json.loads(_tf_text(table)),
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
        return _first_tf(self.evaluate(view)["preset"])

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
    history = _history()
    history.AddPick(int(row))
    return Design(model, history)


def query(image, source=None, view=None, model=None, neighbours=5, thumbnail_size=0, kind=True):
    """Queries the model's design space with an image (a file path or a numpy image): the
    analyzer's design, placed on the outline, with its ``neighbours`` nearest outline rows.
    ``view`` is where its preview is rendered and its explicit TF made (default: the active
    view's camera; a view that shows nothing yet: ParaView's Reset Camera on the volume, as
    ``view_json`` gives it). Returns a Design; its ``picture_psnr`` is the design against the picture,
    both framed on their content (dB: how close it looks without the picture's camera; the
    picture's lighting not known either, the better of the design unlit and lit, which
    ``picture_lit`` says). A picture of lines or text (a chart) raises DDGError; one that cannot
    be read as a rendered volume (a photograph) gives a design with a ``warning`` (also warned).
    With ``thumbnail_size`` > 0 (up to 512; the panel's is 64) the design's ``neighbour_thumbnails`` are the nearest designs'
    thumbnails (the first 64) at ``view``'s camera, ``thumbnail_size`` pixels square, and its
    ``neighbour_picture_psnr`` how each of them looks against the picture (as ``picture_psnr``).
    ``kind``: True (default) checks whether the picture shows a volume of this one's kind with
    the shipped kind network (Data/Models/kind; about 10 s the first time for a volume), a
    directory another kind network, False no check: the Design's ``kind`` (a dict: "agreement",
    "threshold", "differs", "picture_like", "volume_like"; None when not checked) and
    ``kind_differs`` (also warned)."""
    if not 0 <= int(thumbnail_size) <= 512:
        raise DDGError("thumbnail_size must be 0 (none) to 512, not %s" % thumbnail_size)
    model, source = _model(model, source)
    v = view_json(view, source, 256)
    proxy = _proxy(
        "DDGQuery",
        source,
        ModelDirectory=model.directory,
        ViewJSON=json.dumps(v),
        ImageData=_image_text(image, "query"),
        Neighbours=int(neighbours),
        ThumbnailSize=int(thumbnail_size),
        KindNetwork=_kind_network(kind, "query"),
    )
    with _errors_named("query", image):
        _run(proxy)
    table = servermanager.Fetch(proxy, idx=1)
    rows = [int(table.GetValueByName(i, "Row").ToInt()) for i in range(table.GetNumberOfRows())]
    strip = servermanager.Fetch(proxy, idx=2)
    side, gap = int(thumbnail_size), 2
    cells = []
    if side > 0 and strip.GetNumberOfPoints() > 0:
        sheet = _to_numpy(strip)
        count = (sheet.shape[1] - gap) // (side + gap)
        cells = [sheet[gap : gap + side, gap + k * (side + gap) :][:, :side] for k in range(count)]
    latent = [float(x) for x in _field_numbers(table, "Latent")]
    history = _history()
    name = os.path.basename(image) if isinstance(image, str) else ""
    if not history.AddLatent(json.dumps(latent), name):
        raise DDGError(history.GetError())
    design = Design(model, history, rows)
    design.neighbour_thumbnails = cells
    if cells:
        against = table.GetColumnByName("NeighbourPicturePSNR")
        design.neighbour_picture_psnr = [against.GetValue(k) for k in range(len(cells))]
    design.picture_psnr = float(_field_numbers(table, "PicturePSNR")[0])
    design.picture_lit = bool(_field_numbers(table, "PictureLit")[0])
    design.warning = _field_string(table, "Warning")
    if design.warning:
        warnings.warn("query: " + design.warning)
    design.kind = _kind_of(table)
    design.kind_differs = bool(design.kind and design.kind["differs"])
    if design.kind_differs:
        warnings.warn(
            "query: the picture may show a volume of another kind (kind agreement %.2f < %.2f)"
            % (design.kind["agreement"], design.kind["threshold"])
        )
    return design


def interpolate(a, b, t, c=None, d=None, v=0.0):
    """The design at ``t`` between designs ``a`` and ``b`` (t = 0: a, 1: b; with ``c`` (and
    ``d``) the barycentric (bilinear) blend at (t, v), as Core's blendLatents)."""
    anchors = [x for x in (a, b, c, d) if x is not None]
    latents = [[float(z) for z in x.latent] for x in anchors]
    return Design(a.model, _history())._then("AddBlend", json.dumps(latents), float(t), float(v))


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
    if cluster is None and pick_pixel is None and axes is None:
        raise ValueError("edit: give a cluster (or pick_pixel) or axes")
    out = design
    if cluster is not None or pick_pixel is not None:
        x, y = (int(pick_pixel[0]), int(pick_pixel[1])) if pick_pixel is not None else (-1, -1)
        out = out._then(
            "AddEdit",
            json.dumps(view_json(view, design.model.source, 256)),
            int(cluster) if pick_pixel is None else -1,
            x,
            y,
            4,
            float(hue),
            float(saturation),
            float(lightness),
            float(visibility),
            False,
        )
    if axes is not None:
        out = out._then("SetAxes", json.dumps([float(s) for s in axes]))
    return out


# --- the outline ----------------------------------------------------------------------------------


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


# --- animation ------------------------------------------------------------------------------------


def animate(a, b, frames=30, source=None, view=None, directory=None, easing="smoothstep"):
    """ParaView renders of the designs from ``a`` to ``b``: ``frames`` blends on an eased path
    (smoothstep, linear or cosine, as ``ddg animate``) applied to the active view one after the
    other. Returns the frames as numpy images; with ``directory`` also writes frame_0000.png, ...
    The colour map is put back afterwards."""
    view = _view(view)
    source = _source(source)
    array = volume_array(source, view)
    lut, sof = simple.GetColorTransferFunction(array), simple.GetOpacityTransferFunction(array)
    before = (list(lut.RGBPoints), list(sof.Points))
    ease = _vtk_module("DDGFilters").vtkDDGDesignHistory.Ease  # Core's easing, as `ddg animate`
    if ease(0.5, easing) < 0:
        raise ValueError("animate: unknown easing %r (linear, smoothstep or cosine)" % easing)
    if directory:
        os.makedirs(directory, exist_ok=True)
    images = []
    try:
        for k in range(int(frames)):
            t = ease(k / max(1, frames - 1), easing)
            apply(interpolate(a, b, t), source=source, view=view)
            w, h = [int(s) for s in view.ViewSize]
            path = os.path.join(
                directory or os.environ.get("TMPDIR", "/tmp"),
                "frame_%04d.png" % k if directory else "ddg_frame_%d.png" % os.getpid(),
            )
            simple.SaveScreenshot(path, view, ImageResolution=[w, h])
            images.append(_read_png(path))
            if not directory:
                os.remove(path)
    finally:
        lut.RGBPoints, sof.Points = before
        simple.Render(view)
    return images
