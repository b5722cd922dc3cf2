"""Jansen's leg (examples/strandbeest.py) with masses: every link a uniform bar of steel
tube (0.05 kg per unit of length, inertia m L²/12 about its midpoint), the hip and the
foot triangles as bars along their first side, gravity, and a ground reaction on the
foot's toe while it is low (a walking load). The model of bench_forces.py's Strandbeest
figures."""
import os
import sys

from mechgen import Model, Piecewise, location

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples"))
from strandbeest import leg  # noqa: E402

KG = 0.05       # mass per unit of length


def bar(model, name, points, guess, length):
    mass = KG * length
    return model.body(name, points=points, guess=guess, mass=mass,
                      inertia=mass * length ** 2 / 12, centroid=(length / 2, 0))


m = Model("strandbeest_forces")
foot = leg(m, bar)["foot"]
m.gravity(9.807)
toe_y = location(foot[3])[1]
m.force(foot[3], (0, Piecewise((40.0, toe_y < -85.0), (0.0, True))), name="ground")
