"""DDG Volume Render through pvserver: the plugin loads on the server (remote=True), the filter
runs there and the client fetches the image.

Usage: pvpython TestClientServer.py PLUGIN DATA
"""
import os
import socket
import subprocess
import sys
import time

from paraview import servermanager
import paraview.simple as simple

plugin, data = sys.argv[1:3]
with socket.socket() as s:
    s.bind(("localhost", 0))
    port = s.getsockname()[1]
server = subprocess.Popen(
    ["pvserver", f"--server-port={port}"],
    stdout=subprocess.PIPE,
    stderr=subprocess.STDOUT,
    text=True,
)
try:
    deadline = time.time() + 60
    for line in server.stdout:
        if "Accepting connection" in line or "Waiting for client" in line:
            break
        if time.time() > deadline:
            raise RuntimeError("pvserver did not start")
    simple.Connect("localhost", port)
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
    print(f"client/server ok: {dims[0]}x{dims[1]}, max alpha {alpha:.3f}")
    simple.Disconnect()
finally:
    if server.poll() is None:
        server.terminate()
        server.wait(timeout=30)
