"""mpiserver.py: ParaView's MPI engine for the tests and benchmarks — `mpiexec -np N pvserver` on
a free loopback port, its ranks' processes and memory, and the pieces ParaView splits a volume
into. Used with pvpython (Testing/Plugin/TestMPIServer.py, Testing/Benchmarks/mpi_scaling.py)."""
import os
import signal
import socket
import subprocess
import tempfile
import time


def split_boxes(extent, pieces):
    """The boxes vtkExtentTranslator splits `extent` into, piece by piece (bisection of the axis
    with the most cells, z first on ties; neighbours share a point plane)."""

    def split(box, n):
        if n == 1:
            return [box]
        axis = max((2, 1, 0), key=lambda a: box[2 * a + 1] - box[2 * a])
        mid = box[2 * axis] + (box[2 * axis + 1] - box[2 * axis]) * (n // 2) // n
        low, high = list(box), list(box)
        low[2 * axis + 1] = high[2 * axis] = mid
        return split(low, n // 2) + split(high, n - n // 2)

    return split(list(extent), pieces)


def piece_points(extent, box, ghosts):
    """Points of `box` widened by `ghosts` inside `extent`."""
    size = 1
    for a in range(3):
        lo = max(extent[2 * a], box[2 * a] - ghosts)
        hi = min(extent[2 * a + 1], box[2 * a + 1] + ghosts)
        size *= hi - lo + 1
    return size


def split_points(extent, pieces, ghosts):
    """Points of the pieces `extent` is split into (split_boxes), each widened by `ghosts`,
    summed."""
    return sum(piece_points(extent, box, ghosts) for box in split_boxes(extent, pieces))


def mpiexec_command(port, ranks, extra=()):
    """mpiexec for RANKS ranks. Open MPI: --oversubscribe (fewer cores than ranks is fine),
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
            str(ranks),
            "pvserver",
            f"--server-port={port}",
        ] + list(extra)
    return ["mpiexec", "-n", str(ranks), "pvserver", f"--server-port={port}"] + list(extra)


class Server:
    """`mpiexec -np RANKS pvserver` on a free loopback port, with its output in a log file (a
    pipe nobody reads could fill and block the server)."""

    def __init__(self, ranks, extra=(), environment=None):
        with socket.socket() as s:
            s.bind(("localhost", 0))
            self.port = s.getsockname()[1]
        # pvpython initialised MPI as a singleton: its OMPI_/PMIX_ variables would make mpiexec
        # think it runs inside a job. Open MPI refuses root (CI may run as root) without the
        # last two.
        env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "OPAL_"))}
        env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
        env.update(environment or {})
        self.log = tempfile.NamedTemporaryFile("w+", prefix="ddg_mpi_server_", suffix=".log")
        self.process = subprocess.Popen(
            mpiexec_command(self.port, ranks, extra),
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

    def rank_pids(self):
        """{rank: pid} of the pvserver ranks (Open MPI and MPICH give each its rank in the
        environment)."""
        out = {}
        for pid in self.ranks:
            try:
                env = open(f"/proc/{pid}/environ", "rb").read().split(b"\0")
            except OSError:
                continue
            for item in env:
                key, _, value = item.partition(b"=")
                if key in (b"OMPI_COMM_WORLD_RANK", b"PMI_RANK", b"PMIX_RANK"):
                    out[int(value)] = pid
                    break
        return out


def _status_mb(pid, key):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1]) / 1024.0
    raise RuntimeError(f"no {key} for process {pid}")


def peak_rss_mb(pid):
    """The process's peak resident set size (VmHWM), MB."""
    return _status_mb(pid, "VmHWM")


def current_rss_mb(pid):
    """The process's resident set size now (VmRSS), MB."""
    return _status_mb(pid, "VmRSS")


def reset_peak_rss(pid):
    """Restarts the process's peak RSS from its current RSS (Linux: clear_refs 5)."""
    with open(f"/proc/{pid}/clear_refs", "w") as f:
        f.write("5")
