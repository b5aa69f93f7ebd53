"""Another volume's picture (issue 20, part 3): pairs of volumes of one kind, measured.

For every pair (A, B) and TF of carry_look_pairs.json:
  1. A is shown in ParaView with the TF (defined in percentiles of A's object voxels) and saved
     as a user saves it: File > Save Screenshot with the default GUI look (palette background,
     orientation axes), a camera drawn from the picture's seed as the realistic-screenshot suite
     draws it (Testing/Suite/make_suite.py), PNG or JPEG 85;
  2. B's reference: the same percentile definition evaluated on B (A's TF mapped by percentiles);
  3. the methods find a TF for B from A's picture:
       query        B's own design space (`ddg build --budget`, cached per volume) queried with
                    the picture (`ddg query`): the query alone
       query_carry  the query's design as the start of the carried look's fit (`ddg reconstruct
                    --carry-look --init`: free bins from it, refined by colour distribution;
                    without query in --methods, the query.json of an earlier run into OUT)
       carry        `ddg reconstruct --other-volume`: the look carried over
       match_other  `ddg reconstruct` as for a picture of B itself (what a user gets without
                    saying the picture is of another volume)
     and, for comparison, `match_same`: `ddg reconstruct` on B's own picture with the reference
     TF at the same camera (the same-volume match: what the look would reach if the picture had
     been of B);
  4. score: ParaView renders B with the found TF and with the reference at the suite's three
     canonical views on black and white (Testing/Suite/score.py): mean PSNR, and the mean
     colour-histogram EMD (CIELAB, `ddg compare`) of the six pairs.

Writes OUT/pairs.json, OUT/pairs.md and, with --chart, a chart of every case per method.
Run (pvpython under Xvfb; `ddg build` of the three B volumes the first time, BUDGET min each):
    scripts/with-xvfb.sh /usr/bin/pvpython Testing/Benchmarks/carry_look_pairs.py \
        --ddg build/bin/ddg --out build/pairs --chart build/pairs/chart.png [--budget 6]
The Debian volumes need the package mricron-data (scripts/setup.sh installs it).
carry_look_pairs_holdout.json holds two more TFs per pair, written before any figure of them, and
their pictures; volumes and pairs come from carry_look_pairs.json
(--pairs Testing/Benchmarks/carry_look_pairs_holdout.json; Documentation/DesignSpaces.md).
carry_look_pairs_holdout2.json holds two more again (2026-12-04), written for the rule that made
the pool of directions the carried look's default (Documentation/DesignSpaces.md).
"""
import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np
from vtkmodules.util import numpy_support
from vtkmodules.vtkIOImage import vtkNIFTIImageReader
from vtkmodules.vtkIOXML import vtkXMLImageDataReader, vtkXMLImageDataWriter

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
sys.path.insert(0, os.path.join(HERE, "..", "Suite"))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
from make_suite import JPEG_QUALITY, draw_camera, place_camera  # noqa: E402
from score import canonical_renders, score_renders  # noqa: E402
from suite_paraview import VolumeScene, use_default_palette  # noqa: E402

METHODS = ("query", "query_carry", "carry", "match_other", "match_same")
LABELS = {
    "query": "query alone (B's design space)",
    "query_carry": "query, then the look carried from it",
    "carry": "carried look (--other-volume)",
    "match_other": "match, as if the picture were of B",
    "match_same": "same-volume match (B's own picture)",
}


def write_vti(image, path):
    writer = vtkXMLImageDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    writer.SetCompressorTypeToZLib()
    writer.SetDataModeToAppended()
    writer.EncodeAppendedDataOff()
    if not writer.Write():
        raise SystemExit("cannot write %s" % path)


def volume_file(source, out_dir):
    """The .vti of a volume source of the pairs file (converted into out_dir once)."""
    kind, _, rest = source.partition(":")
    if kind == "data":
        return os.path.abspath(os.path.join(ROOT, "Data", "Volumes", rest + ".vti"))
    os.makedirs(out_dir, exist_ok=True)
    if kind == "shared":
        path = os.path.join(out_dir, rest + ".vti")
        if not os.path.isfile(path):
            from import_volumes import convert

            convert(os.path.join(ROOT, "..", "shared", "data", "volumes"), rest, path)
        return os.path.abspath(path)
    if kind == "debian":
        package, _, file = rest.partition(":")
        if not os.path.isfile(file):
            raise SystemExit(
                "%s is missing: install the Debian package %s (scripts/setup.sh)" % (file, package)
            )
        path = os.path.join(out_dir, os.path.basename(file).split(".")[0] + ".vti")
        if not os.path.isfile(path):
            reader = vtkNIFTIImageReader()
            reader.SetFileName(file)
            reader.Update()
            image = reader.GetOutput()
            image.SetOrigin(0.0, 0.0, 0.0)
            image.GetPointData().GetScalars().SetName("scalars")
            write_vti(image, path)
        return os.path.abspath(path)
    raise SystemExit("unknown volume source %s" % source)


def object_values(path):
    """The volume's object voxels: values above p1 + 10 % of (p99.9 - p1); and its range."""
    reader = vtkXMLImageDataReader()
    reader.SetFileName(path)
    reader.Update()
    values = numpy_support.vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars())
    values = values.astype(np.float64).ravel()
    p1, p999 = np.percentile(values, [1.0, 99.9])
    threshold = p1 + 0.1 * (p999 - p1)
    return values[values > threshold], float(values.min()), float(values.max())


def preset_of(tf, volume_path):
    """The TF's percentile definition evaluated on the volume: a ParaView preset."""
    objects, low, high = object_values(volume_path)

    def at(p):
        return float(np.percentile(objects, p))

    rgb = []
    for i, (p, r, g, b) in enumerate(tf["colour"]):
        x = at(p)
        if i == 0 and x > low:
            rgb += [low, r, g, b]
        rgb += [x, r, g, b]
    if rgb[-4] < high:
        rgb += [high] + rgb[-3:]
    points = []
    for i, (p, a) in enumerate(tf["opacity"]):
        x = at(p)
        if i == 0 and x > low:
            points += [low, 0.0, 0.5, 0.0]
        points += [x, a, 0.5, 0.0]
    if points[-4] < high:
        points += [high, points[-3], 0.5, 0.0]
    return {"Name": tf["name"], "ColorSpace": "RGB", "RGBPoints": rgb, "Points": points}


def picture(volume, preset, spec, path):
    """ParaView's screenshot of the volume with the preset, with the GUI look and the spec's
    camera moves (as the realistic-screenshot suite draws them)."""
    use_default_palette()
    moves = draw_camera(spec["seed"])
    scene = VolumeScene(volume, spec["size"], gui_look=True)
    try:
        scene.apply(preset)
        place_camera(scene, moves)
        options = {"Quality": JPEG_QUALITY} if spec["format"] == "jpg" else {}
        scene.screenshot(path, **options)
    finally:
        scene.close()
    return moves


def run(cmd, log):
    start = time.time()
    with open(log, "w") as f:
        f.write(" ".join(cmd) + "\n")
        f.flush()
        status = subprocess.call(cmd, stdout=f, stderr=subprocess.STDOUT)
    return time.time() - start, status


def emd_of(ddg, found_dir, stem, true_stem, renders):
    values = []
    for r in renders:
        name = "_az%03d_%s.png" % (r["azimuth"], r["background"])
        out = subprocess.check_output(
            [
                ddg,
                "compare",
                "--json",
                os.path.join(found_dir, stem + name),
                os.path.join(found_dir, true_stem + name),
            ]
        )
        values.append(json.loads(out)["emd"])
    return float(np.mean(values))


def bundle_for(args, name, volume):
    """B's design space built by `ddg build --budget` (once per volume)."""
    path = os.path.join(args.out, "bundles", name)
    if os.path.isfile(os.path.join(path, "bundle.json")):
        return path
    os.makedirs(os.path.dirname(path), exist_ok=True)
    log = path + ".log"
    cmd = [args.ddg, "build", "--volume", volume, "--out", path, "--budget", str(args.budget)]
    seconds, status = run(cmd + ["--threads", str(args.threads)], log)
    print("  built %s's design space in %.0f s (status %d)" % (name, seconds, status), flush=True)
    return path if status == 0 else None


def run_case(args, pair, tf, spec, volumes, previous):
    name = "%s_%s" % (pair["name"], tf["name"].split("_")[-1])
    work = os.path.abspath(os.path.join(args.out, name))
    os.makedirs(work, exist_ok=True)
    a, b = volumes[pair["a"]], volumes[pair["b"]]
    preset_a, preset_b = preset_of(tf, a), preset_of(tf, b)
    for stem, preset in (("tf_a", preset_a), ("reference", preset_b)):
        with open(os.path.join(work, stem + ".json"), "w") as f:
            json.dump([preset], f, indent=1)
    image = os.path.join(work, "picture_a." + spec["format"])
    moves = picture(a, preset_a, spec, image)
    own = os.path.join(work, "picture_b." + spec["format"])
    picture(b, preset_b, spec, own)
    threads = ["--threads", str(args.threads)]
    jobs = {}
    if "query" in args.methods:
        bundle = bundle_for(args, pair["b"], b)
        if bundle:
            view = os.path.join(work, "query_view.json")
            subprocess.check_call(
                [args.ddg, "view", "--volume", b, "--out", view, "--azimuth", "30"]
                + ["--elevation", "20"],
                stdout=subprocess.DEVNULL,
            )
            if os.path.isfile(os.path.join(work, "query.json")):  # never an older run's
                os.remove(os.path.join(work, "query.json"))
            jobs["query"] = [args.ddg, "query", "--model", bundle, "--volume", b, "--image", image]
            jobs["query"] += ["--view", view, "--out-tf", os.path.join(work, "query.json")]
    query_tf = os.path.join(work, "query.json")
    asked = "query_carry" in args.methods and "query" not in args.methods
    if asked and not os.path.isfile(query_tf):
        raise SystemExit(f"{name}: query_carry starts from {query_tf}; add query to --methods")
    if "query" in jobs or asked:
        # from the query's design: this run's, or an earlier run's of the same picture
        jobs["query_carry"] = [args.ddg, "reconstruct", "--volume", b, "--quiet"]
        jobs["query_carry"] += ["--threads", str(args.threads), "--target", image]
        jobs["query_carry"] += ["--carry-look", "--init", query_tf, "--seed", str(args.seed)]
        jobs["query_carry"] += ["--out", os.path.join(work, "query_carry.json")]
    base = [args.ddg, "reconstruct", "--volume", b, "--quiet"] + threads
    jobs["carry"] = base + ["--target", image, "--other-volume", "--seed", str(args.seed)]
    jobs["carry"] += ["--out", os.path.join(work, "carry.json")]
    jobs["match_other"] = base + [
        "--target",
        image,
        "--out",
        os.path.join(work, "match_other.json"),
    ]
    jobs["match_same"] = base + ["--target", own, "--out", os.path.join(work, "match_same.json")]
    renders = os.path.join(work, "renders")
    os.makedirs(renders, exist_ok=True)
    true = canonical_renders(b, preset_b, out_dir=renders, stem="reference")
    record = {"name": name, "pair": pair["name"], "a": pair["a"], "b": pair["b"]}
    record.update({"tf": tf["name"], "picture": spec, "camera_moves": moves, "methods": {}})
    record["methods"].update(previous.get(name, {}).get("methods", {}))
    print("%s: %s -> %s, %s" % (name, pair["a"], pair["b"], os.path.basename(image)), flush=True)
    for method in [m for m in METHODS if m in args.methods and m in jobs]:
        seconds, status = run(jobs[method], os.path.join(work, method + ".log"))
        entry = {"seconds": round(seconds, 1), "status": status}
        tf_path = os.path.join(work, method + ".json")
        if status == 0 and os.path.isfile(tf_path):
            found = canonical_renders(b, tf_path, out_dir=renders, stem=method)
            scored = score_renders(found, true)
            entry["psnr"] = scored["psnr"]
            entry["psnr_by_background"] = scored["psnr_by_background"]
            entry["emd"] = emd_of(args.ddg, renders, method, "reference", scored["renders"])
        else:
            entry["psnr"] = entry["emd"] = None
        record["methods"][method] = entry
        figure = (
            "failed"
            if entry["psnr"] is None
            else "%6.2f dB  EMD %5.2f"
            % (
                entry["psnr"],
                entry["emd"],
            )
        )
        print("  %-40s %s  %6.1f s" % (LABELS[method], figure, seconds), flush=True)
    return record


def markdown(records):
    lines = ["| case | A -> B | " + " | ".join(LABELS[m] for m in METHODS) + " |"]
    lines.append("|---|---|" + "---|" * len(METHODS))
    for r in records:
        cells = []
        for m in METHODS:
            e = r["methods"].get(m)
            cells.append(
                "-"
                if not e or e["psnr"] is None
                else "%.2f dB / EMD %.2f / %.0f s" % (e["psnr"], e["emd"], e["seconds"])
            )
        lines.append("| %s | %s -> %s | %s |" % (r["name"], r["a"], r["b"], " | ".join(cells)))
    return "\n".join(lines) + "\n"


def chart(records, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    x = np.arange(len(records))
    width = 0.8 / len(METHODS)
    for k, m in enumerate(METHODS):
        for ax, key in zip(axes, ("psnr", "emd")):
            values = [(r["methods"].get(m) or {}).get(key) or float("nan") for r in records]
            ax.bar(x + (k - (len(METHODS) - 1) / 2) * width, values, width, label=LABELS[m])
    for ax, title in zip(axes, ("canonical-view PSNR (dB, higher is better)", "EMD (lower)")):
        ax.set_xticks(x)
        ax.set_xticklabels([r["name"] for r in records], rotation=30, ha="right", fontsize=8)
        ax.set_title(title, fontsize=9)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def read_pairs(path):
    """The pairs file; a file of only TFs (keyed by pair name) and pictures, such as
    carry_look_pairs_holdout.json, takes its volumes and pairs from carry_look_pairs.json."""
    with open(path) as f:
        spec = json.load(f)
    if "pairs" in spec:
        return spec
    with open(os.path.join(HERE, "carry_look_pairs.json")) as f:
        base = json.load(f)
    unknown = set(spec["tfs"]) - {p["name"] for p in base["pairs"]}
    if unknown:
        raise SystemExit(f"{path}: no pair named {', '.join(sorted(unknown))}")
    pairs = [dict(p, tfs=spec["tfs"][p["name"]]) for p in base["pairs"] if p["name"] in spec["tfs"]]
    return {"volumes": base["volumes"], "pairs": pairs, "pictures": spec["pictures"]}


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--ddg", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--pairs", default=os.path.join(HERE, "carry_look_pairs.json"))
    parser.add_argument("--budget", type=float, default=6.0, help="ddg build --budget (minutes)")
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument(
        "--seed", type=int, default=1, help="the carried looks' --seed (their directions)"
    )
    parser.add_argument("--methods", nargs="+", default=list(METHODS), choices=METHODS)
    parser.add_argument("--case", action="append", help="only this pair name (repeatable)")
    parser.add_argument("--chart")
    args = parser.parse_args()
    args.out = os.path.abspath(args.out)
    spec = read_pairs(args.pairs)
    pairs = [p for p in spec["pairs"] if not args.case or p["name"] in args.case]
    needed = {v for p in pairs for v in (p["a"], p["b"])}
    volumes = {
        name: volume_file(source, os.path.join(args.out, "volumes"))
        for name, source in spec["volumes"].items()
        if name in needed
    }
    # methods measured before (another --methods run into the same folder) are kept
    listing = os.path.join(args.out, "pairs.json")
    previous = {}
    if os.path.isfile(listing):
        with open(listing) as f:
            previous = {r["name"]: r for r in json.load(f)}
    records = []
    for pair in pairs:
        for i, tf in enumerate(pair["tfs"]):
            picture_spec = spec["pictures"][i % len(spec["pictures"])]
            records.append(run_case(args, pair, tf, picture_spec, volumes, previous))
            with open(os.path.join(args.out, "pairs.json"), "w") as f:
                json.dump(records, f, indent=1)
    with open(os.path.join(args.out, "pairs.md"), "w") as f:
        f.write(markdown(records))
    print(markdown(records))
    if args.chart:
        chart(records, args.chart)


if __name__ == "__main__":
    main()
