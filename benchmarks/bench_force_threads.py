"""How a design table at the force levels scales over the cores, beside the kinematic
table: the quick-return of examples/quick_return_forces.py, 4,000 designs × 1,000 times,
reduce= on the crank driver's torque (level "dynamic") and on X4 (level "acceleration"),
on 1, 4 and every thread, in one process.

    PYTHONPATH=. MECHGEN_TIER=compiled python3 benchmarks/bench_force_threads.py [--designs N]
"""
import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import mechgen  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--designs", type=int, default=4000)
    args = ap.parse_args()
    mech = mechgen.load(os.path.join(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__))), "generated", "quick_return_forces.py"), tier="compiled")
    L = np.linspace(2.2, 3.5, args.designs)
    cores = os.cpu_count() or 1
    for level, red in (("acceleration", ["X4"]), ("dynamic", ["crank driver", "X4"])):
        kw = dict(params={"longitud": L}, level=level, reduce=red, on_fail="ignore")
        mech.sweep(0.0, 1.0, 8, **dict(kw, params={"longitud": [2.5, 3.0]}))   # compiled
        res = {}
        for w in sorted({1, min(4, cores), cores}):
            t0 = time.perf_counter()
            mech.sweep(0.0, 1.0, 1000, workers=w, **kw)
            res[w] = time.perf_counter() - t0
        print(f"{level:12s} " + ", ".join(f"{w} thread(s) {s:.3f} s" for w, s in res.items())
              + f"; every core {res[1] / res[cores]:.2f}x one thread", flush=True)


if __name__ == "__main__":
    main()
