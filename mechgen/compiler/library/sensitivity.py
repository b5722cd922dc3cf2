"""The numeric part of a sensitivity module (mechgen.compiler.sensitivities): Φ_q X = B
solved block by block on the main module's solving order for any number of right
sides (one small factorisation per block, then one substitution per column), and the
chain position → velocity → acceleration at a point and along a sweep.

Everything below the marker line goes verbatim into a sensitivity module after its model
functions (phi_q, phi_p, velocity_rhs_p, acceleration_rhs_p), which the toy model's
stand-ins replace here.
"""
import math

import numpy as np

from .toy import (N_COORDS, N_EQS, N_PARAMS, SING_RTOL, TINY, acceleration_rhs_p, njit,
                  phi_p, phi_q, velocity_rhs_p)

# -- module body: below this line, the text as a generated module holds it --
# ---------------------------------------------------------------------------------------
# Solving for the derivatives: Φ_q X = B on the blocks of the solving order
# ---------------------------------------------------------------------------------------
SENS_OK = 0
SENS_SINGULAR = 2


@njit(cache=True)
def solve_columns(J, B, X, brow, bvar, bstart, sel):
    """Φ_q X = B for the columns ``sel`` of B, block by block in the solving order
    (``brow``, ``bvar``: the rows and unknowns of the blocks, block b at
    bstart[b]:bstart[b + 1]); each block factorised once (partial pivoting), each column
    then substituted. Returns SENS_SINGULAR where a block's pivot falls below SING_RTOL
    times its row's scale (Φ_q has lost rank: the derivatives are not determined)."""
    n = J.shape[1]
    for k in range(sel.shape[0]):
        for j in range(n):
            X[j, sel[k]] = 0.0
    for b in range(bstart.shape[0] - 1):
        s0 = bstart[b]
        m = bstart[b + 1] - s0
        A = np.empty((m, m))
        perm = np.empty(m, dtype=np.int64)
        for i in range(m):
            perm[i] = i
            for jj in range(m):
                A[i, jj] = J[brow[s0 + i], bvar[s0 + jj]]
        scale = np.empty(m)
        for i in range(m):
            s = 0.0
            for j in range(n):
                s += abs(J[brow[s0 + i], j])
            scale[i] = s
        # LU with partial pivoting, rows swapped in perm
        for c in range(m):
            piv = c
            big = abs(A[c, c])
            for r in range(c + 1, m):
                if abs(A[r, c]) > big:
                    big = abs(A[r, c])
                    piv = r
            if piv != c:
                for jj in range(m):
                    A[c, jj], A[piv, jj] = A[piv, jj], A[c, jj]
                perm[c], perm[piv] = perm[piv], perm[c]
            if not (big > TINY and big > SING_RTOL * scale[perm[c]]):
                return SENS_SINGULAR
            for r in range(c + 1, m):
                f = A[r, c] / A[c, c]
                A[r, c] = f
                for jj in range(c + 1, m):
                    A[r, jj] -= f * A[c, jj]
        rhs = np.empty(m)
        for k in range(sel.shape[0]):
            col = sel[k]
            for i in range(m):
                row = brow[s0 + perm[i]]
                v = B[row, col]
                for j in range(n):
                    a = J[row, j]
                    if a != 0.0:
                        v -= a * X[j, col]   # unknowns not yet solved are 0 here
                rhs[i] = v
            # the block's own unknowns are still 0 in X: the sum above left them out
            for i in range(m):
                v = rhs[i]
                for jj in range(i):
                    v -= A[i, jj] * rhs[jj]
                rhs[i] = v
            for i in range(m - 1, -1, -1):
                v = rhs[i]
                for jj in range(i + 1, m):
                    v -= A[i, jj] * rhs[jj]
                rhs[i] = v / A[i, i]
            for i in range(m):
                X[bvar[s0 + i], col] = rhs[i]
    return SENS_OK


@njit(cache=True)
def sensitivities_point(q, qd, qdd, t, p, level, brow, bvar, bstart, sel, DQ, DQD, DQDD,
                        J, B):
    """The derivatives of q (and of q̇, q̈ up to ``level``) with respect to the parameters
    ``sel`` at a solved point into DQ, DQD, DQDD (N_COORDS × N_PARAMS; the columns not in
    sel are left as they are). J and B are scratch (N_EQS × N_COORDS, N_EQS × N_PARAMS).
    Returns SENS_OK, or SENS_SINGULAR where Φ_q has lost rank."""
    phi_q(q, t, p, J)
    phi_p(q, t, p, B)
    for i in range(B.shape[0]):
        for k in range(sel.shape[0]):
            B[i, sel[k]] = -B[i, sel[k]]
    status = solve_columns(J, B, DQ, brow, bvar, bstart, sel)
    if status != SENS_OK or level < 1:
        return status
    velocity_rhs_p(q, qd, t, p, DQ, sel, B)
    status = solve_columns(J, B, DQD, brow, bvar, bstart, sel)
    if status != SENS_OK or level < 2:
        return status
    acceleration_rhs_p(q, qd, qdd, t, p, DQ, DQD, sel, B)
    return solve_columns(J, B, DQDD, brow, bvar, bstart, sel)


@njit(cache=True)
def sensitivities_rows(ts, Q, QD, QDD, p, level, brow, bvar, bstart, sel, DQ, DQD, DQDD,
                       STATUS):
    """sensitivities_point at every point k of a sweep: DQ[k] (and DQD[k], DQDD[k] up to
    ``level``), STATUS[k] its status. A point whose coordinates are not finite is left NaN
    with SENS_SINGULAR; so is a point where Φ_q has lost rank."""
    J = np.empty((N_EQS, N_COORDS))
    B = np.empty((N_EQS, N_PARAMS))
    for k in range(ts.shape[0]):
        finite = True
        for j in range(Q.shape[1]):
            if not math.isfinite(Q[k, j]):
                finite = False
        kd = k if level >= 1 else 0     # (QD, DQD: one row where the level has none)
        ka = k if level >= 2 else 0
        status = SENS_SINGULAR
        if finite:
            status = sensitivities_point(Q[k], QD[kd], QDD[ka], ts[k], p, level, brow, bvar,
                                         bstart, sel, DQ[k], DQD[kd], DQDD[ka], J, B)
        STATUS[k] = status
        if status != SENS_OK:
            for j in range(DQ.shape[1]):
                for c in range(sel.shape[0]):
                    DQ[k, j, sel[c]] = math.nan
                    if level >= 1:
                        DQD[k, j, sel[c]] = math.nan
                    if level >= 2:
                        DQDD[k, j, sel[c]] = math.nan
    return 0
