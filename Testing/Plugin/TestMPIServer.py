"""The filters on ParaView's MPI engine: `mpiexec -np 2 pvserver` on a free loopback port.

The filters need the whole volume: piece 0 (rank 0) asks for the whole extent and computes, the
other rank asks for nothing and outputs empty data (DDGFilterSupport.h). What is compared with
what: the client fetches (servermanager.Fetch, which gathers the ranks' pieces) the outputs of DDG
Volume Render, DDG Query (shipped Tooth bundle and screenshot) and DDG Reconstruct Transfer
Function (20 iterations) from the 2-rank server, then computes the same in a builtin session:
- render and query: identical (every array of the images and of the designs table, every field
  data array, the Preset string);
- reconstruction: same columns, rows and field data names, values within RECONSTRUCT_TOL
  (1e-6): its gradient is summed over per-thread buffers filled in a dynamic order, so even two
  builtin runs differ in the last float bit (measured: 6e-8);
- rank 1 read nothing (the reader's points over both ranks are the volume's, once), and neither
  rank logged an error.
Then the query's preset is applied to the distributed volume and rendered by both ranks. The
server must exit by itself (status 0) when the client leaves; on any failure its ranks are killed
(they run in their own process groups). A crash in the server log fails the test.

Usage: pvpython TestMPIServer.py PLUGIN DATA
"""
import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time

from paraview import servermanager
import paraview.simple as simple
from vtkmodules.util.numpy_support import vtk_to_numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ddgtest import apply_and_render  # noqa: E402

RECONSTRUCT_TOL = 1e-6
CRASH_MARKERS = (
    "SIGSEGV",
    "SIGABRT",
    "Segmentation fault",
    "signal 11",
    "exited on signal",
    "core dumped",
)

plugin, data = sys.argv[1:3]
tooth_file = os.path.join(data, "Volumes", "tooth.vti")
shot = os.path.join(data, "Screenshots", "tooth_dentin_enamel_oblique.png")
view_file = os.path.join(data, "Views", "tooth_oblique.json")


# ---------------------------------------------------------------------------------------------
# the filters, and what the client receives from them


def arrays(fields):
    """{name: values} of a vtkFieldData / vtkDataSetAttributes (numpy for numeric arrays)."""
    out = {}
    for i in range(fields.GetNumberOfArrays()):
        a = fields.GetAbstractArray(i)
        if a.IsA("vtkDataArray"):
            out[a.GetName()] = vtk_to_numpy(a).copy()
        else:
            out[a.GetName()] = [
                a.GetVariantValue(k).ToString() for k in range(a.GetNumberOfValues())
            ]
    return out


def snapshot(obj):
    """What a fetched image or table holds, as plain Python / numpy values."""
    snap = {"class": obj.GetClassName(), "field": arrays(obj.GetFieldData())}
    if obj.IsA("vtkImageData"):
        snap.update(
            dims=obj.GetDimensions(),
            origin=obj.GetOrigin(),
            spacing=obj.GetSpacing(),
            points=arrays(obj.GetPointData()),
        )
    else:
        snap.update(rows=obj.GetNumberOfRows(), columns=arrays(obj.GetRowData()))
    return snap


def run_filters(remote):
    simple.LoadPlugin(plugin, remote=remote)
    out, seconds = {}, {}
    tooth = simple.XMLImageDataReader(FileName=[tooth_file])
    render = simple.DDGVolumeRender(
        Input=tooth,
        ViewFile=view_file,
        TransferFunctionFile=os.path.join(data, "TransferFunctions", "tooth_dentin_enamel.json"),
    )
    query = simple.DDGQuery(
        Input=tooth,
        ModelDirectory=os.path.join(data, "Models", "tooth"),
        ImageFile=shot,
        ViewFile=view_file,
    )
    rec = simple.DDGReconstructTransferFunction(
        Input=tooth, TargetImageFile=shot, ViewFile=view_file, Iterations=20
    )
    for name, proxy, ports in (
        ("render", render, [0]),
        ("query", query, [0, 1]),
        ("reconstruct", rec, [0]),
    ):
        start = time.time()
        proxy.UpdatePipeline()
        seconds[name] = time.time() - start
        for port in ports:
            out[f"{name}:{port}"] = snapshot(servermanager.Fetch(proxy, idx=port))
    # summed over the ranks: the volume once means rank 1 read nothing (before Show, whose
    # representation asks for pieces of the volume)
    whole = tooth.GetDataInformation().DataInformation.GetExtent()
    out["reader points"] = (
        tooth.GetDataInformation().GetNumberOfPoints(),
        (whole[1] - whole[0] + 1) * (whole[3] - whole[2] + 1) * (whole[5] - whole[4] + 1),
    )
    print(
        ("2 ranks" if remote else "builtin")
        + ": "
        + ", ".join(f"{k} {v:.2f} s" for k, v in seconds.items())
    )
    return tooth, out


def same(a, b):
    """Exact equality of snapshots (numpy arrays compared element by element)."""
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if hasattr(a, "dtype"):
        return hasattr(b, "dtype") and a.dtype == b.dtype and a.shape == b.shape and (a == b).all()
    return a == b


def compare(mpi, builtin):
    for key in ("render:0", "query:0", "query:1"):
        assert mpi[key]["class"] == builtin[key]["class"], (
            key,
            mpi[key]["class"],
            builtin[key]["class"],
        )
        assert same(mpi[key], builtin[key]), f"{key} differs from the builtin session's"
    assert (
        mpi["query:1"]["rows"] > 0 and "Preset" in mpi["query:1"]["field"]
    ), "query: no designs or preset"
    assert "Image" in mpi["render:0"]["points"], "render: no image"
    m, b = mpi["reconstruct:0"], builtin["reconstruct:0"]
    assert m["class"] == b["class"] == "vtkTable" and m["rows"] == b["rows"] > 0, (
        m["class"],
        m["rows"],
        b["rows"],
    )
    assert m["columns"].keys() == b["columns"].keys() and m["field"].keys() == b["field"].keys()
    diff = max(
        float(abs(m["columns"][c].astype(float) - b["columns"][c].astype(float)).max())
        for c in m["columns"]
    )
    assert diff <= RECONSTRUCT_TOL, f"reconstruct differs from the builtin session's by {diff}"
    assert m["field"]["Iterations"] == b["field"]["Iterations"], (
        m["field"]["Iterations"],
        b["field"]["Iterations"],
    )
    return diff


# ---------------------------------------------------------------------------------------------
# the server


def mpiexec_command(port):
    """mpiexec for 2 ranks. Open MPI: --oversubscribe (fewer cores than ranks is fine),
    --bind-to none (rank 0's threads may use every core; Open MPI binds each rank to one core by
    default), idle ranks yield the CPU instead of spinning; root is allowed by the environment."""
    version = subprocess.run(["mpiexec", "--version"], capture_output=True, text=True)
    if (
        "Open MPI" in version.stdout + version.stderr
        or "OpenRTE" in version.stdout + version.stderr
    ):
        return [
            "mpiexec",
            "--oversubscribe",
            "--bind-to",
            "none",
            "--mca",
            "mpi_yield_when_idle",
            "1",
            "-np",
            "2",
            "pvserver",
            f"--server-port={port}",
        ]
    return ["mpiexec", "-n", "2", "pvserver", f"--server-port={port}"]


class Server:
    """`mpiexec -np 2 pvserver` with its output in a log file (a pipe nobody reads could fill
    and block the server)."""

    def __init__(self):
        with socket.socket() as s:
            s.bind(("localhost", 0))
            self.port = s.getsockname()[1]
        # pvpython initialised MPI as a singleton: its OMPI_/PMIX_ variables would make mpiexec
        # think it runs inside a job. Open MPI refuses root (CI may run as root) without the
        # last two.
        env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "OPAL_"))}
        env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
        self.log = tempfile.NamedTemporaryFile("w+", prefix="ddg_mpi_server_", suffix=".log")
        self.process = subprocess.Popen(
            mpiexec_command(self.port),
            stdout=self.log,
            stderr=subprocess.STDOUT,
            env=env,
            start_new_session=True,
        )
        self.ranks = []

    def output(self):
        with open(self.log.name) as f:
            return f.read()

    def wait_ready(self, timeout=90):
        deadline = time.time() + timeout
        while "Accepting connection" not in self.output():
            if self.process.poll() is not None or time.time() > deadline:
                raise RuntimeError("mpiexec pvserver did not start:\n" + self.output())
            time.sleep(0.2)
        # Open MPI starts each rank in its own process group: remember them to stop them
        for task in os.listdir(f"/proc/{self.process.pid}/task"):
            with open(f"/proc/{self.process.pid}/task/{task}/children") as f:
                self.ranks += [int(p) for p in f.read().split()]

    def stop(self):
        """Stops mpiexec (SIGTERM: it forwards the signal to the ranks) and then kills whatever
        is left of it and of its ranks."""
        if self.process.poll() is None:
            os.killpg(self.process.pid, signal.SIGTERM)
            try:
                self.process.wait(timeout=15)
            except subprocess.TimeoutExpired:
                os.killpg(self.process.pid, signal.SIGKILL)
                self.process.wait()
        for pid in self.ranks:
            try:
                if b"pvserver" in open(f"/proc/{pid}/cmdline", "rb").read():
                    os.killpg(pid, signal.SIGKILL)
            except (OSError, ProcessLookupError):
                pass  # already gone


def crashed(log):
    return any(marker in log for marker in CRASH_MARKERS)


# ---------------------------------------------------------------------------------------------
# the test

signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))  # ctest's timeout: still stop the server
server = Server()
try:
    server.wait_ready()
    simple.Connect("localhost", server.port)
    partitions = servermanager.ActiveConnection.GetNumberOfDataPartitions()
    assert partitions == 2, f"the server runs {partitions} processes, expected 2"
    tooth, mpi = run_filters(remote=True)
    points, volume = mpi["reader points"]
    assert (
        points == volume
    ), f"the ranks read {points} points of a {volume}-point volume (rank 1 should read none)"
    preset = json.loads(mpi["query:1"]["field"]["Preset"][0])[0]
    out = os.path.join(tempfile.gettempdir(), f"ddg_mpi_apply_{os.getpid()}.png")
    size = apply_and_render(tooth, preset, view_file, out)
    assert size > 5000, size
    print(
        f"2 ranks: the query's preset applied to the distributed volume and rendered ({size} bytes PNG)"
    )
    del tooth
    # simple.Disconnect() alone keeps the session (servermanager's proxy namespaces refer to it)
    # and so the server; a builtin session replaces it, and the server then exits by itself
    simple.Disconnect()
    simple.Connect()
    try:
        server.process.wait(timeout=30)
    except subprocess.TimeoutExpired:
        raise AssertionError("the server did not exit after the client left")
    log = server.output()
    assert not crashed(log), "pvserver crashed:\n" + log
    assert server.process.returncode == 0, (
        f"mpiexec exit status {server.process.returncode}:\n" + log
    )
    assert log.count("Exiting...") == 2, "both ranks should exit:\n" + log
    assert "ERR|" not in log and "Error" not in log, "the server logged errors:\n" + log
    print("2 ranks: mpiexec exited with status 0 after the client left, no error logged")
finally:
    server.stop()
    log = server.output()
    if crashed(log):
        print(log)
        raise SystemExit("pvserver crashed")

_, builtin = run_filters(remote=False)
diff = compare(mpi, builtin)
print(
    f"identical to the builtin session: render {mpi['render:0']['dims'][:2]}, query preview and "
    f"{mpi['query:1']['rows']} designs with preset; reconstruct ({mpi['reconstruct:0']['rows']} bins) "
    f"max difference {diff:.1e} (tolerance {RECONSTRUCT_TOL:g})"
)
