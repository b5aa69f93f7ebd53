"""The cluster walkthrough's example (Python/examples/cluster_reconstruct.py) against
`mpiexec -np 2 pvserver` started as Documentation/Cluster.md says: the plugin loaded by the server
at its start (its folder in PV_PLUGIN_PATH), and DDG_SERVER_PLUGIN pointing nowhere, so that the
example must use the server's own plugin. Expects the example's report (2 ranks, the render's
PSNR against the screenshot at least 35 dB), its files, and the server to exit by itself with
status 0 and no error when the client leaves.

Usage: pvpython TestClusterExample.py PVPYTHON PLUGIN_DIR DATA OUT_DIR (PVPYTHON: build/bin/pvpython,
which finds the `ddg` package)
"""
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mpiserver import Server  # noqa: E402

pvpython, plugin_dir, data, out = sys.argv[1:5]
root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
example = os.path.join(root, "Python", "examples", "cluster_reconstruct.py")
server = Server(2, environment={"PV_PLUGIN_PATH": os.path.abspath(plugin_dir)})
try:
    server.wait_ready()
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "OPAL_"))}
    env["DDG_SERVER_PLUGIN"] = "/nowhere/DesignGallery.so"  # the server has its own
    run = subprocess.run(
        [
            pvpython,
            example,
            f"localhost:{server.port}",
            os.path.join(data, "Volumes", "tooth.vti"),
            os.path.join(data, "Screenshots", "tooth_dentin_enamel_oblique.png"),
            os.path.join(data, "Screenshots", "tooth_dentin_enamel_oblique.json"),
            out,
        ],
        capture_output=True,
        text=True,
        env=env,
        timeout=240,
    )
    print(run.stdout)
    assert run.returncode == 0, "the example failed:\n" + run.stdout + run.stderr
    report = re.search(r"^2 rank\(s\): .*render vs\. screenshot ([0-9.]+) dB", run.stdout, re.M)
    assert report, "no report of 2 ranks:\n" + run.stdout
    assert float(report.group(1)) >= 35.0, report.group(0)
    for name in ("tf.json", "render.png"):
        assert os.path.getsize(os.path.join(out, name)) > 1000, name
    server.process.wait(timeout=30)
    log = server.output()
    assert (
        server.process.returncode == 0
    ), f"mpiexec exit status {server.process.returncode}:\n{log}"
    assert not [line for line in log.splitlines() if "ERR|" in line], "server errors:\n" + log
    print("the cluster example ran against 2 ranks; the server exited with status 0")
finally:
    server.stop()
