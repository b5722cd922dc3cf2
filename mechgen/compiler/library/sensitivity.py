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

from .toy import (N_COORDS, N_EQS, N_PARAMS, SING_RTOL, SORTED, TINY, TURNED,
                  acceleration_rhs_p, njit, phi_p, phi_q, position_sensitivities, solve_sorted,
                  velocity_rhs_p)

# -- module body: below this line, the text as a generated module holds it --
# ---------------------------------------------------------------------------------------
# Solving for the derivatives: Φ_q X = B on the blocks of the solving order
# ---------------------------------------------------------------------------------------
SENS_OK = 0
SENS_SINGULAR = 2


@njit(cache=True)
def solve_columns(J, B, X, brow, bvar, bstart, sel, work):
    """Φ_q X = B for the columns ``sel`` of B, block by block in the solving order
    (``brow``, ``bvar``: the rows and unknowns of the blocks, block b at
    bstart[b]:bstart[b + 1]); each block factorised once (partial pivoting), each column
    then substituted. ``work``: scratch of at least (N_COORDS + 4) * N_COORDS floats.
    Returns SENS_SINGULAR where a block's pivot falls below SING_RTOL times its row's
    scale (Φ_q has lost rank: the derivatives are not determined)."""
    n = J.shape[1]
    for k in range(sel.shape[0]):
        for j in range(n):
            X[j, sel[k]] = 0.0
    for b in range(bstart.shape[0] - 1):
        s0 = bstart[b]
        m = bstart[b + 1] - s0
        # the block (m × m, row-major in work), its rows' scales, the row order, the rhs
        A = work[:m * m]
        scale = work[m * m:m * m + m]
        perm = work[m * m + m:m * m + 2 * m]
        rhs = work[m * m + 2 * m:m * m + 3 * m]
        if m == 1:
            r = brow[s0]
            a = J[r, bvar[s0]]
            s = 0.0
            for j in range(n):
                s += abs(J[r, j])
            if not (abs(a) > TINY and abs(a) > SING_RTOL * s):
                return SENS_SINGULAR
            for k in range(sel.shape[0]):
                col = sel[k]
                v = B[r, col]
                for j in range(n):
                    if J[r, j] != 0.0:
                        v -= J[r, j] * X[j, col]
                X[bvar[s0], col] = v / a
            continue
        for i in range(m):
            perm[i] = i
            s = 0.0
            for j in range(n):
                s += abs(J[brow[s0 + i], j])
            scale[i] = s
            for jj in range(m):
                A[i * m + jj] = J[brow[s0 + i], bvar[s0 + jj]]
        # LU with partial pivoting, the rows' order in perm
        for c in range(m):
            piv = c
            big = abs(A[c * m + c])
            for r in range(c + 1, m):
                if abs(A[r * m + c]) > big:
                    big = abs(A[r * m + c])
                    piv = r
            if piv != c:
                for jj in range(m):
                    A[c * m + jj], A[piv * m + jj] = A[piv * m + jj], A[c * m + jj]
                perm[c], perm[piv] = perm[piv], perm[c]
            if not (big > TINY and big > SING_RTOL * scale[int(perm[c])]):
                return SENS_SINGULAR
            for r in range(c + 1, m):
                f = A[r * m + c] / A[c * m + c]
                A[r * m + c] = f
                for jj in range(c + 1, m):
                    A[r * m + jj] -= f * A[c * m + jj]
        for k in range(sel.shape[0]):
            col = sel[k]
            for i in range(m):
                row = brow[s0 + int(perm[i])]
                v = B[row, col]
                for j in range(n):
                    if J[row, j] != 0.0:
                        v -= J[row, j] * X[j, col]   # unknowns not yet solved are 0 here
                rhs[i] = v
            for i in range(m):
                v = rhs[i]
                for jj in range(i):
                    v -= A[i * m + jj] * rhs[jj]
                rhs[i] = v
            for i in range(m - 1, -1, -1):
                v = rhs[i]
                for jj in range(i + 1, m):
                    v -= A[i * m + jj] * rhs[jj]
                rhs[i] = v / A[i * m + i]
            for i in range(m):
                X[bvar[s0 + i], col] = rhs[i]
    return SENS_OK


@njit(cache=True, inline="always")
def sensitivities_point(q, qd, qdd, t, p, level, brow, bvar, bstart, sel, DQ, DQD, DQDD,
                        J, B, work, want, sc):
    """The derivatives of q (and of q̇, q̈ up to ``level``) with respect to the parameters
    ``sel`` at a solved point into DQ, DQD, DQDD (N_COORDS × N_PARAMS; the columns not in
    sel are left as they are; ``want``: sel as N_PARAMS flags; ``sc``: trig_pairs' sin
    and cos of the coordinates TURNED). J, B and work are scratch (N_EQS × N_COORDS,
    N_EQS × N_PARAMS, solve_columns'). Dq comes from the module's
    one-pass position_sensitivities where it has one; else, and for the rates, Φ_q X = B
    is solved on the module's blocks written out (solve_sorted) where it is sorted, else
    by solve_columns; each call below passes few arrays (a call between jitted functions
    costs about as much per array as the work). Returns SENS_OK, or SENS_SINGULAR where
    Φ_q has lost rank."""
    status = -1
    if SORTED:
        status = position_sensitivities(q, sc, t, p, want, DQ)
    if status == -1:
        phi_p(q, t, p, B)
        for i in range(B.shape[0]):
            for k in range(sel.shape[0]):
                B[i, sel[k]] = -B[i, sel[k]]
        if SORTED:
            status = solve_sorted(q, t, p, B, sel, DQ)
        else:
            phi_q(q, t, p, J)
            status = solve_columns(J, B, DQ, brow, bvar, bstart, sel, work)
    if status != SENS_OK or level < 1:
        return status
    velocity_rhs_p(q, qd, t, p, DQ, sel, B)
    if SORTED:
        status = solve_sorted(q, t, p, B, sel, DQD)
    else:
        status = solve_columns(J, B, DQD, brow, bvar, bstart, sel, work)
    if status != SENS_OK or level < 2:
        return status
    acceleration_rhs_p(q, qd, qdd, t, p, DQ, DQD, sel, B)
    if SORTED:
        return solve_sorted(q, t, p, B, sel, DQDD)
    return solve_columns(J, B, DQDD, brow, bvar, bstart, sel, work)


@njit(cache=True)
def sensitivities_at(q, qd, qdd, t, p, level, sel, D, blocks, scratch):
    """sensitivities_point as one call from Python (few arguments: numba checks each):
    D (3 × N_COORDS × N_PARAMS) receives Dq, Dq̇, Dq̈ up to ``level``, NaN elsewhere;
    ``blocks`` holds brow, bvar and bstart one after the other; ``scratch`` at least
    N_EQS (N_COORDS + N_PARAMS) + (N_COORDS + 4) N_COORDS floats."""
    n = N_COORDS
    nb = blocks.shape[0] - 2 * n
    brow, bvar, bstart = blocks[:n], blocks[n:2 * n], blocks[2 * n:2 * n + nb]
    J = scratch[:N_EQS * n].reshape((N_EQS, n))
    B = scratch[N_EQS * n:N_EQS * (n + N_PARAMS)].reshape((N_EQS, N_PARAMS))
    work = scratch[N_EQS * (n + N_PARAMS):]
    for k in range(3):
        for i in range(n):
            for j in range(N_PARAMS):
                D[k, i, j] = math.nan
    sc = np.empty((2, N_COORDS))
    trig_pairs(q, sc, q, 0)
    return sensitivities_point(q, qd, qdd, t, p, level, brow, bvar, bstart, sel, D[0], D[1],
                               D[2], J, B, work, wanted(sel), sc)


@njit(cache=True, inline="always")
def trig_pairs(q, sc, last, k):
    """sc[0, i], sc[1, i] = sin q[i], cos q[i] for the coordinates TURNED: called at point
    k of a sweep whose previous point was ``last`` (sc holding its pairs), the pairs are
    turned by the step q[i] − last[i] (its sin and cos by their series, exact to rounding
    below 0.05 rad), as the fast sweep turns its own, and computed afresh every 8 points
    and after a larger step."""
    for m in range(TURNED.shape[0]):
        i = TURNED[m]
        d = q[i] - last[i]
        if k % 8 == 0 or not abs(d) <= 0.05:
            sc[0, i] = math.sin(q[i])
            sc[1, i] = math.cos(q[i])
        else:
            d2 = d * d          # (Taylor's coefficients: products, not divisions)
            sd = d + d * d2 * (-1.0 / 6 + d2 * (1.0 / 120 + d2 * (-1.0 / 5040
                                                                  + d2 * (1.0 / 362880))))
            cd = 1.0 + d2 * (-0.5 + d2 * (1.0 / 24 + d2 * (-1.0 / 720 + d2 * (
                1.0 / 40320 - d2 * (1.0 / 3628800)))))
            s, c = sc[0, i], sc[1, i]
            sc[0, i] = s * cd + c * sd
            sc[1, i] = c * cd - s * sd


@njit(cache=True)
def wanted(sel):
    """The columns ``sel`` as N_PARAMS flags."""
    want = np.zeros(N_PARAMS, dtype=np.bool_)
    for k in range(sel.shape[0]):
        want[sel[k]] = True
    return want


@njit(cache=True)
def sensitivities_rows(ts, Q, QD, QDD, p, level, brow, bvar, bstart, sel, DQ, DQD, DQDD,
                       STATUS):
    """sensitivities_point at every point k of a sweep: DQ[k] (and DQD[k], DQDD[k] up to
    ``level``), STATUS[k] its status. A point whose coordinates are not finite is left NaN
    with SENS_SINGULAR; so is a point where Φ_q has lost rank."""
    J = np.empty((N_EQS, N_COORDS))
    B = np.empty((N_EQS, N_PARAMS))
    work = np.empty((N_COORDS + 4) * N_COORDS)
    want = wanted(sel)
    sc = np.zeros((2, N_COORDS))
    turned = 0              # points since the pairs were last computed afresh
    for k in range(ts.shape[0]):
        finite = True
        for j in range(Q.shape[1]):
            if not math.isfinite(Q[k, j]):
                finite = False
        kd = k if level >= 1 else 0     # (QD, DQD: one row where the level has none)
        ka = k if level >= 2 else 0
        status = SENS_SINGULAR
        if finite:
            trig_pairs(Q[k], sc, Q[k - 1] if k > 0 else Q[k], turned)
            turned += 1
        else:
            turned = 0
        if finite and SORTED and level == 0:
            # the one pass alone (no scratch views: each array view made in this loop
            # costs reference counting, as much as the pass itself)
            status = position_sensitivities(Q[k], sc, ts[k], p, want, DQ[k])
        if finite and status == -1 or finite and not (SORTED and level == 0):
            status = sensitivities_point(Q[k], QD[kd], QDD[ka], ts[k], p, level, brow, bvar,
                                         bstart, sel, DQ[k], DQD[kd], DQDD[ka], J, B, work,
                                         want, sc)
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
