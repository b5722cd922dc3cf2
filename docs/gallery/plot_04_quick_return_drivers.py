"""
The quick-return driven otherwise: by its slider, in stages
===========================================================

The seed's quick-return with other drivers: ``examples/quick_return_slider.py`` drives the
slider (section 2B of seed 001: X4 = 4.13931 + 5.40447 sin 2πT), ``examples/
quick_return_stages.py`` turns the crank forward then back (Mech's TimeSwitch), and
``examples/quick_return_crank_slider.py`` hands the drive from the crank to the slider at
T = 0.25 (Mech's StageSwitch). A sweep across a switch holds its time twice, with each
side's velocities.
"""
import os

import mechgen
from mechgen import plot

ROOT = os.path.abspath(os.path.join("..", ".."))     # docs/gallery/, where it runs
EXAMPLES = os.path.join(ROOT, "examples")

slider = mechgen.compile(os.path.join(EXAMPLES, "quick_return_slider.py"))
# the fitted law overshoots the true stroke: the mechanism locks near T = 0.246 and 0.754
print("lock positions:", slider.singularities(0.0, 1.0))
# (and cannot assemble just past them): the guess's stretch runs from 0.754 − 1 to 0.246
sw = slider.sweep(-0.23, 0.23, 93, level="velocity")
plot.draw(slider, slider.solve(0.0), sweep=sw, trace=("manivela[2]",),
          title="quick_return_slider: the crank pin's path between the locks")
plot.plot(sw, "X4", "Th2")

# %%
# Two stages: forward up to T = 0.5, then back.
stages = mechgen.compile(os.path.join(EXAMPLES, "quick_return_stages.py"))
sw = stages.sweep(0.0, 1.0, 101, level="velocity")
print("switches:", sw.switches, " jump of X4d:", sw.jump("X4d"))
plot.plot(sw, "X4", "X4d")

# %%
# A driver taking over: the crank, then the slider.
handover = mechgen.compile(os.path.join(EXAMPLES, "quick_return_crank_slider.py"))
sw = handover.sweep(0.0, 1.0, 101, level="velocity")
print("switches:", sw.switches)
plot.plot(sw, "X4", "Th2")
