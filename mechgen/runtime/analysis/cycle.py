"""Whether a sweep covers exactly one period of its motion (a full turn of a periodic
driver), so that its ends are one configuration and events may wrap through them.

A sweep from t0 to t1 = t0 + P is one cycle when the constraint equations repeat with
period P up to a shift s of whole turns in some angles (Φ(q + s, t + P) = Φ(q, t) for
every q and t: each driver is P-periodic, a driven angle gains whole turns) and the
sweep's last configuration is its first shifted by s. Both are tested numerically on the
module's own Φ, so any driver expression is covered without the runtime reading it.

numpy only.
"""
from __future__ import annotations

import math

import numpy as np

TWO_PI = 2.0 * math.pi


def _shift(q0, q1):
    """The shift s = q1 − q0 when every coordinate returns to its start or moves by whole
    turns, else None."""
    d = q1 - q0
    if not (np.all(np.isfinite(d))):
        return None
    turns = np.round(d / TWO_PI)
    s = turns * TWO_PI
    tol = 1e-7 * (1.0 + np.abs(q0) + np.abs(q1))
    if np.any(np.abs(d - s) > tol):
        return None
    return s


def _phi_repeats(mech, q, s, t0, period) -> bool:
    """Φ(q + s, t + P) = Φ(q, t) at a few q near the sweep's start and a few t."""
    m = mech.m
    r0, r1 = np.empty(m), np.empty(m)
    n = q.shape[0]
    for trial in range(3):
        qt = q + 0.05 * (trial + 1) * np.cos(np.arange(n) * 1.3 + trial)
        tt = t0 + period * (0.0, 0.29, 0.71)[trial]
        mech.module.phi(qt, tt, mech.p, r0)
        mech.module.phi(qt + s, tt + period, mech.p, r1)
        if not (np.all(np.isfinite(r0)) and np.all(np.isfinite(r1))):
            return False
        if np.max(np.abs(r1 - r0)) > 1e-9 * (1.0 + np.max(np.abs(r0))):
            return False
    return True


def one_cycle(sw) -> bool:
    """True when the sweep ``sw`` covers exactly one period of a periodic motion: its last
    point is its first one period later (modulo whole turns of the angles) and the
    equations repeat with that period."""
    cached = getattr(sw, "_one_cycle", None)
    if cached is not None:
        return cached
    result = False
    t = np.asarray(sw.t, dtype=np.float64)
    if t.shape[0] >= 3 and t[-1] != t[0]:
        Q = np.asarray(sw.Q, dtype=np.float64)
        s = _shift(Q[0], Q[-1])
        if s is not None:
            ok = True
            if sw.QD is not None:       # the velocities repeat too (a cheap first test)
                dv = np.abs(sw.QD[-1] - sw.QD[0])
                ok = bool(np.all(dv <= 1e-7 * (1.0 + np.abs(sw.QD[0]))))
            result = ok and _phi_repeats(sw.mechanism, Q[0], s, float(t[0]),
                                         float(t[-1] - t[0]))
    try:
        sw._one_cycle = result
    except AttributeError:
        pass
    return result
