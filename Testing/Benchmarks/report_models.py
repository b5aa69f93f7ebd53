"""report_models.py: the report's model-size section: the sweep tables (model_sweep.py), which
model suffices, the candidate a confirmation trains (Testing/Models/confirm.py), the chart and
the text.
"""
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from report_common import ROOT, RESULTS, log  # noqa: E402

sys.path.insert(0, os.path.join(ROOT, "Testing", "Models"))
import confirm  # noqa: E402
from confirm import SUFFICES_DB, SUFFICES_SSIM  # noqa: E402

SWEEPS = [
    ("tooth", None),
    ("engine", [0, 1, 2]),
]  # Engine: the three decoder widths at 64 px (time budget)
VOLUMES = [v for v, _ in SWEEPS]


def sweep_md(volume, out):
    return os.path.join(out, f"model_sweep_{volume}.md")


def read_sweeps(out):
    """The rows of model_sweep.py's tables in `out`, one per configuration and volume (the
    committed tables of the last full run when `out` has none of its own)."""
    models = []
    for volume in VOLUMES:
        md_path = sweep_md(volume, out)
        if not os.path.exists(md_path):
            md_path = sweep_md(volume, RESULTS)
        if not os.path.exists(md_path):
            continue
        for line in open(md_path):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if len(cells) >= 15 and re.match(r"^[\d.]+$", cells[1] or "x"):
                models.append(
                    {
                        "volume": volume,
                        "kind": cells[0],
                        "width": int(cells[1]),
                        "image": int(cells[2]),
                        "parameters": int(cells[3]),
                        "analyzer_ms": float(cells[8]),
                        "renderer_ms": float(cells[9]),
                        "psnr": float(cells[10]),
                        "ssim": float(cells[11]),
                        "emd": float(cells[12]),
                        "minutes": float(cells[14]),
                    }
                )
    return models


def is_shipped(m):
    return m["kind"].startswith("decoder (image") and m["width"] == 16 and m["image"] == 64


def reference_model(rows):
    """The scene's best model: the highest PSNR among the models within SUFFICES_SSIM of the best
    SSIM (the best PSNR and the best SSIM can belong to different models)."""
    best_ssim = max(r["ssim"] for r in rows)
    return max((r for r in rows if r["ssim"] >= best_ssim - SUFFICES_SSIM), key=lambda r: r["psnr"])


def smallest_sufficient(rows):
    """The fewest parameters within SUFFICES_DB and SUFFICES_SSIM of the reference model (which is
    one of them)."""
    ref = reference_model(rows)
    enough = [
        r
        for r in rows
        if r["psnr"] >= ref["psnr"] - SUFFICES_DB and r["ssim"] >= ref["ssim"] - SUFFICES_SSIM
    ]
    return min(enough, key=lambda r: r["parameters"])


def confirm_candidate(rows):
    """The model --confirm trains with the shipped recipe for a scene's sweep rows: the smallest
    sufficient one when it is smaller than the shipped one; otherwise the next smaller model of the
    shipped kind and image size (whether the shipped one is the smallest that suffices at full
    training, the sweep's 1.5 min being short and noisy). None without a shipped row or a smaller one.
    """
    shipped = [m for m in rows if is_shipped(m)]
    if not shipped or confirm.shipped_bundle(rows[0]["volume"]) is None:
        return None
    small = smallest_sufficient(rows)
    if small["parameters"] < shipped[0]["parameters"]:
        return small
    smaller = [
        m
        for m in rows
        if (m["kind"], m["image"]) == (shipped[0]["kind"], shipped[0]["image"])
        and m["parameters"] < shipped[0]["parameters"]
    ]
    return max(smaller, key=lambda m: m["parameters"]) if smaller else None


def run_confirmations(models, out, ddg, work):
    """--confirm: trains each scene's confirm_candidate with the shipped recipe
    (model_confirm_VOLUME.json in `out`)."""
    for volume in VOLUMES:
        candidate = confirm_candidate([m for m in models if m["volume"] == volume])
        if candidate is not None:
            confirm.confirm(volume, candidate, out, ddg, work, log)


def confirmations(models, out):
    """The recorded confirmations of each scene's candidate, with their verdict (report.json)."""
    found = []
    for volume in VOLUMES:
        rows = [m for m in models if m["volume"] == volume]
        candidate = confirm_candidate(rows) if rows else None
        c = confirm.read_confirmation(volume, candidate, out, log) if candidate else None
        if c is not None:
            found.append(dict(c, suffices=confirm.confirmation_verdict(c)[0]))
    return found


# --- the chart and the text -----------------------------------------------------------------------


def plot_models(models, out):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for volume, color in zip(VOLUMES, ("tab:blue", "tab:red")):
        rows = [m for m in models if m["volume"] == volume]
        if not rows:
            continue
        small = smallest_sufficient(rows)
        for m in rows:
            label = f"{m['kind'].replace(' (image loss)', '')} w{m['width']} {m['image']}px"
            label += " (shipped)" if is_shipped(m) else ""
            label += " (smallest sufficient)" if m is small and not is_shipped(m) else ""
            ms = m["analyzer_ms"] + m["renderer_ms"]
            axes[0].scatter(
                ms,
                m["psnr"],
                s=30 + m["parameters"] / 2e4,
                color=color,
                marker="*" if is_shipped(m) else "o",
                label=volume if m is rows[0] else None,
            )
            axes[0].annotate(label, (ms, m["psnr"]), fontsize=6)
            axes[1].scatter(
                m["parameters"],
                m["ssim"],
                color=color,
                marker="*" if is_shipped(m) else "o",
                label=volume if m is rows[0] else None,
            )
            axes[1].annotate(label, (m["parameters"], m["ssim"]), fontsize=6)
    axes[0].set_xlabel("analyzer + renderer ms (one image)")
    axes[0].set_ylabel("held-out PSNR (dB)")
    axes[1].set_xscale("log")
    axes[1].set_xlabel("parameters")
    axes[1].set_ylabel("held-out SSIM")
    for ax in axes:
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    fig.suptitle(
        "model kind and size, equal training time (1.5 min each; star: shipped configuration; "
        f"sufficient: within {SUFFICES_DB:g} dB and {SUFFICES_SSIM:g} SSIM of the scene's best)",
        fontsize=10,
    )
    fig.tight_layout()
    fig.savefig(os.path.join(out, "report_models.png"), dpi=110)


def who(c):
    return f"{c['kind'].capitalize()}, width {c['width']}, {c['image']} px"


def confirmation_text(volume, candidate, out):
    """What the full-recipe training of `candidate` says about the shipped choice."""
    c = confirm.read_confirmation(volume, candidate, out, log)
    if c is None:
        return (
            f"  {who(candidate)} is not yet trained with the shipped recipe: `report.py --models-only "
            f"--confirm` does it and says whether it would replace the shipped bundle."
        )
    a, s = c["candidate"], c["shipped"]
    ok, meets_bar, close = confirm.confirmation_verdict(c)
    if a["train_iterations"] < c["iterations"]:  # train_model.sh's 30-minute cap stopped it
        return (
            f"  {who(c)}, trained with the shipped recipe (`{c['command']}`), stopped at "
            f"{a['train_iterations']} of {c['iterations']} steps (the 30-minute cap): no verdict."
        )
    text = (
        f"  {who(c)}, trained with the shipped recipe (`{c['command']}`: {c['exemplars']} exemplars, "
        f"{a['train_iterations']} steps, {a['train_seconds'] / 60:.1f} min of training), on the same "
        f"{a['heldout_count']} held-out exemplars"
        + (f" ({c['image']} px, the shipped bundle's are 64 px)" if c["image"] != 64 else "")
        + f": {a['psnr']:.2f} dB / SSIM {a['ssim']:.4f} / EMD {a['emd']:.2f} / invariance "
        f"{a['invariance']:.3f}, against the shipped bundle's {s['psnr']:.2f} dB / {s['ssim']:.4f} / "
        f"{s['emd']:.2f} / {s['invariance']:.3f} ({s['train_seconds'] / 60:.1f} min of training on the "
        f"machine that trained it): {a['psnr'] - s['psnr']:+.2f} dB, {a['ssim'] - s['ssim']:+.4f} SSIM "
        f"(`--confirm` took {c['wall_minutes']:.1f} min; latencies: the sweep table, one machine). "
    )
    if ok:
        text += "It suffices at full training: the smaller model should be shipped."
    else:
        why = []
        if not close:
            why.append(
                f"more than {SUFFICES_DB:g} dB or {SUFFICES_SSIM:g} SSIM below the shipped bundle"
            )
        if not meets_bar:
            why.append(
                f"below the shipped models' bar (PSNR {confirm.BAR_PSNR:g} dB, SSIM "
                f"{confirm.BAR_SSIM:g}, invariance {confirm.BAR_INVARIANCE:g})"
            )
        text += (
            "With full training it is "
            + " and ".join(why)
            + ", so the shipped configuration is the smallest that "
            "suffices for this scene."
        )
    return text


def shipped_text(models, out):
    """Per scene: where the shipped configuration (decoder, image loss, width 16, 64 px) stands in the sweep, and
    the smallest model within SUFFICES_DB and SUFFICES_SSIM of the best."""
    text = []
    for volume in VOLUMES:
        rows = [m for m in models if m["volume"] == volume]
        if not rows:
            continue
        best, small = reference_model(rows), smallest_sufficient(rows)
        shipped = [m for m in rows if is_shipped(m)]
        line = (
            f"{volume}: best {best['psnr']:.2f} dB / SSIM {best['ssim']:.3f} ({best['kind']}, width "
            f"{best['width']}, {best['image']} px; the highest PSNR within {SUFFICES_SSIM:g} of the best SSIM)"
        )
        if shipped:
            s = shipped[0]
            line += f"; shipped width 16, 64 px: {s['psnr']:.2f} dB / SSIM {s['ssim']:.3f}, {s['parameters']} parameters"
        line += (
            f"; smallest within {SUFFICES_DB:g} dB and {SUFFICES_SSIM:g} SSIM of the best: {small['kind']}, width {small['width']}, "
            f"{small['image']} px, {small['parameters']} parameters"
        )
        if shipped and small is shipped[0]:
            line += " -- the shipped one."
        elif shipped and small["parameters"] < shipped[0]["parameters"]:
            line += (
                f" -- {shipped[0]['parameters'] / small['parameters']:.1f}x fewer parameters than shipped would "
                f"suffice at this training time."
            )
        elif shipped:
            line += " -- larger than the shipped one, which falls short of this sweep's best."
        else:
            line += "."
        candidate = confirm_candidate(rows)  # the sufficient smaller model, else the next smaller
        if candidate is not None:
            line += "\n" + confirmation_text(volume, candidate, out)
        text.append("- " + line)
    return "\n".join(text) or "The shipped configuration is not in this sweep."


def table(rows, cols):
    """A markdown table of `rows`: `cols` = [(header, row -> cell text)]."""
    lines = ["| " + " | ".join(c for c, _ in cols) + " |", "|" + "---|" * len(cols)]
    for r in rows:
        lines.append("| " + " | ".join(f(r) for _, f in cols) + " |")
    return "\n".join(lines)


MODELS_HEADING = "## Model kind and size"


def models_markdown(models, out):
    """The model section of report.md (lines)."""
    if not models:
        return []
    return [
        f"{MODELS_HEADING} (equal training time per configuration)",
        "",
        "![models](report_models.png)",
        "",
        table(
            models,
            [
                ("volume", lambda r: r["volume"]),
                ("kind", lambda r: r["kind"]),
                ("width", lambda r: str(r["width"])),
                ("image", lambda r: str(r["image"])),
                ("parameters", lambda r: str(r["parameters"])),
                (
                    "ms (analyzer + renderer)",
                    lambda r: f"{r['analyzer_ms'] + r['renderer_ms']:.1f}",
                ),
                ("PSNR", lambda r: f"{r['psnr']:.2f}"),
                ("SSIM", lambda r: f"{r['ssim']:.3f}"),
                ("EMD", lambda r: f"{r['emd']:.2f}"),
            ],
        ),
        "",
        shipped_text(models, out),
        "",
    ]
