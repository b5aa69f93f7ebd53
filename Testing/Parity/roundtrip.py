"""Round trip through ParaView: screenshot -> `ddg reconstruct` -> ParaView again.

What is compared with what: ParaView 5.11 renders a volume with a shipped preset at a reference
view and at a second view (8-bit screenshots, the view JSONs of Data/Views). `ddg reconstruct`
sees only the reference screenshot (an opaque RGB image over the view's background) and its
view JSON and writes a ParaView preset. ParaView then renders the reconstructed preset at both
views. PSNR between ParaView's images of the original and of the reconstructed preset must be
>= --min-psnr-reference (default 36 dB) at the reference view and >= --min-psnr-other
(default 30 dB) at the view the reconstruction never saw.

--lighting shade (or shade-specular) does the same with Shade on: ParaView's screenshots are lit
and ddg reconstructs through the lit renderer.

Run with pvpython under a display:
    xvfb-run -a pvpython Testing/Parity/roundtrip.py --ddg build/bin/ddg --data Data --out DIR
"""
import argparse
import json
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pvrender import LIGHTINGS, paraview_render  # noqa: E402

DEFAULT_CASES = [
    ("tooth", "tooth_dentin_enamel"),
    ("engine", "engine_block"),
    ("headsq", "headsq_bone"),
]


def compare(ddg, a, b):
    out = subprocess.run(
        [ddg, "compare", "--json", a, b], check=True, capture_output=True, text=True
    )
    return json.loads(out.stdout)


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--ddg", required=True)
    parser.add_argument("--data", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--min-psnr-reference", type=float, default=36.0)
    parser.add_argument("--min-psnr-other", type=float, default=30.0)
    parser.add_argument("--case", action="append", help="volume:preset (repeatable)")
    parser.add_argument("--reference-view", default="oblique")
    parser.add_argument("--other-view", default="side")
    parser.add_argument(
        "--ddg-arg", action="append", default=[], help="extra argument for ddg reconstruct"
    )
    parser.add_argument(
        "--lighting",
        choices=sorted(LIGHTINGS),
        default="off",
        help="the views' lighting (ParaView renders and ddg reconstructs with it)",
    )
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    cases = [tuple(c.split(":")) for c in args.case] if args.case else DEFAULT_CASES
    rows, failed = [], 0
    for volume, preset_name in cases:
        volume_path = os.path.join(args.data, "Volumes", volume + ".vti")
        with open(os.path.join(args.data, "TransferFunctions", preset_name + ".json")) as f:
            preset = json.load(f)[0]
        views = {}
        for which in (args.reference_view, args.other_view):
            path = os.path.join(args.data, "Views", f"{volume}_{which}.json")
            with open(path) as f:
                view_json = json.load(f)
            if LIGHTINGS[args.lighting]:
                view_json["lighting"] = LIGHTINGS[args.lighting]
                path = os.path.join(args.out, f"{volume}_{which}_{args.lighting}.json")
                with open(path, "w") as f:
                    json.dump(view_json, f)
            views[which] = (path, view_json)
        stem = os.path.join(args.out, preset_name)
        for which, (path, view_json) in views.items():
            paraview_render(volume_path, preset, view_json, f"{stem}_{which}_original.png")
        recovered = stem + "_reconstructed.json"
        ref_path = views[args.reference_view][0]
        start = time.time()
        run = subprocess.run(
            [
                args.ddg,
                "reconstruct",
                "--volume",
                volume_path,
                "--target",
                f"{stem}_{args.reference_view}_original.png",
                "--view",
                ref_path,
                "--out",
                recovered,
                "--quiet",
            ]
            + args.ddg_arg,
            check=True,
            capture_output=True,
            text=True,
        )
        seconds = time.time() - start
        with open(recovered) as f:
            new_preset = json.load(f)[0]
        result = {}
        for which, (path, view_json) in views.items():
            paraview_render(volume_path, new_preset, view_json, f"{stem}_{which}_reconstructed.png")
            result[which] = compare(
                args.ddg, f"{stem}_{which}_original.png", f"{stem}_{which}_reconstructed.png"
            )
        ok_ref = result[args.reference_view]["psnr"] >= args.min_psnr_reference
        ok_other = result[args.other_view]["psnr"] >= args.min_psnr_other
        failed += 0 if (ok_ref and ok_other) else 1
        nodes = len(new_preset["RGBPoints"]) // 4, len(new_preset["Points"]) // 4
        rows.append(
            (
                volume,
                preset_name,
                result[args.reference_view],
                result[args.other_view],
                seconds,
                nodes,
            )
        )
        print(
            f"{volume:7s} {preset_name:20s} reference view PSNR {result[args.reference_view]['psnr']:6.2f} dB "
            f"SSIM {result[args.reference_view]['ssim']:.4f} | unseen view PSNR "
            f"{result[args.other_view]['psnr']:6.2f} dB SSIM {result[args.other_view]['ssim']:.4f} | "
            f"{seconds:.1f} s, {nodes[0]} colour + {nodes[1]} opacity nodes  "
            f"{'ok' if ok_ref and ok_other else 'FAIL'}",
            flush=True,
        )
        print("   ", run.stdout.strip().splitlines()[0])
    with open(os.path.join(args.out, "roundtrip.md"), "w") as f:
        f.write(
            "| volume | preset | PSNR reference view (dB) | SSIM | PSNR unseen view (dB) | SSIM | ddg reconstruct (s) |\n"
        )
        f.write("|---|---|---|---|---|---|---|\n")
        for v, p, r, o, t, _ in rows:
            f.write(
                f"| {v} | {p} | {r['psnr']:.2f} | {r['ssim']:.4f} | {o['psnr']:.2f} | {o['ssim']:.4f} | {t:.1f} |\n"
            )
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
