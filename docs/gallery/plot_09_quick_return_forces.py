"""
Forces on the quick-return
==========================

``examples/quick_return_forces.py``: the seed's quick-return with masses, gravity and a
cutting force of 500 on the slider's slow stroke. A sweep at level ``"dynamic"`` gives the
motor's torque, every pin's force, the frame's shaking and the flywheel.
"""
import os

import mechgen
from mechgen import plot

ROOT = os.path.abspath(os.path.join("..", ".."))     # docs/gallery/, where it runs

mech = mechgen.compile(os.path.join(ROOT, "examples", "quick_return_forces.py"))
sw = mech.sweep(0, 1, 361, level="dynamic")
torque = sw.driver("crank driver")
print(f"peak torque {torque.max():.2f}, mean {torque[:-1].mean():.2f}")
print(f"flywheel for ±2.5 %: {sw.flywheel(0.05)['inertia']:.1f}")

# %%
# The torque against the crank angle, its mean and the areas about it (the energy a
# flywheel stores and gives back).
e = plot.effort(sw)

# %%
# The forces at T = 0.7, and the lever's free body diagram.
plot.draw(mech, mech.solve(0.7, level="dynamic"), forces=True)
plot.draw(mech, mech.solve(0.7, level="dynamic"), forces="colisa")
