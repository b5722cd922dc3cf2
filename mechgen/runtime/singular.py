"""Singular configurations: where Φ_q loses rank, lock (toggle) positions, and why a solve
finds no configuration. numpy only, on the functions of a generated module (never sympy).

A configuration is singular when the row-equilibrated Jacobian Φ_q has a pivot (or a
singular value) below ``SING_RTOL``: the velocities and accelerations are then not
determined by the constraints. Along a sweep two kinds of singular point occur:

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
"""
from __future__ import annotations

import math

import numpy as np

SING_RTOL = 1e-6


def sing_rtol(mech) -> float:
    return float(getattr(mech.module, "SING_RTOL", SING_RTOL))


# -- rank analysis ------------------------------------------------------------------------
def scaled_jacobian(mech, q, t):
    """Φ_q with each row divided by its largest entry (zero rows left alone)."""
    J = mech.jacobian(q, t)
    s = np.max(np.abs(J), axis=1, initial=0.0)
    s[s == 0] = 1.0
    return J / s[:, None]


class NullSpace:
    """What a rank loss of Φ_q involves at one configuration.

    ``rank`` (numerical, at ``rtol``), ``ratio`` (smallest/largest singular value of the
    row-equilibrated Φ_q), ``constraints`` (labels of the equations that become dependent:
    the left null space, strongest first), ``coordinates`` (the coordinates that move in
    the undetermined direction: the right null space) and ``lock`` (the equations that
    hold those coordinates: the ones that lose their grip on them)."""

    def __init__(self, rank, ratio, constraints, coordinates, lock, grouped=None):
        self.rank, self.ratio = rank, ratio
        self.constraints, self.coordinates, self.lock = tuple(constraints), tuple(coordinates), tuple(lock)
        self.grouped = tuple(grouped if grouped is not None else constraints)

    def describe(self) -> str:
        """One line: which constraint loses its grip on which coordinates, and the
        constraints whose equations become dependent."""
        parts = []
        if self.coordinates:
            what = ", ".join(self.coordinates)
            if self.lock:
                parts.append(f"{' and '.join(self.lock)} cannot fix {what}")
            else:
                parts.append(f"{what} not fixed by the constraints")
        if self.grouped:
            parts.append("constraints involved: " + "; ".join(self.grouped))
        return "; ".join(parts) if parts else "(could not tell which constraints)"

    def __repr__(self):
        return (f"NullSpace(rank={self.rank}, ratio={self.ratio:.3g}, constraints={self.constraints}, "
                f"coordinates={self.coordinates}, lock={self.lock})")


def null_space(mech, q, t, rtol=None, force=False) -> NullSpace:
    """Rank analysis of Φ_q at (q, t) by an SVD of the row-equilibrated Jacobian. With
    ``force`` the weakest direction is analysed even when it is above ``rtol`` (to say what
    a near-singular configuration involves)."""
    rtol = sing_rtol(mech) if rtol is None else rtol
    J = scaled_jacobian(mech, q, t)
    m, n = J.shape
    if not np.all(np.isfinite(J)):
        return NullSpace(0, 0.0, mech.constraint_labels, mech.coordinates, ())
    u, s, vt = np.linalg.svd(J)
    top = s[0] if s.size and s[0] > 0 else 1.0
    rank = int(np.sum(s > rtol * top))
    ratio = float(s[n - 1] / top) if s.size >= n else 0.0
    lo = rank if rank < n else (n - 1 if force else n)
    left = u[:, min(lo, m):] if m > lo else u[:, :0]
    if m > n and rank >= n and not force:
        left = u[:, n:]                      # redundant rows of an over-determined model
    right = vt[lo:, :] if lo < n else vt[:0, :]
    labels = mech.constraint_labels
    rows = _support(left, axis=1)
    cols = _support(right.T, axis=1)
    constraints = _unique(labels[i] for i in rows)
    coordinates = tuple(mech.coordinates[j] for j in cols)
    owner = constraint_of_rows(mech)
    lock = ()
    if cols:
        # the dependent rows that act on the undetermined coordinates (structurally: at a
        # lock the entry itself vanishes, so look a little away from q)
        Jp = mech.jacobian(np.asarray(q, dtype=np.float64) +
                           1e-3 * np.random.default_rng(7).standard_normal(n), t)
        acting = [i for i in rows if np.max(np.abs(Jp[i, cols])) > 1e-12]
        lock = _unique(owner[i] for i in acting)
    grouped = tuple(sorted(_unique(owner[i] for i in rows), key=_number))
    return NullSpace(rank, ratio, constraints, coordinates, lock, grouped)


def constraint_of_rows(mech):
    """For each equation row, its constraint as "<number> <label>" (from the module's
    CONSTRAINTS table; the row label when the table is missing)."""
    out = []
    for c in getattr(mech.module, "CONSTRAINTS", ()):
        out += [f"{c[0]} {c[2]}"] * int(c[3])
    if len(out) != mech.m:
        return list(mech.constraint_labels)
    return out


def _number(label):
    head = label.split(" ", 1)[0]
    return (0, int(head)) if head.isdigit() else (1, label)


def _support(vectors, axis=1):
    """Indices whose weight in the given null vectors is at least a tenth of the largest,
    strongest first."""
    if vectors.size == 0:
        return []
    w = np.max(np.abs(vectors), axis=axis)
    if not w.size or w.max() == 0:
        return []
    idx = [i for i in np.argsort(-w, kind="stable") if w[i] > 0.1 * w.max()]
    return [int(i) for i in idx]


def _unique(items):
    out = []
    for x in items:
        if x not in out:
            out.append(x)
    return tuple(out)


def independent_rows(mech, q, t):
    """N_COORDS rows of Φ_q that are independent at (q, t), in declaration order (all the
    rows of a square model)."""
    m, n = mech.m, mech.n
    if m <= n:
        return np.arange(m)
    J = scaled_jacobian(mech, q, t)
    basis, rows = [], []
    for i in range(m):
        v = J[i].copy()
        for b in basis:
            v -= (v @ b) * b
        norm = np.linalg.norm(v)
        if norm > 1e-6 * max(np.linalg.norm(J[i]), 1e-300):
            basis.append(v / norm)
            rows.append(i)
            if len(rows) == n:
                break
    return np.array(rows if len(rows) == n else range(n))


def det_indicator(mech, q, t, rows=None) -> float:
    """det Φ_q (on ``rows``) with each row scaled to unit length: a smooth function of
    (q, t) in [-1, 1] that vanishes exactly where Φ_q loses rank."""
    J = mech.jacobian(q, t)
    if rows is not None:
        J = J[rows]
    norms = np.linalg.norm(J, axis=1)
    norms[norms == 0] = 1.0
    return float(np.linalg.det(J / norms[:, None]))


# -- solving helpers (no exceptions) ------------------------------------------------------
def solve_q(mech, q, t, maxit=None, method=0, tol=None):
    """Position solve from q at t: (q, ok)."""
    q = np.array(q, dtype=np.float64)
    info = np.zeros(4)
    status = mech.module.solve_position(q, float(t), mech.p, mech.tol if tol is None else tol,
                                        mech.xtol, mech.maxit if maxit is None else maxit,
                                        method, info)
    return q, status == 0


def residual_vector(mech, q, t):
    r = np.empty(mech.m)
    mech.module.phi(np.asarray(q, dtype=np.float64), float(t), mech.p, r)
    return r


def least_squares(mech, q, t, maxit=100):
    """Levenberg-Marquardt on ‖Φ(q, t)‖² from q: (q, max|Φ|, converged to a root)."""
    q = np.array(q, dtype=np.float64)
    r = residual_vector(mech, q, t)
    if not np.all(np.isfinite(r)):
        return q, math.inf, False
    f = float(r @ r)
    lam = 1e-3
    for _ in range(maxit):
        if np.max(np.abs(r)) <= mech.tol:
            break
        J = mech.jacobian(q, t)
        g = J.T @ r
        A = J.T @ J
        d = np.diag(A).copy()
        d[d == 0] = 1.0
        improved = False
        for _try in range(30):
            try:
                dq = np.linalg.solve(A + lam * np.diag(d), -g)
            except np.linalg.LinAlgError:
                lam *= 10
                continue
            qn = q + dq
            rn = residual_vector(mech, qn, t)
            fn = float(rn @ rn) if np.all(np.isfinite(rn)) else math.inf
            if fn < f:
                q, r, lam = qn, rn, max(lam / 10, 1e-15)
                improved = f - fn > 1e-15 * f or np.max(np.abs(dq)) > 1e-13 * (1 + np.max(np.abs(q)))
                f = fn
                break
            lam *= 10
        if not improved:
            break
    res = float(np.max(np.abs(r))) if r.size else 0.0
    return q, res, res <= mech.tol


def assemble_near(mech, q, t):
    """A configuration at t near q: least squares from q (which stays in q's neighbourhood
    rather than jumping to another assembly mode as a plain Newton can), then Newton.
    Returns (q, ok)."""
    q_ls, _res, root = least_squares(mech, q, t)
    if not root:
        return q_ls, False
    return solve_q(mech, q_ls, t)


# -- locating singular points ---------------------------------------------------------------
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


def smallest_sv(mech, q, t) -> float:
    """The smallest singular value of the row-equilibrated Φ_q relative to the largest."""
    s = np.linalg.svd(scaled_jacobian(mech, q, t), compute_uv=False)
    if not s.size or not np.isfinite(s[0]) or s[0] == 0:
        return 0.0
    return float(s[min(mech.n, s.size) - 1] / s[0]) if s.size >= mech.n else 0.0


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
    constraints stop determining), ``lock`` (the equations that lose their grip on them),
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
        obj.ratio = null.ratio
        obj.null = null
        return obj

    @property
    def t(self) -> float:
        return float(self)

    @property
    def solution(self):
        from .results import Solution
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
    (count reached, Q, INFO) without raising."""
    times = np.asarray(times, dtype=np.float64)
    N = times.shape[0]
    Q, QD, QDD = np.zeros((N, mech.n)), np.zeros((N, mech.n)), np.zeros((N, mech.n))
    INFO = np.zeros((N, 7))
    done = mech.module.sweep(times, np.array(q0, dtype=np.float64), mech.p, 0, mech.tol,
                             mech.xtol, mech.maxit, 0, Q, QD, QDD, INFO)
    return int(done), Q, INFO


def lock_between(mech, q_good, t_good, t_bad):
    """The lock position between a solved configuration at t_good and a time t_bad where
    the branch does not assemble: step-controlled continuation to the last configuration
    reachable, then the augmented Newton. None when none is found."""
    done, Q, INFO = _continue(mech, q_good, [t_good, t_bad])
    if done == 2:
        return None
    if done == 0:
        return None
    return _lock_from(mech, Q[1], float(INFO[1, 5]), t_bad)


def singularities(mech, t0, t1, n=201, guess=None):
    """Every time in [t0, t1] where Φ_q loses rank along the branch the guess starts on:
    lock positions (where that branch ends: the sweep resumes on the far side of a stretch
    without assembly from the configuration at the lock) and crossings (det Φ_q changes
    sign). ``n`` sample times, refined to ~1e-12 in t. Returns a list of Singularity."""
    from .mechanism import _finite
    t0, t1 = _finite(t0, "t0"), _finite(t1, "t1")
    if isinstance(n, bool) or int(n) != n or n < 2:
        raise ValueError(f"n must be an integer >= 2, got {n!r}")
    ts = np.linspace(t0, t1, int(n))
    q = mech._start(guess)
    found: list[Singularity] = []
    i = 0
    rows = None
    while i < len(ts):
        done, Q, INFO = _continue(mech, q, ts[i:])
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
            elif 0 < k < done - 1 and sv[k] < 0.05 and sv[k] <= sv[k - 1] and sv[k] < sv[k + 1]:
                # Φ_q may touch rank loss without det changing sign (an over-constrained
                # model's minors vanish to second order): the least singular value
                qs, tsg, smin = refine_minimum(mech, Q[k - 1:k + 2], seg_t[k - 1:k + 2])
                if smin < sing_rtol(mech):
                    found.append(Singularity(mech, tsg, qs, "crossing",
                                             null_space(mech, qs, tsg, force=True)))
        if i + done >= len(ts):
            break
        t_fail = ts[i + done]
        near = q
        if done:
            near = Q[done]
            lock = _lock_from(mech, Q[done], float(INFO[done, 5]), t_fail)
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
    cons = getattr(mech.module, "CONSTRAINTS", ())
    return [f"{c[0]} {c[2]}" for c in cons if len(c) > 4 and c[4]]


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
    (text, constraints involved, lock positions found)."""
    drivers = _drivers(mech)
    ask = f" ({'; '.join(drivers)})" if drivers else ""
    lock = None
    if t_good is not None and q_good is not None:
        lock = _lock_from(mech, q_good, t_good, t)
    q_ls, res, root = least_squares(mech, q, t)
    if lock is not None:
        # a sweep ran into a lock: its assembly mode ends there
        text = [f"The assembly mode the sweep follows ends at a lock (toggle) position at "
                f"t≈{lock.t:.10g}, where {lock.null.describe()}: the mechanism cannot move on"]
        locks = [lock]
        if root:
            text.append(f"A configuration does exist at t={t:.10g}, but not one the mechanism "
                        "reaches by moving from the start (a new sweep from there follows it)")
        else:
            gap = ""
            far = [s for s in find_locks_near(mech, q_ls, t)
                   if abs(s.t - lock.t) > 1e-9 * max(1.0, abs(s.t))]
            if far:
                other = min(far, key=lambda s: abs(s.t - t))
                locks.append(other)
                a, b = sorted((lock.t, other.t))
                gap = f": the mechanism has no assembly between t≈{a:.10g} and t≈{b:.10g}"
            text.append(f"The drivers{ask} ask for a configuration that cannot assemble{gap}")
        return ". ".join(text), tuple(lock.lock or lock.grouped), sorted(locks, key=float)
    if root:
        return ("A configuration does exist near the guess (least squares reaches it): "
                "start from a closer guess", (), [])
    if not np.isfinite(res):
        return ("The constraint equations are not finite there (NaN or infinite values: "
                "check parameters and drivers)", (), [])
    null = null_space(mech, q_ls, t, force=True)
    r = residual_vector(mech, q_ls, t)
    worst = [mech.constraint_labels[i] for i in np.argsort(-np.abs(r), kind="stable")[:3]
             if np.isfinite(r[i]) and abs(r[i]) > mech.tol]
    singular = null.ratio < 1e-4
    if mech.m > mech.n and not singular:
        return (f"The constraints disagree: the {mech.m} equations for {mech.n} coordinates "
                f"hold no configuration near the guess (the closest leaves a residual of "
                f"{res:.3g} in {'; '.join(worst)}): the redundant constraints are inconsistent "
                "here", tuple(worst), [])
    if not singular:
        return (f"The closest configuration near the guess leaves a residual of {res:.3g} in "
                f"{'; '.join(worst)}; try another guess", tuple(worst), [])
    text = [f"The drivers{ask} ask for a configuration that cannot assemble: near the guess "
            f"the constraints come no closer than a residual of {res:.3g}, where the Jacobian "
            f"loses rank ({null.describe()})"]
    locks = find_locks_near(mech, q_ls, t)
    before = [s for s in locks if s.t <= t]
    after = [s for s in locks if s.t > t]
    if before and after:
        text.append(f"The mechanism reaches lock (toggle) positions at t≈{before[-1].t:.10g} and "
                    f"t≈{after[0].t:.10g} and has no assembly between them")
    elif locks:
        text.append(f"It is beyond a lock (toggle) position at t≈{locks[0].t:.10g}")
    return ". ".join(text), tuple(null.lock or null.grouped), locks
