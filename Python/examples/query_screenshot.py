"""Query a volume's design space with a screenshot and save what it found.

    build/bin/pvpython Python/examples/query_screenshot.py [VOLUME IMAGE VIEW OUT_DIR]

Defaults: Tooth, the shipped ParaView screenshot tooth_dentin_enamel_oblique.png and its view.
Writes OUT_DIR/preview.png (the model's render of the design), OUT_DIR/preset.json (its TF as
a ParaView preset), OUT_DIR/paraview.png (ParaView's render with that TF) and prints the
design's outline position, nearest outline designs and fidelity.
"""
import os
import sys
import time

import ddg
from paraview.simple import GetActiveView, SaveScreenshot, Show, XMLImageDataReader

volume, image, view, out = (
    sys.argv[1:5]
    if len(sys.argv) > 4
    else (
        ddg.data_path("Volumes/tooth.vti"),
        ddg.data_path("Screenshots/tooth_dentin_enamel_oblique.png"),
        ddg.data_path("Views/tooth_oblique.json"),
        "query_out",
    )
)
os.makedirs(out, exist_ok=True)


source = XMLImageDataReader(FileName=[volume])
Show(source)
ddg.set_camera(view)
start = time.time()
found = ddg.query(image, view=view)
result = found.evaluate(view, fidelity=True)
print(
    f"query: {time.time() - start:.2f} s; outline position ({result['position'][0]:.2f}, "
    f"{result['position'][1]:.2f}); nearest outline rows {found.neighbours}"
)
print(
    f"fidelity (neural vs. ray cast of its TF): PSNR {result['fidelity'][0]:.1f} dB, "
    f"SSIM {result['fidelity'][1]:.3f}"
)
ddg.save_image(result["preview"], os.path.join(out, "preview.png"))
ddg.export(found, os.path.join(out, "preset.json"), view=view)
ddg.apply(found)
SaveScreenshot(os.path.join(out, "paraview.png"), GetActiveView())
print("wrote", ", ".join(sorted(os.listdir(out))), "in", out)
