"""Reconstruct a ParaView preset for every screenshot in a folder.

    build/bin/pvpython Python/examples/batch_reconstruct.py VOLUME FOLDER OUT_DIR [VIEW]

Each FOLDER/NAME.png is a screenshot of VOLUME; its view is FOLDER/NAME.view.json when that
exists, else VIEW. Writes OUT_DIR/NAME.json (a ParaView preset, importable with Import Presets)
and prints, per image, the time and the PSNR of our render with the preset against the image.
"""
import glob
import os
import sys
import time

import numpy as np

import ddg
from paraview.simple import XMLImageDataReader
from vtkmodules.util import numpy_support
from vtkmodules.vtkIOImage import vtkPNGReader

volume, folder, out = sys.argv[1:4]
default_view = sys.argv[4] if len(sys.argv) > 4 else None
os.makedirs(out, exist_ok=True)
source = XMLImageDataReader(FileName=[volume])


def read_png(path):
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    w, h, _ = image.GetDimensions()
    return numpy_support.vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)[
        ::-1, :, :3
    ]


images = sorted(glob.glob(os.path.join(folder, "*.png")))
if not images:
    sys.exit(f"no PNG screenshots in {folder}")
for path in images:
    name = os.path.splitext(os.path.basename(path))[0]
    view = os.path.join(folder, name + ".view.json")
    view = view if os.path.exists(view) else default_view
    if view is None:
        print(f"{name}: skipped (no {name}.view.json and no VIEW given)")
        continue
    start = time.time()
    tf = ddg.reconstruct(path, source=source, view=view)
    seconds = time.time() - start
    ddg.export(tf, os.path.join(out, name + ".json"))
    ours = ddg.render(source, tf, view).astype(float)
    target = read_png(path).astype(float)
    psnr = 10 * np.log10(255.0**2 / max(1e-12, np.mean((ours - target) ** 2)))
    print(
        f"{name}: {len(tf['RGBPoints']) // 4} colour points, {seconds:.1f} s, render vs. image {psnr:.1f} dB"
    )
