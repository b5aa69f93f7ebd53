"""Each shipped screenshot agrees with the view file it is documented with.

Compared: per row of Data/README.md's "Reference screenshots" table, the picture's border (its
outer row and column of pixels on every side) with the "background" of the view file the row
names. Every Data/Screenshots/*.png must have a row. Tolerances: the border's median within 3
levels of 255 per channel of the view's background (PNG is lossless; 8 levels for JPEG), and at
least 75 % of the border's pixels within 3 levels (8 for JPEG) of it (a background, not an object
cut by the frame). The picture must also be the view's size.

Usage: python3 CheckScreenshotBackgrounds.py DATA_DIR
"""
import json
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "Common"))
from pictures import read_png  # noqa: E402

data = sys.argv[1]
with open(os.path.join(data, "README.md")) as f:
    readme = f.read()
section = readme[readme.index("## Reference screenshots") :]
rows = re.findall(r"^\| `([^`]+\.(?:png|jpg|jpeg))` \|[^|]*\| `([^`]+\.json)`", section, re.M)
documented = dict(rows)
shipped = sorted(n for n in os.listdir(os.path.join(data, "Screenshots")) if n.endswith(".png"))
assert shipped, "no shipped screenshots"
missing = [n for n in shipped if n not in documented]
assert not missing, f"screenshots without a documented view file in Data/README.md: {missing}"

failures = []
for name in shipped:
    picture = read_png(os.path.join(data, "Screenshots", name))
    with open(os.path.join(data, documented[name])) as f:
        view = json.load(f)
    h, w, _ = picture.shape
    if [w, h] != list(view["size"]):
        failures.append(f"{name}: {w} x {h}, its view {documented[name]} is {view['size']}")
        continue
    border = np.concatenate([picture[0], picture[-1], picture[:, 0], picture[:, -1]])
    background = np.array(view["background"]) * 255.0
    tol = 8.0 if name.endswith((".jpg", ".jpeg")) else 3.0
    median = np.median(border, axis=0)
    near = np.mean(np.max(np.abs(border - background), axis=1) <= tol)
    line = (
        f"{name}: border median {np.round(median).astype(int).tolist()}, "
        f"{100 * near:.0f} % of the border near {documented[name]}'s background "
        f"{np.round(background).astype(int).tolist()}"
    )
    print(line)
    if np.max(np.abs(median - background)) > tol or near < 0.75:
        failures.append(line)
assert not failures, "screenshots disagree with their view files:\n" + "\n".join(failures)
print(f"{len(shipped)} screenshots agree with their view files")
