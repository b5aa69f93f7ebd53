"""Checks what a Design Gallery GUI test wrote into the volume's colour map.

Usage: python3 CheckGuiRecord.py RECORD EXPECTED_PRESET SEQUENCE
  RECORD: JSON lines of RGBPoints (GuiSetup.py), the first the initial map; for 2D designs
  {"use2d", "boxes", "range", "dims"} lines (the representation's UseTransfer2D and its
  TransferFunction2D's Boxes, Range and OutputDimensions); the last must be the applied one;
  EXPECTED_PRESET: the ParaView preset the ddg command line writes for the design; for 2D the
  TransferFunction2D properties of `ddg export --format paraview-2d` for it;
  SEQUENCE: "apply" (the map ends as the expected preset) or "apply-undo-apply" (expected,
  then the initial map again after Edit > Undo, then expected again); "match-camera" (EXPECTED
  unused): the map goes initial -> matched -> initial -> matched (Apply, Undo, Redo; the two
  matched maps equal, whatever they are), and the camera record (RECORD + ".camera",
  CameraPosition per change) ends away -> the picture's -> away -> the picture's, the picture's
  being the camera before it was moved away (the picture was taken from the current camera;
  moved, Apply, Undo, Redo: the camera moves with the TF's undo step).
"""
import json
import sys

record, expected_file, sequence = sys.argv[1:4]
states = [json.loads(line) for line in open(record) if line.strip()]


def same_numbers(a, b):
    return len(a) == len(b) and all(abs(x - y) <= 1e-6 * max(1.0, abs(y)) for x, y in zip(a, b))


def deduplicated(names):
    return [n for k, n in enumerate(names) if k == 0 or n != names[k - 1]]


if sequence == "match-camera":
    initial = states[0]
    changed = [s for s in states if not same_numbers(s, initial)]
    if not changed or not all(same_numbers(s, changed[0]) for s in changed):
        sys.exit("the applied colour maps differ (or none was applied)")
    names = deduplicated(["initial" if same_numbers(s, initial) else "matched" for s in states])
    print("colour map states:", " -> ".join(names))
    if names != ["initial", "matched", "initial", "matched"]:
        sys.exit(f"the colour map went {names}, expected initial, matched, initial, matched")
    # the picture's camera is the current one at Match; +X moves away, Apply moves back, Undo
    # away, Redo back: the camera positions (deduplicated) end b, a, b, a with a seen before b
    cameras = [json.loads(line) for line in open(record + ".camera") if line.strip()]
    path = [c for k, c in enumerate(cameras) if k == 0 or not same_numbers(c, cameras[k - 1])]
    print("camera positions:", " -> ".join(str([round(x, 1) for x in c]) for c in path))
    if len(path) < 4:
        sys.exit("the camera did not move back and forth")
    b, a = path[-2], path[-1]
    first_b = next(k for k, c in enumerate(path) if same_numbers(c, b))
    if (
        same_numbers(a, b)
        or not same_numbers(path[-3], a)
        or not same_numbers(path[-4], b)
        or not any(same_numbers(c, a) for c in path[:first_b])
    ):
        sys.exit(
            "the camera did not go: the picture's, away, back (Apply), away (Undo), back (Redo)"
        )
    print("Apply, Undo and Redo moved the TF and the camera together")
    sys.exit(0)
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
