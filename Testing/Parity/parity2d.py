"""Parity of ParaView 5.11's 2D transfer function rendering with `ddg render` of our 2D TFs.

What is compared with what: for every (volume, 2D TF, view) case, `ddg render` renders our 2D TF
(value x gradient magnitude, Gaussian primitives); `ddg export --format paraview-2d` converts it
into ParaView's TransferFunction2D boxes for that volume (fitted; and with --box-iterations 0,
one box per primitive as placed before the fit); ParaView renders the volume with those boxes
(UseTransfer2D, gradient magnitude as Y, the default "Smart" mapper = GPU ray caster under Mesa,
no shading). The two 8-bit RGB images are compared with `ddg compare` (PSNR over RGB, SSIM).
Tolerance: the fitted case fails below --min-psnr dB (default 30), and the fit must not be worse
than the placement it starts from by more than 0.5 dB. Results: <out>/parity2d.md.

    scripts/with-xvfb.sh pvpython Testing/Parity/parity2d.py --ddg build/bin/ddg --data Data --out build/Testing/Parity2D
"""
import argparse
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pvrender import paraview_render  # noqa: E402

CASES = [("tooth", "tooth_2d_boundaries"), ("engine", "engine_2d_edges")]
VIEWS = ["oblique", "side"]


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--ddg", required=True, help="path of the ddg program")
    parser.add_argument("--data", required=True, help="the project's Data directory")
    parser.add_argument("--out", required=True, help="directory for the images and results")
    parser.add_argument("--min-psnr", type=float, default=30.0)
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)

    def ddg(*a):
        return subprocess.run([args.ddg, *a], check=True, capture_output=True, text=True).stdout

    rows, failed = [], 0
    for volume, tf_name in CASES:
        volume_path = os.path.join(args.data, "Volumes", volume + ".vti")
        tf_path = os.path.join(args.data, "TransferFunctions", tf_name + ".json")
        for view_name in VIEWS:
            view_path = os.path.join(args.data, "Views", f"{volume}_{view_name}.json")
            with open(view_path) as f:
                view_json = json.load(f)
            stem = os.path.join(args.out, f"{tf_name}_{view_name}")
            ddg(
                "render",
                "--volume",
                volume_path,
                "--tf",
                tf_path,
                "--view",
                view_path,
                "--out",
                stem + "_ddg.png",
            )
            result = {}
            for kind, extra in (("placed", ["--box-iterations", "0"]), ("fitted", [])):
                boxes_path = f"{stem}_{kind}_boxes.json"
                ddg(
                    "export",
                    "--tf",
                    tf_path,
                    "--volume",
                    volume_path,
                    "--view",
                    view_path,
                    "--format",
                    "paraview-2d",
                    "--out",
                    boxes_path,
                    *extra,
                )
                with open(boxes_path) as f:
                    boxes = json.load(f)
                png = f"{stem}_{kind}_paraview.png"
                paraview_render(volume_path, None, view_json, png, boxes_2d=boxes)
                metrics = json.loads(ddg("compare", "--json", png, stem + "_ddg.png"))
                result[kind] = (
                    metrics["psnr"],
                    metrics["ssim"],
                    boxes["Fit"]["rmse"],
                    len(boxes["Boxes"]) // 8,
                )
            ok = (
                result["fitted"][0] >= args.min_psnr
                and result["fitted"][0] >= result["placed"][0] - 0.5
            )
            failed += 0 if ok else 1
            rows.append((volume, tf_name, view_name, result, ok))
            print(
                f"{volume:7s} {tf_name:20s} {view_name:8s} placed {result['placed'][0]:6.2f} dB, "
                f"fitted {result['fitted'][0]:6.2f} dB / SSIM {result['fitted'][1]:.4f} "
                f"(fit RMSE {result['placed'][2]:.4f} -> {result['fitted'][2]:.4f})  {'ok' if ok else 'FAIL'}",
                flush=True,
            )
    with open(os.path.join(args.out, "parity2d.md"), "w") as f:
        f.write(
            "| volume | 2D TF | view | boxes | PSNR placed (dB) | PSNR fitted (dB) | SSIM fitted "
            "| fit RMSE placed | fit RMSE fitted |\n|---|---|---|---|---|---|---|---|---|\n"
        )
        for v, t, w, r, _ in rows:
            f.write(
                f"| {v} | {t} | {w} | {r['fitted'][3]} | {r['placed'][0]:.2f} | {r['fitted'][0]:.2f} | "
                f"{r['fitted'][1]:.4f} | {r['placed'][2]:.4f} | {r['fitted'][2]:.4f} |\n"
            )
    print(
        f"{len(rows) - failed}/{len(rows)} cases at or above {args.min_psnr} dB and not worse than placed"
    )
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
