"""Locating singular configurations along a branch, and saying why a solve failed.

A configuration is singular when the row-equilibrated Jacobian Φ_q loses rank
(mechgen.runtime.analysis.singular measures that). Along a sweep two kinds of singular point occur:

- a *lock* (fold, toggle position): the driven motion cannot go on; the mechanism has no
  assembly on the far side near it. It is located by solving the augmented system
  Φ(q, t) = 0, det Φ_q(q, t) = 0 for (q, t) by Newton, which converges quadratically
  from the last configuration a step-controlled sweep reaches;
- a *crossing* (dead centre passed, branch point): det Φ_q changes sign along the
  branch while the sweep goes on; located by a bracketing root search on det Φ_q
  evaluated on solved configurations of the branch. Over-constrained models can touch
  rank loss without a sign change: a minimum of the smallest singular value that
  reaches zero is located by golden section.

``explain_failure`` says why a position solve found nothing (used by the runtime's
ConvergenceError): no assembly near the guess and the lock positions that bound the
stretch without assembly, or inconsistent redundant constraints, or a bad guess.
``singular_error`` and ``convergence_error`` build the exceptions Mechanism raises.

numpy only, on the functions of a generated module (never sympy).
"""
from __future__ import annotations

import math

import numpy as np

from ...errors import ConvergenceError, SingularError
from ...protocol import (GAVE_UP, METHOD_AUTO, INFO_ITERATIONS, INFO_RESIDUAL, LEVEL,
                        NO_CONVERGENCE, NOT_FINITE, REPORT_REACHED, REPORT_SIZE, SING_RTOL,
                        STATUS_COLUMNS)
from ..results import Solution
from .singular import (NullSpace, assemble_near, det_indicator, independent_rows,
                       least_squares, null_space, residual_vector, smallest_sv, solve_q)


def refine_lock(mech, q, t, maxit=40):
    """Newton on the augmented system Φ(q, t) = 0, det Φ_q(q, t) = 0 for (q, t), from a
    configuration near a lock position. Returns (q, t, converged)."""
    rows = independent_rows(mech, q, t)
    n = mech.n
    z = np.append(np.array(q, dtype=np.float64), float(t))
    scale = 1.0 + np.max(np.abs(z))

    def F(z):
        r = residual_vector(mech, z[:n], z[n])[rows]
        return np.append(r, det_indicator(mech, z[:n], z[n], rows))

    Fz = F(z)
    for _ in range(maxit):
        if not np.all(np.isfinite(Fz)):
            return z[:n], z[n], False
        A = np.empty((n + 1, n + 1))
        A[:n, :n] = mech.jacobian(z[:n], z[n])[rows]
        nu = np.empty(mech.m)
        mech.module.nu(z[:n], z[n], mech.p, nu)
        A[:n, n] = -nu[rows]
        for j in range(n + 1):
            h = 1e-7 * (1.0 + abs(z[j]))
            zp, zm = z.copy(), z.copy()
            zp[j] += h
            zm[j] -= h
            A[n, j] = (det_indicator(mech, zp[:n], zp[n], rows) -
                       det_indicator(mech, zm[:n], zm[n], rows)) / (2 * h)
        try:
            dz = np.linalg.solve(A, -Fz)
        except np.linalg.LinAlgError:
            return z[:n], z[n], False
        lam, base = 1.0, np.max(np.abs(Fz))
        while True:
            zn = z + lam * dz
            Fn = F(zn)
            if np.all(np.isfinite(Fn)) and (np.max(np.abs(Fn)) < base or lam < 1e-3):
                break
            lam *= 0.5
        z, Fz = zn, Fn
        if np.max(np.abs(lam * dz)) <= 1e-13 * scale and np.max(np.abs(Fz[:n])) <= mech.tol:
            break
    ok = np.max(np.abs(residual_vector(mech, z[:n], z[n]))) <= mech.tol and \
        abs(Fz[n]) <= 1e-7
    return z[:n], float(z[n]), bool(ok)


def refine_crossing(mech, qa, ta, qb, tb, rows=None, maxit=100):
    """The time in [ta, tb] where det Φ_q changes sign along the branch through qa and qb
    (Illinois regula falsi on solved configurations). Returns (q, t, converged)."""
    ga = det_indicator(mech, qa, ta, rows)
    gb = det_indicator(mech, qb, tb, rows)
    if ga == 0.0:
        return qa, ta, True
    if gb == 0.0:
        return qb, tb, True
    side = 0
    q, t = qa, ta
    for _ in range(maxit):
        t = (ta * gb - tb * ga) / (gb - ga)
        if not (min(ta, tb) < t < max(ta, tb)):
            t = 0.5 * (ta + tb)
        w = (t - ta) / (tb - ta)
        q, ok = solve_q(mech, (1 - w) * qa + w * qb, t, maxit=200, tol=1e-3 * mech.tol)
        if not ok:
            q, ok = solve_q(mech, (1 - w) * qa + w * qb, t, maxit=200)
        if not ok:
            return q, t, False
        g = det_indicator(mech, q, t, rows)
        if g == 0.0 or abs(tb - ta) <= 4e-16 * (1.0 + abs(t)):
            break
        if (g > 0) == (ga > 0):
            qa, ta, ga = q, t, g
            if side == -1:
                gb *= 0.5
            side = -1
        else:
            qb, tb, gb = q, t, g
            if side == 1:
                ga *= 0.5
            side = 1
        if abs(tb - ta) <= 1e-15 * (1.0 + abs(t)):
            break
    return q, t, True


def refine_minimum(mech, qs, ts, maxit=200):
    """The time near ts[1] where the smallest singular value of Φ_q is least along the
    branch through the configurations qs at the three times ts (golden section on solved
    configurations). Returns (q, t, smallest singular value)."""
    ts = [float(x) for x in ts]

    def at(t):
        # quadratic interpolation of the three configurations as the start
        w = [np.prod([(t - ts[j]) / (ts[i] - ts[j]) for j in range(3) if j != i]) for i in range(3)]
        q0 = sum(wi * qi for wi, qi in zip(w, qs))
        q, ok = solve_q(mech, q0, t, maxit=200)
        return q, (smallest_sv(mech, q, t) if ok else np.inf)

    g = (math.sqrt(5) - 1) / 2
    a, b = ts[0], ts[2]
    c, d = b - g * (b - a), a + g * (b - a)
    (qc, fc), (qd, fd) = at(c), at(d)
    for _ in range(maxit):
        if abs(b - a) <= 1e-13 * (1.0 + abs(a)):
            break
        if fc <= fd:
            b, d, qd, fd = d, c, qc, fc
            c = b - g * (b - a)
            qc, fc = at(c)
        else:
            a, c, qc, fc = c, d, qd, fd
            d = a + g * (b - a)
            qd, fd = at(d)
    return (qc, c, fc) if fc <= fd else (qd, d, fd)


class Singularity(float):
    """A singular configuration found along a sweep: a float (its time) that carries
    ``t``, ``q``, ``kind`` ("lock": the driven motion cannot pass, no assembly beyond;
    "crossing": the branch passes through a dead centre or branch point),
    ``constraints`` (the equations that become dependent), ``coordinates`` (those the
    constraints stop determining), ``lock`` (the equations that lose their grip on them;
    empty where no single equation acts on them), ``grouped`` (the constraints involved,
    in declaration order),
    ``ratio`` (how singular Φ_q is there) and ``solution`` (a Solution, flagged singular)."""

    def __new__(cls, mech, t, q, kind, null: NullSpace, side=None):
        obj = super().__new__(cls, t)
        obj.mechanism = mech
        obj.q = np.array(q, dtype=np.float64)
        obj.kind = kind
        obj.side = side
        obj.constraints = null.constraints
        obj.coordinates = null.coordinates
        obj.lock = null.lock
        obj.grouped = null.grouped
        obj.ratio = null.ratio
        obj.null = null
        return obj

    @property
    def t(self) -> float:
        return float(self)

    @property
    def solution(self):
        mech = self.mechanism
        return Solution(mech, self.t, self.q.copy(), residual=mech.residual(self.q, self.t),
                        singular=True, method="full")

    def __getitem__(self, name):
        return self.solution[name]

    def describe(self) -> str:
        what = {"lock": "lock (toggle) position", "crossing": "singular crossing"}[self.kind]
        return f"{what} at t={self.t:.10g}: {self.null.describe()}"

    def __repr__(self):
        return f"<Singularity {self.describe()}>"

    def __reduce__(self):
        return (float, (float(self),))


def _lock_from(mech, q, t, t_far):
    """The lock position a branch reaches after (q, t), heading towards t_far, or None."""
    qs, ts, ok = refine_lock(mech, q, t)
    lo, hi = min(t, t_far), max(t, t_far)
    slack = 1e-6 * max(1.0, abs(t_far - t))
    if not ok or not (lo - slack <= ts <= hi + slack):
        return None
    null = null_space(mech, qs, ts, force=True)
    return Singularity(mech, ts, qs, "lock", null, side=1 if t_far > t else -1)


def _continue(mech, q0, times):
    """The compiled, step-controlled sweep from q0 over ``times`` at position level:
    (count reached, Q, the sweep's report) without raising. Where it stops, Q[count] is
    the last configuration reached and report[REPORT_REACHED] its time."""
    times = np.asarray(times, dtype=np.float64)
    N = times.shape[0]
    Q, none = np.zeros((N, mech.n)), np.zeros((0, mech.n))
    report = np.zeros(REPORT_SIZE)
    done = mech.module.sweep(times, np.array(q0, dtype=np.float64), mech.p, LEVEL["position"],
                             mech.tol, mech.xtol, mech.maxit, METHOD_AUTO, Q, none, none,
                             np.zeros((N, STATUS_COLUMNS), dtype=np.int16), report)
    return int(done), Q, report


def lock_between(mech, q_good, t_good, t_bad):
    """The lock position between a solved configuration at t_good and a time t_bad where
    the branch does not assemble: step-controlled continuation to the last configuration
    reachable, then the augmented Newton. None when none is found."""
    times = [t_good, t_bad]
    done, Q, report = _continue(mech, q_good, times)
    if done == len(times) or done == 0:     # it assembles at t_bad after all, or not at t_good
        return None
    # on failure the sweep leaves the last configuration it reached in Q[1] and its time
    # in the report
    return _lock_from(mech, Q[1], float(report[REPORT_REACHED]), t_bad)


def singularities(mech, ts, q):
    """Every time of [ts[0], ts[-1]] where Φ_q loses rank along the branch that starts at
    q: lock positions (where that branch ends: the sweep resumes on the far side of a
    stretch without assembly from the configuration at the lock) and crossings (det Φ_q
    changes sign). The sample times ``ts`` bracket them; each is refined to ~1e-12 in t.
    Returns a list of Singularity, in time order."""
    found: list[Singularity] = []
    i = 0
    rows = None
    while i < len(ts):
        done, Q, report = _continue(mech, q, ts[i:])
        if done and rows is None:
            rows = independent_rows(mech, Q[0], ts[i])
        seg_t = ts[i:i + done]
        g = [det_indicator(mech, Q[k], seg_t[k], rows) for k in range(done)]
        sv = [smallest_sv(mech, Q[k], seg_t[k]) for k in range(done)]
        for k in range(done):
            if g[k] == 0.0 or (k + 1 < done and g[k] * g[k + 1] < 0):
                if g[k] == 0.0:
                    qs, tsg, ok = Q[k], seg_t[k], True
                else:
                    qs, tsg, ok = refine_crossing(mech, Q[k], seg_t[k], Q[k + 1], seg_t[k + 1], rows)
                if ok:
                    found.append(Singularity(mech, tsg, qs, "crossing",
                                             null_space(mech, qs, tsg, force=True)))
            elif 0 < k < done - 1 and sv[k] < 0.05 and sv[k] <= sv[k - 1] and sv[k] < sv[k + 1] \
                    and g[k - 1] * g[k] > 0:
                # Φ_q may touch rank loss without det changing sign (an over-constrained
                # model's minors vanish to second order): the least singular value. Not
                # next to an interval where det changed sign: that crossing was found above
                # (the dip in the smallest singular value is the same point)
                qs, tsg, smin = refine_minimum(mech, Q[k - 1:k + 2], seg_t[k - 1:k + 2])
                if smin < SING_RTOL:
                    found.append(Singularity(mech, tsg, qs, "crossing",
                                             null_space(mech, qs, tsg, force=True)))
        if i + done >= len(ts):
            break
        t_fail = ts[i + done]
        near = q
        if done:
            near = Q[done]
            lock = _lock_from(mech, Q[done], float(report[REPORT_REACHED]), t_fail)
            if lock is not None:
                found.append(lock)
                near = lock.q
        # where does it assemble again? near the configuration at the lock, at the
        # following sample times (least squares keeps to the same assembly mode)
        r, q_r = None, None
        for j in range(i + done, len(ts)):
            q_try, ok = assemble_near(mech, near, ts[j])
            if ok:
                r, q_r = j, q_try
                break
        if r is None:
            break
        # the lock on the far side: continue backwards from the first assembled time
        back_to = found[-1].t if found and found[-1].kind == "lock" and done else ts[max(r - 1, 0)]
        if r > 0 and back_to != ts[r]:
            lock = lock_between(mech, q_r, ts[r], back_to)
            if lock is not None:
                found.append(lock)
        i, q = r, q_r
    found.sort(key=float)
    out: list[Singularity] = []
    for s in found:
        if not out or abs(s.t - out[-1].t) > 1e-9 * max(1.0, abs(s.t)):
            out.append(s)
    return out


# -- why a solve failed ---------------------------------------------------------------------
def _drivers(mech):
    """The driving constraints, as "<number> <label>"."""
    return [f"{number} {label}" for number, _kind, label, _rows, driver
            in mech.module.CONSTRAINTS if driver]


def find_locks_near(mech, q, t, spans=(1e-6, 1e-5, 1e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3)):
    """Lock positions on either side of a time t without assembly: the nearest time on
    each side where the mechanism assembles from q (or the model's guess), then the lock
    between it and t. A list of 0, 1 or 2 Singularity."""
    out = []
    scale = max(1.0, abs(t))
    for sign in (-1.0, 1.0):
        for d in spans:
            ts = t + sign * d * scale
            q_s, ok = assemble_near(mech, q, ts)
            if ok:
                lock = lock_between(mech, q_s, ts, t)
                if lock is not None:
                    out.append(lock)
                break
    out.sort(key=float)
    return out


def explain_failure(mech, t, q, t_good=None, q_good=None):
    """Why no configuration was found at t, from the point Newton stopped at (q) and,
    after a sweep, the last configuration reached (q_good at t_good). Returns
    (headline, details, constraints involved, lock positions found): the headline a
    short clause (empty when nothing is known), the details whole sentences."""
    drivers = _drivers(mech)
    ask = f" ({'; '.join(drivers)})" if drivers else ""
    lock = None
    if t_good is not None and q_good is not None:
        lock = _lock_from(mech, q_good, t_good, t)
    q_ls, res, root = least_squares(mech, q, t)
    if lock is not None:
        # a sweep ran into a lock: its assembly mode ends there
        head = f"the assembly mode followed ends at a lock (toggle) position at t≈{lock.t:.10g}"
        details = [f"At the lock, {lock.null.describe()}: the mechanism cannot move on"]
        locks = [lock]
        if root:
            details.append(f"A configuration does exist at t={t:.10g}, but not one the "
                           "mechanism reaches by moving from the start (a new sweep from "
                           "there follows it)")
        else:
            gap = ""
            far = [s for s in find_locks_near(mech, q_ls, t)
                   if abs(s.t - lock.t) > 1e-9 * max(1.0, abs(s.t))]
            if far:
                other = min(far, key=lambda s: abs(s.t - t))
                locks.append(other)
                a, b = sorted((lock.t, other.t))
                gap = f": the mechanism has no assembly between t≈{a:.10g} and t≈{b:.10g}"
            details.append(f"The drivers{ask} ask for a configuration that cannot "
                           f"assemble{gap}")
        return head, details, tuple(lock.lock or lock.grouped), sorted(locks, key=float)
    if root:
        return ("a configuration does exist near the guess (least squares reaches it): "
                "start from a closer guess", [], (), [])
    if not np.isfinite(res):
        return ("the constraint equations are not finite there",
                ["NaN or infinite values: check parameters and drivers"], (), [])
    null = null_space(mech, q_ls, t, force=True)
    r = residual_vector(mech, q_ls, t)
    worst = [mech.constraint_labels[i] for i in np.argsort(-np.abs(r), kind="stable")[:3]
             if np.isfinite(r[i]) and abs(r[i]) > mech.tol]
    singular = null.ratio < 1e-4
    if mech.m > mech.n and not singular:
        return ("the redundant constraints are inconsistent here",
                [f"The constraints disagree: the {mech.m} equations for {mech.n} "
                 f"coordinates hold no configuration near the guess (the closest leaves a "
                 f"residual of {res:.3g} in {'; '.join(worst)})"], tuple(worst), [])
    if not singular:
        return (f"the closest configuration near the guess leaves a residual of {res:.3g}: "
                "try another guess", [f"The residual is in {'; '.join(worst)}"],
                tuple(worst), [])
    details = [f"The drivers{ask} ask for a configuration that cannot assemble: near the "
               f"guess the constraints come no closer than a residual of {res:.3g}, where "
               f"the Jacobian loses rank ({null.describe()})"]
    head = "the drivers ask for a configuration that cannot assemble"
    locks = find_locks_near(mech, q_ls, t)
    before = [s for s in locks if s.t <= t]
    after = [s for s in locks if s.t > t]
    if before and after:
        head += (f": no assembly between the lock (toggle) positions at "
                 f"t≈{before[-1].t:.10g} and t≈{after[0].t:.10g}")
        details.append(f"The mechanism reaches lock (toggle) positions at "
                       f"t≈{before[-1].t:.10g} and t≈{after[0].t:.10g} and has no assembly "
                       "between them")
    elif locks:
        head += f": it is beyond a lock (toggle) position at t≈{locks[0].t:.10g}"
        details.append(f"It is beyond a lock (toggle) position at t≈{locks[0].t:.10g}")
    return head, details, tuple(null.lock or null.grouped), locks


# -- the exceptions Mechanism raises -------------------------------------------------------
def singular_error(mech, t, q, level, where="", status=None) -> SingularError:
    """The SingularError of a configuration (q, t) whose velocities (level "velocity") or
    accelerations are not determined: the rank, the pivot ratio and the constraints that
    lose their grip, from the null space of Φ_q; or (``status`` NOT_FINITE) whose velocity
    or acceleration equations are not finite there (a driver whose rate is infinite)."""
    if status == NOT_FINITE:
        return SingularError(
            f"at t={t:.10g}{where} the {level} equations are not finite (nu or gamma holds "
            "an infinite value or NaN, a division by zero: a driver whose rate is infinite "
            "there, such as sqrt(T) at T = 0): the " f"{level} is not defined",
            t=t, constraints=(), level=level, q=np.array(q, dtype=np.float64))
    null = null_space(mech, q, t, force=True)
    names = tuple(dict.fromkeys(null.lock + null.grouped))
    return SingularError(
        f"singular configuration at t={t:.10g}{where}: the {level} is not determined by "
        f"the constraints (Jacobian rank {null.rank} of {mech.n}, pivot ratio "
        f"{null.ratio:.2g}); {null.describe()}",
        t=t, constraints=names, level=level, q=np.array(q, dtype=np.float64))


def convergence_error(mech, status, t, q, info, t_good=None, q_good=None,
                      where="") -> ConvergenceError:
    """The ConvergenceError of a failed position solve (``status`` and ``info`` as the
    generated solver left them, q where Newton stopped), saying why where it can
    (explain_failure: no assembly, lock positions, inconsistency)."""
    iters, res = int(info[INFO_ITERATIONS]), float(info[INFO_RESIDUAL])
    why = "Newton's method did not converge" if status in (NO_CONVERGENCE, GAVE_UP) else \
        "the solve produced non-finite values" if status == NOT_FINITE else f"status {status}"
    newton = f"{why} in {iters} iterations (residual {res:.3g})"
    where = where.strip()
    if where.startswith("(") and where.endswith(")"):
        where = where[1:-1]
    try:
        head, details, names, locks = explain_failure(
            mech, t, np.array(q, dtype=np.float64), t_good=t_good, q_good=q_good)
    except (ArithmeticError, ValueError, np.linalg.LinAlgError):
        head, details, names, locks = "", [], (), []
    newton += f"; {where}" if where else ""
    msg = headline(f"no configuration found at t={t:.10g}: {head}", [newton] + details) \
        if head else f"no configuration found at t={t:.10g}: {newton}"   # nothing more known
    exc = ConvergenceError(msg, t=t, iterations=iters, residual=res, constraints=names)
    exc.locks = locks
    return exc


def headline(head, details) -> str:
    """An error's text: a short first line, then each detail on a line of its own,
    indented (so that a command's one-line summary stays short and the rest is read below
    it)."""
    return head + "".join(f"\n  {d}" for d in details if d)
