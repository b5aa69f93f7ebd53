"""Writes the shipped reference screenshots (Data/Screenshots/): ParaView's own Volume rendering
of a shipped volume with a shipped preset at a shipped view, as a user would save them with
File > Save Screenshot. They are the query images of the examples, the tests and the main job.
Each picture gets its own view file next to it (<name>.json: the shipped view's camera and size
with the background it was saved over), the view to reconstruct it with.

Run: xvfb-run -a pvpython scripts/make_screenshots.py   (deterministic: same files every run)
"""
import json
import os
import sys

root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
sys.path.insert(0, os.path.join(root, "Testing", "Parity"))
from pvrender import paraview_render  # noqa: E402

CASES = [  # volume, preset, view, background (None: the view's)
    ("tooth", "tooth_dentin_enamel", "oblique", [1.0, 1.0, 1.0]),
    ("tooth", "tooth_cool_warm", "side", [0.0, 0.0, 0.0]),
    ("engine", "engine_block", "oblique", [1.0, 1.0, 1.0]),
]

data = os.path.join(root, "Data")
out_dir = os.path.join(data, "Screenshots")
os.makedirs(out_dir, exist_ok=True)
for volume, preset_name, view_name, background in CASES:
    with open(os.path.join(data, "TransferFunctions", preset_name + ".json")) as f:
        preset = json.load(f)[0]
    with open(os.path.join(data, "Views", f"{volume}_{view_name}.json")) as f:
        view = json.load(f)
    if background is not None:
        view["background"] = background
    out = os.path.join(out_dir, f"{preset_name}_{view_name}.png")
    paraview_render(os.path.join(data, "Volumes", volume + ".vti"), preset, view, out)
    with open(out[: -len(".png")] + ".json", "w") as f:  # the picture's own view
        json.dump(view, f, indent=2, sort_keys=True)
        f.write("\n")
    print("wrote", out, "and its view")
