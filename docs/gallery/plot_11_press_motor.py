"""
A press started by its motor: press_motor and press_motor_demo
==============================================================

``examples/press_motor.py`` is a mechanical press (crank 0.1 m, rod 0.45 m, a 40 kg ram)
driven by a motor whose torque falls with speed, T0 (1 − ω/ω0), pressing 3000 N over the
last 20 mm of each down stroke. ``examples/press_motor_demo.py`` releases the crank's
driver at t = 0 (``mech.simulate``) and lets the motor bring the press up to speed with a
small and a large flywheel. Run here as it is, its picture written to a scratch folder
rather than ``docs/``.
"""
import importlib.util
import os
import tempfile

import matplotlib.image as mpimg
import matplotlib.pyplot as plt

import mechgen
from mechgen import plot

ROOT = os.path.abspath(os.path.join("..", ".."))     # docs/gallery/, where it runs

press = mechgen.compile(os.path.join(ROOT, "examples", "press_motor.py"))
plot.draw(press, press.solve(0.0), title="press_motor at T = 0")

# %%
# The demo: the crank's speed from rest, with a 0.05 and a 2 kg m² flywheel.
spec = importlib.util.spec_from_file_location(
    "press_motor_demo", os.path.join(ROOT, "examples", "press_motor_demo.py"))
demo = importlib.util.module_from_spec(spec)
spec.loader.exec_module(demo)
demo.DOCS = scratch = tempfile.mkdtemp()      # its picture goes here, not docs/
demo.main()

fig, ax = plt.subplots(figsize=(8, 4.2))
ax.imshow(mpimg.imread(os.path.join(scratch, "press_motor_speed.png")))
ax.set_axis_off()
fig.tight_layout()
