"""The defect check of mech.fit: a fitted design passes its k points in one assembly mode
with no singular configuration (no toggle, no branch jump) between them.

The design is swept from the earliest fitted time to the latest, through the fitted
times and ``check_points`` sampled ones, from the configuration least squares found at
the earliest (its mode): every point must be reached with status OK (no JUMP, no
THROUGH_SINGULAR: the careful sweep's branch watch) and, at each fitted time, the sweep
must be at the configuration least squares solved there (the same pose, angles modulo
2π) with the point where it was fitted. A design that passes a point only in the other
mode (a circuit defect), or only beyond a lock (a branch defect), fails one of these.
With timing free, phases more than a cycle apart are first taken modulo the cycle (a
design that turns through a full cycle passes them in one).
"""
from __future__ import annotations

import math
import warnings

import numpy as np

from ...errors import BranchJumpWarning, MechgenError
from ...protocol import JUMP, OK, STATUS_NAMES, THROUGH_SINGULAR
from ..analysis.assembly import angle_coordinates, body_angles, same_pose
from ..results import Solution


class Verdict:
    """The check's answer: ``ok``; ``reason`` (why not, else ""); ``times`` (the fitted
    times as checked: phases taken modulo the cycle where they were spread further);
    ``start`` (the configuration at the earliest of them, a Solution)."""

    __slots__ = ("ok", "reason", "times", "start")

    def __init__(self, ok, reason, times, start):
        self.ok, self.reason, self.times, self.start = ok, reason, times, start


def compact(times, Q, period):
    """Phases spread over more than one cycle taken modulo it into [earliest, earliest +
    period) (their configurations' driven angles turned with them by the module's
    unwrap when solved again); None where they are within a cycle already."""
    lo = float(np.min(times))
    if period is None or float(np.max(times)) - lo < period:
        return None
    return lo + np.mod(times - lo, period)


def check(problem, mech, times, Q, positions) -> Verdict:
    """Whether ``mech`` (the fitted design) passes ``positions`` (k, 2), at ``times``
    in the configurations ``Q`` (k, coordinates), in one mode without a singular
    configuration between them."""
    moved = compact(times, Q, problem.period if problem.free else None)
    if moved is not None:
        try:
            Q = np.array([mech.solve(t, guess=q).q for t, q in zip(moved, Q)])
        except MechgenError as exc:
            return Verdict(False, f"its phases taken modulo the cycle do not solve ({exc})",
                           times, None)
        times = moved
    order = np.argsort(times, kind="stable")
    first = int(order[0])
    start = Solution(mech, float(times[first]), Q[first].copy())
    t0, t1 = float(times[first]), float(times[order[-1]])
    if t1 == t0:
        return _same_time(problem, mech, times, Q, positions, start)
    ts = np.unique(np.concatenate([times, np.linspace(t0, t1, problem.options["check_points"])]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BranchJumpWarning)
        try:
            sw = mech.sweep(t0, t1, None, times=ts, guess=Q[first].copy())
        except MechgenError as exc:
            return Verdict(False, f"a sweep between its fitted times fails: {exc}", times, start)
    bad = np.nonzero(sw.status != OK)[0]
    if bad.size:
        code = int(sw.status[bad[0]])
        what = {JUMP: "a branch jump", THROUGH_SINGULAR: "a singular configuration"}.get(
            code, STATUS_NAMES.get(code, str(code)))
        return Verdict(False, f"between its fitted times it passes {what} at "
                              f"t={float(sw.t[bad[0]]):.6g}", times, start)
    idx = np.searchsorted(sw.t, times)
    points = sw.points()[idx, problem.point]
    return _agree(problem, mech, times, Q, positions, sw.Q[idx], points, start)


def _same_time(problem, mech, times, Q, positions, start):
    """Every fitted time the same: one configuration must pass every target."""
    points = np.array([mech.points_at(q, t)[problem.point] for q, t in zip(Q, times)])
    return _agree(problem, mech, times, Q, positions, Q, points, start)


def _agree(problem, mech, times, Q, positions, swept, points, start):
    same = 1e-7 * (1.0 + problem.scale)
    far = float(np.max(np.abs(points - positions)))
    if not far <= same:
        return Verdict(False, f"swept from its earliest fitted time in one mode, the point "
                              f"misses a fitted position by {far:.3g} (it passes there in "
                              "another assembly mode: a circuit defect)", times, start)
    turns = tuple(sorted(set(angle_coordinates(mech)) | set(body_angles(mech))))
    size = 1e-6 * (1.0 + float(np.max(np.abs(Q))) if Q.size else 1.0)
    for i in range(len(times)):
        if not same_pose(Q[i], swept[i], turns, size):
            return Verdict(False, f"at t={float(times[i]):.6g} the sweep reaches another "
                                  "configuration than least squares fitted (another mode)",
                           times, start)
    return Verdict(True, "", times, start)


def wrap_times(times, t0, period):
    """Times shifted by a common number of cycles so that the earliest lies in
    [t0, t0 + period) (None: as they are)."""
    if period is None:
        return np.asarray(times, dtype=np.float64)
    shift = math.floor((float(np.min(times)) - t0) / period) * period
    return np.asarray(times, dtype=np.float64) - shift
