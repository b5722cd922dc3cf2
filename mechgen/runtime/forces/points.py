"""The multipliers at many solved points, from the generated module alone (no Mechanism):
what a sweep, a design table's chunk on a thread or a dask worker, and the CUDA backend's
points all share.

``solve_points`` runs the module's compiled ``force_rows`` over the points (the driver
factors and, for a sorted build, λ block by block in the reverse solving order: written out
in multipliers_point where every block has one or two rows; with ``extras`` also Φ_q, the
force terms Q_a, Q_c, I, ν and the energies, which a sweep makes only when its power,
energy or shaking is asked for), solves λ with one batched numpy solve where the module
has no blocks, and sends every point whose smallest pivot is below SING_RTOL (or a model
with more equations than coordinates) to the SVD (``svd_solve``): there λ is the
minimum-norm solution and the rows whose λ is not unique are named; where Φ_qᵀλ = Q has no
solution (a lock or toggle position with a load that would move it) the point's λ is NaN
and it is marked singular.
"""
from __future__ import annotations

import numpy as np

from ...protocol import SING_RTOL
from ..kinematics.entry import module_attr
from .directions import mark

CONSISTENT_RTOL = 1e-8     # a residual of Φ_qᵀλ = Q above this share of its size: no solution
MISSING = object()         # (a name the module does not have)


class PointForces:
    """What solve_points gives, per point k: LAM[k] (λ, NaN where singular[k]),
    FACTORS[k] (per DRIVER_ROWS); ``dependent``: the row indices whose λ is not unique
    at some point (redundant constraints); with ``extras`` also TERMS[k] (Q_a, Q_c, I
    over the coordinates), NU[k] (Φ_q q̇) and ENERGY[k] (kinetic, potential, the
    potential's explicit rate), else those have no rows."""

    def __init__(self, N, m, n, drivers, extras=True):
        rows = N if extras else 0
        self.extras = extras
        self.LAM = np.zeros((N, m))
        self.TERMS = np.zeros((rows, 3, n))
        self.NU = np.zeros((rows, m))
        self.ENERGY = np.zeros((rows, 3))
        self.FACTORS = np.zeros((N, drivers))
        self.singular = np.zeros(N, dtype=bool)
        self.dependent = set()


def has_forces(module) -> bool:
    """Whether the module was built with mass or loads (else every λ is zero)."""
    return bool(module_attr(module, "FORCES", False))


def by_blocks(module) -> bool:
    """Whether the module solves the multipliers block by block (a sorted square build;
    a module of an earlier format has multipliers_sorted only then)."""
    flag = module_attr(module, "FORCE_SORTED", MISSING)
    if flag is MISSING:
        return module_attr(module, "multipliers_sorted", MISSING) is not MISSING
    return bool(flag)


def written_out(module):
    """The module's multipliers_point where it writes the multipliers out, else None."""
    if not module_attr(module, "FORCE_POINT", True):
        return None
    return module_attr(module, "multipliers_point", None)


def svd_solve(J, rhs):
    """(λ, rank, dependent rows, consistent) for Φ_qᵀ λ = rhs by the SVD of J = Φ_q: its
    rank on the row-equilibrated J at SING_RTOL (as the kinematic solves read it), the
    minimum-norm λ, the rows whose λ is not unique (rank below the row count) and whether
    the residual is within CONSISTENT_RTOL of the equation's size."""
    scale = np.max(np.abs(J), axis=1, initial=0.0)
    scale[scale == 0] = 1.0
    s_scaled = np.linalg.svd(J / scale[:, None], compute_uv=False)
    top = s_scaled[0] if s_scaled.size and s_scaled[0] > 0 else 1.0
    rank = int(np.sum(s_scaled > SING_RTOL * top))
    u, s, vt = np.linalg.svd(J)
    k = min(rank, s.size)
    lam = u[:, :k] @ ((vt[:k] @ rhs) / s[:k])
    residual = rhs - J.T @ lam
    size = np.linalg.norm(rhs) + np.linalg.norm(np.abs(J).T @ np.abs(lam))
    dependent = ()
    if k < J.shape[0]:
        w = np.linalg.norm(u[:, k:], axis=1)
        dependent = tuple(i for i in range(J.shape[0]) if w[i] > 1e-6 * w.max())
    consistent = bool(np.all(np.isfinite(lam)) and
                      np.linalg.norm(residual) <= CONSISTENT_RTOL * size)
    return lam, rank, dependent, consistent


def solve_points(module, ts, Q, QD, QDD, p, level, extras=True) -> PointForces:
    """λ (and with ``extras`` the force terms, ν and the energies) at every point (ts[k],
    Q[k], QD[k], QDD[k]) of one parameter vector p; level "static" takes q̇ = q̈ = 0 (QD,
    QDD may then be None). A module without blocks makes the extras anyway (its λ are
    solved here from them)."""
    N, n = Q.shape
    m = int(module.N_EQS)
    blocks = by_blocks(module)
    extras = extras or not blocks
    out = PointForces(N, m, n, len(getattr(module, "DRIVER_ROWS", ())), extras)
    if not has_forces(module) or N == 0:
        return out
    Q = np.ascontiguousarray(Q, dtype=np.float64)
    if level == "static" or QD is None:
        QD = np.zeros_like(Q)
    if level == "static" or QDD is None:
        QDD = np.zeros_like(Q)
    JAC = np.empty((1 if blocks else N, m, n))      # one reused where λ comes back solved
    PIV = np.empty(N)
    ts = np.ascontiguousarray(ts, dtype=np.float64)
    QD, QDD = np.ascontiguousarray(QD), np.ascontiguousarray(QDD)
    module.force_rows(ts, Q, QD, QDD, p, JAC, out.TERMS, out.NU, out.ENERGY, out.FACTORS,
                      PIV, out.LAM)
    if extras:
        rhs = out.TERMS[:, 0] + out.TERMS[:, 1] - out.TERMS[:, 2]
    direct = (PIV >= SING_RTOL) if m == n else np.zeros(N, dtype=bool)
    if blocks:                                      # solved block by block already
        direct &= np.all(np.isfinite(out.LAM), axis=1)
    elif direct.any():
        try:
            lam = np.linalg.solve(JAC[direct].transpose(0, 2, 1), rhs[direct][..., None])[..., 0]
        except np.linalg.LinAlgError:
            direct[:] = False
        else:
            good = np.all(np.isfinite(lam), axis=1)
            out.LAM[np.flatnonzero(direct)[good]] = lam[good]
            direct[np.flatnonzero(direct)[~good]] = False
    J = np.empty((m, n))
    terms = np.empty((3, n))
    for k in np.flatnonzero(~direct):
        lam, dependent, consistent = svd_point(module, Q[k], QD[k], QDD[k], ts[k], p, J,
                                               terms, None if blocks else JAC[k],
                                               rhs[k] if extras else None)
        if consistent:
            out.LAM[k] = lam
            out.dependent.update(dependent)
        else:
            out.LAM[k] = np.nan
            out.singular[k] = True
    mark(module, ts, Q, p, out.LAM, out.singular)   # a spring or damper without direction
    return out


def svd_point(module, q, qd, qdd, t, p, J, terms, jac=None, right=None):
    """(λ, dependent rows, consistent) at one point by the SVD, where the block pivots
    fell too small: Φ_q (into J) and the right side (by force_terms, into terms) made here
    unless given as ``jac`` and ``right``."""
    if jac is None:
        module.phi_q(q, float(t), p, J)
        jac = J
    if right is None:
        module.force_terms(q, qd, qdd, float(t), p, terms)
        right = terms[0] + terms[1] - terms[2]
    lam, _, dependent, consistent = svd_solve(jac, right)
    return lam, dependent, consistent


def driver_rows(module) -> dict:
    """{constraint label: (its rows, their columns in DRIVER_ROWS or None where a row has
    none)} for every driver of the module."""
    rows_of, row = {}, 0
    drivers = tuple(getattr(module, "DRIVER_ROWS", ()))
    for _, _, label, count, driver in module.CONSTRAINTS:
        rows = tuple(range(row, row + count))
        row += count
        if driver:
            cols = tuple(drivers.index(r) for r in rows) if all(r in drivers for r in rows) \
                else None
            rows_of[label] = (rows, cols)
    return rows_of


def efforts(LAM, FACTORS, rows, cols) -> np.ndarray:
    """A driver's effort at every point from its rows' λ and factors: Σ λ_r ∂Φ_r/∂f;
    NaN, without numpy's warning, at a point where a λ or a factor is not finite (an
    infinite λ times a zero factor is no effort: the point has no force balance)."""
    lam, fac = LAM[..., list(rows)], FACTORS[..., list(cols)]
    good = np.all(np.isfinite(lam), axis=-1) & np.all(np.isfinite(fac), axis=-1)
    keep = good[..., None]
    total = np.sum(np.where(keep, lam, 0.0) * np.where(keep, fac, 0.0), axis=-1)
    return np.where(good, total, np.nan)
