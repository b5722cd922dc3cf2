"""The compiled loop of a clearance's nonlinear truth (mechgen.runtime.sensitivity.clearance):
every point of every Monte Carlo design moved onto Φ(q, t, p) = offset by Newton, its
rates solved again from Φ_q q̇ = ν and Φ_q q̈ = γ (neither holds the offset, constant in
time). The module's own phi, phi_q, nu and gamma come in as arguments (numba compiles the
loop once per module); a module in the plain tier runs ``correct_designs.py_func`` with
its plain functions. Imported when a Monte Carlo band with a clearance first asks."""
from __future__ import annotations

import numpy as np
from numba import njit, prange


@njit(cache=True)
def lu_solve(A, b, x):
    """x with A x = b by Gaussian elimination with partial pivoting (A and b are
    overwritten); False where a pivot vanishes against its column's largest entry."""
    n = A.shape[0]
    for c in range(n):
        piv, big = c, abs(A[c, c])
        for r in range(c + 1, n):
            if abs(A[r, c]) > big:
                piv, big = r, abs(A[r, c])
        if not big > 1e-300:
            return False
        if piv != c:
            for j in range(n):
                A[c, j], A[piv, j] = A[piv, j], A[c, j]
            b[c], b[piv] = b[piv], b[c]
        for r in range(c + 1, n):
            f = A[r, c] / A[c, c]
            if f != 0.0:
                for j in range(c, n):
                    A[r, j] -= f * A[c, j]
                b[r] -= f * b[c]
    for i in range(n - 1, -1, -1):
        v = b[i]
        for j in range(i + 1, n):
            v -= A[i, j] * x[j]
        x[i] = v / A[i, i]
    return True


@njit(parallel=True)
def correct_designs(phi, phi_q, nu, gamma, ts, P, OFF, level, tol, maxit, Q, QD, QDD, ok):
    """Each design d with ok[d]: every point k of Q[d] (a configuration without the
    offset, the start) moved onto Φ(q, ts[k], P[d]) = OFF[d] (max-norm residual <= tol in
    at most maxit Newton steps), QD[d, k] and QDD[d, k] solved again up to ``level``;
    ok[d] cleared where a point does not converge or Φ_q is singular there."""
    n = Q.shape[2]
    for d in prange(Q.shape[0]):       # the designs on every core, each its own scratch
        if not ok[d]:
            continue
        r = np.empty(n)
        J = np.empty((n, n))
        dx = np.empty(n)
        rhs = np.empty(n)
        shift = np.zeros(n)     # the last point's correction: the next one's first guess
        start = np.empty(n)
        p = P[d]
        for k in range(Q.shape[1]):
            q = Q[d, k]
            t = ts[k]
            for i in range(n):
                start[i] = q[i]
                q[i] += shift[i]
            done = False
            for it in range(maxit + 1):
                phi(q, t, p, r)
                big = 0.0
                for i in range(n):
                    r[i] = OFF[d, i] - r[i]
                    big = max(big, abs(r[i]))
                if not big <= tol * 1e12:       # NaN, or far off: no convergence
                    break
                if big <= tol:
                    done = True
                    break
                if it == maxit:
                    break
                phi_q(q, t, p, J)
                if not lu_solve(J, r, dx):
                    break
                for i in range(n):
                    q[i] += dx[i]
            for i in range(n):
                shift[i] = q[i] - start[i]
            if done and level >= 1:
                phi_q(q, t, p, J)
                nu(q, t, p, rhs)
                done = lu_solve(J, rhs, QD[d, k])
            if done and level >= 2:
                phi_q(q, t, p, J)
                gamma(q, QD[d, k], t, p, rhs)
                done = lu_solve(J, rhs, QDD[d, k])
            if not done:
                ok[d] = False
                break
    return 0
