"""ParaView renders of a volume with a preset and a view JSON, shared by the parity and
round-trip tests (run with pvpython under a display).

As a program it renders every job of a JSON list in a process of its own, so that Mesa's settings
can be its own: `pvpython pvrender.py JOBS_FILE` (paraview_renders_in_process_of_their_own)."""
import argparse
import json
import os
import shutil
import subprocess

from paraview.simple import (
    ColorBy,
    CreateView,
    Delete,
    GetColorTransferFunction,
    GetOpacityTransferFunction,
    Render,
    SaveScreenshot,
    Show,
    XMLImageDataReader,
)


# The view JSON's "lighting" the parity and round-trip tests use (--lighting NAME)
LIGHTINGS = {
    "off": None,
    "shade": {"shade": True},
    "shade-specular": {"shade": True, "specular": 0.5, "specular_power": 30},
}


def paraview_render(volume_path, preset, view_json, out_png, boxes_2d=None):
    """Renders with a 1D ``preset`` or, when ``boxes_2d`` is given (the TransferFunction2D
    properties of `ddg export --format paraview-2d`), with ParaView's 2D TF (UseTransfer2D)."""
    reader = XMLImageDataReader(FileName=[volume_path])
    view = CreateView("RenderView")
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = view_json.get("background", [0.329, 0.349, 0.427])
    size = view_json.get("size", [512, 512])
    view.ViewSize = size
    display = Show(reader, view)
    array = reader.PointData.keys()[0]
    ColorBy(display, ("POINTS", array))
    display.SetRepresentationType("Volume")
    # the view JSON's "lighting" (ParaView's defaults for the keys it leaves out)
    lighting = view_json.get("lighting") or {}
    display.Shade = int(bool(lighting.get("shade", False)))
    display.Ambient = lighting.get("ambient", 0.0)
    display.Diffuse = lighting.get("diffuse", 1.0)
    display.Specular = lighting.get("specular", 0.0)
    display.SpecularPower = lighting.get("specular_power", 100.0)
    lut = GetColorTransferFunction(array)
    pwf = GetOpacityTransferFunction(array)
    lut.AutomaticRescaleRangeMode = "Never"
    if boxes_2d:
        display.UseTransfer2D = 1
        display.UseGradientForTransfer2D = 1
        tf2 = display.TransferFunction2D
        tf2.Range = boxes_2d["Range"]
        tf2.OutputDimensions = boxes_2d["OutputDimensions"]
        tf2.Boxes = boxes_2d["Boxes"]
    else:
        lut.ColorSpace = preset.get("ColorSpace", "RGB")
        lut.HSVWrap = int(preset.get("HSVWrap", 0))
        lut.RGBPoints = preset["RGBPoints"]
        pwf.Points = preset["Points"]
    if view_json.get("opacity_unit_distance"):
        display.ScalarOpacityUnitDistance = view_json["opacity_unit_distance"]
    Render(view)  # the first render resets the camera: set ours afterwards
    cam = view_json["camera"]
    view.CameraPosition = cam["position"]
    view.CameraFocalPoint = cam["focal_point"]
    view.CameraViewUp = cam["view_up"]
    view.CameraViewAngle = cam.get("view_angle", 30.0)
    view.CameraParallelProjection = int(cam.get("parallel_projection", False))
    view.CameraParallelScale = cam.get("parallel_scale", 1.0)
    Render(view)
    SaveScreenshot(out_png, view, ImageResolution=size, TransparentBackground=0)
    Delete(display)
    Delete(view)
    Delete(reader)


# Mesa's llvmpipe filters 8-bit textures on a fast path of its own ("AoS" sampling): each filtered
# value is itself 8-bit, so a gradient from two of them moves in steps of 1/255 of the range.
# GALLIVM_PERF=no_aos_sampling makes it filter in float, as for every other texture type.
EXACT_SAMPLING = {"GALLIVM_PERF": "no_aos_sampling"}


def paraview_renders_in_process_of_their_own(jobs, env):
    """paraview_render of every job in one pvpython of its own, with ``env`` added to its
    environment (Mesa reads its settings once per process, so they cannot be changed in this
    one). A job is a dict: "volume" (path), "view" (view JSON), "out" (PNG) and "preset" (1D) or
    "boxes" (2D, `ddg export --format paraview-2d`). One process for all of them: a pvpython's
    start and ParaView's set-up cost about as much as a render."""
    if not jobs:
        return
    folder = os.path.dirname(os.path.abspath(jobs[0]["out"]))
    stem = os.path.splitext(os.path.basename(jobs[0]["out"]))[0]
    jobs_path = os.path.join(folder, stem + "_pvrender_jobs.json")
    with open(jobs_path, "w") as f:
        json.dump(jobs, f)
    pvpython = shutil.which("pvpython") or "/usr/bin/pvpython"
    subprocess.run(
        [pvpython, os.path.abspath(__file__), jobs_path],
        check=True,
        env={**os.environ, **env},
    )


def _render_job(job):
    paraview_render(
        job["volume"], job.get("preset"), job["view"], job["out"], boxes_2d=job.get("boxes")
    )


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument(
        "jobs", help="a JSON list of jobs (paraview_renders_in_process_of_their_own)"
    )
    with open(parser.parse_args().jobs) as f:
        for job in json.load(f):
            _render_job(job)
