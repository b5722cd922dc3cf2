"""
The quick-return mechanism (seed 001)
=====================================

``examples/quick_return.py``: a crank (``manivela``) turning about ``base[2]`` drives a
slotted lever (``colisa``) through a pin sliding in its slot; the lever's tip pushes a
slider (``deslizadera``) along a guide through a connecting rod of length 5. The crank's
angle is the driver, ``velocidad * T + anguloI``.
"""
import os

import mechgen
from mechgen import plot

ROOT = os.path.abspath(os.path.join("..", ".."))     # docs/gallery/, where it runs

mech = mechgen.compile(os.path.join(ROOT, "examples", "quick_return.py"))
s = mech.solve(0.15, level="acceleration")
print(f"T = 0.15: Th3 = {s['Th3']:.6f}, X4d = {s['X4d']:.4f}, X4dd = {s['X4dd']:.4f}")

# %%
# The mechanism at T = 0.3, with the path of the lever's tip over one crank turn.
sw = mech.sweep(0.0, 1.0, 101, level="velocity")
d = plot.draw(mech, mech.solve(0.3), sweep=sw, trace=("colisa[2]",), labels=True)

# %%
# The slider's stroke and speed over the turn, and for three crank lengths.
plot.plot(sw, "X4", "X4d")
family = [mech.with_params(longitud=L).sweep(0.0, 1.0, 101) for L in (1.5, 2.25, 3.0)]
plot.plot(family, "X4", title="slider stroke X4 for three crank lengths")

# %%
# The two assembly modes at T = 0.85: the slider right or left of the lever.
plot.draw_modes(mech, [mech.solve(0.85), mech.solve(0.85, guess={"X4": 1.0})])
