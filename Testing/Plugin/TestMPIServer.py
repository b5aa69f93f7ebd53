"""The filters on ParaView's MPI engine: `mpiexec -np 2 pvserver` on a free loopback port.

The filters need the whole volume: piece 0 (rank 0) asks for the whole extent and computes, the
other rank asks for nothing and outputs empty data (DDGFilterSupport.h). Compared: DDG Volume
Render's image, DDG Query's designs and preset (identical to a builtin session's), DDG
Reconstruct Transfer Function's table (its multithreaded reductions may differ in the last bits:
max difference 0.02), then the query's preset applied to the distributed volume and rendered.
The server is stopped (its whole process group) whatever happens; a crash fails the test.

Usage: pvpython TestMPIServer.py PLUGIN DATA
"""
import json
import os
import signal
import socket
import subprocess
import sys
import time

from paraview import servermanager
import paraview.simple as simple

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ddgtest import apply_and_render  # noqa: E402

plugin, data = sys.argv[1:3]
tooth_file = os.path.join(data, "Volumes", "tooth.vti")
shot = os.path.join(data, "Screenshots", "tooth_dentin_enamel_oblique.png")
view_file = os.path.join(data, "Views", "tooth_oblique.json")
white = json.load(open(view_file))
white["background"] = [1.0, 1.0, 1.0]


def run_filters(remote):
    simple.LoadPlugin(plugin, remote=remote)
    if remote:
        simple.LoadPlugin(plugin, remote=False)
    tooth = simple.XMLImageDataReader(FileName=[tooth_file])
    render = simple.DDGVolumeRender(Input=tooth, TransferFunctionFile=os.path.join(data, "TransferFunctions", "tooth_dentin_enamel.json"),
                                    ViewFile=view_file)
    render.UpdatePipeline()
    image = servermanager.Fetch(render)
    rgb = image.GetPointData().GetArray("Image")
    pixels = [rgb.GetValue(i) for i in range(0, rgb.GetNumberOfValues(), 97)]
    query = simple.DDGQuery(Input=tooth, ModelDirectory=os.path.join(data, "Models", "tooth"), ImageFile=shot,
                            ViewFile=view_file)
    query.UpdatePipeline()
    table = servermanager.Fetch(query, idx=1)
    rows = [table.GetValue(i, 0).ToInt() for i in range(table.GetNumberOfRows())]
    preset = table.GetFieldData().GetAbstractArray("Preset").GetValue(0)
    rec = simple.DDGReconstructTransferFunction(Input=tooth, TargetImageFile=shot, ViewJSON=json.dumps(white),
                                                Iterations=50)
    rec.UpdatePipeline()
    t = servermanager.Fetch(rec)
    opacity = [t.GetColumnByName("Opacity").GetValue(i) for i in range(t.GetNumberOfRows())]
    return tooth, {"dims": image.GetDimensions(), "pixels": pixels, "rows": rows, "preset": preset,
                   "opacity": opacity}


_, builtin = run_filters(False)
print(f"builtin: image {builtin['dims'][:2]}, query rows {builtin['rows']}, reconstruct {len(builtin['opacity'])} bins")
simple.Disconnect()

with socket.socket() as s:
    s.bind(("localhost", 0))
    port = s.getsockname()[1]
# Open MPI refuses root without these (CI may run as root) and 2 ranks on fewer slots without
# --oversubscribe
# --oversubscribe; pvpython initialised MPI as a singleton: its OMPI_/PMIX_ variables would make
# mpiexec think it runs inside a job, so they are left out
env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "OPAL_"))}
env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
server = subprocess.Popen(["mpiexec", "--oversubscribe", "-np", "2", "pvserver", f"--server-port={port}"],
                          stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True, env=env, start_new_session=True)
try:
    deadline = time.time() + 90
    started, seen = False, []
    for line in server.stdout:
        seen.append(line)
        if "Accepting connection" in line:
            started = True
            break
        if time.time() > deadline:
            break
    if not started:
        raise RuntimeError("mpiexec pvserver did not start:\n" + "".join(seen))
    simple.Connect("localhost", port)
    partitions = servermanager.ActiveConnection.GetNumberOfDataPartitions()
    assert partitions == 2, f"the server runs {partitions} processes, expected 2"
    tooth, mpi = run_filters(True)
    assert mpi["dims"] == builtin["dims"] and mpi["pixels"] == builtin["pixels"], "DDG Volume Render differs"
    assert mpi["rows"] == builtin["rows"] and mpi["preset"] == builtin["preset"], "DDG Query differs"
    assert len(mpi["opacity"]) == len(builtin["opacity"]), "DDG Reconstruct: other bins"
    diff = max(abs(a - b) for a, b in zip(mpi["opacity"], builtin["opacity"]))
    assert diff < 0.02, f"DDG Reconstruct differs by {diff}"
    print(f"2 ranks: render identical, query identical, reconstruct max opacity difference {diff:.2e}")
    # the query's preset applied to the distributed volume, rendered by the two ranks
    out = os.path.join(os.environ.get("TMPDIR", "/tmp"), f"ddg_mpi_apply_{os.getpid()}.png")
    size = apply_and_render(tooth, json.loads(mpi["preset"])[0], view_file, out)
    assert size > 5000, size
    print(f"applied and rendered on 2 ranks ({size} bytes PNG)")
    simple.Disconnect()
    try:
        server.wait(timeout=20)
    except subprocess.TimeoutExpired:
        pass
finally:
    if server.poll() is None:
        os.killpg(server.pid, signal.SIGTERM)
        try:
            server.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.killpg(server.pid, signal.SIGKILL)
            server.wait()
    rest = server.stdout.read()
    if "SIGSEGV" in rest or "SIGABRT" in rest or "Segmentation" in rest:
        print(rest)
        raise SystemExit("pvserver crashed")
    print("mpiexec exit status", server.returncode)
