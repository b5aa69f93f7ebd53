"""The screenshot -> TF methods on every case of the suite, timed and scored.

For each case of a suite built by make_suite.py (OUT/suite.json) it runs, timing each (wall
clock, including the `ddg` process start and loading):
  query                 `ddg query --out-tf` with the volume's shipped model (Data/Models/<volume>;
                        cases of volumes without one skip it), at the true view
  match                 `ddg reconstruct` without a view: background, overlays and camera
                        estimated from the picture (Core's matchPicture), from a grey TF
  match_from_query      the query, then the match started from the query's TF (`--init`); its
                        time is both commands' (volumes without a model skip it)
  match_true_camera     `ddg reconstruct --view <true view>`: the camera given (the upper bound
                        for what a user without the camera can get)
and, only when asked (--methods), "reconstruct_true_camera_default_background": the true camera
with the background the project's tools assume by default (0.329, 0.349, 0.427: `ddg view`'s and
the view JSON's default) instead of what ParaView draws (0.32, 0.34, 0.43), passed as
`--background` (before issue 17 the view's background was used as is).
It scores each found TF against the true one with score.py (ParaView renders at azimuth 0/120/240,
elevation 20, on black and white, mean PSNR). Writes OUT/baseline.json (every figure,
per render too), OUT/baseline.md (the table) and, with --chart, a chart of time against score;
keeps each method's TF, log and (with --keep-renders) the score renders under
OUT/<case>/baseline/.

Run (pvpython under a display; ~1 min per case):
    scripts/with-xvfb.sh /usr/bin/pvpython Testing/Suite/baseline.py --suite build/suite \\
        --ddg build/bin/ddg --out build/suite/baseline [--threads 2] [--chart chart.png]
"""
import argparse
import json
import os
import platform
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from score import canonical_renders, score_renders, SIZE  # noqa: E402
from suite_paraview import DEFAULT_PALETTE_BACKGROUND  # noqa: E402

METHODS = ("query", "match", "match_from_query", "match_true_camera")
# not run by default (--methods): the true camera in a view JSON with the background the project's
# tools assume by default, the RenderView's Background property (ddg view, the view JSON's default)
EXTRA_METHODS = ("reconstruct_true_camera_default_background",)
PROJECT_DEFAULT_BACKGROUND = [0.329, 0.349, 0.427]
LABELS = {
    "query": "query (shipped model, true view)",
    "match": "match (camera estimated), from grey",
    "match_from_query": "query, then match from its TF",
    "match_true_camera": "match at the true camera",
    "reconstruct_true_camera_default_background": "reconstruct, true camera, background "
    + " ".join(str(x) for x in PROJECT_DEFAULT_BACKGROUND),
}


def run(cmd, log):
    """Runs a command, its output into ``log``; returns (seconds, exit status)."""
    start = time.time()
    with open(log, "w") as f:
        f.write(" ".join(cmd) + "\n")
        f.flush()
        status = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT).returncode
    return time.time() - start, status


def last_lines(path, n=2):
    with open(path) as f:
        return " | ".join(line.strip() for line in f.read().strip().splitlines()[-n:])


def run_case(case, args, models_dir):
    """Runs every method on one case; returns its record."""
    work = os.path.join(os.path.dirname(case["image"]), "baseline")
    os.makedirs(work, exist_ok=True)
    ddg, volume, image = args.ddg, case["volume"], case["image"]
    threads = ["--threads", str(args.threads)]
    name = os.path.splitext(os.path.basename(volume))[0]
    model = os.path.join(models_dir, name)
    jobs = {}
    if os.path.isfile(os.path.join(model, "bundle.json")):
        jobs["query"] = [
            [ddg, "query", "--model", model, "--volume", volume, "--image", image]
            + [
                "--view",
                case["true_view"],
                "--out-tf",
                os.path.join(work, "query.json"),
            ]
        ]
    match = [
        ddg,
        "reconstruct",
        "--volume",
        volume,
        "--target",
        image,
        "--quiet",
    ] + threads
    jobs["match"] = [
        match
        + ["--out", os.path.join(work, "match.json")]
        + ["--out-view", os.path.join(work, "match_view.json")]
    ]
    if "query" in jobs:
        query_tf = os.path.join(work, "query_for_match.json")
        jobs["match_from_query"] = [
            jobs["query"][0][:-1] + [query_tf],
            match
            + ["--init", query_tf, "--out", os.path.join(work, "match_from_query.json")]
            + ["--out-view", os.path.join(work, "match_from_query_view.json")],
        ]
    jobs["match_true_camera"] = [
        match
        + [
            "--view",
            case["true_view"],
            "--out",
            os.path.join(work, "match_true_camera.json"),
        ]
    ]
    with open(case["true_view"]) as f:
        other_background = dict(json.load(f), background=PROJECT_DEFAULT_BACKGROUND)
    other_view = os.path.join(work, "true_camera_default_background_view.json")
    with open(other_view, "w") as f:
        json.dump(other_background, f, indent=2)
    jobs["reconstruct_true_camera_default_background"] = [
        [
            ddg,
            "reconstruct",
            "--volume",
            volume,
            "--target",
            image,
            "--view",
            other_view,
        ]
        + ["--background"]
        + [str(x) for x in PROJECT_DEFAULT_BACKGROUND]
        + [
            "--out",
            os.path.join(work, "reconstruct_true_camera_default_background.json"),
        ]
        + ["--quiet"]
        + threads
    ]
    jobs = {m: c for m, c in jobs.items() if m in args.methods}

    keep = work if args.keep_renders else None
    lighting = case.get("lighting")  # the picture's: both TFs scored with the same Shade
    true = canonical_renders(volume, case["true_tf"], args.score_size, keep, "true", lighting)
    results = {}
    for method, commands in jobs.items():
        log = os.path.join(work, method + ".log")
        seconds, status = 0.0, 0
        for i, cmd in enumerate(commands):
            s, status = run(cmd, log if i == len(commands) - 1 else log + ".%d" % i)
            seconds += s
            if status != 0:
                break
        tf = os.path.join(work, method + ".json")
        entry = {"seconds": seconds, "status": status, "tf": tf, "log": last_lines(log)}
        if status == 0 and os.path.isfile(tf):
            found = canonical_renders(volume, tf, args.score_size, keep, method, lighting)
            entry.update(score_renders(found, true))
        else:
            entry["psnr"] = None
        view_file = os.path.join(work, method + "_view.json")
        if method in ("match", "match_from_query") and status == 0 and os.path.isfile(view_file):
            with open(view_file) as f:
                found_view = json.load(f)
            entry["estimated_camera"] = found_view["camera"]
            entry["estimated_shade"] = bool((found_view.get("lighting") or {}).get("shade"))
        results[method] = entry
        psnr = "failed" if entry["psnr"] is None else "%.2f dB" % entry["psnr"]
        print(f"  {LABELS[method]:52s} {psnr:>9s}  {seconds:6.1f} s", flush=True)
    return {
        "name": case["name"],
        "volume": name,
        "size": case["size"],
        "format": case["format"],
        "camera_moves": case["camera_moves"],
        "methods": results,
    }


def markdown(records, meta):
    methods = [m for m in METHODS + EXTRA_METHODS if m in meta["methods"]]
    lines = [
        "# Screenshot -> TF methods on the suite",
        "",
        "Score: mean PSNR (dB) of ParaView's renders of the found TF against the true TF at "
        "azimuth 0/120/240, elevation 20, on black and on white (%dx%d); in brackets black / "
        "white. Time: wall clock of the `ddg` commands (s), %s thread(s), %s."
        % (
            meta["score_size"][0],
            meta["score_size"][1],
            meta["threads"] or "all",
            meta["host"],
        ),
        "",
        "| case | volume | size | format | azimuth / elevation / roll / zoom | "
        + " | ".join(LABELS[m] + ": dB (black / white), s" for m in methods)
        + " |",
        "|---" * (5 + len(methods)) + "|",
    ]
    for r in records:
        m = r["camera_moves"]
        cells = []
        for method in methods:
            e = r["methods"].get(method)
            if e is None:
                cells.append("—")
            elif e["psnr"] is None:
                refused = "no camera explains the picture" in e.get("log", "")
                cells.append("%s (%.1f s)" % ("refused" if refused else "failed", e["seconds"]))
            else:
                b = e["psnr_by_background"]
                cells.append(
                    "%.2f (%.2f / %.2f), %.1f s" % (e["psnr"], b["black"], b["white"], e["seconds"])
                )
        lines.append(
            "| %s | %s | %dx%d | %s | %.0f° / %.0f° / %.0f° / %.2f | %s |"
            % (
                r["name"],
                r["volume"],
                r["size"][0],
                r["size"][1],
                r["format"].upper(),
                m["azimuth"],
                m["elevation"],
                m["roll"],
                m["zoom"],
                " | ".join(cells),
            )
        )
    lines.append("")
    for method in methods:
        values = [
            r["methods"][method]["psnr"]
            for r in records
            if method in r["methods"] and r["methods"][method]["psnr"] is not None
        ]
        times = [r["methods"][method]["seconds"] for r in records if method in r["methods"]]
        runs = [r for r in records if method in r["methods"]]
        failed = len(runs) - len(values)
        at_bar = sum(1 for v in values if v >= 35.0)
        if values:
            lines.append(
                "- %s: mean %.2f dB over %d cases (min %.2f, max %.2f), %d of %d cases >= 35 dB, "
                "%d refused or failed, mean %.1f s"
                % (
                    LABELS[method],
                    sum(values) / len(values),
                    len(values),
                    min(values),
                    max(values),
                    at_bar,
                    len(runs),
                    failed,
                    sum(times) / len(times),
                )
            )
    return "\n".join(lines) + "\n"


def chart(records, meta, path):
    """Time against score, one point per case and method, and each method's mean."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for method in [m for m in METHODS + EXTRA_METHODS if m in meta["methods"]]:
        pts = [
            (r["methods"][method]["seconds"], r["methods"][method]["psnr"])
            for r in records
            if method in r["methods"] and r["methods"][method]["psnr"] is not None
        ]
        if not pts:
            continue
        xs, ys = zip(*pts)
        dots = ax.scatter(xs, ys, alpha=0.45, s=22)
        ax.scatter(
            [sum(xs) / len(xs)],
            [sum(ys) / len(ys)],
            color=dots.get_facecolor()[0],
            edgecolor="black",
            s=90,
            marker="D",
            label="%s (mean %.1f dB, %.1f s)"
            % (LABELS[method], sum(ys) / len(ys), sum(xs) / len(xs)),
        )
    ax.axhline(35, color="grey", linestyle="--", linewidth=0.8)
    ax.set_xlabel("wall-clock seconds (ddg commands, %s threads)" % (meta["threads"] or "all"))
    ax.set_ylabel("score: mean PSNR of canonical renders (dB)")
    ax.set_title("Screenshot -> TF on the suite (%d cases)" % len(records))
    ax.legend(fontsize=7, loc="lower right")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--suite", required=True, help="folder written by make_suite.py")
    parser.add_argument("--ddg", required=True, help="the ddg program")
    parser.add_argument("--out", required=True, help="where baseline.json and .md go")
    parser.add_argument(
        "--models",
        default=os.path.join(HERE, "..", "..", "Data", "Models"),
        help="model bundles",
    )
    parser.add_argument("--threads", type=int, default=0, help="ddg reconstruct --threads")
    parser.add_argument("--score-size", type=int, nargs=2, default=list(SIZE))
    parser.add_argument("--chart", help="also chart time against score (PNG) here")
    parser.add_argument("--case", action="append", help="only this case (repeatable)")
    parser.add_argument("--keep-renders", action="store_true")
    parser.add_argument(
        "--methods",
        nargs="+",
        default=list(METHODS),
        choices=METHODS + EXTRA_METHODS,
        help="methods to run (default: %s)" % " ".join(METHODS),
    )
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.suite, "suite.json")) as f:
        listing = json.load(f)["cases"]
    records = []
    start = time.time()
    for path in listing:
        with open(path) as f:
            case = json.load(f)
        if args.case and case["name"] not in args.case:
            continue
        # a figure's render may have another background (make_suite.py's "figure" cases)
        assert case.get("figure") or case["background"] == DEFAULT_PALETTE_BACKGROUND
        print(case["name"], flush=True)
        records.append(run_case(case, args, os.path.abspath(args.models)))
    meta = {
        "suite": os.path.abspath(args.suite),
        "ddg": os.path.abspath(args.ddg),
        "threads": args.threads,
        "methods": args.methods,
        "score_size": args.score_size,
        "host": "%s, %d cores" % (platform.machine(), os.cpu_count()),
        "minutes": (time.time() - start) / 60.0,
    }
    with open(os.path.join(args.out, "baseline.json"), "w") as f:
        json.dump({"meta": meta, "cases": records}, f, indent=2)
    with open(os.path.join(args.out, "baseline.md"), "w") as f:
        f.write(markdown(records, meta))
    if args.chart:
        chart(records, meta, args.chart)
    print("wrote %s (%.1f min)" % (os.path.join(args.out, "baseline.md"), meta["minutes"]))


if __name__ == "__main__":
    main()
