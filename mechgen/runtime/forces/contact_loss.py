"""Where a cam follower loses contact over a sweep (``sw.contact_lost(name)``): the points
at which the contact force (mechgen.runtime.forces.contact) would have to pull, the
intervals they form and the first time contact is lost, each crossing of zero refined by
solving the mechanism between the sweep's points (scipy's brentq, imported there, as
runtime.events does)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import MechgenError
from ..kinematics.solving import sweep
from .contact import CAM_KINDS
from .lookup import tables
from .solution import force_solve

PULL_RTOL = 1e-12      # a force below −PULL_RTOL × its largest size pulls (not rounding)


@dataclass(frozen=True, eq=False)
class ContactLoss:
    """Where constraint ``name``'s contact force pulls over a sweep: ``mask`` (per point),
    ``times`` (the sweep's times there), ``first`` (the first time the force reaches zero
    going negative; the sweep's start if it pulls there already; None if it never pulls),
    ``intervals`` ((t_lost, t_regained) pairs, t_regained None where it still pulls at
    the sweep's end; each end between two points refined by solving there) and
    ``minimum`` ((t, force) of the least force). True when contact is lost somewhere."""

    name: str
    t: np.ndarray
    force: np.ndarray
    mask: np.ndarray
    first: float | None
    intervals: tuple

    def __bool__(self):
        return bool(self.mask.any())

    @property
    def lost(self) -> bool:
        return bool(self)

    @property
    def times(self) -> np.ndarray:
        return self.t[self.mask]

    @property
    def minimum(self) -> tuple:
        if not np.any(np.isfinite(self.force)):
            return (None, np.nan)
        k = int(np.nanargmin(self.force))
        return (float(self.t[k]), float(self.force[k]))

    def __repr__(self):
        if not self:
            t, f = self.minimum
            return f"<ContactLoss {self.name!r}: contact kept (least force {f:.6g} at t={t})>"
        return (f"<ContactLoss {self.name!r}: lost at {int(self.mask.sum())} point(s), first "
                f"at t={self.first:.10g}, intervals {list(self.intervals)}>")


def pulling(force) -> np.ndarray:
    """Where a contact force pulls: below −PULL_RTOL times its largest size."""
    force = np.asarray(force, dtype=float)
    size = np.nanmax(np.abs(force), initial=0.0) if force.size else 0.0
    with np.errstate(invalid="ignore"):
        return force < -PULL_RTOL * size


def _linear_zero(t0, t1, f0, f1):
    return float(t0 + (t1 - t0) * f0 / (f0 - f1)) if f0 != f1 else float(t0)


def _refine(sw, name, k, f0, f1):
    """The time between points k and k + 1 where the contact force (f0 there, f1 at k + 1,
    of opposite signs) reaches zero: brentq on the force at each time, its configuration
    reached by the module's careful continuation from the nearer point (on the sweep's
    assembly mode: one Newton from a guess between the points may fall into the other one
    near a toggle), the linear estimate where a solve fails."""
    from scipy.optimize import brentq
    mech, t0, t1 = sw.mechanism, float(sw.t[k]), float(sw.t[k + 1])
    state = mech.state
    q0, q1 = sw.Q[k], sw.Q[k + 1]
    last = state.last

    def force(t):
        if t == t0:
            return f0
        if t == t1:
            return f1
        tn, qn = (t0, q0) if abs(t - t0) <= abs(t - t1) else (t1, q1)
        q = sweep(state, tn, t, 2, guess=qn).Q[1]
        with state.lock:
            return force_solve(mech, t, sw.force_level, guess=q).contact(name)

    try:
        return float(brentq(force, t0, t1, xtol=1e-14 * max(1.0, abs(t0), abs(t1)),
                            rtol=4 * np.finfo(float).eps))
    except (MechgenError, ValueError):   # a solve that fails, or no change of sign
        return _linear_zero(t0, t1, f0, f1)
    finally:
        state.last = last


def contact_loss(sw, name) -> ContactLoss:
    """``sw.contact_lost(name)`` for a cam constraint of the sweep ``sw``."""
    mech = sw.mechanism
    label = _cam_label(mech, name)
    force = sw.contact(label)
    mask = pulling(force)
    t = np.asarray(sw.t, dtype=float)
    intervals, first = [], None
    k = 0
    n = len(t)
    while k < n:
        if not mask[k]:
            k += 1
            continue
        j = k
        while j + 1 < n and mask[j + 1]:
            j += 1
        start = float(t[k]) if k == 0 or not np.isfinite(force[k - 1]) else \
            _refine(sw, label, k - 1, force[k - 1], force[k])
        end = None if j + 1 >= n else float(t[j + 1]) if not np.isfinite(force[j + 1]) \
            else _refine(sw, label, j, force[j], force[j + 1])
        if first is None:
            first = start
        intervals.append((start, end))
        k = j + 1
    return ContactLoss(label, t, force, mask, first, tuple(intervals))


def _cam_label(mech, name):
    label = tables(mech).constraint(name, mech)[0]
    kind = next(k for _, k, lab, _, _ in mech.module.CONSTRAINTS if lab == label)
    if kind not in CAM_KINDS:
        raise ValueError(f"contact_lost: constraint {label!r} of model '{mech.name}' is a "
                         f"{kind}, not a cam contact ({', '.join(CAM_KINDS)}): only a cam's "
                         "follower can lose contact")
    return label
