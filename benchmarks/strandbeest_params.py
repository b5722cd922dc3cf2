"""Jansen's leg (examples/strandbeest.py) with four of its lengths parameters (the crank, the
upper and lower links and the foot's side), at the holy numbers: the Strandbeest of
bench_sensitivities.py, whose sweeps carry the derivatives to all four."""
import os
import sys

from mechgen import Model

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples"))
from strandbeest import g, j, k, leg, m_  # noqa: E402

m = Model("strandbeest_params")
leg(m, crank_length=m.param("crank_length", m_), upper_length=m.param("upper_length", j),
    lower_length=m.param("lower_length", k), foot_length=m.param("foot_length", g))
