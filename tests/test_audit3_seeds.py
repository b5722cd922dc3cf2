"""Audit of the seeds' numbers along a user's path (seed 001's maximum and minimum of X4,
section "OBTENCION VALORES MAXIMO Y MINIMO X4").

Seed 001 interpolates a 20-point table (Mathematica's default InterpolatingFunction,
method="lagrange" here) and takes the extremes on the interpolant. That interpolant is
continuous but not smooth: its derivative jumps at the table's times, and scipy's PPoly
reports such a jump through zero as a root. extrema() gives, beside each exact extreme,
"what the interpolant alone says"; that answer must be an extreme of the same kind.
"""
import os

import numpy as np
import pytest

import mechgen

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


@pytest.fixture(scope="module")
def qr():
    return mechgen.load(os.path.join(ROOT, "generated", "quick_return.py"), tier="python")


def _kind_on_interpolant(f, t, h=1e-4):
    """'max' or 'min' where the interpolant f has that extreme at t, else None."""
    left, mid, right = f(t - h), f(t), f(t + h)
    if mid >= left and mid >= right:
        return "max"
    if mid <= left and mid <= right:
        return "min"
    return None


def test_interpolant_side_of_an_extreme_is_an_extreme_of_its_kind(qr):
    """posicionT = SolveMech[{0, 1}, 20] (positions only), the Lagrange interpolant of X4:
    the exact maximum is X4 = 9.542463 at t = 0.8975836. The interpolant's derivative
    jumps from − to + at the table's time 17/19 = 0.8947368 (a kink where the interpolant
    has a local *minimum*, 9.542031); extrema() reported that kink as the interpolant's
    maximum. The interpolant's own maximum in that interval of the table is at t ≈ 0.9021
    (9.545149)."""
    sw = qr.sweep(0.0, 1.0, 20)
    f = sw.interpolate("X4", method="lagrange")
    ev = sw.extrema("X4", method="lagrange")
    assert [e.kind for e in ev] == ["min", "max"]
    for e in ev:
        assert _kind_on_interpolant(f, e.t_interp) == e.kind, (e, f(e.t_interp - 1e-4),
                                                               f(e.t_interp + 1e-4))
        assert abs(e.value_interp - f(e.t_interp)) < 1e-12
    mx = ev[1]
    assert abs(mx.t - 0.8975836177) < 1e-9 and abs(mx.value - 9.542463035) < 1e-8
    assert abs(mx.t_interp - 0.902) < 1e-3 and abs(mx.value_interp - 9.54515) < 1e-5
    # the seed's own route (the interpolated X4d of the velocity table) is unchanged
    vel = qr.sweep(0.0, 1.0, 20, level="velocity").extrema("X4", method="lagrange")
    assert abs(vel[0].t_interp - 0.602307) < 5e-7 and abs(vel[1].t_interp - 0.897082) < 5e-7
    assert abs(vel[0].value_interp + 1.26516) < 5e-6 and abs(vel[1].value_interp - 9.54378) < 5e-6


def test_interpolant_side_of_a_root_crosses_the_same_way(qr):
    """roots() of the rate X4d with a piecewise-linear interpolant: every coarse root
    reported changes sign the way the exact one does."""
    sw = qr.sweep(0.0, 1.0, 20, level="velocity")
    f = sw.interpolate("X4d", method="lagrange")
    for e in sw.roots("X4d", method="lagrange"):
        before, after = f(e.t_interp - 1e-4), f(e.t_interp + 1e-4)
        assert (before < 0 < after) if e.kind == "rising" else (before > 0 > after), e


def test_mathematica_notation_of_sign():
    """`mechgen equations --mathematica` printed the rate of Abs(T - 1) as "sign[T - 1]",
    which is no Mathematica (its function is Sign)."""
    import sympy as sp
    from mechgen.model.printing import mathematica
    t = sp.Symbol("T")
    assert mathematica(sp.sign(t - 1)) == "Sign[T - 1]"
    assert mathematica(sp.Abs(t - 1)) == "Abs[T - 1]"
    assert mathematica(sp.atan2(t, 1 + t ** 2)) == "ArcTan[T^2 + 1, T]"
