"""Pictures for the Python tests: a PNG as a float array (top row first, RGB 0..255) and PSNR."""
import math

import numpy as np
from vtkmodules.util import numpy_support
from vtkmodules.vtkIOImage import vtkPNGReader


def read_png(path):
    """The PNG at ``path`` as an (h, w, 3) float64 array, top row first."""
    r = vtkPNGReader()
    r.SetFileName(path)
    r.Update()
    out = r.GetOutput()
    w, h, _ = out.GetDimensions()
    a = numpy_support.vtk_to_numpy(out.GetPointData().GetScalars()).reshape(h, w, -1)
    return a[::-1, :, :3].astype(np.float64)


def psnr(a, b):
    """PSNR (dB) of two arrays in 0..255; infinite when they are equal."""
    mse = np.mean((a / 255.0 - b / 255.0) ** 2)
    return float("inf") if mse == 0 else 10 * math.log10(1 / mse)
