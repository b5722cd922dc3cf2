"""Mechanism.sweep's work: the arrays a sweep fills (only those its level needs, or the
caller's, see ``out``), the module's compiled loops (sweep_fast while nothing is hard,
then the careful continuation sweep), and what a sweep says when it jumps branch, passes
a singular configuration or stops. numpy only; the module's functions do the solving.

A sweep stores, per point, its coordinates (Q), their velocities (QD, at level velocity
and above) and accelerations (QDD, at level acceleration) and a small int16 STATUS row
(protocol.STATUS_*: the status code and the Newton iterations); one float vector per sweep
(the report, protocol.REPORT_*) says where and why it stopped and the size of its first
branch jump. A position sweep touches no memory for velocities or accelerations.
"""
from __future__ import annotations

import os
import sys
import warnings

import numpy as np

from ...errors import BranchJumpWarning, MechgenError, RedundancyWarning, SingularError
from ...protocol import (ACCELERATION, FUSED_PATHS, JUMP, LEVEL, LEVELS, METHOD_FULL,
                        REPORT_FAILED, REPORT_JUMP, REPORT_REACHED, REPORT_SIZE,
                        REPORT_STATUS, STATUS_CODE, STATUS_COLUMNS, THROUGH_SINGULAR,
                        VELOCITY, fused_path)
from ..results import Sweep

_VEL, _ACC = LEVEL["velocity"], LEVEL["acceleration"]
_KEYS = ("q", "qd", "qdd", "status")
_NO_ROWS = {}       # n -> an empty (0, n) array: QD, QDD of a sweep that does not store them


def no_rows(n) -> np.ndarray:
    """A (0, n) array: what the compiled sweeps get for a level not stored (writeable, as
    the arrays they fill: the same compiled code serves both; it holds nothing)."""
    arr = _NO_ROWS.get(n)
    if arr is None:
        arr = _NO_ROWS[n] = np.empty((0, n))
    return arr


def linspace(t0, t1, n) -> np.ndarray:
    """np.linspace(t0, t1, n) for floats t0, t1 and an int n >= 1, the same numbers (its
    algorithm: arange(n) * step + t0, the last set to t1) at a third of its cost."""
    ts = np.arange(n, dtype=np.float64)
    if n > 1:
        step = (t1 - t0) / (n - 1)
        if step == 0.0:
            ts *= 0.0
        else:
            ts *= step
        ts += t0
        ts[-1] = t1
    else:
        ts += t0
    return ts


_TIMES = {}         # the times of the last plain sweep: (t0, t1, n) -> its times
_SPARE_MIN = (32 << 20) // 8    # float64 entries: blocks from here on are kept (see _block)


def times(t0, t1, n) -> np.ndarray:
    """linspace(t0, t1, n), the last sweep's when it asked for the same: shared, to be
    copied before a result holds it (run(..., shared=True) does)."""
    key = (t0, t1, n)
    ts = _TIMES.get(key)
    if ts is None:
        ts = linspace(t0, t1, n)
        _TIMES.clear()
        _TIMES[key] = ts
    return ts


def _block(mech, size) -> np.ndarray:
    """``size`` float64 of memory for a sweep's arrays. A block the size of glibc's
    largest cached one (32 MiB) or more is kept by the Mechanism (``_spare``) when handed
    out, and handed out again (its first ``size`` entries) to the next sweep that fits in
    it (and needs at least a quarter of it) once nothing holds it any more (no view of it
    alive: the sweep it served was dropped). glibc hands such blocks back to the system at
    once, and a sweep of a million points would otherwise fault its pages in afresh at
    every call. At most one such block a Mechanism stays allocated after its sweep is
    dropped."""
    if size < _SPARE_MIN:
        return np.empty(size)
    state = mech.state
    spare, state.spare = state.spare, None
    if spare is not None and size <= spare.shape[0] <= 4 * size and \
            sys.getrefcount(spare) == 2:
        state.spare = spare     # referenced only here: no sweep holds a view of it
        return spare[:size]
    del spare
    block = state.spare = np.empty(size)
    return block


def no_points(mech, ts, lev) -> Sweep:
    """The sweep of a failed one's error that solved no point (its times none of ts)."""
    n = mech.n
    none = np.empty((0, n))
    return Sweep(mech, ts[:0].copy(), none, none if lev >= _VEL else None,
                 none if lev >= _ACC else None, np.zeros((0, STATUS_COLUMNS), dtype=np.int16),
                 np.zeros(REPORT_SIZE))


def fresh_arrays(ts, n, lev, shared, mech=None):
    """(ts, Q, QD, QDD, STATUS) of a sweep at level ``lev``: views of one new block of
    memory (the times copied into it when ``shared``). One block rather than five
    arrays: freed, it goes back to the allocator whole and the next sweep of that size
    reuses it, where separate arrays of a few hundred kilobytes each are handed back to
    the system and their pages have to be faulted in again (100+ ns a point on a VM)."""
    N = ts.shape[0]
    rows = N * n
    if rows < 4096:                 # small: separate arrays cost less to set up
        return (ts.copy() if shared else ts, np.empty((N, n)),
                np.empty((N, n)) if lev >= _VEL else no_rows(n),
                np.empty((N, n)) if lev >= _ACC else no_rows(n),
                np.empty((N, STATUS_COLUMNS), dtype=np.int16))
    levels = 1 + (lev >= _VEL) + (lev >= _ACC)
    status = -(-N * STATUS_COLUMNS // 4)            # int16 entries, in float64 units
    size = N * shared + levels * rows + status
    block = np.empty(size) if mech is None else _block(mech, size)
    at = 0
    if shared:
        own = block[:N]
        own[:] = ts
        ts, at = own, N
    Q = block[at:at + rows].reshape(N, n)
    QD = QDD = no_rows(n)
    if lev >= _VEL:
        QD = block[at + rows:at + 2 * rows].reshape(N, n)
    if lev >= _ACC:
        QDD = block[at + 2 * rows:at + 3 * rows].reshape(N, n)
    S = block[at + levels * rows:].view(np.int16)[:N * STATUS_COLUMNS]
    return ts, Q, QD, QDD, S.reshape(N, STATUS_COLUMNS)


def _given(arr, what, N, cols, dtype):
    """``arr`` when it is a writeable C-contiguous array of shape (N, cols) and this
    dtype, else a ValueError that says what is wrong."""
    if not isinstance(arr, np.ndarray):
        raise ValueError(f"out: {what} must be a numpy array, got {type(arr).__name__}")
    if arr.dtype != dtype:
        raise ValueError(f"out: {what} must have dtype {np.dtype(dtype).name}, got {arr.dtype}")
    if arr.shape != (N, cols):
        raise ValueError(f"out: {what} must have shape ({N}, {cols}) for a sweep of {N} "
                         f"points, got {arr.shape}")
    if not arr.flags.c_contiguous:
        raise ValueError(f"out: {what} must be C-contiguous (np.ascontiguousarray)")
    if not arr.flags.writeable:
        raise ValueError(f"out: {what} is read-only")
    return arr


def out_arrays(out, N, n, lev):
    """The (Q, QD, QDD, STATUS) a sweep of N points at level ``lev`` writes into: fresh
    arrays (np.empty) for what ``out`` does not give. ``out`` is None, a dict with keys
    "q", "qd", "qdd", "status" (any of them; status of 1 to STATUS_COLUMNS columns), a tuple (Q,), (Q, QD) or (Q, QD, QDD), or a
    Sweep of the same size and at least this level from an earlier call (its arrays are
    reused: that sweep's numbers are overwritten)."""
    given = {}
    if out is not None:
        if isinstance(out, Sweep):
            if len(out) != N or out._have() < lev:
                raise ValueError(f"out: a Sweep to reuse must have {N} points and level "
                                 f"{('position', 'velocity', 'acceleration')[lev]} or above "
                                 f"(it has {len(out)} points, level {out.level})")
            given = {"q": out.Q, "qd": out.QD, "qdd": out.QDD, "status": out._status}
        elif isinstance(out, dict):
            bad = [k for k in out if k not in _KEYS]
            if bad:
                raise ValueError(f"out: unknown key(s) {', '.join(map(repr, bad))} "
                                 f"(keys: 'q', 'qd', 'qdd', 'status')")
            given = out
        elif isinstance(out, (tuple, list)) and 1 <= len(out) <= 3:
            given = dict(zip(_KEYS, out))
        else:
            raise ValueError("out must be a dict {'q': Q, 'qd': QD, 'qdd': QDD, 'status': S}, "
                             "a tuple (Q,), (Q, QD) or (Q, QD, QDD), or a Sweep to reuse")
    Q = given.get("q")
    Q = np.empty((N, n)) if Q is None else _given(Q, "q", N, n, np.float64)
    QD = QDD = no_rows(n)
    if lev >= _VEL:
        QD = given.get("qd")
        QD = np.empty((N, n)) if QD is None else _given(QD, "qd", N, n, np.float64)
    if lev >= _ACC:
        QDD = given.get("qdd")
        QDD = np.empty((N, n)) if QDD is None else _given(QDD, "qdd", N, n, np.float64)
    S = given.get("status")
    if S is None:
        S = np.empty((N, STATUS_COLUMNS), dtype=np.int16)
    else:
        if isinstance(S, np.ndarray) and S.ndim == 2 and S.shape[:1] == (N,) and \
                1 <= S.shape[1] <= STATUS_COLUMNS:
            cols = S.shape[1]
        else:
            cols = STATUS_COLUMNS
        S = _given(S, "status", N, cols, np.int16)
    return Q, QD, QDD, S


def compiled(mech, ts, q0, lev, tol, maxit, meth, Q, QD, QDD, S, report, forces=None,
             unwrap=True, quick=None):
    """The module's quick path (sweep_fast) while nothing is hard, then its careful
    continuation (sweep) from the last point the quick path accepted: (count solved, the
    first point the careful sweep solved: len(ts) when it did not run). Only the careful
    sweep writes the report and marks points JUMP or THROUGH_SINGULAR. ``forces`` (a
    dict; an acceleration sweep of a module with FORCE_FUSED, or a position sweep of one
    with STATIC_FUSED: a dynamic or a static sweep): the quick path solves the
    multipliers too, and the dict receives "LAM", "FACTORS", "FPIV" and "count", the
    points before which they hold (the careful sweep's are not solved). ``unwrap``: q0's
    angles are first turned as the drivers ask (a guess's; False for a configuration
    already solved at ts[0]). ``quick``: a callable that runs in place of the module's
    sweep_fast, with its arguments and its answer (a layer above that solves more on the
    way: sensitivity.fused); called at most once, where the quick path runs."""
    state = mech.state
    mod, p, xtol = state.tiers.module, state.p, state.xtol
    N = ts.shape[0]
    start = 0
    turn = getattr(mod, "unwrap_turns", None) if unwrap else None
    if turn is not None and N:
        turn(q0, ts[0], p)              # the guess's angles as its drivers ask (q0 is ours)
    fused = None
    if forces is not None:          # the force level whose fused path sweeps at lev
        fused = next((f for f in (fused_path(mod, level, lev) for level in FUSED_PATHS)
                      if f is not None), None)
    if meth != METHOD_FULL and mod.SORTED and mod.LEVEL >= 2:
        start = -1
        if fused is not None:
            LAM, FACTORS = np.empty((N, mod.N_EQS)), np.empty((N, len(mod.DRIVER_ROWS)))
            FPIV = np.empty(N)
            try:
                start = fused(ts, q0, p, tol, xtol, maxit, Q, QD, QDD, S, LAM, FACTORS,
                              FPIV)
            except ZeroDivisionError:   # the plain tier, where numba's numpy error model
                pass                    # gives inf: the multipliers are solved afterwards
            else:
                forces.update(LAM=LAM, FACTORS=FACTORS, FPIV=FPIV,
                              count=start if start == N else max(start - 1, 0))
        if start < 0:
            try:
                start = (quick or mod.sweep_fast)(ts, q0, p, tol, xtol, maxit, Q, QD, QDD, S)
            except ZeroDivisionError:   # the equations divide by zero at some point (a
                start = 0               # driver 1/T at T = 0): the careful sweep says where
        if start == N:
            return N, N
        start = max(start - 1, 0)         # resume from the last accepted point
    if start:
        q0 = Q[start].copy()
        QD_ = QD[start:] if lev >= _VEL else QD
        QDD_ = QDD[start:] if lev >= _ACC else QDD
        done = mod.sweep(ts[start:], q0, p, lev, tol, xtol, maxit, meth, Q[start:], QD_,
                         QDD_, S[start:], report)
        return start + done, start
    return mod.sweep(ts, q0, p, lev, tol, xtol, maxit, meth, Q, QD, QDD, S, report), 0


def from_start(mech, ts, q0, lev, tol, maxit, meth) -> Sweep:
    """The sweep over ts (checked times) from q0, a start vector at ts[0] (not changed):
    run() after the tier's look at its size (runtime.loading.tiers)."""
    mech.state.tiers.expect(mech, ts.shape[0])
    return run(mech, ts, np.array(q0, dtype=np.float64), lev, tol, maxit, meth)


def divides(mech, ts, what, **where) -> SingularError:
    """The SingularError of ``what`` (a sweep, a design table) whose equations divide by
    zero at one of its times ts: Python's float division and numba's default error model
    raise where numpy gives inf."""
    return SingularError(
        f"model '{mech.name}': its equations divide by zero at a time of {what} from "
        f"t={ts[0]:.10g} to t={ts[-1]:.10g} (a driver such as 1/T, or the rate of "
        "sqrt(T), at T = 0; the steps use the velocities): sweep a range that avoids that "
        "time", **where)


def run(mech, ts, q0, lev, tol, maxit, meth, out=None, shared=False, forces=None,
        quick=None) -> Sweep:
    """A checked sweep: the compiled loops, the result, its warnings, or the error of the
    point where it stopped (carrying the points solved before it as ``.sweep``).
    ``shared``: ts is times()'s, copied before the result holds it. ``forces``,
    ``quick``: see compiled()."""
    N, n = ts.shape[0], mech.n
    if out is None:
        ts, Q, QD, QDD, S = fresh_arrays(ts, n, lev, shared, mech)
    else:
        if shared:
            ts = ts.copy()
        Q, QD, QDD, S = out_arrays(out, N, n, lev)
    report = np.zeros(REPORT_SIZE)
    try:
        done, careful = compiled(mech, ts, q0, lev, tol, maxit, meth, Q, QD, QDD, S, report,
                                 forces, quick=quick)
    except ZeroDivisionError:       # Python's and numba's default error model raise
        raise divides(mech, ts, "the sweep", level=LEVELS[lev]) from None
    if done == N:
        sw = Sweep(mech, ts, Q, QD if lev >= _VEL else None, QDD if lev >= _ACC else None,
                   S, report)
    else:
        sw = Sweep(mech, ts[:done], Q[:done], QD[:done] if lev >= _VEL else None,
                   QDD[:done] if lev >= _ACC else None, S[:done], report)
    # (the careful sweep marks an accepted point JUMP or THROUGH_SINGULAR, never another
    # status other than OK)
    if careful < done and S[careful:done, STATUS_CODE].any():
        _flag(mech, sw, report)
    if done < N:
        try:
            raise failure(mech, ts, done, Q, report, q0)
        except MechgenError as exc:
            exc.sweep = sw
            raise
    if done:
        if mech.m > n:
            report_redundancy(mech.state, Q[0], ts[0])
        k = done - 1                        # the last point, a Solution when asked for
        mech.state.last = (ts[k], Q[k].copy(), QD[k].copy() if lev >= _VEL else None,
                           QDD[k].copy() if lev >= _ACC else None)
    return sw


_PACKAGE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # mechgen/


def outside() -> int:
    """The stacklevel, seen from its caller, of the first frame outside mechgen: a
    warning then names the user's line, whichever way into the sweep it came."""
    frame, level = sys._getframe(1), 1
    while frame is not None and frame.f_code.co_filename.startswith(_PACKAGE):
        frame, level = frame.f_back, level + 1
    return level


def _flag(mech, sw, report):
    """sw.jumps, sw.crossings and a BranchJumpWarning for each kind."""
    status = sw._status[:, STATUS_CODE]
    jumped, crossed = status == JUMP, status == THROUGH_SINGULAR
    level = outside()
    sw.jumps, sw.crossings = sw.t[jumped], sw.t[crossed]
    if np.any(jumped):
        k = int(np.argmax(jumped))
        warnings.warn(
            f"sweep of '{mech.name}': the step control could not keep the assembly mode at "
            f"{int(jumped.sum())} point(s) (first at t={sw.t[k]:.10g}, a jump of "
            f"{report[REPORT_JUMP]:.3g}): the solutions after it may lie on another branch "
            "(sw.jumps lists the times)", BranchJumpWarning, stacklevel=level)
    if np.any(crossed):
        k = int(np.argmax(crossed))
        more = "" if crossed.sum() == 1 else f" ({int(crossed.sum())} such points)"
        warnings.warn(
            f"sweep of '{mech.name}': the way to t={sw.t[k]:.10g} reaches or passes a singular "
            f"configuration (dead centre, lock or branch point){more}: "
            "there the mechanism may continue in another assembly mode "
            "(sw.crossings lists the times; mech.singularities locates them)",
            BranchJumpWarning, stacklevel=level)


def report_redundancy(state, q, t):
    """Once per module: a model with more equations than coordinates solves by dropping
    dependent rows; say which equations depend on the others."""
    mech, module = state.owner, state.module
    if mech.m <= mech.n or getattr(module, "_mechgen_redundancy_reported", False):
        return
    module._mechgen_redundancy_reported = True     # the runtime's own mark
    from ..analysis.singular import null_space
    null = null_space(mech, q, t)
    extra = mech.m - min(null.rank, mech.n)
    warnings.warn(
        f"model '{mech.name}' has {mech.m} equations for {mech.n} coordinates: {extra} "
        f"redundant (consistent at t={t:.6g}; the solver drops dependent rows). The "
        f"dependent equations are among: {'; '.join(null.constraints)}",
        RedundancyWarning, stacklevel=outside())


def failure(mech, ts, done, Q, report, q0) -> MechgenError:
    """The error of a sweep that stopped at ts[done]: SingularError where the derivatives
    are not determined, else ConvergenceError (with the lock the branch ran into, where
    there is one). The careful sweep left the last configuration it reached in Q[done],
    its time and the time that failed in the report."""
    from ..analysis.locks import convergence_error, singular_error    # an error path: imported here
    from ..analysis.singular import solve_q
    status = int(report[REPORT_STATUS])
    t = float(ts[done])
    t_last, t_try = float(report[REPORT_REACHED]), float(report[REPORT_FAILED])
    q_last = Q[done].copy()
    if status >= VELOCITY:
        q_s, ok = q_last, True
        if t_try != t_last:
            q_s, ok = solve_q(mech, q_last, t_try)
        where = "" if t_try == t else f" (on the way to t={t:.10g})"
        level = "velocity" if status < ACCELERATION else "acceleration"
        return singular_error(mech, t_try if ok else t_last, q_s, level, where)
    if done:
        where = "" if t_try == t else \
            f" (the sweep reached t={t_last:.10g} on the way and could go no further)"
        return convergence_error(mech, status, t, q_last, report, t_good=t_last,
                                 q_good=q_last, where=where)
    return convergence_error(mech, status, t, q0, report)
