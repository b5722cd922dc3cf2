"""Independent baselines for the quick-return of seed 001 (longitud 3, velocidad 2π).

- ``hand_sorted_sweep``: the sorted algorithm written by hand in numba, as PERFORMANCE.md
  describes it: Th2 explicit, 1-unknown Newtons for Th3, Th4 and X4, Y4 explicit. The
  velocity and acceleration formulas use Th4 = 0 (its derivatives vanish), as a hand
  derivation would.
- ``hand_closed_sweep``: the same mechanism in closed form (atan2, square roots, the
  derivatives of those formulas): the fastest loop one writes by hand;
  ``hand_closed_sweep_full`` the same formulas filling every coordinate's rows, as a
  sweep of mechgen returns them.
- ``reference(t)``: closed form evaluated with mpmath at 50 digits — positions, velocities
  and accelerations (derivatives of the closed form by mpmath.diff).
- ``lambdify_fsolve``: what most users write: sympy.lambdify + scipy.optimize.fsolve.
"""
from __future__ import annotations

import math

import mpmath
from numba import njit, prange

L = 3.0
W = 2 * math.pi


@njit(cache=True)
def hand_sorted_sweep(ts, level, tol, Q):
    """Q[k] = (Th3, X4, Th3d, X4d, Th3dd, X4dd) at ts[k]; Newton per unknown, warm start with
    a Taylor predictor from the previous point's velocity and acceleration."""
    return hand_sorted_sweep_of(ts, L, level, tol, Q)


@njit(cache=True)
def hand_designs(ts, lengths, level, tol, Q):
    """A design table by hand, one core: hand_sorted_sweep_of for every crank length
    (Q[d] its sweep)."""
    for d in range(lengths.shape[0]):
        hand_sorted_sweep_of(ts, lengths[d], level, tol, Q[d])
    return Q


@njit(cache=True, parallel=True)
def hand_designs_prange(ts, lengths, level, tol, Q):
    """hand_designs over every core (numba prange over the designs)."""
    for d in prange(lengths.shape[0]):
        hand_sorted_sweep_of(ts, lengths[d], level, tol, Q[d])
    return Q


@njit(cache=True)
def hand_sorted_sweep_of(ts, L, level, tol, Q):
    """hand_sorted_sweep with crank length L."""
    th3, x4, th4 = -0.5, 6.0, 0.0
    th3d = x4d = th3dd = x4dd = 0.0
    for k in range(ts.shape[0]):
        t = ts[k]
        if k > 0:
            h = t - ts[k - 1]
            th3 += h * (th3d + 0.5 * h * th3dd)
            x4 += h * (x4d + 0.5 * h * x4dd)
        th2 = W * t
        c2, s2 = math.cos(th2), math.sin(th2)
        px, py = L * c2, 5.0 + L * s2            # crank pin relative to the colisa pivot
        for _ in range(50):                      # point_on_line: -9 px cos th3 - 9 py sin th3
            c3, s3 = math.cos(th3), math.sin(th3)
            r = -9.0 * px * c3 - 9.0 * py * s3
            d = 9.0 * px * s3 - 9.0 * py * c3
            s = r / d
            th3 -= s
            if abs(r) <= tol and abs(s) <= tol * (1.0 + abs(th3)):
                break
        c3, s3 = math.cos(th3), math.sin(th3)
        cx, cy = -9.0 * s3, 9.0 * c3             # colisa P2
        for _ in range(50):                      # translate, parallel: 34 sin th4 = 0
            r = 34.0 * math.sin(th4)
            s = r / (34.0 * math.cos(th4))
            th4 -= s
            if abs(r) <= tol and abs(s) <= tol * (1.0 + abs(th4)):
                break
        c4, s4 = math.cos(th4), math.sin(th4)
        for _ in range(50):                      # distance, with y4 explicit from the offset
            y4 = 10.0 + (5.0 + x4) * s4 / c4
            r = (cx - x4) ** 2 + (cy - y4) ** 2 - 25.0
            d = -2.0 * (cx - x4) - 2.0 * (cy - y4) * s4 / c4
            s = r / d
            x4 -= s
            if abs(r) <= tol and abs(s) <= tol * (1.0 + abs(x4)):
                break
        y4 = 10.0 + (5.0 + x4) * s4 / c4
        Q[k, 0] = th3
        Q[k, 1] = x4 + 0.0 * y4
        if level >= 1:
            # velocities: differentiate both equations once
            pxd, pyd = -L * s2 * W, L * c2 * W
            a = 9.0 * px * s3 - 9.0 * py * c3
            th3d = -(-9.0 * pxd * c3 - 9.0 * pyd * s3) / a
            cxd, cyd = -9.0 * c3 * th3d, -9.0 * s3 * th3d
            x4d = cxd + (cy - 10.0) * cyd / (cx - x4)
            Q[k, 2] = th3d
            Q[k, 3] = x4d
        if level >= 2:
            pxdd, pydd = -L * c2 * W * W, -L * s2 * W * W
            # d/dt of (a th3d + b) = 0 with b = -9 pxd c3 - 9 pyd s3
            ad = 9.0 * pxd * s3 + 9.0 * px * c3 * th3d - 9.0 * pyd * c3 + 9.0 * py * s3 * th3d
            bd = (-9.0 * pxdd * c3 + 9.0 * pxd * s3 * th3d - 9.0 * pydd * s3
                  - 9.0 * pyd * c3 * th3d)
            th3dd = -(ad * th3d + bd) / a
            cxdd = 9.0 * s3 * th3d * th3d - 9.0 * c3 * th3dd
            cydd = -9.0 * c3 * th3d * th3d - 9.0 * s3 * th3dd
            # (cx - x4)(cxd - x4d) + (cy - 10) cyd = 0, differentiated
            e = cx - x4
            x4dd = cxdd + ((cxd - x4d) ** 2 + cyd * cyd + (cy - 10.0) * cydd) / e
            Q[k, 4] = th3dd
            Q[k, 5] = x4dd
    return Q


@njit(cache=True)
def hand_closed_sweep(ts, level, Q):
    """Q[k] = (Th3, X4, Th3d, X4d, Th3dd, X4dd) at ts[k] in closed form, as one writes it
    by hand: the crank pin P, the lever's angle atan2(−Px, Py) (its sin and cos −Px/|P|,
    Py/|P|), the slider on y = 10 at 5 from the lever's end; velocities and accelerations
    by differentiating those formulas."""
    for k in range(ts.shape[0]):
        th2 = W * ts[k]
        c2, s2 = math.cos(th2), math.sin(th2)
        px, py = L * c2, 5.0 + L * s2
        r2 = px * px + py * py
        r = math.sqrt(r2)
        th3 = math.atan2(-px, py)
        s3, c3 = -px / r, py / r
        cx, cy = -9.0 * s3, 9.0 * c3
        e = 10.0 - cy
        sq = math.sqrt(25.0 - e * e)
        Q[k, 0] = th3
        Q[k, 1] = cx + sq
        if level >= 1:
            pxd, pyd = -L * W * s2, L * W * c2
            num = px * pyd - py * pxd
            th3d = num / r2
            cxd, cyd = -9.0 * c3 * th3d, -9.0 * s3 * th3d
            ed = -cyd
            sqd = -e * ed / sq
            Q[k, 2] = th3d
            Q[k, 3] = cxd + sqd
            if level >= 2:
                pxdd, pydd = -W * W * (px), -W * W * (py - 5.0)
                numd = px * pydd - py * pxdd
                r2d = 2.0 * (px * pxd + py * pyd)
                th3dd = (numd * r2 - num * r2d) / (r2 * r2)
                cxdd = 9.0 * s3 * th3d * th3d - 9.0 * c3 * th3dd
                cydd = -9.0 * c3 * th3d * th3d - 9.0 * s3 * th3dd
                edd = -cydd
                sqdd = -(ed * ed + e * edd + sqd * sqd) / sq
                Q[k, 4] = th3dd
                Q[k, 5] = cxdd + sqdd
    return Q


@njit(cache=True)
def hand_closed_sweep_full(ts, level, Q, QD, QDD):
    """hand_closed_sweep's formulas writing what a sweep of mechgen returns: every
    coordinate (X2, Y2, Th2, X3, Y3, Th3, X4, Y4, Th4) into Q, its velocity into QD and
    its acceleration into QDD (rows of 9; the ground-fixed ones constant), not only the
    two that move: the arrays a user's code gets, and the memory they cost."""
    for k in range(ts.shape[0]):
        th2 = W * ts[k]
        c2, s2 = math.cos(th2), math.sin(th2)
        px, py = L * c2, 5.0 + L * s2
        r2 = px * px + py * py
        r = math.sqrt(r2)
        th3 = math.atan2(-px, py)
        s3, c3 = -px / r, py / r
        cx, cy = -9.0 * s3, 9.0 * c3
        e = 10.0 - cy
        sq = math.sqrt(25.0 - e * e)
        Q[k, 0] = 0.0
        Q[k, 1] = 5.0
        Q[k, 2] = th2
        Q[k, 3] = 0.0
        Q[k, 4] = 0.0
        Q[k, 5] = th3
        Q[k, 6] = cx + sq
        Q[k, 7] = 10.0
        Q[k, 8] = 0.0
        if level >= 1:
            pxd, pyd = -L * W * s2, L * W * c2
            num = px * pyd - py * pxd
            th3d = num / r2
            cxd, cyd = -9.0 * c3 * th3d, -9.0 * s3 * th3d
            ed = -cyd
            sqd = -e * ed / sq
            for j in range(9):
                QD[k, j] = 0.0
            QD[k, 2] = W
            QD[k, 5] = th3d
            QD[k, 6] = cxd + sqd
            if level >= 2:
                pxdd, pydd = -W * W * (px), -W * W * (py - 5.0)
                numd = px * pydd - py * pxdd
                r2d = 2.0 * (px * pxd + py * pyd)
                th3dd = (numd * r2 - num * r2d) / (r2 * r2)
                cxdd = 9.0 * s3 * th3d * th3d - 9.0 * c3 * th3dd
                cydd = -9.0 * c3 * th3d * th3d - 9.0 * s3 * th3dd
                edd = -cydd
                sqdd = -(ed * ed + e * edd + sqd * sqd) / sq
                for j in range(9):
                    QDD[k, j] = 0.0
                QDD[k, 5] = th3dd
                QDD[k, 6] = cxdd + sqdd
    return Q


def _closed(t):
    th2 = 2 * mpmath.pi * t
    px, py = 3 * mpmath.cos(th2), 5 + 3 * mpmath.sin(th2)
    th3 = mpmath.atan2(-px, py)
    cx, cy = -9 * mpmath.sin(th3), 9 * mpmath.cos(th3)
    x4 = cx + mpmath.sqrt(25 - (10 - cy) ** 2)
    return th3, x4


def reference(t, digits=50):
    """(Th3, X4, Th3d, X4d, Th3dd, X4dd) at t from the closed form, at ``digits`` digits."""
    with mpmath.workdps(digits):
        t = mpmath.mpf(t)
        th3, x4 = _closed(t)
        d1 = [mpmath.diff(lambda s, i=i: _closed(s)[i], t) for i in range(2)]
        d2 = [mpmath.diff(lambda s, i=i: _closed(s)[i], t, 2) for i in range(2)]
        return [float(v) for v in (th3, x4, d1[0], d1[1], d2[0], d2[1])]


def lambdify_fsolve(model):
    """A per-point solver built the way most users write one."""
    import scipy.optimize
    import sympy as sp
    from mechgen.model.geometry import T

    eq = model.equations()
    subs = {sym: val for sym, val in model.params.values()}
    q = list(eq.q)
    f = sp.lambdify((q, T), list(eq.phi.subs(subs)), "numpy")
    J = sp.lambdify((q, T), eq.phi_q.subs(subs), "numpy")

    def solve(t, q0):
        return scipy.optimize.fsolve(lambda x: f(x, t), q0, fprime=lambda x: J(x, t),
                                     xtol=1e-13, full_output=False)
    return solve
