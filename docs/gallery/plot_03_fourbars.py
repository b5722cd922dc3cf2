"""
The four-bar of seed 000, three ways
====================================

One four-bar (crank a = 0.8, coupler b = 2.5, rocker c = 2, ground d = 3) written three
ways: ``examples/fourbar.py`` as bodies joined by revolutes, ``examples/fourbar_loop.py``
as the seed writes it (the complex vector loop ``m.loop(...)`` on three angles) and
``examples/fourbar_joints.py`` with joints that bring their own coordinate
(``gen_revolute``; its second model is a slider-crank on ``gen_translate``).
"""
import os

import mechgen
from mechgen import plot

ROOT = os.path.abspath(os.path.join("..", ".."))     # docs/gallery/, where it runs
EXAMPLES = os.path.join(ROOT, "examples")

bodies = mechgen.compile(os.path.join(EXAMPLES, "fourbar.py"))
sw = bodies.sweep(0.0, 1.0, 121, level="velocity")
plot.draw(bodies, bodies.solve(0.1), sweep=sw, trace=("coupler.at(1.25, 0.8)",),
          title="fourbar: the coupler point's curve")

# %%
# The loop form has only the two unknown angles as coordinates (the crank's is the seed's
# θ2 = π/3): one position, the same as the body model's at T = 0.
loop = mechgen.compile(os.path.join(EXAMPLES, "fourbar_loop.py"))
s_loop, s_bodies = loop.solve(0.0), bodies.solve(0.0)
print("loop:", loop.coordinates, [round(s_loop[c], 6) for c in loop.coordinates])
print("bodies: Th3, Th4 =", round(s_bodies["Th3"], 6), round(s_bodies["Th4"], 6))
print("difference:", abs(s_loop["theta3"] - s_bodies["Th3"])
      + abs(s_loop["theta4"] - s_bodies["Th4"]))

# %%
# The joints with their own coordinate: the crank's angle and the slider's travel are
# coordinates, driven and plotted by name.
for name in ("fourbar_gen", "slider_crank_gen"):
    mech = mechgen.compile(mechgen.load_model(os.path.join(EXAMPLES, "fourbar_joints.py"),
                                              name=name))
    plot.draw(mech, mech.solve(0.2), title=f"{name}: coordinates {', '.join(mech.coordinates)}")
