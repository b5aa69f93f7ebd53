"""How far B rendered with a TF is from A's picture, in the carried look's own colour measure.

For every case folder of a carry_look_pairs.py run (picture_a.*, reference.json, carry.json,
query.json, ...), B is rendered with each TF by `ddg render` at the carried look's three views
(azimuth 30/150/270, elevation 20, 64 px) over the picture's background, and compared with the
picture by the sliced Wasserstein distance in CIELAB (256 directions, fixed seed; the mean over the
views of the squared distance, as the fit's loss), two ways:
  framed       the pixels of the square around the object (1.1 x its larger side), background
               included, as the fit frames them;
  object only  the pixels off the background (by more than 0.04) alone.
The picture is subsampled (every other pixel), its background is the median of its top and bottom
rows, and its bottom-left corner (30 % by 20 %: ParaView's orientation axes) is left out. A
render that shows nothing at a view gives NaN.

This is a re-computation outside the fit (Documentation/DesignSpaces.md, "The CT pair's
references do not look like its pictures"), not the fit's own figure: the fit frames and weights
its pixels in Core, so its numbers differ; the comparison between TFs is what it is for.

Run (after carry_look_pairs.py into OUT):
    /usr/bin/python3 Testing/Benchmarks/carry_look_distance.py --ddg build/bin/ddg --pairs-out OUT \
        [--pairs Testing/Benchmarks/carry_look_pairs_holdout.json] [--tfs reference carry query]
"""
import argparse
import glob
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from carry_look_pairs import read_pairs, volume_file  # noqa: E402

VIEWS = (30, 150, 270)
OFF_BACKGROUND = 0.04


def lab(rgb):
    """sRGB in [0, 1] (N x 3) to CIELAB (D65)."""
    c = np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)
    m = np.array([[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]])
    xyz = c @ m.T / np.array([0.95047, 1.0, 1.08883])
    f = np.where(xyz > 0.008856, np.cbrt(xyz), 7.787 * xyz + 16 / 116)
    return np.stack([116 * f[:, 1] - 16, 500 * (f[:, 0] - f[:, 1]), 200 * (f[:, 1] - f[:, 2])], -1)


def object_mask(image, background, left_out=None):
    mask = np.abs(image - background).max(-1) > OFF_BACKGROUND
    return mask if left_out is None else mask & ~left_out


def framed(image, background, left_out=None):
    """CIELAB of the square around the object; outside the image counts as background."""
    ys, xs = np.nonzero(object_mask(image, background, left_out))
    if len(xs) == 0:
        return np.empty((0, 3))
    side = max(4, round(1.1 * max(xs.max() - xs.min() + 1, ys.max() - ys.min() + 1)))
    x0 = (xs.min() + xs.max() + 1 - side) // 2
    y0 = (ys.min() + ys.max() + 1 - side) // 2
    h, w = image.shape[:2]
    yy, xx = np.mgrid[y0 : y0 + side, x0 : x0 + side]
    inside = (xx >= 0) & (xx < w) & (yy >= 0) & (yy < h)
    pixels = np.broadcast_to(background, yy.shape + (3,)).copy()
    pixels[inside] = image[yy[inside], xx[inside]]
    keep = np.ones(yy.shape, bool)
    if left_out is not None:
        keep[inside] = ~left_out[yy[inside], xx[inside]]
    return lab(pixels[keep])


def object_only(image, background, left_out=None):
    return lab(image[object_mask(image, background, left_out)])


def sliced_wasserstein(a, b, directions=256):
    """Mean over random unit directions of the squared 1D Wasserstein-2 distance (NaN when
    either side has no pixel)."""
    if len(a) == 0 or len(b) == 0:
        return float("nan")
    rng = np.random.default_rng(1)
    m = min(len(a), len(b))
    grid = np.linspace(0, 1, m)
    total = 0.0
    for _ in range(directions):
        d = rng.normal(size=3)
        d /= np.linalg.norm(d)
        qa = np.interp(grid, np.linspace(0, 1, len(a)), np.sort(a @ d))
        qb = np.interp(grid, np.linspace(0, 1, len(b)), np.sort(b @ d))
        total += np.mean((qa - qb) ** 2)
    return total / directions


def read_rgb(path):
    return np.asarray(Image.open(path).convert("RGB")).astype(float) / 255


def distances(ddg, volume, picture, tfs, work):
    image = read_rgb(picture)[::2, ::2]
    background = np.median(np.concatenate([image[0], image[-1]]), 0)
    left_out = np.zeros(image.shape[:2], bool)
    left_out[int(image.shape[0] * 0.7) :, : int(image.shape[1] * 0.2)] = True
    picture_framed = framed(image, background, left_out)
    picture_object = object_only(image, background, left_out)
    result = {}
    for name, tf in tfs.items():
        sums = [0.0, 0.0]
        for azimuth in VIEWS:
            view = os.path.join(work, "view.json")
            render = os.path.join(work, "render.png")
            subprocess.run(
                [ddg, "view", "--volume", volume, "--out", view, "--size", "64", "64"]
                + ["--azimuth", str(azimuth), "--elevation", "20", "--background"]
                + [str(v) for v in background],
                check=True,
                capture_output=True,
            )
            subprocess.run(
                [ddg, "render", "--volume", volume, "--tf", tf, "--view", view, "--out", render],
                check=True,
                capture_output=True,
            )
            r = read_rgb(render)
            sums[0] += sliced_wasserstein(picture_framed, framed(r, background)) / len(VIEWS)
            sums[1] += sliced_wasserstein(picture_object, object_only(r, background)) / len(VIEWS)
        result[name] = {"framed": sums[0], "object_only": sums[1]}
    return result


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--ddg", required=True)
    parser.add_argument("--pairs-out", required=True, help="a carry_look_pairs.py --out folder")
    parser.add_argument("--pairs", default=os.path.join(HERE, "carry_look_pairs.json"))
    parser.add_argument("--tfs", nargs="+", default=["reference", "carry", "query"])
    args = parser.parse_args()
    spec = read_pairs(args.pairs)
    rows = {}
    with tempfile.TemporaryDirectory() as work:
        for pair in spec["pairs"]:
            volume = volume_file(
                spec["volumes"][pair["b"]], os.path.join(args.pairs_out, "volumes")
            )
            for tf in pair["tfs"]:
                case = f"{pair['name']}_{tf['name'].split('_')[-1]}"
                folder = os.path.join(args.pairs_out, case)
                pictures = glob.glob(os.path.join(folder, "picture_a.*"))
                if not pictures:
                    print(f"{case}: no picture in {folder}, skipped", file=sys.stderr)
                    continue
                tfs = {t: os.path.join(folder, t + ".json") for t in args.tfs}
                tfs = {t: p for t, p in tfs.items() if os.path.isfile(p)}
                rows[case] = distances(args.ddg, volume, pictures[0], tfs, work)
                cells = [
                    f"{t} {d['framed']:.1f} / {d['object_only']:.1f}" for t, d in rows[case].items()
                ]
                print(f"{case}: " + ", ".join(cells), flush=True)
    rounded = {
        c: {t: {k: round(v, 3) for k, v in d.items()} for t, d in r.items()}
        for c, r in rows.items()
    }
    print(json.dumps(rounded, indent=1))


if __name__ == "__main__":
    main()
