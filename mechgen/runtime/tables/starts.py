"""Where each design of a table starts: on the assembly mode of the guess, carried to the
design's parameters (the module's carry_designs and walk_designs, on threads), and what the table's
results say of a design whose start could not be carried.

The reference is a mechanism's guess, a configuration at its time (``guess_t``) for its
parameters (``guess_p``; mechgen.runtime.kinematics.follow): each design moves from there to its
parameters at that time, then to the table's first time, as ``mech.with_params(...).
sweep(...)`` of that design starts. A table's ``guess=`` makes that mechanism a copy whose
guess it is, at the table's first time with the mechanism's parameters (guess_reference).
A design whose parameters the mode cannot be carried to (a singular configuration on the
way, or parameters at which it does not assemble) starts from the guess itself, as a
table of Mech's does, and is flagged (its first point JUMP or THROUGH_SINGULAR: a
BranchJumpWarning, and mech.optimize rejects it); one that cannot reach the table's first
time from the guess's is not solved (the status of the solve that failed on the way).
"""
from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from ...errors import MechgenError
from ...protocol import JUMP, OK, POINT_INFO_SIZE, STATUS_CODE, THROUGH_SINGULAR
from ..kinematics.entry import module_attr, solve_point
from ..kinematics.follow import CELL, follow
from ..kinematics.guesses import turned_home
from ..results import Solution
from .backends import cpu_count

CHUNK = 4096            # designs a thread carries in one call


def guess_reference(mech, t0, guess):
    """The mechanism whose guess a table's designs start from: ``mech``, or with
    ``guess=`` a copy whose guess is that one, a configuration at the table's first time
    ``t0`` (a Solution: one at its own time, its mode carried to t0) for mech's
    parameters. Its ``with_params`` is a design's mechanism on the mode the table gave it
    (DesignTable.sweep, mech.optimize's result)."""
    if guess is None:
        return mech
    ref = mech.with_params()
    if isinstance(guess, Solution):     # a configuration at its own time, carried to t0
        ref.set_guess(guess)
    else:
        ref.set_guess(guess, t=float(t0))
    return ref


def design_starts(mech, ts, P, tol, maxit, meth, workers=None, followed=False):
    """(Q0, S0): each design's start vector (designs × coordinates), from ``mech``'s guess
    (guess_reference), and its start status (int64: OK, JUMP, THROUGH_SINGULAR or the
    status of a failed way; see the module's docstring). ``followed``: the guess's mode
    followed to the table's first time at the guess's parameters first (runtime.kinematics.follow),
    as for stages, and where the module's way there divides by zero (the rate of sqrt(T)
    at T = 0, the guess's time): then each design is carried at that time alone."""
    try:
        return _starts(mech, ts, P, tol, maxit, meth, workers, followed)
    except ZeroDivisionError:
        if followed or float(mech.guess_t) == float(ts[0]):
            raise
        return _starts(mech, ts, P, tol, maxit, meth, workers, True)


def _starts(mech, ts, P, tol, maxit, meth, workers, followed):
    D, n = P.shape[0], mech.n
    mod = mech.module
    t_ref, p_ref, g = float(mech.guess_t), mech.guess_p, mech.guess.copy()
    start = module_attr(mod, "start_designs")
    q = g.copy()
    if start is not None and D and t_ref != float(ts[0]) and \
            (followed or module_attr(mod, "SWITCH_TIMES", ())):
        # stages: the guess's mode followed to the table's first time at the guess's
        # parameters (stage by stage: runtime.kinematics.follow), then carried to each design there
        ref = quiet_params(mech, dict(zip(mech.parameter_names, map(float, p_ref))))
        try:
            g = follow(ref.state, float(ts[0]), tol, maxit, meth, what="the table's start")
        except MechgenError:
            return np.tile(g, (D, 1)), np.zeros(D, dtype=np.int64)
        q, t_ref = g.copy(), float(ts[0])
    if start is None or D == 0 or solve_point(mod, q, t_ref, p_ref, tol, mech.xtol, maxit,
                                              meth, np.zeros(POINT_INFO_SIZE)) != OK:
        # no mode to carry (the guess does not assemble where it was given): every design
        # from the guess, as Mech's Table[SetGuess[]; SolveMech[...]] does
        return np.tile(g, (D, 1)), np.zeros(D, dtype=np.int64)
    if turned_home(mech, q, g):     # the angles near the guess's, as solve(t) keeps them
        solve_point(mod, q, t_ref, p_ref, tol, mech.xtol, maxit, meth,
                    np.zeros(POINT_INFO_SIZE))
    tw = _way(t_ref, float(ts[0]))
    Q0 = np.empty((D, n))
    S0 = np.zeros(D, dtype=np.int64)
    p_ref = np.ascontiguousarray(p_ref, dtype=np.float64)

    carry, walk = module_attr(mod, "carry_designs"), module_attr(mod, "walk_designs")

    def job(a, b):
        if carry is None:       # a module built before the two were split
            start(tw, q, g, p_ref, P[a:b], tol, mech.xtol, maxit, meth, Q0[a:b], S0[a:b])
            return
        # the careful sweep to the table's first time only where it is not the guess's:
        # a table starting there never compiles it
        carry(tw[0], q, g, p_ref, P[a:b], tol, mech.xtol, maxit, meth, Q0[a:b], S0[a:b])
        if tw.shape[0] > 1:
            walk(tw, P[a:b], tol, mech.xtol, maxit, meth, Q0[a:b], S0[a:b])

    spans = [(a, min(D, a + CHUNK)) for a in range(0, D, CHUNK)]
    threads = 1 if getattr(mod, "__mechgen_tier__", "compiled") == "python" else \
        min(len(spans), workers or cpu_count())
    if threads <= 1:
        for a, b in spans:
            job(a, b)
    else:
        with ThreadPoolExecutor(max_workers=threads) as pool:
            for fut in [pool.submit(job, a, b) for a, b in spans]:
                fut.result()
    return Q0, S0


def _way(t0, t1) -> np.ndarray:
    """The times from the guess's time to the table's first: none between where they are
    one; else steps of at most CELL, as solve(t) follows the motion."""
    if t0 == t1:
        return np.array([t0])
    return np.linspace(t0, t1, max(2, math.ceil(abs(t1 - t0) / CELL) + 1))


def mark_starts(data, S0, N):
    """What each design's start says, put into a backend's results (chunks.TableData):
    a flagged start (JUMP, THROUGH_SINGULAR) marks its design's first point and status
    where they say OK; a failed one leaves its design unsolved (done 0, its status)."""
    if not S0.any():
        return
    flagged = (S0 == JUMP) | (S0 == THROUGH_SINGULAR)
    failed = (S0 != OK) & ~flagged
    if failed.any():
        data.done[failed] = 0
        data.status[failed] = S0[failed]
        if data.INFO is not None and N:
            data.INFO[failed, 0, STATUS_CODE] = S0[failed]
        if data.red is not None:
            for arr in data.red:
                arr[failed] = np.nan
    mark = flagged & (data.done > 0)
    if data.INFO is not None and N:
        first = mark & (data.INFO[:, 0, STATUS_CODE] == OK)
        data.INFO[first, 0, STATUS_CODE] = S0[first]
    worse = mark & (data.status == OK)
    data.status[worse] = S0[worse]


def quiet_params(mech, values):
    """``mech.with_params(**values)`` without asking the symbolic side about cams' contact
    geometry again (Mechanism.with_params warns where it is lost): for the runtime's own
    copies, made in loops (a table's start, the view's redraws and searches)."""
    symbolic, mech.symbolic = mech.symbolic, None
    try:
        other = mech.with_params(**values)
    finally:
        mech.symbolic = symbolic
    other.symbolic = symbolic
    return other
