"""Cam profiles: a closed curve in a cam body's own frame as sympy expressions of a profile
parameter, and the numeric checks that a follower keeps its contact geometry on it.

A profile is one of
- parametric: ``(x(s), y(s))`` from a function of the parameter symbol;
- polar: ``r(θ)``, the curve ``(r cos θ, r sin θ)``;
- a table of points: the smooth periodic cubic spline through them, in a parameter that
  runs from 0 to 2π once round the table (knots equally spaced).

Constraints see a profile through opaque functions (ProfileFunction): ``disc_x(s)``,
``disc_y(s)`` and their derivatives ``disc_x'(s)``, ... in printed equations, so that Φ,
Φ_q and γ stay short whatever the profile; the generated module computes each in a helper
of its own from its explicit expression (mechgen.compiler.functions.profiles_code), and lambdify
evaluates them with numpy (``_imp_``). A table's expression is the piecewise cubic in the
wrapped parameter; ``wrap(s, P)`` (s modulo P, derivative 1) lets a parametric profile
defined over one period (a piecewise motion law) hold for every turn.
"""
from __future__ import annotations

import math

import numpy as np
import sympy as sp

from ...errors import ModelError
from ..dag import differentiator
from ..numpy_eval import evaluate


class wrap(sp.Function):
    """``wrap(s, P)``: s modulo P, in [0, P); its derivative in s is 1 (a sawtooth)."""

    nargs = 2

    @classmethod
    def eval(cls, s, period):
        if s.is_Number and period.is_number:
            return sp.Float(math.fmod(float(s), float(period)) % float(period))
        return None

    def fdiff(self, argindex=1):
        if argindex == 1:
            return sp.Integer(1)
        raise sp.ArgumentIndexError(self, argindex)

    def _pythoncode(self, printer):
        s, period = self.args
        return f"({printer._print(s)} % ({printer._print(period)}))"

    @staticmethod
    def _imp_(s, period):
        return np.mod(s, period)


class ProfileFunction(sp.Function):
    """One coordinate of a profile, or one of its derivatives, as an opaque function:
    ``disc_x(s)`` in printed equations (``disc_x'(s)``, ``disc_x''(s)``, ...), its
    arguments the parameter and the model parameters its expression holds. Class
    attributes: ``expr`` (sympy, in ``var`` and the parameters), ``var``, ``params``,
    ``order``, ``base`` (the order-0 name). The generated module computes it in a helper
    function of its own (mechgen.compiler.functions.profiles_code); lambdify through ``_imp_``."""

    expr = sp.Integer(0)
    var = None
    params: tuple = ()
    order = 0
    base = ""
    wrt: tuple = ()         # the model parameters it is differentiated in (sensitivities)

    @classmethod
    def eval(cls, s, *params):
        if s.is_Number and all(p.is_Number for p in params):
            value = cls.expr.subs(dict(zip((cls.var,) + cls.params, (s,) + params)))
            return sp.Float(value.evalf())
        return None

    def fdiff(self, argindex=1):
        if argindex != 1:    # a model parameter: a sensitivity's (never Φ_q's)
            if self.args[argindex - 1] != self.params[argindex - 2]:
                return sp.Derivative(self, self.args[argindex - 1])
            return profile_function(self.base, self.expr, self.var, self.params, self.order,
                                    self.wrt + (self.params[argindex - 2],))(*self.args)
        return profile_function(self.base, self.expr, self.var, self.params,
                                self.order + 1, self.wrt)(*self.args)

    @property
    def helper(self):
        """The name of its function in a generated module."""
        return f"_profile_{self.func.__name__}"

    def _pythoncode(self, printer):
        return f"{self.helper}({', '.join(printer._print(a) for a in self.args)})"

    def _sympystr(self, printer):
        wrt = "".join(f"/d{p.name}" for p in self.wrt)
        return f"{'d' if wrt else ''}{self.base}{chr(39) * self.order}{wrt}" \
            f"({printer._print(self.args[0])})"

    def _mcode(self, printer):      # Mathematica, as Mech writes a function: disc_x'[s]
        return f"{self.base}{chr(39) * self.order}[{printer._print(self.args[0])}]"

    def _latex(self, printer):
        name = self.base.replace("_", r"\_")
        return rf"\mathrm{{{name}}}{chr(39) * self.order}({printer._print(self.args[0])})"

    @classmethod
    def numeric(cls):
        """The numpy function of (s, *params) it stands for."""
        if "_numeric" not in cls.__dict__:
            cls._numeric = sp.lambdify((cls.var,) + cls.params, cls.diffed(), modules="numpy")
        return cls._numeric

    @classmethod
    def diffed(cls):
        """Its expression, differentiated ``order`` times (and in the parameters ``wrt``)."""
        out = derivative(cls.expr, cls.var, cls.order)
        for p in cls.wrt:
            out = _diff(out, p)
        return out

    @classmethod
    def _imp_(cls, s, *params):
        out = cls.numeric()(s, *params)
        return np.broadcast_to(out, np.shape(s)) * 1.0 if np.ndim(s) else out


_FUNCTIONS: dict = {}
_DERIVATIVES: dict = {}


def derivative(expr, var, order):
    """d^order expr / d var^order, each order computed once; a Piecewise (profiles fold
    theirs to the top) branch by branch, its conditions left as they are."""
    if order == 0:
        return expr
    key = (expr, var, order)
    if key not in _DERIVATIVES:
        _DERIVATIVES[key] = _diff(derivative(expr, var, order - 1), var)
    return _DERIVATIVES[key]


def _diff(expr, var):
    if isinstance(expr, sp.Piecewise):
        return sp.Piecewise(*[(_diff(e, var), c) for e, c in expr.args], evaluate=False)
    return differentiator(var)(expr)


def _folded(expr):
    """A Piecewise anywhere in ``expr`` brought to the top (one smooth branch each)."""
    return sp.piecewise_fold(expr) if expr.has(sp.Piecewise) else expr


def profile_function(base, expr, var, params, order=0, wrt=()):
    """The ProfileFunction class of derivative ``order`` of coordinate ``base`` (and of
    its derivative in the model parameters ``wrt``, sorted: a sensitivity's)."""
    wrt = tuple(sorted(wrt, key=lambda p: p.name))
    key = (base, expr, var, params, order, wrt)
    if key not in _FUNCTIONS:
        name = base + ("_" + "s" * order if order else "") + \
            "".join(f"_d{p.name}" for p in wrt)
        _FUNCTIONS[key] = type(name, (ProfileFunction,), dict(
            expr=expr, var=var, params=params, order=order, base=base, wrt=wrt))
    return _FUNCTIONS[key]


def spline_expression(var, knots, coef):
    """The periodic piecewise cubic in ``wrap(var, period)`` (a Piecewise)."""
    w = wrap(var, sp.Float(knots[-1]))
    pieces = []
    for k, c in enumerate(coef):
        u = w - sp.Float(knots[k]) if k else w
        poly = sp.Float(c[0]) + u * (sp.Float(c[1]) + u * (sp.Float(c[2]) + u * sp.Float(c[3])))
        cond = w < sp.Float(knots[k + 1]) if k < len(coef) - 1 else True
        pieces.append((poly, cond))
    return sp.Piecewise(*pieces)


def periodic_spline(values):
    """Coefficients (N × 4) of the periodic cubic spline through ``values`` at knots
    0, h, ..., (N − 1) h, h = 2π/N, closing back to the first value at 2π."""
    y = np.asarray(values, dtype=float)
    n = len(y)
    h = 2 * math.pi / n
    # second derivatives M: M[i-1] + 4 M[i] + M[i+1] = 6 (y[i+1] - 2 y[i] + y[i-1]) / h²
    A = np.zeros((n, n))
    for i in range(n):
        A[i, i] = 4.0
        A[i, (i - 1) % n] += 1.0
        A[i, (i + 1) % n] += 1.0
    rhs = 6.0 * (np.roll(y, -1) - 2 * y + np.roll(y, 1)) / h ** 2
    M = np.linalg.solve(A, rhs)
    M1, y1 = np.roll(M, -1), np.roll(y, -1)
    c0 = y
    c1 = (y1 - y) / h - h * (2 * M + M1) / 6
    c2 = M / 2
    c3 = (M1 - M) / (6 * h)
    return tuple(tuple(float(v) for v in row) for row in np.column_stack([c0, c1, c2, c3]))


class Profile:
    """A cam profile in its body's frame (``m.profile(...)`` makes one).

    ``raw(s)`` gives (x, y) as explicit sympy expressions of ``s``; ``curve(s)`` the same
    as the opaque functions ``name_x(s)``, ``name_y(s)`` that constraints use (short
    equations; the generated module computes each in a function of its own). ``period``
    is the parameter range of one turn round the profile; ``kind`` is "parametric",
    "polar" or "table"."""

    def __init__(self, name, kind, var, x, y, params, period, text):
        self.name, self.kind, self.period, self.text = name, kind, period, text
        x, y = _folded(sp.sympify(x)), _folded(sp.sympify(y))
        self.var, self.x, self.y, self.params = var, x, y, tuple(params)
        self.fx = profile_function(f"{name}_x", x, var, self.params)
        self.fy = profile_function(f"{name}_y", y, var, self.params)

    def __str__(self):
        return self.name

    def __repr__(self):
        return f"<profile {self.name}: {self.text}>"

    def raw(self, s):
        """(x(s), y(s)) as explicit sympy expressions of ``s``."""
        return self.x.subs(self.var, s), self.y.subs(self.var, s)

    def curve(self, s):
        """(x(s), y(s)) as the profile's functions of ``s``."""
        return self.fx(s, *self.params), self.fy(s, *self.params)


def make_profile(model, name, xy=None, polar=None, points=None, period=None, periodic=False):
    """A Profile from exactly one of ``xy`` (a function s -> (x, y)), ``polar`` (a
    function θ -> r) or ``points`` (a table of (x, y) numbers). ``periodic``: the
    function's argument is the parameter wrapped into [0, period) (for a profile defined
    over one period only)."""
    given = [k for k, v in (("xy", xy), ("polar", polar), ("points", points)) if v is not None]
    if len(given) != 1:
        raise ModelError(f"profile '{name}': give exactly one of xy=, polar= or points= "
                         f"(got {', '.join(given) or 'none'})")
    if points is not None:
        return _table(name, points)
    per = sp.sympify(2 * sp.pi if period is None else period)
    per = model._expr(per, f"profile '{name}': the period")
    fn = xy if xy is not None else polar
    if not callable(fn):
        raise ModelError(f"profile '{name}': {given[0]}= must be a function of the profile "
                         f"parameter (e.g. lambda s: (R*cos(s), R*sin(s))), got {fn!r}")
    probe = sp.Symbol(f"_{name}_s", real=True)
    try:
        out = fn(probe)
    except Exception as exc:  # the user's function: say which profile failed
        raise ModelError(f"profile '{name}': calling {given[0]}= failed: {exc}") from None
    if xy is not None:
        from ..geometry import as_pair
        x, y = as_pair(out, f"profile '{name}': xy(s)")
    else:
        r = sp.sympify(out)
        x, y = r * sp.cos(probe), r * sp.sin(probe)
    held = set()
    for e in (x, y):
        held |= sp.sympify(e).free_symbols
        bad = sorted(map(str, sp.sympify(e).free_symbols - {probe} - set(model.param_symbols)))
        if bad:
            raise ModelError(f"profile '{name}': {', '.join(bad)} is not the profile parameter "
                             f"or a declared parameter of model '{model.name}'")
    shown = sp.Symbol("s")
    text = (f"polar r = {sp.sympify(out).subs(probe, shown)}" if polar is not None else
            f"(x, y) = ({x.subs(probe, shown)}, {y.subs(probe, shown)})")
    turn = per
    if periodic and polar is not None:
        # the function is r(θ): its argument is wrapped, not the angle of the point
        # (r cos θ, r sin θ), which goes once round in 2π whatever r's period (a lobed
        # cam written over one lobe, period=2*pi/3); wrapping cos θ too drew that lobe's
        # sector alone, refused as a cusp
        turn = 2 * sp.pi
        lobes = float((turn / per).subs({sym: val for sym, val in model.params.values()}))
        if not (lobes >= 1 and abs(lobes - round(lobes)) < 1e-9):
            raise ModelError(f"profile '{name}': a polar profile's period must divide one "
                             f"turn, 2π (2π / period = {lobes:.6g}), for r(θ) to close")
        r = sp.sympify(out).subs(probe, wrap(probe, per))
        x, y = r * sp.cos(probe), r * sp.sin(probe)
        held |= per.free_symbols
    elif periodic:
        x, y = x.subs(probe, wrap(probe, per)), y.subs(probe, wrap(probe, per))
        held |= per.free_symbols          # a period in parameters: arguments too
    params = [p for p in model.param_symbols if p in held]
    return Profile(name, "polar" if polar is not None else "parametric", probe, x, y,
                   params, turn, text)


def _table(name, points):
    try:
        xy = np.array([[float(v) for v in p] for p in points], dtype=float)
    except (TypeError, ValueError):
        raise ModelError(f"profile '{name}': points= must be a table of (x, y) numbers") from None
    if xy.ndim != 2 or xy.shape[1] != 2 or len(xy) < 4:
        raise ModelError(f"profile '{name}': points= needs at least 4 (x, y) pairs, "
                         f"got shape {xy.shape}")
    if not np.all(np.isfinite(xy)):
        raise ModelError(f"profile '{name}': points= holds a value that is not finite")
    n = len(xy)
    knots = tuple(float(2 * math.pi * k / n) for k in range(n + 1))
    var = sp.Symbol(f"_{name}_s", real=True)
    x = spline_expression(var, knots, periodic_spline(xy[:, 0]))
    y = spline_expression(var, knots, periodic_spline(xy[:, 1]))
    return Profile(name, "table", var, x, y, (), 2 * sp.pi,
                   f"periodic cubic spline through {n} points")


# -- the numeric checks of contact geometry ---------------------------------------------
SAMPLES = 2000


def sample(model, profile, n=SAMPLES):
    """Parameter values and (x, y, x', y', x'', y'') over one period, at the defaults."""
    subs = {sym: val for sym, val in model.params.values()}
    values = [subs[p] for p in profile.params]
    period = float(sp.sympify(profile.period).subs(subs))
    ss = np.linspace(0.0, period, n, endpoint=False)
    exprs = [derivative(f.expr, f.var, order) for order in range(3)
             for f in (profile.fx, profile.fy)]
    given = {p: float(v) for p, v in zip(profile.params, values)}
    given[profile.var] = ss
    return ss, np.array(evaluate(exprs, given, ss.shape))


def closes(model, profile, ss=None, v=None) -> bool:
    """Whether the profile closes on itself over its period (its end is its start), at the
    parameters' defaults; an open one (a translating cam's track, an arc) has no inside and
    no join from its end back to its start. ``ss, v``: a sample() already taken."""
    if ss is None:
        ss, v = sample(model, profile, 720)
    period = float(ss[-1] + (ss[1] - ss[0]))
    subs = {sym: val for sym, val in model.params.values()}
    given = {p: float(subs[p]) for p in profile.params}
    given[profile.var] = np.array([period])
    end = np.array(evaluate([profile.fx.expr, profile.fy.expr], given, (1,)), dtype=float)
    size = float(np.max(np.hypot(v[0] - v[0].mean(), v[1] - v[1].mean()))) or 1.0
    return bool(np.hypot(end[0][0] - v[0][0], end[1][0] - v[1][0]) <= 1e-6 * size)


def orientation(model, profile) -> int:
    """+1 when the profile runs counter-clockwise (its outward normal is (y', −x')), else −1.

    An open profile (one that does not close over its period: a translating cam's track)
    has no inside: +1, its "outside" the right of its direction of travel, (y', −x'). Its
    signed area ∮ (x y' − y x')/2 would depend on where the track lies in the cam's frame
    (shifting it across the frame's origin flipped the roller to the other side)."""
    ss, v = sample(model, profile, 720)
    if not closes(model, profile, ss, v):
        return 1
    area = 0.5 * np.sum(v[0] * v[3] - v[1] * v[2])
    return 1 if area >= 0 else -1


def _breaks(model, profile, ss, v, closed):
    """(s, jump, corner) of the first place where the profile's point jumps (``jump``,
    the two points) or its tangent turns at once (``corner``, the angle in radians), else
    None. Neighbouring samples that move or turn much more than the speed and curvature
    at both say are candidates; bisecting each down to a parameter step of about 1e-11
    tells a break (it stays) from a steep but smooth part (it vanishes). The join from the
    end back to the start counts when the profile closes (a periodic law whose end does
    not meet its start jumps there)."""
    subs = {sym: val for sym, val in model.params.values()}
    given = {p: float(subs[p]) for p in profile.params}
    exprs = [derivative(f.expr, f.var, order) for order in range(3)
             for f in (profile.fx, profile.fy)]

    def at(s):
        g = dict(given)
        g[profile.var] = np.asarray(s, dtype=float)
        return np.array(evaluate(exprs, g, g[profile.var].shape), dtype=float)

    step = float(ss[1] - ss[0])
    end = float(ss[-1] + step)
    nxt = np.roll(v, -1, axis=1)
    if closed:
        nxt[:, -1] = at([end])[:, 0]        # the limit at the period: the start again
    size = float(np.max(np.hypot(v[0] - v[0].mean(), v[1] - v[1].mean()))) or 1.0
    # the trapezoid rule between neighbours: off by O(step² c'') where the profile is
    # smooth, by the jump (the corner) itself where it breaks
    miss = np.hypot(nxt[0] - v[0] - (v[2] + nxt[2]) * step / 2,
                    nxt[1] - v[1] - (v[3] + nxt[3]) * step / 2)
    moved = miss > np.hypot(nxt[2] - v[2], nxt[3] - v[3]) * step + 1e-9 * size
    turn = np.arctan2(v[2] * nxt[3] - v[3] * nxt[2], v[2] * nxt[2] + v[3] * nxt[3])
    with np.errstate(divide="ignore", invalid="ignore"):     # a cusp: NaN, no corner here
        bend = [(w[2] * w[5] - w[3] * w[4]) / np.maximum(np.hypot(w[2], w[3]), 1e-300) ** 2
                for w in (v, nxt)]                              # κ · speed, signed
    turned = np.abs(turn - (bend[0] + bend[1]) * step / 2) > \
        np.abs(bend[1] - bend[0]) * step + 1e-6
    if not closed:
        moved[-1] = turned[-1] = False
    def gap(lo, hi):
        p = at([lo, hi])
        return (np.hypot(p[0, 1] - p[0, 0], p[1, 1] - p[1, 0]) / size,
                abs(math.atan2(p[2, 0] * p[3, 1] - p[3, 0] * p[2, 1],
                               p[2, 0] * p[2, 1] + p[3, 0] * p[3, 1])))

    cases = [(k, 0) for k in np.flatnonzero(moved)[:8]] + \
        [(k, 1) for k in np.flatnonzero(turned)[:8]]
    for k, which in sorted(cases, key=lambda c: (c[1], c[0])):   # a jump before a corner
        a, b = float(ss[k]), float(ss[k]) + step
        while b - a > 1e-11 * max(1.0, abs(end)):
            m = 0.5 * (a + b)
            a, b = (a, m) if gap(a, m)[which] >= gap(m, b)[which] else (m, b)
        d, t = gap(a, b)
        if d > 1e-7 or t > 1e-5:
            p = at([a, b])
            return b, (p[:2, 0], p[:2, 1]) if d > 1e-7 else None, t
    return None


def check_contact(where, model, profile, radius=None, side=1, convex=False, corners=False):
    """Raise ModelError when a follower loses contact geometry on ``profile``: the profile
    jumps (its point is not continuous: any follower would jump with it), has a cusp (its
    tangent vanishes or turns back), a corner (its tangent turns at once) under a roller,
    a flat face or another cam (``corners``; a knife edge rides over one), a roller of
    ``radius`` is larger than the radius of curvature of a part it rolls against from the
    hollow side, or (``convex``) a flat face meets a concave part. ``where`` names the
    constraint and cam."""
    ss, v = sample(model, profile)
    if not np.all(np.isfinite(v)):
        k = int(np.argmin(np.all(np.isfinite(v), axis=0)))
        raise ModelError(f"{where}: the profile '{profile}' is not finite at s = {ss[k]:.6g}")
    speed = np.hypot(v[2], v[3])
    turn = v[2] * np.roll(v[2], -1) + v[3] * np.roll(v[3], -1)   # t_i · t_(i+1)
    closed = closes(model, profile, ss, v)
    if not closed:
        turn[-1] = 1.0      # an open profile: no join from its end back to its start
    broken = _breaks(model, profile, ss, v, closed)
    if broken is not None and broken[1] is not None:
        s, (p0, p1) = broken[0], broken[1]
        seam = " (its end does not meet its start)" if abs(s - ss[-1] - (ss[1] - ss[0])) < \
            1e-9 * max(1.0, abs(s)) else ""
        raise ModelError(f"{where}: the profile '{profile}' jumps at s = {s:.6g}{seam}, from "
                         f"({p0[0]:.6g}, {p0[1]:.6g}) to ({p1[0]:.6g}, {p1[1]:.6g}): a "
                         "follower would jump with it; make the profile continuous")
    scale = float(np.max(speed)) or 1.0
    if np.min(speed) < 1e-7 * scale or np.any(turn < 0):
        k = int(np.argmin(speed)) if np.min(speed) < 1e-7 * scale else int(np.argmax(turn < 0))
        raise ModelError(f"{where}: the profile '{profile}' has a cusp at s = {ss[k]:.6g} "
                         "(its tangent vanishes or turns back there): a follower loses contact "
                         "geometry; smooth the profile (or the roller is too large for it)")
    if broken is not None and (corners or convex or radius is not None):
        raise ModelError(f"{where}: the profile '{profile}' has a corner at s = "
                         f"{broken[0]:.6g} (its tangent turns by {math.degrees(broken[2]):.4g}° "
                         "at once): a roller, a flat face or another cam loses contact "
                         "geometry there (its contact point jumps); round the corner (a knife "
                         "edge may ride over it)")
    kappa = (v[2] * v[5] - v[3] * v[4]) / speed ** 3
    nu = orientation(model, profile)
    if radius is not None:
        r = float(sp.sympify(radius).subs({sym: val for sym, val in model.params.values()}))
        factor = 1 + side * nu * r * kappa
        if np.min(factor) <= 0:
            k = int(np.argmin(factor))
            raise ModelError(f"{where}: the roller (radius {r:g}) is larger than the radius "
                             f"of curvature {1 / abs(kappa[k]):.6g} of the profile '{profile}' "
                             f"at s = {ss[k]:.6g}: its contact point jumps (contact geometry "
                             "is lost); use a smaller roller or a flatter profile")
    if convex:
        bad = nu * kappa < -1e-9 * np.max(np.abs(kappa))
        if np.any(bad):
            k = int(np.argmax(bad))
            raise ModelError(f"{where}: the profile '{profile}' is concave at s = {ss[k]:.6g} "
                             "(radius of curvature "
                             f"{1 / abs(kappa[k]):.6g}): a flat-faced follower would cut "
                             "through it; a flat face needs a convex profile")
    return nu
