"""The whole story on the embedded default (Tooth and its shipped model), in ParaView:

  1. the design gallery of Tooth's design space (sheet of thumbnails over its outline);
  2. a shipped ParaView screenshot as the query: its nearest designs and its explicit TF;
  3. that TF applied in ParaView at the screenshot's view, ParaView's render compared with it;
  4. the TF reconstructed from the screenshot by differentiable rendering, applied the same way;
  5. the ParaView presets and renders saved; metrics and the time of each step printed.

    scripts/with-xvfb.sh build/bin/pvpython Python/examples/main_job.py [OUT_DIR]

(`bash scripts/demo.sh` sets up, builds and runs this.) OUT_DIR defaults to build/demo.
"""
import json
import os
import subprocess
import sys
import time

import ddg
from paraview.simple import GetActiveViewOrCreate, SaveScreenshot, Show, XMLImageDataReader

out = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else "build/demo")
os.makedirs(out, exist_ok=True)
ddg_exe = os.environ.get("DDG_EXE", "ddg")
reference = ddg.data_path("Screenshots/tooth_dentin_enamel_oblique.png")
view = json.load(open(ddg.data_path("Views/tooth_oblique.json")))
view["background"] = [1.0, 1.0, 1.0]  # the screenshot was saved over white
steps = []


def step(name, start):
    steps.append((name, time.time() - start))
    print(f"[{time.time() - start:6.2f} s] {name}")


def compare(a, b):
    """PSNR, SSIM and colour-histogram EMD of two images (`ddg compare`)."""
    r = json.loads(
        subprocess.run(
            [ddg_exe, "compare", a, b, "--json"], check=True, capture_output=True, text=True
        ).stdout
    )
    return r["psnr"], r["ssim"], r["emd"]


def paraview_render(tf, name):
    """Applies `tf` to Tooth in ParaView at the reference view; saves the preset and the render."""
    ddg.export(tf, os.path.join(out, name + ".json"), view=view)
    ddg.apply(tf, source=tooth, view=render_view)
    png = os.path.join(out, name + ".png")
    SaveScreenshot(png, render_view, ImageResolution=view["size"])
    return compare(png, reference)


t = time.time()
tooth = XMLImageDataReader(FileName=[ddg.data_path("Volumes/tooth.vti")])
render_view = GetActiveViewOrCreate("RenderView")
render_view.OrientationAxesVisibility = 0
render_view.UseColorPaletteForBackground = 0
render_view.Background = view["background"]
Show(tooth, render_view)
ddg.set_camera(view, render_view)
model = ddg.load_model(ddg.data_path("Models/tooth"), tooth)
step(
    "load Tooth (%s) and its model"
    % "x".join(str(d) for d in tooth.GetDataInformation().GetExtent()[1::2]),
    t,
)

t = time.time()
g = ddg.gallery(tooth, model, count=64, thumbnail_size=64)
ddg.save_image(g.sheet, os.path.join(out, "gallery.png"))
step(
    f"gallery: {len(g.x)} designs on the outline, {len(g.thumbnails)} thumbnails -> gallery.png", t
)

t = time.time()
found = ddg.query(reference, source=tooth, view=view, model=model)
result = found.evaluate(view, fidelity=True)
ddg.save_image(result["preview"], os.path.join(out, "query_preview.png"))
step(
    f"query with {os.path.basename(reference)}: outline position ({result['position'][0]:.1f}, "
    f"{result['position'][1]:.1f}), nearest designs {found.neighbours}",
    t,
)

t = time.time()
q = paraview_render(found, "query_paraview")
step("its TF applied in ParaView -> query_paraview.png, query_paraview.json", t)

t = time.time()
tf = ddg.reconstruct(reference, source=tooth, view=view, iterations=300)
step("TF reconstructed from the screenshot (differentiable rendering)", t)
t = time.time()
r = paraview_render(tf, "reconstructed_paraview")
step(
    "reconstructed TF applied in ParaView -> reconstructed_paraview.png, reconstructed_paraview.json",
    t,
)

print()
print("ParaView's render against the reference screenshot (400x320):")
print(
    f"  query (nearest design's explicit TF): PSNR {q[0]:5.2f} dB  SSIM {q[1]:.4f}  EMD {q[2]:.2f}"
)
print(
    f"  differentiable reconstruction:        PSNR {r[0]:5.2f} dB  SSIM {r[1]:.4f}  EMD {r[2]:.2f}"
)
print(
    f"  fidelity of the queried design (neural vs. ray cast of its TF): PSNR {result['fidelity'][0]:.1f} dB"
)
print(f"total {sum(s for _, s in steps):.1f} s; outputs in {out}")
