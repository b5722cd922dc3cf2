"""
Five positions of a gate: Burmester synthesis
=============================================

``examples/burmester_five_poses.py`` asks which four-bars carry a hopper gate through five
positions, in order, on one assembly mode: every real Burmester pair, exactly, each
four-bar screened for circuit, branch and order defects. ``examples/gate_poses.csv`` holds
the same positions for the command line, ``mechgen synthesize``.
"""
import importlib.util
import os
import tempfile

import matplotlib.image as mpimg
import matplotlib.pyplot as plt

from mechgen.cli import main as mechgen_command

ROOT = os.path.abspath(os.path.join("..", ".."))     # docs/gallery/, where it runs

spec = importlib.util.spec_from_file_location(
    "burmester_five_poses", os.path.join(ROOT, "examples", "burmester_five_poses.py"))
gate = importlib.util.module_from_spec(spec)
spec.loader.exec_module(gate)
gate.table()
scratch = tempfile.mkdtemp()
gate.picture(os.path.join(scratch, "burmester_five_poses.png"))

fig, ax = plt.subplots(figsize=(8, 6))
ax.imshow(mpimg.imread(os.path.join(scratch, "burmester_five_poses.png")))
ax.set_axis_off()
fig.tight_layout()

# %%
# The same from the command line: ``mechgen synthesize examples/gate_poses.csv -o
# gate_fourbar.py --png gate.png`` prints the table and writes the best defect-free
# four-bar as a model file and a picture.
code = mechgen_command(["synthesize", os.path.join(ROOT, "examples", "gate_poses.csv"),
                        "-o", os.path.join(scratch, "gate_fourbar.py"),
                        "--png", os.path.join(scratch, "gate.png")])
print("exit status", code)
fig, ax = plt.subplots(figsize=(8, 6))
ax.imshow(mpimg.imread(os.path.join(scratch, "gate.png")))
ax.set_axis_off()
fig.tight_layout()
