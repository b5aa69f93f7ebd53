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
    scene = VolumeScene(volume, case["size"], gui_look=True, lighting=case.get("lighting"))
    try:
        scene.apply(preset)
        place_camera(scene, moves, case.get("projection") == "parallel")
        image = os.path.join(case_dir, "screenshot." + case["format"])
        options = {"Quality": JPEG_QUALITY} if case["format"] == "jpg" else {}
        scene.screenshot(image, **options)
        camera = scene.camera_json()
    finally:
        scene.close()
    pixels = read_image(image)
    if list(pixels.shape[:2]) != [case["size"][1], case["size"][0]]:
        raise RuntimeError("%s: screenshot is %s, not %s" % (image, pixels.shape, case["size"]))
    view = {"camera": camera, "size": list(case["size"]), "background": background}
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
        "size": list(case["size"]),
        "format": case["format"],
        "jpeg_quality": JPEG_QUALITY if case["format"] == "jpg" else None,
        "seed": case["seed"],
        "camera_moves": moves,
        "background": background,
        "lighting": case.get("lighting"),
        # top-right pixel: the background as written (the orientation axes sit bottom left)
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
            f"{case['name']:9s} {case['volume']:7s} {case['size'][0]}x{case['size'][1]} "
            f"{case['format']:3s} azimuth {m['azimuth']:7.1f} elevation {m['elevation']:6.1f} "
            f"roll {m['roll']:6.1f} pan {m['pan'][0]:+.3f},{m['pan'][1]:+.3f} "
            f"zoom {m['zoom']:.2f} corner {record['corner_pixel']}  {time.time() - start:.1f} s",
            flush=True,
        )
    with open(os.path.join(args.out, "suite.json"), "w") as f:
        json.dump({"cases": listing}, f, indent=2)


if __name__ == "__main__":
    main()
