"""Benchmark (b): our analytic adjoint vs the same forward + backward written naively with
PyTorch autograd (trilinear sampling and compositing as tensor ops), same image and samples.

Engine 256x256x128, view Data/Views/engine_oblique.json at SIZE x SIZE, preset engine_block
baked into ParaView's 1024-entry table, sample distance 0.5 (ParaView's), first sample at half
a step, no early termination (so both visit exactly the same samples), L = sum of premultiplied
RGBA, gradient w.r.t. the table. Prints the time of both, the autograd version's peak-RSS growth
against our working memory (counted exactly by BenchDifferentiable --memory), the ratios, and the
sum of dL/dTable of both (they must agree). Run with Debian's Python (python3-torch):

    /usr/bin/python3 Testing/Benchmarks/bench_torch_autograd.py --bench build/bin/BenchDifferentiable
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import time

import numpy as np
import torch
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLImageDataReader

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "Data")


def peak_rss_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def load_volume(path):
    r = vtkXMLImageDataReader()
    r.SetFileName(path)
    r.Update()
    img = r.GetOutput()
    dims = img.GetDimensions()
    values = vtk_to_numpy(img.GetPointData().GetScalars()).astype(np.float32)
    return values, dims, np.array(img.GetOrigin()), np.array(img.GetSpacing())


def paraview_table(preset, vmin, vmax, width=1024):
    x = vmin + np.arange(width) * (vmax - vmin) / (width - 1)
    rgb = np.array(preset["RGBPoints"]).reshape(-1, 4)
    pts = np.array(preset["Points"]).reshape(-1, 4)
    table = np.zeros((width, 4))
    for c in range(3):
        table[:, c] = np.interp(x, rgb[:, 0], rgb[:, c + 1])
    table[:, 3] = np.interp(x, pts[:, 0], pts[:, 1])  # engine_block: midpoint 0.5, sharpness 0
    return table


def rays(view, size):
    cam = view["camera"]
    pos, focal, up = (
        np.array(cam[k], dtype=np.float64) for k in ("position", "focal_point", "view_up")
    )
    fwd = (focal - pos) / np.linalg.norm(focal - pos)
    right = np.cross(fwd, up)
    right /= np.linalg.norm(right)
    upo = np.cross(right, fwd)
    half = np.tan(np.radians(cam.get("view_angle", 30.0)) / 2)
    ys, xs = np.mgrid[0:size, 0:size]
    ndc_x = 2 * (xs + 0.5) / size - 1
    ndc_y = 2 * ((size - 1 - ys) + 0.5) / size - 1
    d = fwd[None, None] + (ndc_x * half)[..., None] * right + (ndc_y * half)[..., None] * upo
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    return np.broadcast_to(pos, d.shape).reshape(-1, 3), d.reshape(-1, 3)


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--bench", required=True, help="path of BenchDifferentiable")
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--threads", type=int, default=os.cpu_count())
    args = parser.parse_args()
    torch.set_num_threads(args.threads)

    values, dims, origin, spacing = load_volume(os.path.join(DATA, "Volumes", "engine.vti"))
    with open(os.path.join(DATA, "Views", "engine_oblique.json")) as f:
        view = json.load(f)
    with open(os.path.join(DATA, "TransferFunctions", "engine_block.json")) as f:
        preset = json.load(f)[0]
    vmin, vmax = float(values.min()), float(values.max())
    width = 1024
    table0 = paraview_table(preset, vmin, vmax, width)
    q = 256.0 / 255.0  # ParaView's uint8 texture normalisation
    d = (spacing.sum()) / 6.0
    diag = np.linalg.norm((np.array(dims) - 1) * spacing)
    unit = diag / np.cbrt(np.prod(np.array(dims) - 1))
    expo = d / unit

    # ray segments in index space (float64, as ddg::raySegment)
    o, dirs = rays(view, args.size)
    lo, hi = origin, origin + (np.array(dims) - 1) * spacing
    with np.errstate(divide="ignore", invalid="ignore"):
        ta, tb = (lo - o) / dirs, (hi - o) / dirs
    t0 = np.maximum(np.nanmax(np.minimum(ta, tb), axis=1), 0)
    t1 = np.nanmin(np.maximum(ta, tb), axis=1)
    hit = t1 >= t0
    e = (o + t0[:, None] * dirs - origin) / spacing
    s = d * dirs / spacing
    span = (t1 - t0) / d - 0.5
    k_last = np.where(span > 0, np.floor(span), 0).astype(np.int64)
    k_last[~hit] = -1
    K = int(k_last.max()) + 1
    n = len(o)
    print(f"{n} rays, up to {K} samples per ray, {int((k_last + 1).sum())} samples in all")

    vol = torch.from_numpy(values)
    nx, ny, nz = dims
    start_rss = peak_rss_mb()
    t_start = time.time()
    table = torch.tensor(table0, dtype=torch.float32, requires_grad=True)
    kk = torch.arange(K, dtype=torch.float32) + 0.5
    pos = (
        torch.from_numpy(e.astype(np.float32))[:, None, :]
        + kk[None, :, None] * torch.from_numpy(s.astype(np.float32))[:, None, :]
    )
    mask = (torch.arange(K)[None, :] <= torch.from_numpy(k_last)[:, None]).float()
    maxs = torch.tensor([nx - 1, ny - 1, nz - 1], dtype=torch.float32)
    pos = torch.minimum(torch.maximum(pos, torch.zeros(3)), maxs)
    i0 = torch.minimum(pos.floor().long(), torch.tensor([nx - 2, ny - 2, nz - 2]))
    f = pos - i0.float()
    fx, fy, fz = f[..., 0], f[..., 1], f[..., 2]
    base = i0[..., 0] + nx * (i0[..., 1] + ny * i0[..., 2])

    def corner(dx, dy, dz):
        return vol[base + dx + nx * (dy + ny * dz)]

    c00 = corner(0, 0, 0) + fx * (corner(1, 0, 0) - corner(0, 0, 0))
    c10 = corner(0, 1, 0) + fx * (corner(1, 1, 0) - corner(0, 1, 0))
    c01 = corner(0, 0, 1) + fx * (corner(1, 0, 1) - corner(0, 0, 1))
    c11 = corner(0, 1, 1) + fx * (corner(1, 1, 1) - corner(0, 1, 1))
    v = (c00 + fy * (c10 - c00)) * (1 - fz) + (c01 + fy * (c11 - c01)) * fz
    t = torch.clamp(
        v * (q * width / (vmax - vmin)) - vmin * width / (vmax - vmin) - 0.5, 0, width - 1
    )
    ti = torch.clamp(t.floor().long(), max=width - 2)
    tf = (t - ti.float())[..., None]
    alpha = table[:, 3].clamp(0, 1)
    corrected = torch.where(alpha > 1e-4, 1 - (1 - alpha) ** expo, alpha).clamp(max=1 - 1e-6)
    prepared = torch.cat([table[:, :3].clamp(0, 1), corrected[:, None]], dim=1)
    rgba = prepared[ti] * (1 - tf) + prepared[ti + 1] * tf
    a = rgba[..., 3] * mask
    trans = torch.cumprod(torch.cat([torch.ones(n, 1), 1 - a[:, :-1]], dim=1), dim=1)
    w = trans * a
    C = (w[..., None] * rgba[..., :3]).sum(dim=1)
    A = 1 - torch.prod(1 - a, dim=1)
    loss = C.sum() + A.sum()
    loss.backward()
    torch_s = time.time() - t_start
    torch_mb = peak_rss_mb() - start_rss
    torch_grad = float(table.grad.sum())
    print(
        f"PyTorch autograd: forward+backward {torch_s * 1000:.0f} ms, peak RSS growth {torch_mb:.0f} MB, "
        f"sum dL/dTable {torch_grad:.6g}"
    )

    out = subprocess.run(
        [args.bench, "--memory", "--size", str(args.size)],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    print(out.strip())
    ours_ms = float(out.split("forward+backward ")[1].split(" ms")[0])
    ours_mb = float(out.split("working memory ")[1].split(" MB")[0])
    ours_grad = float(out.split("sum of dL/dTable ")[1].split()[0])
    print(
        f"(b) time: ours {ours_ms:.0f} ms vs autograd {torch_s * 1000:.0f} ms -> {torch_s * 1000 / ours_ms:.1f}x faster"
    )
    print(
        f"(b) memory: ours {ours_mb:.2f} MB working memory (counted) vs autograd {torch_mb:.0f} MB "
        f"peak RSS growth -> {torch_mb / ours_mb:.0f}x less"
    )
    print(
        f"    gradient agreement: sum dL/dTable ours {ours_grad:.6g}, autograd {torch_grad:.6g} "
        f"(relative difference {abs(ours_grad - torch_grad) / max(abs(torch_grad), 1e-12):.2e})"
    )


if __name__ == "__main__":
    sys.exit(main())
