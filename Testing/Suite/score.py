"""The suite's score: how close a found TF is to the true one, seen by ParaView.

What is compared with what: ParaView 5.11 renders the volume (Volume representation, unlit,
no orientation axes) with the found TF and with the true TF at three canonical views
(ParaView's reset camera, then azimuth 0, 120 and 240 degrees and elevation 20), each on a black
and on a white background: 6 pairs of 8-bit RGB images of the same size (default 400 x 300).
The score is the mean of the 6 PSNRs (dB, over all pixels and channels; a pair of identical
images counts as PSNR_CAP). It does not depend on the screenshot's camera, size, background or
overlays, and it catches a haze: air painted in the screenshot's background colour is invisible
over that background but shows over black or white.

As a program (pvpython under a display):
    scripts/with-xvfb.sh /usr/bin/pvpython Testing/Suite/score.py VOLUME FOUND.json TRUE.json
        [--size 400 300] [--out DIR] [--json]
As a function: ``score(volume, found_preset, true_preset)`` (presets as dicts or file paths).
"""
import argparse
import json
import math
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from suite_paraview import VolumeScene, read_image  # noqa: E402

AZIMUTHS = (0.0, 120.0, 240.0)
ELEVATION = 20.0
BACKGROUNDS = {"black": [0.0, 0.0, 0.0], "white": [1.0, 1.0, 1.0]}
SIZE = (400, 300)
PSNR_CAP = 100.0  # dB, for identical images


def load_preset(tf):
    """A ParaView preset as a dict, from a dict or a preset JSON file (first entry)."""
    if isinstance(tf, dict):
        return tf
    with open(tf) as f:
        data = json.load(f)
    return data[0] if isinstance(data, list) else data


def psnr(a, b):
    mse = float(np.mean((a.astype(np.float64) - b.astype(np.float64)) ** 2))
    return PSNR_CAP if mse == 0 else min(PSNR_CAP, 10.0 * math.log10(255.0**2 / mse))


def canonical_renders(volume, tf, size=SIZE, out_dir=None, stem="tf", lighting=None):
    """ParaView's renders of ``tf`` at the canonical views: a list of dicts (azimuth,
    background, image as a (h, w, 3) uint8 array), in the order of AZIMUTHS x BACKGROUNDS,
    lit as ``lighting`` (the view JSON's "lighting"; unlit when None) says.
    With ``out_dir`` the PNGs are kept there as <stem>_az<A>_<background>.png."""
    preset = load_preset(tf)
    renders = []
    with tempfile.TemporaryDirectory() as tmp:
        scene = VolumeScene(volume, size, lighting=lighting)
        try:
            scene.apply(preset)
            for azimuth in AZIMUTHS:
                scene.orbit(azimuth, ELEVATION)
                for name, rgb in BACKGROUNDS.items():
                    scene.set_background(rgb)
                    path = os.path.join(out_dir or tmp, "%s_az%03d_%s.png" % (stem, azimuth, name))
                    scene.screenshot(path)
                    renders.append(
                        {"azimuth": azimuth, "background": name, "image": read_image(path)}
                    )
        finally:
            scene.close()
    return renders


def score_renders(found, true):
    """The score of two lists of canonical renders (canonical_renders)."""
    per_render = []
    for f, t in zip(found, true):
        assert (f["azimuth"], f["background"]) == (t["azimuth"], t["background"])
        per_render.append(
            {
                "azimuth": f["azimuth"],
                "elevation": ELEVATION,
                "background": f["background"],
                "psnr": psnr(f["image"], t["image"]),
            }
        )
    mean = sum(r["psnr"] for r in per_render) / len(per_render)
    by_background = {
        name: sum(r["psnr"] for r in per_render if r["background"] == name) / len(AZIMUTHS)
        for name in BACKGROUNDS
    }
    return {"psnr": mean, "psnr_by_background": by_background, "renders": per_render}


def score(volume, found_tf, true_tf, size=SIZE, out_dir=None, lighting=None):
    """Mean PSNR (dB) of ParaView's renders of ``found_tf`` against ``true_tf`` at the canonical
    views on black and white, both lit as ``lighting`` (the picture's: the same Shade);
    returns {"psnr", "psnr_by_background", "renders": [...]}."""
    true = canonical_renders(volume, true_tf, size, out_dir, "true", lighting)
    found = canonical_renders(volume, found_tf, size, out_dir, "found", lighting)
    return score_renders(found, true)


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("volume")
    parser.add_argument("found", help="the found TF (ParaView preset JSON)")
    parser.add_argument("true", help="the true TF (ParaView preset JSON)")
    parser.add_argument("--size", type=int, nargs=2, default=list(SIZE), metavar=("W", "H"))
    parser.add_argument("--out", help="keep the renders in this folder")
    parser.add_argument("--json", action="store_true", help="print the result as JSON")
    parser.add_argument(
        "--lighting", help='the view JSON\'s "lighting" (JSON text) to render both TFs with'
    )
    parser.add_argument(
        "--min-psnr", type=float, help="exit 1 when the score is below this (dB)", default=None
    )
    parser.add_argument(
        "--max-psnr", type=float, help="exit 1 when the score is above this (dB)", default=None
    )
    args = parser.parse_args()
    if args.out:
        os.makedirs(args.out, exist_ok=True)
    lighting = json.loads(args.lighting) if args.lighting else None
    result = score(args.volume, args.found, args.true, args.size, args.out, lighting)
    if args.json:
        print(json.dumps(result, indent=2))
    else:
        for r in result["renders"]:
            print(f"azimuth {r['azimuth']:5.0f} on {r['background']:5s}: {r['psnr']:6.2f} dB")
        print(f"mean PSNR {result['psnr']:.2f} dB")
    ok = (args.min_psnr is None or result["psnr"] >= args.min_psnr) and (
        args.max_psnr is None or result["psnr"] <= args.max_psnr
    )
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
