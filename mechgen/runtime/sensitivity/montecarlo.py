"""The Monte Carlo band of mech.tolerance (method="montecarlo"): the exact, nonlinear
answer over random designs.

Each of ``samples`` designs draws every tolerance uniformly in its interval (the
parameter's value plus low .. high) and every clearance's offset e uniformly in its disc
(radius c·√u, angle 2πv: uniform in area). The tolerances make a design table of listed
designs (``mech.design_sweep(..., params={name: values}, grid=False)``) at the result's
own times, started from the result's first configuration (its assembly mode) on
``backend`` ("cpu", "dask", "cuda"); the clearances then move each design's points onto
Φ(q) = E·e by Newton (mechgen.runtime.sensitivity.clearance.correct, compiled).

A design counts only where it was solved at every time, reached none by a branch jump or
through a singular configuration (it may be on another assembly mode) and, with
clearances, converged at every point; the others are left out and counted. Values of a
name over the designs kept: coordinates and their rates read off the arrays, declared
outputs and points by the module's compiled eval_outputs / eval_points per design with
its parameters, a driver's effort (a result at a force level) by the table, a symbolic
quantity by mech.evaluate on each design's own sweep (slow: a sympy-evaluated expression
per design).
"""
from __future__ import annotations

import numbers

import numpy as np

from ...errors import MechgenError
from ...protocol import JUMP, THROUGH_SINGULAR
from ..quantity import Quantity
from ..results import Solution, Sweep
from .clearance import correct, offsets_of

SAMPLES = 10_000


class Samples:
    """The designs of a Monte Carlo band: ``P`` (designs × parameters), ``E`` (designs ×
    2 clearances' offsets, x then y of each), their points ``Q``, ``QD``, ``QDD`` (designs ×
    times × coordinates), ``ok`` (the designs kept); ``count``, ``used``, ``failed`` and
    ``reasons`` ({why: count})."""

    def __init__(self, mech, ts, level, force_level, P, E, Q, QD, QDD, ok, reasons, seed,
                 table=None):
        self.mechanism, self.ts, self.level, self.force_level = mech, ts, level, force_level
        self.P, self.E, self.Q, self.QD, self.QDD = P, E, Q, QD, QDD
        self.ok, self.reasons, self.seed, self.table = ok, reasons, seed, table
        self.count = int(P.shape[0])
        self.used = int(ok.sum())
        self.failed = self.count - self.used

    def why(self) -> str:
        return ", ".join(f"{k} {v}" for k, v in self.reasons.items() if v) or "none"

    def values(self, name, point=None) -> np.ndarray:
        """``name`` at every time of every design kept: (used, times) (a vector quantity:
        a last axis)."""
        mech, used = self.mechanism, np.flatnonzero(self.ok)
        N = len(self.ts)
        if point is not None:
            out = np.empty((N, len(mech.point_names), 2))
            vals = np.empty((used.size, N))
            for i, d in enumerate(used):
                mech.module.eval_points(self.Q[d], self.ts, self.P[d], out)
                vals[i] = out[:, point[0], point[1]]
            return vals
        if isinstance(name, str) and self.force_level is not None and \
                name not in mech.coordinates and self._is_driver(name):
            return self.table.driver(name).reshape(self.count, N)[used]
        quantity = Quantity(mech, name)
        if quantity.kind == "q":
            arr = (self.Q, self.QD, self.QDD)[quantity.order]
            if arr is None:
                quantity.needs(self.level)
            return arr[used, :, quantity.k]
        if quantity.kind == "out":
            quantity.needs(self.level)
            out = np.empty((N, len(mech.outputs)))
            zero = np.zeros((N, mech.n))
            vals = np.empty((used.size, N))
            for i, d in enumerate(used):
                mech.module.eval_outputs(self.Q[d], zero if self.QD is None else self.QD[d],
                                         zero if self.QDD is None else self.QDD[d], self.ts,
                                         self.P[d], quantity.order, out)
                vals[i] = out[:, quantity.k]
            return vals
        return np.stack([np.asarray(mech.evaluate(name, self._sweep(d)), dtype=float)
                         for d in used]) if used.size else np.full((0, N), np.nan)

    def _is_driver(self, name) -> bool:
        from ..forces.lookup import tables
        mech = self.mechanism
        try:
            entry = tables(mech).find(name, mech)
        except ValueError:
            return False
        return entry is not None and bool(entry[2])

    def _sweep(self, d) -> Sweep:
        """Design d as a Sweep of a mechanism with its parameters."""
        mech = self.mechanism
        other = mech.with_params(**dict(zip(mech.parameter_names, self.P[d].tolist())))
        return Sweep(other, self.ts.copy(), self.Q[d], None if self.QD is None else self.QD[d],
                     None if self.QDD is None else self.QDD[d])


def _count(samples) -> int:
    if isinstance(samples, bool) or not isinstance(samples, numbers.Integral) or samples < 1:
        raise MechgenError(f"samples must be a positive integer, got {samples!r}")
    return int(samples)


def draw(mech, tols, clears, count, seed):
    """(P, E): the designs' parameters (count × parameters) and offsets (count × 2
    clearances), drawn by numpy's default generator from ``seed``."""
    rng = np.random.default_rng(seed)
    P = np.tile(np.asarray(mech.p, dtype=np.float64), (count, 1))
    for name, (lo, hi) in tols.items():
        j = mech.parameter_names.index(name)
        P[:, j] += rng.uniform(lo, hi, count)
    E = np.empty((count, 2 * len(clears)))
    for i, (c, _) in enumerate(clears.values()):
        r = c * np.sqrt(rng.uniform(0.0, 1.0, count))
        a = rng.uniform(0.0, 2 * np.pi, count)
        E[:, 2 * i], E[:, 2 * i + 1] = r * np.cos(a), r * np.sin(a)
    return P, E


def run(mech, result, tols, clears, samples=SAMPLES, seed=None, backend="cpu", workers=None,
        client=None) -> Samples:
    """The Monte Carlo designs of a band over ``result`` (a Sweep or a Solution of ``mech``)."""
    count = _count(samples)
    single = isinstance(result, Solution) or not hasattr(result, "Q")
    ts = np.array([result.t], dtype=float) if single else np.asarray(result.t, dtype=float)
    q0 = np.asarray(result.q if single else result.Q[0], dtype=float)
    force_level = result.__dict__.get("force_level", getattr(type(result), "force_level", None))
    if force_level is not None and clears:
        raise MechgenError("a Monte Carlo band with clearances is of a kinematic sweep or "
                           "solution (solve again without level='static'/'dynamic')")
    have = result.level if isinstance(result.level, str) else "position"
    P, E = draw(mech, tols, clears, count, seed)
    reasons = {"not solved at every time": 0, "branch jump or singular": 0,
               "clearance did not converge": 0}
    table = None
    N = ts.shape[0]
    if tols:
        params = {name: P[:, mech.parameter_names.index(name)] for name in tols}
        table = mech.design_sweep(ts[0], ts[-1], N, params, times=ts, grid=False,
                                  level=force_level or have, guess=q0, on_fail="ignore",
                                  backend=backend, workers=workers, client=client)
        Q, QD, QDD = table.Q, table.QD, table.QDD
        done = np.asarray(table.done).reshape(-1) == N
        status = np.asarray(table.status).reshape(-1)
        flagged = done & np.isin(status, (JUMP, THROUGH_SINGULAR))
        reasons["not solved at every time"] = int((~done).sum())
        reasons["branch jump or singular"] = int(flagged.sum())
        ok = done & ~flagged
    else:       # the clearances alone: every design starts from the result's points
        if backend != "cpu" or workers is not None or client is not None:
            raise MechgenError("backend=, workers= and client= run the tolerances' design "
                               "table: give a tolerance, or leave them out")
        rows = (result.q[None], result.qd, result.qdd) if single else \
            (result.Q, result.QD, result.QDD)
        Q, QD, QDD = (None if a is None else
                      np.ascontiguousarray(np.broadcast_to(np.reshape(a, (N, mech.n)),
                                                           (count, N, mech.n)))
                      for a in rows)
        ok = np.ones(count, dtype=bool)
    if clears:
        Q, QD, QDD = (None if a is None else np.ascontiguousarray(a, dtype=np.float64)
                      for a in (Q, QD, QDD))
        before = ok.copy()
        OFF = offsets_of(mech, [rows for _, rows in clears.values()], E)
        level = 0 if QD is None else 1 if QDD is None else 2
        correct(mech, ts, P, OFF, level, Q, QD, QDD, ok)
        reasons["clearance did not converge"] = int((before & ~ok).sum())
    if not ok.any():
        said = ", ".join(f"{k} {v}" for k, v in reasons.items() if v)
        raise MechgenError(f"every one of the {count} Monte Carlo samples of '{mech.name}' "
                           f"failed ({said}): the tolerances reach designs that do not "
                           "assemble over these times")
    return Samples(mech, ts, 0 if QD is None else 1 if QDD is None else 2, force_level,
                   P, E, Q, QD, QDD, ok, reasons, seed, table)
