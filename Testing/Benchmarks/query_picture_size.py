"""What a large picture costs the query: `ddg query` with one screenshot at its own size and
enlarged (a Full HD, 4K and 8K copy, as HiDPI screens and posters give them), side by side.

A query reads a picture at most kQueryPictureSide (2048) pixels on its longer side, halving a
larger one first (Core's shrinkPicture): the answer should not change, and a large picture
should cost about what a small one does. For each size: the median wall time of --repeat runs,
the peak memory (maximum resident set of the process), and the answer (outline position, the
design against the picture); ratios to the picture at its own size. With --ddg-before, a second
`ddg` is run on the same pictures in the same run (for each picture, one binary's runs then the
other's), and the ratios after / before are printed too.

Run: /usr/bin/python3 Testing/Benchmarks/query_picture_size.py --ddg build/bin/ddg
         [--ddg-before OTHER/ddg] [--repeat 3] [--longest 1920 3840 7680]
"""
import argparse
import os
import re
import statistics
import subprocess
import tempfile
import time

from PIL import Image

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))


def query_command(ddg, args, picture, work):
    view = os.path.join(work, "view.json")
    if not os.path.isfile(view):
        subprocess.run(
            [ddg, "view", "--volume", args.volume, "--out", view], check=True, capture_output=True
        )
    cmd = [ddg, "query", "--model", args.model, "--volume", args.volume, "--image", picture]
    return cmd + ["--view", view, "--out-tf", os.path.join(work, "tf.json")]


def run_query(ddg, args, picture, work):
    cmd = query_command(ddg, args, picture, work)
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{proc.stderr}")
    return seconds, proc.stdout


def peak_memory_mb(ddg, args, picture, work):
    """The query's maximum resident set (MB), from a run under /usr/bin/time."""
    cmd = ["/usr/bin/time", "-f", "%M"] + query_command(ddg, args, picture, work)
    proc = subprocess.run(cmd, capture_output=True, text=True, check=True)
    return int(proc.stderr.strip().splitlines()[-1]) / 1024


def answer(out):
    position = re.search(r"outline position \(([-0-9.]+), ([-0-9.]+)\)", out)
    figure = re.search(r"against the picture: ([-0-9.]+) dB", out)
    return (float(position.group(1)), float(position.group(2))), float(figure.group(1))


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--ddg", required=True)
    parser.add_argument("--ddg-before", help="another ddg to compare with, side by side")
    parser.add_argument("--model", default=os.path.join(ROOT, "Data", "Models", "tooth"))
    parser.add_argument("--volume", default=os.path.join(ROOT, "Data", "Volumes", "tooth.vti"))
    parser.add_argument(
        "--picture",
        default=os.path.join(ROOT, "Data", "Screenshots", "tooth_dentin_enamel_oblique.png"),
    )
    parser.add_argument("--longest", type=int, nargs="+", default=[1920, 3840, 7680])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    binaries = {"after": args.ddg}
    if args.ddg_before:
        binaries["before"] = args.ddg_before
    with tempfile.TemporaryDirectory() as work:
        original = Image.open(args.picture).convert("RGB")
        pictures = [("own size", args.picture, original.size)]
        for longest in args.longest:
            f = longest / max(original.size)
            size = (round(original.size[0] * f), round(original.size[1] * f))
            path = os.path.join(work, f"picture_{longest}.png")
            original.resize(size, Image.LANCZOS).save(path)
            pictures.append((f"{longest} px", path, size))
        rows = {}
        for label, path, size in pictures:
            for name, ddg in binaries.items():
                times, out = [], ""
                for _ in range(args.repeat):
                    seconds, out = run_query(ddg, args, path, work)
                    times.append(seconds)
                memory = peak_memory_mb(ddg, args, path, work)
                rows[(label, name)] = (statistics.median(times), memory, answer(out), size)
    print(
        f"picture: {os.path.relpath(args.picture, ROOT)}; model {os.path.relpath(args.model, ROOT)}"
    )
    print(f"median of {args.repeat} runs of `ddg query`; peak memory of one more run\n")
    print(
        "| picture | ddg | size | time (s) | × own size | peak memory (MB) | × own size "
        "| outline position | against the picture |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for label, _, size in pictures:
        for name in binaries:
            t, m, ((u, v), dB), _ = rows[(label, name)]
            t0, m0 = rows[("own size", name)][:2]
            print(
                f"| {label} | {name} | {size[0]} x {size[1]} | {t:.2f} | {t / t0:.2f} | {m:.0f} "
                f"| {m / m0:.2f} | ({u:.3f}, {v:.3f}) | {dB:.2f} dB |"
            )
    if "before" in binaries:
        print("\nafter / before:")
        for label, _, _ in pictures:
            ta, ma = rows[(label, "after")][:2]
            tb, mb = rows[(label, "before")][:2]
            print(f"  {label}: time {ta / tb:.2f}, peak memory {ma / mb:.2f}")


if __name__ == "__main__":
    main()
