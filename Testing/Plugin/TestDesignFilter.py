"""DDG Design in pvpython on the shipped Tooth bundle, and the text inputs the panel uses
(ViewJSON, ImageData) on DDG Query.

A design given as a history (pick, latent, blend, edit, axes, lock) at a view: its "Preset" must
equal what `ddg replay` writes for the same history (the same Core code), blend corners must
reproduce their anchors, an edit must change the design, the fidelity must be high. DDG Query
given the screenshot as base64 ImageData and the view as ViewJSON must give exactly the outputs of
ImageFile/ViewFile. Bad input: exactly one error and empty outputs.

Usage: pvpython TestDesignFilter.py PLUGIN DDG DATA TESTDATA OUTDIR
"""
import base64
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ddgtest import Errors  # noqa: E402

from paraview import servermanager  # noqa: E402
from paraview.simple import LoadPlugin, XMLImageDataReader  # noqa: E402
import paraview.simple as simple  # noqa: E402

plugin, ddg, data, testdata, outdir = sys.argv[1:6]
os.makedirs(outdir, exist_ok=True)
LoadPlugin(plugin, remote=False)
volume = os.path.join(data, "Volumes", "tooth.vti")
model = os.path.join(data, "Models", "tooth")
shot = os.path.join(data, "Screenshots", "tooth_dentin_enamel_oblique.png")
view_file = os.path.join(data, "Views", "tooth_oblique.json")
view_text = open(view_file).read()


def history(*steps):
    return json.dumps({"format": "ddg-history", "version": 1, "steps": list(steps)})


reader = XMLImageDataReader(FileName=[volume])
design = simple.DDGDesign(Input=reader, ModelDirectory=model, ViewJSON=view_text, ComputeFidelity=1)


def run(h, **props):
    design.History = h
    for key, value in props.items():
        setattr(design, key, value)
    design.UpdatePipeline()
    table = servermanager.Fetch(design, idx=1)
    fields = table.GetFieldData()
    latent = fields.GetArray("Latent")
    return {
        "table": table,
        "latent": [latent.GetValue(i) for i in range(latent.GetNumberOfTuples())],
        "preset": json.loads(fields.GetAbstractArray("Preset").GetValue(0)),
        "fidelity": [fields.GetArray("Fidelity").GetValue(i) for i in range(3)],
        "preview": servermanager.Fetch(design, idx=0),
    }


# a pick equals ddg replay of the same history
pick = history({"action": "pick", "row": 4725})
r = run(pick)
with open(os.path.join(outdir, "pick.json"), "w") as f:
    f.write(pick)
cli_tf = os.path.join(outdir, "pick_tf.json")
subprocess.run(
    [
        ddg,
        "replay",
        "--model",
        model,
        "--volume",
        volume,
        "--history",
        os.path.join(outdir, "pick.json"),
        "--view",
        view_file,
        "--out-tf",
        cli_tf,
    ],
    check=True,
    capture_output=True,
)
assert (
    json.load(open(cli_tf))[0]["RGBPoints"] == r["preset"][0]["RGBPoints"]
), "Preset differs from ddg replay"
dims = r["preview"].GetDimensions()
view = json.loads(view_text)
assert [dims[0], dims[1]] == view["size"], dims
clusters = r["table"].GetNumberOfRows()
assert 1 <= clusters <= 4, clusters
assert r["fidelity"][0] > 35, r["fidelity"]
print(
    f"pick: preset = ddg replay's; preview {dims[0]}x{dims[1]}, {clusters} colour clusters, "
    f"fidelity {r['fidelity'][0]:.1f} dB / SSIM {r['fidelity'][1]:.3f}"
)

# a latent step reproduces the design; blend corners reproduce their anchors
other = run(history({"action": "pick", "row": 39027}))
same = run(history({"action": "latent", "latent": r["latent"]}))
assert same["preset"] == r["preset"], "a latent step should reproduce the design"
for u, want in ((0.0, r), (1.0, other)):
    b = run(history({"action": "blend", "latents": [r["latent"], other["latent"]], "u": u, "v": 0}))
    assert (
        max(abs(x - y) for x, y in zip(b["latent"], want["latent"])) < 1e-6
    ), f"blend corner u={u}"
mid = run(history({"action": "blend", "latents": [r["latent"], other["latent"]], "u": 0.5, "v": 0}))
assert mid["preset"] != r["preset"] and mid["preset"] != other["preset"]
print("latent step and blend corners reproduce their designs; the midpoint is a third design")

# an edit and an axis move change the design; a lock keeps region 0 of the locked design
edited = run(
    history(
        {"action": "pick", "row": 4725},
        {"action": "edit", "view": view, "cluster": 0, "hue": 90},
        {"action": "axes", "steps": [1.0, -0.5]},
    )
)
assert edited["latent"] != r["latent"], "an edit should change the latent"
locked = run(history({"action": "pick", "row": 39027}), LockedRegions=[0], LockHistory=pick)
assert locked["preview"].GetNumberOfPoints() > 0 and locked["preset"] != other["preset"]
design.LockedRegions = []
design.LockHistory = ""
print("edit + axes changed the design; a lock on region 0 changed the other design")

errors = Errors(design)
errors.expect("no history", "no History set", History="")
errors.expect("bad json", "History:", History="{bad")
errors.expect(
    "other model's latent",
    "this model's latents have 64",
    History=history({"action": "latent", "latent": [0.5] * 10}),
)
errors.expect("bad view", "ViewJSON", History=pick, ViewJSON='{"camera": {"position": [0, 0, 1]}}')
errors.expect(
    "lock on a missing region", "region", ViewJSON=view_text, LockedRegions=[9], LockHistory=pick
)
design.LockedRegions = []

# the panel's inputs: base64 image data and view JSON give the file inputs' results
by_file = simple.DDGQuery(Input=reader, ModelDirectory=model, ImageFile=shot, ViewFile=view_file)
by_text = simple.DDGQuery(
    Input=reader,
    ModelDirectory=model,
    ViewJSON=view_text,
    ImageData=base64.b64encode(open(shot, "rb").read()).decode(),
)
by_file.UpdatePipeline()
by_text.UpdatePipeline()
a, b = servermanager.Fetch(by_file, idx=1), servermanager.Fetch(by_text, idx=1)
assert a.GetFieldData().GetAbstractArray("Preset").GetValue(0) == b.GetFieldData().GetAbstractArray(
    "Preset"
).GetValue(0)
assert [a.GetValue(i, 0).ToInt() for i in range(5)] == [b.GetValue(i, 0).ToInt() for i in range(5)]
print("DDG Query: ImageData + ViewJSON = ImageFile + ViewFile")
qerr = Errors(by_text)
qerr.expect("not base64", "is not base64", ImageData="%%%%")
qerr.expect(
    "not an image",
    "not a PNG, JPEG, TIFF, BMP, GIF or WebP",
    ImageData=base64.b64encode(b"hello world!").decode(),
)
qerr.expect(
    "corrupt png",
    "cannot read the picture: ",
    ImageData=base64.b64encode(open(shot, "rb").read()[:200]).decode(),
)
assert "library error" not in qerr.messages[0], "libpng's own lines: " + qerr.messages[0]
print("ok")
