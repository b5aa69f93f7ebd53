"""What bounds the query alone (issue 20): the same score down a ladder of pictures, from the
picture a user has to a design the design space holds.

For each volume (its shipped bundle Data/Models/<volume>, or --model VOLUME=DIR) and each unlit
case of that volume in the --suite folders (make_suite.py output; lit cases are left out, the
ladder's clean renders being unlit), the query's TF (`ddg query --out-tf`) is scored against the
true TF at the suite's canonical views (Testing/Suite/score.py: ParaView, azimuth 0/120/240,
elevation 20, black and white, mean PSNR). The rungs:
  screenshot    the case's picture: the GUI look (palette background, orientation axes), a camera
                with roll, pan and zoom, PNG or JPEG (the query alone as baseline.py scores it)
  camera        `ddg render` of the true TF at the picture's camera, over black
  canonical     `ddg render` of the true TF at azimuth 0, elevation 20, over black, 400 x 300
                (once per TF)
  paraview_tfs  the same clean render of TFs drawn as users write them in ParaView: opacity
                piecewise linear above the volume's air (a ramp to the top of the range, a
                faint plateau then a ramp, or two tents), a colour map of 3-5 points anywhere in
                hue and lightness (--draws per volume, from --seed)
  design_space  the same clean render of designs the bundle's own design space draws (`ddg
                generate --tfs` with the bundle's spec, indices from 7 000 000: outside the
                training, held-out and recall ranges)
and, with no query at all:
  family        `ddg reconstruct --primitives 4` of the true TF's six canonical renders by ddg
                (200 x 150): how close four free Gaussian primitives hold the TF, i.e. whether
                the kind of TF the decoder writes could reach it
The gap between two rungs is what the step between them costs the query. Beside the screenshot
rung, a diagnosis of what it misses: the query's TF scored again with the true TF's colour map
(its opacity kept: "true colours") and with the true TF's opacity (its colours kept: "true
opacity").

Writes OUT/query_gaps.json (every figure), OUT/query_gaps.md and OUT/query_gaps.png.
Run (pvpython under a display; about 5 min per volume on 2 cores):
    scripts/with-xvfb.sh /usr/bin/pvpython Testing/Benchmarks/query_gaps.py \\
        --suite SUITE_DIR [SUITE_DIR ...] --out build/query_gaps [--volumes tooth engine]
"""
import argparse
import colorsys
import json
import os
import random
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "Testing", "Suite"))
from score import load_preset, score  # noqa: E402

RUNGS = ("screenshot", "camera", "canonical", "paraview_tfs", "design_space", "family")
HALVES = ("true_colours", "true_opacity")
LABELS = {
    "screenshot": "the user's screenshot (GUI look, camera unknown)",
    "camera": "clean render at the picture's camera, black",
    "canonical": "clean render at azimuth 0, elevation 20, black",
    "paraview_tfs": "ParaView-style TFs, clean canonical render",
    "design_space": "the design space's own designs, clean canonical render",
    "family": "4 free Gaussian primitives fitted (no query)",
    "true_colours": "the screenshot's query with the true TF's colours (diagnosis)",
    "true_opacity": "the screenshot's query with the true TF's opacity (diagnosis)",
}
SHORT = {
    "screenshot": "screenshot\n(GUI look)",
    "camera": "clean render,\nits camera",
    "canonical": "clean render,\ncanonical view",
    "paraview_tfs": "ParaView-style\nTFs",
    "design_space": "the design\nspace's designs",
    "family": "4 free primitives\n(no query)",
}
DESIGN_SPACE_FIRST_INDEX = 7000000


def ddg(args, *cmd):
    done = subprocess.run([args.ddg, *cmd], capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError("ddg %s failed: %s" % (cmd[0], done.stderr.strip()))
    return done.stdout


def value_range(args, volume):
    info = ddg(args, "info", "--volume", volume)
    m = re.search(r"^range\s+(\S+)\s*\.\.\s*(\S+)", info, re.MULTILINE)
    return float(m.group(1)), float(m.group(2))


def view_file(args, volume, path, azimuth, size, background):
    ddg(
        args,
        "view",
        "--volume",
        volume,
        "--out",
        path,
        "--size",
        *map(str, size),
        "--azimuth",
        str(azimuth),
        "--elevation",
        "20",
        "--background",
        *map(str, background)
    )
    return path


def query_tf(work, stem):
    """Where query_score writes the query's TF."""
    return os.path.join(work, stem + "_query.json")


def query_score(args, volume, model, picture, view, true_tf, work, stem):
    """The query's TF for `picture` (query_tf) scored against `true_tf` at the canonical views."""
    found = query_tf(work, stem)
    ddg(
        args,
        "query",
        "--model",
        model,
        "--volume",
        volume,
        "--image",
        picture,
        "--view",
        view,
        "--out-tf",
        found,
    )
    return score(volume, found, true_tf)["psnr"]


def halves_scores(volume, found, true_tf, work, stem):
    """The query's TF `found` with the true TF's colours, then with its opacity, each scored."""

    q, t = load_preset(found), load_preset(true_tf)
    mixes = {
        "true_colours": dict(q, RGBPoints=t["RGBPoints"], ColorSpace=t.get("ColorSpace", "RGB")),
        "true_opacity": dict(q, Points=t["Points"]),
    }
    out = {}
    for half, tf in mixes.items():
        path = os.path.join(work, "%s_%s.json" % (stem, half))
        with open(path, "w") as f:
            json.dump([tf], f)
        out[half] = score(volume, path, true_tf)["psnr"]
    return out


def increasing(points):
    """(x, y) pairs sorted, each x nudged above the last (ParaView needs increasing x)."""
    out = []
    for x, y in sorted(points):
        if out and x <= out[-1][0]:
            x = out[-1][0] + 1e-3
        out.append((x, y))
    return out


def paraview_style_tf(rng, lo, hi, air, name):
    """A TF as users write them in ParaView (see the module's doc), over [lo, hi], transparent
    up to `air` (the lowest feature region's start)."""
    span = hi - air
    xs = sorted([lo, hi] + [rng.uniform(air, hi) for _ in range(rng.randint(1, 3))])
    rgb = []
    for x in xs:
        r, g, b = colorsys.hls_to_rgb(rng.random(), rng.uniform(0.15, 0.95), rng.random())
        rgb += [x, r, g, b]
    start = air + rng.uniform(0.0, 0.4) * span
    kind = rng.choice(("ramp", "plateau_ramp", "tents"))
    if kind == "ramp":
        pts = [(lo, 0), (start, 0), (hi, rng.uniform(0.3, 1.0))]
    elif kind == "plateau_ramp":
        faint, top = rng.uniform(0.01, 0.15), rng.uniform(0.4, 1.0)
        end = start + rng.uniform(0.2, 0.6) * (hi - start)
        pts = [
            (lo, 0),
            (start, 0),
            (start + 0.04 * span, faint),
            (end, faint),
            (end + 0.04 * span, 0),
            (end + 0.12 * span, top),
            (hi, top),
        ]
        pts = [(min(x, hi), y) for x, y in pts]
    else:
        c1 = rng.uniform(start, start + 0.6 * (hi - start))
        c2 = rng.uniform(c1 + 0.1 * span, hi)
        w1, w2 = rng.uniform(0.02, 0.1) * span, rng.uniform(0.02, 0.1) * span
        pts = [
            (lo, 0),
            (c1 - w1, 0),
            (c1, rng.uniform(0.02, 0.3)),
            (c1 + w1, 0),
            (c2 - w2, 0),
            (c2, rng.uniform(0.3, 1.0)),
        ]
        pts += [(hi, 0)] if c2 + w2 < hi else []
    opacity = []
    for x, y in increasing([(max(lo, min(hi, x)), y) for x, y in pts]):
        opacity += [x, y, 0.5, 0.0]
    return [{"Name": name, "ColorSpace": "RGB", "RGBPoints": rgb, "Points": opacity}], kind


def family_fit(args, volume, true_tf, work, stem):
    """Four free Gaussian primitives fitted to ddg's six canonical renders of the true TF."""
    targets = []
    for azimuth in (0, 120, 240):
        for name, background in (("b", (0, 0, 0)), ("w", (1, 1, 1))):
            view = view_file(
                args,
                volume,
                os.path.join(work, "%s_v%d%s.json" % (stem, azimuth, name)),
                azimuth,
                (200, 150),
                background,
            )
            target = view.replace(".json", ".png")
            ddg(
                args, "render", "--volume", volume, "--tf", true_tf, "--view", view, "--out", target
            )
            targets += ["--target", target, "--view", view]
    found = os.path.join(work, stem + "_family.json")
    ddg(
        args,
        "reconstruct",
        "--volume",
        volume,
        *targets,
        "--primitives",
        "4",
        "--iterations",
        "800",
        "--threads",
        str(args.threads),
        "--quiet",
        "--out",
        found
    )
    return score(volume, found, true_tf)["psnr"]


def measure_volume(args, volume_name, model, cases, work):
    volume = os.path.join(ROOT, "Data", "Volumes", volume_name + ".vti")
    lo, hi = value_range(args, volume)
    with open(os.path.join(model, "bundle.json")) as f:
        bundle = json.load(f)
    air = min(r["lo"] for r in bundle["regions"])
    canonical = view_file(
        args, volume, os.path.join(work, "canonical.json"), 0, (400, 300), (0, 0, 0)
    )
    rows = {rung: [] for rung in RUNGS + HALVES}

    def clean_query(tf, stem):
        picture = os.path.join(work, stem + "_canonical.png")
        ddg(args, "render", "--volume", volume, "--tf", tf, "--view", canonical, "--out", picture)
        return query_score(args, volume, model, picture, canonical, tf, work, stem)

    tfs = {}
    for case in cases:
        name = case["name"]
        rows["screenshot"].append(
            {
                "case": name,
                "psnr": query_score(
                    args,
                    volume,
                    model,
                    case["image"],
                    case["true_view"],
                    case["true_tf"],
                    work,
                    name,
                ),
            }
        )
        for half, value in halves_scores(
            volume, query_tf(work, name), case["true_tf"], work, name
        ).items():
            rows[half].append({"case": name, "psnr": value})
        with open(case["true_view"]) as f:
            at_camera = json.load(f)
        at_camera["background"] = [0.0, 0.0, 0.0]
        camera_view = os.path.join(work, name + "_camera.json")
        with open(camera_view, "w") as f:
            json.dump(at_camera, f)
        picture = os.path.join(work, name + "_camera.png")
        ddg(
            args,
            "render",
            "--volume",
            volume,
            "--tf",
            case["true_tf"],
            "--view",
            camera_view,
            "--out",
            picture,
        )
        rows["camera"].append(
            {
                "case": name,
                "psnr": query_score(
                    args,
                    volume,
                    model,
                    picture,
                    camera_view,
                    case["true_tf"],
                    work,
                    name + "_camera",
                ),
            }
        )
        tfs.setdefault(os.path.basename(case["true_tf_name"]), case["true_tf"])
        print(
            "  %s: screenshot %.2f dB, clean at its camera %.2f dB"
            % (name, rows["screenshot"][-1]["psnr"], rows["camera"][-1]["psnr"]),
            flush=True,
        )
    for tf_name, tf in sorted(tfs.items()):
        rows["canonical"].append({"case": tf_name, "psnr": clean_query(tf, tf_name)})
        rows["family"].append(
            {"case": tf_name, "psnr": family_fit(args, volume, tf, work, tf_name)}
        )
        print(
            "  %s: clean canonical %.2f dB, four free primitives %.2f dB"
            % (tf_name, rows["canonical"][-1]["psnr"], rows["family"][-1]["psnr"]),
            flush=True,
        )
    rng = random.Random("%d %s" % (args.seed, volume_name))
    for i in range(args.draws):
        preset, kind = paraview_style_tf(rng, lo, hi, air, "paraview_style_%d" % i)
        tf = os.path.join(work, "paraview_style_%d.json" % i)
        with open(tf, "w") as f:
            json.dump(preset, f)
        rows["paraview_tfs"].append(
            {"case": "%d (%s)" % (i, kind), "psnr": clean_query(tf, "paraview_style_%d" % i)}
        )
    spec = os.path.join(work, "spec.json")
    with open(spec, "w") as f:
        json.dump(bundle["spec"], f)
    designs = os.path.join(work, "designs")
    ddg(
        args,
        "generate",
        "--volume",
        volume,
        "--spec",
        spec,
        "--count",
        str(args.draws),
        "--size",
        "64",
        "--out",
        os.path.join(work, "designs_data"),
        "--first-index",
        str(DESIGN_SPACE_FIRST_INDEX),
        "--tfs",
        designs,
        "--no-viewport",
        "--quiet",
        "--threads",
        str(args.threads),
    )
    for tf_file in sorted(os.listdir(designs)):
        stem = os.path.splitext(tf_file)[0]
        rows["design_space"].append(
            {"case": stem, "psnr": clean_query(os.path.join(designs, tf_file), stem)}
        )
    for rung in ("paraview_tfs", "design_space"):
        print("  %s: %s" % (rung, " ".join("%.2f" % r["psnr"] for r in rows[rung])), flush=True)
    return rows


def summary(rows):
    out = {}
    for rung, entries in rows.items():
        values = [e["psnr"] for e in entries]
        if values:
            out[rung] = {
                "mean": sum(values) / len(values),
                "min": min(values),
                "count": len(values),
            }
    return out


def markdown(result):
    lines = [
        "# What bounds the query alone",
        "",
        "The query's TF against the true TF at the suite's canonical views (ParaView, mean "
        "PSNR, dB), down the ladder of pictures (`Testing/Benchmarks/query_gaps.py`; "
        "bundles: %s)." % ", ".join("%s `%s`" % (v, m) for v, m in result["models"].items()),
        "",
    ]
    volumes = list(result["volumes"])
    lines.append("| rung | " + " | ".join("%s: mean (lowest), n" % v for v in volumes) + " |")
    lines.append("|---|" + "---|" * len(volumes))
    for rung in RUNGS + HALVES:
        cells = []
        for v in volumes:
            s = result["volumes"][v]["summary"].get(rung)
            cells.append("%.2f (%.2f), %d" % (s["mean"], s["min"], s["count"]) if s else "—")
        lines.append("| %s | %s |" % (LABELS[rung], " | ".join(cells)))
    lines += ["", "Every figure:", ""]
    for v in volumes:
        for rung in RUNGS + HALVES:
            entries = result["volumes"][v]["rows"].get(rung, [])
            lines.append(
                "- %s, %s: %s"
                % (v, rung, ", ".join("%s %.2f" % (e["case"], e["psnr"]) for e in entries))
            )
    return "\n".join(lines) + "\n"


def chart(result, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 4.2))
    volumes = list(result["volumes"])
    for k, v in enumerate(volumes):
        for i, rung in enumerate(RUNGS):
            entries = result["volumes"][v]["rows"][rung]
            x = i + (k - (len(volumes) - 1) / 2) * 0.25
            ax.scatter(
                [x] * len(entries),
                [e["psnr"] for e in entries],
                s=14,
                alpha=0.6,
                color="C%d" % k,
                label=v if i == 0 else None,
            )
            s = result["volumes"][v]["summary"].get(rung)
            if s:
                ax.plot([x - 0.1, x + 0.1], [s["mean"]] * 2, color="C%d" % k, lw=2)
    ax.axhline(28, color="grey", ls="--", lw=1)
    ax.text(len(RUNGS) - 0.5, 28.3, "issue 20's bar", ha="right", fontsize=8, color="grey")
    ax.set_xticks(range(len(RUNGS)))
    ax.set_xticklabels([SHORT[r] for r in RUNGS], fontsize=8)
    ax.set_ylabel("canonical-view PSNR against the true TF (dB)")
    ax.set_title("The query alone down the ladder of pictures (bars: means)", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    p = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("--suite", nargs="+", help="make_suite.py output folders")
    p.add_argument(
        "--render-only",
        action="store_true",
        help="rewrite OUT's table and chart from OUT/query_gaps.json, measure nothing",
    )
    p.add_argument("--out", required=True)
    p.add_argument("--volumes", nargs="+", default=["tooth", "engine"])
    p.add_argument(
        "--model",
        action="append",
        default=[],
        help="VOLUME=BUNDLE_DIR instead of " "Data/Models/VOLUME",
    )
    p.add_argument("--ddg", default=os.path.join(ROOT, "build", "bin", "ddg"))
    p.add_argument("--draws", type=int, default=8, help="ParaView-style TFs and designs per volume")
    p.add_argument("--seed", type=int, default=62)
    p.add_argument("--threads", type=int, default=2)
    args = p.parse_args()
    models = {v: os.path.join(ROOT, "Data", "Models", v) for v in args.volumes}
    for item in args.model:
        v, _, path = item.partition("=")
        models[v] = os.path.abspath(path)
    os.makedirs(args.out, exist_ok=True)
    if args.render_only:
        with open(os.path.join(args.out, "query_gaps.json")) as f:
            render(json.load(f), args.out)
        return
    if not args.suite:
        p.error("--suite is required (or --render-only)")
    result = {
        "models": {v: os.path.relpath(models[v], ROOT) for v in args.volumes},
        "draws": args.draws,
        "seed": args.seed,
        "volumes": {},
    }
    for v in args.volumes:
        cases = []
        for suite in args.suite:
            with open(os.path.join(suite, "suite.json")) as f:
                for path in json.load(f)["cases"]:
                    with open(path) as c:
                        case = json.load(c)
                    if os.path.basename(case["volume"]) == v + ".vti" and not case.get("lighting"):
                        with open(case["true_tf"]) as t:
                            case["true_tf_name"] = json.load(t)[0]["Name"]
                        cases.append(case)
        print("%s: %d unlit cases" % (v, len(cases)), flush=True)
        with tempfile.TemporaryDirectory() as work:
            rows = measure_volume(args, v, models[v], cases, work)
        result["volumes"][v] = {"rows": rows, "summary": summary(rows)}
    with open(os.path.join(args.out, "query_gaps.json"), "w") as f:
        json.dump(result, f, indent=1)
    render(result, args.out)


def render(result, out):
    with open(os.path.join(out, "query_gaps.md"), "w") as f:
        f.write(markdown(result))
    chart(result, os.path.join(out, "query_gaps.png"))
    print(markdown(result))


if __name__ == "__main__":
    main()
