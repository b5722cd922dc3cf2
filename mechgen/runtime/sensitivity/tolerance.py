"""Tolerance and clearance bands (docs/reference/sensitivities.md): how far a quantity of a solved
sweep (or solution) may move when the parameters move within their tolerances and revolute joints
have radial clearance.

``mech.tolerance(result, {"longitud": 0.01, "altura": (-0.02, 0.01)},
clearance={"O2": 0.05}, method="worst")`` returns a :class:`Band`; ``band["X4"]`` is
{"nominal", "low", "high"} over the result's points, for every name ``result.sensitivity``
answers (coordinates and their rates at the result's level, declared outputs, Mech's
symbolic quantities on a mechanism built by mechgen.compile, a driver's effort at a force
level) and for a point's global coordinate (``"coupler[3].x"``, a label of the module's
POINTS). On a Solution the values are floats, on a Sweep arrays over its points (a vector
quantity gains a last axis).

A tolerance ``t`` (> 0) is ±t about the parameter's value; ``(low, high)`` are the
deviations, low <= 0 <= high. With g = ∂out/∂p (the result's exact sensitivities: its own
where it carries them for the parameters, else computed for them on a copy):

- "worst": each tolerance's term ranges over [min(g·low, g·high), max(g·low, g·high)]; a
  clearance c's over ±c·‖∂out/∂e‖; low and high add the terms' lower and upper ends.
- "rss": a tolerance is a uniform-looking spread of σ = (high − low)/6 about its centre
  (low + high)/2 (σ = t/3 for a symmetric one, the contract's); a clearance of radius c
  has σ = c/3 in each direction of e; band = nominal + Σ g·centre ± 3·sqrt(Σ σ²·g²).
- "montecarlo": ``samples`` designs (default 10,000, ``seed``), each tolerance uniform in
  its interval and each clearance uniform in its disc, solved as a design table of listed
  designs on ``backend`` ("cpu", "dask", "cuda"; ``workers``, ``client``) at the result's
  times, a clearance by Newton on Φ(q) − E·e = 0 from each design's point (the nonlinear
  truth: mechgen.runtime.sensitivity.montecarlo); low/high are the samples' minimum and
  maximum at each time. Samples that fail (not solved at every time, a branch jump, a
  clearance that does not converge) are left out, counted (``band.failed``) and warned of.

``band.contributions("X4")`` is the stack-up table whatever the method: {name: array},
each tolerance's share of the worst-case band's half-width, |g|·(high − low)/2 (|g|·t for
a symmetric one), and each clearance's c·‖∂X4/∂e‖; ``side="high"`` gives each term's upper
end max(g·low, g·high) (+c‖∂X4/∂e‖), ``side="low"`` its lower end. Their sum is the worst
band's half-width (high − nominal, nominal − low). ``band.worst_index(name)`` is the point
where the worst band is widest.
"""
from __future__ import annotations

import copy
import math
import numbers
import warnings

import numpy as np

from ...errors import MechgenError
from ..forces.lookup import tables
from .values import point_index, point_sensitivity
from .clearance import AXES, along, offset_derivatives, revolute_rows

METHODS = ("worst", "rss", "montecarlo")
_MONTECARLO_OPTIONS = ("samples", "seed", "backend", "workers", "client")


class ToleranceError(MechgenError, ValueError):
    """Tolerances, clearances or options that cannot make a band; names the culprit."""


# -- the arguments ------------------------------------------------------------------------
def _number(value, what) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ToleranceError(f"{what}: give a number, got {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise ToleranceError(f"{what}: must be finite, got {value!r}")
    return value


def parse_tolerances(mech, tolerances) -> dict:
    """{parameter: (low, high)} from {parameter: t or (low, high)}: t >= 0 is ±t; low <= 0
    <= high are the deviations from the parameter's value."""
    if tolerances is None:
        return {}
    if not hasattr(tolerances, "items"):
        raise ToleranceError(f"tolerances: give a mapping {{parameter: t or (low, high)}}, "
                             f"got {tolerances!r}")
    names = mech.parameter_names
    out = {}
    for name, value in tolerances.items():
        if name not in names:
            raise ToleranceError(f"tolerance {name!r}: model '{mech.name}' has no such "
                                 f"parameter (its parameters: {', '.join(names) or 'none'})")
        what = f"tolerance of {name!r}"
        if isinstance(value, (tuple, list, np.ndarray)):
            if len(value) != 2:
                raise ToleranceError(f"{what}: give t or (low, high), got {value!r}")
            low, high = _number(value[0], what + " (low)"), _number(value[1], what + " (high)")
            if low > 0:
                raise ToleranceError(f"{what}: low = {low:g} > 0; (low, high) are deviations "
                                     "from the parameter's value, low <= 0 <= high")
            if high < 0:
                raise ToleranceError(f"{what}: high = {high:g} < 0; (low, high) are "
                                     "deviations from the parameter's value, low <= 0 <= high")
        else:
            t = _number(value, what)
            if t < 0:
                raise ToleranceError(f"{what}: {t:g} is negative; a tolerance t is ±t (give "
                                     "t >= 0, or (low, high) with low <= 0 <= high)")
            low, high = -t, t
        out[name] = (low, high)
    return out


def parse_clearances(mech, clearance) -> dict:
    """{revolute's name: (c, its two rows of Φ)} from {name: c}, c >= 0."""
    if clearance is None:
        return {}
    if not hasattr(clearance, "items"):
        raise ToleranceError(f"clearance: give a mapping {{revolute: c}}, got {clearance!r}")
    out, seen = {}, {}
    for name, value in clearance.items():
        c = _number(value, f"clearance of {name!r}")
        if c < 0:
            raise ToleranceError(f"clearance of {name!r}: {c:g} is negative; a radial "
                                 "clearance c >= 0 lets the pin centres be |e| <= c apart")
        rows = revolute_rows(mech, name)
        if rows in seen:
            raise ToleranceError(f"clearance: {seen[rows]!r} and {name!r} name the same "
                                 "revolute")
        seen[rows] = name
        out[str(name)] = (c, rows)
    return out


# -- the band ------------------------------------------------------------------------------
def tolerance(mech, result, tolerances=None, clearance=None, method="worst", **options):
    """Mechanism.tolerance (see the module docstring): a Band over ``result``."""
    if method not in METHODS:
        raise ToleranceError(f"method must be one of {', '.join(map(repr, METHODS))}, got "
                             f"{method!r}")
    unknown = [k for k in options if k not in _MONTECARLO_OPTIONS]
    if unknown:
        raise TypeError(f"tolerance() got unexpected option(s) {', '.join(unknown)} (its "
                        f"options: {', '.join(_MONTECARLO_OPTIONS)}, for method='montecarlo')")
    if options and method != "montecarlo":
        raise ToleranceError(f"{', '.join(options)}: options of method='montecarlo' (this "
                             f"band's method is {method!r})")
    if "P" in getattr(result, "__dict__", {}) or not hasattr(result, "mechanism") or \
            not hasattr(result, "sensitivity"):
        raise ToleranceError("tolerance bands are of a Sweep or a Solution (a design table: "
                             "take one design with tab.sweep(i))")
    own = result.mechanism
    if own.name != mech.name or own.parameter_names != mech.parameter_names:
        raise ToleranceError(f"this result is of '{own.name}', not of '{mech.name}'")
    tols = parse_tolerances(own, tolerances)
    clears = parse_clearances(own, clearance)
    if not tols and not clears:
        raise ToleranceError("give at least one tolerance ({parameter: t}) or clearance "
                             "({revolute: c})")
    samples = None
    if method == "montecarlo":
        from .montecarlo import run
        samples = run(own, result, tols, clears, **options)
        if samples.failed:
            warnings.warn(f"{samples.failed} of {samples.count} Monte Carlo samples of "
                          f"'{own.name}' failed ({samples.why()}); the band is of the "
                          f"{samples.used} others", RuntimeWarning, stacklevel=3)
    return Band(result, tols, clears, method, samples)


class Band:
    """Tolerance and clearance bands over a Sweep or at a Solution (module docstring).

    ``band[name]``: {"nominal", "low", "high"}; ``band.contributions(name)``: the stack-up
    table; ``band.method``, ``band.times`` (the result's times; one for a Solution),
    ``band.tolerances`` ({parameter: (low, high)}), ``band.clearances`` ({revolute: c}),
    ``band.result``; a Monte Carlo band's ``samples`` (how many were drawn), ``used``,
    ``failed`` and ``seed``."""

    def __init__(self, result, tolerances, clearances, method, samples=None):
        self.result = result
        self.mechanism = result.mechanism
        self.method = method
        self.tolerances = dict(tolerances)
        self.clearances = {name: c for name, (c, _) in clearances.items()}
        self._rows = [rows for _, rows in clearances.values()]
        self.times = np.asarray(result.t, dtype=float).reshape(-1).copy()
        self._mc = samples
        self.samples = None if samples is None else samples.count
        self.used = None if samples is None else samples.used
        self.failed = None if samples is None else samples.failed
        self.seed = None if samples is None else samples.seed
        self._sens = None           # the result with the tolerances' sensitivities
        self._offsets = None        # offset_derivatives of the clearances
        self._grads = {}
        self._bands = {}

    # -- the linear terms --------------------------------------------------------------
    def _with_sensitivities(self):
        if self._sens is None:
            res = self.result
            need = list(self.tolerances)
            carried = res.__dict__.get("sensitivities")
            if carried is None or not all(p in carried.params for p in need):
                from . import attach
                res = copy.copy(res)
                res.__dict__.pop("force_sensitivity", None)
                attach(self.mechanism, res, need)
            self._sens = res
        return self._sens

    def gradients(self, name) -> tuple:
        """({parameter: ∂name/∂p}, {revolute: ∂name/∂e with a last axis (x, y)}) on the
        result's points."""
        key = _key(name)
        if key not in self._grads:
            point = _point_coordinate(self.mechanism, name)
            params, offsets = {}, {}
            if self.tolerances:
                res = self._with_sensitivities()
                for p in self.tolerances:
                    params[p] = np.asarray(
                        _point_part(point_sensitivity(res, point[0])[..., point[1], :], res, p)
                        if point else res.sensitivity(name, p), dtype=float)
            if self.clearances:
                self._refuse_effort(name, "a clearance band")
                if self._offsets is None:
                    self._offsets = offset_derivatives(self.mechanism, self.result, self._rows)
                for i, c in enumerate(self.clearances):
                    parts = [self._offset_part(name, point, 2 * i + a) for a in range(2)]
                    offsets[c] = np.stack([np.asarray(v, dtype=float) for v in parts], axis=-1)
            self._grads[key] = (params, offsets)
        return self._grads[key]

    def _offset_part(self, name, point, column):
        if point is None:
            return along(self.result, name, self._offsets, column)
        return _point_along(self.result, point, self._offsets, column)

    def _refuse_effort(self, name, what):
        mech = self.mechanism
        if isinstance(name, str) and name not in mech.coordinates and \
                getattr(type(self.result), "force_level", None) is not None:
            try:
                entry = tables(mech).find(name, mech)
            except ValueError:
                entry = None
            if entry is not None and entry[2]:
                raise ToleranceError(f"{name!r}: {what} of a driver's effort is not "
                                     "available (tolerances on parameters are)")

    def contributions(self, name, side=None) -> dict:
        """{tolerance or clearance: its share of ``name``'s band} (module docstring):
        side None the share of the worst band's half-width, "high" each term's upper end,
        "low" its lower end."""
        if side not in (None, "high", "low"):
            raise ValueError(f"side must be None, 'high' or 'low', got {side!r}")
        params, offsets = self.gradients(name)
        out = {}
        for p, g in params.items():
            lo, hi = self.tolerances[p]
            out[p] = _out(np.abs(g) * (hi - lo) / 2 if side is None else
                          np.maximum(g * lo, g * hi) if side == "high" else
                          np.minimum(g * lo, g * hi))
        for c, ge in offsets.items():
            share = self.clearances[c] * np.sqrt(np.sum(ge * ge, axis=-1))
            out[c] = _out(-share if side == "low" else share)
        return out

    def worst_index(self, name) -> int:
        """The index of the result's point where ``name``'s worst-case band is widest
        (its first component's, for a vector quantity)."""
        width = sum(np.asarray(v, dtype=float) for v in self.contributions(name).values())
        width = np.asarray(width, dtype=float).reshape(len(self.times), -1)[:, 0]
        if not np.any(np.isfinite(width)):
            return 0
        return int(np.nanargmax(width))

    # -- the bands ---------------------------------------------------------------------
    def __getitem__(self, name) -> dict:
        key = _key(name)
        if key not in self._bands:
            nominal = np.asarray(nominal_value(self.result, name), dtype=float)
            if self.method == "montecarlo":
                if self.clearances:
                    self._refuse_effort(name, "a Monte Carlo clearance band")
                values = self._mc.values(name, _point_coordinate(self.mechanism, name))
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", RuntimeWarning)   # an all-NaN time
                    low, high = np.nanmin(values, axis=0), np.nanmax(values, axis=0)
                low, high = low.reshape(nominal.shape), high.reshape(nominal.shape)
            else:
                low, high = self._linear(name, nominal)
            self._bands[key] = {"nominal": _out(nominal), "low": _out(low), "high": _out(high)}
        return dict(self._bands[key])

    def _linear(self, name, nominal):
        params, offsets = self.gradients(name)
        if self.method == "worst":
            low = nominal + sum((v for v in self.contributions(name, "low").values()), 0.0)
            high = nominal + sum((v for v in self.contributions(name, "high").values()), 0.0)
            return np.asarray(low, dtype=float), np.asarray(high, dtype=float)
        shift, var = 0.0, 0.0
        for p, g in params.items():
            lo, hi = self.tolerances[p]
            shift = shift + g * (lo + hi) / 2
            var = var + (g * (hi - lo) / 6) ** 2
        for c, ge in offsets.items():
            var = var + (self.clearances[c] / 3) ** 2 * np.sum(ge * ge, axis=-1)
        centre = nominal + shift
        half = 3 * np.sqrt(var)
        return np.asarray(centre - half, dtype=float), np.asarray(centre + half, dtype=float)

    def keys(self) -> tuple:
        return ("nominal", "low", "high")

    def __repr__(self):
        mech = self.mechanism
        terms = [f"{p} {_interval(lo, hi)}" for p, (lo, hi) in self.tolerances.items()]
        terms += [f"{c} clearance {v:g}" for c, v in self.clearances.items()]
        where = f"{len(self.times)} points, T from {self.times[0]:.6g} to " \
                f"{self.times[-1]:.6g}" if len(self.times) > 1 or not self._single() \
            else f"T = {self.times[0]:.6g}"
        mc = "" if self._mc is None else \
            f"; {self.used} of {self.samples} samples" + \
            (f" ({self.failed} failed)" if self.failed else "") + \
            ("" if self.seed is None else f", seed {self.seed}")
        return (f"<Band {self.method!r} of '{mech.name}' over {where}: "
                f"{', '.join(terms)}{mc}>")

    def _single(self) -> bool:
        return not hasattr(self.result, "Q")


def _interval(lo, hi) -> str:
    return f"±{hi:g}" if lo == -hi else f"({lo:+g}, {hi:+g})"


def _out(a):
    """A float for a 0-d value (a Solution's), else the array."""
    a = np.asarray(a, dtype=float)
    return float(a) if a.ndim == 0 else a


def _key(name):
    try:
        hash(name)
        return name
    except TypeError:
        return ("repr", repr(name))


# -- names: a point's coordinate, the nominal value -------------------------------------------
def _point_coordinate(mech, name):
    """(point index, axis) for ``"label.x"`` / ``"label.y"`` of a point the module lists,
    else None."""
    if not isinstance(name, str) or not name.endswith((".x", ".y")):
        return None
    label = name[:-2]
    if label not in mech.point_names:
        return None
    return point_index(mech, label), "xy".index(name[-1])


def _point_part(columns, res, p):
    """The column of parameter p in point_sensitivity's answer."""
    return columns[..., list(res.sensitivity_params).index(p)]


def _point_along(result, point, directions, column):
    """A point coordinate's derivative along an offset component: points_p's chain rule
    with the direction in place of dq/dp, its explicit part taken away."""
    from .solve import Sensitivities
    mech = result.mechanism
    npar = len(mech.parameter_names)
    if npar == 0:
        raise ToleranceError(f"the clearance band of a point needs a parameter in "
                             f"'{mech.name}' (its derivatives are written per parameter)")

    def value(scale):
        d = directions[0]
        F = np.zeros(d.shape[:-1] + (npar,))
        F[..., 0] = scale * d[..., column]
        fake = copy.copy(result)
        fake.sensitivities = Sensitivities((mech.parameter_names[0],),
                                           np.zeros(1, dtype=np.int64), (F, None, None))
        return point_sensitivity(fake, point[0])[..., point[1], 0]

    return np.asarray(value(1.0)) - np.asarray(value(0.0))


def nominal_value(result, name):
    """The value of ``name`` on the result: a coordinate, rate or output (result[name]), a
    point's coordinate ("coupler[3].x"), a driver's effort at a force level, or a symbolic
    quantity (mech.evaluate)."""
    mech = result.mechanism
    point = _point_coordinate(mech, name)
    if point is not None:
        pts = np.asarray(result.points())
        return pts[..., point[0], point[1]]
    if isinstance(name, str):
        if getattr(type(result), "force_level", None) is not None and \
                name not in mech.coordinates:
            try:
                entry = tables(mech).find(name, mech)
            except ValueError:
                entry = None
            if entry is not None and entry[2]:
                return result.driver(name)
        return result[name]
    return mech.evaluate(name, result)


__all__ = ["Band", "METHODS", "ToleranceError", "nominal_value", "parse_clearances",
           "parse_tolerances", "tolerance", "AXES"]
