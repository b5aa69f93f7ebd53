#!/usr/bin/env python3
"""model_sweep.py: the model-size sweep of issue 4 -- which network is the smallest that suffices.

Trains every configuration on the same generated exemplars for the same wall-clock budget and
evaluates it on the same held-out exemplars (never seen in training), then prints one markdown
table: kind (unet = the paper's U-Net renderer, decoder = latent -> explicit TF, ray cast),
analyzer width, image size, parameters, bundle size, training iterations and exemplars/s,
analyzer and renderer latency (one image, 2 threads), PSNR, SSIM, EMD and invariance.

  /usr/bin/python3 Testing/Benchmarks/model_sweep.py --ddg build/bin/ddg --volume tooth \
      --minutes 4 --out Documentation/Results/model_sweep_tooth.md

Exemplars are generated once per image size into --work (reused when present). Every
configuration trains with a constant learning rate for the same wall-clock budget (the shipped
bundles add a cosine schedule over a fixed iteration count: scripts/train_model.sh).
"""
import argparse
import json
import os
import subprocess
import sys
import time

CONFIGS = [  # (kind, width, image size, extra train arguments)
    ("decoder", 8, 64, ["--image-weight", "100"]),
    ("decoder", 16, 64, ["--image-weight", "100"]),
    ("decoder", 32, 64, ["--image-weight", "100"]),
    ("decoder", 16, 32, ["--image-weight", "100"]),
    ("decoder", 16, 64, ["--image-weight", "0"]),
    ("unet", 16, 64, []),
]


def run(cmd):
    print("+", " ".join(cmd), flush=True)
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


def du(path):
    return sum(os.path.getsize(os.path.join(d, f)) for d, _, fs in os.walk(path) for f in fs)


def main():
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--ddg", default="build/bin/ddg")
    ap.add_argument("--volume", default="tooth", help="name under Data/Volumes")
    ap.add_argument(
        "--data-dir", default=os.path.join(os.path.dirname(__file__), "..", "..", "Data")
    )
    ap.add_argument("--minutes", type=float, default=4.0, help="training budget per configuration")
    ap.add_argument("--count", type=int, default=10000, help="training exemplars")
    ap.add_argument("--heldout", type=int, default=200, help="held-out exemplars evaluated")
    ap.add_argument("--work", default="build/sweep")
    ap.add_argument("--only", type=int, nargs="*", help="indices of CONFIGS to run")
    ap.add_argument("--out", help="also write the table (markdown) here")
    a = ap.parse_args()
    vol = os.path.join(a.data_dir, "Volumes", a.volume + ".vti")
    os.makedirs(a.work, exist_ok=True)
    rows = []
    for k, (kind, width, size, extra) in enumerate(CONFIGS):
        if a.only and k not in a.only:
            continue
        data = {}
        for name, count, first in (("train", a.count, 0), ("heldout", a.heldout, 1000000)):
            d = os.path.join(a.work, f"{a.volume}_{size}_{name}_{count}")
            if not os.path.exists(os.path.join(d, "dataset.json")):
                run(
                    [
                        a.ddg,
                        "generate",
                        "--volume",
                        vol,
                        "--count",
                        str(count),
                        "--size",
                        str(size),
                        "--seed",
                        "1",
                        "--first-index",
                        str(first),
                        "--out",
                        d,
                        "--quiet",
                    ]
                )
            data[name] = d
        bundle = os.path.join(a.work, f"{a.volume}_{kind}_w{width}_s{size}_{k}")
        lr = "1e-3" if kind == "decoder" else "2e-4"
        t0 = time.time()
        run(
            [
                a.ddg,
                "train",
                "--kind",
                kind,
                "--volume",
                vol,
                "--data",
                data["train"],
                "--eval-data",
                data["heldout"],
                "--eval-count",
                str(a.heldout),
                "--check-count",
                "1",
                "--out",
                bundle,
                "--width",
                str(width),
                "--lr",
                lr,
                "--minutes",
                str(a.minutes),
                "--seed",
                "1",
                "--threads",
                "2",
                "--quiet",
            ]
            + extra
        )
        wall = time.time() - t0
        m = json.load(open(os.path.join(bundle, "bundle.json")))["metrics"]
        weights = os.path.getsize(os.path.join(bundle, "model.pt"))
        label = kind
        if kind == "decoder":
            label += " (image loss)" if extra[-1] != "0" else " (TF parameters only)"
        rows.append(
            (
                label,
                width,
                size,
                m["parameters"],
                weights / 1e6,
                du(bundle) / 1e6,
                m["train_iterations"],
                m["train_exemplars_per_second"],
                m["analyzer_ms"],
                m["renderer_ms"],
                m["psnr"],
                m["ssim"],
                m["emd"],
                m["invariance"],
                wall / 60,
            )
        )
    head = (
        "| kind | width | image | parameters | weights MB | bundle MB | iterations | exemplars/s "
        "| analyzer ms | renderer ms | PSNR dB | SSIM | EMD | invariance | wall min |"
    )
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for r in rows:
        lines.append(
            "| %s | %d | %d | %d | %.2f | %.2f | %d | %.0f | %.2f | %.2f | %.2f | %.3f | %.2f | %.3f | %.1f |"
            % r
        )
    table = "\n".join(lines)
    print(table)
    if a.out:
        with open(a.out, "w") as f:
            f.write(
                f"# Model sweep: {a.volume}, {a.minutes:g} min of training each, {a.count} training "
                f"exemplars, {a.heldout} held-out\n\nProduced by `Testing/Benchmarks/model_sweep.py` "
                f"on {os.cpu_count()} cores.\n\n{table}\n"
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
