"""Figures as a paper has them, from render-view screenshots.

A render view's screenshot is pasted on a white page with matplotlib (150 dpi): a panel label,
the true TF's colour map as a colour bar beside or below it, and a caption. From a folder
make_suite.py wrote from cases_figure.json, every case (its "figure" object says where the bar
goes and the figure's format, PNG or JPEG at quality 90; the render's background was set by
make_suite.py); from one it wrote from cases_window.json, four cases (LAYOUTS), the render
view's own screenshot (view.png) pasted. Writes OUT/<case>/figure.png|jpg, OUT/<case>/case.json
(the case's, its image the figure, "pasted" the whole pixels {x, y, width, height} the render
covers, from matplotlib's transform), OUT/<case>/pasted.png (the figure cut exactly there: the
render as the figure holds it, without the page) and OUT/suite.json, which baseline.py runs as
any suite.

    /usr/bin/python3 Testing/Suite/make_figures.py build/suite_figure build/suite_figures
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


def figure(render, mappable, layout, volume, path, quality=None):
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
    fig.canvas.draw()
    # where the render lands on the page: its pixel corners through matplotlib's own transform
    # (the display's y axis points up, the saved picture's down)
    height, width = render.shape[:2]
    (x0, y0), (x1, y1) = ax.transData.transform([(-0.5, height - 0.5), (width - 0.5, -0.5)])
    page_height = fig.bbox.height
    ax.text(0.0, 1.02, "(b)", transform=ax.transAxes, fontsize=12, weight="bold")
    fig.text(
        0.05,
        0.04,
        "Figure 4: Volume rendering of the %s data set with the transfer\n"
        "function of Table 2 (colour map shown by the bar)." % volume,
        fontsize=8,
    )
    # at the figure's own size, as drawn (the rectangle above holds in the saved picture)
    fig.savefig(
        path,
        facecolor="white",
        dpi=fig.dpi,
        bbox_inches=None,
        **({"pil_kwargs": {"quality": quality}} if quality else {}),
    )
    plt.close(fig)
    saved = Image.open(path).size
    assert saved == (round(fig.bbox.width), round(fig.bbox.height)), (saved, fig.bbox)
    # the whole pixels inside it
    return [
        int(np.ceil(x0)),
        int(np.ceil(page_height - y1)),
        int(np.floor(x1)) - int(np.ceil(x0)),
        int(np.floor(page_height - y0)) - int(np.ceil(page_height - y1)),
    ]


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument(
        "suite", help="a folder make_suite.py wrote from cases_figure.json or cases_window.json"
    )
    parser.add_argument("out", help="output folder (not committed)")
    args = parser.parse_args()
    with open(os.path.join(args.suite, "suite.json")) as f:
        cases = [json.load(open(path)) for path in json.load(f)["cases"]]
    listing = []
    for case in cases:
        name, look = case["name"], case.get("figure")
        if look:
            layout, fmt, render_file = look["bar"], look.get("format", "png"), case["image"]
        elif name in LAYOUTS:
            layout, fmt, render_file = (
                LAYOUTS[name],
                "png",
                os.path.join(args.suite, name, "view.png"),
            )
        else:
            continue
        with open(case["true_tf"]) as f:
            preset = json.load(f)[0]
        render = np.asarray(Image.open(render_file).convert("RGB"))
        os.makedirs(os.path.join(args.out, name), exist_ok=True)
        image = os.path.abspath(os.path.join(args.out, name, "figure." + fmt))
        volume = os.path.splitext(os.path.basename(case["volume"]))[0]
        pasted = figure(
            render, colour_map(preset), layout, volume, image, 90 if fmt == "jpg" else None
        )
        # the figure cut exactly where the render is (the same pixels, without the page)
        x, y, w, h = pasted
        cut = np.asarray(Image.open(image).convert("RGB"))[y : y + h, x : x + w]
        Image.fromarray(cut).save(os.path.join(args.out, name, "pasted.png"))
        case.update(image=image, format=fmt, pasted=pasted)
        record = os.path.abspath(os.path.join(args.out, name, "case.json"))
        with open(record, "w") as f:
            json.dump(case, f, indent=1)
        listing.append(record)
        print(name, layout, image)
    with open(os.path.join(args.out, "suite.json"), "w") as f:
        json.dump({"cases": listing}, f, indent=1)


if __name__ == "__main__":
    main()
