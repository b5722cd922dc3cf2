"""
Cams: roller, flat-faced and oscillating followers
==================================================

Three of Mech's cam contacts, each adding its contact parameter as a coordinate:
``examples/cam_cycloidal.py`` (a disc cam designed from a cycloidal motion law, an offset
translating roller follower: ``cam_to_point`` with ``radius=``),
``examples/cam_eccentric.py`` (an eccentric circle and a flat-faced follower:
``cam_to_line``) and ``examples/cam_roller_arm.py`` (an oscillating roller arm).
"""
import os

import mechgen
from mechgen import plot

ROOT = os.path.abspath(os.path.join("..", ".."))     # docs/gallery/, where it runs
EXAMPLES = os.path.join(ROOT, "examples")

for name, t in (("cam_cycloidal", 0.2), ("cam_eccentric", 0.1), ("cam_roller_arm", 0.25)):
    mech = mechgen.compile(os.path.join(EXAMPLES, name + ".py"))
    sw = mech.sweep(0.0, 1.0, 121, level="acceleration")
    plot.draw(mech, mech.solve(t), title=f"{name} at T = {t}")
    print(f"{name}: coordinates {', '.join(mech.coordinates)}")

# %%
# The last one's follower: the arm's angle and its rates over one turn of the cam.
plot.plot(sw, "Th3", "Th3d", "Th3dd")
