"""report.py: speed against accuracy, stability where methods fail, model size -- one command.

    scripts/with-xvfb.sh build/bin/pvpython Testing/Benchmarks/report.py [--quick] [--out DIR]

Writes DIR (default Documentation/Results) report.md (tables of the raw numbers, what fails and
which method to use), report.json, and the charts report_methods.png, report_stability.png,
report_optimisation.png, report_tf_resolution.png, report_renderer.png, report_models.png.
--quick (CI: Tooth only, fewer budgets, strengths and seeds) runs in a few minutes; the full run
(Tooth and Engine) in under 45 minutes on 2 cores. --confirm then trains, per scene, the smallest
sufficient model of the sweep when it is smaller than the shipped one, else the next smaller model
(width 8), with the shipped bundle's recipe (about 12 min for Tooth, 20-25 for Engine) and compares
it with the shipped bundle (Testing/Models/confirm.py): the model-size verdict at full training.
--sections S.. re-measures only the named sections (methods, stability, optimisation, renderer) and
keeps the others from DIR's report.json. --render-only redraws report.md and the charts from DIR's report.json without measuring (also
`/usr/bin/python3 Testing/Benchmarks/report_render.py --out DIR`).

What is measured. A reference: ParaView renders a shipped preset on a shipped volume at the
reference view and at an unseen view (white background, as the shipped screenshots). Each
screenshot -> TF method gets only the reference-view screenshot; the TF it returns is rendered
by ParaView at both views and compared with the references (PSNR, SSIM of `ddg compare`). Time is
the wall-clock of the method's `ddg` command (2 cores, including its process start and loading).
Methods: (a) nearest outline design (its decoded TF), (b) the paper's neural path: analyzer ->
U-Net render at the view -> reconstruction (`ddg query` on a U-Net bundle; full run, Tooth: the
model sweep's U-Net with a 2000-design outline), (b') analyzer -> TF decoder (`ddg query`), (b'+c)
that TF refined by differentiable reconstruction, (c) differentiable reconstruction from scratch,
(d) parametric fit of PRIMITIVES Gaussian primitives (`ddg reconstruct --primitives`), (e)
multi-view reconstruction (the screenshot and a second view of the same TF); (b'+c), (c), (d) and
(e) at several iteration budgets (curves). Stability: (b'), (b'+c), (c), (d), (f) the match
(`ddg reconstruct` without --view: background, overlays and camera estimated, from grey) and
(b'+f) the match from the query's TF, on perturbed screenshots (viewpoint, zoom, roll, pan, crop,
noise, JPEG, gamma, colour shift, a wrong background, backgrounds as screenshots have them:
ParaView's palette, black, its gradient; annotation and ParaView's orientation axes, another
volume, shading); success = ParaView's render at the reference view within SUCCESS_DB of the
unperturbed reference. (b'+f) runs on the unperturbed and the strongest of each kind; --quick runs
b' + reconstruction and (d) on the unperturbed screenshot only and (f) and (b'+f) nowhere. Optimisation: random initial TFs and seeds, learning
rates. TF resolution and smoothness prior. Renderer speed (BenchRayCaster, BenchDifferentiable,
bench_torch_autograd.py). Model size (Testing/Benchmarks/model_sweep.py: every configuration on
Tooth, the three decoder widths on Engine; --quick plots the last committed tables).

The parts: report_measure.py (the sections; report_methods.py: ParaView's renders, the `ddg`
program, the methods) writes the dict that report.json holds; report_render.py draws the charts
and writes report.md from it (report_models.py: the model-size section); report_common.py holds
what they share; Testing/Models/confirm.py trains and judges a confirmation candidate.
"""
import argparse
import os
import sys
import tempfile
import time

import report_models
import report_render
from report_common import (
    RESULTS,
    ROOT,
    commit,
    log,
    machine,
    minutes,
    read_report,
    report_json,
    section,
    section_minutes,
    write_report,
)

parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("--quick", action="store_true", help="CI size: Tooth only, fewer points")
parser.add_argument("--out", default=RESULTS)
parser.add_argument("--build", default=os.path.join(ROOT, "build"))
parser.add_argument(
    "--models-only",
    action="store_true",
    help="only redraw the model-size chart and section of the report in --out from its sweep tables",
)
parser.add_argument(
    "--confirm",
    action="store_true",
    help="train, per scene, the sweep's smallest sufficient model if smaller than the shipped one, "
    "else the next smaller one, with the shipped bundle's recipe (scripts/train_model.sh; 10-25 min "
    "each) and compare it with the shipped bundle; writes model_confirm_VOLUME.json (with "
    "--models-only: only this and the model section)",
)
parser.add_argument(
    "--render-only",
    action="store_true",
    help="measure nothing: redraw report.md and the charts in --out from its report.json",
)
parser.add_argument(
    "--sections",
    nargs="+",
    metavar="SECTION",
    choices=["methods", "stability", "optimisation", "renderer"],
    help="measure only these sections (methods, stability, optimisation, renderer) and keep the "
    "others' results from --out's report.json (the model sweep is never rerun); report.json "
    "records the re-run (its minutes, the machine and its load)",
)
args = parser.parse_args()
if args.sections and (args.confirm or args.models_only or args.render_only):
    parser.error(
        "--sections re-measures report sections; it goes with neither --confirm, "
        "--models-only nor --render-only"
    )
if args.confirm and args.quick:
    parser.error(
        "--confirm trains full-size models (about 25 min each); it does not go with --quick"
    )
if args.render_only and (args.quick or args.confirm or args.models_only):
    parser.error("--render-only renders the existing report.json; it measures nothing")
DDG = os.environ.get("DDG_EXE", os.path.join(args.build, "bin", "ddg"))
os.makedirs(args.out, exist_ok=True)
work = tempfile.mkdtemp(prefix="ddg-report-")


def rewrite_models_section(models):
    """Redraws the model-size chart and replaces the model section of report.md and report.json."""
    report_models.plot_models(models, args.out)
    saved = read_report(report_json(args.out))
    saved["models"] = models
    saved["model_confirmations"] = report_models.confirmations(models, args.out)
    write_report(saved, args.out)
    with open(os.path.join(args.out, "report.md")) as f:
        head = f.read().split(report_models.MODELS_HEADING)[0]
    with open(os.path.join(args.out, "report.md"), "w") as f:
        f.write(head + "\n".join(report_models.models_markdown(models, args.out)) + "\n")
    log(f"redrew {args.out}/report_models.png and the model section of report.md")


if args.render_only:
    report_render.render(args.out)
    sys.exit(0)

if args.models_only:  # redraw the model-size chart and section of an existing report
    models = report_models.read_sweeps(args.out)
    if args.confirm:
        report_models.run_confirmations(models, args.out, DDG, work)
    rewrite_models_section(models)
    sys.exit(0)

from report_measure import measure  # noqa: E402  (pvpython: ParaView renders every result)

saved = None
if args.sections:
    if not os.path.exists(report_json(args.out)):
        parser.error(f"--sections keeps the other sections from {report_json(args.out)}: missing")
    saved = read_report(report_json(args.out))
    if saved["quick"] != args.quick:
        parser.error(
            f"{report_json(args.out)} is a {'quick' if saved['quick'] else 'full'} report: "
            f"re-measure its sections {'with' if saved['quick'] else 'without'} --quick"
        )
at_start = machine()
results = measure(DDG, work, args.out, args.quick, args.confirm, args.sections, saved)
section("charts")
report_render.charts(results, args.out)
if args.sections:  # the full run's minutes stay; the re-run is recorded beside them
    # an earlier re-run of only these sections no longer describes any of them: dropped
    results["reruns"] = [
        r for r in results.get("reruns", []) if not set(r["sections"]) <= set(args.sections)
    ]
    results["reruns"].append(
        {
            "sections": args.sections,
            "date": time.strftime("%Y-%m-%d"),
            "commit": commit(),
            "minutes": minutes(),
            "section_minutes": section_minutes(),
            "machine": dict(at_start, load_average_end=os.getloadavg()[0]),
        }
    )
else:
    results["section_minutes"] = section_minutes()
    results["model_confirmations"] = report_models.confirmations(results["models"], args.out)
    results["minutes"] = minutes()
    results["machine"] = dict(at_start, load_average_end=os.getloadavg()[0])
    results["commit"] = commit()
write_report(results, args.out)
report_render.write_markdown(read_report(report_json(args.out)), args.out)  # from report.json
log(f"wrote {args.out}/report.md, report.json and the report_*.png charts")
if args.confirm:  # after the report is safely written: this trains for a while
    report_models.run_confirmations(results["models"], args.out, DDG, work)
    rewrite_models_section(results["models"])
runs = results["optimisation"]["random_starts"]
nonfinite = sum(not r["finite"] for r in runs)
if nonfinite:
    sys.exit(f"{nonfinite} reconstructions from random starts ended with non-finite values")
