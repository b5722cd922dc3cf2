"""Mechanism.sweep of this tree against an older commit's runtime, side by side in one
process (as bench_solve_overhead.py: the older package extracted by ``git archive`` as
``mechgen_old``, its Mechanism wrapping the same loaded module object, so both call the
same compiled functions). Each case alternates between the two, round after round; each
figure is the best round's time per point; the ratio is new / old. Before timing, each
case's arrays (t, Q, QD, QDD, status) are compared bit for bit.

    python benchmarks/bench_runtime_side_by_side.py --old f544645 --rounds 15
"""
from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

import mechgen

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from bench_solve_overhead import old_runtime  # noqa: E402

CASES = (("quick_return", ("position", "acceleration", "dynamic")),
         ("strandbeest_leg", ("position", "acceleration")))
CASES_FORCES = {"dynamic": "quick_return_forces"}
SIZES = (100, 10_000, 200_000)


def arrays(sw):
    return [None if a is None else np.asarray(a).tobytes()
            for a in (sw.t, sw.Q, sw.QD, sw.QDD, sw.status, getattr(sw, "LAM", None))]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--old", default="f544645", help="the commit to compare with")
    ap.add_argument("--rounds", type=int, default=15)
    args = ap.parse_args(argv)
    Old = old_runtime(args.old)
    print(f"ns per point (best of {args.rounds} alternating rounds); old = {args.old}, "
          "new = this tree")
    print(f"{'model':<22}{'level':<14}{'points':>8}{'old':>10}{'new':>10}{'new/old':>9}")
    worst = 0.0
    for name, levels in CASES:
        for level in levels:
            model = CASES_FORCES.get(level, name)
            new = mechgen.load(os.path.join(ROOT, "generated", model + ".py"), tier="compiled")
            old = Old(new.module)
            for N in SIZES:
                a, b = new.sweep(0.0, 1.0, N, level=level), old.sweep(0.0, 1.0, N, level=level)
                assert arrays(a) == arrays(b), (model, level, N, "the numbers differ")
                del a, b
                reps = max(1, 20_000 // N)
                best = {"old": float("inf"), "new": float("inf")}
                for _ in range(args.rounds):
                    for label, mech in (("old", old), ("new", new)):
                        t0 = time.perf_counter()
                        for _ in range(reps):
                            mech.sweep(0.0, 1.0, N, level=level)
                        best[label] = min(best[label], (time.perf_counter() - t0) / reps)
                o, n = best["old"] / N * 1e9, best["new"] / N * 1e9
                worst = max(worst, n / o)
                print(f"{model:<22}{level:<14}{N:>8}{o:>10.1f}{n:>10.1f}{n / o:>9.3f}")
    print(f"bit-identical in every case; largest new/old: {worst:.3f}")


if __name__ == "__main__":
    main()
