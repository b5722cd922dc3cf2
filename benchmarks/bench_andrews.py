"""Andrews' squeezing mechanism to t = 0.03 (issue 22): mech.simulate on the compiled
module beside the same scipy integrator on a right side that a SymPy user builds by hand
with lambdify, in one process; steps, right-side evaluations, time a step and in total,
and the error of each against the IVP test set's reference solution.

    PYTHONPATH=. MECHGEN_TIER=compiled python benchmarks/bench_andrews.py [--rtol 1e-8]

The hand-built side is Hairer & Wanner's own formulation (VII.7): seven relative angles,
their 7×7 mass matrix, the force vector with its velocity terms, six loop equations g(q),
G = ∂g/∂q and γ = −∂(G q̇)/∂q q̇ from SymPy, lambdified to numpy, and the index-1 system
[M Gᵀ; G 0] [q̈; λ] = [f; γ] solved by numpy at each evaluation. mechgen integrates the
body coordinates of examples/andrews_squeezer.py (21 coordinates, 20 pin equations) with
its projection onto the constraints at every output.
"""
from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
sys.path.insert(0, os.path.join(ROOT, "tests"))

import mechgen                         # noqa: E402
from test_andrews import REF_Q, REF_QD, hairer   # noqa: E402

Y0 = [-0.0617138900142764496358948458001, 0.0, 0.455279819163070380255912382449,
      0.222668390165885884674473185609, 0.487364979543842550225598953530,
      -0.222668390165885884674473185609, 1.23054744454982119249735015568]


def hand_built():
    """(rhs, counter) of Hairer's index-1 squeezer from SymPy and lambdify."""
    m1, m2, m3, m4, m5, m6, m7 = .04325, .00365, .02373, .00706, .07050, .00706, .05498
    i1, i2, i3, i4, i5, i6, i7 = 2.194e-6, 4.410e-7, 5.255e-6, 5.667e-7, 1.169e-5, \
        5.667e-7, 1.912e-5
    xa, ya, xb, yb, xc, yc = -.06934, -.00227, -.03635, .03273, .014, .072
    d, da, e, ea, rr, ra = 28e-3, 115e-4, 2e-2, 1421e-5, 7e-3, 92e-5
    ss, sa, sb, sc, sd = 35e-3, 1874e-5, 1043e-5, 18e-3, 2e-2
    ta, tb, u, ua, ub = 2308e-5, 916e-5, 4e-2, 1228e-5, 449e-5
    zf, zt, fa, mom, c0, l0 = 2e-2, 4e-2, 1421e-5, 33e-3, 4530.0, 7785e-5
    q = sp.symbols("be th ga ph de om ep", real=True)
    v = sp.symbols("bep thp gap php dep omp epp", real=True)
    be, th, ga, ph, de, om, ep = q
    bep, thp, gap, php, dep, omp, epp = v
    M = sp.zeros(7, 7)
    M[0, 0] = m1 * ra ** 2 + m2 * (rr ** 2 - 2 * da * rr * sp.cos(th) + da ** 2) + i1 + i2
    M[1, 0] = M[0, 1] = m2 * (da ** 2 - da * rr * sp.cos(th)) + i2
    M[1, 1] = m2 * da ** 2 + i2
    M[2, 2] = m3 * (sa ** 2 + sb ** 2) + i3
    M[3, 3] = m4 * (e - ea) ** 2 + i4
    M[4, 3] = M[3, 4] = m4 * ((e - ea) ** 2 + zt * (e - ea) * sp.sin(ph)) + i4
    M[4, 4] = m4 * (zt ** 2 + 2 * zt * (e - ea) * sp.sin(ph) + (e - ea) ** 2) + \
        m5 * (ta ** 2 + tb ** 2) + i4 + i5
    M[5, 5] = m6 * (zf - fa) ** 2 + i6
    M[6, 5] = M[5, 6] = m6 * ((zf - fa) ** 2 - u * (zf - fa) * sp.sin(om)) + i6
    M[6, 6] = m6 * ((zf - fa) ** 2 - 2 * u * (zf - fa) * sp.sin(om) + u ** 2) + \
        m7 * (ua ** 2 + ub ** 2) + i6 + i7
    xd = sd * sp.cos(ga) + sc * sp.sin(ga) + xb
    yd = sd * sp.sin(ga) - sc * sp.cos(ga) + yb
    L = sp.sqrt((xd - xc) ** 2 + (yd - yc) ** 2)
    force = -c0 * (L - l0) / L
    fx, fy = force * (xd - xc), force * (yd - yc)
    f = sp.Matrix([
        mom - m2 * da * rr * thp * (thp + 2 * bep) * sp.sin(th),
        m2 * da * rr * bep ** 2 * sp.sin(th),
        fx * (sc * sp.cos(ga) - sd * sp.sin(ga)) + fy * (sd * sp.cos(ga) + sc * sp.sin(ga)),
        m4 * zt * (e - ea) * dep ** 2 * sp.cos(ph),
        -m4 * zt * (e - ea) * php * (php + 2 * dep) * sp.cos(ph),
        -m6 * u * (zf - fa) * epp ** 2 * sp.cos(om),
        m6 * u * (zf - fa) * omp * (omp + 2 * epp) * sp.cos(om)])
    ex = rr * sp.cos(be) - d * sp.cos(be + th)
    ey = rr * sp.sin(be) - d * sp.sin(be + th)
    g = sp.Matrix([ex - ss * sp.sin(ga) - xb, ey + ss * sp.cos(ga) - yb,
                   ex - e * sp.sin(ph + de) - zt * sp.cos(de) - xa,
                   ey + e * sp.cos(ph + de) - zt * sp.sin(de) - ya,
                   ex - zf * sp.cos(om + ep) - u * sp.sin(ep) - xa,
                   ey - zf * sp.sin(om + ep) + u * sp.cos(ep) - ya])
    G = g.jacobian(q)
    gamma = -(G * sp.Matrix(v)).jacobian(q) * sp.Matrix(v)
    args = (q, v)
    fM, ff = sp.lambdify(args, M, "numpy"), sp.lambdify(args, f, "numpy")
    fG, fgam = sp.lambdify(args, G, "numpy"), sp.lambdify(args, gamma, "numpy")
    calls = [0]
    A = np.zeros((13, 13))
    b = np.zeros(13)

    def rhs(t, y):
        calls[0] += 1
        qq, vv = y[:7], y[7:]
        Gv = np.asarray(fG(qq, vv), dtype=float)
        A[:7, :7] = fM(qq, vv)
        A[:7, 7:] = Gv.T
        A[7:, :7] = Gv
        b[:7] = np.asarray(ff(qq, vv), dtype=float).ravel()
        b[7:] = np.asarray(fgam(qq, vv), dtype=float).ravel()
        return np.concatenate([vv, np.linalg.solve(A, b)[:7]])
    return rhs, calls


def best(fn, rounds):
    times, out = [], None
    for _ in range(rounds):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rtol", type=float, default=1e-8)
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    rtol = args.rtol
    mech = mechgen.load(os.path.join(ROOT, "generated", "andrews_squeezer.py"),
                        tier="compiled")
    rhs, calls = hand_built()
    mech.simulate(0.0, 0.001, 2)                      # compile before timing
    print(f"Andrews' squeezer to t = 0.03, rtol = atol = {rtol:g}, best of {args.rounds}")
    print(f"{'method':8s} {'right side':22s} {'steps':>6s} {'evals':>6s} {'us/step':>8s} "
          f"{'total s':>8s} {'err q':>9s} {'err qd':>9s}")
    for method in ("dopri5", "DOP853", "RK45", "Radau"):
        s, sw = best(lambda: mech.simulate(0.0, 0.03, 2, rtol=rtol, atol=rtol,
                                           method=method), args.rounds)
        method = "RK45" if method == "dopri5" else method  # its pair, beside scipy's
        eq = np.abs(hairer(sw, -1) - REF_Q).max()
        ev = np.abs(hairer(sw, -1, "d") - REF_QD).max()
        label = "mechgen, compiled" if sw.simulation["method"] == "dopri5" else \
            "mechgen (21 coords)"
        print(f"{sw.simulation['method']:8s} {label:22s} {sw.steps:6d} {sw.evaluations:6d} "
              f"{1e6 * s / sw.steps:8.1f} {s:8.4f} {eq:9.2e} {ev:9.2e}")
        mine = s
        if sw.simulation["method"] == "dopri5":
            print(f"{'':8s} (the Dormand-Prince pair of RK45, compiled in the module)")
            compiled = s
            continue
        if method == "RK45":
            print(f"{'':8s} compiled / scipy RK45 on the same module: {compiled / s:.2f}")

        def hand():
            calls[0] = 0
            return solve_ivp(rhs, (0.0, 0.03), np.concatenate([Y0, np.zeros(7)]),
                             method=method, rtol=rtol, atol=rtol)
        s, sol = best(hand, args.rounds)
        eq = np.abs(sol.y[:7, -1] - REF_Q).max()
        ev = np.abs(sol.y[7:, -1] - REF_QD).max()
        steps = len(sol.t) - 1
        print(f"{method:8s} {'lambdify (7 angles)':22s} {steps:6d} {sol.nfev:6d} "
              f"{1e6 * s / steps:8.1f} {s:8.4f} {eq:9.2e} {ev:9.2e}   "
              f"time mechgen/lambdify {mine / s:.2f}")


if __name__ == "__main__":
    main()
