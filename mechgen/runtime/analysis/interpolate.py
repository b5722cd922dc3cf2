"""Interpolation of a sweep (Mech's TimeInterpolate): Hermite pieces through the
derivatives a sweep holds, a cubic spline on positions alone, or Mathematica's default
InterpolatingFunction (a local Lagrange polynomial) to read beside seed 001.

numpy, and scipy.interpolate when an interpolant is built (imported there, so that
``import mechgen.runtime`` stays light). Never sympy.
"""
from __future__ import annotations

import numpy as np

from ...protocol import LEVEL, LEVELS
from ..quantity import Quantity

METHODS = ("auto", "hermite", "cubic", "lagrange", "linear")


def _lagrange_ppoly(t, y, degree=3):
    """Mathematica's default InterpolatingFunction (InterpolationOrder -> 3): on each
    interval, the polynomial through the degree + 1 nearest data points (continuous, not
    smooth). Seed 001's printed FindRoot results come from exactly this."""
    from scipy.interpolate import PPoly
    n = t.shape[0]
    if degree < 1 or degree % 2 == 0:
        raise ValueError(f"lagrange interpolation takes an odd degree, got {degree}")
    if n < degree + 1:
        raise ValueError(f"lagrange interpolation of degree {degree} needs {degree + 1} points, "
                         f"the sweep has {n}")
    half = (degree - 1) // 2
    i = np.arange(n - 1)
    lo = np.clip(i - half, 0, n - degree - 1)
    rows = lo[:, None] + np.arange(degree + 1)          # the points of each piece
    x = t[rows] - t[i][:, None]                         # local to the piece's start
    V = x[:, :, None] ** np.arange(degree, -1, -1)      # Vandermonde, highest power first
    c = np.linalg.solve(V, y[rows][:, :, None])[:, :, 0]   # all pieces in one batch
    return PPoly(c.T.copy(), t)


def _quintic_hermite(t, y, d, dd):
    """The piecewise quintic matching values, first and second derivatives at every node,
    built for all pieces at once (BPoly.from_derivatives loops over them in Python)."""
    from scipy.interpolate import PPoly
    h = np.diff(t)
    y0, d0, dd0 = y[:-1], d[:-1], dd[:-1]
    gap = y[1:] - (y0 + h * (d0 + 0.5 * h * dd0))       # what the quadratic misses at t1
    gap1 = d[1:] - (d0 + h * dd0)
    gap2 = dd[1:] - dd0
    c = np.empty((6, h.size))
    c[0] = (12.0 * gap - 6.0 * h * gap1 + h * h * gap2) / (2.0 * h ** 5)
    c[1] = (-30.0 * gap + 14.0 * h * gap1 - 2.0 * h * h * gap2) / (2.0 * h ** 4)
    c[2] = (20.0 * gap - 8.0 * h * gap1 + h * h * gap2) / (2.0 * h ** 3)
    c[3] = 0.5 * dd0
    c[4] = d0
    c[5] = y0
    return PPoly(c, t)


class Interpolant:
    """A callable of t interpolating one quantity of a sweep (Mech's TimeInterpolate).

    ``f(t)`` (scalar or array), ``f(t, 1)`` its derivative, ``f.derivative()``,
    ``f.roots()``. Outside the sweep's time range it raises unless ``extrapolate=True``.
    """

    def __init__(self, poly, name, method, extrapolate=False):
        self.poly = poly
        self.name = name
        self.method = method
        self.extrapolate = extrapolate
        self.domain = (float(poly.x[0]), float(poly.x[-1]))

    def __call__(self, t, nu=0):
        t_arr = np.asarray(t, dtype=np.float64)
        if not self.extrapolate:
            a, b = self.domain
            slack = 1e-12 * max(1.0, b - a)
            if np.any(t_arr < a - slack) or np.any(t_arr > b + slack):
                raise ValueError(f"t = {t!r} is outside the interpolated range [{a:g}, {b:g}] "
                                 "(pass extrapolate=True to extrapolate)")
            t_arr = np.clip(t_arr, a, b)
        out = self.poly(t_arr, nu)
        return float(out) if out.ndim == 0 else out

    def derivative(self, n=1) -> "Interpolant":
        return Interpolant(self.poly.derivative(n), self.name + "'" * n, self.method,
                           self.extrapolate)

    def roots(self, a=None, b=None) -> np.ndarray:
        """Real roots inside the interpolated range, or only in the pieces that meet
        [a, b] and their neighbours (a root search per piece: on a long sweep, far
        cheaper than all of them)."""
        poly = self.poly
        if a is not None and b is not None:
            from scipy.interpolate import PPoly
            x = poly.x
            i0 = max(int(np.searchsorted(x, a, side="right")) - 2, 0)
            i1 = min(int(np.searchsorted(x, b, side="left")) + 1, len(x) - 1)
            if i1 - i0 < len(x) - 1:
                poly = PPoly(poly.c[:, i0:i1], x[i0:i1 + 1], extrapolate=False)
        r = poly.roots(extrapolate=False)
        return np.unique(r[np.isfinite(r)])

    def __repr__(self):
        a, b = self.domain
        return f"<Interpolant of {self.name} on [{a:g}, {b:g}] ({self.method})>"


class NotFinite(ValueError):
    """A quantity to interpolate is NaN or infinite at some time of the sweep."""


def _finite(t, y, label):
    bad = np.flatnonzero(~np.isfinite(y))
    if bad.size:
        raise NotFinite(f"{label!r} is not a number at t = {t[bad[0]]:.10g}"
                        f"{f' (and {bad.size - 1} more times)' if bad.size > 1 else ''}: "
                        "interpolation needs finite values at every point of the sweep")


def _increasing(sw):
    t = np.asarray(sw.t, dtype=np.float64)
    if t.shape[0] < 2:
        raise ValueError("interpolation needs a sweep of at least 2 points")
    d = np.diff(t)
    if np.all(d > 0):
        return slice(None)
    if np.all(d < 0):
        return slice(None, None, -1)
    raise ValueError("interpolation needs strictly monotonic sweep times")


def interpolate(sw, what, method="auto", degree=3, extrapolate=False) -> Interpolant:
    """Interpolate a coordinate, output or symbolic quantity of a sweep.

    method ``"auto"`` uses the derivatives the sweep holds: quintic Hermite with first
    and second derivatives (acceleration sweeps), cubic Hermite with first derivatives
    (velocity sweeps), a not-a-knot cubic spline on positions alone. ``"hermite"`` insists
    on derivatives, ``"cubic"`` is the spline whatever the level, ``"lagrange"`` is
    Mathematica's default InterpolatingFunction (piecewise polynomial through the
    ``degree + 1`` nearest points; Mech's TimeInterpolate), ``"linear"`` joins the points.
    """
    from scipy.interpolate import CubicHermiteSpline, CubicSpline
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    qty = Quantity(sw.mechanism, what)
    have = LEVEL[sw.level]
    qty.needs(have)
    slice_ = _increasing(sw)
    t = np.ascontiguousarray(sw.t[slice_], dtype=np.float64)
    y = np.ascontiguousarray(qty.on_sweep(sw)[slice_])
    _finite(t, y, qty.label)
    derivs = []
    q = qty
    if method in ("auto", "hermite"):
        for _ in range(2):
            q = q.derivative()
            if q is None or q.level > have:
                break
            derivs.append(np.ascontiguousarray(q.on_sweep(sw)[slice_]))
            _finite(t, derivs[-1], q.label)
    if method == "hermite" and not derivs:
        raise ValueError(f"hermite interpolation of {qty.label!r} needs its derivative: sweep at "
                         f"level {LEVELS[min(qty.level + 1, LEVEL['acceleration'])]}")
    if method in ("auto", "hermite") and len(derivs) == 2:
        poly, used = _quintic_hermite(t, y, derivs[0], derivs[1]), "quintic hermite"
    elif method in ("auto", "hermite") and len(derivs) == 1:
        poly, used = CubicHermiteSpline(t, y, derivs[0]), "cubic hermite"
    elif method == "linear":
        poly, used = _lagrange_ppoly(t, y, 1), "linear"
    elif method == "lagrange":
        poly, used = _lagrange_ppoly(t, y, degree), f"lagrange (degree {degree})"
    else:
        if t.shape[0] < 4:
            poly, used = _lagrange_ppoly(t, y, 1), "linear"
        else:
            poly, used = CubicSpline(t, y), "cubic spline"
    return Interpolant(poly, qty.label, used, extrapolate)
