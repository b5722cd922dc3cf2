"""Scale family: chains of N four-bar loops (benchmarks/chain_model.py), N up to 50.

For each N: build time (sympy + render, this process), numba compile time of a fresh
module (first sweep in a new process, empty cache), cached start-up (second process),
and the per-point time of a compiled sweep with positions, velocities and accelerations.
Ends with the growth exponents fitted on log-log scales (time ∝ N^k).

    python benchmarks/bench_scale.py                 # N = 1 2 5 10 20 50
    python benchmarks/bench_scale.py 1 2 5 10        # chosen sizes
"""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from chain_model import chain  # noqa: E402

from mechgen.compiler.build import build  # noqa: E402

RUN = r"""
import json, sys, time
t0 = time.perf_counter()
import numpy as np
import mechgen
mech = mechgen.load(sys.argv[1])
t1 = time.perf_counter()
mech.sweep(0.0, 1.0, 3, level=sys.argv[2])          # compiles (or loads from the cache)
t2 = time.perf_counter()
n = int(sys.argv[3])
best = float("inf")
for _ in range(3):
    a = time.perf_counter()
    sw = mech.sweep(0.0, 1.0, n, level=sys.argv[2])
    best = min(best, time.perf_counter() - a)
# (the solver of each point is no longer recorded: "sorted" is None since format 3)
print(json.dumps(dict(load=t1 - t0, first=t2 - t1, per_point=best / n * 1e9,
                      iterations=float(sw.iterations.mean()), sorted=None)))
"""


def run(path, level, n):
    out = subprocess.run([sys.executable, "-c", RUN, path, level, str(n)], capture_output=True,
                         text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def slope(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx)


def main():
    sizes = [int(a) for a in sys.argv[1:]] or [1, 2, 5, 10, 20, 50]
    rows = []
    print(f"{'N':>3s} {'coords':>6s} {'build s':>8s} {'lines':>7s} {'compile s':>10s} "
          f"{'cached s':>9s} {'ns/point':>9s} {'ns/point/loop':>14s} {'iters':>6s}")
    for n_loops in sizes:
        model = chain(n_loops)
        outdir = tempfile.mkdtemp(prefix=f"mechgen-chain{n_loops}-")
        t0 = time.perf_counter()
        path = build(model, outdir)
        t_build = time.perf_counter() - t0
        with open(path) as fh:
            lines = fh.read().count("\n")
        cold = run(path, "acceleration", 2000)
        warm = run(path, "acceleration", 2000)
        row = dict(N=n_loops, n=len(model.coords), build=t_build, lines=lines,
                   compile=cold["first"] + cold["load"], cached=warm["first"] + warm["load"],
                   per_point=warm["per_point"], iterations=warm["iterations"])
        rows.append(row)
        print(f"{n_loops:3d} {row['n']:6d} {t_build:8.2f} {lines:7d} {row['compile']:10.1f} "
              f"{row['cached']:9.2f} {row['per_point']:9.0f} {row['per_point'] / n_loops:14.0f} "
              f"{row['iterations']:6.2f}", flush=True)
    if len(rows) >= 3:
        big = [r for r in rows if r["N"] >= 2] or rows
        xs = [r["N"] for r in big]
        print("growth exponents k (time ∝ N^k, fitted on N >= 2): "
              f"build {slope(xs, [r['build'] for r in big]):.2f}, "
              f"compile {slope(xs, [r['compile'] for r in big]):.2f}, "
              f"per point {slope(xs, [r['per_point'] for r in big]):.2f}")


if __name__ == "__main__":
    main()
