"""Checks what a Design Gallery GUI test wrote into the volume's colour map.

Usage: python3 CheckGuiRecord.py RECORD EXPECTED_PRESET SEQUENCE
  RECORD: JSON lines of RGBPoints (GuiSetup.py), the first the initial map;
  EXPECTED_PRESET: the ParaView preset the ddg command line writes for the design;
  SEQUENCE: "apply" (the map ends as the expected preset) or "apply-undo-apply" (expected,
  then the initial map again after Edit > Undo, then expected again).
"""
import json
import sys

record, expected_file, sequence = sys.argv[1:4]
states = [json.loads(line) for line in open(record) if line.strip()]
preset = json.load(open(expected_file))
expected = (preset[0] if isinstance(preset, list) else preset)["RGBPoints"]
initial = states[0]


def same(a, b):
    return len(a) == len(b) and all(abs(x - y) <= 1e-6 * max(1.0, abs(y)) for x, y in zip(a, b))


distinct = [states[0]]
for s in states[1:]:
    if not same(s, distinct[-1]):
        distinct.append(s)
names = [
    "initial" if same(s, initial) else "expected" if same(s, expected) else "other"
    for s in distinct
]
print("colour map states:", " -> ".join(names), f"({len(expected) // 4} expected control points)")
want = {
    "apply": ["initial", "expected"],
    "apply-undo-apply": ["initial", "expected", "initial", "expected"],
}[sequence]
if names != want:
    sys.exit(f"the colour map went {names}, expected {want}")
print("RGBPoints equal the ddg command line's preset (relative tolerance 1e-6)")
