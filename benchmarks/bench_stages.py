"""Stages (Mech's TimeSwitch): what a switch costs, and its error against the single-stage
model, in one process.

- the seed's quick-return driven forward then back (examples/quick_return_stages.py) swept
  over [0, 1] against the single-stage crank-driven model (generated/quick_return.py) over
  the same times: time per point of each, their ratio, and the largest difference of the
  staged sweep from the single-stage one at the mirrored times (positions, velocities with
  their sign reversed after the switch, accelerations);
- the crank-then-slider handover (examples/quick_return_crank_slider.py), whose slider
  stage couples four coordinates in one Newton block, per point against the same baseline.

Run from the top of the repository: ``python benchmarks/bench_stages.py [N]``.
"""
from __future__ import annotations

import os
import sys
import time

import numpy as np

import mechgen

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def best_of(fn, repeat=7):
    out = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return min(out)


def main(n=10001):
    gen = os.path.join(ROOT, "generated")
    single = mechgen.load(os.path.join(gen, "quick_return.py"))
    staged = mechgen.load(os.path.join(gen, "quick_return_stages.py"))
    handover = mechgen.load(os.path.join(gen, "quick_return_crank_slider.py"))
    lev = "acceleration"
    for mech in (single, staged, handover):       # compile (or load numba's cache) first
        mech.sweep(0, 0.5 if mech is handover else 1, 11, level=lev)
    base = best_of(lambda: single.sweep(0, 1, n, level=lev))
    st = best_of(lambda: staged.sweep(0, 1, n, level=lev))
    ho = best_of(lambda: handover.sweep(0, 0.5, n, level=lev))
    base_half = best_of(lambda: single.sweep(0, 0.5, n, level=lev))
    sw, ref = staged.sweep(0, 1, n, level=lev), single.sweep(0, 1, n, level=lev)
    # the staged sweep holds the switch time twice: drop its right limit, then compare
    # the stage after the switch with the single-stage sweep read backwards (1 - t)
    keep = np.ones(len(sw), bool)
    keep[sw.switches[0].row_after] = False
    Q, QD, QDD, t = sw.Q[keep], sw.QD[keep], sw.QDD[keep], sw.t[keep]
    back = t > 0.5
    mirror = np.where(back, np.arange(len(t))[::-1], np.arange(len(t)))
    sign = np.where(back, -1.0, 1.0)[:, None]
    assert np.allclose(np.where(back, 1 - t, t), ref.t[mirror], atol=1e-12)
    err = [float(np.abs(Q - ref.Q[mirror]).max()), float(np.abs(QD - sign * ref.QD[mirror]).max()),
           float(np.abs(QDD - ref.QDD[mirror]).max())]
    print(f"quick-return sweeps of {n} points, acceleration level, best of 7:")
    print(f"  single stage (quick_return)            {base / n * 1e6:8.3f} us/point")
    print(f"  forward then back (quick_return_stages) {st / len(sw) * 1e6:8.3f} us/point   "
          f"ratio {st / base:.2f}")
    print(f"  crank then slider, [0, 0.5]             {ho / n * 1e6:8.3f} us/point   "
          f"ratio {ho / base_half:.2f} (vs the single stage over [0, 0.5])")
    print(f"  staged vs single at mirrored times: |dq| {err[0]:.2e}, |dqd| {err[1]:.2e}, "
          f"|dqdd| {err[2]:.2e}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 10001)
