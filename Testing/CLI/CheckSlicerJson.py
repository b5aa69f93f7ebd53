"""Checks 3D Slicer volume property files (.vp.json) against the fields their published schema
requires (Slicer/Modules/Loadable/VolumeRendering/Resources/Schema/
volume-property-schema-v1.0.0.json): "@schema" and "volumeProperties" at the top; per property
an "effectiveRange" of 2 numbers, "interpolationType" in nearest/linear/cubic; per component a
"componentWeight" in [0, 1], "scalarOpacityUnitDistance" >= 0, "lighting" with ambient, diffuse,
specular in [0, 1] and specularPower >= 0, and piecewise functions whose points carry x, y,
midpoint, sharpness (colour points: x, color of 3 values in [0, 1], midpoint, sharpness).
Usage: CheckSlicerJson.py FILE...   (exit 1 naming the first violation)
"""
import json
import sys


def fail(path, what):
    print(f"{path}: {what}")
    sys.exit(1)


def number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def check_points(path, name, fn, color):
    if not isinstance(fn, dict) or not isinstance(fn.get("points"), list) or not fn["points"]:
        fail(path, f"{name} needs a non-empty 'points' list")
    xs = []
    for p in fn["points"]:
        keys = (
            ("x", "color", "midpoint", "sharpness")
            if color
            else ("x", "y", "midpoint", "sharpness")
        )
        for k in keys:
            if k not in p:
                fail(path, f"{name} point {p} lacks '{k}'")
        if color:
            c = p["color"]
            if not (
                isinstance(c, list) and len(c) == 3 and all(number(v) and 0 <= v <= 1 for v in c)
            ):
                fail(path, f"{name} colour {c} is not 3 numbers in [0, 1]")
        elif not number(p["y"]):
            fail(path, f"{name} y is not a number")
        xs.append(p["x"])
    if xs != sorted(xs):
        fail(path, f"{name} x values are not increasing")


def check(path):
    with open(path) as f:
        doc = json.load(f)
    for k in ("@schema", "volumeProperties"):
        if k not in doc:
            fail(path, f"missing required '{k}'")
    if "volume-property-schema-v1.0.0.json" not in doc["@schema"]:
        fail(path, "'@schema' does not name volume-property-schema-v1.0.0.json")
    if not isinstance(doc["volumeProperties"], list) or not doc["volumeProperties"]:
        fail(path, "'volumeProperties' must be a non-empty array")
    for prop in doc["volumeProperties"]:
        r = prop.get("effectiveRange")
        if not (isinstance(r, list) and len(r) == 2 and all(number(v) for v in r) and r[0] < r[1]):
            fail(path, f"effectiveRange {r} is not 2 increasing numbers")
        if prop.get("interpolationType", "linear") not in ("nearest", "linear", "cubic"):
            fail(path, "interpolationType is not nearest, linear or cubic")
        comps = prop.get("components")
        if not isinstance(comps, list) or not comps:
            fail(path, "no components")
        for c in comps:
            if not (
                number(c.get("componentWeight", 1.0)) and 0 <= c.get("componentWeight", 1.0) <= 1
            ):
                fail(path, "componentWeight outside [0, 1]")
            if not (
                number(c.get("scalarOpacityUnitDistance", 1.0))
                and c.get("scalarOpacityUnitDistance", 1.0) >= 0
            ):
                fail(path, "scalarOpacityUnitDistance is negative")
            light = c.get("lighting")
            if light is not None:
                for k in ("ambient", "diffuse", "specular", "specularPower"):
                    if k not in light or not number(light[k]):
                        fail(path, f"lighting lacks '{k}'")
                for k in ("ambient", "diffuse", "specular"):
                    if not 0 <= light[k] <= 1:
                        fail(path, f"lighting {k} outside [0, 1]")
            check_points(path, "scalarOpacity", c.get("scalarOpacity"), False)
            check_points(path, "rgbTransferFunction", c.get("rgbTransferFunction"), True)
            if "gradientOpacity" in c:
                check_points(path, "gradientOpacity", c["gradientOpacity"], False)
    print(f"{path}: valid ({len(doc['volumeProperties'])} volume property)")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        fail("CheckSlicerJson.py", "usage: CheckSlicerJson.py FILE...")
    for p in sys.argv[1:]:
        check(p)
