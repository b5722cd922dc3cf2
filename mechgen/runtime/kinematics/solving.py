"""A solve at one time and a kinematic sweep over many, from a Mechanism's state
(runtime.state): what ``Mechanism.solve`` and ``Mechanism.sweep`` do once their
arguments are checked. They return results (Solution, Sweep) and never call the
Mechanism: the state's ``owner`` is only the handle the results and errors carry."""
from __future__ import annotations

from math import isfinite as _isfinite

import numpy as np

from ...errors import MechgenError
from ...protocol import (ACCELERATION, INFO_ITERATIONS, INFO_METHOD, INFO_RANK, LEVEL, METHOD, OK,
                         POINT_PIVOT, POINT_RESIDUAL, SING_RTOL, VELOCITY)
from .entry import module_attr, solve_acceleration, solve_point as solve_position
from .entry import solve_point_derivatives, solve_velocity
from .follow import at_guess_params, follow, start_at
from ..guards import finite, point_bytes, sweep_count, sweep_times
from .guesses import guess_at, turned_home
from ..results import Solution
from .sweeping import no_points, report_redundancy, run, times as sweep_times_of

_FLOAT64 = np.float64
_METHOD = METHOD      # (name -> index: a valid name looked up, an invalid one checked)
_VELOCITY, _ACCELERATION = LEVEL["velocity"], LEVEL["acceleration"]


def solve(state, t, guess, level, method, tol, maxit, fused=None, lev=None) -> Solution:
    """solve() at a kinematic level; ``fused``: see entry.solve_point_derivatives;
    ``lev``: the level's index where the caller has looked it up (else None)."""
    cls = t.__class__
    if (cls is float or cls is _FLOAT64) and _isfinite(t):
        t = float(t)            # what finite() makes of it, without its call
    else:
        t = finite(t, "t")
    if lev is None:
        lev = state.level_of(level)
    name = state.method if method is None else method
    meth = _METHOD.get(name) if name.__class__ is str else None
    if meth is None:
        meth = state.method_of(name)
    tol = state.tol if tol is None else state.tol_of(tol)
    maxit = state.maxit if maxit is None else state.maxit_of(maxit)
    mech = state.owner
    if guess is None:
        q = follow(state, t, tol, maxit, meth)
        qd, qdd, info = solve_point(state, t, q, lev, meth, tol, maxit, fused)
    else:
        q = guess_at(mech, guess, t)
        start = q.copy()
        qd, qdd, info = solve_point(state, t, q, lev, meth, tol, maxit, fused)
        if turned_home(mech, q, start):
            # Newton from a poor guess may throw an angle whole turns away (1e8 rad,
            # where a float keeps only 1e-8 of it): the same configuration nearer the
            # guess, solved again to full precision
            qd, qdd, info = solve_point(state, t, q, lev, meth, tol, maxit, fused)
    if mech.m > mech.n:
        report_redundancy(state, q, t)
    # a singular position is returned (flagged); its velocity is not determined
    singular = int(info[INFO_RANK]) < mech.n or not info[POINT_PIVOT] >= SING_RTOL
    sol = Solution(mech, t, q, qd, qdd, int(info[INFO_ITERATIONS]), info[POINT_RESIDUAL],
                   singular, "full" if info[INFO_METHOD] else "sorted")
    state.last = sol
    return sol


def solve_point(state, t, q, lev, meth, tol, maxit, fused=None):
    """The position (in place), its checks and the derivatives asked for, as the
    module's solve_point_derivatives makes them, one compiled call per step
    (runtime.kinematics.entry): (qd, qdd, the info row as a list of Python numbers: one call, not a
    numpy scalar a field). ``fused``: see there."""
    info = state.info
    qd = np.empty(q.shape[0]) if lev >= _VELOCITY else None
    qdd = np.empty(q.shape[0]) if lev >= _ACCELERATION else None
    # one small compiled call at a time (runtime.kinematics.entry): a position solve compiles
    # neither the full Newton (unless the sorted solver gives up) nor the derivative passes
    if lev or fused is not None:
        none = state.none
        status = solve_point_derivatives(state.tiers.module, q, t, state.p, tol, state.xtol,
                                         maxit, meth, lev, none if qd is None else qd,
                                         none if qdd is None else qdd, info, fused)
    else:                   # (what solve_point_derivatives does at level position)
        status = solve_position(state.tiers.module, q, t, state.p, tol, state.xtol, maxit,
                                meth, info)
    if status != OK:
        mech = state.owner
        if OK < status < VELOCITY:
            raise convergence_error(mech, status, t, q, info)
        if status >= ACCELERATION:
            raise singular_error(mech, t, q, "acceleration", status=status - ACCELERATION)
        raise singular_error(mech, t, q, "velocity", status=status - VELOCITY)
    return qd, qdd, info.tolist()


def solve_derivatives(state, ts, Q, QD=None, QDD=None, level="velocity"):
    """(QD, QDD) at solved positions Q (rows, at times ts) up to ``level`` (a name or an
    index into LEVELS): the levels not given are solved (linear solves, no Newton
    iteration); a level above the one asked for stays as given. Raises SingularError
    where they are not determined."""
    lev = LEVEL[level] if isinstance(level, str) else int(level)
    meth = state.method_of(None)
    mod, p, N, n = state.module, state.p, len(ts), state.guess.shape[0]
    if lev >= _VELOCITY and QD is None:
        QD = np.empty((N, n))
        for k in range(N):
            if solve_velocity(mod, Q[k], float(ts[k]), p, meth, QD[k]) != OK:
                raise singular_error(state.owner, float(ts[k]), Q[k], "velocity")
    if lev >= _ACCELERATION and QDD is None:
        QDD = np.empty((N, n))
        for k in range(N):
            if solve_acceleration(mod, Q[k], QD[k], float(ts[k]), p, meth, QDD[k]) != OK:
                raise singular_error(state.owner, float(ts[k]), Q[k], "acceleration")
    return QD, QDD


def sweep(state, t0, t1, n, level="position", guess=None, method=None, tol=None, maxit=None,
          times=None, out=None, forces=None, quick=None):
    """One kinematic sweep (Mechanism.sweep without params); ``forces``: a dict that a
    dynamic or static sweep's quick path fills with the multipliers it solved on the
    way (sweeping.compiled), where the module has it; ``quick``: a quick path in place
    of the module's sweep_fast (sweeping.compiled; not in a sweep across stages)."""
    mech = state.owner
    if module_attr(state.module, "SWITCH_TIMES", ()):
        # a model with stages: a sweep across a switch runs stage by stage, each piece
        # this sweep over its own times (which cross no switch)
        from .stages import staged_sweep

        def piece(solved, start):
            return sweep(state, solved[0], solved[-1], len(solved), level, guess=start,
                         method=method, tol=tol, maxit=maxit, times=solved)
        staged = staged_sweep(mech, sweep_times(t0, t1, n, times), guess, piece, tol)
        if staged is not None:
            return staged
    lev = state.levels.get(level) if level.__class__ is str else None
    if lev is None:
        lev = state.level_of(level)
    meth = state.method_of(method)
    shared = times is None and t0.__class__ is float and t1.__class__ is float and \
        n.__class__ is int and n >= 1 and t0 - t0 == 0.0 and t1 - t1 == 0.0
    if shared:
        if n > 1 << 20:
            sweep_count(n, mech.n, lev)         # refused before anything is allocated
        ts = sweep_times_of(t0, t1, n)          # plain numbers: no further checks
    else:
        ts = sweep_times(t0, t1, n, times, each=point_bytes(mech.n, lev))
    tol = state.tol if tol is None else state.tol_of(tol)
    maxit = state.maxit if maxit is None else state.maxit_of(maxit)
    # (a force sweep's quick path is its own: what a large one compiles first)
    kind = "sweep" if forces is None else ("dynamic" if lev >= 2 else "static")
    state.tiers.expect(mech, ts.shape[0], kind)
    if guess is None and ts[0] == state.guess_t and at_guess_params(state):
        try:                # the guess solved where it was given, its angles kept
            with state.lock:    # near it as solve(t) keeps them (kinematics.follow)
                q0 = follow(state, float(ts[0]), tol, maxit, meth)
        except MechgenError:    # the sweep says why, from the guess itself
            q0 = state.guess.copy()
    else:       # where solve(ts[0]) is (no guess: the guess's mode followed there), or
        try:    # a Solution at another time, its mode followed to ts[0] (start_at)
            q0 = start_at(state, guess, float(ts[0]), tol, maxit, meth, "the sweep's start")
        except MechgenError as exc:
            exc.sweep = no_points(mech, ts, lev)
            raise
    return run(mech, ts, q0, lev, tol, maxit, meth, out, shared, forces, quick)


def convergence_error(*args, **kwargs):
    """runtime.analysis.locks.convergence_error, imported when a solve first fails."""
    from ..analysis.locks import convergence_error as error
    return error(*args, **kwargs)


def singular_error(*args, **kwargs):
    """runtime.analysis.locks.singular_error, imported when a solve first fails."""
    from ..analysis.locks import singular_error as error
    return error(*args, **kwargs)
