"""A fitting problem, checked once and passed explicitly to each stage of mech.fit: the
mechanism, the point, the targets, the parameters chosen and their bounds, the timing,
the period of the drivers (timing free) and the options."""
from __future__ import annotations

import math

import numpy as np

from ...errors import MechgenError
from ...protocol import OK
from ..guards import finite
from ..sensitivity.values import point_index

# mech.fit's options and their defaults (docs/reference/sensitivities.md;
# mechgen.runtime.fitting.fit says what each does)
DEFAULTS = dict(samples=4096, n=65, rounds=5, starts=2, modes="all", period=None, t0=None,
                tol=None, seed=0, backend="cpu", workers=None, max_nfev=100, check_points=257,
                enough=None)


class Problem:
    """The checked arguments of one fit. ``names``: the parameters chosen, ``lows`` and
    ``highs`` their bounds; ``timing``: the k times, or None (phases free); ``period``:
    one cycle of the drivers (timing free), ``t0`` its start; ``scale``: the targets'
    size (tolerances are relative to 1 + scale); ``options``: DEFAULTS as given."""

    def __init__(self, mech, point, targets, names, lows, highs, timing, options):
        self.mech = mech
        self.point = point
        self.label = mech.point_names[point]
        self.targets = targets
        self.k = targets.shape[0]
        self.names = tuple(names)
        self.lows = lows
        self.highs = highs
        self.timing = timing
        self.options = options
        self.scale = float(np.max(np.abs(targets)))
        self.t0 = mech.guess_t if options["t0"] is None else finite(options["t0"], "t0")
        self.period = None
        enough = options["enough"]
        self.enough = 1e-12 * (1.0 + self.scale) if enough is None else float(enough)

    @property
    def free(self) -> bool:
        """Whether the phases are unknowns (timing None)."""
        return self.timing is None

    def params_of(self, x) -> dict:
        """{name: value} of the chosen parameters from the first len(names) of ``x``."""
        return {n: float(v) for n, v in zip(self.names, x)}


def make_problem(mech, point, target, params, timing, options) -> Problem:
    """The Problem of ``mech.fit(point, target, params, timing, **options)``; a
    ValueError, KeyError or TypeError that says which argument is wrong."""
    unknown = sorted(set(options) - set(DEFAULTS))
    if unknown:
        raise TypeError(f"fit() got unexpected option(s) {', '.join(unknown)} (its options: "
                        f"{', '.join(DEFAULTS)})")
    opts = dict(DEFAULTS, **options)
    k = point_index(mech, point)
    targets = np.asarray(target, dtype=np.float64)
    if targets.ndim != 2 or targets.shape[1] != 2 or targets.shape[0] < 1:
        raise ValueError(f"target must be (k, 2) points, got shape {targets.shape}")
    if not np.all(np.isfinite(targets)):
        raise ValueError("target: every coordinate must be finite")
    if not isinstance(params, dict) or not params:
        raise ValueError("params must be a dict of parameter names to (low, high) bounds")
    names, lows, highs = [], [], []
    for name, bound in params.items():
        if name not in mech.parameter_names:
            raise ValueError(f"model '{mech.name}' has no parameter {name!r} "
                             f"(parameters: {', '.join(mech.parameter_names)})")
        try:
            lo, hi = (float(v) for v in bound)
        except (TypeError, ValueError):
            raise ValueError(f"params[{name!r}] must be (low, high), got {bound!r}") from None
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise ValueError(f"params[{name!r}] = ({lo}, {hi}): give finite low < high")
        names.append(name)
        lows.append(lo)
        highs.append(hi)
    if timing is not None:
        timing = np.asarray(timing, dtype=np.float64).reshape(-1)
        if timing.shape[0] != targets.shape[0] or not np.all(np.isfinite(timing)):
            raise ValueError(f"timing must be None or {targets.shape[0]} finite times (one "
                             f"a target), got {timing.shape[0]}")
    for name in ("samples", "n", "rounds", "starts", "max_nfev", "check_points"):
        value = opts[name]
        least = 0 if name == "rounds" else 1
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < least:
            raise ValueError(f"{name} must be an integer >= {least}, got {value!r}")
    if opts["n"] < 3 or opts["check_points"] < 3:
        raise ValueError("n and check_points must be at least 3")
    if opts["modes"] not in ("all", "guess"):
        raise ValueError(f"modes must be 'all' or 'guess', got {opts['modes']!r}")
    if opts["tol"] is not None and not float(opts["tol"]) > 0:
        raise ValueError(f"tol must be None or a positive number, got {opts['tol']!r}")
    problem = Problem(mech, k, targets, names, np.array(lows), np.array(highs), timing, opts)
    if problem.free:
        problem.period = period_of(mech, problem.t0, opts["period"])
    return problem


def period_of(mech, t0, given=None) -> float:
    """One cycle of the drivers: ``given``, else the period a body's angle turns once in
    at t0 (2π over its rate) for which a sweep over it at the mechanism's parameters is
    one closed cycle (mechgen.runtime.analysis.cycle); a MechgenError asking for
    ``period=`` when none is."""
    if given is not None:
        period = finite(given, "period")
        if not period > 0:
            raise ValueError(f"period must be positive, got {given!r}")
        return period
    from ..analysis.assembly import body_angles
    from ..analysis.cycle import one_cycle
    try:
        s = mech.solve(t0, level="velocity")
    except MechgenError as exc:
        raise MechgenError(f"fit: the period of '{mech.name}''s drivers could not be found "
                           f"(its configuration at t={t0:.6g}: {exc}); give period=") from None
    tried = set()
    for j in body_angles(mech):
        rate = abs(float(s.qd[j]))
        if not rate > 1e-12:
            continue
        period = 2 * math.pi / rate
        key = round(period, 9)
        if key in tried:
            continue
        tried.add(key)
        try:
            sw = mech.sweep(t0, t0 + period, 65, level="velocity")
        except MechgenError:
            continue
        if np.all(sw.status == OK) and one_cycle(sw):
            return period
    raise MechgenError(f"fit: '{mech.name}' with its parameters {mech.parameters} does not "
                       f"move through a closed cycle from t={t0:.6g} that a body's turn "
                       "measures; give period= (the time of one cycle of its drivers)")
