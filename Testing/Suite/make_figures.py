"""Figures as a paper has them, from the window suite's render-view screenshots.

For four cases of a folder make_suite.py wrote from cases_window.json, the render view's own
screenshot (view.png, ParaView's palette background) is pasted on a white page with matplotlib
(150 dpi): a panel label, the true TF's colour map as a colour bar beside or below it, and a
caption. Writes OUT/<case>/figure.png, OUT/<case>/case.json (the window case's, its image the
figure) and OUT/suite.json, which baseline.py runs as any suite.

    /usr/bin/python3 Testing/Suite/make_figures.py build/suite_window build/suite_figures
"""
import argparse
import json
import os

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from PIL import Image  # noqa: E402

# case -> where the colour bar goes
LAYOUTS = {"tooth_w1": "right", "tooth_w2": "below", "engine_w1": "below", "engine_w2": "right"}


def colour_map(preset):
    """The preset's RGB points as a matplotlib colour map over its value range."""
    points = np.array(preset["RGBPoints"], dtype=float).reshape(-1, 4)
    lo, hi = points[0, 0], points[-1, 0]
    stops = [((x - lo) / (hi - lo), tuple(c)) for x, *c in points]
    cmap = matplotlib.colors.LinearSegmentedColormap.from_list("tf", stops)
    return matplotlib.cm.ScalarMappable(cmap=cmap, norm=matplotlib.colors.Normalize(lo, hi))


def figure(render, mappable, layout, volume, path):
    """The render, its colour bar, a panel label and a caption on a white page."""
    if layout == "right":
        fig = plt.figure(figsize=(6.4, 4.4), dpi=150)
        ax = fig.add_axes([0.02, 0.16, 0.8, 0.78])
        bar = fig.add_axes([0.86, 0.24, 0.03, 0.62])
        fig.colorbar(mappable, cax=bar, label="scalar value")
    else:
        fig = plt.figure(figsize=(5.6, 5.0), dpi=150)
        ax = fig.add_axes([0.05, 0.3, 0.9, 0.65])
        bar = fig.add_axes([0.2, 0.2, 0.6, 0.035])
        fig.colorbar(mappable, cax=bar, orientation="horizontal", label="scalar value")
    ax.imshow(render)
    ax.axis("off")
    ax.text(0.0, 1.02, "(b)", transform=ax.transAxes, fontsize=12, weight="bold")
    fig.text(
        0.05,
        0.04,
        "Figure 4: Volume rendering of the %s data set with the transfer\n"
        "function of Table 2 (colour map shown by the bar)." % volume,
        fontsize=8,
    )
    fig.savefig(path, facecolor="white")
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("suite", help="a folder make_suite.py wrote from cases_window.json")
    parser.add_argument("out", help="output folder (not committed)")
    args = parser.parse_args()
    listing = []
    for name, layout in LAYOUTS.items():
        with open(os.path.join(args.suite, name, "case.json")) as f:
            case = json.load(f)
        with open(case["true_tf"]) as f:
            preset = json.load(f)[0]
        render = np.asarray(Image.open(os.path.join(args.suite, name, "view.png")).convert("RGB"))
        os.makedirs(os.path.join(args.out, name), exist_ok=True)
        image = os.path.abspath(os.path.join(args.out, name, "figure.png"))
        volume = os.path.splitext(os.path.basename(case["volume"]))[0]
        figure(render, colour_map(preset), layout, volume, image)
        case.update(image=image, format="png")
        record = os.path.abspath(os.path.join(args.out, name, "case.json"))
        with open(record, "w") as f:
            json.dump(case, f, indent=1)
        listing.append(record)
        print(name, layout, image)
    with open(os.path.join(args.out, "suite.json"), "w") as f:
        json.dump({"cases": listing}, f, indent=1)


if __name__ == "__main__":
    main()
