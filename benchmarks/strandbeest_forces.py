"""Jansen's leg (examples/strandbeest.py) with masses: every link a uniform bar of steel
tube (0.05 kg per unit of length, inertia m L²/12 about its midpoint), the hip and the
foot triangles as bars along their first side, gravity, and a ground reaction on the
foot's toe while it is low (a walking load). The model of bench_forces.py's Strandbeest
figures."""
import os
import sys

from mechgen import Model, Piecewise, T, location, pi

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples"))
from strandbeest import A, B, C, D, E, F, G, _frame, b, c, f, g, j, k, m_  # noqa: E402

KG = 0.05       # mass per unit of length


def bar(model, name, points, guess, length):
    mass = KG * length
    return model.body(name, points=points, guess=guess, mass=mass,
                      inertia=mass * length ** 2 / 12, centroid=(length / 2, 0))


m = Model("strandbeest_forces")
frame = m.ground("frame", points=[(0.0, 0.0), B])
crank = bar(m, "crank", [(0, 0), (m_, 0)], (0, 0, 0), m_)
upper = bar(m, "upper", [(0, 0), (j, 0)], (*A, _frame(A, C)), j)
hip = bar(m, "hip", [(0, 0), (b, 0), _frame(B, C, D)], (*B, _frame(B, C)), b)
lower = bar(m, "lower", [(0, 0), (k, 0)], (*A, _frame(A, E)), k)
cee = bar(m, "cee", [(0, 0), (c, 0)], (*B, _frame(B, E)), c)
eff = bar(m, "eff", [(0, 0), (f, 0)], (*D, _frame(D, F)), f)
foot = bar(m, "foot", [(0, 0), (g, 0), _frame(E, F, G)], (*E, _frame(E, F)), g)
m.revolute(frame[1], crank[1])
m.rotation_lock(crank, 2 * pi * T, name="crank angle")
m.revolute(crank[2], upper[1])
m.revolute(crank[2], lower[1])
m.revolute(frame[2], hip[1])
m.revolute(upper[2], hip[2])
m.revolute(frame[2], cee[1])
m.revolute(cee[2], lower[2])
m.revolute(cee[2], foot[1])
m.revolute(hip[3], eff[1])
m.revolute(eff[2], foot[2])
m.gravity(9.807)
toe_y = location(foot[3])[1]
m.force(foot[3], (0, Piecewise((40.0, toe_y < -85.0), (0.0, True))), name="ground")
