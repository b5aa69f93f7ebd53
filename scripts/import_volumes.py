"""Converts the shared raw.gz + JSON volumes into zlib-compressed .vti files in Data/Volumes.

Run with ParaView's Python (it uses ParaView's bundled VTK):
    /usr/bin/python3 scripts/import_volumes.py [--shared ../shared/data/volumes]
Deterministic: the same inputs give byte-identical .vti files. Checks each raw file's sha256
against its JSON before converting.
"""
import argparse
import gzip
import hashlib
import json
import os
import sys

import numpy as np
from paraview.vtk.util import numpy_support
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

# shared file stem -> name in Data/Volumes
VOLUMES = {
    "tooth_103x94x161_uint8": "tooth",
    "engine_256x256x128_uint8": "engine",
    "bonsai_256x256x256_uint8": "bonsai",
    "neghip_64x64x64_uint8": "neghip",
    "vtk_headsq_64x64x93_int16": "headsq",
    "lidc_chest_ct_256x256x133_uint8": "chest",
    "mni152_2009a_t1_197x233x189_uint8": "mri",
    "vtk_ironprot_68x68x68_uint8": "ironprot",
}


def convert(shared, stem, out_path):
    with open(os.path.join(shared, stem + ".json")) as f:
        meta = json.load(f)
    with gzip.open(os.path.join(shared, meta["file"]), "rb") as f:
        raw = f.read()
    digest = hashlib.sha256(raw).hexdigest()
    if digest != meta["sha256"]:
        sys.exit(f"{stem}: sha256 mismatch ({digest} != {meta['sha256']})")
    dtype = np.dtype(meta["dtype"]).newbyteorder(
        "<" if meta.get("endian", "little") == "little" else ">"
    )
    values = np.frombuffer(raw, dtype=dtype).astype(dtype.newbyteorder("="))
    nx, ny, nz = meta["dims"]
    assert values.size == nx * ny * nz
    image = vtkImageData()
    image.SetDimensions(nx, ny, nz)
    image.SetSpacing(*meta["spacing"])
    image.SetOrigin(0.0, 0.0, 0.0)
    array = numpy_support.numpy_to_vtk(values, deep=1)
    array.SetName("scalars")
    image.GetPointData().SetScalars(array)
    writer = vtkXMLImageDataWriter()
    writer.SetFileName(out_path)
    writer.SetInputData(image)
    writer.SetCompressorTypeToZLib()
    writer.SetCompressionLevel(9)
    writer.SetDataModeToAppended()
    writer.EncodeAppendedDataOff()
    if not writer.Write():
        sys.exit(f"cannot write {out_path}")
    return meta


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument(
        "--shared", default=os.path.join(here, "..", "..", "shared", "data", "volumes")
    )
    parser.add_argument("--out", default=os.path.join(here, "..", "Data", "Volumes"))
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    for stem, name in VOLUMES.items():
        out_path = os.path.join(args.out, name + ".vti")
        meta = convert(args.shared, stem, out_path)
        print(
            f"{name:8s} {meta['dims']} {meta['dtype']} spacing {meta['spacing']} -> "
            f"{out_path} ({os.path.getsize(out_path) / 1e6:.1f} MB)"
        )


if __name__ == "__main__":
    main()
