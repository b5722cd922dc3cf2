"""`mechgen check` over the whole cycle: a driver that cannot turn (a rocker driven as a
crank, a crank too long for its loop) assembles at the time checked and locks later.

The drivers' period comes from the drivers that turn a body at a constant rate (an angle
linear in T: a period of 2π/|rate|); the check follows the configuration from the time
checked through one period in small steps, by the same damped Gauss-Newton that check's
``System`` solves with, and where a step finds no configuration it bisects for the time
the mechanism locks and names it. A model whose drivers do not turn at a constant rate is
said to have been checked at that time only.
"""
from __future__ import annotations

import copy
import math

import numpy as np
import sympy as sp

from ..model.geometry import T

STEPS = 360         # steps over one period (1° of a turning driver's angle)
BISECTIONS = 30     # halvings of the step that fails: the lock's time to ~1e-9 period


def driver_period(model, eq, angles):
    """(period, labels of the turning drivers) of the drivers that turn a body at a
    constant rate (a row whose coordinates are body angles and whose derivative in T is
    a nonzero constant at the parameters' defaults), or (None, ()) when none does. With
    several rates the longest period (the slowest driver's turn) is taken."""
    values = dict(zip(eq.params, model.param_defaults.values()))
    angle_symbols = {eq.q[j] for j in angles}
    coordinates = set(eq.q)
    periods, labels = [], []
    for c in model.drivers:
        for expr in c.exprs:
            expr = sp.sympify(expr).subs(values)
            used = expr.free_symbols & coordinates
            if not used or not used <= angle_symbols:
                continue
            rate = sp.diff(expr, T)
            if rate.free_symbols or not rate.is_number:
                continue
            rate = float(rate)
            if math.isfinite(rate) and rate != 0.0:
                periods.append(2 * math.pi / abs(rate))
                labels.append(c.name or c.label)
    if not periods:
        return None, ()
    return max(periods), tuple(dict.fromkeys(labels))


def _rank_text(system, q) -> str:
    """The scaled smallest singular value of Φ_q at q (how near a lock it is)."""
    s = np.linalg.svd(system(q)[1], compute_uv=False)
    return f"{s[-1] / s[0]:.1e}" if s.size and s[0] > 0 else "0"


def whole_cycle(system, model, eq, q, t, angles, steps=STEPS) -> tuple[list, bool]:
    """(report lines, ok): q (assembled at t) followed through one period of the drivers.
    ok is False where a step finds no configuration: the lines name the time it locks."""
    period, labels = driver_period(model, eq, angles)
    if period is None:
        return [f"  whole cycle: not checked (no driver turns a body at a constant rate): "
                f"the check above holds at t = {t:g} only"], True
    system = copy.copy(system)          # its time changes below; check's stays at t
    span = f"t = {t:g} .. {t + period:g}"
    dt = period / steps
    q = np.array(q, dtype=float)
    for k in range(steps):
        system.t = np.float64(t + (k + 1) * dt)
        qn, _, _, ok = system.solve(q, maxit=30)
        if not ok:
            return _locked(system, q, t + k * dt, dt, period, labels, span), False
        q = qn
    return [f"  whole cycle: assembled at each of {steps} steps over one period of the "
            f"drivers ({span}; turning: {', '.join(labels)})"], True


def _locked(system, q, t_good, dt, period, labels, span) -> list:
    """The lines of a cycle that stops: the time between t_good (q assembled) and
    t_good + dt past which no configuration follows, found by bisection."""
    low, high = t_good, t_good + dt
    for _ in range(BISECTIONS):
        mid = 0.5 * (low + high)
        system.t = np.float64(mid)
        qn, _, _, ok = system.solve(q, maxit=30)
        if ok:
            low, q = mid, qn
        else:
            high = mid
    system.t = np.float64(low)
    return [
        f"  LOCKS at t = {low:.6g} (whole cycle, {span}): the mechanism cannot follow "
        f"{', '.join(labels)} past there (no configuration at t = {high:.6g}; Phi_q's "
        f"scaled smallest singular value {_rank_text(system, q)} at the last one)",
        f"  the driver cannot turn through its whole period ({period:g}): a dead centre, as "
        "of a rocker driven as a crank or a link too long for its loop; drive another "
        "link, change the lengths, or limit the driver's range (--no-cycle checks at -t "
        "only)"]
