"""Speed against error for the quick-return of seed 001, all methods side by side in one
process (interleaved rounds, medians), each checked against a 50-digit mpmath reference.

    python benchmarks/bench_speed.py            # the table
    python benchmarks/bench_speed.py --quick    # fewer points and rounds

Methods: the generated module's compiled sweep into preallocated arrays (as the hand-written
baseline is run), the same through mech.sweep (which allocates its result arrays; the
first touch of fresh pages adds some 15 ns a point at this size), one mech.solve
per point with its Python overhead, the generated full-Newton path (method="full"), the
hand-written sorted numba baseline, the hand-written closed form in numba and
sympy.lambdify + scipy.optimize.fsolve.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)

import baselines  # noqa: E402

import mechgen  # noqa: E402
from mechgen.compiler.build import build  # noqa: E402
from mechgen.model.loader import load_models  # noqa: E402

NAMES = ("Th3", "X4")
MODULE = "generated, compiled sweep (module)"
CLOSED = "hand-written numba, closed form"


def per_point(fn, n_points, rounds):
    times = []
    for _ in range(rounds):
        t0 = time.perf_counter()
        fn()
        times.append((time.perf_counter() - t0) / n_points * 1e9)
    return statistics.median(times)


def errors(values, ts, ref):
    """Largest error over the sample times, per derivative level."""
    worst = [0.0, 0.0, 0.0]
    for k, t in enumerate(ts):
        r = ref[t]
        for lev in range(3):
            for i in range(2):
                v = values[lev][i][k]
                if v is not None and np.isfinite(v):
                    worst[lev] = max(worst[lev], abs(v - r[2 * lev + i]))
    return worst


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    N = 20_000 if args.quick else 100_000
    rounds = 3 if args.quick else 7
    model = load_models(os.path.join(ROOT, "examples", "quick_return.py"))[0]
    outdir = tempfile.mkdtemp(prefix="mechgen-bench-")
    mech = mechgen.load(build(model, outdir), tier="compiled")     # (the module itself)
    full = mechgen.load(build(model, os.path.join(outdir, "full"), sort=False), tier="compiled")

    ts = np.linspace(0.0, 1.0, N, endpoint=False)
    sample_idx = np.linspace(0, N - 1, 25).astype(int)
    ref = {float(ts[k]): baselines.reference(float(ts[k])) for k in sample_idx}

    # warm up every compiled path once
    mech.sweep(0, 1, 5, level="acceleration")
    mech.sweep(0, 1, 5)
    full.sweep(0, 1, 5, level="acceleration", method="full")
    full.sweep(0, 1, 5, method="full")
    Qh = np.zeros((N, 6))
    baselines.hand_sorted_sweep(ts[:5], 2, 1e-10, Qh[:5])
    baselines.hand_closed_sweep(ts[:5], 2, Qh[:5])

    results = {}
    sweeps = {}

    def gen(level, m=mech, method=None):
        def run():
            sweeps[(id(m), level)] = m.sweep(None, None, None, level=level, method=method,
                                             times=ts)
        return run

    def hand(level):
        def run():
            baselines.hand_sorted_sweep(ts, level, 1e-10, Qh)
        return run

    def hand_closed(level):
        def run():
            baselines.hand_closed_sweep(ts, level, Qh)
        return run

    # the generated module's compiled sweep into preallocated arrays, as the hand-written
    # baselines are run (QD and QDD without rows: its position sweep)
    mod, n = mech.module, mech.n
    Qg, QDg, QDDg = np.zeros((N, n)), np.zeros((N, n)), np.zeros((N, n))
    INFOg = np.zeros((N, 3), dtype=np.int16)       # the STATUS rows (protocol.STATUS_*)
    q0 = np.array(mod.GUESS, dtype=float)
    mod.sweep_fast(ts[:5], q0, mech.p, mech.tol, mech.xtol, mech.maxit, Qg, QDg, QDDg, INFOg)
    mod.sweep_fast(ts[:5], q0, mech.p, mech.tol, mech.xtol, mech.maxit, Qg, QDg[:0], QDDg[:0],
                   INFOg)

    none = np.zeros((0, n))

    def module_sweep(full=True):
        def run():
            qd, qdd = (QDg, QDDg) if full else (none, none)    # no rows: a position sweep
            done = mod.sweep_fast(ts, q0, mech.p, mech.tol, mech.xtol, mech.maxit, Qg, qd, qdd,
                                  INFOg)
            assert done == N, f"the quick path stopped at point {done}"
        return run

    cases = [
        (MODULE, module_sweep(False), module_sweep(True)),
        ("mech.sweep (Python API, new arrays)", gen("position"), gen("acceleration")),
        ("generated, full Newton (--no-sort)", gen("position", full, "full"),
         gen("acceleration", full, "full")),
        ("hand-written numba, sorted", hand(0), hand(2)),
        (CLOSED, hand_closed(0), hand_closed(2)),
    ]
    timing = {name: ([], []) for name, _, _ in cases}
    for _ in range(rounds):
        for name, pos, acc in cases:
            timing[name][0].append(per_point(pos, N, 1))
            timing[name][1].append(per_point(acc, N, 1))
    for name, (tp, ta) in timing.items():
        results[name] = [statistics.median(tp), statistics.median(ta)]

    # errors of each compiled method at the sample times
    errs = {}
    c = mech.coordinates
    cols = [c.index("Th3"), c.index("X4")]

    def of_arrays(Q, QD, QDD):      # the sample rows of Th3 and X4 at the three levels
        return [[A[sample_idx, j] for j in cols] for A in (Q, QD, QDD)]

    module_sweep()()
    errs[MODULE] = errors(of_arrays(Qg, QDg, QDDg), ts[sample_idx], ref)
    for name, m in (("mech.sweep (Python API, new arrays)", mech),
                    ("generated, full Newton (--no-sort)", full)):
        sw = sweeps[(id(m), "acceleration")]
        errs[name] = errors(of_arrays(sw.Q, sw.QD, sw.QDD), ts[sample_idx], ref)
    baselines.hand_sorted_sweep(ts, 2, 1e-10, Qh)
    errs["hand-written numba, sorted"] = errors(
        [[Qh[sample_idx, 0], Qh[sample_idx, 1]], [Qh[sample_idx, 2], Qh[sample_idx, 3]],
         [Qh[sample_idx, 4], Qh[sample_idx, 5]]], ts[sample_idx], ref)
    baselines.hand_closed_sweep(ts, 2, Qh)
    errs[CLOSED] = errors(
        [[Qh[sample_idx, 0], Qh[sample_idx, 1]], [Qh[sample_idx, 2], Qh[sample_idx, 3]],
         [Qh[sample_idx, 4], Qh[sample_idx, 5]]], ts[sample_idx], ref)

    # one mech.solve per point: Python overhead included
    few = ts[:: max(1, N // 2000)]
    mech.solve(0.1, level="acceleration")

    def single(level):
        def run():
            for t in few:
                mech.solve(t, level=level)
        return run
    results["mech.solve(t) per call (Python API)"] = [per_point(single("position"), len(few), rounds),
                                                    per_point(single("acceleration"), len(few), rounds)]
    errs["mech.solve(t) per call (Python API)"] = errs["mech.sweep (Python API, new arrays)"]

    # lambdify + fsolve, per point, warm started
    solve = baselines.lambdify_fsolve(model)
    few2 = ts[:: max(1, N // 2000)]
    qs = {}

    def lf():
        q = np.array(model.guess_vector())
        for t in few2:
            q = solve(t, q)
            qs[float(t)] = q
    results["sympy.lambdify + scipy fsolve"] = [per_point(lf, len(few2), max(1, rounds // 2)), float("nan")]
    worst = 0.0
    for t, r in ref.items():
        if t in qs:
            q = qs[t]
            worst = max(worst, abs(q[5] - r[0]), abs(q[6] - r[1]))
    errs["sympy.lambdify + scipy fsolve"] = [worst, float("nan"), float("nan")]

    base = results["hand-written numba, sorted"]
    slow = results["sympy.lambdify + scipy fsolve"][0]
    print(f"quick-return sweep over T in [0, 1), {N} points, medians of {rounds} interleaved rounds")
    print(f"{'method':42s} {'pos ns':>9s} {'+vel+acc':>9s} {'vs hand':>8s} {'vs fsolve':>10s} "
          f"{'err pos':>9s} {'err vel':>9s} {'err acc':>9s}")
    for name, (tp, ta) in results.items():
        e = errs[name]
        own = ta if ta == ta else tp
        print(f"{name:42s} {tp:9.0f} {ta:9.0f} {own / base[1]:8.2f} "
              f"{slow / own:10.0f} {e[0]:9.1e} {e[1]:9.1e} {e[2]:9.1e}")
    closed = results[CLOSED]
    mod_t = results[MODULE]
    print(f"generated module / hand-written closed form: position {mod_t[0] / closed[0]:.2f}, "
          f"+vel+acc {mod_t[1] / closed[1]:.2f}; the module's position sweep / its full one "
          f"{mod_t[0] / mod_t[1]:.2f}")
    print("vs hand: the +vel+acc time (position time where there is none) over the hand-written "
          "sorted numba's +vel+acc time;\nvs fsolve: lambdify + fsolve's time per position over "
          "the same time (a position with its velocity and acceleration against a position alone).")


if __name__ == "__main__":
    main()
