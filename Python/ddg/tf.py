"""ddg.tf: transfer functions as dicts: reconstructed from a screenshot, matched to a picture as
users have it (camera and background estimated), converted to ParaView's TransferFunction2D,
exported as files.
"""
import math
import json
import re

from paraview import servermanager
from paraview import simple

from .designs import Design
from .plugin import DDGError, _field_numbers, _field_string, _first_tf, _kind_network, _kind_of
from .plugin import _run, _tf_text, _whole
from .scene import _errors_named, _image_text, _proxy, _rgb, _scene, _source, view_json


def _tf_dict(tf, view=None):
    """A TF as a dict: a Design (its explicit TF at `view`), a Match's or a CarriedLook's TF, a
    dict, a preset list or a file."""
    if isinstance(tf, Design):
        return tf.transfer_function(view)
    if isinstance(tf, (Match, CarriedLook)):
        return tf.tf
    if isinstance(tf, str):
        with open(tf) as f:
            tf = json.load(f)
    tf = _first_tf(tf)
    if not isinstance(tf, dict):
        raise TypeError(
            "a transfer function is a Design, a Match, a CarriedLook, a preset dict or a JSON "
            "file path"
        )
    return tf


def _background_props(background):
    """The filter's EstimateBackground / Background for ``background`` (None: estimated)."""
    if background is None:
        return dict(EstimateBackground=1)
    rgb = [float(c) for c in background]
    if len(rgb) != 3 or not all(0.0 <= c <= 1.0 for c in rgb):
        raise ValueError("background is (r, g, b) in [0, 1], or None (estimated)")
    return dict(EstimateBackground=0, Background=rgb)


def reconstruct(
    image,
    source=None,
    view=None,
    iterations=300,
    bins=128,
    smoothness=None,
    learning_rate=None,
    two_d=False,
    background=None,
    seed=None,
):
    """The TF that renders ``source`` like ``image`` (a screenshot file or numpy image of the
    volume, the view's size) at ``view`` (a view JSON file or dict, or the active view's camera:
    then the image must have the view's size): differentiable reconstruction (DDG Reconstruct
    Transfer Function), at most ``iterations`` Adam steps (it stops once converged; the filter's
    and ``ddg reconstruct``'s default is 500). ``background``: the screenshot's background
    (r, g, b) in [0, 1]; None (default) estimates it from the screenshot's border (the view's
    when they agree; otherwise the border's, with a warning). ``seed``: of the pixels sampled
    (``--seed``; default 1). Returns the TF dict (a ParaView preset)."""
    source = _source(source)
    v = view_json(view, source)
    proxy = _proxy(
        "DDGReconstructTransferFunction",
        source,
        TargetImageData=_image_text(image, "reconstruct"),
        ViewJSON=json.dumps(v),
        Iterations=_whole(iterations, "reconstruct", "iterations", 1, 100000),
        Bins=_whole(bins, "reconstruct", "bins", 2, 4096),
        TwoD=int(two_d),
        **_background_props(background),
    )
    if smoothness is not None:
        proxy.SetPropertyWithName("Smoothness", float(smoothness))
    if learning_rate is not None:
        proxy.SetPropertyWithName("LearningRate", float(learning_rate))
    if seed is not None:
        proxy.SetPropertyWithName("Seed", _seed(seed, "reconstruct"))
    return _fit_picture(
        proxy,
        "reconstruct",
        lambda table, _: _first_tf(json.loads(_tf_text(table))),
        image,
        images=False,
    )


def _initial_json(initial, view, caller):
    """A fit's start (a Design, a preset dict or file; 1D) as the filter's
    InitialTransferFunction text; None: ""."""
    if initial is None:
        return ""
    d = _tf_dict(initial, view)
    if "RGBPoints" not in d:
        raise ValueError(caller + ": initial is a 1D transfer function (a ParaView preset)")
    return json.dumps([d])


def _fit_picture(proxy, label, result, image=None, images=True):
    """Runs a Reconstruct Transfer Function proxy set up for a picture; returns
    ``result(table, images)`` (``images``: output port 1 is fetched, else None is passed);
    DDGError names ``label`` (and ``image`` when it is a file). The picture is dropped from the
    proxy."""
    try:
        with _errors_named(label, image):
            _run(proxy)
            table = servermanager.Fetch(proxy, idx=0)
            if not _tf_text(table):
                raise DDGError("no transfer function (see the Output Messages)")
            return result(table, servermanager.Fetch(proxy, idx=1) if images else None)
    finally:
        proxy.SetPropertyWithName("TargetImageData", "")  # do not keep megabytes in the proxy


def _seed(seed, caller):
    """The filter's Seed (ddg reconstruct --seed): a whole number >= 0."""
    return _whole(seed, caller, "seed", 0)


class Match:
    """What ``match`` found for a picture.

    Attributes:
        tf: the fitted TF (ParaView preset dict; 2D: the DDG 2D TF dict).
        view: the picture's camera as a view JSON dict (README "View file"): camera, the
            picture's size, the estimated background (``background``, and ``background2`` for
            ParaView's gradient background) and the opacity unit distance. ``set_camera(view)``
            or ``apply(tf, camera=view)`` moves a render view there.
        camera_estimated: True when the camera came from the search (not given as is).
        lighting, lighting_estimated: the picture's lighting (the view's "lighting": {} is
            unlit) and whether the match chose it (unlit, Shade on, Shade on with specular:
            the best fit) rather than the given view.
        overlap: silhouette IoU of the camera (1 = exact).
        fit_psnr: PSNR (dB) of the fit over the compared pixels (Core's figure).
        psnr_before, psnr_after: PSNR (dB) against the picture of the project's render at
            ``view`` over the estimated background of the initial TF (NaN without ``initial``)
            and of the found TF, overlay pixels left out.
        background: ((r, g, b) bottom, (r, g, b) top) in [0, 1]; gradient: True for a gradient.
        orbit: (azimuth, elevation, roll) in degrees from ParaView's reset camera; zoom: the
            distance factor (and the parallel scale's divisor); pan: (right, up) in view
            heights. The projection, perspective or parallel (estimated when the camera is),
            is the view's ``camera["parallel_projection"]``.
        timings: seconds per stage, dict with "background", "camera", "fit", "total".
        crop: (x, y, width, height), the part of the picture matched (inside a letterbox; the
            whole picture otherwise): ``view``, ``image`` and the masks are its size.
        iterations: fit steps taken.
        image: the found TF's render at ``view`` over the background, (h, w, 3) uint8.
        foreground, overlay: the picture's masks, (h, w) bool: what differs from the
            background, and what was judged an overlay and left out.
    """

    def __init__(self, table, images):
        self.tf = _first_tf(json.loads(_tf_text(table)))
        self.view = json.loads(_field_string(table, "View"))
        self.camera_estimated = bool(_field_numbers(table, "CameraEstimated")[0])
        # the picture's lighting (the view JSON's "lighting"; {} unlit), and whether it was
        # estimated (matched unlit and lit, the best fit kept) or given with the view
        self.lighting = self.view.get("lighting") or {}
        self.lighting_estimated = bool(_field_numbers(table, "LightingEstimated")[0])
        self.overlap = float(_field_numbers(table, "Overlap")[0])
        self.fit_psnr = float(_field_numbers(table, "FitPSNR")[0])
        self.psnr_before, self.psnr_after = (float(x) for x in _field_numbers(table, "PicturePSNR"))
        bg = _field_numbers(table, "Background")
        self.background = (tuple(bg[:3]), tuple(bg[3:]))
        self.gradient = bool(_field_numbers(table, "GradientBackground")[0])
        self.orbit = tuple(float(x) for x in _field_numbers(table, "Orbit"))
        self.zoom = float(_field_numbers(table, "Zoom")[0])
        self.pan = tuple(float(x) for x in _field_numbers(table, "Pan"))
        t = _field_numbers(table, "Timings")
        self.timings = dict(zip(("background", "camera", "fit", "total"), (float(x) for x in t)))
        self.iterations = int(_field_numbers(table, "Iterations")[0])
        self.crop = tuple(int(x) for x in _field_numbers(table, "Crop"))
        pd = images.GetPointData()
        self.image = _rgb(images, pd.GetArray("Image")).astype("uint8")
        self.foreground = (
            _rgb(images, pd.GetArray("Foreground"))[:, :, 0] > 127
            if pd.GetArray("Foreground")
            else None
        )
        self.overlay = (
            _rgb(images, pd.GetArray("Overlay"))[:, :, 0] > 127 if pd.GetArray("Overlay") else None
        )

    def __repr__(self):
        # without an initial TF there is no "before" (NaN): the found TF's figure alone
        before = "" if math.isnan(self.psnr_before) else "%.1f -> " % self.psnr_before
        lit = "lit" if self.lighting else "unlit"
        return (
            "Match(PSNR %s%.1f dB against the picture, fit %.1f dB, overlap %.2f, camera %s, "
            "picture %s (%s), %.1f s)"
            % (
                before,
                self.psnr_after,
                self.fit_psnr,
                self.overlap,
                "estimated" if self.camera_estimated else "given",
                lit,
                "estimated" if self.lighting_estimated else "given",
                self.timings["total"],
            )
        )


def match(
    image,
    source=None,
    camera=None,
    initial=None,
    refine_camera=False,
    iterations=None,
    bins=128,
    two_d=False,
    mask_overlays=True,
    minimum_overlap=None,
    background=None,
    seed=None,
):
    """A TF and the camera that make ``source`` (default: the active source) look like
    ``image``, a picture as users have it (a file path or a numpy image (h, w, 3); any size,
    ParaView's GUI background or gradient, orientation axes or a scalar bar in it): DDG
    Reconstruct Transfer Function with Match Picture on (Core's ``matchPicture``). The
    background is estimated from the picture, overlays are masked, and the TF keeps empty space
    transparent.

    ``camera``: None (default) estimates it from ParaView's reset camera (azimuth, elevation,
    roll, distance, pan; perspective or parallel projection); "current" takes the active render
    view's camera (the picture was taken from it); a view JSON file path or dict gives it.
    ``refine_camera`` searches from a given camera instead of taking it as is. ``initial``: the
    TF the fit starts from (a Design, e.g. ``query(image)``'s, a preset dict or file; 1D); None:
    grey. ``iterations``: the final fit's maximum steps (default: the filter's, 500; it stops
    once converged). ``minimum_overlap``: below this silhouette IoU (default 0.6) no camera
    explains the picture. ``background``: the picture's background (r, g, b) in [0, 1]; None
    (default): estimated (uniform or gradient). ``seed``: of the fit's pixels sampled (``--seed``;
    default 1).

    Returns a ``Match``: ``.tf`` (preset dict, for ``apply``/``export``), ``.view`` (the
    camera as a view JSON dict, for ``set_camera`` or ``apply(tf, camera=...)``), and the
    figures (``psnr_before``, ``psnr_after``, ``overlap``, ``timings``, the masks). Raises
    DDGError with the filter's reason (a uniform picture, a picture under 16 pixels a side, one
    no camera explains: another volume, an unreadable image)."""
    source = _source(source)
    if isinstance(camera, str) and camera == "current":
        v = view_json(None, source)
    elif camera is not None:
        v = view_json(camera)
    else:
        v = None
    init = _initial_json(initial, v, "match")
    props = dict(
        MatchPicture=1,
        TargetImageData=_image_text(image, "match"),
        ViewJSON=json.dumps(v) if v is not None else "",
        EstimateCamera=int(bool(refine_camera)),
        InitialTransferFunction=init,
        Bins=_whole(bins, "match", "bins", 2, 4096),
        TwoD=int(two_d),
        MaskOverlays=int(bool(mask_overlays)),
        **_background_props(background),
    )
    if iterations is not None:
        props["Iterations"] = _whole(iterations, "match", "iterations", 1, 100000)
    if minimum_overlap is not None:
        props["MinimumOverlap"] = float(minimum_overlap)
    if seed is not None:
        props["Seed"] = _seed(seed, "match")
    proxy = _proxy("DDGReconstructTransferFunction", source, **props)
    return _fit_picture(proxy, "match", Match, image)


class CarriedLook:
    """What ``carry_look`` found: another volume's look carried over to this one.

    Attributes:
        tf: the TF (ParaView preset dict, for ``apply``/``export``).
        view: where the look is shown (view JSON dict: azimuth 30, elevation 20 from ParaView's
            reset camera, 256 x 256, over the picture's background, and the "lighting" it was
            fitted under, which ``apply`` sets). Not the picture's camera: another volume's
            picture has none here.
        regions: per feature region of this volume, a dict: "values" (from, to), "colour" (the
            picture's r, g, b in [0, 1] it was matched with), "share" (that colour's share of
            the picture's object).
        distance_start, distance_end: the colour distance (CIELAB, sliced Wasserstein) of the
            start and of the result.
        overlay_share: share of the picture's foreground left out as overlays.
        shape_agreement: this volume's best silhouette IoU against the picture's object;
            shapes_agree: it reaches 0.6 (False: the picture may show a volume of another kind;
            blob-like volumes of other kinds agree too, so only a gross mismatch is caught).
        kind: the kind network's check (``carry_look(kind=...)``), a dict: "agreement" (1 =
            the network answers alike for the picture and this volume's own exemplars),
            "threshold", "differs" (agreement under threshold: the picture may show a volume of
            another kind), "picture_like" and "volume_like" (the training volume each is most
            like); None when not checked. kind_differs: its "differs" (False when not checked).
        seconds: the whole carry's time; iterations: the fit's steps.
        image: the TF's render at ``view`` over the background, (h, w, 3) uint8.
    """

    def __init__(self, table, images):
        self.tf = _first_tf(json.loads(_tf_text(table)))
        self.view = json.loads(_field_string(table, "View"))
        rows = _field_numbers(table, "Regions")
        self.regions = [
            {
                "values": (float(rows[k]), float(rows[k + 1])),
                "colour": tuple(float(x) for x in rows[k + 2 : k + 5]),
                "share": float(rows[k + 5]),
            }
            for k in range(0, len(rows), 6)
        ]
        self.distance_start, self.distance_end = (
            float(x) for x in _field_numbers(table, "ColourDistance")
        )
        self.overlay_share = float(_field_numbers(table, "OverlayShare")[0])
        agreement = _field_numbers(table, "ShapeAgreement")
        self.shape_agreement, self.shapes_agree = float(agreement[0]), bool(agreement[1])
        self.kind = _kind_of(table)
        self.kind_differs = bool(self.kind and self.kind["differs"])
        self.seconds = float(_field_numbers(table, "Timings")[0])
        self.iterations = int(_field_numbers(table, "Iterations")[0])
        self.image = _rgb(images, images.GetPointData().GetArray("Image")).astype("uint8")

    def __repr__(self):
        return (
            "CarriedLook(%d regions, colour distance %.1f -> %.1f, shape agreement %.2f%s%s, %.1f s)"
            % (
                len(self.regions),
                self.distance_start,
                self.distance_end,
                self.shape_agreement,
                "" if self.shapes_agree else " (shapes disagree: another kind?)",
                (
                    ", kind agreement %.2f%s"
                    % (
                        self.kind["agreement"],
                        " (another kind? under %.2f)" % self.kind["threshold"]
                        if self.kind_differs
                        else "",
                    )
                    if self.kind
                    else ""
                ),
                self.seconds,
            )
        )


def carry_look(image, source=None, initial=None, shade=None, seed=None, kind=True):
    """The look of ``image``, a picture of *another* volume of the same kind (a figure from a
    paper, a colleague's screenshot; a file path or a numpy image (h, w, 3)), carried over to
    ``source`` (default: the active source): DDG Reconstruct Transfer Function with Carry Look
    on (Core's ``carryLook``). The picture's object colours are matched to this volume's feature
    regions by rank (darkest to the lowest values), then refined by colour distribution; no
    pixel of the picture has to line up with this volume. ``initial``: a TF of this volume to
    start from instead (a Design, e.g. ``query(image)``'s, a preset dict or file; 1D): the fit
    is of free bins from it, the regions still matched and reported (``ddg reconstruct
    --carry-look --init``). ``shade``: None (default) fits the look under the lighting
    ``source`` has in the active render view (its Shade and coefficients, which ``apply`` then
    sets; unlit when Shade is off, when it is not shown or the active view is not a render view),
    True under ParaView's default lighting (Shade on), False unlit (``--shade on|off``).
    ``seed``: of the colour distance's directions (``--seed``; default 1). ``kind``: True
    (default) checks whether the picture shows a volume of this one's kind with the project's
    kind network (Data/Models/kind, when it is there; about 10 s the first time for a volume),
    a directory another kind network, False no check (``--kind-network``); ``.kind`` says.

    Returns a ``CarriedLook`` (``.tf`` for ``apply``, ``.regions`` says what was matched with
    what). Raises DDGError with the filter's reason (a picture of nothing but its background,
    no dominant background, an unreadable image, a volume without feature regions)."""
    source = _source(source)
    if shade is None:  # as source is shown in the active render view (none: unlit)
        view = simple.GetActiveView()
        try:
            lighting = view_json(view, source, 16).get("lighting") if view is not None else None
        except ValueError:  # a spreadsheet, a chart: not a render view
            lighting = None
    else:
        lighting = {"shade": True} if shade else None
    props = dict(
        CarryLook=1,
        TargetImageData=_image_text(image, "carry_look"),
        ViewJSON=json.dumps({"lighting": lighting}) if lighting else "",  # only its lighting read
        InitialTransferFunction=_initial_json(initial, None, "carry_look"),
    )
    if seed is not None:
        props["Seed"] = _seed(seed, "carry_look")
    props["KindNetwork"] = _kind_network(kind, "carry_look")
    proxy = _proxy("DDGReconstructTransferFunction", source, **props)
    return _fit_picture(proxy, "carry_look", CarriedLook, image)


def paraview_2d(tf, source=None, view=None):
    """ParaView 5.11's TransferFunction2D for a 2D TF (Design, DDG 2D JSON dict or file) on
    ``source``: a dict of the proxy's ``Boxes`` (8 numbers per Gaussian box: lower-left x, y,
    width, height, r, g, b, a), ``Range`` and ``OutputDimensions``, fitted on the server so that
    ParaView's 2D rendering matches the project's (its axes are value and gradient magnitude in
    value units per voxel; alpha per ray sample), and ``Fit`` (rmse, initial_rmse, alpha_rmse,
    max_alpha on the fit grid). ``view`` gives the opacity unit distance."""
    source = _source(source)
    if isinstance(tf, Design):
        out = tf.evaluate(view_json(view, source, 256))
        if "paraview_2d" not in out:
            raise ValueError("paraview_2d: the design is 1D (apply it as a ParaView preset)")
        return out["paraview_2d"]
    d = _tf_dict(tf)
    if d.get("Format") != "ddg-transfer-function-2d":
        raise ValueError(
            'paraview_2d: not a DDG 2D transfer function ("Format": "ddg-transfer-function-2d")'
        )
    v = view_json(view, source, 16)
    v["size"] = [8, 8]  # the fit is what is wanted, not the image
    proxy = _proxy(
        "DDGVolumeRender", source, TransferFunctionJSON=json.dumps(d), ViewJSON=json.dumps(v)
    )
    proxy.UpdatePipeline()
    boxes = _field_string(servermanager.Fetch(proxy, idx=0), "ParaViewTransferFunction2D")
    if not boxes:
        raise DDGError("the 2D transfer function could not be converted (see the Output Messages)")
    return json.loads(boxes)


def _export_name(tf, d, path, source):
    """The preset's "Name" for ``path`` (Core's exportName through vtkSMDDGScene): "DDG <volume>
    <origin> <stem> <date> <time>" (the volume: ``source``'s name, a Design's, or the active
    source's; the origin: a Design's last step, or the TF's own name without "DDG" and a date),
    so that ParaView imports each exported file (it refuses a name it holds already)."""
    if isinstance(tf, Design):
        source = source or tf.model.source
        steps = tf.steps
        origin = steps[-1]["action"] if steps else "design"
        if origin == "latent" and steps[-1].get("image"):
            origin = "query"  # analysed from a picture: ddg.query
    else:
        origin = re.sub(r"^(ddg|DDG) ?", "", str(d.get("Name", "")))
        origin = re.sub(r" ?\d{4}-\d\d-\d\d \d\d:\d\d:\d\d$", "", origin)
    source = source or simple.GetActiveSource()
    volume = ""
    for (name, _), proxy in simple.GetSources().items() if source is not None else []:
        if proxy == source:
            volume = name
    # a reader says its volume by its file ("tooth.vti"), not by pvpython's "XMLImageDataReader1"
    files = source.GetProperty("FileName") if source is not None else None
    if files is not None:
        files = [files] if isinstance(files.GetData(), str) else list(files.GetData() or [])
        volume = files[0] if files and files[0] else volume
    return _scene().ExportName(volume, origin, path)


def export(tf, path, format="paraview", view=None, source=None):
    """Writes a TF: ``format`` "paraview" (preset JSON list, importable with
    ``ImportPresets``; its "Name" says the volume (``source``, default: a Design's or the active
    source), the TF's origin, the file's stem and the time, so that every exported file
    imports), "slicer" (3D Slicer .vp.json; Designs only) or "history" (a Design's path,
    replayed by ``ddg replay``)."""
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
        d = dict(_tf_dict(tf, view))
        d["Name"] = _export_name(tf, d, path, source)
        text = json.dumps([d] if "RGBPoints" in d else d, indent=1)
    else:
        raise ValueError("export: format is paraview, slicer or history")
    with open(path, "w") as f:
        f.write(text)
    return path
