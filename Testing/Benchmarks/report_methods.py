"""report_methods.py: what the report measures with: the `ddg` program, views, ParaView's render
of a preset (the judge of every method) and the screenshot -> TF methods (each: a screenshot and
its view -> a preset file and the seconds its `ddg` commands took).
"""
import json
import math
import os
import re
import subprocess
import time

import numpy as np

from paraview.simple import (
    ColorBy,
    CreateView,
    GetColorTransferFunction,
    GetOpacityTransferFunction,
    Render,
    SaveScreenshot,
    Show,
    XMLImageDataReader,
)

from report_common import DATA, PRIMITIVES

# --- views ----------------------------------------------------------------------------------------


def load_view(volume, name):
    with open(os.path.join(DATA, "Views", f"{volume}_{name}.json")) as f:
        v = json.load(f)
    v["background"] = [1.0, 1.0, 1.0]
    return v


def rotated(view, azimuth=0.0, elevation=0.0, zoom=1.0, roll=0.0, pan=(0.0, 0.0)):
    """The view's camera orbited about its focal point (degrees), moved closer by `zoom`, rolled
    about its direction of view (degrees) and panned by `pan` (right, up) view heights at the
    focal point (the picture's content moves the other way)."""
    v = json.loads(json.dumps(view))
    c = v["camera"]
    f, p, up = (np.array(c[k], float) for k in ("focal_point", "position", "view_up"))
    d = p - f
    up = up / np.linalg.norm(up)

    def rot(x, axis, deg):
        axis = axis / np.linalg.norm(axis)
        t = math.radians(deg)
        return (
            x * math.cos(t)
            + np.cross(axis, x) * math.sin(t)
            + axis * np.dot(axis, x) * (1 - math.cos(t))
        )

    d = rot(d, up, azimuth)
    right = np.cross(d, up)
    d, up = rot(d, right, elevation), rot(up, right, elevation)
    up = rot(up, -d, roll)  # about the direction of view (focal point - position)
    d = d / zoom
    right = np.cross(-d, up)
    right /= np.linalg.norm(right)
    height = 2 * np.linalg.norm(d) * math.tan(math.radians(c.get("view_angle", 30.0)) / 2)
    shift = height * (pan[0] * right + pan[1] * up)
    c["focal_point"] = list(f + shift)
    c["position"] = list(f + shift + d)
    c["view_up"] = list(up)
    return v


# --- ParaView renders -----------------------------------------------------------------------------


class ParaViewScene:
    """One ParaView render view per volume; renders a preset at a view (as pvrender.py does)."""

    def __init__(self, volume):
        self.reader = XMLImageDataReader(FileName=[os.path.join(DATA, "Volumes", volume + ".vti")])
        self.view = CreateView("RenderView")
        self.view.OrientationAxesVisibility = 0
        self.view.UseColorPaletteForBackground = 0
        self.display = Show(self.reader, self.view)
        self.array = self.reader.PointData.keys()[0]
        ColorBy(self.display, ("POINTS", self.array))
        self.display.SetRepresentationType("Volume")
        self.display.Shade = 0
        self.lut = GetColorTransferFunction(self.array)
        self.pwf = GetOpacityTransferFunction(self.array)
        self.lut.AutomaticRescaleRangeMode = "Never"
        Render(self.view)

    def render(self, preset_file, view, out, shade=False, axes=False):
        """ParaView's screenshot of the preset at `view` (its "background2": ParaView's gradient,
        Background at the bottom, Background2 at the top); `axes`: with the orientation axes, as
        a screenshot of the GUI has them."""
        with open(preset_file) as f:
            p = json.load(f)
        p = p[0] if isinstance(p, list) else p
        self.lut.ColorSpace = p.get("ColorSpace", "RGB")
        self.lut.HSVWrap = int(p.get("HSVWrap", 0))
        self.lut.RGBPoints = p["RGBPoints"]
        self.pwf.Points = p["Points"]
        self.display.Shade = int(shade)
        self.view.Background = view["background"]
        gradient = view.get("background2") is not None
        self.view.BackgroundColorMode = "Gradient" if gradient else "Single Color"
        if gradient:
            self.view.Background2 = view["background2"]
        self.view.OrientationAxesVisibility = int(axes)
        self.view.ViewSize = view["size"]
        c = view["camera"]
        self.view.CameraPosition, self.view.CameraFocalPoint = c["position"], c["focal_point"]
        self.view.CameraViewUp = c["view_up"]
        self.view.CameraViewAngle = c.get("view_angle", 30.0)
        SaveScreenshot(out, self.view, ImageResolution=view["size"], TransparentBackground=0)
        self.display.Shade = 0
        self.view.BackgroundColorMode = "Single Color"
        self.view.OrientationAxesVisibility = 0
        return out


# --- the `ddg` program and the methods --------------------------------------------------------------


class Methods:
    """The `ddg` program (`exe`), a scratch directory (`work`) and the screenshot -> TF methods.
    A case is a dict: volume, model (bundle), preset, scene (ParaViewScene), views, view_files,
    refs (ParaView's renders of the preset at the views) and, for (b), unet (a U-Net bundle)."""

    def __init__(self, exe, work):
        self.exe, self.work = exe, work
        self.bin = os.path.dirname(exe)  # the benchmark programs beside it

    def ddg(self, *a, check=True):
        t = time.time()
        r = subprocess.run([self.exe, *map(str, a)], capture_output=True, text=True)
        if check and r.returncode != 0:
            raise RuntimeError(f"ddg {' '.join(map(str, a))}:\n{r.stderr.strip()}")  # reason last
        return r, time.time() - t

    def compare(self, a, b):
        r, _ = self.ddg("compare", a, b, "--json")
        return json.loads(r.stdout)

    def path(self, name):
        return os.path.join(self.work, name)

    def write_json(self, obj, name):
        path = self.path(name)
        with open(path, "w") as f:
            json.dump(obj, f)
        return path

    def query(self, case, shot, view_file, tag, model="model", suffix="query"):
        """(b'): analyzer -> TF decoder (`ddg query` with the case's `model` bundle)."""
        out = self.path(f"{tag}_{suffix}.json")
        _, s = self.ddg(
            "query",
            "--model",
            case[model],
            "--volume",
            case["volume"],
            "--image",
            shot,
            "--view",
            view_file,
            "--out-tf",
            out,
        )
        return out, s

    def nearest(self, case, shot, view_file, tag):
        """(a): the nearest outline design's decoded TF."""
        r, s1 = self.ddg(
            "query",
            "--model",
            case["model"],
            "--volume",
            case["volume"],
            "--image",
            shot,
            "--view",
            view_file,
            "--neighbours",
            "1",
        )
        row = int(re.search(r"design row (\d+)", r.stdout).group(1))
        history = self.write_json(
            {"format": "ddg-history", "version": 1, "steps": [{"action": "pick", "row": row}]},
            f"{tag}_pick.json",
        )
        out = self.path(f"{tag}_nearest.json")
        _, s2 = self.ddg(
            "replay",
            "--model",
            case["model"],
            "--volume",
            case["volume"],
            "--history",
            history,
            "--view",
            view_file,
            "--out-tf",
            out,
        )
        return out, s1 + s2

    def reconstruct(self, case, targets, views, tag, iterations, init=None, extra=()):
        """Differentiable reconstruction from the `targets` at their `views` (e: two of them)."""
        out = self.path(f"{tag}.json")
        cmd = [
            "reconstruct",
            "--volume",
            case["volume"],
            "--out",
            out,
            "--iterations",
            iterations,
            "--quiet",
            *extra,
        ]
        for t, v in zip(targets, views):
            cmd += ["--target", t, "--view", v]
        if init:
            cmd += ["--init", init]
        _, s = self.ddg(*cmd)
        return out, s

    def refine(self, case, shot, view_file, tag, iterations):
        """(b' + c): the query's TF refined by reconstruction."""
        init, s1 = self.query(case, shot, view_file, tag)
        out, s2 = self.reconstruct(
            case, [shot], [view_file], f"{tag}_refine{iterations}", iterations, init=init
        )
        return out, s1 + s2

    def direct(self, case, shot, view_file, tag, iterations):
        """(c): reconstruction from scratch."""
        return self.reconstruct(case, [shot], [view_file], f"{tag}_direct{iterations}", iterations)

    def primitives(self, case, shot, view_file, tag, iterations):
        """(d): PRIMITIVES Gaussian primitives fitted through the renderer's adjoint."""
        return self.reconstruct(
            case,
            [shot],
            [view_file],
            f"{tag}_prim{iterations}",
            iterations,
            extra=["--primitives", PRIMITIVES],
        )

    def match(self, case, shot, tag, init=None):
        """(f): the match, `ddg reconstruct` without --view: the picture's background, overlays
        and camera (from ParaView's reset camera) estimated, then the TF fitted; from grey, or
        from `init`. Returns the TF and the seconds; raises RuntimeError when it refuses."""
        out = self.path(f"{tag}_match.json")
        cmd = ["reconstruct", "--volume", case["volume"], "--target", shot, "--out", out]
        _, s = self.ddg(*cmd, "--quiet", *(["--init", init] if init else []))
        return out, s

    def query_match(self, case, shot, view_file, tag):
        """(b' + f): the match started from the query's TF (the query at `view_file`, the current
        camera)."""
        init, s1 = self.query(case, shot, view_file, tag)
        out, s2 = self.match(case, shot, f"{tag}_from_query", init=init)
        return out, s1 + s2

    def neural(self, case, shot, view_file, tag):
        """(b): the U-Net bundle's analyzer and renderer, then reconstruction from its render."""
        return self.query(case, shot, view_file, tag, model="unet", suffix="neural")

    def evaluate(self, case, preset, tag):
        """PSNR/SSIM of ParaView's renders of `preset` against the references at both views."""
        scene = case["scene"]
        out = {}
        for which in ("reference", "unseen"):
            png = scene.render(preset, case["views"][which], self.path(f"{tag}_{which}.png"))
            m = self.compare(png, case["refs"][which])
            out[which] = (m["psnr"], m["ssim"])
        return out
