"""Exported presets import into ParaView side by side (ParaView's preset store, 5.11).

ParaView keeps imported presets by name; vtkSMTransferFunctionPresets::ImportPresets gives an
imported preset a new name only while its "Name" is not taken, and one whose name it holds
already comes in nameless after the warning "Giving up. Cannot find a unique name" (5.11). So
every exported file needs its own name.

Compared: three presets written by `ddg` the ways users export them (`ddg export` of one TF to
two files, `ddg reconstruct --out`) are imported with paraview.simple.ImportPresets into a fresh
preset store (HOME is the test's own folder): each must add exactly one preset whose name is the
file's "Name" — non-empty, all three different, "DDG <volume> <origin> <stem> <date> <time>".
The control: two files with one name (as every export had before) — the second comes in
nameless, which is what the check above would catch.

Usage: python3 TestPresetImport.py DDG DATA TESTDATA OUTDIR   (ParaView's /usr/bin/python3)
"""
import json
import os
import re
import shutil
import subprocess
import sys

ddg, data, testdata, outdir = sys.argv[1:5]
os.makedirs(outdir, exist_ok=True)
# ParaView's user settings (its custom presets) in the test's own, fresh folder
home = os.path.join(outdir, "home")
shutil.rmtree(home, ignore_errors=True)
os.makedirs(home)
os.environ["HOME"] = home

tooth = os.path.join(data, "Volumes", "tooth.vti")
source_tf = os.path.join(data, "TransferFunctions", "tooth_enamel.json")
files = []
for stem in ("enamel_a", "enamel_b"):
    out = os.path.join(outdir, stem + ".json")
    subprocess.run([ddg, "export", "--tf", source_tf, "--volume", tooth, "--out", out], check=True)
    files.append(out)
out = os.path.join(outdir, "small_reconstructed.json")
subprocess.run(
    [
        ddg,
        "reconstruct",
        "--volume",
        os.path.join(testdata, "small.vti"),
        "--target",
        os.path.join(testdata, "small_target.png"),
        "--target",
        os.path.join(testdata, "small_target.png"),
        "--view",
        os.path.join(testdata, "small_view.json"),
        "--view",
        os.path.join(testdata, "small_view.json"),
        "--iterations",
        "5",
        "--out",
        out,
        "--quiet",
    ],
    check=True,
)
files.append(out)

names = [json.load(open(f))[0]["Name"] for f in files]
print("exported names:", names)
pattern = r"^DDG \S+ .+ \d{4}-\d\d-\d\d \d\d:\d\d:\d\d$"
assert all(re.match(pattern, n) for n in names), names
assert names[0].startswith("DDG tooth tooth_enamel enamel_a "), names[0]
assert names[2].startswith("DDG small reconstruction small_reconstructed "), names[2]
assert len(set(names)) == 3, names

from paraview import servermanager  # noqa: E402
from paraview.simple import ImportPresets  # noqa: E402

presets = servermanager.vtkSMTransferFunctionPresets.GetInstance()


def import_file(path):
    """The names of the presets ImportPresets added for `path`."""
    before = presets.GetNumberOfPresets()
    assert ImportPresets(path), path
    return [presets.GetPresetName(i) for i in range(before, presets.GetNumberOfPresets())]


imported = [import_file(f) for f in files]
print("imported as:", imported)
assert imported == [[n] for n in names], (imported, names)

# control: one name twice (the exports before they were named) -> the second is nameless
same = []
for k in range(2):
    preset = json.load(open(source_tf))
    preset[0]["Name"] = "ddg design"
    preset[0]["RGBPoints"][1] = 0.25 * (k + 1)
    same.append(os.path.join(outdir, f"same_name_{k}.json"))
    json.dump(preset, open(same[-1], "w"))
control = [import_file(f) for f in same]
print("control, one name twice, imported as:", control)
assert control[0] == ["ddg design"] and control[1] != ["ddg design"], control
print("ok")
