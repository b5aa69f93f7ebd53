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

The package's modules: ``ddg.plugin`` (loading the plugin, ``DDGError``, ``data_path``),
``ddg.scene`` (the volume's array, views, images, ``apply``, ``render``), ``ddg.designs`` (models,
designs, queries, the gallery, ``animate``) and ``ddg.tf`` (``reconstruct``, ``match``,
``carry_look``, ``paraview_2d``, ``export``); every public name is also ``ddg.<name>``.
"""
from .plugin import DDGError, _ensure_plugin, data_path

_ensure_plugin()  # importing the package loads the plugin (on the server too when connected)

from .scene import apply, render, save_image, set_camera, view_json  # noqa: E402
from .designs import (  # noqa: E402
    Design,
    Gallery,
    Model,
    animate,
    build_design_space,
    build_plan,
    edit,
    gallery,
    interpolate,
    load_model,
    pick,
    query,
)
from .tf import (
    CarriedLook,
    Match,
    carry_look,
    export,
    match,
    paraview_2d,
    reconstruct,
)  # noqa: E402

__all__ = [
    "Model",
    "Design",
    "Gallery",
    "load_model",
    "build_design_space",
    "build_plan",
    "gallery",
    "query",
    "pick",
    "reconstruct",
    "match",
    "Match",
    "carry_look",
    "CarriedLook",
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
