"""
Seed 001 step by step: the notebook
===================================

``examples/quick_return.ipynb`` walks through all of seed 001 — the model, its equations,
SolveMech, the assembly modes, the seed's drawing, every output function, sweeps,
velocities, accelerations and the slider's extremes — the way Mech's notebook does. This
page runs its code cells in order, from ``examples/`` as the notebook does (its IPython
magics left out), and shows the pictures it draws; the notebook itself, with its
outputs, is in the repository.
"""
import json
import os

ROOT = os.path.abspath(os.path.join("..", ".."))     # docs/gallery/, where it runs
NOTEBOOK = os.path.join(ROOT, "examples", "quick_return.ipynb")

with open(NOTEBOOK, encoding="utf-8") as fh:
    cells = [c for c in json.load(fh)["cells"] if c["cell_type"] == "code"]

here = os.getcwd()
os.chdir(os.path.dirname(NOTEBOOK))
try:
    namespace = {"__name__": "quick_return_notebook"}
    for number, cell in enumerate(cells, 1):
        source = "".join(line for line in cell["source"] if not line.startswith("%"))
        exec(compile(source, f"quick_return.ipynb, code cell {number}", "exec"), namespace)
finally:
    os.chdir(here)
print(f"{len(cells)} code cells run")
