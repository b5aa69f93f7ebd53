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


def run_one(args, volume, budget):
    vol = os.path.join(ROOT, "Data", "Volumes", volume + ".vti")
    bundle = os.path.join(args.work, f"{volume}_{budget:g}min")
    if os.path.exists(bundle):
        subprocess.run(["rm", "-rf", bundle], check=True)
    options = shlex.split(args.build_args) if args.build_args else ["--budget", f"{budget:g}"]
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
        }
    )
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
        r"outline: (\d+) of (\d+) designs .*?: (\d+) empty, (\d+) flat box .*?; " r"(\d+) give", out
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
        "| volume | budget (min) | build (min) | exemplars | training (min), iterations, "
        "image-loss rays | held-out PSNR (dB) | SSIM | outline: empty + flat box of checked | "
        "boundary faces hazy |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for e in rows:
        if "error" in e:
            lines.append(
                f"| {e['volume']} | {e['budget_minutes']:g} | {e['build_minutes']} | "
                f"failed: {e['error'][:80]} | | | | | |"
            )
            continue
        junk = e.get("outline_empty", 0) + e.get("outline_flat_box", 0)
        lines.append(
            f"| {e['volume']} | {e['budget_minutes']:g} | {e['build_minutes']:.1f} | "
            f"{e.get('exemplars') or '—'} | {e['train_minutes']:.1f}, "
            f"{e.get('train_iterations', '—')}, {e.get('image_rays', 512)} | "
            f"{e['psnr']:.2f} | {e['ssim']:.3f} | "
            f"{junk} of {e.get('outline_checked', 0)} ({e.get('outline_empty', 0)} empty, "
            f"{e.get('outline_flat_box', 0)} flat box) | {e.get('outline_hazy_faces', 0)} |"
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
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for volume in sorted({e["volume"] for e in rows}):
        pts = [e for e in rows if e["volume"] == volume and "psnr" in e]
        xs = [e["build_minutes"] for e in pts]
        axes[0].plot(xs, [e["psnr"] for e in pts], "o-", label=volume)
        axes[1].plot(xs, [e["ssim"] for e in pts], "o-", label=volume)
    for ax, bar, name in ((axes[0], 28, "held-out PSNR (dB)"), (axes[1], 0.9, "held-out SSIM")):
        ax.axhline(bar, color="grey", ls="--", lw=1)
        ax.set_xlabel("whole build (minutes, 2 cores)")
        ax.set_ylabel(name)
        ax.grid(alpha=0.3)
    axes[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "build_budget.png"), dpi=90)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--ddg", default=os.path.join(ROOT, "build", "bin", "ddg"))
    p.add_argument(
        "--volumes", nargs="+", default=["bonsai", "headsq", "chest", "mri", "neghip", "ironprot"]
    )
    p.add_argument("--budgets", nargs="+", type=float, default=[2, 10, 30])
    p.add_argument("--build-args", default="", help="ddg build options instead of --budget")
    p.add_argument("--outline-check", type=int, default=200)
    p.add_argument(
        "--sheet-budget", type=float, default=10, help="the budget whose outline sheets are written"
    )
    p.add_argument("--work", default="/tmp/ddg_build_budget")
    p.add_argument("--out", default=os.path.join(ROOT, "Documentation", "Results", "build_budget"))
    p.add_argument("--render-only", action="store_true")
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
                results = [
                    e for e in results if (e["volume"], e["budget_minutes"]) != (volume, budget)
                ] + [entry]
                with open(path, "w") as f:
                    json.dump(results, f, indent=1)
    render(args.out, results)
    print("wrote", os.path.join(args.out, "build_budget.md"))


if __name__ == "__main__":
    sys.exit(main())
