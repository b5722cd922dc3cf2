"""Analysis on solved configurations: interpolation, exact extremes and roots, assembly
modes and design tables (Mech's TimeInterpolate, FindRoot on an interpolant, SolveMech
from several guesses and Table[SetGuess[]; SolveMech[...], {param, ...}]).

The coarse route of seed 001 interpolates 20 points and finds extremes on the
interpolant; here the sweep only brackets, and the compiled solver refines: the time
derivative of the quantity is solved exactly (velocity or acceleration level) and its
root found by Brent's method to ~1e-12 in t. Both answers are reported, so the error
of the coarse route is visible.

numpy (+ scipy.interpolate / scipy.optimize when used) only: never sympy, except when the
quantity asked for is itself a sympy expression (then the model is already loaded).
"""
from __future__ import annotations

import math
import sys
import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import MechgenError

_ORDER = {"": 0, "d": 1, "dd": 2}
_LEVELS = ("position", "velocity", "acceleration")
METHODS = ("auto", "hermite", "cubic", "lagrange", "linear")


# ---------------------------------------------------------------------------------------
# Quantities: a coordinate, an output (by name, maybe with d / dd) or a sympy expression
# ---------------------------------------------------------------------------------------
class _Quantity:
    """What a name or expression means on a mechanism: its values on a sweep or a
    solution, the level each derivative needs, and how to take one more derivative."""

    def __init__(self, mech, what):
        from .results import _lookup
        self.mech = mech
        self.what = what
        if isinstance(what, str):
            kind, k, order = _lookup(mech, what)
            self.kind, self.k = kind, k
            base = mech.coordinates[k] if kind == "q" else mech.outputs[k]
            self.base = base
            own = 0 if kind == "q" else mech.output_orders[k]
            self.level = own + order          # solve level the value needs
            self.order = order                # how many d's the name carries
            self.label = what
        else:
            self.kind, self.k = "expr", None
            if mech.model is None:
                raise MechgenError("a symbolic quantity needs the symbolic model: load the "
                                   "mechanism with mechgen.compile(model)")
            self.expr = what
            self.level = _expr_level(mech, what)
            self.order = 0
            self.label = _short(what)

    def derivative(self):
        """The quantity's time derivative, or None when it needs a third derivative."""
        if self.level >= 2:
            return None
        if self.kind == "expr":
            from ..model.quantities import dt
            return _Quantity(self.mech, dt(self.expr, model=self.mech.model))
        name = self.base + "d" * (self.order + 1)
        return _Quantity(self.mech, name)

    def on_sweep(self, sw) -> np.ndarray:
        if self.kind == "expr":
            values = np.asarray(self.mech.evaluate(self.expr, sw), dtype=np.float64)
            if values.shape != (len(sw),):
                raise ValueError(f"{self.label} is not a scalar quantity (values of shape "
                                 f"{values.shape} on a sweep of {len(sw)} points); take one "
                                 "component, e.g. location(p)[0]")
            return values
        return sw[self.what]

    def on_solution(self, s) -> float:
        if self.kind == "expr":
            return float(np.asarray(self.mech.evaluate(self.expr, s), dtype=np.float64).ravel()[0])
        return s[self.what]


def _expr_level(mech, expr) -> int:
    names = {s.name for s in getattr(expr, "free_symbols", ())}
    coords = mech.coordinates
    if any(c + "dd" in names for c in coords):
        return 2
    if any(c + "d" in names for c in coords):
        return 1
    return 0


def _short(expr) -> str:
    text = str(expr)
    return text if len(text) <= 40 else text[:37] + "..."


# ---------------------------------------------------------------------------------------
# Interpolation
# ---------------------------------------------------------------------------------------
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
    mech = sw.mechanism
    qty = _Quantity(mech, what)
    have = sw._have()
    if qty.level > have:
        raise KeyError(f"{qty.label!r} needs a sweep at level {_LEVELS[min(qty.level, 2)]} "
                       f"(this sweep is at level {sw.level})")
    slice_ = _increasing(sw)
    t = np.ascontiguousarray(sw.t[slice_], dtype=np.float64)
    y = np.ascontiguousarray(qty.on_sweep(sw)[slice_])
    derivs = []
    q = qty
    if method in ("auto", "hermite"):
        for _ in range(2):
            q = q.derivative()
            if q is None or q.level > have:
                break
            derivs.append(np.ascontiguousarray(q.on_sweep(sw)[slice_]))
    if method == "hermite" and not derivs:
        raise ValueError(f"hermite interpolation of {qty.label!r} needs its derivative: sweep at "
                         f"level {_LEVELS[min(qty.level + 1, 2)]}")
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


# ---------------------------------------------------------------------------------------
# Exact solves inside a bracket
# ---------------------------------------------------------------------------------------
def _node_derivatives(sw, level):
    """(QD, QDD) of a sweep up to ``level``, solving the missing (linear) levels at the
    sweep's own positions: no Newton iteration is needed for them."""
    mech = sw.mechanism
    mod = mech.module
    meth = mech._method(None)
    QD, QDD = sw.QD, sw.QDD
    N = len(sw)
    if level >= 1 and QD is None:
        QD = np.empty((N, mech.n))
        for k in range(N):
            if mod.solve_velocity(sw.Q[k], float(sw.t[k]), mech.p, meth, QD[k]) != 0:
                mech._singular(float(sw.t[k]), sw.Q[k], "velocity")
    if level >= 2 and QDD is None:
        QDD = np.empty((N, mech.n))
        for k in range(N):
            if mod.solve_acceleration(sw.Q[k], QD[k], float(sw.t[k]), mech.p, meth, QDD[k]) != 0:
                mech._singular(float(sw.t[k]), sw.Q[k], "acceleration")
    return QD, QDD


class _Exact:
    """Exact values of a quantity at any t inside a sweep: a compiled solve warm-started
    from the nearest sweep point by a Taylor predictor (so it stays on the sweep's branch)."""

    def __init__(self, sw, qty, QD, QDD):
        self.sw = sw
        self.qty = qty
        self.mech = sw.mechanism
        self.level = _LEVELS[qty.level]
        self.QD, self.QDD = QD, QDD   # at the sweep's nodes, for the predictor
        self.calls = 0

    def solution(self, t):
        sw = self.sw
        k = int(np.argmin(np.abs(sw.t - t)))
        h = t - sw.t[k]
        q0 = sw.Q[k] + h * self.QD[k]
        if self.QDD is not None:
            q0 = q0 + 0.5 * h * h * self.QDD[k]
        self.calls += 1
        return self.mech.solve(t, guess=q0, level=self.level)

    def __call__(self, t):
        return self.qty.on_solution(self.solution(float(t)))


def _zero_tol(values, scale_extra=0.0):
    """Values this small count as zero: round-off of a quantity that is really constant."""
    big = float(np.max(np.abs(values))) if values.size else 0.0
    return 1e-11 * max(big, scale_extra, 1e-300)


def _sign_changes(t, v, tol):
    """Brackets (k, exact) where v changes sign: (k, None) for a change inside
    (t[k], t[k+1]), (k, k) when v[k] itself is zero between opposite signs."""
    s = np.where(np.abs(v) <= tol, 0, np.sign(v)).astype(int)
    out = []
    n = len(v)
    k = 0
    while k < n - 1:
        if s[k] != 0 and s[k + 1] != 0 and s[k] != s[k + 1]:
            out.append((k, None, s[k]))
            k += 1
            continue
        if s[k + 1] == 0 and s[k] != 0:
            j = k + 1
            while j < n and s[j] == 0:
                j += 1
            if j < n and s[j] != s[k]:
                if j == k + 2:
                    out.append((k + 1, k + 1, s[k]))
                else:  # a flat stretch: report its middle node
                    out.append(((k + 1 + j - 1) // 2, (k + 1 + j - 1) // 2, s[k]))
            k = j
            continue
        k += 1
    return out


def _brent(f, a, b, fa, fb, xtol):
    from scipy.optimize import brentq
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    return brentq(f, a, b, xtol=xtol, rtol=4 * np.finfo(float).eps, maxiter=200)


@dataclass(frozen=True)
class Event:
    """An extreme (kind 'max' / 'min') or a root (kind 'rising' / 'falling') of a
    quantity, found exactly, with what the interpolant alone says beside it."""
    name: str
    kind: str
    t: float
    value: float
    t_interp: float
    value_interp: float
    method: str
    solves: int = 0

    @property
    def error_t(self) -> float:
        """How far the interpolant's time is from the exact one."""
        return self.t_interp - self.t

    @property
    def error_value(self) -> float:
        return self.value_interp - self.value

    def __repr__(self):
        return (f"<{self.kind} of {self.name} at t={self.t:.10g}: {self.value:.10g}; "
                f"{self.method} interpolant: t={self.t_interp:.7g}, {self.value_interp:.7g}>")


class Events(list):
    """A list of :class:`Event` in time order, with ``.t`` and ``.value`` arrays."""

    @property
    def t(self) -> np.ndarray:
        return np.array([e.t for e in self], dtype=np.float64)

    @property
    def value(self) -> np.ndarray:
        return np.array([e.value for e in self], dtype=np.float64)

    values = value

    def of(self, kind) -> "Events":
        return Events(e for e in self if e.kind == kind)

    @property
    def maxima(self) -> "Events":
        return self.of("max")

    @property
    def minima(self) -> "Events":
        return self.of("min")

    def __repr__(self):
        if not self:
            return "Events([])"
        lines = [f"{'kind':>8}  {'t':>16}  {'value':>16}  {'t (interp.)':>12}  "
                 f"{'value (interp.)':>15}"]
        for e in self:
            lines.append(f"{e.kind:>8}  {e.t:16.10f}  {e.value:16.10g}  {e.t_interp:12.7g}  "
                         f"{e.value_interp:15.7g}")
        return "\n".join(lines)

    def _repr_html_(self):
        rows = "".join(f"<tr><td>{e.kind}</td><td>{e.t:.10f}</td><td>{e.value:.10g}</td>"
                       f"<td>{e.t_interp:.7g}</td><td>{e.value_interp:.7g}</td></tr>" for e in self)
        return ("<table><thead><tr><th>kind</th><th>t</th><th>value</th><th>t (interpolant)</th>"
                f"<th>value (interpolant)</th></tr></thead><tbody>{rows}</tbody></table>")


def _nearest(roots, t, a, b):
    inside = roots[(roots >= a - 1e-12) & (roots <= b + 1e-12)]
    pool = inside if inside.size else roots
    if not pool.size:
        return math.nan
    return float(pool[np.argmin(np.abs(pool - t))])


def extrema(sw, what, method="auto", xtol=1e-12) -> Events:
    """Interior extremes of a quantity over the sweep: the sweep brackets a sign change of
    the exact time derivative, Brent's method on exactly solved derivatives refines it.

    Each :class:`Event` also holds the coarse answer: the root of the interpolated
    derivative (Mech's FindRoot on TimeInterpolate) and the interpolated value there.
    """
    mech = sw.mechanism
    qty = _Quantity(mech, what)
    if qty.level > sw._have():
        raise KeyError(f"{qty.label!r} needs a sweep at level {_LEVELS[min(qty.level, 2)]} "
                       f"(this sweep is at level {sw.level})")
    dq = qty.derivative()
    if dq is None:
        raise ValueError(f"the extremes of {qty.label!r} need its time derivative, a third "
                         "derivative of the coordinates, which mechgen does not solve for; "
                         f"use roots() of {qty.label!r}'s own derivative where available")
    t = np.asarray(sw.t, dtype=np.float64)
    if len(t) < 2:
        return Events()
    last = mech.last
    try:
        QD, QDD = _node_derivatives(sw, max(1, dq.level))   # dy at the nodes, and a predictor
        exact_d = _Exact(sw, dq, QD, QDD)
        exact_v = _Exact(sw, qty, QD, QDD)
        view = _upgraded(sw, QD, QDD)
        y = qty.on_sweep(sw)
        dy = dq.on_sweep(view)
        span = abs(t[-1] - t[0]) or 1.0
        tol = _zero_tol(dy, float(np.max(np.abs(y))) / span if y.size else 0.0)
        # the coarse route: interpolate the derivative the sweep holds, or differentiate
        if dq.level <= sw._have():
            coarse_d = interpolate(sw, dq.what, method=method)
        else:
            coarse_d = interpolate(sw, qty.what, method=method).derivative()
        coarse_v = interpolate(sw, qty.what, method=method)
        events = Events()
        for k, node, sign in _sign_changes(t, dy, tol):
            calls = exact_d.calls + exact_v.calls
            kind = "max" if sign > 0 else "min"
            if t[-1] < t[0]:
                kind = "min" if kind == "max" else "max"
            if node is not None:
                t_star = float(t[node])
                value = float(y[node])
            else:
                a, b = float(t[k]), float(t[k + 1])
                lo, hi = min(a, b), max(a, b)
                fa, fb = (dy[k], dy[k + 1]) if a < b else (dy[k + 1], dy[k])
                t_star = _brent(exact_d, lo, hi, float(fa), float(fb), xtol)
                value = float(exact_v(t_star))
            a, b = float(min(t[k], t[k + 1])), float(max(t[k], t[k + 1]))
            ti = _nearest(coarse_d.roots(a, b), t_star, a, b)
            vi = float(coarse_v(ti)) if math.isfinite(ti) else math.nan
            events.append(Event(qty.label, kind, t_star, value, ti, vi, coarse_v.method,
                                exact_d.calls + exact_v.calls - calls))
        events.sort(key=lambda e: e.t)
        return events
    finally:
        mech.last = last


def roots(sw, what, method="auto", xtol=1e-12) -> Events:
    """Times where a quantity crosses zero inside the sweep, refined by Brent's method on
    exact solves; each Event holds the interpolant's root beside the exact one."""
    mech = sw.mechanism
    qty = _Quantity(mech, what)
    if qty.level > sw._have():
        raise KeyError(f"{qty.label!r} needs a sweep at level {_LEVELS[min(qty.level, 2)]} "
                       f"(this sweep is at level {sw.level})")
    t = np.asarray(sw.t, dtype=np.float64)
    if len(t) < 2:
        return Events()
    last = mech.last
    try:
        QD, QDD = _node_derivatives(sw, max(1, qty.level))
        exact = _Exact(sw, qty, QD, QDD)
        y = qty.on_sweep(sw)
        tol = _zero_tol(y)
        coarse = interpolate(sw, qty.what, method=method)
        events = Events()
        for k, node, sign in _sign_changes(t, y, tol):
            calls = exact.calls
            kind = "falling" if sign > 0 else "rising"
            if t[-1] < t[0]:
                kind = "rising" if kind == "falling" else "falling"
            if node is not None:
                t_star, value = float(t[node]), float(y[node])
            else:
                a, b = float(t[k]), float(t[k + 1])
                lo, hi = min(a, b), max(a, b)
                fa, fb = (y[k], y[k + 1]) if a < b else (y[k + 1], y[k])
                t_star = _brent(exact, lo, hi, float(fa), float(fb), xtol)
                value = float(exact(t_star))
            a, b = float(min(t[k], t[k + 1])), float(max(t[k], t[k + 1]))
            ti = _nearest(coarse.roots(a, b), t_star, a, b)
            vi = float(coarse(ti)) if math.isfinite(ti) else math.nan
            events.append(Event(qty.label, kind, t_star, value, ti, vi, coarse.method,
                                exact.calls - calls))
        events.sort(key=lambda e: e.t)
        return events
    finally:
        mech.last = last


def _upgraded(sw, QD, QDD):
    """The sweep with the derivative levels filled in (same positions)."""
    from .results import Sweep
    return Sweep(sw.mechanism, sw.t, sw.Q, QD, QDD, sw.info)


# ---------------------------------------------------------------------------------------
# Assembly modes
# ---------------------------------------------------------------------------------------
_PRIMES = (2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61, 67, 71, 73,
           79, 83, 89, 97, 101, 103, 107, 109, 113)


def _halton(k, dim):
    """Point k (k >= 1) of the Halton sequence in [0, 1)^dim: deterministic and even."""
    out = np.empty(dim)
    for d in range(dim):
        base = _PRIMES[d % len(_PRIMES)]
        f, r, i = 1.0, 0.0, k + d // len(_PRIMES) * 7919
        while i > 0:
            f /= base
            r += f * (i % base)
            i //= base
        out[d] = r
    return out


def angle_coordinates(mech) -> tuple:
    """Indices of the coordinates in which Φ is 2π-periodic (angles equal modulo 2π are
    the same configuration). A driven angle (Th2 − ωT) is not: its value is fixed."""
    cached = getattr(mech, "_angle_coordinates", None)
    if cached is not None and cached[0] is mech.module and np.array_equal(cached[1], mech.p):
        return cached[2]
    n, m = mech.n, mech.m
    base = np.asarray(mech.guess, dtype=np.float64)
    r0, r1 = np.empty(m), np.empty(m)
    found = []
    for j in range(n):
        periodic = True
        for trial in range(3):
            q = base + 0.37 * (trial + 1) * np.cos(np.arange(n) * 1.7 + trial)
            t = 0.1234 + 0.31 * trial
            mech.module.phi(q, t, mech.p, r0)
            q2 = q.copy()
            q2[j] += 2 * math.pi
            mech.module.phi(q2, t, mech.p, r1)
            if not (np.all(np.isfinite(r0)) and np.all(np.isfinite(r1))):
                periodic = False
                break
            if np.max(np.abs(r1 - r0)) > 1e-9 * (1.0 + np.max(np.abs(r0))):
                periodic = False
                break
        if periodic:
            found.append(j)
    result = tuple(found)
    mech._angle_coordinates = (mech.module, mech.p.copy(), result)
    return result


def _wrap(q, angles):
    q = q.copy()
    for j in angles:
        w = math.remainder(q[j], 2 * math.pi)   # in [-π, π]
        q[j] = math.pi if w == -math.pi else w
    return q


def _flip_of(a, b, angles, same):
    """True when b is a turned half a turn in some angle coordinates and equal elsewhere:
    the mirror root of a parallel or point-on-line condition (a slider reversed on its
    guide), not a different assembly of the mechanism."""
    flipped = False
    for j in range(a.shape[0]):
        d = b[j] - a[j]
        if j in angles:
            d = math.remainder(d, 2 * math.pi)
            if abs(abs(d) - math.pi) <= same:
                flipped = True
                continue
        if abs(d) > same:
            return False
    return flipped


def assemblies(mech, t, starts=256, guess=None, level="position", tol=None, flips=False):
    """Every distinct real assembly mode at time t: the compiled solver run from the guess
    and from ``starts`` quasi-random starts (angles over [−π, π), positions within the
    mechanism's size of the guess). Angles equal modulo 2π count once and come back in
    (−π, π]; the mode the plain guess reaches comes first.

    A body turned half a turn with every other coordinate unchanged (a slider reversed on
    its guide: u1 × u2 = 0 holds for opposite directions too) is the same mode unless
    ``flips=True``; the representative kept is the one nearest the guess's angles.
    """
    from .mechanism import _finite
    t = _finite(t, "t")
    if isinstance(starts, bool) or int(starts) != starts or starts < 0:
        raise ValueError(f"starts must be a non-negative integer, got {starts!r}")
    tol = mech._tol(tol)
    mod = mech.module
    meth = mech._method(None)
    q_guess = mech._start(guess)
    angles = angle_coordinates(mech)
    others = [j for j in range(mech.n) if j not in angles]
    pts = mech.points_at(q_guess, t)
    finite = pts[np.isfinite(pts)]
    size = max([1.0] + [abs(float(q_guess[j])) for j in others] +
               ([float(np.max(np.abs(finite)))] if finite.size else []))
    same = 1e-7 * (1.0 + size)
    info = np.zeros(4)
    found = []

    def attempt(q):
        status = mod.solve_position(q, t, mech.p, tol, mech.xtol, mech.maxit, meth, info)
        if status != 0 or not np.all(np.isfinite(q)) or mech.residual(q, t) > tol:
            return
        w = _wrap(q, angles)
        for other in found:
            d = w - other
            for j in angles:
                d[j] = math.remainder(d[j], 2 * math.pi)
            if np.max(np.abs(d)) <= same:
                return
        found.append(w)

    attempt(q_guess.copy())
    guess_mode = found[0] if found else None
    for k in range(1, int(starts) + 1):
        u = _halton(k, mech.n)
        q = q_guess.copy()
        for j in angles:
            q[j] = -math.pi + 2 * math.pi * u[j]
        if k % 2 == 0:  # every other start also moves the positions
            for j in others:
                q[j] = q_guess[j] + size * (2 * u[j] - 1)
        attempt(q)
    if not flips and found:
        target = _wrap(q_guess, angles)

        def distance(w):   # to the guess, over the angles
            return sum(abs(math.remainder(w[j] - target[j], 2 * math.pi)) for j in angles)

        groups = []
        for w in found:
            for g in groups:
                if _flip_of(g[0], w, angles, same):
                    g.append(w)
                    break
            else:
                groups.append([w])
        found = [g[0] if g[0] is guess_mode else min(g, key=distance) for g in groups]
    last = mech.last
    try:
        sols = []
        for q in found:
            s = mech.solve(t, guess=q, level=level, tol=tol)
            s.q[:] = _wrap(s.q, angles)  # Newton's last step may leave the range by an ulp
            sols.append(s)
    finally:
        mech.last = last
    return sols


# ---------------------------------------------------------------------------------------
# Design tables
# ---------------------------------------------------------------------------------------
def _axis(name, values):
    arr = np.atleast_1d(np.asarray(values, dtype=np.float64))
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f"parameter {name!r}: give a number or a 1-D sequence of numbers")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"parameter {name!r}: values must be finite")
    return arr


class DesignTable:
    """Sweeps of one mechanism over a grid of parameter values (a design table).

    ``tab["X4"]`` has shape ``tab.shape + (len(tab.t),)`` (one axis per varied parameter,
    in the order given, then time); points a design could not solve are NaN and
    ``tab.ok`` / ``tab.failures`` say which. ``tab.sweep(i, ...)`` or
    ``tab.sweep(longitud=1.5)`` is one design as a :class:`~mechgen.Sweep`.
    """

    def __init__(self, mech, names, axes, t, P, Q, QD, QDD, INFO, done, level):
        self.mechanism = mech
        self.names = tuple(names)
        self.axes = tuple(axes)
        self.params = dict(zip(self.names, self.axes))
        self.shape = tuple(len(a) for a in axes)
        self.t = t
        self.P = P
        self.Q, self.QD, self.QDD, self.INFO = Q, QD, QDD, INFO
        self.done = done
        self.level = level
        self._have = _LEVELS.index(level)

    @property
    def ok(self) -> np.ndarray:
        """True for the designs solved at every time."""
        return (self.done == len(self.t)).reshape(self.shape)

    @property
    def failures(self) -> list:
        """(parameter values, time of failure, status) of each design that failed."""
        out = []
        for d in np.nonzero(self.done < len(self.t))[0]:
            k = int(self.done[d])
            values = {n: float(self.P[d, self.mechanism._param_index[n]]) for n in self.names}
            out.append((values, float(self.t[k]), int(self.INFO[d, k, 4])))
        return out

    def __len__(self):
        return int(np.prod(self.shape))

    def _flat(self, index=None, **values):
        if values:
            if index is not None:
                raise TypeError("give grid indices or parameter values, not both")
            idx = []
            for name, axis in zip(self.names, self.axes):
                if name not in values:
                    raise KeyError(f"give a value for each varied parameter ({', '.join(self.names)})")
                hit = np.nonzero(np.isclose(axis, values.pop(name), rtol=1e-12, atol=1e-12))[0]
                if not hit.size:
                    raise KeyError(f"{name} = {values} is not on the grid {axis.tolist()}")
                idx.append(int(hit[0]))
            if values:
                raise KeyError(f"{', '.join(values)} is not a varied parameter "
                               f"({', '.join(self.names)})")
            index = tuple(idx)
        if not isinstance(index, tuple):
            index = (index,)
        return int(np.ravel_multi_index(index, self.shape))

    def sweep(self, *index, **values):
        """One design as a Sweep (only the points it solved)."""
        d = self._flat(index if index else None, **values)
        mech = self.mechanism.with_params(**{n: float(self.P[d, self.mechanism._param_index[n]])
                                             for n in self.names})
        k = int(self.done[d])
        from .results import Sweep
        return Sweep(mech, self.t[:k].copy(), self.Q[d, :k].copy(),
                     self.QD[d, :k].copy() if self._have >= 1 else None,
                     self.QDD[d, :k].copy() if self._have >= 2 else None, self.INFO[d, :k].copy())

    @property
    def sweeps(self) -> list:
        """Every design as a Sweep, in grid order (Mech's Table)."""
        return [self.sweep(*np.unravel_index(d, self.shape)) for d in range(len(self))]

    def __getitem__(self, name) -> np.ndarray:
        if not isinstance(name, str):
            raise TypeError("index a design table by quantity name (tab['X4']); "
                            "use tab.sweep(i) for one design")
        from .results import _lookup
        mech = self.mechanism
        kind, k, order = _lookup(mech, name)
        N = len(self.t)
        D = len(self)
        if kind == "q":
            if order > self._have:
                raise KeyError(f"{name!r} needs a table at level {_LEVELS[order]}")
            arr = (self.Q, self.QD, self.QDD)[order][:, :, k].copy()
        else:
            need = mech.output_orders[k] + order
            if need > self._have:
                raise KeyError(f"output {name!r} needs a table at level {_LEVELS[min(need, 2)]}")
            arr = np.empty((D, N))
            out = np.empty((N, len(mech.outputs)))
            for d in range(D):
                mech.module.eval_outputs(self.Q[d], self.QD[d], self.QDD[d], self.t,
                                         self.P[d], order, out)
                arr[d] = out[:, k]
        for d in range(D):
            arr[d, int(self.done[d]):] = np.nan
        return arr.reshape(self.shape + (N,))

    def table(self) -> tuple[list, np.ndarray]:
        """A long table: one row per design and time; the varied parameters, T, then the
        coordinates (and derivatives) and outputs the table's level provides."""
        grid = np.stack(np.meshgrid(*self.axes, indexing="ij"), axis=-1).reshape(-1, len(self.axes))
        N = len(self.t)
        header = list(self.names) + ["T"]
        cols = [np.repeat(grid[:, j], N) for j in range(len(self.names))]
        cols.append(np.tile(self.t, len(self)))
        mech = self.mechanism
        names = list(mech.coordinates)
        if self._have >= 1:
            names += [c + "d" for c in mech.coordinates]
        if self._have >= 2:
            names += [c + "dd" for c in mech.coordinates]
        for k, o in enumerate(mech.outputs):
            names += [o + s for s, d in (("", 0), ("d", 1), ("dd", 2))
                      if mech.output_orders[k] + d <= self._have]
        for name in names:
            header.append(name)
            cols.append(self[name].reshape(-1))
        return header, np.column_stack(cols)

    def to_csv(self, path):
        """Write the long table (see table()) to a CSV file; unsolved points are empty."""
        from .results import write_csv
        return write_csv(path, *self.table())

    def to_dataframe(self):
        """The long table (see table()) as a pandas DataFrame (needs pandas)."""
        pd = _pandas()
        header, data = self.table()
        return pd.DataFrame(data, columns=header)

    def __repr__(self):
        axes = ", ".join(f"{n} in [{', '.join(f'{v:g}' for v in a[:6])}{', ...' if len(a) > 6 else ''}]"
                         for n, a in zip(self.names, self.axes))
        bad = len(self) - int(np.sum(self.done == len(self.t)))
        return (f"<DesignTable of '{self.mechanism.name}': {len(self)} designs ({axes}) × "
                f"{len(self.t)} times, level {self.level}"
                f"{f', {bad} failed' if bad else ''}>")


def _pandas():
    try:
        import pandas as pd
    except ImportError:
        raise ImportError("to_dataframe() needs pandas (pip install pandas); "
                          "to_csv() works without it") from None
    return pd


def design_sweep(mech, t0, t1, n, params, level="position", guess=None, method=None,
                 tol=None, maxit=None, times=None, progress=None, on_fail="warn"):
    """Sweep over time for every combination of parameter values in ``params`` (a dict:
    a sequence varies the parameter, a number fixes it). Each design starts from the
    same guess, as Mech's Table[SetGuess[]; SolveMech[{t0, t1}, n], {param, ...}] does,
    and the loop over designs runs inside the compiled module.

    progress: None (quiet), True (a progress line on stderr) or a callable
    ``progress(done, total)`` called between compiled chunks.
    on_fail: "warn" (default), "raise" or "ignore" for designs that fail to solve.
    """
    from .mechanism import _finite
    if not isinstance(params, dict) or not params:
        raise ValueError("params must be a dict of parameter names to values or sequences")
    if on_fail not in ("warn", "raise", "ignore"):
        raise ValueError(f"on_fail must be 'warn', 'raise' or 'ignore', got {on_fail!r}")
    fixed, names, axes = {}, [], []
    for name, values in params.items():
        if name not in mech._param_index:
            known = ", ".join(mech._param_index) or "none"
            raise ValueError(f"model '{mech.name}' has no parameter {name!r} (parameters: {known})")
        if np.ndim(values) == 0:
            fixed[name] = _finite(values, f"parameter {name!r}")
        else:
            names.append(name)
            axes.append(_axis(name, values))
    base = mech._params_array(fixed) if fixed else mech.p.copy()
    if not names:
        return mech.with_params(**fixed).sweep(t0, t1, n, level=level, guess=guess,
                                               method=method, tol=tol, maxit=maxit, times=times)
    lev = mech._level(level)
    meth = mech._method(method)
    ts = mech._times(t0, t1, n, times)
    tol = mech._tol(tol)
    maxit = mech._maxit(maxit)
    q0 = mech._start(guess)
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, len(axes))
    D, N, nq = grid.shape[0], ts.shape[0], mech.n
    P = np.tile(base, (D, 1))
    for j, name in enumerate(names):
        P[:, mech._param_index[name]] = grid[:, j]
    P = np.ascontiguousarray(P)
    Q, QD, QDD = np.zeros((D, N, nq)), np.zeros((D, N, nq)), np.zeros((D, N, nq))
    INFO = np.zeros((D, N, 5))
    done = np.zeros(D, dtype=np.int64)
    fn = getattr(mech.module, "sweep_designs", None)
    if fn is None:
        raise MechgenError(f"{getattr(mech.module, '__file__', mech.name)} has no sweep_designs(): "
                           "it was generated by an older mechgen; rebuild it with `mechgen build`")
    report = _progress_reporter(progress, D)
    chunk = D if report is None else max(1, min(D, -(-D // 50), max(1, 200_000 // max(N, 1))))
    for a in range(0, D, chunk):
        b = min(D, a + chunk)
        done[a:b] = fn(ts, q0, P[a:b], lev, tol, mech.xtol, maxit, meth,
                       Q[a:b], QD[a:b], QDD[a:b], INFO[a:b])
        if report is not None:
            report(b, D)
    if report is not None:
        report(None, D)
    table = DesignTable(mech, names, axes, ts, P, Q, QD, QDD, INFO, done, _LEVELS[lev])
    bad = table.failures
    if bad and on_fail != "ignore":
        first = bad[0]
        where = ", ".join(f"{k}={v:g}" for k, v in first[0].items())
        msg = (f"{len(bad)} of {D} designs of '{mech.name}' could not be solved at every time "
               f"(first: {where} fails at t={first[1]:.10g}, status {first[2]}); "
               "their unsolved points are NaN")
        if on_fail == "raise":
            err = MechgenError(msg)
            err.table = table
            raise err
        warnings.warn(msg, RuntimeWarning, stacklevel=3)
    return table


def _progress_reporter(progress, total):
    if progress is None or progress is False:
        return None
    if callable(progress):
        def call(done, total_):
            if done is not None:
                progress(done, total_)
        return call

    def line(done, total_):
        if done is None:
            sys.stderr.write("\n")
        else:
            sys.stderr.write(f"\rdesigns solved: {done}/{total_} ({100.0 * done / total_:.0f}%)")
        sys.stderr.flush()
    return line


def parse_param_option(items) -> dict:
    """``--param`` values of the command line: ``NAME=V`` fixes a parameter,
    ``NAME=V1,V2,...`` lists values and ``NAME=START:STOP:STEP`` is Mathematica's
    {name, start, stop, step} (stop included)."""
    out = {}
    for item in items or ():
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise MechgenError(f"--param takes NAME=VALUES, got {item!r}")
        try:
            if ":" in text:
                start, stop, step = (float(x) for x in text.split(":"))
                if not step > 0 or stop < start:
                    raise ValueError
                count = int(math.floor((stop - start) / step + 1e-9)) + 1
                values = start + step * np.arange(count)
            elif "," in text:
                values = np.array([float(x) for x in text.split(",")])
            else:
                values = float(text)
        except ValueError:
            raise MechgenError(f"--param {item!r}: give NAME=V, NAME=V1,V2,... or "
                               "NAME=START:STOP:STEP with STEP > 0") from None
        out[name] = values
    return out
