"""The locals a generated function reads from its argument arrays (``X2 = q[0]``, ...)."""
from __future__ import annotations

import sympy as sp

from ...model.geometry import T
from .ir import Code, load
from .printer import Local


def sym(name):
    """A local of the generated code (real, as every model symbol)."""
    return Local(name, real=True)


def free(exprs) -> set:
    """The symbols of a list of expressions."""
    out = set()
    for e in exprs:
        out |= sp.sympify(e).free_symbols
    return out


def unpack(used, vector, array):
    """``X2 = q[0]``, ... for the symbols of ``vector`` that are ``used``."""
    return [load(s, array, k) for k, s in enumerate(vector) if s in used]


def time_local():
    """``T = t``: the model's time symbol from the argument ``t``."""
    return Code("{0} = t", (T,))


def prologue(eq, exprs, with_qd=False, with_qdd=False, with_t=True):
    """The loads of the coordinates, velocities, accelerations, parameters and time that
    ``exprs`` read."""
    used = free(exprs)
    st = unpack(used, eq.q, "q")
    if with_qd:
        st += unpack(used, eq.qd, "qd")
    if with_qdd:
        st += unpack(used, eq.qdd, "qdd")
    st += unpack(used, eq.params, "p")
    if with_t and T in used:
        st.append(time_local())
    return st
