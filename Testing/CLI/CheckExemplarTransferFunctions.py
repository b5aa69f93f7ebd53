"""ddg generate --tfs: every exemplar's TF file, rendered by `ddg render` at the exemplar's view
(V_exp, from dataset.json), gives the image the generator rendered of it (the first cell of the
--preview contact sheet: 2-pixel gaps, three cells a row) — the file holds the design, not just a
file of the right name.

    /usr/bin/python3 CheckExemplarTransferFunctions.py DDG VOLUME SPEC_2D WORKDIR
"""
import json
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Common"))
from pictures import psnr, read_png  # noqa: E402

ddg, volume, spec_2d, work = sys.argv[1:5]
SIZE = 32
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


def run(*args):
    done = subprocess.run([ddg, *args], capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit("ddg %s failed (%d): %s" % (args[0], done.returncode, done.stderr))
    return done.stdout


def check(name, spec_args, extension_key):
    data, tfs, sheet = (os.path.join(work, name + s) for s in ("_data", "_tfs", "_sheet.png"))
    out = run(
        "generate",
        "--volume",
        volume,
        "--count",
        "3",
        "--size",
        str(SIZE),
        "--out",
        data,
        "--first-index",
        "40",
        "--tfs",
        tfs,
        "--preview",
        sheet,
        "--quiet",
        *spec_args
    )
    if "wrote 3 exemplar TFs to" not in out:
        sys.exit("%s: generate did not report the TF files:\n%s" % (name, out))
    files = sorted(os.listdir(tfs))
    if files != ["exemplar_40.json", "exemplar_41.json", "exemplar_42.json"]:
        sys.exit("%s: unexpected TF files %s" % (name, files))
    with open(os.path.join(tfs, files[0])) as f:
        tf = json.load(f)
    if extension_key not in json.dumps(tf):
        sys.exit(
            "%s: %s is not the expected kind of TF file (no %s)" % (name, files[0], extension_key)
        )
    with open(os.path.join(data, "dataset.json")) as f:
        exemplar = json.load(f)["exemplars"][0]
    view = os.path.join(work, name + "_view.json")
    with open(view, "w") as f:
        json.dump(exemplar["view_exp"], f)
    render = os.path.join(work, name + "_render.png")
    run(
        "render",
        "--volume",
        volume,
        "--tf",
        os.path.join(tfs, files[0]),
        "--view",
        view,
        "--out",
        render,
    )
    generated = read_png(sheet)[2 : 2 + SIZE, 2 : 2 + SIZE]
    figure = psnr(generated, read_png(render))
    print(
        "%s: %s rendered at its V_exp against the generator's image: %.1f dB"
        % (name, files[0], figure)
    )
    if figure < 40:
        sys.exit("%s: the TF file does not render as the exemplar (%.1f dB < 40)" % (name, figure))


check("1d", [], "RGBPoints")
check("2d", ["--spec", spec_2d], "ddg-transfer-function-2d")
print("ok")
