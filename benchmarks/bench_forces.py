"""Forces (issue 21): the figures of the first slice and what a force solve costs beside
the kinematics, in one process on one machine.

    PYTHONPATH=. MECHGEN_TIER=compiled python benchmarks/bench_forces.py

Accuracy: the slider-crank of tests/test_forces.py (driver torque at 1,000 crank angles
against the power form, pin forces against Newton–Euler body by body, power residual),
the four-bar held still (virtual work, 5-point finite differences of the closed-form
potential), the quick-return of examples/quick_return_forces.py (power residual over a
turn, flywheel). Speed: a sweep of 10^5 points at level "acceleration" and "dynamic"
(and "position" and "static", λ in the sweep's quick path and after it), and
one solve at each, best of 5 after a warm-up, on the quick-return and the Strandbeest leg
with masses (benchmarks/strandbeest_forces.py); a design table of peak torque on all
cores beside the kinematic one.
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
                         outdir=os.path.join(folder, "qr"), tier="compiled")
    sw = qr.sweep(0, 1, 1001, level="dynamic")
    p = sw.power()
    tau = sw.driver("crank driver")
    print(f"quick-return with a cutting force, 1001 points: power residual / max driver "
          f"power {np.abs(p['residual']).max() / np.abs(p['drivers']).max():.2e}; torque "
          f"peak {tau.max():.2f}, mean {tau[:-1].mean():.2f}; flywheel (cs 0.05) "
          f"{sw.flywheel(0.05)['inertia']:.2f}")
    return qr


def _best(fn, rounds):
    best = math.inf
    for _ in range(rounds):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def speed(mech, name, n=100_000, rounds=5):
    """A sweep of n points at level "acceleration" and "dynamic", and at "position" and
    "static" (with λ in the position sweep's quick path, sweep_fast_statics, and with λ
    solved after the sweep instead), interleaved, best of ``rounds``; the dynamic one's λ
    and driver effort against a dense numpy solve."""
    module = mech.module
    statics = getattr(module, "STATIC_FUSED", False)

    def separate():                 # λ after the sweep (force_rows), as without the path
        module.STATIC_FUSED = False     # (the runtime reads the flag: forces.lookup)
        try:
            mech.sweep(0, 1, n, level="static")
        finally:
            module.STATIC_FUSED = statics
    runs = {level: (lambda level=level: mech.sweep(0, 1, n, level=level))
            for level in ("position", "static", "acceleration", "dynamic")}
    if statics is not None:
        runs["static, λ after"] = separate
    for level in ("position", "static", "acceleration", "dynamic"):
        mech.sweep(0, 1, 11, level=level)
    best = {}
    for _ in range(rounds):
        for level, run in runs.items():
            best[level] = min(best.get(level, math.inf), _best(run, 1))
    print(f"{name}: sweep of {n} points: acceleration {best['acceleration'] * 1e9 / n:.0f} ns "
          f"a point, dynamic {best['dynamic'] * 1e9 / n:.0f} ns "
          f"({best['dynamic'] / best['acceleration']:.2f}x); position "
          f"{best['position'] * 1e9 / n:.0f} ns, static {best['static'] * 1e9 / n:.0f} ns "
          f"({best['static'] / best['position']:.2f}x)" +
          (f"; static with λ after the sweep {best['static, λ after'] * 1e9 / n:.0f} ns "
           f"({best['static, λ after'] / best['position']:.2f}x)" if statics else ""))
    sw = mech.sweep(0, 1, 401, level="dynamic")
    worst = 0.0
    for k in range(0, 401, 8):
        J = mech.jacobian(sw.Q[k], float(sw.t[k]))
        terms = np.zeros((3, mech.n))
        mech.module.force_terms(sw.Q[k], sw.QD[k], sw.QDD[k], float(sw.t[k]), mech.p, terms)
        want = np.linalg.lstsq(J.T, terms[0] + terms[1] - terms[2], rcond=None)[0]
        worst = max(worst, np.abs(sw.LAM[k] - want).max() / np.abs(want).max())
    print(f"  λ against numpy's dense solve (51 points): max rel. error {worst:.1e}; "
          f"power residual / peak input {np.abs(sw.power()['residual']).max() / np.abs(sw.power()['drivers']).max():.1e}")


def solve_speed(mech, rounds=5, count=2000, when=""):
    """One solve with a guess, best of ``rounds`` loops of ``count`` (each result let go,
    as a loop that keeps a number of each does: a list of 2,000 Solutions would add the
    collector's work on them, about 1 µs a solve)."""
    s = mech.solve(0.1, level="dynamic")
    out = {}

    def loop(level):
        for _ in range(count):
            mech.solve(0.1, level=level, guess=s)

    for level in ("acceleration", "dynamic"):
        out[level] = _best(lambda: loop(level), rounds) / count
    print(f"quick-return solve with a guess{when}: acceleration "
          f"{out['acceleration'] * 1e6:.1f} µs, dynamic {out['dynamic'] * 1e6:.1f} µs")


def table_speed(mech, designs=2000, n=1000):
    """Peak driver torque per design on every core (reduce=), beside the kinematic table
    of the same designs reducing X4."""
    L = np.linspace(2.0, 4.0, designs)
    kw = dict(params={"longitud": L}, on_fail="ignore")
    mech.sweep(0, 1, 10, level="dynamic", reduce=["crank driver"], params={"longitud": L[:4]})
    ta = _best(lambda: mech.sweep(0, 1, n, level="acceleration", reduce=["X4"], **kw), 2)
    td = _best(lambda: mech.sweep(0, 1, n, level="dynamic", reduce=["crank driver"], **kw), 2)
    red = mech.sweep(0, 1, n, level="dynamic", reduce=["crank driver"], **kw).reduced("crank driver")
    import mechgen.runtime.tables.chunks as chunks         # the separate pass, for comparison
    fused, chunks.fused_level = chunks.fused_level, (lambda *args: None)
    try:
        ts = _best(lambda: mech.sweep(0, 1, n, level="dynamic", reduce=["crank driver"], **kw),
                   2)
    finally:
        chunks.fused_level = fused
    print(f"design table, {designs} designs x {n} times, all cores: kinematic {ta:.2f} s, "
          f"peak torque {td:.2f} s ({td / ta:.2f}x; λ after the sweeps instead: {ts:.2f} s, "
          f"{ts / ta:.2f}x); peak torque from {np.nanmin(red.max):.4g} to "
          f"{np.nanmax(red.max):.4g}")


if __name__ == "__main__":
    with tempfile.TemporaryDirectory() as folder:
        qr = accuracy(folder)
        solve_speed(qr, when=" (before the large sweeps)")
        speed(qr, "quick-return")
        sb = mechgen.compile(os.path.join(ROOT, "benchmarks", "strandbeest_forces.py"),
                             outdir=os.path.join(folder, "sb"), tier="compiled")
        speed(sb, "Strandbeest leg")
        solve_speed(qr, when=" (after them)")
        table_speed(qr)
