"""ddg.tf: transfer functions as dicts: reconstructed from a screenshot, converted to ParaView's
TransferFunction2D, exported as files.
"""
import json

from paraview import servermanager

from .designs import Design
from .plugin import DDGError, _field_string, _first_tf, _tf_text
from .scene import _image_text, _proxy, _source, view_json


def _tf_dict(tf, view=None):
    """A TF as a dict: a Design (its explicit TF at `view`), a dict, a preset list or a file."""
    if isinstance(tf, Design):
        return tf.transfer_function(view)
    if isinstance(tf, str):
        with open(tf) as f:
            tf = json.load(f)
    tf = _first_tf(tf)
    if not isinstance(tf, dict):
        raise TypeError("a transfer function is a Design, a preset dict or a JSON file path")
    return tf


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
    text = _tf_text(servermanager.Fetch(proxy, idx=0))
    if not text:
        raise DDGError("the reconstruction failed (see the Output Messages)")
    return _first_tf(json.loads(text))


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
