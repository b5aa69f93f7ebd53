"""DDG Build Design Space in the background (the panel's way), in a builtin session or through a
pvserver (``--server``): StartBuild runs the build on a server thread while the client polls the
Build* information properties.

Compared: a tiny build (small.vti, 16 exemplars of 16 px, 10 iterations, 20 outline designs)
ends "done" with its stages seen in order, the fraction never decreasing, held-out figures and a
bundle on disk; a long build cancelled during training ends "cancelled" and leaves no folder;
bad input (a constant volume, a folder holding a bundle) ends "failed" with the message, nothing
written; PlanBuild for a 2-minute budget gives a plan within it; deleting the proxy during a
build stops it (the folder is removed). The cancel latency is printed, never asserted.

Usage: pvpython TestBuildBackground.py PLUGIN TESTDATA OUTDIR [--server]
"""
import json
import os
import shutil
import sys
import time

import paraview.simple as simple

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ddgtest import start_pvserver, stop_pvserver, wait_for_build as wait  # noqa: E402

plugin, testdata, outdir = sys.argv[1:4]
remote = "--server" in sys.argv[4:]
outdir = os.path.abspath(os.path.join(outdir, "background_" + ("server" if remote else "builtin")))
shutil.rmtree(outdir, ignore_errors=True)
os.makedirs(outdir)
server = start_pvserver() if remote else None
simple.LoadPlugin(plugin, remote=remote)


def info(proxy, name):
    return proxy.GetPropertyValue(name)


def new_build(volume, directory, **props):
    reader = simple.XMLImageDataReader(FileName=[os.path.join(testdata, volume)])
    build = simple.DDGBuildDesignSpace(Input=reader)
    build.OutputDirectory = directory
    build.Count = 16
    build.Size = 16
    build.Iterations = 10
    build.OutlineCount = 20
    for key, value in props.items():
        setattr(build, key, value)
    build.UpdateVTKObjects()
    return build


try:
    # --- a build that finishes -----------------------------------------------------------------
    bundle = os.path.join(outdir, "bundle")
    build = new_build("small.vti", bundle)
    build.UpdatePropertyInformation()
    assert info(build, "BuildState") == "idle", info(build, "BuildState")  # not started by setup
    build.SMProxy.InvokeCommand("StartBuild")
    stages, fractions = wait(build)
    assert info(build, "BuildState") == "done", (
        info(build, "BuildState"),
        info(build, "BuildError"),
    )
    order = ["exemplars", "training", "evaluation", "outline"]
    assert [s for s in order if s in stages] == stages and "training" in stages, stages
    assert all(b >= a for a, b in zip(fractions, fractions[1:])), fractions
    figures = info(build, "BuildFigures")
    assert figures[0] > 5 and 0 < figures[1] <= 1 and figures[5] == 10, figures
    assert os.path.exists(os.path.join(bundle, "bundle.json"))
    assert os.path.exists(os.path.join(bundle, "outline.bin"))
    print(
        f"built in {info(build, 'BuildSecondsElapsed'):.1f} s, stages {stages}, figures {figures}"
    )

    # --- the same folder again: refused, nothing changed ---------------------------------------
    before = sorted(os.listdir(bundle))
    build.SMProxy.InvokeCommand("StartBuild")
    wait(build)
    assert info(build, "BuildState") == "failed", info(build, "BuildState")
    assert "already holds a model bundle" in info(build, "BuildError"), info(build, "BuildError")
    assert sorted(os.listdir(bundle)) == before
    print("existing bundle:", info(build, "BuildError"))

    # --- cancel during training ----------------------------------------------------------------
    cancelled = os.path.join(outdir, "cancelled")
    long_build = new_build("small.vti", cancelled, Iterations=0, Minutes=10)
    long_build.SMProxy.InvokeCommand("StartBuild")
    wait(long_build, until=lambda p: info(p, "BuildStage") == "training")
    t0 = time.time()
    long_build.SMProxy.InvokeCommand("CancelBuild")
    wait(long_build, polls=600)
    latency = time.time() - t0
    assert info(long_build, "BuildState") == "cancelled", info(long_build, "BuildState")
    assert not os.path.exists(cancelled), os.listdir(cancelled)
    print(f"cancelled during training: state after {latency:.2f} s (poll 0.1 s), no folder left")

    # --- bad input: a constant volume ----------------------------------------------------------
    constant = new_build("constant.vti", os.path.join(outdir, "constant"))
    constant.SMProxy.InvokeCommand("StartBuild")
    wait(constant)
    assert info(constant, "BuildState") == "failed"
    assert "one value" in info(constant, "BuildError"), info(constant, "BuildError")
    assert not os.path.exists(os.path.join(outdir, "constant"))
    print("constant volume:", info(constant, "BuildError"))

    # --- the plan of a 2-minute budget ---------------------------------------------------------
    planner = new_build("small.vti", bundle, BudgetMinutes=2)
    planner.SMProxy.InvokeCommand("PlanBuild")
    planner.UpdatePropertyInformation()
    plan = json.loads(info(planner, "BuildPlan"))
    assert plan["count"] >= 256 and plan["total_seconds"] <= 120, plan
    assert "already holds a model bundle" in plan["output_error"], plan
    print(f"plan for 2 min: {plan['describe']}")

    # --- deleting the proxy during a build stops it --------------------------------------------
    dropped = os.path.join(outdir, "dropped")
    dropping = new_build("small.vti", dropped, Iterations=0, Minutes=10)
    dropping.SMProxy.InvokeCommand("StartBuild")
    wait(dropping, until=lambda p: info(p, "BuildStage") == "training")
    t0 = time.time()
    simple.Delete(dropping)
    del dropping
    for _ in range(100):  # the server deletes it with the next message
        simple.GetSources()
        if not os.path.exists(dropped):
            break
        time.sleep(0.1)
    assert not os.path.exists(dropped), os.listdir(dropped)
    print(f"deleted during training: folder gone after {time.time() - t0:.2f} s")
    print("ok")
finally:
    if server:
        stop_pvserver(server)
