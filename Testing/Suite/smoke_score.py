"""Smoke test of the suite's score (score.py), in one pvpython process (~15 s).

What is compared with what, on Tooth with the suite's preset suite_tooth_amber_ivory (true):
  - the true TF against itself: ParaView renders identically, the score is PSNR_CAP (>= 99 dB);
  - another suite preset (suite_tooth_shell_violet) against it: <= 30 dB;
  - a haze (the true TF plus opacity 0.02 on the air, 0..100, coloured as ParaView's default
    palette background, as a reconstruction from a screenshot on that background may paint it):
    <= 40 dB, and lower on white than on black.
Tolerances are bars set before running: an identical TF must be exact, a different or hazed TF
must be clearly apart.

    scripts/with-xvfb.sh pvpython Testing/Suite/smoke_score.py Data/Volumes/tooth.vti
"""
import copy
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from score import PSNR_CAP, canonical_renders, load_preset, score_renders  # noqa: E402
from suite_paraview import DEFAULT_PALETTE_BACKGROUND  # noqa: E402


def hazed(preset, air_max=100.0, opacity=0.02):
    """``preset`` with the air (values <= air_max) painted translucent in the palette's
    background colour."""
    out = copy.deepcopy(preset)
    rgb = preset["RGBPoints"]
    keep = [rgb[i : i + 4] for i in range(0, len(rgb), 4) if rgb[i] > air_max + 10]
    out["RGBPoints"] = [0.0, *DEFAULT_PALETTE_BACKGROUND, air_max, *DEFAULT_PALETTE_BACKGROUND]
    out["RGBPoints"] += [x for node in keep for x in node]
    pts = preset["Points"]
    keep = [pts[i : i + 4] for i in range(0, len(pts), 4) if pts[i] > air_max + 10]
    out["Points"] = [0.0, opacity, 0.5, 0.0, air_max, opacity, 0.5, 0.0]
    out["Points"] += [air_max + 10, 0.0, 0.5, 0.0] + [x for node in keep for x in node]
    return out


def main():
    volume = sys.argv[1]
    tfs = os.path.join(HERE, "TransferFunctions")
    true = load_preset(os.path.join(tfs, "suite_tooth_amber_ivory.json"))
    other = load_preset(os.path.join(tfs, "suite_tooth_shell_violet.json"))
    reference = canonical_renders(volume, true)
    results = {
        "itself": score_renders(canonical_renders(volume, true), reference),
        "other TF": score_renders(canonical_renders(volume, other), reference),
        "haze": score_renders(canonical_renders(volume, hazed(true)), reference),
    }
    for name, r in results.items():
        b = r["psnr_by_background"]
        print(f"{name:9s} {r['psnr']:6.2f} dB (black {b['black']:.2f}, white {b['white']:.2f})")
    haze = results["haze"]
    checks = [
        ("itself >= 99 dB", results["itself"]["psnr"] >= min(99.0, PSNR_CAP)),
        ("other TF <= 30 dB", results["other TF"]["psnr"] <= 30.0),
        ("haze <= 40 dB", haze["psnr"] <= 40.0),
        (
            "haze lower on white",
            haze["psnr_by_background"]["white"] < haze["psnr_by_background"]["black"],
        ),
    ]
    failed = [name for name, ok in checks if not ok]
    print("FAILED: " + ", ".join(failed) if failed else "all checks passed")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
