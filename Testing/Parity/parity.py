"""Parity of `ddg render` with ParaView's own volume rendering.

What is compared with what: for every (volume, preset, view) case, ParaView 5.11 renders the
volume (Volume representation, default "Smart" mapper = GPU ray caster under Mesa, Shade as
--lighting says (off by default; on with ParaView's default light kit and coefficients, or with
Specular 0.5 / SpecularPower 30),
the preset written into the LookupTable / ScalarOpacityFunction, the camera from the view
JSON) and saves a screenshot; `ddg render` renders the same volume, preset and view JSON. The
two 8-bit RGB images are compared with `ddg compare` (PSNR over RGB, SSIM).
Tolerance: the case fails below --min-psnr dB (default 45).

Run with ParaView's Python under a display, e.g.
    xvfb-run -a pvpython Testing/Parity/parity.py --ddg build/bin/ddg --data Data --out build/Testing/Parity
"""
import argparse
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pvrender import LIGHTINGS, paraview_render  # noqa: E402

DEFAULT_CASES = [
    ("tooth", "tooth_dentin_enamel"),
    ("tooth", "tooth_cool_warm"),
    ("engine", "engine_block"),
    ("engine", "engine_hsv"),
    ("headsq", "headsq_skin_bone"),
    ("headsq", "headsq_bone"),
]
DEFAULT_VIEWS = ["oblique", "side"]


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--ddg", required=True, help="path of the ddg program")
    parser.add_argument("--data", required=True, help="the project's Data directory")
    parser.add_argument("--out", required=True, help="directory for the images and results")
    parser.add_argument("--min-psnr", type=float, default=45.0)
    parser.add_argument("--case", action="append", help="volume:preset (repeatable)")
    parser.add_argument("--view", action="append", help="view suffix (repeatable)")
    parser.add_argument(
        "--ddg-arg", action="append", default=[], help="extra argument for ddg render"
    )
    parser.add_argument(
        "--lighting",
        action="append",
        choices=sorted(LIGHTINGS),
        help="lighting of every case (repeatable; default: off)",
    )
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    cases = [tuple(c.split(":")) for c in args.case] if args.case else DEFAULT_CASES
    views = args.view or DEFAULT_VIEWS
    lightings = args.lighting or ["off"]

    rows, failed = [], 0
    for volume, preset_name in cases:
        volume_path = os.path.join(args.data, "Volumes", volume + ".vti")
        preset_path = os.path.join(args.data, "TransferFunctions", preset_name + ".json")
        with open(preset_path) as f:
            preset = json.load(f)[0]
        for view_name, lighting in [(v, li) for v in views for li in lightings]:
            view_path = os.path.join(args.data, "Views", f"{volume}_{view_name}.json")
            with open(view_path) as f:
                view_json = json.load(f)
            suffix = "" if lighting == "off" else "_" + lighting
            stem = os.path.join(args.out, f"{preset_name}_{view_name}{suffix}")
            if LIGHTINGS[lighting]:
                view_json["lighting"] = LIGHTINGS[lighting]
                view_path = stem + "_view.json"
                with open(view_path, "w") as f:
                    json.dump(view_json, f)
            paraview_render(volume_path, preset, view_json, stem + "_paraview.png")
            subprocess.run(
                [
                    args.ddg,
                    "render",
                    "--volume",
                    volume_path,
                    "--tf",
                    preset_path,
                    "--view",
                    view_path,
                    "--out",
                    stem + "_ddg.png",
                ]
                + args.ddg_arg,
                check=True,
                stdout=subprocess.DEVNULL,
            )
            result = subprocess.run(
                [args.ddg, "compare", "--json", stem + "_paraview.png", stem + "_ddg.png"],
                check=True,
                capture_output=True,
                text=True,
            )
            metrics = json.loads(result.stdout)
            ok = metrics["psnr"] >= args.min_psnr
            failed += 0 if ok else 1
            rows.append(
                (volume, preset_name, view_name, lighting, metrics["psnr"], metrics["ssim"], ok)
            )
            print(
                f"{volume:8s} {preset_name:22s} {view_name:8s} {lighting:14s} "
                f"PSNR {metrics['psnr']:6.2f} dB  SSIM {metrics['ssim']:.5f}  "
                f"{'ok' if ok else 'FAIL'}",
                flush=True,
            )
    with open(os.path.join(args.out, "parity.md"), "w") as f:
        f.write("| volume | preset | view | lighting | PSNR (dB) | SSIM |\n")
        f.write("|---|---|---|---|---|---|\n")
        for r in rows:
            f.write(f"| {r[0]} | {r[1]} | {r[2]} | {r[3]} | {r[4]:.2f} | {r[5]:.5f} |\n")
    print(f"{len(rows) - failed}/{len(rows)} cases at or above {args.min_psnr} dB")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
