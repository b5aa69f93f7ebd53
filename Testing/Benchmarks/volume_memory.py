#!/usr/bin/env python3
"""volume_memory.py: what a large volume costs in memory and time (issue 21, part 1).

Makes a 512^3 uint8 volume (the project's Bonsai, Data/Volumes/bonsai.vti, upsampled 2x by
trilinear interpolation, spacing halved: the same object at 8x the voxels; 134 MB) and runs on it,
each under /usr/bin/time -v (peak resident set size, wall seconds):

  render        ddg render, 1D TF (Data/TransferFunctions/bonsai_tree.json), unlit
  render_lit    the same with Shade on (ParaView's default coefficients)
  render_2d     ddg render with a 2D TF (the gradient axis taken per sample)
  recon1d       ddg reconstruct from the render, view given, --iterations N
  recon2d       ddg reconstruct --2d, the same
  process       ddg render of Data/Volumes/neghip.vti (64^3): the process alone (libraries,
                libtorch, VTK), to tell what the volume costs from what the program costs
  kernel*       ddg render of Data/Volumes/engine.vti at 1200 x 1000, 1D / Shade / 2D / 2D Shade:
                the render time ddg prints (the ray march alone, loading excluded)
  kernel_recon* ddg reconstruct on Engine from those renders (1D, Shade, 2D), --iterations N:
                the fit time ddg prints (forward, adjoint and Adam steps alone)

and prints per command the peak, the bytes per voxel above the data itself ((peak - data bytes) /
voxels, the issue's measure, the process included) and above data and process ((peak - data -
process peak) / voxels). With --baseline-ddg (another build of ddg, e.g. an older commit's), both
run in turn, A B A B, --repeat times, and the medians and ratios A/B are printed side by side.

  /usr/bin/python3 Testing/Benchmarks/volume_memory.py --ddg build/bin/ddg \
      [--baseline-ddg /tmp/old/ddg] --work /tmp/volmem --out Documentation/Results/volume_memory

Writes OUT.json and OUT.md. Bars (the issue's): render and 1D reconstruct <= 2.5 bytes per voxel
above the data, 2D <= 4.5; speed not worse than the baseline by more than 10 %.
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys

import numpy as np
from vtkmodules.util import numpy_support
from vtkmodules.vtkIOXML import vtkXMLImageDataReader

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DATA = os.path.join(ROOT, "Data")


def make_volume(work, factor):
    """Bonsai upsampled `factor` times per axis (trilinear; one factor, or one per axis x, y, z),
    written as raw + JSON; its path."""
    factors = tuple(factor) if isinstance(factor, (tuple, list)) else (factor,) * 3
    name = (
        "bonsai_x" + "x".join(str(f) for f in factors)
        if len(set(factors)) > 1
        else f"bonsai_x{factors[0]}"
    )
    json_path = os.path.join(work, name + ".json")
    if os.path.exists(json_path):
        return json_path
    reader = vtkXMLImageDataReader()
    reader.SetFileName(os.path.join(DATA, "Volumes", "bonsai.vti"))
    reader.Update()
    image = reader.GetOutput()
    nx, ny, nz = image.GetDimensions()
    a = numpy_support.vtk_to_numpy(image.GetPointData().GetScalars()).reshape(nz, ny, nx)
    a = a.astype(np.float32)
    for axis in range(3):  # numpy axes z, y, x
        n, factor_axis = a.shape[axis], factors[2 - axis]
        if factor_axis == 1:
            continue
        x = np.linspace(0, n - 1, factor_axis * n)
        i0 = np.floor(x).astype(int)
        i1 = np.minimum(i0 + 1, n - 1)
        shape = [1, 1, 1]
        shape[axis] = -1
        f = (x - i0).astype(np.float32).reshape(shape)
        a = np.take(a, i0, axis) * (1 - f) + np.take(a, i1, axis) * f
    a = np.clip(np.rint(a), 0, 255).astype(np.uint8)
    raw = os.path.join(work, name + ".raw")
    a.tofile(raw)
    spacing = [s / f for s, f in zip(image.GetSpacing(), factors)]
    origin = list(image.GetOrigin())
    with open(json_path, "w") as f:
        json.dump(
            {
                "dims": [a.shape[2], a.shape[1], a.shape[0]],
                "dtype": "uint8",
                "spacing": spacing,
                "origin": origin,
                "file": name + ".raw",
                "source": "Data/Volumes/bonsai.vti upsampled by trilinear interpolation",
            },
            f,
        )
    return json_path


def view_file(work, lit):
    view = json.load(open(os.path.join(DATA, "Views", "bonsai_oblique.json")))
    if lit:
        view["lighting"] = {"shade": True}
    path = os.path.join(work, "view_lit.json" if lit else "view.json")
    json.dump(view, open(path, "w"))
    return path


def timed(cmd, env=None):
    """(peak MB, wall seconds, ddg's own render milliseconds or None) of one run under
    /usr/bin/time -v."""
    proc = subprocess.run(["/usr/bin/time", "-v"] + cmd, capture_output=True, text=True, env=env)
    if proc.returncode != 0:
        raise SystemExit(f"failed: {' '.join(cmd)}\n{proc.stdout[-800:]}{proc.stderr[-1500:]}")
    peak = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", proc.stderr).group(1))
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", proc.stderr).group(
        1
    )
    seconds = 0.0
    for part in wall.split(":"):
        seconds = seconds * 60 + float(part)
    render = re.search(r"render ([0-9.]+) ms", proc.stdout)
    fit = re.search(r"fit ([0-9.]+)[;)]", proc.stdout + proc.stderr)
    own = float(render.group(1)) if render else (1000 * float(fit.group(1)) if fit else None)
    return peak / 1024.0, seconds, own


def commands(ddg, work, volume, iterations, threads, tag):
    """(name, command) pairs in the order they run (renders before the reconstructions that
    read them)."""
    common = ["--threads", str(threads)]

    def render(vol, tf, view, out):
        return [
            ddg,
            "render",
            "--volume",
            vol,
            "--tf",
            tf,
            "--view",
            view,
            "--out",
            os.path.join(work, out),
        ] + common

    def reconstruct(vol, target, view, out, extra=()):
        return (
            [
                ddg,
                "reconstruct",
                "--volume",
                vol,
                "--target",
                os.path.join(work, target),
                "--view",
                view,
                "--out",
                os.path.join(work, out),
                "--iterations",
                str(iterations),
                "--quiet",
            ]
            + list(extra)
            + common
        )

    tfs = os.path.join(DATA, "TransferFunctions")
    tf1, tf2 = os.path.join(tfs, "bonsai_tree.json"), os.path.join(tfs, "engine_2d_edges.json")
    view, lit = view_file(work, False), view_file(work, True)
    # the march's own time: Engine (8.4 M voxels) at 1200 x 1000, loading excluded
    engine = os.path.join(DATA, "Volumes", "engine.vti")
    engine_tf = os.path.join(tfs, "engine_block.json")
    kernel = json.load(open(os.path.join(DATA, "Views", "engine_oblique.json")))
    kernel["size"] = [1200, 1000]
    kview = os.path.join(work, "kernel.json")
    json.dump(kernel, open(kview, "w"))
    kernel["lighting"] = {"shade": True}
    klit = os.path.join(work, "kernel_lit.json")
    json.dump(kernel, open(klit, "w"))
    return [
        ("kernel", render(engine, engine_tf, kview, f"kernel_{tag}.png")),
        ("kernel_lit", render(engine, engine_tf, klit, f"kernel_lit_{tag}.png")),
        ("kernel_2d", render(engine, tf2, kview, f"kernel_2d_{tag}.png")),
        ("kernel_2d_lit", render(engine, tf2, klit, f"kernel_2d_lit_{tag}.png")),
        ("kernel_recon", reconstruct(engine, f"kernel_{tag}.png", kview, f"kr_{tag}.json")),
        (
            "kernel_recon_lit",
            reconstruct(engine, f"kernel_lit_{tag}.png", klit, f"kr_lit_{tag}.json"),
        ),
        (
            "kernel_recon_2d",
            reconstruct(engine, f"kernel_{tag}.png", kview, f"kr_2d_{tag}.json", ["--2d"]),
        ),
        (
            "process",
            render(
                os.path.join(DATA, "Volumes", "neghip.vti"),
                os.path.join(tfs, "neghip_shells.json"),
                os.path.join(DATA, "Views", "neghip_oblique.json"),
                f"small_{tag}.png",
            ),
        ),
        ("render", render(volume, tf1, view, f"ref_{tag}.png")),
        ("render_lit", render(volume, tf1, lit, f"lit_{tag}.png")),
        ("render_2d", render(volume, tf2, view, f"twod_{tag}.png")),
        ("recon1d", reconstruct(volume, f"ref_{tag}.png", view, f"r1_{tag}.json")),
        ("recon2d", reconstruct(volume, f"ref_{tag}.png", view, f"r2_{tag}.json", ["--2d"])),
    ]


def env_for(ddg):
    """A copied ddg (a baseline) finds its own libraries beside it."""
    env = dict(os.environ)
    here = os.path.dirname(os.path.abspath(ddg))
    if any(f.startswith("libDDGCore") for f in os.listdir(here)):
        env["LD_LIBRARY_PATH"] = here + ":" + env.get("LD_LIBRARY_PATH", "")
    return env


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--ddg", required=True)
    p.add_argument("--baseline-ddg", help="another ddg build run side by side (B)")
    p.add_argument("--work", default="/tmp/volume_memory")
    p.add_argument("--out", help="write OUT.json and OUT.md")
    p.add_argument("--factor", type=int, default=2, help="upsampling per axis (2: 512^3)")
    p.add_argument("--iterations", type=int, default=100)
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--threads", type=int, default=2)
    args = p.parse_args()
    os.makedirs(args.work, exist_ok=True)
    volume = make_volume(args.work, args.factor)
    meta = json.load(open(volume))
    voxels = int(np.prod(meta["dims"]))
    data_mb = voxels / 1024.0 / 1024.0  # uint8
    builds = [("A", args.ddg)] + ([("B", args.baseline_ddg)] if args.baseline_ddg else [])
    runs = {}
    for r in range(args.repeat):
        for tag, ddg in builds:
            for name, cmd in commands(ddg, args.work, volume, args.iterations, args.threads, tag):
                peak, wall, render = timed(cmd, env_for(ddg))
                runs.setdefault((tag, name), []).append((peak, wall, render))
                print(
                    f"run {r + 1} {tag} {name}: peak {peak:.0f} MB, {wall:.2f} s"
                    + (f", render {render:.0f} ms" if render else ""),
                    flush=True,
                )
    with open(os.path.join(args.work, "runs.json"), "w") as f:
        json.dump({f"{t} {n}": v for (t, n), v in runs.items()}, f)
    rows = []
    names = [n for n, _ in commands(args.ddg, args.work, volume, 1, 1, "A")]
    for tag, _ in builds:
        process = statistics.median(r[0] for r in runs[(tag, "process")])
        for name in names:
            peak = statistics.median(r[0] for r in runs[(tag, name)])
            wall = statistics.median(r[1] for r in runs[(tag, name)])
            row = {
                "build": tag,
                "command": name,
                "peak_mb": round(peak, 1),
                "wall_s": round(wall, 2),
            }
            if name.startswith("kernel"):
                row["render_ms"] = round(statistics.median(r[2] for r in runs[(tag, name)]), 1)
            elif name != "process":
                row["bytes_per_voxel_above_data"] = round((peak - data_mb) * 2**20 / voxels, 2)
                row["bytes_per_voxel_above_data_and_process"] = round(
                    (peak - data_mb - process) * 2**20 / voxels, 2
                )
            rows.append(row)
    lines = [
        f"volume {meta['dims'][0]}x{meta['dims'][1]}x{meta['dims'][2]} uint8 "
        f"({data_mb:.0f} MB), {args.iterations} iterations, {args.threads} threads, "
        f"median of {args.repeat}",
        "",
        "| build | command | peak MB | B/voxel above data | above data + process | wall s "
        "| render ms |",
        "|---|---|---|---|---|---|---|",
    ]
    for row in rows:
        lines.append(
            f"| {row['build']} | {row['command']} | {row['peak_mb']:.0f} | "
            f"{row.get('bytes_per_voxel_above_data', '')} | "
            f"{row.get('bytes_per_voxel_above_data_and_process', '')} | "
            f"{row['wall_s']:.2f} | {row.get('render_ms', '')} |"
        )
    if args.baseline_ddg:
        lines += ["", "| command | peak A/B | wall A/B | render A/B |", "|---|---|---|---|"]
        for name in names:
            a = next(r for r in rows if r["build"] == "A" and r["command"] == name)
            b = next(r for r in rows if r["build"] == "B" and r["command"] == name)
            kernel = f"{a['render_ms'] / b['render_ms']:.3f}" if "render_ms" in a else ""
            lines.append(
                f"| {name} | {a['peak_mb'] / b['peak_mb']:.3f} | "
                f"{a['wall_s'] / b['wall_s']:.3f} | {kernel} |"
            )
    text = "\n".join(lines)
    print(text)
    if args.out:
        os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
        json.dump(
            {
                "volume": meta,
                "voxels": voxels,
                "iterations": args.iterations,
                "threads": args.threads,
                "repeat": args.repeat,
                "builds": {t: d for t, d in builds},
                "rows": rows,
            },
            open(args.out + ".json", "w"),
            indent=1,
        )
        open(args.out + ".md", "w").write(text + "\n")
        print(f"wrote {args.out}.json, {args.out}.md")


if __name__ == "__main__":
    sys.exit(main())
