"""Helpers shared by the plugin's pvpython tests."""
import json
import os
import time

from paraview import servermanager
import paraview.simple as simple
from vtkmodules.vtkCommonCore import VTK_STRING, vtkCommand
from vtkmodules.util.misc import calldata_type


class Errors:
    """Collects the error messages a filter reports (its client-side object: builtin sessions)."""

    def __init__(self, proxy):
        self.messages = []
        self.proxy = proxy

        @calldata_type(VTK_STRING)
        def on_error(obj, event, calldata):
            self.messages.append(calldata)

        proxy.GetClientSideObject().AddObserver(vtkCommand.ErrorEvent, on_error)

    def expect(self, label, expected, port=0, **props):
        """Sets `props`, updates: exactly one error containing `expected` and an empty output."""
        self.messages.clear()
        for key, value in props.items():
            setattr(self.proxy, key, value)
        self.proxy.UpdatePipeline()
        data = servermanager.Fetch(self.proxy, idx=port)
        assert (
            data.GetNumberOfElements(0) == 0 and data.GetNumberOfElements(6) == 0
        ), f"{label}: output {port} should be empty"
        assert len(self.messages) == 1, f"{label}: expected one error, got {self.messages}"
        assert expected in self.messages[0], f"{label}: '{expected}' not in '{self.messages[0]}'"
        print(f"{label}: {self.messages[0].strip().splitlines()[-1]}")


def apply_and_render(source, preset, view_file, out_png, size=(320, 320)):
    """Shows `source` as a volume with a ParaView preset (dict) at a view JSON's camera, saves a
    screenshot and returns its size in bytes (the file is removed)."""
    display = simple.Show(source)
    display.SetRepresentationType("Volume")
    array = source.PointData.keys()[0]
    simple.ColorBy(display, ("POINTS", array))
    lut = simple.GetColorTransferFunction(array)
    lut.AutomaticRescaleRangeMode = "Never"
    lut.RGBPoints = preset["RGBPoints"]
    simple.GetOpacityTransferFunction(array).Points = preset["Points"]
    camera = json.load(open(view_file))["camera"]
    view = simple.GetActiveView()
    view.CameraPosition, view.CameraFocalPoint = camera["position"], camera["focal_point"]
    view.CameraViewUp = camera["view_up"]
    simple.SaveScreenshot(out_png, view, ImageResolution=list(size))
    assert list(lut.RGBPoints) == list(preset["RGBPoints"]), "the LUT does not hold the preset"
    bytes_ = os.path.getsize(out_png)
    os.remove(out_png)
    simple.Hide(source)
    return bytes_


def start_pvserver(timeout=60):
    """Starts a pvserver on a free loopback port and connects this session to it; returns the
    server process (stop_pvserver ends it)."""
    import socket
    import subprocess
    import time

    with socket.socket() as s:
        s.bind(("localhost", 0))
        port = s.getsockname()[1]
    server = subprocess.Popen(
        ["pvserver", f"--server-port={port}"],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    deadline = time.time() + timeout
    for line in server.stdout:
        if "Accepting connection" in line or "Waiting for client" in line:
            break
        if time.time() > deadline:
            server.terminate()
            raise RuntimeError("pvserver did not start")
    simple.Connect("localhost", port)
    return server


def stop_pvserver(server):
    """Disconnects and stops a server of start_pvserver (pvserver 5.11 keeps running after
    Disconnect); fails when it crashed."""
    try:
        simple.Disconnect()
    finally:
        if server.poll() is None:
            server.terminate()
        rest, _ = server.communicate(timeout=30)
        if "SIGSEGV" in rest or "SIGABRT" in rest or "Segmentation" in rest:
            print(rest)
            raise SystemExit("pvserver crashed")
        print("pvserver exit status", server.returncode)


def wait_for_build(proxy, until=None, polls=6000):
    """Polls a DDG Build Design Space proxy every 0.1 s (at most `polls` times) until `until(proxy)`
    (default: its BuildState is no longer "running"); returns the stages and fractions seen."""
    if until is None:
        until = lambda p: p.GetPropertyValue("BuildState") != "running"  # noqa: E731
    stages, fractions = [], []
    for _ in range(polls):
        proxy.UpdatePropertyInformation()
        stage = proxy.GetPropertyValue("BuildStage")
        if stage and (not stages or stages[-1] != stage):
            stages.append(stage)
        fractions.append(proxy.GetPropertyValue("BuildProgress"))
        if until(proxy):
            return stages, fractions
        time.sleep(0.1)
    raise RuntimeError("the build did not end")
