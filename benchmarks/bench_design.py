"""Design tables of the quick-return of seed 001 (crank lengths x times, positions) on every
backend, against the hand-written sorted sweep (benchmarks/baselines.py) on one core and
on every core (numba prange), all in one process, the same designs, interleaved rounds,
medians of ns per (design, time) point; then the largest difference of each from the
one-core table. Both the median and the best of the rounds are printed: on a shared
machine other work only adds time, so the best is the figure least disturbed by it.

    python benchmarks/bench_design.py                  # 2,000 designs x 1,000 times
    python benchmarks/bench_design.py --quick          # 400 x 500, fewer rounds
    python benchmarks/bench_design.py --designs 100000 --times 1000 --no-dask

Rows: mech.sweep(..., params=...) with workers=1 and with every core (the default), the
same with reduce=["X4"] (per-design min/max only), backend="dask" on a LocalCluster of 2
worker processes (--no-dask skips it), backend="cuda" where mechgen.runtime.tables.cuda and a
GPU are present, and the hand-written kernels.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
sys.path.insert(0, ROOT)

import baselines  # noqa: E402

import mechgen  # noqa: E402
from mechgen.runtime.tables.backends import cpu_count  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--designs", type=int, default=2000)
    ap.add_argument("--times", type=int, default=1000)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--no-dask", action="store_true")
    args = ap.parse_args()
    if args.quick:
        args.designs, args.times, args.rounds = 400, 500, 3
    D, N = args.designs, args.times
    mech = mechgen.load(os.path.join(ROOT, "generated", "quick_return.py"))
    lengths = np.linspace(1.0, 3.5, D)
    ts = np.linspace(0.0, 1.0, N)
    params = {"longitud": lengths}

    def table(**kw):
        return mech.sweep(0.0, 1.0, N, params=params, on_fail="ignore", **kw)

    runs = {
        "mechgen, 1 core (workers=1)": lambda: table(workers=1),
        f"mechgen, all cores ({cpu_count()})": lambda: table(),
        "mechgen, all cores, reduce=['X4']": lambda: table(reduce=["X4"]),
    }
    client = cluster = None
    if not args.no_dask:
        from distributed import Client, LocalCluster
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        client = Client(cluster)
        runs["mechgen, dask (LocalCluster, 2 workers)"] = lambda: table(backend="dask",
                                                                        client=client)
    try:
        from mechgen.runtime.tables.cuda import run_table_cuda  # noqa: F401
        mech.sweep(0.0, 1.0, 10, params={"longitud": lengths[:4]}, backend="cuda")
        runs["mechgen, cuda"] = lambda: table(backend="cuda")
    except Exception as exc:          # no kernel in this build, or no GPU
        print(f"(cuda: not measured: {str(exc).splitlines()[0][:100]})")
    Qh = np.zeros((D, N, 6))
    runs["hand-written sorted, 1 core"] = lambda: baselines.hand_designs(ts, lengths, 0, 1e-10, Qh)
    Qp = np.zeros((D, N, 6))
    runs["hand-written sorted, prange"] = lambda: baselines.hand_designs_prange(ts, lengths, 0,
                                                                                  1e-10, Qp)
    # warm every path (compiles, numba's cache, the workers' imports) on a few designs
    small = lengths[:4]
    mech.sweep(0.0, 1.0, N, params={"longitud": small}, workers=1)
    mech.sweep(0.0, 1.0, N, params={"longitud": small}, reduce=["X4"])
    if client is not None:
        mech.sweep(0.0, 1.0, N, params={"longitud": small}, backend="dask", client=client)
    baselines.hand_designs(ts, small, 0, 1e-10, np.zeros((4, N, 6)))
    baselines.hand_designs_prange(ts, small, 0, 1e-10, np.zeros((4, N, 6)))

    times = {name: [] for name in runs}
    results = {}
    for _ in range(args.rounds):
        for name, fn in runs.items():
            results.pop(name, None)         # the last round's table freed outside the timing
            t0 = time.perf_counter()
            results[name] = fn()
            times[name].append((time.perf_counter() - t0) / (D * N) * 1e9)
    ref = results["mechgen, 1 core (workers=1)"]
    x4 = ref["X4"]
    print(f"quick-return design table: {D} crank lengths x {N} times, positions; "
          f"{args.rounds} interleaved rounds, ns per (design, time) point: their median and "
          "their best (other work on a shared machine only adds time)")
    base = statistics.median(times["mechgen, 1 core (workers=1)"])
    base_best = min(times["mechgen, 1 core (workers=1)"])
    print(f"{'':44s} {'median':>9s} {'vs 1 core':>9s} {'best':>7s} {'vs 1 core':>9s}  "
          "largest |X4 - 1 core|")
    for name in runs:
        med = statistics.median(times[name])
        best = min(times[name])
        got = results[name]
        if isinstance(got, np.ndarray):
            diff = np.nanmax(np.abs(got[:, :, 1] - x4))
        elif got.kept_points:
            diff = np.nanmax(np.abs(got["X4"] - x4)) if np.any(np.isfinite(got["X4"])) else 0.0
            same = np.array_equal(got.Q, ref.Q) and np.array_equal(got.status, ref.status)
            diff = f"{diff:.2e}{' (bit-identical)' if same else ''}"
        else:
            r = got.reduced("X4")
            diff = max(np.nanmax(np.abs(r.max - np.nanmax(x4, axis=1))),
                       np.nanmax(np.abs(r.min - np.nanmin(x4, axis=1))))
            diff = f"{diff:.2e} (min/max)"
        print(f"{name:44s} {med:9.1f} {base / med:8.2f}x {best:7.1f} {base_best / best:8.2f}x  "
              f"{diff if isinstance(diff, str) else f'{diff:.2e}'}")
    if client is not None:
        client.close()
        cluster.close()


if __name__ == "__main__":
    main()
