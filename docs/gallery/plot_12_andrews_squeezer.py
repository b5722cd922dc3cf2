"""
Andrews' squeezing mechanism
============================

``examples/andrews_squeezer.py``: seven bodies, ten pins, a motor torque and a stiff
spring — Hairer & Wanner's benchmark of multibody integrators. Released from rest, it
moves under its loads alone (``mech.simulate``): here its first 0.03 s, with the energy
it gains beside the motor's work.
"""
import os

import mechgen
from mechgen import plot

ROOT = os.path.abspath(os.path.join("..", ".."))     # docs/gallery/, where it runs

mech = mechgen.compile(os.path.join(ROOT, "examples", "andrews_squeezer.py"))
sw = mech.simulate(0.0, 0.03, 31, rtol=1e-8, atol=1e-10)
print(f"{len(mech.coordinates)} coordinates; {sw.steps} steps")
energy = sw.energy()
print(f"kinetic energy at t = 0.03: {energy['kinetic'][-1]:.6g}")
plot.draw(mech, mech.solve(0.0), sweep=sw, title="andrews_squeezer at rest, t = 0")

# %%
# The crank's angle and the first arm's over the 0.03 s.
plot.plot(sw, "Th2", "Th3")
