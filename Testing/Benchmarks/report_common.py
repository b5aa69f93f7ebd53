"""report_common.py: what the report's measurement (report_measure.py) and its rendering
(report_render.py) share: paths, the methods' names, the success bar, the log and report.json.
"""
import json
import os
import platform
import subprocess
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DATA = os.path.join(ROOT, "Data")
RESULTS = os.path.join(ROOT, "Documentation", "Results")  # the committed report and its records

SUCCESS_DB = 30.0  # a perturbed screenshot's TF succeeds within this PSNR of the reference
PRIMITIVES = 12  # Gaussian primitives of method (d)

# the screenshot -> TF methods as report.json and report.md name them, in the charts' order
NEAREST = "nearest design (a)"
NEURAL = "neural path (b)"
QUERY = "analyzer -> decoder (b')"
REFINE = "b' + reconstruction"
DIRECT = "reconstruction (c)"
PRIMITIVE_FIT = f"{PRIMITIVES} primitives (d)"
TWO_VIEW = "2-view reconstruction (e)"
MATCH = "match, no view (f)"  # `ddg reconstruct` without --view: background, overlays, camera, TF
QUERY_MATCH = "b' + match"  # the match started from the query's TF
METHODS = [NEAREST, NEURAL, QUERY, REFINE, DIRECT, PRIMITIVE_FIT, TWO_VIEW, MATCH, QUERY_MATCH]
# the ones run on perturbed screenshots; all but the match get the reference view's file
STABLE_METHODS = [QUERY, REFINE, DIRECT, PRIMITIVE_FIT, MATCH, QUERY_MATCH]
EXACT_VIEW_METHODS = [REFINE, DIRECT, PRIMITIVE_FIT]  # reconstructions at the view they are given

# --- the log and the minutes of each section ----------------------------------------------------

started = time.time()
_section_starts = []  # (name, seconds since start)


def log(text):
    print(f"[{time.time() - started:7.1f} s] {text}", flush=True)


def section(name):
    _section_starts.append((name, time.time() - started))
    log(f"section: {name}")


def section_minutes():
    """Minutes spent in each section, up to now."""
    ends = [t for _, t in _section_starts[1:]] + [time.time() - started]
    return {name: (end - t) / 60 for (name, t), end in zip(_section_starts, ends)}


def minutes():
    """Minutes since the start."""
    return (time.time() - started) / 60


def machine():
    """The processor, its cores and the load average (1 min) now: what the timings depend on."""
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return {"cpu": cpu, "cores": os.cpu_count(), "load_average": os.getloadavg()[0]}


def commit():
    """The source tree's commit (the report's scripts; the `ddg` program's unless --build points
    elsewhere), or None outside a git checkout."""
    r = subprocess.run(
        ["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True
    )
    return r.stdout.strip() or None


# --- report.json --------------------------------------------------------------------------------


def report_json(out):
    return os.path.join(out, "report.json")


def read_report(path):
    """The content of a report.json file."""
    with open(path) as f:
        return json.load(f)


def write_report(results, out):
    with open(report_json(out), "w") as f:
        json.dump(results, f, indent=1)
