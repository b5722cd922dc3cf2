"""
A family of quick-returns: a design table
=========================================

``examples/quick_return_synthesis.py`` makes the crank's length (``longitud``), the height
of its pivot (``altura``) and the lever's length (``palanca``) parameters. A design table
sweeps every combination over one crank turn in one call; here the slider's stroke over a
grid of crank and lever lengths (the user guide's design page chooses them with
``mech.optimize`` for a stroke of 10 and a time ratio of 1.8).
"""
import os

import matplotlib.pyplot as plt
import numpy as np

import mechgen
from mechgen import plot

ROOT = os.path.abspath(os.path.join("..", ".."))     # docs/gallery/, where it runs

mech = mechgen.compile(os.path.join(ROOT, "examples", "quick_return_synthesis.py"))
longitud, palanca = np.linspace(1.5, 4.0, 12), np.linspace(8.0, 12.0, 12)
tab = mech.sweep(0, 1, 61, params={"longitud": longitud, "palanca": palanca},
                 reduce=["X4"])
x4 = tab.reduced("X4")
stroke = np.where(x4.ok, x4.max - x4.min, np.nan)
print(f"{stroke.size} designs, {int(np.sum(~x4.ok))} that cannot turn")

fig, ax = plt.subplots(figsize=(6.4, 4.8))
cs = ax.contourf(palanca, longitud, stroke, levels=12, cmap="viridis")
fig.colorbar(cs, ax=ax, label="stroke of the slider")
ax.set_xlabel("palanca (lever length)")
ax.set_ylabel("longitud (crank length)")
ax.set_title("quick_return_synthesis: the slider's stroke")

# %%
# One design of the table, drawn.
design = mech.with_params(longitud=3.09, altura=7.12, palanca=11.52)
plot.draw(design, design.solve(0.0), sweep=design.sweep(0, 1, 61), trace=("colisa[2]",))
