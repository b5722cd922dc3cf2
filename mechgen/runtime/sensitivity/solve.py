"""dq/dp, dq̇/dp, dq̈/dp at a solved point and along a sweep, by the sensitivity module's
compiled block solve (companion.py); a module with more equations than coordinates (a
redundant build) by least squares on Φ_q, its rows consistent.

A point where Φ_q has lost rank has no derivatives: a single solve raises SingularError,
a sweep gives NaN there and lists the times (``sw.sensitivity_singular``).
"""
from __future__ import annotations

import weakref

import numpy as np

from ...errors import SolveError
from ...protocol import LEVEL, SING_RTOL
from .companion import companion


class Sensitivities:
    """The derivatives of a result with respect to ``params`` (names, their indices in
    the module's PARAMETERS ``columns``): ``full`` holds (Dq, Dq̇, Dq̈), each of shape
    (coordinates, all parameters) for a solution, (points, coordinates, all parameters)
    for a sweep, NaN in the columns not asked for, None above the result's level;
    ``singular``: per point of a sweep, whether Φ_q had lost rank there (a solution's:
    False, it raised)."""

    __slots__ = ("params", "columns", "full", "singular")

    def __init__(self, params, columns, full, singular=False):
        self.params, self.columns, self.full, self.singular = params, columns, full, singular

    def value(self, result, what, param):
        """∂what/∂param on ``result`` (mechgen.runtime.sensitivity.values)."""
        from .values import sensitivity
        return sensitivity(result, what, param)

    def of_order(self, order):
        """dq (0), dq̇ (1) or dq̈ (2) on the parameters asked for, or None."""
        D = self.full[order]
        return None if D is None else D[..., self.columns]


def parameter_columns(mech, which) -> tuple:
    """(names, indices) of the parameters ``which`` asks for: True (all), a name or a
    list of names."""
    names = list(mech.parameter_names)
    if which is True:
        chosen = names
    elif isinstance(which, str):
        chosen = [which]
    else:
        chosen = list(which)
    if not chosen:
        raise ValueError(f"sensitivities: '{mech.name}' has no parameters"
                         if not names else "sensitivities: no parameter named")
    unknown = [c for c in chosen if c not in names]
    if unknown:
        raise KeyError(f"sensitivities: {', '.join(map(repr, unknown))} "
                       f"{'is' if len(unknown) == 1 else 'are'} not a parameter of "
                       f"'{mech.name}' (its parameters: {', '.join(names) or 'none'})")
    return tuple(dict.fromkeys(chosen)), np.array([names.index(c) for c in dict.fromkeys(chosen)],
                                                  dtype=np.int64)


def _level(qd, qdd) -> int:
    return LEVEL["position"] if qd is None else \
        LEVEL["velocity"] if qdd is None else LEVEL["acceleration"]


_PLANS = {}     # (id(module), which) -> (weak reference to the module, _plan's answer)
_LAST = [None, None, None, None]    # the last call's module, which, a copy of it, its plan


def _plan(mech, which) -> tuple:
    """(companion, Blocks, names, columns) of the parameters ``which`` on ``mech``'s
    module: looked up once per module and question (a single solve's derivatives cost
    about a microsecond; finding them again would cost half as much), the last one
    answered at once (the same module, and ``which`` the same object, still equal)."""
    module = mech.module
    last = _LAST
    if module is last[0] and which is last[1] and which == last[2]:
        return last[3]
    key = (id(module), which if which is True or which.__class__ is str else tuple(which))
    hit = _PLANS.get(key)
    if hit is not None and hit[0]() is module:
        plan = hit[1]
    else:
        comp, blocks = companion(mech)
        plan = (comp, blocks) + parameter_columns(mech, which)
        _PLANS[key] = (weakref.ref(module), plan)
    if which is True or which.__class__ in (str, tuple, list):
        last[:] = (module, which, which[:] if which.__class__ is list else which, plan)
    return plan


def of_solution(mech, sol, which) -> Sensitivities:
    """The sensitivities of a Solution; SingularError where Φ_q has lost rank."""
    comp, blocks, names, cols = _plan(mech, which)
    qd, qdd = sol.qd, sol.qdd
    if qd is None:
        level, qd, qdd = 0, blocks.zero, blocks.zero
    elif qdd is None:
        level, qdd = 1, blocks.zero
    else:
        level = 2
    D = np.empty(blocks.shape)
    if blocks.square:
        status = comp.sensitivities_at(sol.q, qd, qdd, sol.t, mech.p, level, cols, D,
                                       blocks.packed, blocks.scratch)
    else:
        D[:] = np.nan
        status = _least_squares(comp, mech, sol.q, qd, qdd, sol.t, mech.p, level, cols, D)
    if status != 0:
        from ..analysis.locks import singular_error
        raise singular_error(mech, sol.t, sol.q, "parameter derivatives")
    return Sensitivities(names, cols, (D[0], D[1] if level else None,
                                       D[2] if level == 2 else None), False)


def _least_squares(comp, mech, q, qd, qdd, t, p, level, cols, D) -> int:
    """The chain on a redundant build: each right side must lie in Φ_q's range."""
    J = np.empty((mech.m, mech.n))
    B = np.empty((mech.m, len(mech.parameter_names)))
    comp.phi_q(q, t, p, J)
    scale = np.abs(J).sum(axis=1, keepdims=True)
    scale[scale == 0] = 1.0
    Js = J / scale
    u, s, vt = np.linalg.svd(Js, full_matrices=False)
    if s.size == 0 or s[-1] <= SING_RTOL * s[0] or s.size < mech.n:
        return 2

    def solve(rhs, out):
        x = vt.T @ ((u.T @ (rhs / scale)) / s[:, None])
        if np.max(np.abs(Js @ x - rhs / scale), initial=0.0) > 1e-8 * (1 + np.max(np.abs(x))):
            raise SolveError(f"the redundant constraints of '{mech.name}' disagree at "
                             f"t={t:.10g} once a parameter moves: its derivatives do not exist")
        out[:, cols] = x[:, cols]

    comp.phi_p(q, t, p, B)
    solve(-B, D[0])
    if level >= 1:
        comp.velocity_rhs_p(q, qd, t, p, D[0], cols, B)
        solve(B, D[1])
    if level >= 2:
        comp.acceleration_rhs_p(q, qd, qdd, t, p, D[0], D[1], cols, B)
        solve(B, D[2])
    return 0


def of_sweep(mech, sw, which) -> Sensitivities:
    """The sensitivities along a Sweep (NaN, and flagged, where Φ_q has lost rank)."""
    names, cols = parameter_columns(mech, which)
    comp, blocks = companion(mech)
    N, n, npar = len(sw), mech.n, len(mech.parameter_names)
    level = _level(sw.QD, sw.QDD)
    Q = np.ascontiguousarray(sw.Q, dtype=np.float64)
    QD = np.ascontiguousarray(sw.QD) if level >= 1 else np.zeros((1, n))
    QDD = np.ascontiguousarray(sw.QDD) if level >= 2 else np.zeros((1, n))
    # every selected column of every point is written (a value, or NaN where singular):
    # others are NaN; with all of them selected, the memory is touched once (it is several
    # times the sweep's own: writing it is much of what the derivatives cost)
    blank = np.empty if len(cols) == npar else (lambda shape: np.full(shape, np.nan))
    DQ = blank((N, n, npar))
    DQD = blank((N if level >= 1 else 1, n, npar))
    DQDD = blank((N if level >= 2 else 1, n, npar))
    status = np.zeros(N, dtype=np.int64)
    ts = np.ascontiguousarray(sw.solved_t, dtype=np.float64)
    p = np.asarray(mech.p, dtype=np.float64)
    if blocks.square:
        comp.sensitivities_rows(ts, Q, QD, QDD, np.asarray(p, dtype=np.float64), level,
                                blocks.brow, blocks.bvar,
                                blocks.bstart, cols, DQ, DQD, DQDD, status)
    else:
        for k in range(N):
            D = [DQ[k], DQD[k if level >= 1 else 0], DQDD[k if level >= 2 else 0]]
            try:
                status[k] = _least_squares(comp, mech, Q[k], QD[k if level >= 1 else 0],
                                           QDD[k if level >= 2 else 0], ts[k], p, level,
                                           cols, D)
            except SolveError:
                status[k] = 2
            if status[k]:
                for d in D:
                    d[:, cols] = np.nan
    singular = status != 0
    return Sensitivities(names, cols, (DQ, DQD if level >= 1 else None,
                                       DQDD if level >= 2 else None), singular)
