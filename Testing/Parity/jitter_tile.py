"""ParaView's per-pixel ray-start jitter against `ddg render --jitter`.

ParaView's GPU volume mapper starts each ray's samples at entry + j * step, j from a 64 x 64
tile indexed by the window pixel. To see j, a volume whose scalar is its z coordinate (8 x 8 x 64
points, spacing 1000 x 1000 x 1, so one sample step is most of the depth) is looked at straight
down -z with opacity 1 everywhere: the first sample decides the pixel, and a colour map that
falls from white to black over one step before the top face makes red = j. ParaView renders it
at 128 x 128 (two tiles each way); `ddg render --jitter` renders the same preset and view. The
images must agree to one 8-bit level in every pixel and channel (the rounding of the colour
ramp); --write-tile prints the tile ParaView shows (how Core/Render/Jitter.cxx's table was
measured).

    scripts/with-xvfb.sh pvpython Testing/Parity/jitter_tile.py --ddg build/bin/ddg --out build/Testing/Jitter
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np
from paraview.simple import (
    ColorBy,
    CreateView,
    Delete,
    GetColorTransferFunction,
    GetOpacityTransferFunction,
    Render,
    SaveScreenshot,
    Show,
    XMLImageDataReader,
)
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

DIMS = (8, 8, 64)
SPACING = (1000.0, 1000.0, 1.0)


def sample_distance():
    """ParaView's sample distance for this volume (mean spacing / 2, scaled below 100 points)."""
    n = ((DIMS[0] - 1) * (DIMS[1] - 1) * (DIMS[2] - 1)) ** (1 / 3)
    return sum(SPACING) / 6 * (0.01 + 0.99 * n / 100)


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--ddg", required=True, help="path of the ddg program")
    parser.add_argument("--out", required=True, help="directory for the files")
    parser.add_argument("--size", type=int, default=128)
    parser.add_argument("--write-tile", action="store_true", help="print the 64 x 64 tile")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)

    image = vtkImageData()
    image.SetDimensions(*DIMS)
    image.SetSpacing(*SPACING)
    z = np.repeat(np.arange(DIMS[2], dtype=np.float32), DIMS[0] * DIMS[1])
    array = numpy_to_vtk(z, deep=1)
    array.SetName("z")
    image.GetPointData().SetScalars(array)
    volume_path = os.path.join(args.out, "ramp.vti")
    writer = vtkXMLImageDataWriter()
    writer.SetFileName(volume_path)
    writer.SetInputData(image)
    writer.Write()

    top = DIMS[2] - 1
    d = sample_distance()
    preset = {
        "Name": "first sample depth",
        "ColorSpace": "RGB",
        "RGBPoints": [0, 1, 1, 1, top - d, 1, 1, 1, top, 0, 0, 0],
        "Points": [0, 1, 0.5, 0, top, 1, 0.5, 0],
    }
    centre = [(DIMS[0] - 1) * SPACING[0] / 2, (DIMS[1] - 1) * SPACING[1] / 2]
    view_json = {
        "camera": {
            "position": centre + [1000.0],
            "focal_point": centre + [0.0],
            "view_up": [0, 1, 0],
            "view_angle": 30.0,
            "parallel_projection": True,
            "parallel_scale": 0.4 * centre[0] * 2,
        },
        "size": [args.size, args.size],
        "background": [0, 0, 0],
    }
    tf_path = os.path.join(args.out, "ramp_tf.json")
    view_path = os.path.join(args.out, "ramp_view.json")
    with open(tf_path, "w") as f:
        json.dump([preset], f)
    with open(view_path, "w") as f:
        json.dump(view_json, f)

    reader = XMLImageDataReader(FileName=[volume_path])
    view = CreateView("RenderView")
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = [0, 0, 0]
    view.ViewSize = [args.size, args.size]
    display = Show(reader, view)
    ColorBy(display, ("POINTS", "z"))
    display.SetRepresentationType("Volume")
    lut = GetColorTransferFunction("z")
    lut.AutomaticRescaleRangeMode = "Never"
    lut.RGBPoints = preset["RGBPoints"]
    GetOpacityTransferFunction("z").Points = preset["Points"]
    Render(view)
    cam = view_json["camera"]
    view.CameraPosition = cam["position"]
    view.CameraFocalPoint = cam["focal_point"]
    view.CameraViewUp = cam["view_up"]
    view.CameraParallelProjection = 1
    view.CameraParallelScale = cam["parallel_scale"]
    Render(view)
    pv_png = os.path.join(args.out, "ramp_paraview.png")
    SaveScreenshot(pv_png, view, ImageResolution=[args.size, args.size], TransparentBackground=0)
    Delete(display)
    Delete(view)
    Delete(reader)

    ddg_png = os.path.join(args.out, "ramp_ddg.png")
    subprocess.run(
        [
            args.ddg,
            "render",
            "--volume",
            volume_path,
            "--tf",
            tf_path,
            "--view",
            view_path,
            "--out",
            ddg_png,
            "--jitter",
        ],
        check=True,
        capture_output=True,
    )

    def read_rgb(path):
        png = vtkPNGReader()
        png.SetFileName(path)
        png.Update()
        dims = png.GetOutput().GetDimensions()
        rgb = vtk_to_numpy(png.GetOutput().GetPointData().GetScalars())[:, :3]
        return rgb.astype(int).reshape(dims[1], dims[0], 3)

    pv, ours = read_rgb(pv_png), read_rgb(ddg_png)
    red = pv[:, :, 0]
    if args.write_tile:  # rows from the bottom, as the window counts them (VTK images do too)
        for row in red[:64, :64]:
            print(", ".join(str(int(v)) for v in row) + ",")
    metrics = json.loads(
        subprocess.run(
            [args.ddg, "compare", "--json", pv_png, ddg_png],
            check=True,
            capture_output=True,
            text=True,
        ).stdout
    )
    levels = len(np.unique(red))
    worst = int(np.abs(pv - ours).max())
    print(
        f"jitter tile: ParaView vs ddg --jitter {metrics['psnr']:.2f} dB, largest difference "
        f"{worst} level(s); {levels} distinct first-sample depths in ParaView's image"
    )
    ok = worst <= 1 and levels > 200
    print("ok" if ok else "FAIL")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
