#!/usr/bin/env python3
"""confirm.py: a model-size candidate trained with a shipped bundle's recipe, against that bundle.

The report's model sweep trains every configuration for 1.5 minutes; whether a smaller model
than the shipped one would do is settled here at full training: the candidate (kind, width,
image size) is trained with the shipped bundle's recipe (design space, exemplars, iterations,
seeds, schedule: scripts/train_model.sh with SPEC (the spec bundle.json records), MODEL_OUT,
OUTLINE=0) and its held-out metrics are recorded next to
the shipped bundle's in model_confirm_VOLUME.json. It suffices when it meets the shipped models'
bar (bar.json, as CheckBundle.cmake) and is within SUFFICES_DB / SUFFICES_SSIM of the better of
the two. `Testing/Benchmarks/report.py --confirm` picks the candidate from the sweep; alone:

    /usr/bin/python3 Testing/Models/confirm.py tooth --width 8 [--out Documentation/Results]
"""
import argparse
import functools
import json
import os
import subprocess
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
RESULTS = os.path.join(ROOT, "Documentation", "Results")

# a model suffices when its held-out PSNR and SSIM are this close to the best (of its scene's
# sweep, or of itself and the shipped bundle here)
SUFFICES_DB, SUFFICES_SSIM = 0.5, 0.01

# issue 4's bar for a shipped bundle, on its 1000 held-out exemplars (as CheckBundle.cmake)
with open(os.path.join(HERE, "bar.json")) as f:
    BAR = json.load(f)
BAR_PSNR, BAR_SSIM, BAR_INVARIANCE = BAR["psnr"], BAR["ssim"], BAR["invariance"]

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
    path = os.path.join(ROOT, "Data", "Models", volume, "bundle.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def confirm_path(volume, out):
    return os.path.join(out, f"model_confirm_{volume}.json")


def read_confirmation(volume, candidate, out, log=print):
    """The recorded full-recipe training of `candidate` (a sweep row: kind, width, image) in `out`
    or the committed results, if there is one for it and for the current shipped bundle (same
    metrics and recipe); None for an unreadable record."""
    shipped = shipped_bundle(volume)
    if shipped is None:
        return None
    committed = confirm_path(volume, RESULTS)
    for path in dict.fromkeys((confirm_path(volume, out), committed)):  # once when out is RESULTS
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


def confirm(volume, candidate, out, ddg, work, log=print):
    """Trains `candidate` with the shipped bundle's recipe (its design space, exemplars, iterations,
    seeds, schedule: scripts/train_model.sh, with the `ddg` program) in `work` and records its held-out metrics
    next to the shipped bundle's in `out`/model_confirm_VOLUME.json. Returns the record."""
    shipped = shipped_bundle(volume)
    iterations = shipped["metrics"]["train_iterations"]
    exemplars = shipped["training_exemplars"]
    weight = "100" if candidate["kind"].startswith("decoder (image") else "0"
    kind = candidate["kind"].split()[0]
    bundle = os.path.join(work, f"confirm_{volume}")
    # the shipped bundle's design space (e.g. lit exemplars): the spec it records, as `SPEC`
    os.makedirs(work, exist_ok=True)
    spec = os.path.join(work, f"confirm_{volume}_spec.json")
    with open(spec, "w") as f:
        json.dump(shipped["spec"], f, indent=1)
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
        env=dict(
            os.environ, DDG=ddg, WORK=bundle + "_work", MODEL_OUT=bundle, OUTLINE="0", SPEC=spec
        ),
    )
    with open(os.path.join(bundle, "bundle.json")) as f:
        metrics = json.load(f)["metrics"]
    record = {
        "volume": volume,
        "kind": candidate["kind"],
        "width": candidate["width"],
        "image": candidate["image"],
        "command": "SPEC=<the shipped bundle's spec> MODEL_OUT=DIR OUTLINE=0 scripts/train_model.sh "
        + " ".join(cmd[2:]),
        "exemplars": exemplars,
        "iterations": iterations,
        "wall_minutes": (time.time() - t0) / 60,
        "candidate": {k: metrics[k] for k in CONFIRM_KEYS},
        "shipped": {k: shipped["metrics"][k] for k in CONFIRM_KEYS},
    }
    with open(confirm_path(volume, out), "w") as f:
        json.dump(record, f, indent=1)
    return record


def confirmation_verdict(c):
    """Whether the candidate, trained like the shipped bundle, suffices: issue 4's bar and within
    SUFFICES_DB / SUFFICES_SSIM of the better of the two. (suffices, meets_bar, close)"""
    a, s = c["candidate"], c["shipped"]
    meets_bar = (
        a["psnr"] >= BAR_PSNR and a["ssim"] >= BAR_SSIM and a["invariance"] >= BAR_INVARIANCE
    )
    close = (
        a["psnr"] >= max(a["psnr"], s["psnr"]) - SUFFICES_DB
        and a["ssim"] >= max(a["ssim"], s["ssim"]) - SUFFICES_SSIM
    )
    return meets_bar and close, meets_bar, close


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("volume", help="a volume with a shipped bundle (Data/Models/VOLUME)")
    parser.add_argument("--width", type=int, required=True, help="the candidate's width")
    parser.add_argument("--image", type=int, default=64, help="its image size (default: 64)")
    parser.add_argument(
        "--kind",
        default="decoder (image loss)",
        help='its kind as the sweep tables name it (default: "decoder (image loss)")',
    )
    parser.add_argument("--out", default=RESULTS, help="where model_confirm_VOLUME.json goes")
    parser.add_argument("--ddg", default=os.path.join(ROOT, "build", "bin", "ddg"))
    args = parser.parse_args()
    if shipped_bundle(args.volume) is None:
        parser.error(f"no shipped bundle Data/Models/{args.volume}")
    candidate = {"kind": args.kind, "width": args.width, "image": args.image}
    record = confirm(
        args.volume, candidate, args.out, args.ddg, tempfile.mkdtemp(prefix="ddg-confirm-")
    )
    suffices, meets_bar, close = confirmation_verdict(record)
    a, s = record["candidate"], record["shipped"]
    print(
        f"{args.volume}: candidate {a['psnr']:.2f} dB / SSIM {a['ssim']:.4f}, shipped "
        f"{s['psnr']:.2f} / {s['ssim']:.4f}; meets the bar: {meets_bar}, within {SUFFICES_DB:g} dB "
        f"and {SUFFICES_SSIM:g} SSIM: {close}; suffices: {suffices} "
        f"({confirm_path(args.volume, args.out)})"
    )


if __name__ == "__main__":
    main()
