"""Forces (issue 21): the figures of the first slice and what a force solve costs beside
the kinematics, in one process on one machine.

    PYTHONPATH=. MECHGEN_TIER=compiled python benchmarks/bench_forces.py

Accuracy: the slider-crank of tests/test_forces.py (driver torque at 1,000 crank angles
against the power form, pin forces against Newton–Euler body by body, power residual),
the four-bar held still (virtual work, 5-point finite differences of the closed-form
potential), the quick-return of examples/quick_return_forces.py (power residual over a
turn, flywheel). Speed: a sweep of 10^5 points at level "acceleration" and "dynamic", and
one solve at each, best of 3 after a warm-up.
"""
from __future__ import annotations

import math
import os
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests"))

import mechgen                 # noqa: E402
import test_forces as tf       # noqa: E402


def accuracy(folder):
    sc = tf._compile(tf.slider_crank(), os.path.join(folder, "sc"))
    sw = sc.sweep(0.0, 2 * math.pi / tf.W, 1000, level="dynamic")
    tau = sw.driver("crank driver")
    expected = np.array([tf.power_torque(tf.closed_form(t)) for t in sw.t])
    print(f"slider-crank, 1000 angles: driver torque max rel. error "
          f"{np.abs(tau - expected).max() / np.abs(expected).max():.2e} (peak "
          f"{np.abs(expected).max():.4g})")
    p = sw.power()
    print(f"  power residual / max driver power {np.abs(p['residual']).max() / np.abs(p['drivers']).max():.2e}")
    worst = 0.0
    for t in np.linspace(0, 2 * math.pi / tf.W, 13):
        s = sc.solve(t, level="dynamic", guess=sc.last)
        ne = tf.newton_euler(tf.closed_form(t))
        for got, want in ((s.reaction("B", on="rod")[:2], ne["FB"]),
                          (s.reaction("C", on="slider")[:2], ne["FC"]),
                          (s.reaction("A", on="crank")[:2], ne["FA"]),
                          (s.reaction("guide", on="slider"), [0, ne["N"], ne["guide"]])):
            worst = max(worst, np.abs(np.asarray(got) - want).max())
    print(f"  pin forces (13 angles) against Newton–Euler: max abs. error {worst:.2e} N")
    fb = tf._compile(tf.four_bar(), os.path.join(folder, "fb"))
    errs = []
    for th in (0.6, 1.0, 1.4, 2.0):
        s = fb.with_params(th0=th).solve(0.0, level="static")
        upper = s["Y4"] + tf.C4R * math.sin(s["Th4"]) > 0
        h = 1e-3
        V = [tf.four_bar_potential(th + j * h, upper) for j in (-2, -1, 1, 2)]
        dV = (V[0] - 8 * V[1] + 8 * V[2] - V[3]) / (12 * h)
        errs.append(abs(s.driver("hold") - dV) / abs(dV))
    print(f"four-bar held still, 4 angles: holding torque against virtual work, max rel. "
          f"error {max(errs):.2e}")
    qr = mechgen.compile(os.path.join(ROOT, "examples", "quick_return_forces.py"),
                         outdir=os.path.join(folder, "qr"))
    sw = qr.sweep(0, 1, 1001, level="dynamic")
    p = sw.power()
    tau = sw.driver("crank driver")
    print(f"quick-return with a cutting force, 1001 points: power residual / max driver "
          f"power {np.abs(p['residual']).max() / np.abs(p['drivers']).max():.2e}; torque "
          f"peak {tau.max():.2f}, mean {tau[:-1].mean():.2f}; flywheel (cs 0.05) "
          f"{sw.flywheel(0.05)['inertia']:.2f}")
    return qr


def speed(mech, n=100_000):
    mech.sweep(0, 1, 11, level="dynamic")
    mech.sweep(0, 1, 11, level="acceleration")
    best = {}
    for _ in range(3):
        for level in ("acceleration", "dynamic"):
            t0 = time.perf_counter()
            mech.sweep(0, 1, n, level=level)
            best[level] = min(best.get(level, math.inf), time.perf_counter() - t0)
    print(f"quick-return sweep of {n} points: acceleration {best['acceleration']:.4f} s, "
          f"dynamic {best['dynamic']:.4f} s ({best['dynamic'] / best['acceleration']:.1f}x)")
    s = mech.solve(0.1, level="dynamic")
    for level in ("acceleration", "dynamic"):
        times = []
        for _ in range(3):
            t0 = time.perf_counter()
            for _ in range(500):
                mech.solve(0.1, level=level, guess=s)
            times.append((time.perf_counter() - t0) / 500)
        print(f"quick-return solve at level {level}: {min(times) * 1e6:.1f} µs")


if __name__ == "__main__":
    with tempfile.TemporaryDirectory() as folder:
        speed(accuracy(folder))
