"""Jansen's leg (examples/strandbeest.py) with its crank's length a parameter, ``crank_length``
(the holy number m = 15): the Strandbeest model of bench_view.py, whose slider changes
the leg's shape and gait."""
import os
import sys

from mechgen import Model, T, pi

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples"))
from strandbeest import A, B, C, D, E, F, G, _frame, b, c, f, g, j, k, m_  # noqa: E402

m = Model("strandbeest_view")
crank_length = m.param("crank_length", m_)
frame = m.ground("frame", points=[(0.0, 0.0), B])
crank = m.body("crank", points=[(0, 0), (crank_length, 0)], guess=(0, 0, 0))
upper = m.body("upper", points=[(0, 0), (j, 0)], guess=(*A, _frame(A, C)))
hip = m.body("hip", points=[(0, 0), (b, 0), _frame(B, C, D)], guess=(*B, _frame(B, C)))
lower = m.body("lower", points=[(0, 0), (k, 0)], guess=(*A, _frame(A, E)))
cee = m.body("cee", points=[(0, 0), (c, 0)], guess=(*B, _frame(B, E)))
eff = m.body("eff", points=[(0, 0), (f, 0)], guess=(*D, _frame(D, F)))
foot = m.body("foot", points=[(0, 0), (g, 0), _frame(E, F, G)], guess=(*E, _frame(E, F)))
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
