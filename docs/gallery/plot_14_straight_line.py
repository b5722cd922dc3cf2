"""
A straight-line four-bar, fitted and toleranced
===============================================

``examples/straight_line.py`` is Hoekens' straight-line four-bar with its lengths as
parameters; ``examples/straight_line_demo.py`` chooses them with ``mech.fit`` so that a
coupler point passes ten points of the segment y = 4, 0 ≤ x ≤ 4, then asks how far from
straight the real part runs with every length held to ±0.01 and each pin's clearance
0.005 (``mech.tolerance``: worst case, RSS and Monte Carlo). Run here as it is, its
pictures written to a scratch folder rather than ``docs/``.

The fit and the Monte Carlo samples are design tables of some 30,000 designs: this page
runs them compiled (``MECHGEN_TIER=auto``), on the repository's ``generated/`` module
whose numba cache the test suite has filled.
"""
import importlib.util
import os
import tempfile

import matplotlib.image as mpimg
import matplotlib.pyplot as plt

import mechgen
from mechgen import plot

ROOT = os.path.abspath(os.path.join("..", ".."))     # docs/gallery/, where it runs

hoekens = mechgen.compile(os.path.join(ROOT, "examples", "straight_line.py"))
sw = hoekens.sweep(0, 1, 181)
plot.draw(hoekens, hoekens.solve(0.25), sweep=sw, trace=("coupler[3]",),
          title="Hoekens' linkage (the model's defaults)")

# %%
# The demo: the fit, the bands and the stack-up table.
spec = importlib.util.spec_from_file_location(
    "straight_line_demo", os.path.join(ROOT, "examples", "straight_line_demo.py"))
demo = importlib.util.module_from_spec(spec)
spec.loader.exec_module(demo)
demo.DOCS = scratch = tempfile.mkdtemp()      # its pictures go here, not docs/
tier = os.environ.get("MECHGEN_TIER")
os.environ["MECHGEN_TIER"] = "auto"
try:
    demo.main()
finally:
    os.environ["MECHGEN_TIER"] = tier or "python"

for name in ("straight_line_fit.png", "straight_line_band.png"):
    fig, ax = plt.subplots(figsize=(8, 5))
    ax.imshow(mpimg.imread(os.path.join(scratch, name)))
    ax.set_axis_off()
    fig.tight_layout()
