"""Jansen's leg (examples/strandbeest.py) with its crank's length a parameter, ``crank_length``
(the holy number m = 15): the Strandbeest model of bench_view.py, whose slider changes
the leg's shape and gait."""
import os
import sys

from mechgen import Model

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples"))
from strandbeest import leg, m_  # noqa: E402

m = Model("strandbeest_view")
leg(m, crank_length=m.param("crank_length", m_))
