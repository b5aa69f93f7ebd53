"""Animate between two designs of a volume's design space in ParaView.

    build/bin/pvpython Python/examples/animate_designs.py [OUT_DIR [FRAMES]]

Tooth and its shipped model: the design found by querying the shipped screenshot and the
outline's first thumbnail; FRAMES (default 12) ParaView renders on a smoothstep path are written
to OUT_DIR/frame_NNNN.png (default animation_out).
"""
import os
import sys

import ddg
from paraview.simple import Show, XMLImageDataReader

out = sys.argv[1] if len(sys.argv) > 1 else "animation_out"
frames = int(sys.argv[2]) if len(sys.argv) > 2 else 12
tooth = XMLImageDataReader(FileName=[ddg.data_path("Volumes/tooth.vti")])
Show(tooth)
ddg.set_camera(ddg.data_path("Views/tooth_oblique.json"))
a = ddg.query(ddg.data_path("Screenshots/tooth_dentin_enamel_oblique.png"))
b = ddg.gallery(tooth).design(0)
images = ddg.animate(a, b, frames, directory=out)
change = [
    float(abs(images[k + 1].astype(int) - images[k].astype(int)).mean())
    for k in range(len(images) - 1)
]
print(
    f"{len(images)} frames in {out}; mean change between frames {min(change):.2f}..{max(change):.2f} grey levels"
)
