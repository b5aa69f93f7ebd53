"""Builds the suite of realistic screenshots (issue 17, item 5) with ParaView itself.

For every case of cases.json (volume, TF, size, format, seed; optional: "lighting", a view
JSON's lighting object, the Volume representation then lit with it; "projection": "parallel",
ParaView's Camera Parallel Projection) it writes, under OUT/<case>/:
  screenshot.png|jpg  ParaView's File > Save Screenshot with the default GUI look: the default
                      palette's background (0.32, 0.34, 0.43), the orientation axes in the corner,
                      the Volume representation unlit (unless the case is lit), the true TF;
                      JPEG at quality 85
  true_tf.json        the case's preset (a copy of Testing/Suite/TransferFunctions/<tf>.json)
  true_view.json      the true camera as the project's view JSON (size, palette background)
  case.json           volume, image, true TF, true view, size, format, seed, drawn camera
and OUT/suite.json, the list of case files.

A case with "figure": {"background": "black" | "gradient" | "palette", ...} (make_figures.py's
cases) has its render view's background so: black, ParaView's gradient (the palette's
Background at the bottom, Background2 (0, 0, 0.16) at the top, as the GUI's "Gradient" shows
it) or the palette's colour (the default); its orientation axes stay.

A case with "window": [width, height] is a screenshot of ParaView's whole window instead (the
toolbars, the pipeline browser and the properties around the render view, as a user's grab of the
window has them): the GUI (`paraview --dr`, default settings) is started under an X server of its
own with that screen size (Xvfb, its frame buffer in a file), shows the scene in its render view
through a script, and the window is cut from the frame buffer (everything but the black root
window). The render view's own screenshot is kept beside it (view.png) and true_view.json is the
render view's camera and size. "size" is then not given: the window's is recorded.

Cameras: ParaView's reset camera on the volume (looking down -z, +y up), then, drawn from the
case's seed with Python's random.Random: azimuth in [-180, 180), elevation in [-45, 45], roll in
[-20, 20] degrees, pan by up to 5 % of the view height along the view's right and up, and a zoom
(dolly towards the focal point, as ParaView's mouse wheel) in [0.8, 1.4].

Run (a minute or two):
    scripts/with-xvfb.sh /usr/bin/pvpython Testing/Suite/make_suite.py --out build/suite
"""
import argparse
import json
import os
import random
import shutil
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from suite_paraview import VolumeScene, read_image, use_default_palette  # noqa: E402

AZIMUTH = (-180.0, 180.0)
ELEVATION = (-45.0, 45.0)
ROLL = (-20.0, 20.0)
PAN = 0.05  # of the view height, each of right and up
ZOOM = (0.8, 1.4)
JPEG_QUALITY = 85


def draw_camera(seed):
    """The case's camera moves, from its seed."""
    rng = random.Random(seed)
    return {
        "azimuth": rng.uniform(*AZIMUTH),
        "elevation": rng.uniform(*ELEVATION),
        "roll": rng.uniform(*ROLL),
        "pan": [rng.uniform(-PAN, PAN), rng.uniform(-PAN, PAN)],
        "zoom": rng.uniform(*ZOOM),
    }


def place_camera(scene, moves, parallel=False):
    """The scene's camera moved from ParaView's reset camera by draw_camera's moves; with
    ``parallel``, in parallel projection (ParaView's Camera Parallel Projection, its scale the
    reset camera's), where the zoom is the mouse wheel's: the parallel scale divided by it."""
    cam = scene.orbit(moves["azimuth"], moves["elevation"])
    cam.Roll(moves["roll"])
    if parallel:
        scene.view.CameraParallelProjection = 1
    scene.pan(*moves["pan"])
    if parallel:
        cam.Zoom(moves["zoom"])
    else:
        cam.Dolly(moves["zoom"])


def load_cases(path, names=None):
    with open(path) as f:
        cases = json.load(f)["cases"]
    if names:
        cases = [c for c in cases if c["name"] in names]
        if len(cases) != len(set(names)):
            raise SystemExit("unknown case in %s" % ", ".join(names))
    return cases


GUI_SCRIPT = """
import json, os, sys
sys.path.insert(0, {here!r})
from paraview import simple
from suite_paraview import VolumeScene, use_default_palette
from make_suite import place_camera
use_default_palette()
scene = VolumeScene({volume!r}, None, gui_look=True, lighting={lighting!r},
                    view=simple.GetActiveViewOrCreate("RenderView"))
scene.apply({preset!r})
place_camera(scene, {moves!r}, {parallel!r})
simple.Render(scene.view)
scene.screenshot({view_png!r})
simple.Render(scene.view)
with open({done!r} + ".part", "w") as f:
    json.dump({{"camera": scene.camera_json(), "size": scene.size}}, f)
os.rename({done!r} + ".part", {done!r})
"""


def read_frame_buffer(path):
    """The screen of an Xvfb started with -fbdir (an XWD file of 32-bit pixels), as (h, w, 3)."""
    import struct

    with open(path, "rb") as f:
        data = f.read()
    header = struct.unpack(">25I", data[:100])
    size, width, height, line, colours = header[0], header[4], header[5], header[12], header[19]
    if header[11] != 32:
        raise RuntimeError("%s: %d bits per pixel, 32 expected" % (path, header[11]))
    pixels = np.frombuffer(data, np.uint8, line * height, size + 12 * colours)
    bgrx = pixels.reshape(height, line // 4, 4)[:, :width]
    return np.ascontiguousarray(bgrx[:, :, 2::-1])


def write_image(path, rgb, quality=None):
    """An (h, w, 3) uint8 array as PNG, or JPEG at ``quality``, through VTK's writers."""
    from vtkmodules.util import numpy_support
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkIOImage import vtkJPEGWriter, vtkPNGWriter

    h, w, _ = rgb.shape
    image = vtkImageData()
    image.SetDimensions(w, h, 1)
    flat = np.ascontiguousarray(rgb[::-1]).reshape(-1, 3)
    image.GetPointData().SetScalars(numpy_support.numpy_to_vtk(flat, deep=True))
    writer = vtkJPEGWriter() if quality else vtkPNGWriter()
    if quality:
        writer.SetQuality(quality)
    writer.SetFileName(path)
    writer.SetInputData(image)
    writer.Write()


def grab_window(case, volume, preset, moves, image, view_png):
    """Case "window": ParaView's GUI under an X server of its own shows the scene; the window is
    cut from the screen into ``image``. Returns the render view's camera JSON and size."""
    import subprocess
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        display = next(n for n in range(140, 400) if not os.path.exists("/tmp/.X%d-lock" % n))
        screen = "%dx%dx24" % tuple(case["window"])
        xvfb = subprocess.Popen(
            ["Xvfb", ":%d" % display, "-screen", "0", screen, "-fbdir", tmp, "-nolisten", "tcp"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        gui = None
        try:
            done = os.path.join(tmp, "done.json")
            script = os.path.join(tmp, "scene.py")
            with open(script, "w") as f:
                f.write(
                    GUI_SCRIPT.format(
                        here=HERE,
                        volume=volume,
                        lighting=case.get("lighting"),
                        preset=preset,
                        moves=moves,
                        parallel=case.get("projection") == "parallel",
                        view_png=view_png,
                        done=done,
                    )
                )
            time.sleep(1)
            env = dict(os.environ, DISPLAY=":%d" % display)
            gui = subprocess.Popen(
                ["paraview", "--dr", "--script=" + script],
                env=env,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
            )
            deadline = time.time() + 180
            while not os.path.exists(done):
                if time.time() > deadline or gui.poll() is not None:
                    raise RuntimeError("%s: ParaView's GUI did not show the scene" % case["name"])
                time.sleep(0.5)
            time.sleep(3)  # the window repainted after the script
            screen_rgb = read_frame_buffer(os.path.join(tmp, "Xvfb_screen0"))
            with open(done) as f:
                shown = json.load(f)
        finally:
            for process in (gui, xvfb):
                if process is not None:
                    process.terminate()
                    process.wait()
    rows = np.flatnonzero(screen_rgb.any(axis=(1, 2)))
    cols = np.flatnonzero(screen_rgb.any(axis=(0, 2)))
    window = screen_rgb[rows[0] : rows[-1] + 1, cols[0] : cols[-1] + 1]
    write_image(image, window, JPEG_QUALITY if case["format"] == "jpg" else None)
    return shown["camera"], shown["size"]


def make_case(case, data_dir, out_dir):
    """Writes one case's files; returns its case JSON (dict)."""
    case_dir = os.path.join(out_dir, case["name"])
    os.makedirs(case_dir, exist_ok=True)
    volume = os.path.abspath(os.path.join(data_dir, "Volumes", case["volume"] + ".vti"))
    true_tf = os.path.join(case_dir, "true_tf.json")
    shutil.copyfile(os.path.join(HERE, "TransferFunctions", case["tf"] + ".json"), true_tf)
    with open(true_tf) as f:
        preset = json.load(f)[0]
    background = use_default_palette()
    moves = draw_camera(case["seed"])
    image = os.path.join(case_dir, "screenshot." + case["format"])
    if case.get("window"):
        view_png = os.path.join(case_dir, "view.png")
        camera, size = grab_window(case, volume, preset, moves, image, view_png)
        return write_records(
            case, case_dir, volume, true_tf, image, size, moves, background, camera
        )
    scene = VolumeScene(volume, case["size"], gui_look=True, lighting=case.get("lighting"))
    try:
        background = set_figure_background(scene, case, background)
        scene.apply(preset)
        place_camera(scene, moves, case.get("projection") == "parallel")
        options = {"Quality": JPEG_QUALITY} if case["format"] == "jpg" else {}
        scene.screenshot(image, **options)
        camera = scene.camera_json()
    finally:
        scene.close()
    return write_records(
        case, case_dir, volume, true_tf, image, case["size"], moves, background, camera
    )


GRADIENT_TOP = [0.0, 0.0, 0.16]


def set_figure_background(scene, case, palette):
    """The render view's background as the case's "figure" asks; returns it as the view JSON
    states it (a colour, or {"background", "background2"} for a gradient)."""
    wanted = (case.get("figure") or {}).get("background", "palette")
    if wanted == "palette":
        return palette
    scene.view.UseColorPaletteForBackground = 0
    if wanted == "black":
        scene.view.BackgroundColorMode = "Single Color"
        scene.view.Background = [0.0, 0.0, 0.0]
        return [0.0, 0.0, 0.0]
    if wanted == "gradient":
        scene.view.BackgroundColorMode = "Gradient"
        scene.view.Background = list(palette)
        scene.view.Background2 = GRADIENT_TOP
        return {"background": list(palette), "background2": GRADIENT_TOP}
    raise ValueError("%s: figure background %r" % (case["name"], wanted))


def write_records(case, case_dir, volume, true_tf, image, view_size, moves, background, camera):
    """true_view.json (the render view's camera and size) and case.json; returns the latter."""
    pixels = read_image(image)
    shape = [pixels.shape[1], pixels.shape[0]]
    if not case.get("window") and shape != list(case["size"]):
        raise RuntimeError("%s: screenshot is %s, not %s" % (image, shape, case["size"]))
    view = {"camera": camera, "size": list(view_size)}
    view.update(background if isinstance(background, dict) else {"background": background})
    if case.get("lighting"):
        view["lighting"] = case["lighting"]
    true_view = os.path.join(case_dir, "true_view.json")
    with open(true_view, "w") as f:
        json.dump(view, f, indent=2)
    record = {
        "name": case["name"],
        "volume": volume,
        "image": os.path.abspath(image),
        "true_tf": os.path.abspath(true_tf),
        "true_view": os.path.abspath(true_view),
        "size": shape,
        "window": case.get("window"),
        "format": case["format"],
        "jpeg_quality": JPEG_QUALITY if case["format"] == "jpg" else None,
        "seed": case["seed"],
        "camera_moves": moves,
        "background": background,
        "lighting": case.get("lighting"),
        "figure": case.get("figure"),
        # top-right pixel: the background as written (the orientation axes sit bottom left; a
        # window's screenshot: its frame's)
        "corner_pixel": [int(x) for x in pixels[0, -1]],
    }
    with open(os.path.join(case_dir, "case.json"), "w") as f:
        json.dump(record, f, indent=2)
    return record


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--out", required=True, help="output folder (not committed)")
    parser.add_argument("--cases", default=os.path.join(HERE, "cases.json"))
    parser.add_argument(
        "--data", default=os.path.join(HERE, "..", "..", "Data"), help="the project's Data"
    )
    parser.add_argument("--case", action="append", help="only this case (repeatable)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    listing = []
    for case in load_cases(args.cases, args.case):
        start = time.time()
        record = make_case(case, args.data, args.out)
        listing.append(os.path.join(os.path.abspath(args.out), case["name"], "case.json"))
        m = record["camera_moves"]
        print(
            f"{case['name']:9s} {case['volume']:7s} {record['size'][0]}x{record['size'][1]} "
            f"{case['format']:3s} azimuth {m['azimuth']:7.1f} elevation {m['elevation']:6.1f} "
            f"roll {m['roll']:6.1f} pan {m['pan'][0]:+.3f},{m['pan'][1]:+.3f} "
            f"zoom {m['zoom']:.2f} corner {record['corner_pixel']}  {time.time() - start:.1f} s",
            flush=True,
        )
    with open(os.path.join(args.out, "suite.json"), "w") as f:
        json.dump({"cases": listing}, f, indent=2)


if __name__ == "__main__":
    main()
