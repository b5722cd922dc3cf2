"""``mech.solve(t)`` without a guess: the configuration the mechanism reaches by moving
from its guess to t, never the one a Newton from the guess happens to fall into.

The guess is a configuration at a time: the model's own guess at t = 0 (where ``mechgen
check`` and sweeps start), or what ``set_guess`` made it (a Solution at its time, or
``set_guess(q, t=...)``). Solved there, it fixes the assembly mode; the module's careful
continuation (``sweep``, with its branch tests and step control) carries it to t, its quick
path (``sweep_fast``, which accepts a point only where it passes sweep()'s tests) first,
as a sweep goes (runtime.kinematics.sweeping.compiled). The configurations on the way are kept, one
every CELL of time from the guess's time (a path per guess, parameters, tolerances and
method), so that a later solve continues from the nearest kept one between the guess's
time and its own: a solve costs one short continuation once the way is known. Where the
way is blocked (a lock, no assembly, a jump the step control could not avoid) the solve
raises the error of the sweep that stopped there, naming the time; a singular
configuration passed on the way (a dead centre, where the mechanism may go on in either
mode) is a BranchJumpWarning.
"""
from __future__ import annotations

import warnings
from math import floor as _floor

import numpy as np

from ...errors import BranchJumpWarning, SolveError
from ...protocol import (JUMP, LEVEL, POINT_INFO_SIZE, REPORT_JUMP, REPORT_SIZE,
                        STATUS_CODE, STATUS_COLUMNS, THROUGH_SINGULAR)
from .entry import module_attr, solve_point
from .guesses import guess_at, turned_home
from ..results import Solution
from .sweeping import compiled, failure, from_start, no_rows, outside

CELL = 1.0 / 16.0       # time between the configurations kept on the way (a 16th of a
                        # turn of a driver at one turn per unit of time)
MAX_CELLS = 1 << 20     # the farthest a solve follows: 65,536 units of time from the guess
CHUNK = 4096            # cells solved by one call of the careful sweep
_POSITION = LEVEL["position"]


class Path:
    """The configurations reached from one guess: at t0 (``q0``) and every CELL of time
    on either side of it, as far as solves have gone (row k - 1 of ``side[+1]`` at
    t0 + k CELL, of ``side[-1]`` at t0 - k CELL; ``count[sign]`` rows hold), and the
    times of singular configurations passed."""
    __slots__ = ("key", "t0", "q0", "side", "count", "crossings", "step", "last")

    def __init__(self, key, t0, q0):
        self.key, self.t0, self.q0 = key, t0, q0
        n = q0.shape[0]
        self.side = {1: np.empty((16, n)), -1: np.empty((16, n))}
        self.count = {1: 0, -1: 0}
        self.crossings = []
        self.step = None        # the arrays of the last step's sweep (_last_step)
        self.last = (None, None)    # the last time solved and its configuration

    def cell_time(self, k) -> float:
        """The time of cell k (0: t0; k > 0 ahead, k < 0 behind)."""
        return self.t0 + k * CELL

    def cell(self, k):
        if k == 0:
            return self.q0
        return self.side[1 if k > 0 else -1][abs(k) - 1]

    def keep(self, sign, rows):
        """Append configurations (rows of an array) to a side, growing it as needed."""
        have, arr = self.count[sign], self.side[sign]
        need = have + rows.shape[0]
        if need > arr.shape[0]:
            grown = np.empty((max(need, 2 * arr.shape[0]), arr.shape[1]))
            grown[:have] = arr[:have]
            arr = self.side[sign] = grown
        arr[have:need] = rows
        self.count[sign] = need


def _key(state, tol, maxit, meth):
    return (state.p.tobytes(), state.guess.tobytes(), float(state.guess_t), tol, state.xtol,
            maxit, meth)      # (guess_p changes only with set_guess, which drops the path)


def _said(t, what) -> str:
    """The solve that follows the motion, as its messages name it."""
    return f"solve(t={t:.10g})" if what is None else f"{what} (t={t:.10g})"


def _context(exc, t, t0, what=None):
    """The error of a solve whose way from the guess was blocked, saying so first."""
    exc.args = (f"{_said(t, what)} follows the motion from the guess, a configuration at "
                f"t={t0:.10g}, and could not reach t: {exc.args[0] if exc.args else exc}",)
    return exc


def _start(state, tol, maxit, meth) -> Path:
    """The path of the current guess: the guess solved at its time, kept while the guess,
    parameters, tolerances and method stay the same."""
    key = _key(state, tol, maxit, meth)
    path = state.path
    if path is not None and path.key == key:
        return path
    t0 = float(state.guess_t)
    info = np.zeros(POINT_INFO_SIZE)
    q, note = carried(state, tol, maxit, meth, info)
    start = q.copy()
    status = solve_point(state.module, q, t0, state.p, tol, state.xtol, maxit, meth, info)
    if status == 0 and turned_home(state.owner, q, start):
        # Newton from a poor guess threw angles whole turns away (a rocker at -101 rad
        # for a guess of 1.2): the same configuration near the guess, as solve(t, guess=)
        # gives it, solved again to full precision
        status = solve_point(state.module, q, t0, state.p, tol, state.xtol, maxit, meth, info)
    if status != 0:
        from ..analysis.locks import convergence_error     # an error path: imported when needed
        exc = convergence_error(state.owner, status, t0, q, info)
        exc.args = (f"the guess does not assemble at its time t={t0:.10g}, from which "
                    f"solve(t) follows the motion (pass guess= to solve from a guess at t, "
                    f"or set_guess() a configuration): {exc.args[0]}",)
        raise exc
    if note is not None:
        warnings.warn(note, BranchJumpWarning, stacklevel=outside())
    path = state.path = Path(key, t0, q)
    return path


def start_at(state, guess, t, tol, maxit, meth, what) -> np.ndarray:
    """The start vector at t of a guess given to a sweep or a search from t: a Solution
    at another time is a configuration at its own time (as set_guess takes it), its mode
    followed to t as solve(t) follows it, not a Newton from it at t, which may fall into
    another mode (a mode picked by assemblies(t'), swept from t); none, where solve(t) is
    (the mechanism's guess followed to t: a Newton from it at t could start on another
    mode than solve's); any other guess, the Newton start at t (guesses.guess_at)."""
    if guess is None:
        with state.lock:    # (the way is kept on the mechanism, as solve's)
            return follow(state, float(t), tol, maxit, meth, what=what)
    if not isinstance(guess, Solution) or float(guess.t) == float(t):
        return guess_at(state.owner, guess, t)
    ref = state.with_guess(guess.q.copy(), float(guess.t))   # (its own path)
    return follow(ref, float(t), tol, maxit, meth, what=what)


def at_guess_params(state) -> bool:
    """Whether the mechanism's parameters are those its guess was given for (guess_p):
    then the guess needs no carrying."""
    p0, p = state.guess_p, state.p
    return p0 is p or p0.tobytes() == p.tobytes()


def carried(state, tol, maxit, meth, info):
    """(start vector, note): a start at the mechanism's parameters for its guess, a
    configuration at time guess_t with parameters guess_p. The guess itself where those
    are the mechanism's (at_guess_params); else the guess solved at p0 and carried along
    its assembly mode to the mechanism's parameters (the module's carry_params). Where
    that way is blocked (a singular configuration, or parameters on the way at which it
    does not assemble) the guess itself, and ``note`` says so (a solve from it may land
    in another mode); where the guess does not assemble at p0, the guess itself: there is
    no mode to carry."""
    guess, t0, p0, p = state.guess, float(state.guess_t), state.guess_p, state.p
    mod = state.module
    if at_guess_params(state):
        return guess.copy(), None
    carry = module_attr(mod, "carry_params")
    q = guess.copy()
    if carry is None or solve_point(mod, q, t0, p0, tol, state.xtol, maxit, meth, info) != 0:
        return guess.copy(), None
    if turned_home(state.owner, q, guess):     # (its angles near the guess's, as _start keeps them)
        solve_point(mod, q, t0, p0, tol, state.xtol, maxit, meth, info)
    status = int(carry(q, t0, p0, p, tol, state.xtol, maxit, meth, info))
    if status == 0:
        return q, None
    why = "a singular configuration" if status == THROUGH_SINGULAR else \
        "parameters at which it does not assemble"
    return guess.copy(), (
        f"'{state.name}' with {_changed(state, p0)}: the assembly mode of the guess (a "
        f"configuration at t={t0:.10g} for {_changed(state, p0, p0)}) could not be carried to "
        f"these parameters ({why} on the way): solved from the guess itself, which may "
        "reach another assembly mode (set_guess() a configuration of these parameters to "
        "choose one)")


def _changed(state, p0, values=None) -> str:
    """The parameters where the mechanism's differ from p0, with the mechanism's values
    (or those of ``values``)."""
    values = state.p if values is None else values
    return ", ".join(f"{name}={values[k]:.6g}" for k, name in enumerate(tuple(state.param_index))
                     if state.p[k] != p0[k]) or "its parameters"


def _segment(state, ts, q0, tol, maxit, meth):
    """The careful sweep over ts from q0 (a configuration at ts[0]): (Q, count solved,
    status rows, report). A module with stages goes two times at a time (the ends)."""
    N, n = ts.shape[0], state.guess.shape[0]
    Q = np.empty((N, n))
    S = np.zeros((N, STATUS_COLUMNS), dtype=np.int16)
    report = np.zeros(REPORT_SIZE)
    if module_attr(state.module, "SWITCH_TIMES", ()):
        # stages: each stage's piece swept on its own (stages.staged_sweep)
        owner = state.owner.state           # (run() makes the pieces' ends its last)
        last = owner.last

        def piece(times, q):
            return from_start(state.owner, times, q, _POSITION, tol, maxit, meth)
        from .stages import staged_sweep        # (stages: imported where a model has them)
        try:
            sw = staged_sweep(state.owner, ts, q0, piece, tol)
            if sw is None:
                sw = piece(ts, q0)
        finally:
            owner.last = last
        return sw.Q[[0, -1]], N, S[[0, -1]], report      # (two times: the ends)
    none = no_rows(n)
    done, _ = compiled(state.owner, ts, q0.copy(), _POSITION, tol, maxit, meth, Q, none, none, S,
                       report, unwrap=False)
    return Q, done, S, report


def _extend(state, path, ts, q0, sign, t, tol, maxit, meth, what=None):
    """Solve along ts from q0 (the last known cell, at ts[0]); the rows after the first
    are the next cells when ``sign`` is nonzero. Returns the configuration at ts[-1].
    A step between two cells that the careful sweep could take only by a jump is taken
    again in REFINE substeps (and REFINE² where those jump too) before it counts as one:
    a fast driver turns a crank many times in one cell (CELL is a time, not an angle)."""
    while True:
        Q, done, S, report = _segment(state, ts, q0, tol, maxit, meth)
        code = S[:done, STATUS_CODE]
        if done == ts.shape[0] and not np.count_nonzero(code):    # the usual case, in short
            if sign:
                path.keep(sign, Q[1:])
            return Q[-1]
        jumped = np.flatnonzero(code == JUMP)
        ok = done if not jumped.size else int(jumped[0])
        if sign and ok > 1:
            path.keep(sign, Q[1:ok])
        _crossed(path, ts, code[:ok])
        if jumped.size:
            k = int(jumped[0])
            qk = _refined(state, path, ts[k - 1], ts[k], Q[k - 1], tol, maxit, meth) \
                if k >= 1 else None
            if qk is not None:
                if sign:
                    path.keep(sign, qk[None, :])
                if k == ts.shape[0] - 1:
                    return qk
                ts, q0 = ts[k:], qk         # on from the cell the substeps reached
                continue
            exc = SolveError(
                f"the continuation could not keep the assembly mode on the way to "
                f"t={ts[k]:.10g} (a jump of {report[REPORT_JUMP]:.3g} the smallest step "
                "could not avoid): the configuration there may lie on another assembly mode "
                "(state.singularities locates singular configurations on the way; guess= "
                "solves from a guess at t)")
            exc.t = float(ts[k])
            raise _context(exc, t, path.t0, what)
        if done < ts.shape[0]:
            exc = failure(state.owner, ts, done, Q, report, q0)
            raise _context(exc, t, path.t0, what)
        return Q[-1]


REFINE = 64     # substeps of a step between two cells that jumped (see _extend)


def _crossed(path, ts, code):
    """Keep the times of the points reached at or through a singular configuration."""
    for k in np.flatnonzero(code == THROUGH_SINGULAR):
        if float(ts[k]) not in path.crossings:
            path.crossings.append(float(ts[k]))


def _refined(state, path, ta, tb, qa, tol, maxit, meth, depth=2):
    """The configuration at tb from qa at ta by the careful sweep in REFINE substeps (each
    taken again in REFINE where it jumps, ``depth`` levels), or None where a jump remains
    or a substep fails (the caller then reports the jump)."""
    ts = np.linspace(ta, tb, REFINE + 1)
    q = qa
    while True:
        Q, done, S, _report = _segment(state, ts, q, tol, maxit, meth)
        code = S[:done, STATUS_CODE]
        jumped = np.flatnonzero(code == JUMP)
        ok = done if not jumped.size else int(jumped[0])
        if np.count_nonzero(code[:ok] == THROUGH_SINGULAR):
            _crossed(path, np.full(ok, tb), code[:ok])     # (named by the cell's time)
        if done == ts.shape[0] and not jumped.size:
            return Q[-1].copy()
        if not jumped.size or depth <= 1 or ok < 1:
            return None
        qk = _refined(state, path, ts[ok - 1], ts[ok], Q[ok - 1], tol, maxit, meth, depth - 1)
        if qk is None:
            return None
        if ok == ts.shape[0] - 1:
            return qk
        ts, q = ts[ok:], qk


def _last_step(state, path, tc, qc, t, tol, maxit, meth, what=None) -> np.ndarray:
    """The careful sweep from the cell (tc, qc) to t, in the path's own two-point arrays
    when nothing is in the way (the cost of a solve once the way is known)."""
    mod = state.module
    if not module_attr(mod, "SWITCH_TIMES", ()):
        step = path.step
        if step is None:
            step = path.step = _step_arrays(state.guess.shape[0])
        ts, Q, S, report, none, times, codes, last = step
        times[0], times[1] = tc, t
        done, _ = compiled(state.owner, ts, qc.copy(), _POSITION, tol, maxit, meth, Q, none, none,
                           S, report, unwrap=False)
        if done == 2 and codes[0] == 0 and codes[1] == 0:
            return last.copy()
    return _extend(state, path, np.array([tc, t]), qc, 0, t, tol, maxit, meth, what).copy()


def _step_arrays(n):
    """The two-point sweep's arrays of _last_step (ts, Q, S, report, no rows), with
    memoryviews of ts and of S's status codes (a Python float in, a Python int out, with
    no numpy scalar on the way) and the view of Q's last row."""
    ts, Q = np.empty(2), np.empty((2, n))
    S = np.empty((2, STATUS_COLUMNS), dtype=np.int16)
    return (ts, Q, S, np.empty(REPORT_SIZE), no_rows(n), memoryview(ts),
            memoryview(S[:, STATUS_CODE]), Q[1])


def follow(state, t, tol, maxit, meth, what=None) -> np.ndarray:
    """The configuration at t on the assembly mode of the guess, reached by continuation
    from the guess's time (see the module docstring): a position that solves Φ to the
    sweep's tolerance, to be polished by the caller's solve at t. Raises the blocked
    way's error (ConvergenceError, SingularError, SolveError) naming where it stopped;
    ``what`` names the caller's solve in it (default "solve(t=...)")."""
    # (a solve's own cost once the way is known: the path's key compared, the last cell
    # before t found and the one short continuation from it; see _start and Path)
    path = state.path
    if path is None or path.key != (state.p.tobytes(), state.guess.tobytes(),   # (_key)
                                    float(state.guess_t), tol, state.xtol, maxit, meth):
        path = _start(state, tol, maxit, meth)
    t0 = path.t0
    if t == t0:
        return path.q0.copy()
    last = path.last
    if t == last[0]:
        return last[1].copy()
    sign = 1 if t > t0 else -1
    far = abs(t - t0)
    m = _floor(far / CELL)                      # the last cell between t0 and t (an int)
    if m > MAX_CELLS:
        raise ValueError(
            f"{_said(t, what)}: t is {far:.6g} from the guess's time t={t0:.10g}, "
            f"farther than solve(t) follows the motion ({MAX_CELLS * CELL:.0f}); give a "
            "guess near t (guess=, or set_guess() a configuration at a time near it)")
    tc = t0 + (sign * m) * CELL                 # path.cell_time(sign * m)
    while m and abs(tc - t0) > far:
        m -= 1                                  # (rounding of t0 + m CELL)
        tc = t0 + (sign * m) * CELL
    have = path.count[sign]
    if m > have:                                # the cells still missing, CHUNK at a time
        state.tiers.expect(state.owner, m - have)
        chunk = 1 if module_attr(state.module, "SWITCH_TIMES", ()) else CHUNK
        while have < m:
            ks = np.arange(have, min(m, have + chunk) + 1)
            ts = path.t0 + (sign * ks) * CELL
            _extend(state, path, ts, path.cell(sign * have), sign, t, tol, maxit, meth, what)
            have = path.count[sign]
    qc = path.side[sign][m - 1] if m else path.q0   # path.cell(sign * m)
    if tc == t:
        q = qc.copy()
    else:
        q = _last_step(state, path, tc, qc, t, tol, maxit, meth, what)
    crossings = path.crossings
    passed = [c for c in crossings if min(t0, t) < c <= max(t0, t)] if crossings else None
    if passed:
        warnings.warn(
            f"{_said(t, what)} of '{state.name}': the way from the guess at t={t0:.10g} "
            f"passes a singular configuration (dead centre, lock or branch point) near "
            f"t={passed[0]:.10g}: there the mechanism may continue in another assembly "
            "mode (state.singularities locates it)", BranchJumpWarning, stacklevel=3)
    else:
        path.last = (t, q.copy())
    return q
