"""The forces of a generated module with masses or loads: the multipliers block by block,
forward dynamics (the accelerations of a mechanism with drivers set free, and its compiled
integrator), and the compiled loops over the points of a sweep and the designs of a table
(the loops that solve the multipliers in a table's own sweeps: force_designs.py).

The renderer copies the body below the marker into a module built with mass or loads,
after its own force functions (force_terms, energies, driver_factors, mass_matrix, and
where every block has one or two rows multipliers_point) and its constants FORCE_SORTED
(a sorted square build: Φ_q's blocks FORCE_BLOCK_START, FORCE_BLOCK_ROWS, FORCE_BLOCK_COLS
in the solving order) and FORCE_POINT (multipliers_point written out). The code branches
on those two constants, which numba folds. toy.py stands for them here (a model without
masses: every force is zero), so that this file imports and lints on its own; the
numbers are tested through generated modules (tests/test_forces.py, test_simulate.py,
test_andrews.py, test_force_tables.py).
"""
import math

import numpy as np

from .linalg import _fp_solve
from .solve import pivot_ratio
from .toy import (FORCE_BLOCK_COLS, FORCE_BLOCK_ROWS, FORCE_BLOCK_START, FORCE_POINT,
                  FORCE_SORTED, N_COORDS, N_EQS, SING_RTOL, driver_factors,
                  energies, force_terms, gamma, mass_matrix, multipliers_point, njit, phi_q)

# -- module body: below this line, the text as a generated module holds it --
# ---------------------------------------------------------------------------------------
# Forces: the multipliers block by block, forward dynamics, the loops over points
# ---------------------------------------------------------------------------------------
@njit(cache=True)
def _cholesky(A, rtol):
    """A = L Lᵀ in place (L in the lower triangle) for a symmetric A. False, with A
    spoiled, where A is not positive definite to rtol: a pivot not above rtol times the
    largest diagonal entry (a body without mass or inertia, a coordinate without either)."""
    n = A.shape[0]
    big = 0.0
    for i in range(n):
        big = max(big, abs(A[i, i]))
    if not big > 0.0:
        return False
    for j in range(n):
        d = A[j, j]
        for k in range(j):
            d -= A[j, k] * A[j, k]
        if not d > rtol * big:
            return False
        d = math.sqrt(d)
        A[j, j] = d
        for i in range(j + 1, n):
            s = A[i, j]
            for k in range(j):
                s -= A[i, k] * A[j, k]
            A[i, j] = s / d
    return True


@njit(cache=True)
def _cholesky_solve(L, x):
    """x = (L Lᵀ)⁻¹ x in place, L from _cholesky."""
    n = L.shape[0]
    for i in range(n):
        s = x[i]
        for k in range(i):
            s -= L[i, k] * x[k]
        x[i] = s / L[i, i]
    for i in range(n - 1, -1, -1):
        s = x[i]
        for k in range(i + 1, n):
            s -= L[k, i] * x[k]
        x[i] = s / L[i, i]


@njit(cache=True)
def _eliminate(_A, _y, _k):
    """_A[:_k, :_k] x = _y[:_k] by elimination with partial pivoting, x into _y: the
    smallest pivot met, 0.0 at the first that is zero (_y then not to be used)."""
    _worst = 1.0
    for _e in range(_k):                     # partial pivoting down column _e
        _piv = _e
        for _a in range(_e + 1, _k):
            if abs(_A[_a, _e]) > abs(_A[_piv, _e]):
                _piv = _a
        _worst = min(_worst, abs(_A[_piv, _e]))
        if not abs(_A[_piv, _e]) > 0.0:
            return 0.0
        if _piv != _e:
            for _c in range(_k):
                _A[_e, _c], _A[_piv, _c] = _A[_piv, _c], _A[_e, _c]
            _y[_e], _y[_piv] = _y[_piv], _y[_e]
        for _a in range(_e + 1, _k):
            _f = _A[_a, _e] / _A[_e, _e]
            for _c in range(_e, _k):
                _A[_a, _c] -= _f * _A[_e, _c]
            _y[_a] -= _f * _y[_e]
    for _e in range(_k - 1, -1, -1):         # back substitution
        _v = _y[_e]
        for _c in range(_e + 1, _k):
            _v -= _A[_e, _c] * _y[_c]
        _y[_e] = _v / _A[_e, _e]
    return _worst


@njit(cache=True)
def multipliers_sorted(_J, _rhs, _lam, _A, _y, _r):
    """Φ_qᵀ λ = _rhs block by block in the reverse of the solving order: Φ_q is block
    lower-triangular in it, so Φ_qᵀ is block upper-triangular. Each block's equations (its
    coordinates' columns) are solved by elimination with partial pivoting on its rows
    scaled by their largest entry in Φ_q; returns the smallest pivot met (below SING_RTOL
    the caller solves Φ_q's rank instead: _lam is then not to be used). _A (N_COORDS ×
    N_COORDS), _y and _r (N_COORDS) are workspace."""
    for _c in range(_rhs.shape[0]):
        _r[_c] = _rhs[_c]
    _worst = 1.0
    for _b in range(FORCE_BLOCK_START.shape[0] - 2, -1, -1):
        _s0 = FORCE_BLOCK_START[_b]
        _k = FORCE_BLOCK_START[_b + 1] - _s0
        for _e in range(_k):
            _i = FORCE_BLOCK_ROWS[_s0 + _e]
            _size = 0.0
            for _c in range(_J.shape[1]):
                _size = max(_size, abs(_J[_i, _c]))
            if not _size > 0.0:
                return 0.0
            for _a in range(_k):
                _A[_a, _e] = _J[_i, FORCE_BLOCK_COLS[_s0 + _a]] / _size
        for _a in range(_k):
            _y[_a] = _r[FORCE_BLOCK_COLS[_s0 + _a]]
        _p = _eliminate(_A, _y, _k)             # _y: the block's scaled multipliers
        _worst = min(_worst, _p)
        if not _p > 0.0:
            return 0.0
        for _e in range(_k):
            _i = FORCE_BLOCK_ROWS[_s0 + _e]
            _size = 0.0
            for _c in range(_J.shape[1]):
                _size = max(_size, abs(_J[_i, _c]))
            _lam[_i] = _y[_e] / _size
            for _c in range(_J.shape[1]):
                _r[_c] -= _J[_i, _c] * _lam[_i]
    return _worst


@njit(cache=True)
def coordinates_sorted(_J, _rhs, _x, _A, _y):
    """Φ_q x = _rhs block by block in the solving order (Φ_q is block lower-triangular in
    it): each block's rows, less what the blocks before it carry, scaled by their largest
    entry, by elimination with partial pivoting. Returns the smallest pivot met (below
    SING_RTOL the caller takes another way: _x is then not to be used). _A (N_COORDS ×
    N_COORDS) and _y (N_COORDS) are workspace."""
    for _c in range(_x.shape[0]):
        _x[_c] = 0.0
    _worst = 1.0
    for _b in range(FORCE_BLOCK_START.shape[0] - 1):
        _s0 = FORCE_BLOCK_START[_b]
        _k = FORCE_BLOCK_START[_b + 1] - _s0
        for _e in range(_k):
            _i = FORCE_BLOCK_ROWS[_s0 + _e]
            _size = 0.0
            _v = _rhs[_i]
            for _c in range(_J.shape[1]):
                _size = max(_size, abs(_J[_i, _c]))
                _v -= _J[_i, _c] * _x[_c]         # the blocks solved: the others are 0
            if not _size > 0.0:
                return 0.0
            for _a in range(_k):
                _A[_e, _a] = _J[_i, FORCE_BLOCK_COLS[_s0 + _a]] / _size
            _y[_e] = _v / _size
        _p = _eliminate(_A, _y, _k)
        _worst = min(_worst, _p)
        if not _p > 0.0:
            return 0.0
        for _a in range(_k):
            _x[FORCE_BLOCK_COLS[_s0 + _a]] = _y[_a]
    return _worst


@njit(cache=True)
def _embedded(_J, _g, _M, _z, keep, _f, qdd, lam):
    """free_accelerations on the sorted blocks (the square Φ_q with the freed rows): q̈ =
    x0 + Σ u_k T_k, where Φ_q x0 = γ on the rows kept (0 on the freed ones) and Φ_q T_k =
    e_k on freed row k, so that every such q̈ keeps the constraints still acting; the _f
    accelerations u of the freed rows from the reduced equations T M Tᵀ u = T (Q − h −
    M x0); then Φ_qᵀ λ = Q − h − M q̈ by multipliers_sorted (λ is 0 on the freed rows).
    Four block-sorted solves and an _f × _f system instead of the whole saddle point.
    False where a pivot falls below √SING_RTOL (a configuration where the freed rows do
    not drive the mechanism, or near a lock of the rows kept): the caller takes the general
    way, whose Φ_C M⁻¹ Φ_Cᵀ has the squares of these pivots and so stops at a lock (at
    SING_RTOL) as close to it as this way would have. At SING_RTOL here, a prescribed
    motion reaching a dead centre was bounced back by a spike of acceleration a few 1e-6
    from it, unseen by either way."""
    _n = N_COORDS
    _A = np.empty((_n, _n))
    _y = np.empty(_n)
    _r = np.empty(_n)
    _x0 = np.empty(_n)
    for _i in range(_n):
        _r[_i] = _g[_i] if keep[_i] else 0.0
    if not coordinates_sorted(_J, _r, _x0, _A, _y) >= SING_RTOL ** 0.5:
        return False
    _T = np.empty((_f, _n))
    _k = 0
    for _i in range(_n):
        if not keep[_i]:
            for _j in range(_n):
                _r[_j] = 0.0
            _r[_i] = 1.0
            if not coordinates_sorted(_J, _r, _T[_k], _A, _y) >= SING_RTOL ** 0.5:
                return False
            _k += 1
    _MT = np.empty((_f, _n))
    for _a in range(_f):
        for _j in range(_n):
            _s = 0.0
            for _l in range(_n):
                _s += _M[_j, _l] * _T[_a, _l]
            _MT[_a, _j] = _s
    for _j in range(_n):                        # Q − h − M x0
        _s = _z[_j]
        for _l in range(_n):
            _s -= _M[_j, _l] * _x0[_l]
        _r[_j] = _s
    _R = np.empty((_f, _f))
    _v = np.empty(_f)
    for _a in range(_f):
        _s = 0.0
        for _j in range(_n):
            _s += _T[_a, _j] * _r[_j]
        _v[_a] = _s
        for _b in range(_f):
            _s = 0.0
            for _j in range(_n):
                _s += _T[_a, _j] * _MT[_b, _j]
            _R[_a, _b] = _s
    _u = np.empty(_f)
    if _fp_solve(_R, _v, _u, SING_RTOL) < _f:
        return False
    for _j in range(_n):
        _s = _x0[_j]
        for _a in range(_f):
            _s += _u[_a] * _T[_a, _j]
        qdd[_j] = _s
    for _j in range(_n):                        # Q − h − M q̈
        _s = _z[_j]
        for _l in range(_n):
            _s -= _M[_j, _l] * qdd[_l]
        _x0[_j] = _s
    if not multipliers_sorted(_J, _x0, lam, _A, _y, _r) >= SING_RTOL:
        return False
    for _i in range(_n):
        if not keep[_i]:
            lam[_i] = 0.0
    return True


@njit(cache=True)
def free_accelerations(q, qd, t, p, keep, qdd, lam):
    """Forward dynamics (mechgen's simulate): q̈ and λ of M q̈ + Φ_Cᵀ λ_C = Q_a + Q_c − h,
    Φ_C q̈ = γ_C, C the rows where keep is True (every row but those of the drivers set
    free); h from force_terms at q̈ = 0, M from mass_matrix. Where M is positive definite
    (every body has mass and inertia), by its Cholesky factor: the c × c system
    Φ_C M⁻¹ Φ_Cᵀ λ_C = Φ_C M⁻¹ (Q − h) − γ_C, then q̈ = M⁻¹ (Q − h − Φ_Cᵀ λ_C); else the
    whole saddle-point system. Both by the rank-revealing elimination; lam is 0 on the
    rows not kept. Returns the rank: below N_COORDS + len(C) the constraints lock or are
    redundant (the runtime says which)."""
    _n = N_COORDS
    _c = 0
    for _i in range(N_EQS):
        if keep[_i]:
            _c += 1
    _h = np.empty((3, _n))
    _z = np.zeros(_n)
    force_terms(q, qd, _z, t, p, _h)            # at q̈ = 0: Q_a, Q_c and h
    for _j in range(_n):
        _z[_j] = _h[0, _j] + _h[1, _j] - _h[2, _j]
    _M = np.empty((_n, _n))
    mass_matrix(q, t, p, _M)
    _J = np.empty((N_EQS, _n))
    _g = np.empty(N_EQS)
    phi_q(q, t, p, _J)
    gamma(q, qd, t, p, _g)
    _rows = np.empty(_c, dtype=np.int64)
    _r = 0
    for _i in range(N_EQS):
        if keep[_i]:
            _rows[_r] = _i
            _r += 1
    if FORCE_SORTED and _c < _n and _embedded(_J, _g, _M, _z, keep, _n - _c, qdd, lam):
        return _n + _c
    _x = np.empty(_n + _c)
    _L = _M.copy()
    if _cholesky(_L, SING_RTOL):
        _Y = np.empty((_c, _n))                 # row a: M⁻¹ times kept row a of Φ_q
        for _a in range(_c):
            for _j in range(_n):
                _Y[_a, _j] = _J[_rows[_a], _j]
            _cholesky_solve(_L, _Y[_a])
        _cholesky_solve(_L, _z)                 # M⁻¹ (Q − h)
        _W = np.empty((_c, _c))
        _w = np.empty(_c)
        for _a in range(_c):
            _s = -_g[_rows[_a]]
            for _j in range(_n):
                _s += _J[_rows[_a], _j] * _z[_j]
            _w[_a] = _s
            for _k in range(_c):
                _s = 0.0
                for _j in range(_n):
                    _s += _J[_rows[_a], _j] * _Y[_k, _j]
                _W[_a, _k] = _s
        _rank = _n + _fp_solve(_W, _w, _x[_n:], SING_RTOL)
        for _j in range(_n):
            _s = _z[_j]
            for _a in range(_c):
                _s -= _Y[_a, _j] * _x[_n + _a]
            _x[_j] = _s
    else:
        _A = np.zeros((_n + _c, _n + _c))
        _b = np.zeros(_n + _c)
        for _j in range(_n):
            _b[_j] = _z[_j]
            for _k in range(_n):
                _A[_j, _k] = _M[_j, _k]
        for _a in range(_c):
            for _j in range(_n):
                _A[_n + _a, _j] = _J[_rows[_a], _j]
                _A[_j, _n + _a] = _J[_rows[_a], _j]
            _b[_n + _a] = _g[_rows[_a]]
        _rank = _fp_solve(_A, _b, _x, SING_RTOL)
    for _j in range(_n):
        qdd[_j] = _x[_j]
    for _i in range(N_EQS):
        lam[_i] = 0.0
    for _a in range(_c):
        lam[_rows[_a]] = _x[_n + _a]
    return _rank


@njit(cache=True)
def _free_rates(y, t, p, keep, c, dy):
    """dy = (q̇, q̈) of the state y = (q, q̇) (free_accelerations); False where the
    equations of motion lose rank."""
    _n = N_COORDS
    _qdd = np.empty(_n)
    _lam = np.empty(N_EQS)
    _rank = free_accelerations(y[:_n], y[_n:], t, p, keep, _qdd, _lam)
    for _j in range(_n):
        dy[_j] = y[_n + _j]
        dy[_n + _j] = _qdd[_j]
    return _rank >= _n + c


@njit(cache=True)
def integrate_span(y, t0, t1, p, keep, rtol, atol, max_step, max_evals, stats):
    """Integrate the state y = (q, q̇) in place from t0 to t1 by the Dormand–Prince 5(4)
    pair with its error control (mechgen's simulate, method "dopri5": the steps of scipy's
    RK45, compiled). stats: in [0] the first step to try (0: choose one), out [0] the step
    to try next, [1] steps taken, [2] evaluations, [3] the time reached. Returns 0 (t1
    reached), 1 (the equations of motion lose rank at stats[3]), 2 (max_evals spent) or
    3 (the step fell below round-off at stats[3])."""
    _m = y.shape[0]
    _c = 0
    for _i in range(N_EQS):
        if keep[_i]:
            _c += 1
    _k = np.empty((7, _m))
    _z = np.empty(_m)
    _t = t0
    _span = t1 - t0
    _dir = 1.0 if _span >= 0.0 else -1.0
    _evals = 0
    _steps = 0
    stats[3] = t0
    if not _free_rates(y, _t, p, keep, _c, _k[0]):
        return 1
    _evals += 1
    _h = abs(stats[0])
    if not _h > 0.0:                    # Hairer's starting step: a first-order guess
        _d0 = 0.0
        _d1 = 0.0
        for _i in range(_m):
            _sc = atol + rtol * abs(y[_i])
            _d0 += (y[_i] / _sc) ** 2
            _d1 += (_k[0, _i] / _sc) ** 2
        _d0 = math.sqrt(_d0 / _m)
        _d1 = math.sqrt(_d1 / _m)
        _h = 1e-6 if _d0 < 1e-5 or _d1 < 1e-5 else 0.01 * _d0 / _d1
        _h = min(_h, abs(_span))
    _h = min(_h, max_step)
    _a = (
        (0.2, 0.0, 0.0, 0.0, 0.0, 0.0),
        (3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0),
        (44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0),
        (19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0),
        (9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0,
         0.0),
        (35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0),
    )
    _cs = (0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0)
    _e = (71.0 / 57600.0, 0.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0,
          22.0 / 525.0, -1.0 / 40.0)
    _rejected = False
    while _dir * (t1 - _t) > 0.0:
        if _evals >= max_evals:
            stats[0] = _h
            stats[1] = _steps
            stats[2] = _evals
            stats[3] = _t
            return 2
        if _h < 10.0 * abs(_t) * 2.2e-16:
            stats[3] = _t
            return 3
        _last = _h >= _dir * (t1 - _t)
        _free = _h                      # the step the control chose, before t1 cut it
        if _last:
            _h = _dir * (t1 - _t)
        _hs = _dir * _h
        for _s in range(6):
            for _i in range(_m):
                _v = y[_i]
                for _r in range(_s + 1):
                    _v += _hs * _a[_s][_r] * _k[_r, _i]
                _z[_i] = _v
            if not _free_rates(_z, _t + _cs[_s] * _hs, p, keep, _c, _k[_s + 1]):
                stats[3] = _t + _cs[_s] * _hs
                return 1
            _evals += 1
        _err = 0.0                      # _z holds the fifth-order solution (FSAL)
        for _i in range(_m):
            _d = 0.0
            for _s in range(7):
                _d += _e[_s] * _k[_s, _i]
            _sc = atol + rtol * max(abs(y[_i]), abs(_z[_i]))
            _err += (_hs * _d / _sc) ** 2
        _err = math.sqrt(_err / _m)
        if _err <= 1.0:
            _t = t1 if _last else _t + _hs
            for _i in range(_m):
                y[_i] = _z[_i]
                _k[0, _i] = _k[6, _i]
            _steps += 1
            _grow = 10.0 if _err == 0.0 else min(10.0, 0.9 * _err ** -0.2)
            if _rejected:
                _grow = min(1.0, _grow)
            _rejected = False
            _h = _h * _grow
            if _last:                   # the next span starts from the step chosen here
                _h = max(_h, _free)
            _h = min(_h, max_step)
        else:
            _h = _h * max(0.2, 0.9 * _err ** -0.2)
            _rejected = True
    stats[0] = _h
    stats[1] = _steps
    stats[2] = _evals
    stats[3] = _t
    return 0


@njit(cache=True, nogil=True)
def force_rows(ts, Q, QD, QDD, p, JAC, TERMS, NU, ENERGY, FACTORS, PIV, LAM):
    """The multipliers of a sweep at each point k (a static sweep passes zero velocities
    and accelerations), the driver factors, and the smallest pivot met solving them block
    by block (multipliers_point where the module writes them out, FORCE_POINT, else
    multipliers_sorted), or on an unsorted build (not FORCE_SORTED) the pivot ratio of
    Φ_q (the runtime solves the multipliers from JAC and TERMS). It releases the GIL: a
    design table's
    threads solve their chunks' multipliers at once. With TERMS of a row per point (else none:
    what power, energy and shaking need is made only when asked) also Φ_q into JAC (one
    row reused for every point, or a row each), the force terms, ν = Φ_q q̇ and the
    energies."""
    _n = Q.shape[1]
    _extras = TERMS.shape[0] == ts.shape[0]
    _terms = np.empty((3, _n))
    _rhs = np.empty(_n)
    _A = np.empty((_n, _n))
    _y = np.empty(_n)
    _r = np.empty(_n)
    for k in range(ts.shape[0]):
        t = ts[k]
        driver_factors(Q[k], t, p, FACTORS[k])
        if FORCE_POINT:
            PIV[k] = multipliers_point(Q[k], QD[k], QDD[k], t, p, LAM[k])
            if not _extras:
                continue
        _w = k if JAC.shape[0] == ts.shape[0] else 0
        phi_q(Q[k], t, p, JAC[_w])
        _T = TERMS[k] if _extras else _terms
        force_terms(Q[k], QD[k], QDD[k], t, p, _T)
        if _extras:
            for _i in range(NU.shape[1]):    # ν = Φ_q q̇ as solved (both sides of a switch)
                NU[k, _i] = 0.0
                for _j in range(_n):
                    NU[k, _i] += JAC[_w, _i, _j] * QD[k, _j]
            energies(Q[k], QD[k], t, p, ENERGY[k])
        if FORCE_POINT:
            continue
        if FORCE_SORTED:
            for _j in range(_rhs.shape[0]):
                _rhs[_j] = _T[0, _j] + _T[1, _j] - _T[2, _j]
            PIV[k] = multipliers_sorted(JAC[_w], _rhs, LAM[k], _A, _y, _r)
        else:
            PIV[k] = pivot_ratio(Q[k], t, p)


@njit(cache=True, nogil=True)
def force_rows_designs(ts, Q, QD, QDD, P, done, FACTORS, PIV, LAM):
    """force_rows for every design d of a design table (Q[d], ..., its parameters P[d])
    over the times it solved (done[d]), without the extras: a chunk of designs in one
    call, the GIL released throughout (the threads of a table at the force levels)."""
    _n = Q.shape[2]
    _jac = np.empty((1, LAM.shape[2], _n))
    _terms = np.empty((0, 3, _n))
    _nu = np.empty((0, LAM.shape[2]))
    _energy = np.empty((0, 3))
    for _d in range(Q.shape[0]):
        _k = done[_d]
        if _k > 0:
            force_rows(ts[:_k], Q[_d, :_k], QD[_d, :_k], QDD[_d, :_k], P[_d], _jac, _terms,
                       _nu, _energy, FACTORS[_d, :_k], PIV[_d, :_k], LAM[_d, :_k])
