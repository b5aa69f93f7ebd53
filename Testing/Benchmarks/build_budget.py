#!/usr/bin/env python3
"""build_budget.py: what a design space for your own volume costs and gives, per time budget.

For each volume and budget it runs `ddg build --budget MINUTES` (or the given --build-args
instead of --budget), times the whole build (exemplars, training, evaluation, outline), reads the
held-out imitation figures the build records in bundle.json (PSNR, SSIM on held-out exemplars
never trained on), and checks the outline with `ddg validity --outline-count N` (designs whose
image is empty or a flat box: Core/Design/DesignCheck.h). Results are merged into --out/
build_budget.json (one entry per volume and budget, a re-run replaces it), and rendered as
build_budget.md and build_budget.png (PSNR and SSIM against the build's minutes, the issue's bar
at 28 dB / 0.90 drawn).

  /usr/bin/python3 Testing/Benchmarks/build_budget.py --ddg build/bin/ddg \
      --volumes bonsai headsq chest mri neghip ironprot --budgets 2 10 30 \
      --work /tmp/budget --out Documentation/Results/build_budget

  --render-only re-renders the markdown and chart from the JSON.

With --suite (folders written by Testing/Suite/make_suite.py) each bundle also answers the
realistic screenshots of its volume: the query alone (`baseline.py --methods query` with the
bundle in place of the shipped one), scored at the canonical views against the true TF; the
table gains its mean and lowest PSNR and the chart a third panel, query accuracy against the
build's minutes, one line per analyzer width (issue 20: query accuracy against model size and
training minutes). --build-args "--budget 5 --width 8" gives another width; entries are kept
per volume, budget and options.

  /usr/bin/python3 Testing/Benchmarks/build_budget.py --volumes tooth --budgets 2 5 10 \
      --suite build/suite/cases build/suite/cases_holdout --out Documentation/Results/query_budget
"""
import argparse
import json
import os
import re
import shlex
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def options_of(args, budget):
    return shlex.split(args.build_args) if args.build_args else ["--budget", f"{budget:g}"]


def tag_of(volume, budget, options):
    extra = [o.lstrip("-") for o in options if o not in ("--budget", f"{budget:g}")]
    return "_".join([volume, f"{budget:g}min"] + extra)


def query_suite(args, volume, bundle, tag):
    """The query alone with `bundle` on every case of `volume` in the --suite folders: the
    canonical-view PSNR per case (Testing/Suite/baseline.py, pvpython under Xvfb)."""
    models = os.path.join(args.work, "models_" + tag)
    subprocess.run(["rm", "-rf", models], check=True)
    os.makedirs(models)
    os.symlink(os.path.abspath(bundle), os.path.join(models, volume))
    scores = {}
    for suite in args.suite:
        with open(os.path.join(suite, "suite.json")) as f:
            cases = [json.load(open(c)) for c in json.load(f)["cases"]]
        names = [c["name"] for c in cases if os.path.basename(c["volume"]) == volume + ".vti"]
        if not names:
            continue
        out = os.path.join(args.work, "query_" + tag + "_" + os.path.basename(suite.rstrip("/")))
        cmd = [os.path.join(ROOT, "scripts", "with-xvfb.sh"), args.pvpython]
        cmd += [os.path.join(ROOT, "Testing", "Suite", "baseline.py"), "--suite", suite]
        cmd += [
            "--ddg",
            args.ddg,
            "--out",
            out,
            "--models",
            models,
            "--methods",
            "query",
        ]
        for n in names:
            cmd += ["--case", n]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        with open(os.path.join(out, "baseline.json")) as f:
            for record in json.load(f)["cases"]:
                scores[record["name"]] = record["methods"]["query"]["psnr"]
    return scores


def run_one(args, volume, budget):
    vol = os.path.join(ROOT, "Data", "Volumes", volume + ".vti")
    options = options_of(args, budget)
    tag = tag_of(volume, budget, options)
    bundle = os.path.join(args.work, tag)
    if os.path.exists(bundle):
        subprocess.run(["rm", "-rf", bundle], check=True)
    cmd = [args.ddg, "build", "--volume", vol, "--out", bundle, "--quiet"] + options
    t0 = time.time()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    minutes = (time.time() - t0) / 60
    entry = {
        "volume": volume,
        "budget_minutes": budget,
        "options": " ".join(options),
        "build_minutes": round(minutes, 2),
    }
    if proc.returncode != 0:
        entry["error"] = (proc.stderr or proc.stdout).strip()[-400:]
        return entry
    recorded = json.load(open(os.path.join(bundle, "bundle.json")))
    metrics = recorded["metrics"]
    entry.update(
        {
            "exemplars": recorded.get("training_exemplars"),
            "psnr": metrics["psnr"],
            "ssim": metrics["ssim"],
            "heldout": metrics["heldout_count"],
            "train_minutes": round(metrics["train_seconds"] / 60, 2),
            "train_iterations": metrics["train_iterations"],
            "image_rays": metrics["image_rays"],
            "width": recorded["architecture"]["width"],
            "parameters": recorded.get("parameters"),
        }
    )
    if args.suite:
        entry["query_psnr"] = query_suite(args, volume, bundle, tag)
    sheet = os.path.join(args.out, f"outline_{volume}.png") if budget == args.sheet_budget else ""
    vcmd = [
        args.ddg,
        "validity",
        "--model",
        bundle,
        "--volume",
        vol,
        "--count",
        "4",
        "--out",
        os.path.join(args.work, f"{volume}_validity.png"),
        "--outline-count",
        str(args.outline_check),
    ]
    if sheet:
        vcmd += ["--outline-sheet", sheet]
    out = subprocess.run(vcmd, capture_output=True, text=True, check=True).stdout
    m = re.search(
        r"outline: (\d+) of (\d+) designs .*?: (\d+) empty, (\d+) flat box .*?; " r"(\d+) give",
        out,
    )
    if m:
        checked, _, empty, box, hazy = (int(g) for g in m.groups())
        entry.update(
            {
                "outline_checked": checked,
                "outline_empty": empty,
                "outline_flat_box": box,
                "outline_hazy_faces": hazy,
            }
        )
    return entry


def render(out_dir, results):
    rows = sorted(results, key=lambda e: (e["volume"], e["budget_minutes"]))
    lines = [
        "| volume | build options | build (min) | exemplars | training (min), iterations, "
        "image-loss rays | held-out PSNR (dB) | SSIM | outline: empty + flat box of checked | "
        "boundary faces hazy |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for e in rows:
        if "error" in e:
            lines.append(
                f"| {e['volume']} | `{e['options']}` | {e['build_minutes']} | "
                f"failed: {e['error'][:80]} | | | | | |"
            )
            continue
        junk = e.get("outline_empty", 0) + e.get("outline_flat_box", 0)
        lines.append(
            f"| {e['volume']} | `{e['options']}` | {e['build_minutes']:.1f} | "
            f"{e.get('exemplars') or '—'} | {e['train_minutes']:.1f}, "
            f"{e.get('train_iterations', '—')}, {e.get('image_rays', 512)} | "
            f"{e['psnr']:.2f} | {e['ssim']:.3f} | "
            f"{junk} of {e.get('outline_checked', 0)} ({e.get('outline_empty', 0)} empty, "
            f"{e.get('outline_flat_box', 0)} flat box) | {e.get('outline_hazy_faces', 0)} |"
        )
    queried = [e for e in rows if e.get("query_psnr")]
    if queried:
        names = sorted({n for e in queried for n in e["query_psnr"]})
        lines += [
            "",
            "The query alone on the realistic screenshots (canonical-view PSNR against the true "
            "TF, dB):",
            "",
            "| volume | build options | analyzer width, parameters | build (min) | training "
            "iterations | " + " | ".join(names) + " | mean | lowest |",
            "|---|---|---|---|---|" + "---|" * (len(names) + 2),
        ]
        for e in queried:
            got = [e["query_psnr"].get(n) for n in names]
            valid = [v for v in got if v is not None]
            cells = ["—" if v is None else f"{v:.2f}" for v in got]
            mean = f"{sum(valid) / len(valid):.2f}" if valid else "—"
            low = f"{min(valid):.2f}" if valid else "—"
            lines.append(
                f"| {e['volume']} | `{e['options']}` | {e.get('width')}, {e.get('parameters')} | "
                f"{e['build_minutes']:.1f} | {e.get('train_iterations')} | "
                + " | ".join(cells)
                + f" | {mean} | {low} |"
            )
    options = sorted({e["options"] for e in rows})
    text = (
        "# Design spaces per time budget (`Testing/Benchmarks/build_budget.py`)\n\n"
        + "\n".join(lines)
        + "\n\n`ddg build` options: "
        + "; ".join(f"`{o}`" for o in options)
        + "\n"
    )
    with open(os.path.join(out_dir, "build_budget.md"), "w") as f:
        f.write(text)
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    panels = [(28, "held-out PSNR (dB)"), (0.9, "held-out SSIM")]
    if queried:
        panels.append((28, "query alone, realistic screenshots (dB)"))
    fig, axes = plt.subplots(1, len(panels), figsize=(5 * len(panels), 4))
    # one line per volume; with the query's panel, per volume and analyzer width
    groups = sorted({(e["volume"], (e.get("width") or 16) if queried else 0) for e in rows})
    for g, (volume, width) in enumerate(groups):
        pts = [
            e
            for e in rows
            if e["volume"] == volume
            and "psnr" in e
            and (not queried or (e.get("width") or 16) == width)
        ]
        pts.sort(key=lambda e: e["build_minutes"])
        label = f"{volume}, width {width}" if queried else volume
        xs = [e["build_minutes"] for e in pts]
        axes[0].plot(xs, [e["psnr"] for e in pts], "o-", color=f"C{g}", label=label)
        axes[1].plot(xs, [e["ssim"] for e in pts], "o-", color=f"C{g}", label=label)
        q = [e for e in pts if e.get("query_psnr")]
        if queried and q:
            qx = [e["build_minutes"] for e in q]
            means = [sum(e["query_psnr"].values()) / len(e["query_psnr"]) for e in q]
            lows = [min(e["query_psnr"].values()) for e in q]
            axes[2].plot(qx, means, "o-", color=f"C{g}", label=label + ", mean")
            axes[2].plot(qx, lows, "v:", color=f"C{g}", label=label + ", lowest case")
    for ax, (bar, name) in zip(axes, panels):
        ax.axhline(bar, color="grey", ls="--", lw=1)
        ax.set_xlabel("whole build (minutes, 2 cores)")
        ax.set_ylabel(name)
        ax.grid(alpha=0.3)
    axes[-1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "build_budget.png"), dpi=90)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--ddg", default=os.path.join(ROOT, "build", "bin", "ddg"))
    p.add_argument(
        "--volumes",
        nargs="+",
        default=["bonsai", "headsq", "chest", "mri", "neghip", "ironprot"],
    )
    p.add_argument("--budgets", nargs="+", type=float, default=[2, 10, 30])
    p.add_argument("--build-args", default="", help="ddg build options instead of --budget")
    p.add_argument("--outline-check", type=int, default=200)
    p.add_argument(
        "--sheet-budget",
        type=float,
        default=10,
        help="the budget whose outline sheets are written",
    )
    p.add_argument("--work", default="/tmp/ddg_build_budget")
    p.add_argument("--out", default=os.path.join(ROOT, "Documentation", "Results", "build_budget"))
    p.add_argument("--render-only", action="store_true")
    p.add_argument("--suite", nargs="*", default=[], help="make_suite.py folders to query")
    p.add_argument("--pvpython", default="/usr/bin/pvpython")
    args = p.parse_args()
    os.makedirs(args.out, exist_ok=True)
    os.makedirs(args.work, exist_ok=True)
    path = os.path.join(args.out, "build_budget.json")
    results = json.load(open(path)) if os.path.exists(path) else []
    if not args.render_only:
        for volume in args.volumes:
            for budget in args.budgets:
                entry = run_one(args, volume, budget)
                print(json.dumps(entry), flush=True)
                key = (volume, budget, entry["options"])
                results = [
                    e for e in results if (e["volume"], e["budget_minutes"], e["options"]) != key
                ] + [entry]
                with open(path, "w") as f:
                    json.dump(results, f, indent=1)
    render(args.out, results)
    print("wrote", os.path.join(args.out, "build_budget.md"))


if __name__ == "__main__":
    sys.exit(main())
