"""The interpolants built for all pieces at once (issue 6: extremes of long sweeps) against
scipy's piece-by-piece constructions, and root searches restricted to a bracket."""
import numpy as np
from scipy.interpolate import BPoly, PPoly

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
