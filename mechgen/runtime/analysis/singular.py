"""Rank analysis of Φ_q at one configuration, and solving helpers that never raise.

A configuration is singular when the row-equilibrated Jacobian Φ_q has a pivot (or a
singular value) below ``SING_RTOL`` (mechgen.protocol): the velocities and accelerations
are then not determined by the constraints. ``null_space`` says which constraints become
dependent there and which coordinates they stop fixing; ``det_indicator`` and
``smallest_sv`` measure how far a configuration is from that along a branch.

The search for lock positions and crossings along a branch, and the explanation of a
failed solve, build on these in mechgen.runtime.analysis.locks. numpy only, on the functions of a
generated module (never sympy).
"""
from __future__ import annotations

import math

import numpy as np

from ...protocol import METHOD_AUTO, OK, POINT_INFO_SIZE, SING_RTOL


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
    rtol = SING_RTOL if rtol is None else rtol
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
    rows = support(left, axis=1)
    cols = support(right.T, axis=1)
    constraints = unique(labels[i] for i in rows)
    coordinates = tuple(mech.coordinates[j] for j in cols)
    owner = constraint_of_rows(mech)
    lock = ()
    if cols:
        # the dependent rows that act on the undetermined coordinates (structurally: at a
        # lock the entry itself vanishes, so look a little away from q)
        Jp = mech.jacobian(np.asarray(q, dtype=np.float64) +
                           1e-3 * np.random.default_rng(7).standard_normal(n), t)
        acting = [i for i in rows if np.max(np.abs(Jp[i, cols])) > 1e-12]
        lock = unique(owner[i] for i in acting)
    grouped = tuple(sorted(unique(owner[i] for i in rows), key=_number))
    return NullSpace(rank, ratio, constraints, coordinates, lock, grouped)


def constraint_of_rows(mech):
    """For each equation row, its constraint as "<number> <label>" (from the module's
    CONSTRAINTS table: number, kind, label, rows, driver)."""
    out = []
    for number, _kind, label, rows, _driver in mech.module.CONSTRAINTS:
        out += [f"{number} {label}"] * int(rows)
    return out


def _number(label):
    head = label.split(" ", 1)[0]
    return (0, int(head)) if head.isdigit() else (1, label)


def support(vectors, axis=1):
    """Indices whose weight in the given null vectors is at least a tenth of the largest,
    strongest first."""
    if vectors.size == 0:
        return []
    w = np.max(np.abs(vectors), axis=axis)
    if not w.size or w.max() == 0:
        return []
    idx = [i for i in np.argsort(-w, kind="stable") if w[i] > 0.1 * w.max()]
    return [int(i) for i in idx]


def unique(items):
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
def solve_q(mech, q, t, maxit=None, method=METHOD_AUTO, tol=None):
    """Position solve from q at t: (q, ok)."""
    q = np.array(q, dtype=np.float64)
    info = np.zeros(POINT_INFO_SIZE)
    status = mech.module.solve_position(q, float(t), mech.p, mech.tol if tol is None else tol,
                                        mech.xtol, mech.maxit if maxit is None else maxit,
                                        method, info)
    return q, status == OK


def residual_vector(mech, q, t):
    """Φ(q, t), every equation."""
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


def smallest_sv(mech, q, t) -> float:
    """The smallest singular value of the row-equilibrated Φ_q relative to the largest."""
    s = np.linalg.svd(scaled_jacobian(mech, q, t), compute_uv=False)
    if not s.size or not np.isfinite(s[0]) or s[0] == 0:
        return 0.0
    return float(s[min(mech.n, s.size) - 1] / s[0]) if s.size >= mech.n else 0.0
