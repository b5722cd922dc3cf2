"""Exact extremes of a quantity for every design of a design table (``tab.extremes("X4")``):
the table's grid minimum and maximum of each design, refined on the quantity's time
derivative. Each value off the grid comes from the module's careful continuation (its
step control and branch tests) from the design's nearest grid point, so that it stays on
the design's assembly mode: near a toggle, where the two modes lie close, one Newton from
a Taylor predictor falls into the other one. The root of the derivative is found by
Brent's method in each grid interval next to the grid extreme where the derivative changes
sign (and in the interval at the other end, for a grid extreme at an end of the range: the
first and last points of a closed cycle are one configuration). A refined value is kept
only where it is at least as extreme as the grid's; else the grid value stands (an extreme
at an end of the range stays there). A module with stages refines by Newton's method from
Taylor predictors, each step a compiled solve. numpy and scipy.optimize.brentq.
"""
from __future__ import annotations

import numpy as np

from ...errors import MechgenError
from ...protocol import OK, REPORT_SIZE, STATUS_CODE, STATUS_COLUMNS
from ..kinematics.entry import module_attr
from .reduce import COORDINATE, DRIVER, Reduction, reduce_chunk, reduce_slots

NEWTON_STEPS = 12
T_TOL = 1e-14           # relative to the table's time span


def extremes(tab, name) -> Reduction:
    """The exact minimum and maximum of ``name`` per design, and their times (see the
    module's docstring); NaN for a design that solved no time. Needs a table that kept
    its points, and a quantity whose second time derivative the module computes."""
    tab._need_points(f"tab.extremes({name!r})")
    mech = tab.mechanism
    module = mech.module
    _, slots = reduce_slots(mech, [name], tab._have, tab.force_level)
    kind, index, order = (int(v) for v in slots[0])
    if kind == DRIVER:
        raise MechgenError(f"tab.extremes({name!r}): a driver's effort is not refined off the "
                           "time grid (it has no time derivatives in the module); its extremes "
                           f"on the grid are tab.reduced({name!r})")
    need = order + 2 if kind == COORDINATE else mech.output_orders[index] + order + 2
    if need > 2 or mech.built_level < 2:
        raise MechgenError(f"tab.extremes({name!r}) refines with the second time derivative of "
                           f"{name!r}, which this module does not compute (a module built to "
                           "acceleration level refines a coordinate or an output of order 0)")
    mn, mx, tmn, tmx = (arr[:, 0] for arr in reduce_chunk(module, slots, tab.t, tab.P, tab.Q,
                                                          tab.QD, tab.QDD, tab.done))
    ts = tab.t
    out = [mn.copy(), mx.copy(), tmn.copy(), tmx.copy()]
    span = abs(ts[-1] - ts[0]) if len(ts) > 1 else 1.0
    probe = _Probe(mech, kind, index, order)
    staged = bool(module_attr(module, "SWITCH_TIMES", ()))
    for d in np.nonzero(tab.done > 0)[0]:
        for j, (value, t_at, sign) in enumerate(((mn[d], tmn[d], 1.0), (mx[d], tmx[d], -1.0))):
            k = int(np.searchsorted(ts, t_at)) if ts[0] <= ts[-1] else int(np.argmin(np.abs(ts - t_at)))
            k = min(max(k, 0), len(ts) - 1)
            last = int(tab.done[d]) - 1
            if staged:
                lo = ts[max(k - 1, 0)]
                hi = ts[min(k + 1, last)]
                found = [probe.newton(tab, d, k, min(lo, hi), max(lo, hi), span)]
            else:
                found = [probe.brent(tab, d, a, span) for a in _brackets(k, last)]
            for got in found:
                if got is not None and sign * (got[1] - value) <= 0.0:
                    value = got[1]
                    out[j][d], out[j + 2][d] = got[1], got[0]
    shape = tab.shape
    return Reduction(name, *(arr.reshape(shape) for arr in out), tab.ok, tab.status)


def _brackets(k, last):
    """The first points of the grid intervals where an extreme at grid point k may lie
    (points 0..last solved): the two around it, and at an end of the range the interval
    at the other end too."""
    out = [a for a in (k - 1, k) if 0 <= a < last]
    if last >= 1 and k in (0, last):
        other = last - 1 if k == 0 else 0
        if other not in out:
            out.append(other)
    return out


class _Probe:
    """The quantity and its first two time derivatives at (t, design), solved."""

    def __init__(self, mech, kind, index, order):
        self.mech, self.kind, self.index, self.order = mech, kind, index, order
        n = mech.n
        self.q, self.qd, self.qdd = np.empty(n), np.empty(n), np.empty(n)
        self.info = np.zeros(8)
        self.out = np.empty(max(len(mech.outputs), 1))
        # the two-point careful sweep of at(): times, rows, status, report
        self.ts = np.empty(2)
        self.rows = (np.empty((2, n)), np.empty((2, n)), np.empty((2, n)))
        self.status = np.zeros((2, STATUS_COLUMNS), dtype=np.int16)
        self.report = np.zeros(REPORT_SIZE)

    def at(self, tab, d, k, t):
        """Solve q, qd, qdd of design d at t by the module's careful continuation from its
        grid point k (on its assembly mode); False where it fails, jumps or passes a
        singular configuration."""
        mech = self.mech
        self.ts[0], self.ts[1] = tab.t[k], t
        Q, QD, QDD = self.rows
        done = mech.module.sweep(self.ts, tab.Q[d, k].copy(), tab.P[d], 2, mech.tol,
                                 mech.xtol, mech.maxit, mech.state.method_of(None), Q, QD, QDD,
                                 self.status, self.report)
        if done != 2 or self.status[:, STATUS_CODE].any():
            return False
        self.q[:], self.qd[:], self.qdd[:] = Q[1], QD[1], QDD[1]
        return True

    def brent(self, tab, d, a, span):
        """(t, value) of the root of the derivative in grid interval (a, a + 1) of design d,
        where it changes sign there, else None; each value by at() from the nearer end."""
        from scipy.optimize import brentq
        p = tab.P[d]
        ta, tb = float(tab.t[a]), float(tab.t[a + 1])

        def derivative(t):
            k = a if abs(t - ta) <= abs(t - tb) else a + 1
            if not self.at(tab, d, k, t):
                raise _Lost
            return self.values(t, p)[1]

        try:
            fa, fb = derivative(ta), derivative(tb)
            if not (np.isfinite(fa) and np.isfinite(fb)) or fa * fb > 0.0:
                return None
            t = ta if fa == 0.0 else tb if fb == 0.0 else \
                brentq(derivative, min(ta, tb), max(ta, tb), xtol=T_TOL * span,
                       rtol=4 * np.finfo(float).eps, maxiter=200)
            derivative(t)
        except (_Lost, ValueError, RuntimeError):
            return None
        return float(t), float(self.values(t, p)[0])

    def values(self, t, p):
        """(value, first, second derivative) at the solved q, qd, qdd."""
        if self.kind == COORDINATE:
            arrs = (self.q, self.qd, self.qdd)
            i, o = self.index, self.order
            return arrs[o][i], arrs[o + 1][i], arrs[o + 2][i]
        mod = self.mech.module
        vals = []
        for fn in (mod.outputs, mod.outputs_d, mod.outputs_dd)[self.order:self.order + 3]:
            fn(self.q, self.qd, self.qdd, t, p, self.out)
            vals.append(float(self.out[self.index]))
        return tuple(vals)

    def newton(self, tab, d, k, lo, hi, span):
        """(t, value) of the root of the derivative in [lo, hi] from the grid point k of
        design d, or None when Newton fails or leaves the interval."""
        mech, mod = self.mech, self.mech.module
        p = tab.P[d]
        t = float(tab.t[k])
        tk = t
        meth = mech.state.method_of(None)
        for _ in range(NEWTON_STEPS):
            h = t - tk          # Taylor from the grid point, as far as the table holds
            self.q[:] = tab.Q[d, k]
            if tab._have >= 1:
                self.q += h * tab.QD[d, k]
            if tab._have >= 2:
                self.q += 0.5 * h * h * tab.QDD[d, k]
            status = mod.solve_point_derivatives(self.q, t, p, mech.tol, mech.xtol, mech.maxit,
                                                 meth, 2, self.qd, self.qdd, self.info)
            if status != OK:
                return None
            value, f, df = self.values(t, p)
            if not (np.isfinite(f) and np.isfinite(df)) or df == 0.0:
                return None
            step = f / df
            t_new = t - step
            if not lo <= t_new <= hi:
                return None
            if abs(t_new - t) <= T_TOL * span:
                status = mod.solve_point_derivatives(self.q, t_new, p, mech.tol, mech.xtol,
                                                     mech.maxit, meth, 2, self.qd, self.qdd,
                                                     self.info)
                return (t_new, self.values(t_new, p)[0]) if status == OK else None
            t = t_new
        return None


class _Lost(Exception):
    """The careful continuation could not reach a time inside the bracket."""
