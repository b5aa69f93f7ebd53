#!/usr/bin/env python3
"""report_render.py: the report's charts and report.md, from report.json (no measuring).

    /usr/bin/python3 Testing/Benchmarks/report_render.py [--out DIR] [--json REPORT_JSON]

Reads REPORT_JSON (default DIR/report.json; DIR: Documentation/Results), the model confirmations
(DIR's and the committed ones) and the shipped bundles; writes DIR/report.md and report_*.png
(methods, stability, optimisation, tf_resolution, renderer, models). report.py calls it too.
"""
import argparse
import math
import os

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from report_common import (  # noqa: E402
    DIRECT,
    EXACT_VIEW_METHODS,
    MATCH,
    METHODS,
    NEAREST,
    NEURAL,
    PRIMITIVE_FIT,
    PRIMITIVES,
    QUERY,
    QUERY_MATCH,
    REFINE,
    RESULTS,
    STABLE_METHODS,
    TWO_VIEW,
    log,
    read_report,
    report_json,
)
from report_models import models_markdown, plot_models, table  # noqa: E402

COLORS = {
    NEAREST: "tab:gray",
    NEURAL: "tab:brown",
    QUERY: "tab:purple",
    REFINE: "tab:red",
    DIRECT: "tab:blue",
    PRIMITIVE_FIT: "tab:orange",
    TWO_VIEW: "tab:green",
    MATCH: "tab:cyan",
    QUERY_MATCH: "tab:pink",
}
MARKERS = {m: k for m, k in zip(METHODS, "o^vsDPX*h")}

# advice for a screenshot problem where no measured method held (not measured by this report);
# where another method held, the table names it and its measured rate instead
CAMERA = "give the screenshot's camera: ParaView's camera when it was taken, as `--view`"
AS_SAVED = "use the screenshot as ParaView saved it, without colour management"
REMEDIES = {
    "viewpoint (deg)": CAMERA,
    "zoom (x)": CAMERA,
    "roll (deg)": CAMERA,
    "pan (view heights)": CAMERA,
    "crop (fraction)": "use the uncropped screenshot (its border shows the background)",
    "noise (sigma, grey levels)": "a screenshot without the noise (PNG as ParaView saved it)",
    "gamma": AS_SAVED,
    "colour shift (warm, x)": AS_SAVED,
    "wrong background": "`--background` with the screenshot's background colour",
    "background (view gives it)": "`--background` with the screenshot's background colour",
    "annotation": "`--mask` over the annotations",
    "shading (lit render)": "take the screenshot with the volume's Shade off",
    "another volume's screenshot": "none: the TF of another volume's picture is not this volume's",
}


# --- charts ---------------------------------------------------------------------------------------


def plot_methods(results, out):
    cases = results["cases"]
    fig, axes = plt.subplots(len(cases), 2, figsize=(11, 4.2 * len(cases)), squeeze=False)
    for i, volume in enumerate(cases):
        rows = cases[volume]["methods"]
        for j, key in enumerate(("psnr", "psnr_unseen")):
            ax = axes[i][j]
            for method, color in COLORS.items():
                pts = sorted((r["seconds"], r[key]) for r in rows if r["method"] == method)
                if pts:
                    ax.plot(
                        *zip(*pts),
                        "-" if len(pts) > 1 else "",
                        marker=MARKERS[method],
                        color=color,
                        label=method,
                    )
            ax.set_xscale("log")
            ax.set_xlabel("time on 2 cores (s, log)")
            ax.set_ylabel("PSNR of ParaView's render (dB)")
            ax.set_title(f"{volume}: {'reference view' if j == 0 else 'unseen view'}")
            ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "report_methods.png"), dpi=110)


def stable_methods(results):
    """The methods of the stability section that report.json holds rows of, in the charts' order."""
    cases = results["cases"]
    ran = {r["method"] for v in cases for r in cases[v]["stability"]}
    return [m for m in STABLE_METHODS if m in ran]


def plot_stability(results, out):
    cases = results["cases"]
    stable = stable_methods(results)
    rows = [r for v in cases for r in cases[v]["stability"]]
    kinds = list(dict.fromkeys(r["perturbation"] for r in rows))
    rows_of_charts = int(math.ceil(len(kinds) / 4))
    fig, axes = plt.subplots(rows_of_charts, 4, figsize=(16, 3.3 * rows_of_charts), squeeze=False)
    for k, kind in enumerate(kinds):
        ax = axes[k // 4][k % 4]
        labels = {r["strength"]: r["label"] for r in rows if r["perturbation"] == kind}
        xs = sorted(labels)
        for q, method in enumerate(stable):
            pts = {}
            for r in rows:
                if r["perturbation"] == kind and r["method"] == method:
                    pts.setdefault(r["strength"], []).append(r["success"])
            if not pts:
                continue
            shift = (q - (len(stable) - 1) / 2) * 0.06  # equal rates stay visible
            ax.plot(
                [xs.index(x) + shift for x in sorted(pts)],
                [np.mean(pts[x]) + shift / 3 for x in sorted(pts)],
                "-",
                marker=MARKERS[method],
                color=COLORS[method],
                label=method,
                alpha=0.85,
            )
        ax.set_xticks(range(len(xs)))
        ax.set_xticklabels([labels[x] for x in xs], fontsize=7)
        ax.set_ylim(-0.05, 1.05)
        ax.set_title(kind, fontsize=9)
        ax.set_ylabel("success rate", fontsize=8)
    for k in range(len(kinds), axes.size):
        axes[k // 4][k % 4].axis("off")
    axes[0][0].legend(fontsize=7)
    fig.suptitle(
        f"success = ParaView's render at the reference view within {results['success_db']:.0f} dB "
        "of the reference (lines shifted slightly so that equal rates stay visible)"
    )
    fig.tight_layout()
    fig.savefig(os.path.join(out, "report_stability.png"), dpi=110)


def plot_optimisation(results, out):
    runs, rates = (
        results["optimisation"]["random_starts"],
        results["optimisation"]["learning_rates"],
    )
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    axes[0].hist([r["psnr"] for r in runs if r["finite"]], bins=10, color="tab:blue")
    axes[0].set_xlabel("PSNR after 300 steps (dB)")
    axes[0].set_title(f"{len(runs)} random initial TFs and seeds (Tooth)")
    axes[1].plot([r["lr"] for r in rates], [r["psnr"] for r in rates], "o-")
    axes[1].set_xscale("log")
    axes[1].set_xlabel("Adam learning rate (logit space, log)")
    axes[1].set_ylabel("PSNR (dB)")
    axes[1].set_title("learning-rate sensitivity (Tooth, 300 steps)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "report_optimisation.png"), dpi=110)


def plot_tf_resolution(results, out):
    resolution = results["tf_resolution"]
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    for smooth in sorted({r["smoothness"] for r in resolution}):
        pts = [r for r in resolution if r["smoothness"] == smooth]
        label = f"smoothness {smooth}"
        axes[0].plot([r["bins"] for r in pts], [r["psnr_unseen"] for r in pts], "o-", label=label)
        axes[1].plot([r["bins"] for r in pts], [r["seconds"] for r in pts], "o-", label=label)
    for ax, label in zip(axes, ("PSNR at the unseen view (dB)", "time (s)")):
        ax.set_xscale("log", base=2)
        ax.set_xlabel("TF bins")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "report_tf_resolution.png"), dpi=110)


def plot_renderer(results, out):
    renderer = results["renderer"]
    samples, sample_size = results["renderer_samples"]["rows"], results["renderer_samples"]["size"]
    ours, adjoint = "ours, forward (block skipping)", "ours, forward + adjoint"
    vtk = "VTK FixedPointVolumeRayCastMapper"
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4))
    sizes = [r["size"] ** 2 for r in renderer]
    ax.plot(sizes, [r["ours_ms"] for r in renderer], "o-", label=ours)
    ax.plot(sizes, [r["forward_backward_ms"] for r in renderer], "o-", label=adjoint)
    ax.plot(sizes, [r["vtk_ms"] for r in renderer], "o-", label=vtk)
    tp = [
        (s, r["torch_forward_backward_ms"])
        for s, r in zip(sizes, renderer)
        if r.get("torch_forward_backward_ms")
    ]
    if tp:
        ax.plot(*zip(*tp), "o-", label="PyTorch autograd, forward + backward")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("pixels (Engine, engine_block, 2 samples per voxel)")
    ax.set_ylabel("ms on 2 cores")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    spv = [r["samples_per_voxel"] for r in samples]
    ax2.plot(spv, [r["ours_ms"] for r in samples], "o-", label=ours)
    ax2.plot(spv, [r["forward_backward_ms"] for r in samples], "o-", label=adjoint)
    ax2.plot(spv, [r["vtk_ms"] for r in samples], "o-", label=vtk)
    ax2.set_xscale("log", base=2)
    ax2.set_yscale("log")
    ax2.set_xlabel(f"samples per voxel (Engine, {sample_size}^2; ParaView's rule: 2)")
    ax2.set_ylabel("ms on 2 cores")
    ax2.legend(fontsize=7)
    ax2.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "report_renderer.png"), dpi=110)


def charts(results, out):
    """Every chart of the report into `out`."""
    plot_methods(results, out)
    plot_stability(results, out)
    plot_optimisation(results, out)
    plot_tf_resolution(results, out)
    plot_renderer(results, out)
    if results["models"]:
        plot_models(results["models"], out)


# --- report.md ------------------------------------------------------------------------------------


def method_guide(results):
    """Markdown table: per perturbation kind, each method's success rate on the perturbed cases, the
    one to use (among the methods that ran on every perturbed case: the highest success, then mean
    PSNR), how far it held, where it broke and, beyond that, the method that held where it broke
    (measured) or, where none did, advice (REMEDIES, not measured)."""
    cases = results["cases"]
    methods = stable_methods(results)
    kinds = list(dict.fromkeys(r["perturbation"] for v in cases for r in cases[v]["stability"]))
    rows = []
    for kind in kinds:
        perturbed = [
            (v, r)
            for v in cases
            for r in cases[v]["stability"]
            if r["perturbation"] == kind and r["strength"] != 0
        ]
        if not perturbed:
            continue
        every = {(v, r["strength"]) for v, r in perturbed}
        ran = {m: [(v, r) for v, r in perturbed if r["method"] == m] for m in methods}
        stats = {
            m: (np.mean([r["success"] for _, r in ran[m]]), np.mean([r["psnr"] for _, r in ran[m]]))
            for m in methods
            if ran[m]
        }
        full = [m for m in stats if {(v, r["strength"]) for v, r in ran[m]} == every]
        use = max(full, key=lambda m: stats[m])
        held, broke, failed = "-", "-", set()
        for strength in sorted({r["strength"] for _, r in perturbed}):
            mine = [(v, r) for v, r in ran[use] if r["strength"] == strength]
            if all(r["success"] for _, r in mine):
                held = mine[0][1]["label"]
            else:
                broke = mine[0][1]["label"]
                failed = {(v, r["strength"]) for v, r in ran[use] if r["strength"] >= strength}
                failed -= {(v, r["strength"]) for v, r in ran[use] if r["success"]}
                break
        beyond = "-"
        if failed:
            tried = {
                m: [r["success"] for v, r in ran[m] if (v, r["strength"]) in failed]
                for m in stats
                if m != use
            }
            alt = max(tried, key=lambda m: (sum(tried[m]), -len(tried[m])), default=None)
            if alt and sum(tried[alt]):
                beyond = f"{alt}: {sum(tried[alt])} of its {len(tried[alt])} there succeed"
            elif kind in REMEDIES:
                beyond = REMEDIES[kind] + " (not measured)"
        cell = lambda m: (  # noqa: E731
            "-"
            if m not in stats
            else f"{100 * stats[m][0]:.0f} %" + ("" if m in full else f" ({len(ran[m])} cases)")
        )
        rows.append(
            [kind]
            + [cell(m) for m in methods]
            + [use if stats[use][0] > 0 else "none succeeds", held, broke, beyond]
        )
    head = ["screenshot problem"] + methods + ["use", "withstood up to", "broke at", "beyond that"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


def confirmed_in_this_run(results):
    """Whether the measuring run went on with --confirm: report.json's "confirm". A report.json
    written before that key existed: a full run (--confirm does not go with --quick) that holds
    confirmations (the committed one of the last full run was one)."""
    if "confirm" in results:
        return results["confirm"]
    return not results["quick"] and bool(results.get("model_confirmations"))


def methods_markdown(results):
    cases = results["cases"]
    md = []
    for volume, case in cases.items():
        md += [
            f"## Screenshot -> TF: {volume} ({case['preset']})",
            "",
            "![methods](report_methods.png)",
            "",
            table(
                case["methods"],
                [
                    ("method", lambda r: r["method"]),
                    ("iterations", lambda r: str(r["budget"] or "-")),
                    ("time s", lambda r: f"{r['seconds']:.2f}"),
                    ("PSNR ref", lambda r: f"{r['psnr']:.2f}"),
                    ("SSIM ref", lambda r: f"{r['ssim']:.4f}"),
                    ("PSNR unseen", lambda r: f"{r['psnr_unseen']:.2f}"),
                    ("SSIM unseen", lambda r: f"{r['ssim_unseen']:.4f}"),
                ],
            ),
            "",
        ]
    neural = any(r["method"] == NEURAL for case in cases.values() for r in case["methods"])
    md += [
        "(b), the paper's neural path, needs a U-Net bundle: in the full run the model sweep's Tooth "
        "U-Net (1.5 min of training, a 2000-design outline); the shipped models are decoders, whose "
        "render at a view is the ray cast of their decoded TF, so for them (b) is (b') + "
        "reconstruction. "
        + ("" if neural else "This run has no U-Net (quick run): (b) is not measured. ")
        + f"(d) fits {PRIMITIVES} Gaussian primitives (mean, width, colour, peak opacity each) "
        "through the same renderer adjoint.",
        "",
    ]
    return md


def stability_markdown(results):
    cases = results["cases"]
    methods = stable_methods(results)
    seconds = lambda r: f"{r['seconds']:.1f}" if "seconds" in r else "-"  # noqa: E731

    def refusal(r):
        """The reason `ddg` gave ("... error: REASON"), "yes" when the row holds none (a report.json
        that recorded the command instead), "-" when it did not refuse."""
        if not r["error"]:
            return "-"
        reason = r["error"].split(" error: ", 1)
        return reason[1].replace("|", "/") if len(reason) == 2 else "yes"

    md = ["## Stability: where each method breaks", "", "![stability](report_stability.png)", ""]
    if MATCH in methods:
        md += [
            f"{MATCH} is `ddg reconstruct` without `--view`, started from grey: it estimates the "
            "background (uniform or ParaView's gradient), masks overlays and estimates the camera "
            "(azimuth, elevation, roll, distance, pan from ParaView's reset camera) before fitting "
            f"the TF. {QUERY_MATCH} starts it from the query's TF"
            + (
                " (on the unperturbed screenshot and the strongest of each kind only)"
                if QUERY_MATCH in methods
                else ""
            )
            + ". The other methods get the reference view's file (camera and white background) "
            "whatever the perturbation; in *background (view gives it)* their view file has the "
            "screenshot's background (the gradient as `background2`), the match is told nothing. "
            "Time: the `ddg` commands' wall-clock, as in the methods section.",
            "",
        ]
    fails = {}
    for volume in cases:
        st = cases[volume]["stability"]
        md += [
            f"### {volume}",
            "",
            table(
                st,
                [
                    ("perturbation", lambda r: r["perturbation"]),
                    ("strength", lambda r: r["label"]),
                    ("method", lambda r: r["method"]),
                    ("PSNR", lambda r: f"{r['psnr']:.1f}"),
                    ("success", lambda r: "yes" if r["success"] else "no"),
                    ("time s", seconds),
                    ("refused", refusal),
                ],
            ),
            "",
        ]
        for r in st:
            if not r["success"]:
                fails.setdefault((r["perturbation"], r["method"]), []).append(
                    f"{volume} {r['label']}"
                )
    md += ["Failures seen (perturbation, method: cases):", ""]
    md += [f"- {k[0]}, {k[1]}: {', '.join(v)}" for k, v in sorted(fails.items())] or ["- none"]
    ran = {
        m: [r for v in cases for r in cases[v]["stability"] if r["method"] == m] for m in methods
    }
    rate = {m: np.mean([r["success"] for r in ran[m]]) for m in methods}
    everywhere = [m for m in methods if len(ran[m]) == max(len(x) for x in ran.values())]
    best = max(everywhere, key=rate.get)
    timed = {m: [r["seconds"] for r in ran[m] if r.get("seconds")] for m in methods}
    md += [
        "",
        "Success rate over all perturbations (the cases each method ran on): "
        + ", ".join(
            f"{m} {100 * rate[m]:.0f} % of {len(ran[m])}"
            + (
                f" ({refused} refused)"
                if (refused := sum(bool(r["error"]) for r in ran[m]))
                else ""
            )
            for m in methods
        )
        + f". Most robust of the methods run on every case: {best}.",
        "",
    ]
    if any(timed.values()):
        md += [
            "Time per case (median, min-max, s): "
            + ", ".join(
                f"{m} {np.median(t):.1f} ({min(t):.1f}-{max(t):.1f})" for m, t in timed.items() if t
            )
            + ".",
            "",
        ]
    md += [
        "### Which method to use when",
        "",
        "Per kind of screenshot problem, over its perturbed cases on "
        + " and ".join(cases)
        + ": each method's success rate (with its number of cases where it did not run on all), "
        "the method to use (of those that ran on all: highest success, then mean PSNR), the "
        "strongest perturbation it withstood on every volume and the first it did not. The last "
        "column is what held where it broke: another method's measured successes there, or, "
        "where none held, advice (not measured here).",
        "",
        method_guide(results),
        "",
    ]
    return md


def optimisation_markdown(results):
    runs, rates = (
        results["optimisation"]["random_starts"],
        results["optimisation"]["learning_rates"],
    )
    psnrs = [r["psnr"] for r in runs]
    return [
        "## Optimisation",
        "",
        "![optimisation](report_optimisation.png)",
        "",
        f"{len(runs)} random initial TFs with their own pixel-sampling seeds, 300 steps: PSNR "
        f"{np.nanmin(psnrs):.2f}..{np.nanmax(psnrs):.2f} dB (median {np.nanmedian(psnrs):.2f}), "
        f"non-finite results: {sum(not r['finite'] for r in runs)}.",
        "",
        table(
            rates,
            [
                ("learning rate", lambda r: f"{r['lr']}"),
                ("PSNR", lambda r: f"{r['psnr']:.2f}"),
                ("time s", lambda r: f"{r['seconds']:.2f}"),
            ],
        ),
        "",
        "## TF resolution and smoothness prior (Tooth, 300 steps)",
        "",
        "![resolution](report_tf_resolution.png)",
        "",
        table(
            results["tf_resolution"],
            [
                ("bins", lambda r: str(r["bins"])),
                ("smoothness", lambda r: str(r["smoothness"])),
                ("PSNR ref", lambda r: f"{r['psnr']:.2f}"),
                ("PSNR unseen", lambda r: f"{r['psnr_unseen']:.2f}"),
                ("time s", lambda r: f"{r['seconds']:.2f}"),
            ],
        ),
        "",
    ]


def renderer_markdown(results):
    torch_ms = lambda r: (  # noqa: E731
        f"{r['torch_forward_backward_ms']:.1f}" if r.get("torch_forward_backward_ms") else "-"
    )
    return [
        "## Renderer (Engine, engine_block)",
        "",
        "![renderer](report_renderer.png)",
        "",
        table(
            results["renderer"],
            [
                ("size", lambda r: f"{r['size']}^2"),
                ("ours ms", lambda r: f"{r['ours_ms']:.1f}"),
                ("VTK ms", lambda r: f"{r['vtk_ms']:.1f}"),
                ("ours fwd+adjoint ms", lambda r: f"{r['forward_backward_ms']:.1f}"),
                ("PyTorch autograd ms", torch_ms),
            ],
        ),
        "",
        "Samples per voxel (sample distance = mean spacing / S), "
        f"{results['renderer_samples']['size']}^2:",
        "",
        table(
            results["renderer_samples"]["rows"],
            [
                ("samples/voxel", lambda r: f"{r['samples_per_voxel']:g}"),
                ("ours ms", lambda r: f"{r['ours_ms']:.1f}"),
                ("VTK ms", lambda r: f"{r['vtk_ms']:.1f}"),
                ("ours fwd+adjoint ms", lambda r: f"{r['forward_backward_ms']:.1f}"),
            ],
        ),
        "",
    ]


def markdown(results, out):
    """report.md's text: the measured `results` (report.json's content) and, for the model
    section, the confirmations recorded in `out` or committed."""
    quick = " --quick" if results["quick"] else ""
    md = [
        f"# Speed against accuracy, stability, model size{' (quick run)' if quick else ''}",
        "",
        f"Produced by `Testing/Benchmarks/report.py{quick}` on 2 cores in {results['minutes']:.1f} min"
        + (f" at commit {results['commit']}" if results.get("commit") else "")
        + (
            " (before --confirm, whose time is in its section)"
            if confirmed_in_this_run(results)
            else ""
        )
        + ". Raw numbers: `report.json`.",
        "",
        "Minutes per section: "
        + ", ".join(f"{name} {m:.1f}" for name, m in results["section_minutes"].items())
        + ".",
        "",
    ]
    for rerun in results.get("reruns", []):
        mach = rerun["machine"]
        md += [
            f"Re-measured on {rerun['date']}"
            + (f" at commit {rerun['commit']}" if rerun.get("commit") else "")
            + f" with `report.py{quick} --sections "
            f"{' '.join(rerun['sections'])}` in {rerun['minutes']:.1f} min ("
            + ", ".join(f"{name} {m:.1f}" for name, m in rerun["section_minutes"].items())
            + f"): the {', '.join(rerun['sections'])} section(s) below; the others are from the "
            f"run above. Machine: {mach['cpu']}, {mach['cores']} cores shared with other jobs "
            f"(load average {mach['load_average']:.1f} at the start, "
            f"{mach['load_average_end']:.1f} at the end), so its times are upper bounds.",
            "",
        ]
    md += methods_markdown(results)
    md += stability_markdown(results)
    md += optimisation_markdown(results)
    md += renderer_markdown(results)
    md += models_markdown(results["models"], out)
    return "\n".join(md) + "\n"


def write_markdown(results, out):
    with open(os.path.join(out, "report.md"), "w") as f:
        f.write(markdown(results, out))


def render(out, json_path=None):
    """report.md and the charts in `out` from report.json (`json_path`, default out's)."""
    json_path = json_path or report_json(out)
    results = read_report(json_path)
    charts(results, out)
    write_markdown(results, out)
    log(f"wrote {out}/report.md and the report_*.png charts from {json_path}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=RESULTS, help="where report.md and the charts go")
    parser.add_argument("--json", help="the report.json to render (default: OUT/report.json)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    render(args.out, args.json)


if __name__ == "__main__":
    main()
