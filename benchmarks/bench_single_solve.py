"""What following the motion costs a single solve (issue 20): ``mech.solve(t)`` (the
careful continuation from the guess's configuration, its way kept every 1/16 of time)
against ``mech.solve(t, guess=mech.guess)`` (Newton from the guess at t: what solve(t)
did before), in one process, on the committed modules. Times: 2000 times over a turn
(the path known after the first), the same time again and again, and the first solve
of a fresh path (a new Mechanism, t = 0.97: 15 cells and the last step).

    python benchmarks/bench_single_solve.py [--rounds 5]
"""
from __future__ import annotations

import argparse
import os
import time
import timeit

import numpy as np

import mechgen

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODELS = ("quick_return", "fourbar", "cam_eccentric")


def best(fn, number, rounds):
    return min(timeit.repeat(fn, number=1, repeat=rounds)) / number


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args()
    ts = np.linspace(0.0, 1.0, 2000)
    print(f"{'model':<16}{'case':<34}{'guess= (Newton)':>16}{'solve(t) (follows)':>20}{'ratio':>8}")
    for name in MODELS:
        mech = mechgen.load(os.path.join(ROOT, "generated", name + ".py"), tier="compiled")
        g = mech.guess
        mech.solve(0.5)
        mech.solve(0.5, guess=g)

        def sweep_new():
            for t in ts:
                mech.solve(t)

        def sweep_old():
            for t in ts:
                mech.solve(t, guess=g)

        old = best(sweep_old, len(ts), args.rounds)
        new = best(sweep_new, len(ts), args.rounds)
        print(f"{name:<16}{'2000 times over a turn':<34}{old * 1e6:>13.2f} µs{new * 1e6:>17.2f} µs"
              f"{new / old:>8.2f}")
        old = best(lambda: [mech.solve(0.37, guess=g) for _ in range(500)], 500, args.rounds)
        new = best(lambda: [mech.solve(0.37) for _ in range(500)], 500, args.rounds)
        print(f"{'':<16}{'t = 0.37, 500 times':<34}{old * 1e6:>13.2f} µs{new * 1e6:>17.2f} µs"
              f"{new / old:>8.2f}")
        cold = []
        for _ in range(args.rounds):
            fresh = mech.with_params()
            t0 = time.perf_counter()
            fresh.solve(0.97)
            cold.append(time.perf_counter() - t0)
        old = best(lambda: mech.solve(0.97, guess=g), 1, args.rounds)
        print(f"{'':<16}{'first solve(0.97), fresh path':<34}{old * 1e6:>13.2f} µs"
              f"{min(cold) * 1e6:>17.2f} µs{min(cold) / old:>8.2f}")


if __name__ == "__main__":
    main()
