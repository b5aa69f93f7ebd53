"""Checks what a Design Gallery GUI test wrote into the volume's colour map.

Usage: python3 CheckGuiRecord.py RECORD EXPECTED_PRESET SEQUENCE
  RECORD: JSON lines of RGBPoints (GuiSetup.py), the first the initial map; for 2D designs
  {"use2d", "boxes", "range", "dims"} lines (the representation's UseTransfer2D and its
  TransferFunction2D's Boxes, Range and OutputDimensions); the last must be the applied one;
  EXPECTED_PRESET: the ParaView preset the ddg command line writes for the design; for 2D the
  TransferFunction2D properties of `ddg export --format paraview-2d` for it;
  SEQUENCE: "apply" (the map ends as the expected preset) or "apply-undo-apply" (expected,
  then the initial map again after Edit > Undo, then expected again).
"""
import json
import sys

record, expected_file, sequence = sys.argv[1:4]
states = [json.loads(line) for line in open(record) if line.strip()]
preset = json.load(open(expected_file))
two_d = isinstance(states[0], dict)
if two_d:  # UseTransfer2D is written before the Boxes: the states in between are dropped below
    expected = {
        "use2d": 1,
        "boxes": preset["Boxes"],
        "range": preset["Range"],
        "dims": preset["OutputDimensions"],
    }
else:
    expected = (preset[0] if isinstance(preset, list) else preset)["RGBPoints"]
initial = states[0]


def same(a, b):
    if two_d:
        return a["use2d"] == b["use2d"] and all(
            same_numbers(a[k], b[k]) for k in ("boxes", "range", "dims")
        )
    return same_numbers(a, b)


def same_numbers(a, b):
    return len(a) == len(b) and all(abs(x - y) <= 1e-6 * max(1.0, abs(y)) for x, y in zip(a, b))


names = [
    "initial" if same(s, initial) else "expected" if same(s, expected) else "other" for s in states
]
if two_d:
    names = [n for n in names if n != "other"]
names = [n for k, n in enumerate(names) if k == 0 or n != names[k - 1]]
print(
    "colour map states:",
    " -> ".join(names),
    f"({len(expected['boxes']) // 8} expected boxes)"
    if two_d
    else f"({len(expected) // 4} expected control points)",
)
want = {
    "apply": ["initial", "expected"],
    "apply-undo-apply": ["initial", "expected", "initial", "expected"],
}[sequence]
if names != want:
    sys.exit(f"the colour map went {names}, expected {want}")
if two_d and not same(states[-1], expected):  # nothing (e.g. the Color Map Editor) changed it after
    sys.exit(f"the last 2D state is not the applied one: {states[-1]}")
print(
    (
        "TransferFunction2D Boxes equal ddg export --format paraview-2d's"
        if two_d
        else "RGBPoints equal the ddg command line's preset"
    )
    + " (relative tolerance 1e-6)"
)
