"""
A yoke: point_on_lines, origin_lock, directed_distance
======================================================

``examples/yoke.py`` holds three of Mech's less common constraints in one small mechanism:
a crank turns about the origin, a block's origin is held where two lines cross
(``point_on_lines``), a cover is locked to it (``origin_lock``) and tilted by a directed
distance driven in time (``directed_distance``).
"""
import os

import mechgen
from mechgen import plot

ROOT = os.path.abspath(os.path.join("..", ".."))     # docs/gallery/, where it runs

mech = mechgen.compile(os.path.join(ROOT, "examples", "yoke.py"))
sw = mech.sweep(0.0, 1.0, 101, level="velocity")
plot.draw(mech, mech.solve(0.15), sweep=sw, labels=True)
plot.plot(sw, *mech.coordinates[3:6])
