"""report_measure.py: the report's measurements, section by section, into the dict report.json
holds (see report.py for what is measured). Runs in pvpython (ParaView renders every result).
"""
import json
import math
import os
import re
import subprocess

import numpy as np
from PIL import Image, ImageDraw

from report_common import (
    DATA,
    DIRECT,
    MATCH,
    QUERY_MATCH,
    NEAREST,
    NEURAL,
    PRIMITIVE_FIT,
    QUERY,
    REFINE,
    ROOT,
    SUCCESS_DB,
    TWO_VIEW,
    log,
    section,
)
from report_methods import Methods, ParaViewScene, load_view, rotated
from report_models import SWEEPS, read_sweeps, sweep_md

# --- 0. model sweep (full run; before the methods, whose (b) uses its U-Net) ---------------------


def model_sweep(m, out):
    """model_sweep.py on each scene (tables in `out`); the Tooth U-Net bundle with a 2000-design
    outline for method (b), or None."""
    sweep_work = m.path("sweep")
    for volume, only in SWEEPS:
        log(f"{volume}: model sweep")
        subprocess.run(
            [
                "/usr/bin/python3",
                os.path.join(ROOT, "Testing", "Benchmarks", "model_sweep.py"),
                "--ddg",
                m.exe,
                "--volume",
                volume,
                "--minutes",
                "1.5",
                "--out",
                sweep_md(volume, out),
                "--work",
                sweep_work,
            ]
            + (["--only"] + [str(k) for k in only] if only else []),
            check=True,
        )
    unet = next(
        (
            os.path.join(sweep_work, d)
            for d in sorted(os.listdir(sweep_work))
            if d.startswith("tooth_unet")
        ),
        None,
    )
    if unet:
        m.ddg(
            "outline",
            "--model",
            unet,
            "--volume",
            os.path.join(DATA, "Volumes", "tooth.vti"),
            "--count",
            "2000",
        )
    return unet


# --- 1. methods: accuracy against time ----------------------------------------------------------


def new_case(m, volume, preset_name):
    """A scene of `volume` with its views and ParaView's references of the preset at them."""
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
        k: m.write_json(v, f"{volume}_{k}_view.json") for k, v in case["views"].items()
    }
    case["refs"] = {
        k: case["scene"].render(case["preset"], v, m.path(f"{volume}_ref_{k}.png"))
        for k, v in case["views"].items()
    }
    return case


def methods(m, volume, case, budgets, unet):
    """Every method on the case's reference screenshot: report.json's cases[volume]["methods"]."""
    shot, vfile = case["refs"]["reference"], case["view_files"]["reference"]
    rows = []

    def record(method, budget, preset, seconds):
        e = m.evaluate(case, preset, f"{volume}_{method}_{budget}")
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

    record(NEAREST, 0, *m.nearest(case, shot, vfile, volume))
    if unet and volume == "tooth":
        case["unet"] = unet
        record(NEURAL, 0, *m.neural(case, shot, vfile, volume))
    record(QUERY, 0, *m.query(case, shot, vfile, volume))
    for b in budgets:
        record(REFINE, b, *m.refine(case, shot, vfile, volume, b))
        record(DIRECT, b, *m.direct(case, shot, vfile, volume, b))
        record(PRIMITIVE_FIT, b, *m.primitives(case, shot, vfile, volume, b))
        record(
            TWO_VIEW,
            b,
            *m.reconstruct(
                case,
                [shot, case["refs"]["second"]],
                [vfile, case["view_files"]["second"]],
                f"{volume}_multi{b}",
                b,
            ),
        )
    return rows


# --- 2. stability: perturbed screenshots --------------------------------------------------------

PALETTE = [0.32, 0.34, 0.43]  # ParaView 5.11's default palette background (a new view's)
PALETTE2 = [0.0, 0.0, 0.16]  # the palette's Background2: the top of its gradient


def runs_on(method, index, strength, count, quick):
    """Whether `method` runs on the index-th of a perturbation's `count` strengths (`strength` 0: the
    unperturbed screenshot, run once and shared). The query + match runs on the unperturbed and
    the strongest of each kind (--quick: nowhere); the others on every strength, except with
    --quick, where b' + reconstruction and the 12-primitive fit run on the unperturbed screenshot
    only (the query and the reconstruction still on every strength) and the match not at all
    (73 s in a CI run, a quarter of the test's time; ctest has the whole match on a Tooth
    screenshot in Reconstruction.Match.ToothScreenshotWithoutItsCamera and the CLI's view-less
    path in CLI.ReconstructWithoutView)."""
    if method == QUERY_MATCH:
        return not quick and index in (0, count - 1)
    if method == MATCH:
        return not quick
    if method in (REFINE, PRIMITIVE_FIT):
        return not quick or strength == 0
    return True


def perturbations(m, case, quick):
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
        path = m.path(f"{tag}_{name}.png")
        Image.fromarray(np.clip(a, 0, 255).astype(np.uint8)).save(path)
        return path

    angles = [0, 15, 30, 60, 90] if not quick else [0, 30, 90]
    out["viewpoint (deg)"] = [
        (a, a, scene.render(preset, rotated(view, azimuth=a), m.path(f"{tag}_az{a}.png")), vfile)
        for a in angles
    ]
    zooms = [1.0, 1.15, 1.4, 0.75] if not quick else [1.0, 1.4]
    out["zoom (x)"] = [
        (
            z,
            abs(math.log(z)),
            scene.render(preset, rotated(view, zoom=z), m.path(f"{tag}_zoom{z}.png")),
            vfile,
        )
        for z in zooms
    ]
    rolls = [0, 10, 20, 45] if not quick else [0, 20]
    out["roll (deg)"] = [
        (r, r, scene.render(preset, rotated(view, roll=r), m.path(f"{tag}_roll{r}.png")), vfile)
        for r in rolls
    ]
    pans = [0.0, 0.05, 0.1] if not quick else [0.0, 0.1]  # view heights, right and up
    out["pan (view heights)"] = [
        (
            p,
            p,
            scene.render(preset, rotated(view, pan=(p, p / 2)), m.path(f"{tag}_pan{p}.png")),
            vfile,
        )
        for p in pans
    ]
    h, w, _ = img.shape
    crops = [0.0, 0.1, 0.25] if not quick else [0.0, 0.25]
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
    noises = [0, 5, 15, 40] if not quick else [0, 15]
    out["noise (sigma, grey levels)"] = [
        (s, s, save(img + rng.normal(0, s, img.shape), f"noise{s}"), vfile) for s in noises
    ]
    out["JPEG (quality)"] = []
    for q in [95, 50, 20, 5] if not quick else [50, 5]:
        path = m.path(f"{tag}_jpeg{q}.jpg")
        Image.open(ref).convert("RGB").save(path, quality=q)
        out["JPEG (quality)"].append((q, 100 - q, path, vfile))
    out["gamma"] = [
        (g, abs(math.log(g)), save(255 * (img / 255) ** g, f"gamma{g}"), vfile)
        for g in ([1.0, 1.25, 0.8, 1.6] if not quick else [1.0, 1.6])
    ]
    shift = np.array([1.0, 0.9, 0.8])
    out["colour shift (warm, x)"] = [
        (k, k, save(img * (1 - k + k * shift), f"tint{k}"), vfile)
        for k in ([0, 0.5, 1.0, 2.0] if not quick else [0, 2.0])
    ]
    black = dict(view, background=[0.0, 0.0, 0.0])
    out["wrong background"] = [
        ("white (right)", 0, ref, vfile),
        (
            "black, view says white",
            1,
            scene.render(preset, black, m.path(f"{tag}_black.png")),
            vfile,
        ),
    ]
    # the background as screenshots have it; the methods with a view get it in their view file
    backgrounds = [
        ("white", 0, view, None),
        ("palette 0.32 0.34 0.43", 1, dict(view, background=PALETTE), None),
        ("black", 2, black, None),
        ("gradient", 3, dict(view, background=PALETTE, background2=PALETTE2), None),
    ]
    out["background (view gives it)"] = [
        (
            label,
            k,
            ref if k == 0 else scene.render(preset, v, m.path(f"{tag}_bg{k}.png")),
            vfile if k == 0 else m.write_json(v, f"{tag}_bg{k}_view.json"),
        )
        for label, k, v, _ in backgrounds
        if not quick or k in (0, 3)
    ]
    annotated = Image.open(ref).convert("RGB")
    d = ImageDraw.Draw(annotated)
    d.line([(20, 20), (w // 2, h // 2)], fill=(220, 0, 0), width=4)
    d.rectangle([w - 120, 10, w - 10, 40], outline=(0, 0, 0), width=3)
    d.text((w - 115, 15), "enamel", fill=(0, 0, 0))
    out["annotation"] = [
        ("none", 0, ref, vfile),
        ("arrow, box, text", 1, save(np.asarray(annotated).astype(float), "annot"), vfile),
        (
            "orientation axes",
            2,
            scene.render(preset, view, m.path(f"{tag}_axes.png"), axes=True),
            vfile,
        ),
    ]
    out["shading (lit render)"] = [
        ("unlit", 0, ref, vfile),
        ("lit", 1, scene.render(preset, view, m.path(f"{tag}_lit.png"), shade=True), vfile),
    ]
    other = "engine_block_oblique.png" if tag != "engine" else "tooth_dentin_enamel_oblique.png"
    other_img = Image.open(os.path.join(DATA, "Screenshots", other)).convert("RGB").resize((w, h))
    out["another volume's screenshot"] = [
        ("own", 0, ref, vfile),
        ("other volume", 1, save(np.asarray(other_img).astype(float), "other"), vfile),
    ]
    return out


def stability(m, volume, case, quick):
    """The stable methods on every perturbation: report.json's cases[volume]["stability"]."""
    steps = 150 if quick else 300
    runs = {
        QUERY: lambda c, s, v, t: m.query(c, s, v, t),
        REFINE: lambda c, s, v, t: m.refine(c, s, v, t, steps),
        DIRECT: lambda c, s, v, t: m.direct(c, s, v, t, steps),
        PRIMITIVE_FIT: lambda c, s, v, t: m.primitives(c, s, v, t, steps),
        MATCH: lambda c, s, v, t: m.match(c, s, t),
        QUERY_MATCH: lambda c, s, v, t: m.query_match(c, s, v, t),
    }
    rows = []
    baseline = {}  # method -> its result on the unperturbed screenshot (every kind's strength 0)
    for kind, items in perturbations(m, case, quick).items():
        for index, (label, strength, image, vfile) in enumerate(items):
            done = []
            for name, run in runs.items():
                if not runs_on(name, index, strength, len(items), quick):
                    continue
                if strength == 0 and name in baseline:
                    rows.append(dict(baseline[name], perturbation=kind, label=str(label)))
                    done.append(rows[-1])
                    continue
                tag = f"{volume}_{re.sub('[^a-z0-9]', '', kind.lower())}_{strength}_{re.sub('[^a-z]', '', name)}"
                try:
                    preset, seconds = run(case, image, vfile, tag)
                    png = case["scene"].render(
                        preset, case["views"]["reference"], m.path(tag + ".png")
                    )
                    psnr = m.compare(png, case["refs"]["reference"])["psnr"]
                    error = ""
                except RuntimeError as e:
                    psnr, seconds, error = 0.0, 0.0, str(e).splitlines()[-1][:160]  # the reason
                rows.append(
                    {
                        "perturbation": kind,
                        "label": str(label),
                        "strength": strength,
                        "method": name,
                        "psnr": psnr,
                        "success": psnr >= SUCCESS_DB,
                        "seconds": seconds,
                        "error": error,
                    }
                )
                done.append(rows[-1])
                if strength == 0:
                    baseline[name] = rows[-1]
            log(
                f"{volume} {kind} {label}: "
                + ", ".join(
                    f"{r['method']} {r['psnr']:.1f} ({r['seconds']:.0f} s)"
                    + (" refused" if r["error"] else "")
                    for r in done
                )
            )
    return rows


# --- 3. optimisation stability, learning rate, TF resolution ------------------------------------


def optimisation(m, case, quick):
    """Random initial TFs and seeds, learning rates (report.json's "optimisation") and TF bins
    against the smoothness prior ("tf_resolution"), on Tooth."""
    shot, vfile = case["refs"]["reference"], case["view_files"]["reference"]

    def psnr_of(preset, name):
        png = case["scene"].render(preset, case["views"]["reference"], m.path(name))
        return m.compare(png, case["refs"]["reference"])["psnr"]

    rng = np.random.default_rng(7)
    lo, hi = 0.0, 255.0
    runs = []
    for k in range(4 if quick else 20):
        xs = np.sort(rng.uniform(lo, hi, 6))
        rgb = rng.uniform(0, 1, (6, 3))
        alpha = rng.uniform(0, 1, 6)
        init = m.write_json(
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
        preset, seconds = m.reconstruct(
            case, [shot], [vfile], f"seed{k}", 300, init=init, extra=["--seed", k + 1]
        )
        with open(preset) as f:
            p = json.load(f)[0]
        finite = all(math.isfinite(v) for v in p["RGBPoints"] + p["Points"])
        psnr = psnr_of(preset, f"seed{k}.png") if finite else float("nan")
        runs.append({"seed": k + 1, "psnr": psnr, "finite": finite, "seconds": seconds})
    log(
        f"random starts: PSNR {min(r['psnr'] for r in runs):.1f}..{max(r['psnr'] for r in runs):.1f} dB, "
        f"{sum(not r['finite'] for r in runs)} non-finite"
    )
    rates = []
    for lr in [0.05, 0.2] if quick else [0.01, 0.03, 0.1, 0.2, 0.5, 1.0, 3.0]:
        preset, seconds = m.reconstruct(case, [shot], [vfile], f"lr{lr}", 300, extra=["--lr", lr])
        rates.append({"lr": lr, "psnr": psnr_of(preset, f"lr{lr}.png"), "seconds": seconds})
    resolution = []
    for bins in [16, 128] if quick else [16, 32, 64, 128, 256]:
        for smooth in [0.0, 0.01] if quick else [0.0, 0.01, 0.1, 1.0]:
            preset, seconds = m.reconstruct(
                case,
                [shot],
                [vfile],
                f"bins{bins}_{smooth}",
                300,
                extra=["--bins", bins, "--smoothness", smooth],
            )
            e = m.evaluate(case, preset, f"bins{bins}_{smooth}")
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
    return {"random_starts": runs, "learning_rates": rates}, resolution


# --- 4. renderer speed --------------------------------------------------------------------------


class RendererBench:
    """Ours (forward, forward + adjoint) and VTK's fixed-point mapper on Engine (BenchRayCaster,
    BenchDifferentiable beside the `ddg` program); each (size, samples per voxel) timed once."""

    def __init__(self, bin_dir):
        self.bin, self.timed = bin_dir, {}

    def __call__(self, size, spv=2):
        """At size^2 and spv samples per voxel (ParaView's rule: 2)."""
        if (size, spv) not in self.timed:
            common = ["--size", str(size), "--samples-per-voxel", str(spv)]
            r = subprocess.run(
                [os.path.join(self.bin, "BenchRayCaster"), "--runs", "5", *common],
                capture_output=True,
                text=True,
            )
            d = subprocess.run(
                [
                    os.path.join(self.bin, "BenchDifferentiable"),
                    "--runs",
                    "3",
                    "--timing-only",
                    *common,
                ],
                capture_output=True,
                text=True,
            )
            m = re.search(r"forward ([\d.]+) ms, backward ([\d.]+) ms", d.stdout)
            self.timed[(size, spv)] = {
                "ours_ms": float(re.search(r"ddg RayCaster +([\d.]+) ms", r.stdout).group(1)),
                "vtk_ms": float(
                    re.search(r"VTK FixedPointVolumeRayCastMapper +([\d.]+) ms", r.stdout).group(1)
                ),
                "forward_ms": float(m.group(1)),
                "forward_backward_ms": float(m.group(1)) + float(m.group(2)),
            }
        return dict(self.timed[(size, spv)])

    def torch_ms(self, size):
        """bench_torch_autograd.py's forward + backward at size^2 (None when it printed none)."""
        t = subprocess.run(
            [
                "/usr/bin/python3",
                os.path.join(ROOT, "Testing", "Benchmarks", "bench_torch_autograd.py"),
                "--bench",
                os.path.join(self.bin, "BenchDifferentiable"),
                "--size",
                str(size),
            ],
            capture_output=True,
            text=True,
        )
        m = re.search(r"PyTorch autograd: forward\+backward ([\d.]+) ms", t.stdout)
        return float(m.group(1)) if m else None


def renderer(m, quick):
    """Time against image size (report.json's "renderer") and against samples per voxel
    ("renderer_samples")."""
    bench = RendererBench(m.bin)
    rows = []
    for size in [64, 128] if quick else [64, 128, 256, 512]:
        row = dict(size=size, **bench(size))
        if size <= 128:
            row["torch_forward_backward_ms"] = bench.torch_ms(size)
        rows.append(row)
        log(
            f"renderer {size}^2: ours {row['ours_ms']:.1f} ms, VTK {row['vtk_ms']:.1f} ms, "
            f"fwd+bwd {row['forward_backward_ms']:.1f} ms, torch {row.get('torch_forward_backward_ms')}"
        )
    samples = []  # sample distance = mean spacing / S; ParaView: S = 2
    sample_size = 64 if quick else 256
    for spv in [1, 4] if quick else [0.5, 1, 2, 4, 8]:
        row = dict(samples_per_voxel=spv, **bench(sample_size, spv))
        samples.append(row)
        log(
            f"renderer {sample_size}^2, {spv} samples/voxel: ours {row['ours_ms']:.1f} ms, VTK {row['vtk_ms']:.1f} ms, "
            f"fwd+bwd {row['forward_backward_ms']:.1f} ms"
        )
    return rows, {"size": sample_size, "rows": samples}


# --- all of it -------------------------------------------------------------------------------------


SECTIONS = ["methods", "stability", "optimisation", "renderer"]  # what --sections may name


def measure(exe, work, out, quick, confirm, sections=None, saved=None):
    """Every section with the `ddg` program `exe`, scratch files in `work` and the sweep tables in
    `out`: the dict report.json holds, without the keys report.py adds when it is done
    (section_minutes, model_confirmations, minutes). With `sections` (names of SECTIONS), only
    those are measured and the others' results are kept from `saved` (report.json's content);
    the model sweep is not rerun (its tables in `out` are read)."""
    m = Methods(exe, work)
    cases = [("tooth", "tooth_dentin_enamel")] + ([] if quick else [("engine", "engine_block")])
    budgets = [30, 150] if quick else [10, 30, 100, 300, 1000]
    wanted = set(sections or SECTIONS)
    if sections:
        results = json.loads(json.dumps(saved))
    else:
        results = {"quick": quick, "confirm": confirm, "success_db": SUCCESS_DB, "cases": {}}
    scenes = {}  # volume -> its case (scene, views, references)

    if not sections:
        section("model sweep")
    unet = None if quick or sections else model_sweep(m, out)

    if wanted & {"methods", "stability", "optimisation"}:  # these need the references
        section("methods" if "methods" in wanted else "references")
        for volume, preset_name in cases:
            log(f"{volume}: references")
            scenes[volume] = new_case(m, volume, preset_name)
            if "methods" in wanted:
                rows = methods(m, volume, scenes[volume], budgets, unet)
                results["cases"][volume] = {"preset": preset_name, "methods": rows}

    if "stability" in wanted:
        section("stability")
        for volume, case in scenes.items():
            results["cases"][volume]["stability"] = stability(m, volume, case, quick)

    if "optimisation" in wanted:
        section("optimisation and TF resolution")
        results["optimisation"], results["tf_resolution"] = optimisation(m, scenes["tooth"], quick)

    if "renderer" in wanted:
        section("renderer")
        results["renderer"], results["renderer_samples"] = renderer(m, quick)

    if not sections:
        results["models"] = read_sweeps(out)  # the sweeps ran first (section 0)
    return results
