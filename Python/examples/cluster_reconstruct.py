"""Reconstruct a transfer function from a screenshot on a volume served by ParaView's MPI engine.

    pvpython Python/examples/cluster_reconstruct.py HOST:PORT VOLUME SCREENSHOT VIEW OUT_DIR

The server runs `mpiexec -np N pvserver --server-port=PORT` (see Documentation/Cluster.md), with
the plugin loaded at its start (its folder in PV_PLUGIN_PATH) or by `ddg` (from
DDG_SERVER_PLUGIN, the plugin's path on the server's nodes). VOLUME is a path on the
server's nodes: every rank reads only its own piece of it. SCREENSHOT and VIEW (the view JSON it
was taken at) are read here, on the client, and sent to the server.

The reconstruction and the render of its result are distributed over the ranks (each renders its
own piece; the pieces are composited sort-last). Writes OUT_DIR/tf.json (a ParaView preset) and
OUT_DIR/render.png, and prints the ranks, the times and the render's PSNR against the screenshot.
"""
import os
import sys
import time

import numpy as np

import ddg
from paraview import servermanager
import paraview.simple as simple
from vtkmodules.util import numpy_support
from vtkmodules.vtkIOImage import vtkPNGReader

address, volume, screenshot, view, out = sys.argv[1:6]
host, _, port = address.rpartition(":")
os.makedirs(out, exist_ok=True)

simple.Connect(host or "localhost", int(port))
ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
source = simple.XMLImageDataReader(FileName=[volume])

start = time.time()
tf = ddg.reconstruct(screenshot, source=source, view=view, iterations=100)
reconstruct_seconds = time.time() - start
ddg.export(tf, os.path.join(out, "tf.json"))

start = time.time()
ours = ddg.render(source, tf, view)
render_seconds = time.time() - start
ddg.save_image(ours, os.path.join(out, "render.png"))

reader = vtkPNGReader()
reader.SetFileName(screenshot)
reader.Update()
image = reader.GetOutput()
w, h, _ = image.GetDimensions()
target = numpy_support.vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)[
    ::-1, :, :3
]
mse = np.mean((ours.astype(float) - target.astype(float)) ** 2)
print(
    f"{ranks} rank(s): reconstruction {reconstruct_seconds:.1f} s, render {render_seconds:.1f} s, "
    f"render vs. screenshot {10 * np.log10(255.0**2 / max(mse, 1e-12)):.1f} dB; wrote "
    f"{os.path.join(out, 'tf.json')}"
)
simple.Disconnect()
