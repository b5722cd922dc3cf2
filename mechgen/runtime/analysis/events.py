"""Exact extremes and roots of a quantity along a sweep (Mech's FindRoot on a
TimeInterpolate, done exactly).

The coarse route of seed 001 interpolates 20 points and finds extremes on the
interpolant; here the sweep only brackets, and the compiled solver refines: the time
derivative of the quantity is solved exactly (velocity or acceleration level) and its
root found by Brent's method to ~1e-12 in t. Both answers are reported, so the error
of the coarse route is visible.

A sweep's ends count: on a closed time interval the first and last points are extremes
of the sweep (and a zero there is a root), reported with ``at="start"`` / ``at="end"``.
A sweep over exactly one period of its motion (``cycle.one_cycle``: its last point is its
first, the equations repeat) is a closed cycle instead: an extreme or root that wraps
through its ends is found as an interior one of the cycle, at a time in [t0, t1), once.

numpy, and scipy.optimize when a root is refined. Never sympy: a symbolic quantity is
evaluated by the symbolic side that mechgen.compile attaches to the mechanism.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ...protocol import LEVEL, LEVELS
from .cycle import one_cycle
from .interpolate import NotFinite, interpolate
from ..quantity import Quantity


class _Exact:
    """Exact values of a quantity at any t inside a sweep: the module's careful
    continuation from the nearest sweep point to t (so it stays on the sweep's assembly
    mode). ``sw`` holds at least the velocities (Sweep.at_level)."""

    def __init__(self, sw, qty):
        self.sw = sw
        self.qty = qty
        self.mech = sw.mechanism
        self.level = LEVELS[qty.level]
        self.calls = 0

    def solution(self, t):
        sw = self.sw
        k = int(np.argmin(np.abs(sw.t - t)))
        if sw.simulation is not None:      # motion under forces: integrated again from k
            self.calls += 1
            return _integrated(sw, k, t)
        self.calls += 1
        tk = float(sw.t[k])
        if t == tk:
            return self.mech.solve(t, guess=sw.Q[k], level=self.level)
        # the sweep's careful continuation from point k to t (its step control and branch
        # tests), not one Newton from a Taylor predictor: near a toggle, where the two
        # assembly modes lie close, the predictor of a coarse sweep falls into the other
        # mode, and the extreme found would be that mode's value
        return self.mech.sweep(tk, t, 2, guess=sw.Q[k], level=self.level)[1]

    def __call__(self, t):
        return self.qty.on_solution(self.solution(float(t)))


def _integrated(sw, k, t):
    """The state of a simulated sweep at t, integrated from its output k as it was (back
    in time where t is before it: the simulation's own ``integrate``, which the public
    mech.simulate refuses to run backwards)."""
    if t == sw.t[k]:
        return sw[k]
    run = sw.simulation
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")     # its outputs lie on the constraints already
        part = run["integrate"](sw.mechanism, float(sw.t[k]), float(t), 2, free=run["free"],
                                q0=sw.Q[k], qd0=sw.QD[k], rtol=run["rtol"],
                                atol=run["atol"], method=run["method"],
                                max_step=run["max_step"])
    return part[1]


def _finite_abs_max(values) -> float:
    """The largest |value| among the finite ones (0.0 when there are none)."""
    a = np.abs(np.asarray(values, dtype=np.float64))
    a = a[np.isfinite(a)]
    return float(np.max(a)) if a.size else 0.0


def _scale(values) -> float:
    """The size of a quantity's values, for its round-off: the largest finite |value|,
    leaving out a spike, a value over 1e3 times each of its neighbours' (a pole: an
    intersection's x, 5e8 at a sample a hair from its axes turning parallel, 20 about it,
    made every value 'zero' and lost every root and extreme; its rate 1.7e17). A value that
    is not finite is left out, and counts as 0 beside its neighbours."""
    a = np.abs(np.asarray(values, dtype=np.float64))
    finite = np.isfinite(a)
    if not finite.any():
        return 0.0
    a = np.where(finite, a, 0.0)
    big = float(np.max(a))
    if a.size < 3:
        return big
    near = np.empty_like(a)
    near[1:-1] = np.maximum(a[:-2], a[2:])
    near[0], near[-1] = a[1], a[-2]
    rest = a[a <= 1e3 * near]
    return float(np.max(rest)) if rest.size and np.max(rest) > 0 else big


def _zero_tol(values, scale_extra=0.0):
    """Values this small count as zero: round-off of a quantity that is really constant.
    Only finite values count: a NaN (an intersection of parallel axes) is no scale."""
    big = _scale(values)
    return 1e-11 * max(big, scale_extra if math.isfinite(scale_extra) else 0.0, 1e-300)


# the sign of a value that is not a number (NaN, ±inf): no bracket reaches across it
_UNKNOWN = 2


def _signs(v, tol):
    """-1, 0 (|v| <= tol), +1 for each value, _UNKNOWN where it is not finite."""
    v = np.asarray(v, dtype=np.float64)
    finite = np.isfinite(v)
    with np.errstate(invalid="ignore"):
        s = np.where(np.abs(v) <= tol, 0, np.sign(v))
    return np.where(finite, s, _UNKNOWN).astype(int)


def _sign_changes(t, v, tol):
    """Brackets (k, exact) where v changes sign: (k, None) for a change inside
    (t[k], t[k+1]), (k, k) when v[k] itself is zero between opposite signs. A node whose
    value is not finite brackets nothing."""
    s = _signs(v, tol)
    out = []
    n = len(v)
    k = 0
    while k < n - 1:
        if _UNKNOWN in (s[k], s[k + 1]):
            k += 1
            continue
        if s[k] != 0 and s[k + 1] != 0 and s[k] != s[k + 1]:
            out.append((k, None, s[k]))
            k += 1
            continue
        if s[k + 1] == 0 and s[k] != 0:
            j = k + 1
            while j < n and s[j] == 0:
                j += 1
            if j < n and s[j] != s[k] and s[j] != _UNKNOWN:
                if j == k + 2:
                    out.append((k + 1, k + 1, s[k]))
                else:  # a flat stretch: report its middle node
                    out.append(((k + 1 + j - 1) // 2, (k + 1 + j - 1) // 2, s[k]))
            k = j
            continue
        k += 1
    return out


def _cyclic_sign_changes(t, v, tol):
    """The brackets of _sign_changes on a closed cycle whose last node is its first one
    period later (node n−1 ≡ node 0): the sequence is read from its first nonzero node
    round to it again, so that a change through the wrap is found once, and each bracket
    is given back in the sweep's own indices (a node at the wrap as node 0)."""
    n = len(v)
    s = _signs(v, tol)
    nonzero = np.flatnonzero((s[:-1] != 0) & (s[:-1] != _UNKNOWN))
    if not nonzero.size:
        return []
    r = int(nonzero[0])
    period = t[-1] - t[0]
    virt = np.arange(r, n + r)                      # r, ..., n−1 (the wrap), ..., n−1+r
    orig = np.where(virt <= n - 1, virt, virt - (n - 1))
    tt = np.where(virt <= n - 1, t[orig], t[orig] + period)
    vv = v[orig].copy()
    if r > 0:                                       # the wrap node is node 0 itself
        vv[n - 1 - r] = v[0]
    out = []
    for k, node, sign in _sign_changes(tt, vv, tol):
        i = int(orig[k])
        out.append((0 if i == n - 1 else i, None if node is None else int(orig[node]) % (n - 1),
                    sign))
    return out


def _first_sign(s):
    """The first nonzero entry of s, or 0 (also where a value that is not finite comes
    first: the quantity's way from that end is unknown)."""
    nz = np.flatnonzero(s)
    return int(s[nz[0]]) if nz.size and s[nz[0]] != _UNKNOWN else 0


def _end_events(qty, t, y, f, tol, roots, method):
    """The Events at a sweep's two ends: for extremes (roots False) both ends, a maximum
    where the quantity falls away from the end into the sweep (the sign of its derivative
    f, skipping a flat stretch); for roots, an end where the quantity itself is zero, rising
    or falling as it leaves or reaches zero."""
    s = _signs(f, tol)
    forward = 1 if t[-1] >= t[0] else -1
    head, tail = _first_sign(s), _first_sign(s[::-1])
    events = Events()
    for at, k, sign in (("start", 0, head), ("end", len(t) - 1, tail)):
        if sign == 0 or not (math.isfinite(float(y[k])) and math.isfinite(float(t[k]))):
            continue
        # the rate at which the quantity (or its derivative) moves away from this end,
        # into the sweep, in the direction of increasing time
        away = sign * forward if at == "start" else -sign * forward
        if roots:
            if s[k] != 0:
                continue
            kind = "rising" if away > 0 else "falling"
        else:
            kind = "min" if away > 0 else "max"     # it rises into the sweep: a minimum
        events.append(Event(qty.label, kind, float(t[k]), float(y[k]), float(t[k]),
                            float(y[k]), method, 0, at))
    return events


def _repeats(v, tol):
    """The first and last values agree (a quantity that closes over one cycle)."""
    return abs(float(v[-1]) - float(v[0])) <= max(tol, 1e-7 * _finite_abs_max(v))


class _Undefined(Exception):
    """The exact quantity is not a number at a time Brent's method asked for (a pole: the
    intersection of two axes as they turn parallel)."""


def _brent(f, a, b, fa, fb, xtol):
    from scipy.optimize import brentq
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b

    def finite(x):
        v = f(x)
        if not math.isfinite(v):
            raise _Undefined(x)
        return v
    return brentq(finite, a, b, xtol=xtol, rtol=4 * np.finfo(float).eps, maxiter=200)


def _crosses_zero(value, t_star, a, b, fa, fb, tol, xtol) -> bool:
    """Whether Brent's answer in [a, b] is a zero of the quantity, not a jump through
    zero: an angle's wrap from +π to −π, or a pole (f ~ 1/(t − t*)), where Brent's
    method also closes in on a change of sign. At a zero the value left is the slope
    times the time's last step, far below |f| at the bracket's ends."""
    slope = abs(fb - fa) / max(b - a, 1e-300)
    step = xtol + 4 * np.finfo(float).eps * abs(t_star)
    return abs(value) <= max(tol, 1e-3 * min(abs(fa), abs(fb)), 1e3 * step * slope)


class _NoCoarse:
    """The coarse route where the sweep's values are not all finite (no interpolant):
    no roots, NaN values."""
    method = "none (values not finite)"

    def __call__(self, t, nu=0):
        return math.nan

    def roots(self, a=None, b=None):
        return np.empty(0)

    def derivative(self, n=1):
        return self


def _coarse(sw, what, method):
    """The interpolant of the coarse route, or _NoCoarse where a value is not finite."""
    try:
        return interpolate(sw, what, method=method)
    except NotFinite:
        return _NoCoarse()


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
    at: str = "interior"     # "start" / "end": at the sweep's first / last time

    @property
    def at_end(self) -> bool:
        """Whether the event lies at one end of the sweep (not a stationary point of the
        quantity, for an extreme, unless its derivative vanishes there too)."""
        return self.at != "interior"

    @property
    def error_t(self) -> float:
        """How far the interpolant's time is from the exact one."""
        return self.t_interp - self.t

    @property
    def error_value(self) -> float:
        return self.value_interp - self.value

    def __repr__(self):
        where = "" if self.at == "interior" else f" (the sweep's {self.at})"
        return (f"<{self.kind}{where} of {self.name} at t={self.t:.10g}: {self.value:.10g}; "
                f"{self.method} interpolant: t={self.t_interp:.7g}, {self.value_interp:.7g}>")


class Events(list):
    """A list of :class:`Event` in time order, with ``.t`` and ``.value`` arrays.
    ``periodic``: the sweep was one closed cycle (no end events: see the module's doc)."""

    periodic = False

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

    @property
    def interior(self) -> "Events":
        """The events inside the sweep (those of a closed cycle included)."""
        return Events(e for e in self if e.at == "interior")

    @property
    def ends(self) -> "Events":
        """The events at the sweep's first or last time."""
        return Events(e for e in self if e.at != "interior")

    def __repr__(self):
        if not self:
            return "Events([])"
        w = max(8, max(len(e.kind) + (0 if e.at == "interior" else len(e.at) + 3)
                       for e in self))
        lines = [f"{'kind':>{w}}  {'t':>16}  {'value':>16}  {'t (interp.)':>12}  "
                 f"{'value (interp.)':>15}"]
        for e in self:
            kind = e.kind if e.at == "interior" else f"{e.kind} ({e.at})"
            lines.append(f"{kind:>{w}}  {e.t:16.10f}  {e.value:16.10g}  {e.t_interp:12.7g}  "
                         f"{e.value_interp:15.7g}")
        return "\n".join(lines)

    def _repr_html_(self):
        rows = "".join(f"<tr><td>{e.kind if e.at == 'interior' else e.kind + ' (' + e.at + ')'}</td><td>{e.t:.10f}</td><td>{e.value:.10g}</td>"
                       f"<td>{e.t_interp:.7g}</td><td>{e.value_interp:.7g}</td></tr>" for e in self)
        return ("<table><thead><tr><th>kind</th><th>t</th><th>value</th><th>t (interpolant)</th>"
                f"<th>value (interpolant)</th></tr></thead><tbody>{rows}</tbody></table>")


def _turning(f, roots, before, width):
    """The roots of the interpolant f where it changes sign from ``before`` to its
    opposite (in time order), as the exact quantity does: a piecewise polynomial whose
    derivative jumps at the nodes (Mathematica's InterpolatingFunction, "lagrange") has
    roots there through which it turns the other way, a kink minimum as a maximum's."""
    if not len(roots):
        return roots
    lo, hi = f.domain if hasattr(f, "domain") else (-math.inf, math.inf)
    h = 1e-7 * width
    keep = []
    for r in roots:
        left, right = max(r - h, lo), min(r + h, hi)
        sl = np.sign(f(left)) if left < r else before          # an end: that side is free
        sr = np.sign(f(right)) if right > r else -before
        if sl == before and sr == -before:
            keep.append(r)
    return np.asarray(keep, dtype=np.float64)


def _nearest(roots, t, a, b):
    inside = roots[(roots >= a - 1e-12) & (roots <= b + 1e-12)]
    pool = inside if inside.size else roots
    if not pool.size:
        return math.nan
    return float(pool[np.argmin(np.abs(pool - t))])


def _leveled(sw, qty):
    """``sw``, with the derivatives ``qty`` is made of solved at the sweep's own positions
    where it lacks them (linear solves, as the extremes of X4 take X4d): the extremes and
    roots of X4d or of an output's rate from a sweep at level position."""
    if LEVEL[sw.level] < qty.level <= LEVEL["acceleration"] and len(sw):
        last = sw.mechanism.last
        try:
            sw = sw.at_level(qty.level)
        finally:
            sw.mechanism.last = last
    qty.needs(LEVEL[sw.level])
    return sw


def extrema(sw, what, method="auto", xtol=1e-12) -> Events:
    """Extremes of a quantity over the sweep: the sweep brackets a sign change of the exact
    time derivative, Brent's method on exactly solved derivatives refines it. The sweep's
    two ends are extremes too (``at="start"``/``"end"``), except on a sweep over exactly
    one period, a closed cycle, where an extreme through the ends is an interior one.

    Each :class:`Event` also holds the coarse answer: the root of the interpolated
    derivative (Mech's FindRoot on TimeInterpolate) and the interpolated value there.
    """
    mech = sw.mechanism
    qty = Quantity(mech, what)
    sw = _leveled(sw, qty)
    have = LEVEL[sw.level]
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
        # dy at the nodes, and a predictor: the missing levels solved at the sweep's own
        # positions (linear solves, no Newton iteration)
        view = sw.at_level(max(LEVEL["velocity"], dq.level))
        exact_d = _Exact(view, dq)
        exact_v = _Exact(view, qty)
        y = qty.on_sweep(sw)
        dy = dq.on_sweep(view)
        span = abs(t[-1] - t[0]) or 1.0
        tol = _zero_tol(dy, _scale(y) / span)
        # the coarse route: interpolate the derivative the sweep holds, or differentiate
        coarse_v = _coarse(sw, qty.what, method)
        if not isinstance(coarse_v, _NoCoarse) and dq.level <= have:
            coarse_d = _coarse(sw, dq.what, method)
        else:
            coarse_d = coarse_v.derivative()
        calls = lambda: exact_d.calls + exact_v.calls  # noqa: E731 - a counter to read
        periodic = one_cycle(sw) and _repeats(dy, tol)
        brackets = (_cyclic_sign_changes if periodic else _sign_changes)(t, dy, tol)
        events = _refined(qty, t, y, dy, tol, ("max", "min"), exact_d, exact_v, calls,
                          coarse_d, coarse_v, xtol, brackets)
        return _finish(events, periodic, qty, t, y, dy, tol, False, coarse_v.method)
    finally:
        mech.last = last


def _finish(events, periodic, qty, t, y, f, tol, roots, method) -> Events:
    """Add the end events of a sweep that is not a closed cycle; time order."""
    if not periodic:
        events += _end_events(qty, t, y, f, tol, roots, method)
    events.sort(key=lambda e: e.t)
    events.periodic = periodic
    return events


def _refined(qty, t, y, f, tol, kinds, exact_f, exact_y, calls, coarse_f, coarse_y,
             xtol, brackets, zero=False) -> Events:
    """The Events of the sign changes of f (sampled at the sweep's times t): each bracket
    refined by Brent's method on exact_f, its value y from exact_y; beside it the root of
    the interpolant coarse_f that changes sign the same way (_turning), and coarse_y
    there. kinds names a change from positive to negative and the other way, for time
    running forwards. A bracket whose exact f is
    not a number somewhere Brent's method looks is dropped, and so, with ``zero`` (roots:
    f is the quantity itself), is one where f jumps through zero rather than crossing it."""
    events = Events()
    for k, node, sign in brackets:
        before = calls()
        kind = kinds[0] if (sign > 0) == (t[-1] >= t[0]) else kinds[1]
        if node is not None:
            t_star, value = float(t[node]), float(y[node])
        else:
            a, b = float(t[k]), float(t[k + 1])
            lo, hi = min(a, b), max(a, b)
            fa, fb = (f[k], f[k + 1]) if a < b else (f[k + 1], f[k])
            try:
                t_star = _brent(exact_f, lo, hi, float(fa), float(fb), xtol)
            except _Undefined:          # a pole inside: no zero of a rate, no root
                continue
            value = float(exact_y(t_star))
            if zero and not _crosses_zero(value, t_star, lo, hi, float(fa), float(fb), tol,
                                          xtol):
                continue                # a jump through zero (a wrap, a pole): no root
        a, b = float(min(t[k], t[k + 1])), float(max(t[k], t[k + 1]))
        was = sign if t[-1] >= t[0] else -sign      # f's sign before, in time order
        ti = _nearest(_turning(coarse_f, coarse_f.roots(a, b), was, b - a), t_star, a, b)
        vi = float(coarse_y(ti)) if math.isfinite(ti) else math.nan
        events.append(Event(qty.label, kind, t_star, value, ti, vi, coarse_y.method,
                            calls() - before))
    events.sort(key=lambda e: e.t)
    return events


def roots(sw, what, method="auto", xtol=1e-12) -> Events:
    """Times where a quantity crosses zero inside the sweep, refined by Brent's method on
    exact solves; each Event holds the interpolant's root beside the exact one. A zero at
    one of the sweep's ends is a root too (``at="start"``/``"end"``), except on a closed
    cycle (one period), where a crossing through the ends is an interior root. A change of
    sign through a jump is no root: an angle's wrap from +π to −π (``angle(axis)``), a pole
    (``intersection`` of axes turning parallel)."""
    mech = sw.mechanism
    qty = Quantity(mech, what)
    sw = _leveled(sw, qty)
    t = np.asarray(sw.t, dtype=np.float64)
    if len(t) < 2:
        return Events()
    last = mech.last
    try:
        exact = _Exact(sw.at_level(max(LEVEL["velocity"], qty.level)), qty)
        y = qty.on_sweep(sw)
        tol = _zero_tol(y)
        coarse = _coarse(sw, qty.what, method)
        periodic = one_cycle(sw) and _repeats(y, tol)
        brackets = (_cyclic_sign_changes if periodic else _sign_changes)(t, y, tol)
        events = _refined(qty, t, y, y, tol, ("falling", "rising"), exact, exact,
                          lambda: exact.calls, coarse, coarse, xtol, brackets, zero=True)
        return _finish(events, periodic, qty, t, y, y, tol, True, coarse.method)
    finally:
        mech.last = last
