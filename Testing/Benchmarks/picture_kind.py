#!/usr/bin/env python3
"""picture_kind.py: can a picture of another volume be told from a picture of this one? (issue 20)

Pictures: folders written by Testing/Suite/make_suite.py (one <case>/case.json each: ParaView
screenshots with the default GUI look, a camera nobody wrote down, PNG or JPEG). Every picture
is checked against every bundle / volume given; "same" when the picture's volume is the bundle's.

  query   `ddg query` of the picture on the bundle, at the bundle volume's oblique view
          (Data/Views/<volume>_oblique.json: the user's camera, not the picture's). Two figures:
          S1, the printed PSNR of the design against the picture (both framed on their content),
          and S2, the nearest outline design's latent distance over the outline's own spacing (the
          median, over 2 000 rows drawn evenly, of a row's distance to its nearest other row).
          Each gets one threshold for every bundle, from the calibration pictures (each against
          its own volume only): the lowest S1, the highest S2. A test query is "warned" beyond it.
  match   `ddg reconstruct --target PICTURE` on the volume (camera estimated): refused ("no
          camera explains the picture") or answered.

  /usr/bin/python3 Testing/Benchmarks/picture_kind.py --ddg build/bin/ddg \
      --bundle tooth=Data/Models/tooth --bundle engine=Data/Models/engine \
      --calibration build/calib --test build/suite build/suite_holdout --match-test build/suite \
      --out build/picture_kind.json
"""
import argparse
import glob
import json
import os
import re
import subprocess
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def read_latents(path):
    """outline.bin (Core/Gallery/Outline.h): header, count indices, count x dim halves."""
    data = open(path, "rb").read()
    dim, count = (int(v) for v in np.frombuffer(data[12:20], np.uint32))
    start = 32 + 8 * count
    values = np.frombuffer(data[start : start + 2 * count * dim], np.float16)
    return values.astype(np.float32).reshape(count, dim)


def outline_spacing(bundle):
    latents = read_latents(os.path.join(bundle, "outline.bin"))
    rows = np.linspace(0, len(latents) - 1, min(2000, len(latents))).astype(int)
    nearest = []
    for r in rows:
        d = np.sqrt(((latents - latents[r]) ** 2).sum(1))
        d[r] = np.inf
        nearest.append(d.min())
    return float(np.median(nearest))


def pictures(folders):
    for folder in folders:
        for case_file in sorted(glob.glob(os.path.join(folder, "*", "case.json"))):
            case = json.load(open(case_file))
            volume = os.path.splitext(os.path.basename(case["volume"]))[0]
            yield os.path.basename(folder), case["name"], volume, case["image"]


def volume_file(name):
    return os.path.join(ROOT, "Data", "Volumes", name + ".vti")


def query(ddg, bundle, volume, image):
    view = os.path.join(ROOT, "Data", "Views", volume + "_oblique.json")
    cmd = [ddg, "query", "--model", bundle, "--volume", volume_file(volume), "--image", image]
    cmd += ["--no-key"]  # S2 is a latent distance, over the latents' spacing
    out = subprocess.run(cmd + ["--view", view], capture_output=True, text=True, check=True)
    d1 = float(re.search(r"neighbour 1: .*latent distance ([0-9.]+)", out.stdout).group(1))
    s1 = float(re.search(r"against the picture: ([-0-9.]+) dB", out.stdout).group(1))
    return s1, d1


def record(folder, case, shows, name, **figures):
    """One picture checked against one design space or volume (`name`)."""
    return dict(set=folder, case=case, picture=shows, bundle=name, same=shows == name, **figures)


def run_queries(args, bundles, spacing, folders, own_only):
    rows = []
    for folder, case, shows, image in pictures(folders):
        for name in [shows] if own_only else list(bundles):
            s1, d1 = query(args.ddg, bundles[name], name, image)
            rows.append(record(folder, case, shows, name, s1=s1, s2=d1 / spacing[name]))
            print(
                "query %-14s %-7s -> %-7s S1 %6.2f dB  S2 %5.2f"
                % (case, shows, name, s1, rows[-1]["s2"]),
                flush=True,
            )
    return rows


def run_matches(args, volumes, folders):
    rows = []
    for folder, case, shows, image in pictures(folders):
        for name in volumes:
            out_tf = os.path.join(args.work, "%s_%s.json" % (case, name))
            cmd = [
                args.ddg,
                "reconstruct",
                "--volume",
                volume_file(name),
                "--target",
                image,
                "--out",
                out_tf,
                "--threads",
                str(args.threads),
                "--quiet",
            ]
            start = time.time()
            proc = subprocess.run(cmd, capture_output=True, text=True)
            refused = proc.returncode != 0 and "no camera explains" in proc.stderr
            if proc.returncode != 0 and not refused:
                raise SystemExit("%s failed: %s" % (" ".join(cmd), proc.stderr[-400:]))
            found = re.search(r"differs from it by ([0-9.]+) dB", proc.stderr)
            seconds = round(time.time() - start, 1)
            best_db = float(found.group(1)) if found else None
            rows.append(
                record(folder, case, shows, name, refused=refused, seconds=seconds, best_db=best_db)
            )
            print(
                "match %-14s %-7s -> %-7s %s"
                % (case, shows, name, "refused" if refused else "answered"),
                flush=True,
            )
    return rows


def count(rows, same, test):
    picked = [r for r in rows if r["same"] == same]
    return "%d of %d" % (sum(1 for r in picked if test(r)), len(picked))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--ddg", default=os.path.join(ROOT, "build", "bin", "ddg"))
    parser.add_argument("--bundle", action="append", default=[], help="VOLUME=BUNDLE_DIR")
    parser.add_argument("--calibration", nargs="*", default=[])
    parser.add_argument("--test", nargs="*", default=[])
    parser.add_argument("--match-test", nargs="*", default=[])
    parser.add_argument("--work", default="/tmp/picture_kind")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    bundles = dict(b.split("=", 1) for b in args.bundle)
    result = {}
    if args.calibration and args.test:
        spacing = {name: outline_spacing(path) for name, path in bundles.items()}
        calibration = run_queries(args, bundles, spacing, args.calibration, own_only=True)
        tests = run_queries(args, bundles, spacing, args.test, own_only=False)
        lowest_s1 = min(r["s1"] for r in calibration)
        highest_s2 = max(r["s2"] for r in calibration)
        summary = {
            "S1 threshold (dB)": lowest_s1,
            "S2 threshold": highest_s2,
            "S1 warned, same volume": count(tests, True, lambda r: r["s1"] < lowest_s1),
            "S1 warned, another volume": count(tests, False, lambda r: r["s1"] < lowest_s1),
            "S2 warned, same volume": count(tests, True, lambda r: r["s2"] > highest_s2),
            "S2 warned, another volume": count(tests, False, lambda r: r["s2"] > highest_s2),
        }
        result.update(
            spacing=spacing, calibration=calibration, queries=tests, query_summary=summary
        )
    if args.match_test:
        matches = run_matches(args, list(bundles), args.match_test)
        result["matches"] = matches
        result["match_summary"] = {
            "refused, same volume": count(matches, True, lambda r: r["refused"]),
            "refused, another volume": count(matches, False, lambda r: r["refused"]),
        }
    with open(args.out, "w") as f:
        json.dump(result, f, indent=1)
    for key in ("query_summary", "match_summary"):
        for k, v in result.get(key, {}).items():
            print("%s: %s" % (k, v))


if __name__ == "__main__":
    main()
