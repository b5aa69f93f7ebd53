"""vtkDDGDesignHistory (the panel's and pvpython's one writer of history steps) in pvpython.

Compared: the JSON it writes for each kind of step against the documented history format
(README, "File contracts"; Core/Gallery/History.h), exactly; an "axes" step replaced by the next
one (the sliders move one step); the JSON read back (SetJSON) gives the same steps; Ease against
the closed forms (linear t, smoothstep 3t^2 - 2t^3, cosine (1 - cos(pi t)) / 2) at 1e-12. Bad
input (malformed latents, an unknown easing, a history that starts with an edit): False / -1 and
a message, the history unchanged.

Usage: pvpython TestDesignHistory.py PYTHON_DIR
"""
import json
import math
import sys

sys.path.insert(0, sys.argv[1])
from ddg_vtk import DDGFilters  # noqa: E402

h = DDGFilters.vtkDDGDesignHistory()
assert h.GetJSON() == "" and h.GetNumberOfSteps() == 0
h.AddPick(12)
assert h.AddLatent("[0.5, -1.0]", "shot.png")
assert h.AddBlend("[[1, 2], [3, 4], [5, 6]]", 0.25, 0.75)
view = {"camera": {"position": [0, 0, 5], "focal_point": [0, 0, 0], "view_up": [0, 1, 0]}}
assert h.AddEdit(json.dumps(view), 2, -1, -1, 4, 30.0, 1.0, 0.0, 1.5, False)
assert h.AddEdit(json.dumps(view), -1, 7, 9, 4, 0.0, 1.0, 0.0, 0.5, True)
assert h.SetAxes("[1.0]")
assert h.SetAxes("[1.0, -0.5]")  # replaces the last axes step
doc = json.loads(h.GetJSON())
assert doc["format"] == "ddg-history" and doc["version"] == 1
steps = doc["steps"]
assert [s["action"] for s in steps] == ["pick", "latent", "blend", "edit", "edit", "axes"], steps
assert steps[0] == {"action": "pick", "row": 12}
assert steps[1] == {"action": "latent", "latent": [0.5, -1.0], "image": "shot.png"}
assert steps[2] == {"action": "blend", "latents": [[1, 2], [3, 4], [5, 6]], "u": 0.25, "v": 0.75}
assert steps[3]["cluster"] == 2 and "pick" not in steps[3] and steps[3]["visibility"] == 1.5
assert steps[3]["view"] == view
assert steps[4]["pick"] == [7, 9] and "cluster" not in steps[4] and steps[4]["white"] is True
assert steps[5] == {"action": "axes", "steps": [1.0, -0.5]}
assert h.GetAction(5) == "axes" and h.GetAction(6) == ""

copy = DDGFilters.vtkDDGDesignHistory()
assert copy.SetJSON(h.GetJSON()) and copy.GetJSON() == h.GetJSON()
h.RemoveLastStep()
assert h.GetNumberOfSteps() == 5

for t in (0.0, 0.3, 0.5, 1.0):
    assert abs(DDGFilters.vtkDDGDesignHistory.Ease(t, "linear") - t) < 1e-12
    assert abs(DDGFilters.vtkDDGDesignHistory.Ease(t, "smoothstep") - t * t * (3 - 2 * t)) < 1e-12
    c = (1 - math.cos(math.pi * t)) / 2
    assert abs(DDGFilters.vtkDDGDesignHistory.Ease(t, "cosine") - c) < 1e-12
assert DDGFilters.vtkDDGDesignHistory.Ease(0.5, "bounce") == -1

before = h.GetJSON()
assert not h.AddLatent("[1, 'x']", "")
assert h.GetError() and h.GetJSON() == before
assert not h.AddBlend("{}", 0, 0)
bad = {"format": "ddg-history", "version": 1, "steps": [{"action": "axes", "steps": [1]}]}
assert not h.SetJSON(json.dumps(bad))
assert "starts with" in h.GetError(), h.GetError()
assert h.GetJSON() == before
print("ok")
