"""
Jansen's Strandbeest leg
========================

``examples/strandbeest.py``: seven moving bodies (the crank, five links and the foot),
21 coordinates, Jansen's "holy numbers". Its foot's path over one crank turn is the
flat-bottomed curve that makes the walker walk.
"""
import os

import mechgen
from mechgen import plot

ROOT = os.path.abspath(os.path.join("..", ".."))     # docs/gallery/, where it runs

mech = mechgen.compile(os.path.join(ROOT, "examples", "strandbeest.py"))
print(len(mech.coordinates), "coordinates")
sw = mech.sweep(0.0, 1.0, 181, level="acceleration")
foot = "foot[3]"                  # the toe
plot.draw(mech, mech.solve(0.3), sweep=sw, trace=(foot,), title=f"the path of {foot}")
