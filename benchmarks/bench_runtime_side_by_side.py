"""Mechanism.sweep of this tree against an older commit's runtime, side by side in one
process (as bench_solve_overhead.py: the older package extracted by ``git archive`` as
``mechgen_old``, its Mechanism wrapping the same loaded module object, so both call the
same compiled functions). Each case alternates between the two; each
figure is the best sweep's time per point (old, new, their ratio) and the median of the
ratios of the pairs, one sweep of each taken in turn (the order alternating): a machine
shared with other work slows single sweeps at random, which the median of pairs mostly
cancels. Before timing, each
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
    ap.add_argument("--sizes", type=int, nargs="*", default=SIZES)
    ap.add_argument("--min-pairs", type=int, default=15)
    args = ap.parse_args(argv)
    Old = old_runtime(args.old)
    print(f"ns per point (best of {args.rounds} alternating rounds); old = {args.old}, "
          "new = this tree")
    print(f"{'model':<22}{'level':<14}{'points':>8}{'old':>10}{'new':>10}{'new/old':>9}"
          f"{'median':>9}")
    worst = 0.0
    for name, levels in CASES:
        for level in levels:
            model = CASES_FORCES.get(level, name)
            new = mechgen.load(os.path.join(ROOT, "generated", model + ".py"), tier="compiled")
            old = Old(new.module)
            for N in args.sizes:
                a, b = new.sweep(0.0, 1.0, N, level=level), old.sweep(0.0, 1.0, N, level=level)
                assert arrays(a) == arrays(b), (model, level, N, "the numbers differ")
                del a, b
                pairs = max(args.min_pairs, args.rounds * 20_000 // N)
                best = {"old": float("inf"), "new": float("inf")}
                ratios = []
                for k in range(pairs):      # one sweep each, in turn, the order alternating
                    took = {}
                    for label, mech in ((("old", old), ("new", new)) if k % 2 else
                                        (("new", new), ("old", old))):
                        t0 = time.perf_counter()
                        mech.sweep(0.0, 1.0, N, level=level)
                        took[label] = time.perf_counter() - t0
                        best[label] = min(best[label], took[label])
                    ratios.append(took["new"] / took["old"])
                o, n = best["old"] / N * 1e9, best["new"] / N * 1e9
                med = float(np.median(ratios))
                worst = max(worst, med)
                print(f"{model:<22}{level:<14}{N:>8}{o:>10.1f}{n:>10.1f}{n / o:>9.3f}"
                      f"{med:>9.3f}")
    print(f"bit-identical in every case; largest median new/old: {worst:.3f}")


if __name__ == "__main__":
    main()
