"""The interpolants of a sweep: those built for all pieces at once (issue 6: extremes of
long sweeps) against scipy's piece-by-piece constructions, root searches restricted to a
bracket, and what the interpolant alone says beside each exact extreme or root.

Seed 001 interpolates a 20-point table (Mathematica's default InterpolatingFunction,
method="lagrange" here) and takes the extremes on the interpolant (section "OBTENCION
VALORES MAXIMO Y MINIMO X4"). That interpolant is continuous but not smooth: its
derivative jumps at the table's times, and scipy's PPoly reports such a jump through zero
as a root. extrema() gives, beside each exact extreme, "what the interpolant alone says";
that answer must be an extreme of the same kind.
"""
import os

import numpy as np
import pytest
from scipy.interpolate import BPoly, PPoly

import mechgen
from mechgen.runtime.analysis.interpolate import Interpolant, _lagrange_ppoly, _quintic_hermite


def _data(n, seed):
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.01, 0.2, n))
    return t, rng.normal(size=n), rng.normal(size=n), rng.normal(size=n)


def test_quintic_hermite_is_scipys():
    t, y, d, dd = _data(60, 1)
    ref = PPoly.from_bernstein_basis(BPoly.from_derivatives(t, np.column_stack([y, d, dd])))
    ours = _quintic_hermite(t, y, d, dd)
    s = np.linspace(t[0], t[-1], 2001)
    for nu in range(3):
        assert np.allclose(ours(s, nu), ref(s, nu), rtol=1e-9, atol=1e-9)
        assert np.allclose(ours(t, nu), (y, d, dd)[nu], rtol=1e-9, atol=1e-9)


def test_lagrange_pieces_pass_through_their_points():
    t, y, _, _ = _data(40, 2)
    for degree in (1, 3, 5):
        pp = _lagrange_ppoly(t, y, degree)
        half = (degree - 1) // 2
        for i in (0, 1, 17, 38):
            lo = min(max(i - half, 0), len(t) - degree - 1)
            pts = t[lo:lo + degree + 1]
            ref = np.polyfit(pts - t[i], y[lo:lo + degree + 1], degree)
            assert np.allclose(pp.c[:, i], ref, rtol=1e-8, atol=1e-8)


def test_roots_in_a_bracket_are_the_roots_there():
    t = np.linspace(0.0, 10.0, 400)
    f = Interpolant(_quintic_hermite(t, np.sin(t), np.cos(t), -np.sin(t)), "sin", "quintic")
    everywhere = f.roots()
    assert np.allclose(everywhere, [0.0, np.pi, 2 * np.pi, 3 * np.pi], atol=1e-9)
    k = int(np.searchsorted(t, np.pi)) - 1
    near = f.roots(t[k], t[k + 1])
    assert np.allclose(near, [np.pi], atol=1e-9)


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
    import mpmath as mp
    from closed_forms import quick_return
    with mp.workdps(30):                  # the exact maximum: X4' = 0 on the closed form
        t_max = mp.findroot(lambda u: mp.diff(lambda v: quick_return(v)[6], u), mp.mpf(0.8976))
        x_max = quick_return(t_max)[6]
    assert abs(mx.t - float(t_max)) < 1e-9 and abs(mx.value - float(x_max)) < 1e-8
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
