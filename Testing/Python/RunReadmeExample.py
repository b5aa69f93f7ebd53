"""Runs the README's pvpython example verbatim: the block between the markers
<!-- pvpython-example:begin --> and <!-- pvpython-example:end --> (a ```python fence inside).

Usage: build/bin/pvpython RunReadmeExample.py README.md WORKDIR
"""
import os
import re
import sys

readme, workdir = sys.argv[1:3]
text = open(readme).read()
block = re.search(
    r"<!-- pvpython-example:begin -->\s*```python\n(.*?)```\s*<!-- pvpython-example:end -->",
    text,
    re.S,
)
if not block:
    sys.exit("the README has no pvpython example between its markers")
code = block.group(1)
print(f"running the README's example ({len(code.strip().splitlines())} lines)")
os.makedirs(workdir, exist_ok=True)
os.chdir(workdir)
exec(compile(code, "README example", "exec"), {"__name__": "__main__"})
for name in ("found.json", "found.png"):
    assert os.path.getsize(name) > 0, name
print("the README example ran and wrote found.json and found.png")
