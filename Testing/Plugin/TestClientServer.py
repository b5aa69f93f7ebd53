"""The filters through pvserver: the plugin loads on the server (remote=True), the filters run
there and the client fetches only their small results: DDG Volume Render's image, DDG Query's
designs table and preset (shipped Tooth bundle, shipped screenshot), DDG Reconstruct Transfer
Function's table and preset.

Usage: pvpython TestClientServer.py PLUGIN DATA
"""
import base64
import json
import os
import sys

from paraview import servermanager
import paraview.simple as simple

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ddgtest import apply_and_render, start_pvserver, stop_pvserver  # noqa: E402

plugin, data = sys.argv[1:3]
server = start_pvserver()
try:
    simple.LoadPlugin(plugin, remote=True)
    reader = simple.XMLImageDataReader(FileName=[os.path.join(data, "Volumes", "neghip.vti")])
    render = simple.DDGVolumeRender(Input=reader)
    render.TransferFunctionFile = os.path.join(data, "TransferFunctions", "neghip_shells.json")
    render.ViewFile = os.path.join(data, "Views", "neghip_side.json")
    render.UpdatePipeline()
    image = servermanager.Fetch(render)
    dims = image.GetDimensions()
    assert dims[0] == 320 and dims[1] == 320, dims
    rgba = image.GetPointData().GetArray("RGBA")
    alpha = max(rgba.GetRange(3))
    assert alpha > 0.1, alpha
    print(f"client/server render ok: {dims[0]}x{dims[1]}, max alpha {alpha:.3f}")

    tooth = simple.XMLImageDataReader(FileName=[os.path.join(data, "Volumes", "tooth.vti")])
    shot = os.path.join(data, "Screenshots", "tooth_dentin_enamel_oblique.png")
    view = os.path.join(data, "Views", "tooth_oblique.json")
    if hasattr(simple, "DDGQuery"):
        query = simple.DDGQuery(Input=tooth)
        query.ModelDirectory = os.path.join(data, "Models", "tooth")
        query.ImageFile = shot
        query.ViewFile = view
        query.UpdatePipeline()
        table = servermanager.Fetch(query, idx=1)
        assert table.GetNumberOfRows() == 5, table.GetNumberOfRows()
        preset = table.GetFieldData().GetAbstractArray("Preset").GetValue(0)
        assert '"RGBPoints"' in preset
        print(
            f"client/server query ok: {table.GetNumberOfRows()} designs, preset {len(preset)} chars"
        )
        # the panel's way: the image as base64 text and the view as JSON text (nothing read from
        # the server's disk but the bundle and the volume), then apply and render
        query.ImageFile = ""
        query.ViewFile = ""
        query.ImageData = base64.b64encode(open(shot, "rb").read()).decode()
        query.ViewJSON = open(view).read()
        query.UpdatePipeline()
        same = (
            servermanager.Fetch(query, idx=1).GetFieldData().GetAbstractArray("Preset").GetValue(0)
        )
        assert same == preset, "ImageData/ViewJSON should give the ImageFile/ViewFile preset"
        shot_out = os.path.join(os.environ.get("TMPDIR", "/tmp"), f"ddg_cs_apply_{os.getpid()}.png")
        size = apply_and_render(tooth, json.loads(preset)[0], view, shot_out)
        assert size > 5000, size
        print(f"client/server apply ok: the query's preset in the LUT, rendered ({size} bytes PNG)")
    rec = simple.DDGReconstructTransferFunction(Input=tooth)
    rec.TargetImageFile = os.path.join(data, "Screenshots", "tooth_cool_warm_side.png")
    rec.ViewFile = os.path.join(data, "Views", "tooth_side.json")
    rec.Iterations = 20
    rec.UpdatePipeline()
    table = servermanager.Fetch(rec)
    assert table.GetNumberOfRows() == 128, table.GetNumberOfRows()
    print("client/server reconstruct ok")
finally:
    stop_pvserver(server)
