"""report.py: speed against accuracy, stability where methods fail, model size -- one command.

    scripts/with-xvfb.sh build/bin/pvpython Testing/Benchmarks/report.py [--quick] [--out DIR]

Writes DIR (default Documentation/Results) report.md (tables of the raw numbers, what fails and
which method to use), report.json, and the charts report_methods.png, report_stability.png,
report_optimisation.png, report_tf_resolution.png, report_renderer.png, report_models.png.
--quick (CI: Tooth only, fewer budgets, strengths and seeds) runs in a few minutes; the full run
(Tooth and Engine) in under 45 minutes on 2 cores. --confirm then trains, per scene, the smallest
sufficient model of the sweep when it is smaller than the shipped one, else the next smaller model
(width 8), with the shipped bundle's recipe (about 12 min for Tooth, 20-25 for Engine) and compares
it with the shipped bundle: the model-size verdict at full training.

What is measured. A reference: ParaView renders a shipped preset on a shipped volume at the
reference view and at an unseen view (white background, as the shipped screenshots). Each
screenshot -> TF method gets only the reference-view screenshot; the TF it returns is rendered
by ParaView at both views and compared with the references (PSNR, SSIM of `ddg compare`). Time is
the wall-clock of the method's `ddg` command (2 cores, including its process start and loading).
Methods: (a) nearest outline design (its decoded TF), (b) the paper's neural path: analyzer ->
U-Net render at the view -> reconstruction (`ddg query` on a U-Net bundle; full run, Tooth: the
model sweep's U-Net with a 2000-design outline), (b') analyzer -> TF decoder (`ddg query`), (b'+c)
that TF refined by differentiable reconstruction, (c) differentiable reconstruction from scratch,
(d) parametric fit of PRIMITIVES Gaussian primitives (`ddg reconstruct --primitives`), (e)
multi-view reconstruction (the screenshot and a second view of the same TF); (b'+c), (c), (d) and
(e) at several iteration budgets (curves). Stability: the same methods on perturbed
screenshots (viewpoint, zoom, crop, noise, JPEG, gamma, colour shift, background, annotation,
another volume, shading); success = ParaView's render at the reference view within
SUCCESS_DB of the unperturbed reference. Optimisation: random initial TFs and seeds, learning
rates. TF resolution and smoothness prior. Renderer speed (BenchRayCaster, BenchDifferentiable,
bench_torch_autograd.py). Model size (Testing/Benchmarks/model_sweep.py: every configuration on
Tooth, the three decoder widths on Engine; --quick plots the last committed tables).
"""
import argparse
import functools
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time

import numpy as np
from PIL import Image, ImageDraw

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from paraview.simple import (  # noqa: E402
    ColorBy,
    CreateView,
    GetColorTransferFunction,
    GetOpacityTransferFunction,
    Render,
    SaveScreenshot,
    Show,
    XMLImageDataReader,
)

SUCCESS_DB = 30.0
PRIMITIVES = 12
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DATA = os.path.join(ROOT, "Data")

parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("--quick", action="store_true", help="CI size: Tooth only, fewer points")
parser.add_argument("--out", default=os.path.join(ROOT, "Documentation", "Results"))
parser.add_argument("--build", default=os.path.join(ROOT, "build"))
parser.add_argument(
    "--models-only",
    action="store_true",
    help="only redraw the model-size chart and section of the report in --out from its sweep tables",
)
parser.add_argument(
    "--confirm",
    action="store_true",
    help="train, per scene, the sweep's smallest sufficient model if smaller than the shipped one, "
    "else the next smaller one, with the shipped bundle's recipe (scripts/train_model.sh; 10-25 min "
    "each) and compare it with the shipped bundle; writes model_confirm_VOLUME.json (with "
    "--models-only: only this and the model section)",
)
args = parser.parse_args()
if args.confirm and args.quick:
    parser.error(
        "--confirm trains full-size models (about 25 min each); it does not go with --quick"
    )
DDG = os.environ.get("DDG_EXE", os.path.join(args.build, "bin", "ddg"))
BIN = os.path.dirname(DDG)
os.makedirs(args.out, exist_ok=True)
work = tempfile.mkdtemp(prefix="ddg-report-")
started = time.time()
CASES = [("tooth", "tooth_dentin_enamel")] + ([] if args.quick else [("engine", "engine_block")])
BUDGETS = [30, 150] if args.quick else [10, 30, 100, 300, 1000]
results = {"quick": args.quick, "success_db": SUCCESS_DB, "cases": {}}
CASE_OBJECTS = {}  # volume -> its scene, views, references


def log(text):
    print(f"[{time.time() - started:7.1f} s] {text}", flush=True)


SECTION_STARTS = []  # (name, seconds since start)


def section(name):
    SECTION_STARTS.append((name, time.time() - started))
    log(f"section: {name}")


def section_minutes():
    """Minutes spent in each section, up to now."""
    ends = [t for _, t in SECTION_STARTS[1:]] + [time.time() - started]
    return {name: (end - t) / 60 for (name, t), end in zip(SECTION_STARTS, ends)}


def ddg(*a, check=True):
    t = time.time()
    r = subprocess.run([DDG, *map(str, a)], capture_output=True, text=True)
    if check and r.returncode != 0:
        raise RuntimeError(f"ddg {' '.join(map(str, a))}: {r.stderr.strip()}")
    return r, time.time() - t


def compare(a, b):
    r, _ = ddg("compare", a, b, "--json")
    return json.loads(r.stdout)


# --- views ------------------------------------------------------------------------------------


def load_view(volume, name):
    with open(os.path.join(DATA, "Views", f"{volume}_{name}.json")) as f:
        v = json.load(f)
    v["background"] = [1.0, 1.0, 1.0]
    return v


def rotated(view, azimuth=0.0, elevation=0.0, zoom=1.0):
    """The view's camera orbited about its focal point (degrees) and moved closer by `zoom`."""
    v = json.loads(json.dumps(view))
    c = v["camera"]
    f, p, up = (np.array(c[k], float) for k in ("focal_point", "position", "view_up"))
    d = p - f
    up = up / np.linalg.norm(up)

    def rot(x, axis, deg):
        axis = axis / np.linalg.norm(axis)
        t = math.radians(deg)
        return (
            x * math.cos(t)
            + np.cross(axis, x) * math.sin(t)
            + axis * np.dot(axis, x) * (1 - math.cos(t))
        )

    d = rot(d, up, azimuth)
    right = np.cross(d, up)
    d, up = rot(d, right, elevation), rot(up, right, elevation)
    c["position"] = list(f + d / zoom)
    c["view_up"] = list(up)
    return v


def write_json(obj, name):
    path = os.path.join(work, name)
    with open(path, "w") as f:
        json.dump(obj, f)
    return path


# --- ParaView renders -----------------------------------------------------------------------------


class ParaViewScene:
    """One ParaView render view per volume; renders a preset at a view (as pvrender.py does)."""

    def __init__(self, volume):
        self.reader = XMLImageDataReader(FileName=[os.path.join(DATA, "Volumes", volume + ".vti")])
        self.view = CreateView("RenderView")
        self.view.OrientationAxesVisibility = 0
        self.view.UseColorPaletteForBackground = 0
        self.display = Show(self.reader, self.view)
        self.array = self.reader.PointData.keys()[0]
        ColorBy(self.display, ("POINTS", self.array))
        self.display.SetRepresentationType("Volume")
        self.display.Shade = 0
        self.lut = GetColorTransferFunction(self.array)
        self.pwf = GetOpacityTransferFunction(self.array)
        self.lut.AutomaticRescaleRangeMode = "Never"
        Render(self.view)

    def render(self, preset_file, view, out, shade=False):
        with open(preset_file) as f:
            p = json.load(f)
        p = p[0] if isinstance(p, list) else p
        self.lut.ColorSpace = p.get("ColorSpace", "RGB")
        self.lut.HSVWrap = int(p.get("HSVWrap", 0))
        self.lut.RGBPoints = p["RGBPoints"]
        self.pwf.Points = p["Points"]
        self.display.Shade = int(shade)
        self.view.Background = view["background"]
        self.view.ViewSize = view["size"]
        c = view["camera"]
        self.view.CameraPosition, self.view.CameraFocalPoint = c["position"], c["focal_point"]
        self.view.CameraViewUp = c["view_up"]
        self.view.CameraViewAngle = c.get("view_angle", 30.0)
        SaveScreenshot(out, self.view, ImageResolution=view["size"], TransparentBackground=0)
        self.display.Shade = 0
        return out


# --- methods (each: screenshot + its view -> preset file, seconds) ---------------------------


def method_query(case, shot, view_file, tag):
    out = os.path.join(work, f"{tag}_query.json")
    _, s = ddg(
        "query",
        "--model",
        case["model"],
        "--volume",
        case["volume"],
        "--image",
        shot,
        "--view",
        view_file,
        "--out-tf",
        out,
    )
    return out, s


def method_nearest(case, shot, view_file, tag):
    r, s1 = ddg(
        "query",
        "--model",
        case["model"],
        "--volume",
        case["volume"],
        "--image",
        shot,
        "--view",
        view_file,
        "--neighbours",
        "1",
    )
    row = int(re.search(r"design row (\d+)", r.stdout).group(1))
    history = write_json(
        {"format": "ddg-history", "version": 1, "steps": [{"action": "pick", "row": row}]},
        f"{tag}_pick.json",
    )
    out = os.path.join(work, f"{tag}_nearest.json")
    _, s2 = ddg(
        "replay",
        "--model",
        case["model"],
        "--volume",
        case["volume"],
        "--history",
        history,
        "--view",
        view_file,
        "--out-tf",
        out,
    )
    return out, s1 + s2


def reconstruct(case, targets, views, tag, iterations, init=None, extra=()):
    out = os.path.join(work, f"{tag}.json")
    cmd = [
        "reconstruct",
        "--volume",
        case["volume"],
        "--out",
        out,
        "--iterations",
        iterations,
        "--quiet",
        *extra,
    ]
    for t, v in zip(targets, views):
        cmd += ["--target", t, "--view", v]
    if init:
        cmd += ["--init", init]
    _, s = ddg(*cmd)
    return out, s


def method_refine(case, shot, view_file, tag, iterations):
    init, s1 = method_query(case, shot, view_file, tag)
    out, s2 = reconstruct(
        case, [shot], [view_file], f"{tag}_refine{iterations}", iterations, init=init
    )
    return out, s1 + s2


def method_direct(case, shot, view_file, tag, iterations):
    return reconstruct(case, [shot], [view_file], f"{tag}_direct{iterations}", iterations)


def method_primitives(case, shot, view_file, tag, iterations):
    return reconstruct(
        case,
        [shot],
        [view_file],
        f"{tag}_prim{iterations}",
        iterations,
        extra=["--primitives", PRIMITIVES],
    )


def method_neural(case, shot, view_file, tag):
    """(b): the U-Net bundle's analyzer and renderer, then reconstruction from its render."""
    out = os.path.join(work, f"{tag}_neural.json")
    _, s = ddg(
        "query",
        "--model",
        case["unet"],
        "--volume",
        case["volume"],
        "--image",
        shot,
        "--view",
        view_file,
        "--out-tf",
        out,
    )
    return out, s


def evaluate(case, preset, tag):
    """PSNR/SSIM of ParaView's renders of `preset` against the references at both views."""
    scene = case["scene"]
    out = {}
    for which in ("reference", "unseen"):
        png = scene.render(preset, case["views"][which], os.path.join(work, f"{tag}_{which}.png"))
        m = compare(png, case["refs"][which])
        out[which] = (m["psnr"], m["ssim"])
    return out


# --- model size: the sweep tables, their chart and section (also alone: --models-only) ---------------

SWEEPS = [
    ("tooth", None),
    ("engine", [0, 1, 2]),
]  # Engine: the three decoder widths at 64 px (time budget)
sweep_mds = {v: os.path.join(args.out, f"model_sweep_{v}.md") for v, _ in SWEEPS}
# a model suffices when its held-out PSNR and SSIM are this close to the best of its scene's sweep
SUFFICES_DB, SUFFICES_SSIM = 0.5, 0.01


def read_sweeps():
    """The rows of model_sweep.py's tables, one per configuration and volume (the committed tables
    of the last full run when --quick has none of its own)."""
    models = []
    for volume, md_path in sweep_mds.items():
        if not os.path.exists(md_path):
            md_path = os.path.join(ROOT, "Documentation", "Results", os.path.basename(md_path))
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


def plot_models(models):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for volume, color in zip(sweep_mds, ("tab:blue", "tab:red")):
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
    fig.savefig(os.path.join(args.out, "report_models.png"), dpi=110)


def shipped_text(models):
    """Per scene: where the shipped configuration (decoder, image loss, width 16, 64 px) stands in the sweep, and
    the smallest model within SUFFICES_DB and SUFFICES_SSIM of the best."""
    text = []
    for volume in sweep_mds:
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
            line += "\n" + confirmation_text(volume, candidate)
        text.append("- " + line)
    return "\n".join(text) or "The shipped configuration is not in this sweep."


# issue 4's bar for a shipped bundle, on its 1000 held-out exemplars (as Testing/Models/CheckBundle.cmake)
with open(os.path.join(ROOT, "Testing", "Models", "bar.json")) as f:
    BAR = json.load(f)
BAR_PSNR, BAR_SSIM, BAR_INVARIANCE = BAR["psnr"], BAR["ssim"], BAR["invariance"]


def confirm_path(volume):
    return os.path.join(args.out, f"model_confirm_{volume}.json")


# the held-out metrics a confirmation records for the candidate and the shipped bundle
CONFIRM_KEYS = (
    "psnr",
    "ssim",
    "emd",
    "invariance",
    "heldout_count",
    "parameters",
    "analyzer_ms",
    "renderer_ms",
    "train_seconds",
    "train_iterations",
)


@functools.lru_cache(maxsize=None)
def shipped_bundle(volume):
    """The shipped bundle.json of `volume` (None when it ships no model)."""
    path = os.path.join(DATA, "Models", volume, "bundle.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def read_confirmation(volume, candidate):
    """The recorded full-recipe training of `candidate` (a sweep row), if there is one for it and
    for the current shipped bundle (same metrics and recipe); None for an unreadable record."""
    shipped = shipped_bundle(volume)
    if shipped is None:
        return None
    committed = os.path.join(ROOT, "Documentation", "Results", f"model_confirm_{volume}.json")
    for path in dict.fromkeys((confirm_path(volume), committed)):  # once when --out is the default
        if not os.path.exists(path):
            continue
        try:
            with open(path) as f:
                c = json.load(f)
            same_candidate = (c["kind"], c["width"], c["image"]) == (
                candidate["kind"],
                candidate["width"],
                candidate["image"],
            )
            same_shipped = (
                c["exemplars"] == shipped["training_exemplars"]
                and c["iterations"] == shipped["metrics"]["train_iterations"]
                and all(c["shipped"][k] == shipped["metrics"][k] for k in CONFIRM_KEYS)
            )
            if same_candidate and same_shipped:
                return c
        except (KeyError, TypeError, ValueError) as e:
            log(f"ignoring {path}: {e!r}")
    return None


def confirm(volume, candidate):
    """Trains `candidate` with the shipped bundle's recipe (exemplars, iterations, seeds, schedule:
    scripts/train_model.sh) and records its held-out metrics next to the shipped bundle's."""
    shipped = shipped_bundle(volume)
    iterations = shipped["metrics"]["train_iterations"]
    exemplars = shipped["training_exemplars"]
    weight = "100" if candidate["kind"].startswith("decoder (image") else "0"
    kind = candidate["kind"].split()[0]
    out = os.path.join(work, f"confirm_{volume}")
    cmd = [
        "bash",
        os.path.join(ROOT, "scripts", "train_model.sh"),
        volume,
        str(iterations),
        str(exemplars),
        str(candidate["image"]),
        str(candidate["width"]),
        kind,
        weight,
    ]
    log(
        f"{volume}: confirming width {candidate['width']}, {candidate['image']} px at the shipped recipe"
    )
    t0 = time.time()
    subprocess.run(
        cmd,
        check=True,
        env=dict(os.environ, DDG=DDG, WORK=out + "_work", MODEL_OUT=out, OUTLINE="0"),
    )
    with open(os.path.join(out, "bundle.json")) as f:
        metrics = json.load(f)["metrics"]
    record = {
        "volume": volume,
        "kind": candidate["kind"],
        "width": candidate["width"],
        "image": candidate["image"],
        "command": "MODEL_OUT=DIR OUTLINE=0 scripts/train_model.sh " + " ".join(cmd[2:]),
        "exemplars": exemplars,
        "iterations": iterations,
        "wall_minutes": (time.time() - t0) / 60,
        "candidate": {k: metrics[k] for k in CONFIRM_KEYS},
        "shipped": {k: shipped["metrics"][k] for k in CONFIRM_KEYS},
    }
    with open(confirm_path(volume), "w") as f:
        json.dump(record, f, indent=1)
    return record


def confirmation_verdict(c):
    """Whether the candidate, trained like the shipped bundle, suffices: issue 4's bar and within
    SUFFICES_DB / SUFFICES_SSIM of the better of the two."""
    a, s = c["candidate"], c["shipped"]
    meets_bar = (
        a["psnr"] >= BAR_PSNR and a["ssim"] >= BAR_SSIM and a["invariance"] >= BAR_INVARIANCE
    )
    close = (
        a["psnr"] >= max(a["psnr"], s["psnr"]) - SUFFICES_DB
        and a["ssim"] >= max(a["ssim"], s["ssim"]) - SUFFICES_SSIM
    )
    return meets_bar and close, meets_bar, close


def who(c):
    return f"{c['kind'].capitalize()}, width {c['width']}, {c['image']} px"


def confirmation_text(volume, candidate):
    """What the full-recipe training of `candidate` says about the shipped choice."""
    c = read_confirmation(volume, candidate)
    if c is None:
        return (
            f"  {who(candidate)} is not yet trained with the shipped recipe: `report.py --models-only "
            f"--confirm` does it and says whether it would replace the shipped bundle."
        )
    a, s = c["candidate"], c["shipped"]
    ok, meets_bar, close = confirmation_verdict(c)
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
                f"below the shipped models' bar (PSNR {BAR_PSNR:g} dB, SSIM {BAR_SSIM:g}, invariance {BAR_INVARIANCE:g})"
            )
        text += (
            "With full training it is "
            + " and ".join(why)
            + ", so the shipped configuration is the smallest that "
            "suffices for this scene."
        )
    return text


# advice for a screenshot problem beyond what the methods withstand (not measured by this report)
CAMERA = "match ParaView's camera to the screenshot, or `ddg reconstruct --estimate-view`"
AS_SAVED = "use the screenshot as ParaView saved it, without colour management"
REMEDIES = {
    "viewpoint (deg)": CAMERA,
    "zoom (x)": CAMERA,
    "crop (fraction)": "use the uncropped screenshot, or `ddg reconstruct --estimate-view`",
    "gamma": AS_SAVED,
    "colour shift (warm, x)": AS_SAVED,
    "wrong background": "`--background` with the screenshot's background colour",
    "annotation": "`--mask` over the annotations",
    "shading (lit render)": "take the screenshot with the volume's Shade off",
    "another volume's screenshot": "none: the TF of another volume's picture is not this volume's",
}


def method_guide():
    """Markdown table: per perturbation kind, each method's success rate on the perturbed cases and
    the one to use, how far it held and where it broke."""
    kinds = list(
        dict.fromkeys(
            r["perturbation"] for v in CASE_OBJECTS for r in results["cases"][v]["stability"]
        )
    )
    methods = list(STABLE_METHODS)
    rows = []
    for kind in kinds:
        cases = [
            r
            for v in CASE_OBJECTS
            for r in results["cases"][v]["stability"]
            if r["perturbation"] == kind and r["strength"] != 0
        ]
        if not cases:
            continue
        stats = {
            m: (
                np.mean([r["success"] for r in cases if r["method"] == m]),
                np.mean([r["psnr"] for r in cases if r["method"] == m]),
            )
            for m in methods
        }
        use = max(methods, key=lambda m: stats[m])
        held, broke = "-", "-"
        for strength in sorted({r["strength"] for r in cases}):
            mine = [r for r in cases if r["method"] == use and r["strength"] == strength]
            if all(r["success"] for r in mine):
                held = mine[0]["label"]
            else:
                broke = mine[0]["label"]
                break
        rows.append(
            [kind]
            + [f"{100 * stats[m][0]:.0f} %" for m in methods]
            + [use if stats[use][0] > 0 else "none succeeds", held, broke]
            + [REMEDIES.get(kind, "-") if broke != "-" else "-"]
        )
    head = ["screenshot problem"] + methods + ["use", "withstood up to", "broke at", "beyond that"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


def table(rows, cols):
    lines = ["| " + " | ".join(c for c, _ in cols) + " |", "|" + "---|" * len(cols)]
    for r in rows:
        lines.append("| " + " | ".join(f(r) for _, f in cols) + " |")
    return "\n".join(lines)


def models_markdown(models):
    if not models:
        return []
    return [
        "## Model kind and size (equal training time per configuration)",
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
        shipped_text(models),
        "",
    ]


def confirm_candidate(rows):
    """The model --confirm trains with the shipped recipe for a scene's sweep rows: the smallest
    sufficient one when it is smaller than the shipped one; otherwise the next smaller model of the
    shipped kind and image size (whether the shipped one is the smallest that suffices at full
    training, the sweep's 1.5 min being short and noisy). None without a shipped row or a smaller one.
    """
    shipped = [m for m in rows if is_shipped(m)]
    if not shipped or shipped_bundle(rows[0]["volume"]) is None:
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


def run_confirmations(models):
    """--confirm: trains each scene's confirm_candidate with the shipped recipe
    (model_confirm_VOLUME.json)."""
    for volume in sweep_mds if args.confirm else ():
        candidate = confirm_candidate([m for m in models if m["volume"] == volume])
        if candidate is not None:
            confirm(volume, candidate)


def confirmations(models):
    found = []
    for volume in sweep_mds:
        rows = [m for m in models if m["volume"] == volume]
        candidate = confirm_candidate(rows) if rows else None
        c = read_confirmation(volume, candidate) if candidate else None
        if c is not None:
            found.append(dict(c, suffices=confirmation_verdict(c)[0]))
    return found


def rewrite_models_section(models):
    """Redraws the model-size chart and replaces the model section of report.md and report.json."""
    plot_models(models)
    with open(os.path.join(args.out, "report.json")) as f:
        saved = json.load(f)
    saved["models"] = models
    saved["model_confirmations"] = confirmations(models)
    with open(os.path.join(args.out, "report.json"), "w") as f:
        json.dump(saved, f, indent=1)
    with open(os.path.join(args.out, "report.md")) as f:
        head = f.read().split("## Model kind and size")[0]
    with open(os.path.join(args.out, "report.md"), "w") as f:
        f.write(head + "\n".join(models_markdown(models)) + "\n")
    log(f"redrew {args.out}/report_models.png and the model section of report.md")


if args.models_only:  # redraw the model-size chart and section of an existing report
    models = read_sweeps()
    run_confirmations(models)
    rewrite_models_section(models)
    sys.exit(0)

# --- 0. model sweep (full run; before the methods, whose (b) uses its U-Net) ---------------------------

section("model sweep")

UNET = None
if not args.quick:
    sweep_work = os.path.join(work, "sweep")
    for volume, only in SWEEPS:
        log(f"{volume}: model sweep")
        subprocess.run(
            [
                "/usr/bin/python3",
                os.path.join(ROOT, "Testing", "Benchmarks", "model_sweep.py"),
                "--ddg",
                DDG,
                "--volume",
                volume,
                "--minutes",
                "1.5",
                "--out",
                sweep_mds[volume],
                "--work",
                sweep_work,
            ]
            + (["--only"] + [str(k) for k in only] if only else []),
            check=True,
        )
    UNET = next(
        (
            os.path.join(sweep_work, d)
            for d in sorted(os.listdir(sweep_work))
            if d.startswith("tooth_unet")
        ),
        None,
    )
    if UNET:
        ddg(
            "outline",
            "--model",
            UNET,
            "--volume",
            os.path.join(DATA, "Volumes", "tooth.vti"),
            "--count",
            "2000",
        )

# --- 1. methods: accuracy against time ------------------------------------------------------------

section("methods")

for volume, preset_name in CASES:
    log(f"{volume}: references")
    case = {
        "volume": os.path.join(DATA, "Volumes", volume + ".vti"),
        "model": os.path.join(DATA, "Models", volume),
        "preset": os.path.join(DATA, "TransferFunctions", preset_name + ".json"),
        "scene": ParaViewScene(volume),
    }
    case["views"] = {
        "reference": load_view(volume, "oblique"),
        "unseen": load_view(volume, "side"),
        "second": rotated(load_view(volume, "oblique"), elevation=45),
    }
    case["view_files"] = {
        k: write_json(v, f"{volume}_{k}_view.json") for k, v in case["views"].items()
    }
    case["refs"] = {
        k: case["scene"].render(case["preset"], v, os.path.join(work, f"{volume}_ref_{k}.png"))
        for k, v in case["views"].items()
    }
    shot, vfile = case["refs"]["reference"], case["view_files"]["reference"]
    rows = []

    def record(method, budget, preset, seconds):
        e = evaluate(case, preset, f"{volume}_{method}_{budget}")
        rows.append(
            {
                "method": method,
                "budget": budget,
                "seconds": seconds,
                "psnr": e["reference"][0],
                "ssim": e["reference"][1],
                "psnr_unseen": e["unseen"][0],
                "ssim_unseen": e["unseen"][1],
            }
        )
        log(
            f"{volume} {method} {budget}: {seconds:.2f} s, {e['reference'][0]:.1f} dB / {e['unseen'][0]:.1f} dB unseen"
        )

    record("nearest design (a)", 0, *method_nearest(case, shot, vfile, volume))
    if UNET and volume == "tooth":
        case["unet"] = UNET
        record("neural path (b)", 0, *method_neural(case, shot, vfile, volume))
    record("analyzer -> decoder (b')", 0, *method_query(case, shot, vfile, volume))
    for b in BUDGETS:
        record("b' + reconstruction", b, *method_refine(case, shot, vfile, volume, b))
        record("reconstruction (c)", b, *method_direct(case, shot, vfile, volume, b))
        record(f"{PRIMITIVES} primitives (d)", b, *method_primitives(case, shot, vfile, volume, b))
        record(
            "2-view reconstruction (e)",
            b,
            *reconstruct(
                case,
                [shot, case["refs"]["second"]],
                [vfile, case["view_files"]["second"]],
                f"{volume}_multi{b}",
                b,
            ),
        )
    results["cases"][volume] = {"preset": preset_name, "methods": rows}
    CASE_OBJECTS[volume] = case

# --- 2. stability: perturbed screenshots ------------------------------------------------------------

section("stability")


def perturbations(case):
    """name -> list of (strength label, numeric strength, image file, view file the method gets)."""
    ref, vfile, view = (
        case["refs"]["reference"],
        case["view_files"]["reference"],
        case["views"]["reference"],
    )
    scene, preset = case["scene"], case["preset"]
    img = np.asarray(Image.open(ref).convert("RGB")).astype(float)
    out = {}
    tag = os.path.basename(case["volume"]).split(".")[0]

    def save(a, name):
        path = os.path.join(work, f"{tag}_{name}.png")
        Image.fromarray(np.clip(a, 0, 255).astype(np.uint8)).save(path)
        return path

    angles = [0, 15, 30, 60, 90] if not args.quick else [0, 30, 90]
    out["viewpoint (deg)"] = [
        (
            a,
            a,
            scene.render(preset, rotated(view, azimuth=a), os.path.join(work, f"{tag}_az{a}.png")),
            vfile,
        )
        for a in angles
    ]
    zooms = [1.0, 1.15, 1.4, 0.75] if not args.quick else [1.0, 1.4]
    out["zoom (x)"] = [
        (
            z,
            abs(math.log(z)),
            scene.render(preset, rotated(view, zoom=z), os.path.join(work, f"{tag}_zoom{z}.png")),
            vfile,
        )
        for z in zooms
    ]
    h, w, _ = img.shape
    crops = [0.0, 0.1, 0.25] if not args.quick else [0.0, 0.25]
    out["crop (fraction)"] = []
    for c in crops:
        y0, x0 = int(h * c / 2), int(w * c / 2)
        part = Image.fromarray(img[y0 : h - y0, x0 : w - x0].astype(np.uint8)).resize(
            (w, h), Image.BILINEAR
        )
        out["crop (fraction)"].append(
            (c, c, save(np.asarray(part).astype(float), f"crop{c}"), vfile)
        )
    rng = np.random.default_rng(1)
    noises = [0, 5, 15, 40] if not args.quick else [0, 15]
    out["noise (sigma, grey levels)"] = [
        (s, s, save(img + rng.normal(0, s, img.shape), f"noise{s}"), vfile) for s in noises
    ]
    out["JPEG (quality)"] = []
    for q in [95, 50, 20, 5] if not args.quick else [50, 5]:
        path = os.path.join(work, f"{tag}_jpeg{q}.jpg")
        Image.open(ref).convert("RGB").save(path, quality=q)
        out["JPEG (quality)"].append((q, 100 - q, path, vfile))
    out["gamma"] = [
        (g, abs(math.log(g)), save(255 * (img / 255) ** g, f"gamma{g}"), vfile)
        for g in ([1.0, 1.25, 0.8, 1.6] if not args.quick else [1.0, 1.6])
    ]
    shift = np.array([1.0, 0.9, 0.8])
    out["colour shift (warm, x)"] = [
        (k, k, save(img * (1 - k + k * shift), f"tint{k}"), vfile)
        for k in ([0, 0.5, 1.0, 2.0] if not args.quick else [0, 2.0])
    ]
    black = dict(view, background=[0.0, 0.0, 0.0])
    out["wrong background"] = [
        ("white (right)", 0, ref, vfile),
        (
            "black, view says white",
            1,
            scene.render(preset, black, os.path.join(work, f"{tag}_black.png")),
            vfile,
        ),
    ]
    annotated = Image.open(ref).convert("RGB")
    d = ImageDraw.Draw(annotated)
    d.line([(20, 20), (w // 2, h // 2)], fill=(220, 0, 0), width=4)
    d.rectangle([w - 120, 10, w - 10, 40], outline=(0, 0, 0), width=3)
    d.text((w - 115, 15), "enamel", fill=(0, 0, 0))
    out["annotation"] = [
        ("none", 0, ref, vfile),
        ("arrow, box, text", 1, save(np.asarray(annotated).astype(float), "annot"), vfile),
    ]
    out["shading (lit render)"] = [
        ("unlit", 0, ref, vfile),
        (
            "lit",
            1,
            scene.render(preset, view, os.path.join(work, f"{tag}_lit.png"), shade=True),
            vfile,
        ),
    ]
    other = "engine_block_oblique.png" if tag != "engine" else "tooth_dentin_enamel_oblique.png"
    other_img = Image.open(os.path.join(DATA, "Screenshots", other)).convert("RGB").resize((w, h))
    out["another volume's screenshot"] = [
        ("own", 0, ref, vfile),
        ("other volume", 1, save(np.asarray(other_img).astype(float), "other"), vfile),
    ]
    return out


STABILITY_STEPS = 150 if args.quick else 300
STABLE_METHODS = {
    "analyzer -> decoder (b')": lambda c, s, v, t: method_query(c, s, v, t),
    "b' + reconstruction": lambda c, s, v, t: method_refine(c, s, v, t, STABILITY_STEPS),
    "reconstruction (c)": lambda c, s, v, t: method_direct(c, s, v, t, STABILITY_STEPS),
    f"{PRIMITIVES} primitives (d)": lambda c, s, v, t: method_primitives(
        c, s, v, t, STABILITY_STEPS
    ),
}
for volume, case in CASE_OBJECTS.items():
    stability = []
    baseline = {}  # method -> its result on the unperturbed screenshot (every kind's strength 0)
    for kind, items in perturbations(case).items():
        for label, strength, image, vfile in items:
            for name, run in STABLE_METHODS.items():
                if strength == 0 and name in baseline:
                    stability.append(dict(baseline[name], perturbation=kind, label=str(label)))
                    continue
                tag = f"{volume}_{re.sub('[^a-z0-9]', '', kind.lower())}_{strength}_{re.sub('[^a-z]', '', name)}"
                try:
                    preset, seconds = run(case, image, vfile, tag)
                    png = case["scene"].render(
                        preset, case["views"]["reference"], os.path.join(work, tag + ".png")
                    )
                    psnr = compare(png, case["refs"]["reference"])["psnr"]
                    error = ""
                except RuntimeError as e:
                    psnr, seconds, error = 0.0, 0.0, str(e).splitlines()[-1][:120]
                stability.append(
                    {
                        "perturbation": kind,
                        "label": str(label),
                        "strength": strength,
                        "method": name,
                        "psnr": psnr,
                        "success": psnr >= SUCCESS_DB,
                        "error": error,
                    }
                )
                if strength == 0:
                    baseline[name] = stability[-1]
            log(
                f"{volume} {kind} {label}: "
                + ", ".join(
                    f"{r['method'].split(' ')[0]} {r['psnr']:.1f}"
                    for r in stability[-len(STABLE_METHODS) :]
                )
            )
    results["cases"][volume]["stability"] = stability

# --- 3. optimisation stability, learning rate, TF resolution ------------------------------------------

section("optimisation and TF resolution")

case = CASE_OBJECTS["tooth"]
shot, vfile = case["refs"]["reference"], case["view_files"]["reference"]
rng = np.random.default_rng(7)
lo, hi = 0.0, 255.0
seeds = 4 if args.quick else 20
runs = []
for k in range(seeds):
    xs = np.sort(rng.uniform(lo, hi, 6))
    rgb = rng.uniform(0, 1, (6, 3))
    alpha = rng.uniform(0, 1, 6)
    init = write_json(
        [
            {
                "Name": f"random {k}",
                "ColorSpace": "RGB",
                "RGBPoints": [float(v) for x, c in zip(xs, rgb) for v in (x, *c)],
                "Points": [float(v) for x, a in zip(xs, alpha) for v in (x, a, 0.5, 0.0)],
            }
        ],
        f"init{k}.json",
    )
    preset, seconds = reconstruct(
        case, [shot], [vfile], f"seed{k}", 300, init=init, extra=["--seed", k + 1]
    )
    with open(preset) as f:
        p = json.load(f)[0]
    finite = all(math.isfinite(v) for v in p["RGBPoints"] + p["Points"])
    psnr = (
        compare(
            case["scene"].render(
                preset, case["views"]["reference"], os.path.join(work, f"seed{k}.png")
            ),
            case["refs"]["reference"],
        )["psnr"]
        if finite
        else float("nan")
    )
    runs.append({"seed": k + 1, "psnr": psnr, "finite": finite, "seconds": seconds})
log(
    f"random starts: PSNR {min(r['psnr'] for r in runs):.1f}..{max(r['psnr'] for r in runs):.1f} dB, "
    f"{sum(not r['finite'] for r in runs)} non-finite"
)
rates = []
for lr in [0.05, 0.2] if args.quick else [0.01, 0.03, 0.1, 0.2, 0.5, 1.0, 3.0]:
    preset, seconds = reconstruct(case, [shot], [vfile], f"lr{lr}", 300, extra=["--lr", lr])
    psnr = compare(
        case["scene"].render(preset, case["views"]["reference"], os.path.join(work, f"lr{lr}.png")),
        case["refs"]["reference"],
    )["psnr"]
    rates.append({"lr": lr, "psnr": psnr, "seconds": seconds})
results["optimisation"] = {"random_starts": runs, "learning_rates": rates}
resolution = []
for bins in [16, 128] if args.quick else [16, 32, 64, 128, 256]:
    for smooth in [0.0, 0.01] if args.quick else [0.0, 0.01, 0.1, 1.0]:
        preset, seconds = reconstruct(
            case,
            [shot],
            [vfile],
            f"bins{bins}_{smooth}",
            300,
            extra=["--bins", bins, "--smoothness", smooth],
        )
        e = evaluate(case, preset, f"bins{bins}_{smooth}")
        resolution.append(
            {
                "bins": bins,
                "smoothness": smooth,
                "seconds": seconds,
                "psnr": e["reference"][0],
                "psnr_unseen": e["unseen"][0],
            }
        )
    log(
        f"bins {bins}: "
        + ", ".join(
            f"smoothness {r['smoothness']}: {r['psnr']:.1f}/{r['psnr_unseen']:.1f} dB"
            for r in resolution
            if r["bins"] == bins
        )
    )
results["tf_resolution"] = resolution

# --- 4. renderer speed ------------------------------------------------------------------------------

section("renderer")

_timed = {}


def bench_renderer(size, spv=2):
    """Ours (forward, forward + adjoint) and VTK's fixed-point mapper on Engine at size^2 and spv
    samples per voxel (ParaView's rule: 2); each (size, spv) is timed once."""
    if (size, spv) not in _timed:
        common = ["--size", str(size), "--samples-per-voxel", str(spv)]
        r = subprocess.run(
            [os.path.join(BIN, "BenchRayCaster"), "--runs", "5", *common],
            capture_output=True,
            text=True,
        )
        d = subprocess.run(
            [os.path.join(BIN, "BenchDifferentiable"), "--runs", "3", "--timing-only", *common],
            capture_output=True,
            text=True,
        )
        m = re.search(r"forward ([\d.]+) ms, backward ([\d.]+) ms", d.stdout)
        _timed[(size, spv)] = {
            "ours_ms": float(re.search(r"ddg RayCaster +([\d.]+) ms", r.stdout).group(1)),
            "vtk_ms": float(
                re.search(r"VTK FixedPointVolumeRayCastMapper +([\d.]+) ms", r.stdout).group(1)
            ),
            "forward_ms": float(m.group(1)),
            "forward_backward_ms": float(m.group(1)) + float(m.group(2)),
        }
    return dict(_timed[(size, spv)])


renderer = []
for size in [64, 128] if args.quick else [64, 128, 256, 512]:
    row = dict(size=size, **bench_renderer(size))
    if size <= 128:
        t = subprocess.run(
            [
                "/usr/bin/python3",
                os.path.join(ROOT, "Testing", "Benchmarks", "bench_torch_autograd.py"),
                "--bench",
                os.path.join(BIN, "BenchDifferentiable"),
                "--size",
                str(size),
            ],
            capture_output=True,
            text=True,
        )
        m = re.search(r"PyTorch autograd: forward\+backward ([\d.]+) ms", t.stdout)
        row["torch_forward_backward_ms"] = float(m.group(1)) if m else None
    renderer.append(row)
    log(
        f"renderer {size}^2: ours {row['ours_ms']:.1f} ms, VTK {row['vtk_ms']:.1f} ms, "
        f"fwd+bwd {row['forward_backward_ms']:.1f} ms, torch {row.get('torch_forward_backward_ms')}"
    )
results["renderer"] = renderer
samples = []  # time against samples per voxel (sample distance = mean spacing / S; ParaView: S = 2)
sample_size = 64 if args.quick else 256
for spv in [1, 4] if args.quick else [0.5, 1, 2, 4, 8]:
    row = dict(samples_per_voxel=spv, **bench_renderer(sample_size, spv))
    samples.append(row)
    log(
        f"renderer {sample_size}^2, {spv} samples/voxel: ours {row['ours_ms']:.1f} ms, VTK {row['vtk_ms']:.1f} ms, "
        f"fwd+bwd {row['forward_backward_ms']:.1f} ms"
    )
results["renderer_samples"] = {"size": sample_size, "rows": samples}

# --- 5. model size (the model sweep) ----------------------------------------------------------------

models = read_sweeps()  # the sweeps ran first (section 0)
results["models"] = models

# --- charts -------------------------------------------------------------------------------------------

section("charts")

COLORS = {
    "nearest design (a)": "tab:gray",
    "neural path (b)": "tab:brown",
    "analyzer -> decoder (b')": "tab:purple",
    "b' + reconstruction": "tab:red",
    "reconstruction (c)": "tab:blue",
    f"{PRIMITIVES} primitives (d)": "tab:orange",
    "2-view reconstruction (e)": "tab:green",
}
MARKERS = {m: k for m, k in zip(COLORS, "o^vsDPX")}
fig, axes = plt.subplots(len(CASES), 2, figsize=(11, 4.2 * len(CASES)), squeeze=False)
for i, (volume, _) in enumerate(CASES):
    rows = results["cases"][volume]["methods"]
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
fig.savefig(os.path.join(args.out, "report_methods.png"), dpi=110)

kinds = list(dict.fromkeys(r["perturbation"] for r in results["cases"]["tooth"]["stability"]))
fig, axes = plt.subplots(
    int(math.ceil(len(kinds) / 4)), 4, figsize=(16, 3.3 * math.ceil(len(kinds) / 4)), squeeze=False
)
for k, kind in enumerate(kinds):
    ax = axes[k // 4][k % 4]
    for q, method in enumerate(STABLE_METHODS):
        pts = {}
        for volume in CASE_OBJECTS:
            for r in results["cases"][volume]["stability"]:
                if r["perturbation"] == kind and r["method"] == method:
                    pts.setdefault(r["strength"], []).append(r["success"])
        xs = sorted(pts)
        shift = (q - (len(STABLE_METHODS) - 1) / 2) * 0.06  # equal rates stay visible side by side
        ax.plot(
            [i + shift for i in range(len(xs))],
            [np.mean(pts[x]) + shift / 3 for x in xs],
            "-",
            marker=MARKERS[method],
            color=COLORS[method],
            label=method,
            alpha=0.85,
        )
        labels = [
            next(
                r["label"]
                for r in results["cases"]["tooth"]["stability"]
                if r["perturbation"] == kind and r["strength"] == x
            )
            for x in xs
        ]
        ax.set_xticks(range(len(xs)))
        ax.set_xticklabels(labels, fontsize=7)
    ax.set_ylim(-0.05, 1.05)
    ax.set_title(kind, fontsize=9)
    ax.set_ylabel("success rate", fontsize=8)
for k in range(len(kinds), axes.size):
    axes[k // 4][k % 4].axis("off")
axes[0][0].legend(fontsize=7)
fig.suptitle(
    f"success = ParaView's render at the reference view within {SUCCESS_DB:.0f} dB of the reference "
    "(lines shifted slightly so that equal rates stay visible)"
)
fig.tight_layout()
fig.savefig(os.path.join(args.out, "report_stability.png"), dpi=110)

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
fig.savefig(os.path.join(args.out, "report_optimisation.png"), dpi=110)

fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
for smooth in sorted({r["smoothness"] for r in resolution}):
    pts = [r for r in resolution if r["smoothness"] == smooth]
    axes[0].plot(
        [r["bins"] for r in pts],
        [r["psnr_unseen"] for r in pts],
        "o-",
        label=f"smoothness {smooth}",
    )
    axes[1].plot(
        [r["bins"] for r in pts], [r["seconds"] for r in pts], "o-", label=f"smoothness {smooth}"
    )
for ax, label in zip(axes, ("PSNR at the unseen view (dB)", "time (s)")):
    ax.set_xscale("log", base=2)
    ax.set_xlabel("TF bins")
    ax.set_ylabel(label)
    ax.grid(alpha=0.3)
axes[0].legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(args.out, "report_tf_resolution.png"), dpi=110)

fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4))
sizes = [r["size"] ** 2 for r in renderer]
ax.plot(sizes, [r["ours_ms"] for r in renderer], "o-", label="ours, forward (block skipping)")
ax.plot(sizes, [r["forward_backward_ms"] for r in renderer], "o-", label="ours, forward + adjoint")
ax.plot(sizes, [r["vtk_ms"] for r in renderer], "o-", label="VTK FixedPointVolumeRayCastMapper")
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
ax2.plot(spv, [r["ours_ms"] for r in samples], "o-", label="ours, forward (block skipping)")
ax2.plot(spv, [r["forward_backward_ms"] for r in samples], "o-", label="ours, forward + adjoint")
ax2.plot(spv, [r["vtk_ms"] for r in samples], "o-", label="VTK FixedPointVolumeRayCastMapper")
ax2.set_xscale("log", base=2)
ax2.set_yscale("log")
ax2.set_xlabel(f"samples per voxel (Engine, {sample_size}^2; ParaView's rule: 2)")
ax2.set_ylabel("ms on 2 cores")
ax2.legend(fontsize=7)
ax2.grid(alpha=0.3)
fig.tight_layout()
fig.savefig(os.path.join(args.out, "report_renderer.png"), dpi=110)

if models:
    plot_models(models)

# --- report.md ------------------------------------------------------------------------------------------

charts_minutes = (time.time() - started) / 60
results["section_minutes"] = section_minutes()
results["model_confirmations"] = confirmations(models)


md = [
    f"# Speed against accuracy, stability, model size{' (quick run)' if args.quick else ''}",
    "",
    f"Produced by `Testing/Benchmarks/report.py{' --quick' if args.quick else ''}` on 2 cores in "
    f"{charts_minutes:.1f} min"
    + (" (before --confirm, whose time is in its section)" if args.confirm else "")
    + ". Raw numbers: `report.json`.",
    "",
    "Minutes per section: "
    + ", ".join(f"{name} {m:.1f}" for name, m in results["section_minutes"].items())
    + ".",
    "",
]
for volume, preset_name in CASES:
    md += [
        f"## Screenshot -> TF: {volume} ({preset_name})",
        "",
        f"![methods](report_methods.png)",
        "",
        table(
            results["cases"][volume]["methods"],
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
md += [
    "(b), the paper's neural path, needs a U-Net bundle: in the full run the model sweep's Tooth U-Net (1.5 min "
    "of training, a 2000-design outline); the shipped models are decoders, whose render at a view is the ray "
    "cast of their decoded TF, so for them (b) is (b') + reconstruction. "
    + ("" if UNET else "This run has no U-Net (quick run): (b) is not measured. ")
    + f"(d) fits {PRIMITIVES} Gaussian primitives (mean, width, colour, peak opacity each) through the same "
    "renderer adjoint.",
    "",
]
md += ["## Stability: where each method breaks", "", "![stability](report_stability.png)", ""]
fails = {}
for volume in CASE_OBJECTS:
    st = results["cases"][volume]["stability"]
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
            ],
        ),
        "",
    ]
    for r in st:
        if not r["success"]:
            fails.setdefault((r["perturbation"], r["method"]), []).append(f"{volume} {r['label']}")
md += ["Failures seen (perturbation, method: cases):", ""]
md += [f"- {k[0]}, {k[1]}: {', '.join(v)}" for k, v in sorted(fails.items())] or ["- none"]
rate = {
    m: np.mean(
        [
            r["success"]
            for v in CASE_OBJECTS
            for r in results["cases"][v]["stability"]
            if r["method"] == m
        ]
    )
    for m in STABLE_METHODS
}
best = max(rate, key=rate.get)
md += [
    "",
    "Success rate over all perturbations: "
    + ", ".join(f"{m} {100 * s:.0f} %" for m, s in rate.items())
    + f". Most robust here: {best}.",
    "",
    "### Which method to use when",
    "",
    "Per kind of screenshot problem, over its perturbed cases on "
    + " and ".join(CASE_OBJECTS)
    + ": each method's success rate, the method to use (highest success, then mean PSNR), the "
    "strongest perturbation it withstood on every volume and the first it did not. The last column "
    "is advice for what no method withstands (not measured here).",
    "",
    method_guide(),
    "",
]
md += [
    "## Optimisation",
    "",
    "![optimisation](report_optimisation.png)",
    "",
    f"{len(runs)} random initial TFs with their own pixel-sampling seeds, 300 steps: PSNR "
    f"{np.nanmin([r['psnr'] for r in runs]):.2f}..{np.nanmax([r['psnr'] for r in runs]):.2f} dB "
    f"(median {np.nanmedian([r['psnr'] for r in runs]):.2f}), non-finite results: "
    f"{sum(not r['finite'] for r in runs)}.",
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
        resolution,
        [
            ("bins", lambda r: str(r["bins"])),
            ("smoothness", lambda r: str(r["smoothness"])),
            ("PSNR ref", lambda r: f"{r['psnr']:.2f}"),
            ("PSNR unseen", lambda r: f"{r['psnr_unseen']:.2f}"),
            ("time s", lambda r: f"{r['seconds']:.2f}"),
        ],
    ),
    "",
    "## Renderer (Engine, engine_block)",
    "",
    "![renderer](report_renderer.png)",
    "",
    table(
        renderer,
        [
            ("size", lambda r: f"{r['size']}^2"),
            ("ours ms", lambda r: f"{r['ours_ms']:.1f}"),
            ("VTK ms", lambda r: f"{r['vtk_ms']:.1f}"),
            ("ours fwd+adjoint ms", lambda r: f"{r['forward_backward_ms']:.1f}"),
            (
                "PyTorch autograd ms",
                lambda r: f"{r['torch_forward_backward_ms']:.1f}"
                if r.get("torch_forward_backward_ms")
                else "-",
            ),
        ],
    ),
    "",
    f"Samples per voxel (sample distance = mean spacing / S), {sample_size}^2:",
    "",
    table(
        samples,
        [
            ("samples/voxel", lambda r: f"{r['samples_per_voxel']:g}"),
            ("ours ms", lambda r: f"{r['ours_ms']:.1f}"),
            ("VTK ms", lambda r: f"{r['vtk_ms']:.1f}"),
            ("ours fwd+adjoint ms", lambda r: f"{r['forward_backward_ms']:.1f}"),
        ],
    ),
    "",
]
md += models_markdown(models)
results["minutes"] = charts_minutes
with open(os.path.join(args.out, "report.json"), "w") as f:
    json.dump(results, f, indent=1)
with open(os.path.join(args.out, "report.md"), "w") as f:
    f.write("\n".join(md) + "\n")
log(f"wrote {args.out}/report.md, report.json and the report_*.png charts")
if args.confirm:  # after the report is safely written: this trains for a while
    run_confirmations(models)
    rewrite_models_section(models)
nonfinite = sum(not r["finite"] for r in runs)
if nonfinite:
    sys.exit(f"{nonfinite} reconstructions from random starts ended with non-finite values")
