"""What sensitivities cost: a sweep with the derivatives to every parameter (up to 4
asked) against the same sweep without them, and a single solve with and without, side
by side in one process (compiled tier, numba's cache warm before timing); then their
error against central differences of the closed-form-free module itself at a few points
(a plausibility check only: the references are in tests/test_sensitivity_references.py).

    python benchmarks/bench_sensitivities.py                    # quick-return, Strandbeest
    python benchmarks/bench_sensitivities.py --n 100000 --rounds 5

Prints per model: the sweep's wall time per point without and with sensitivities (the
sweep is mech.sweep's; at position level its quick path solves them on its way where the
sensitivity module has it: SWEEP_FUSED, mechgen/compiler/sensitivity_sweep.py), their
ratio, the same sweep then the separate compiled pass over its points (of_sweep, what a
sweep without the fused path does: "pass ns/pt" and its ratio), and the same for a single
solve (median of many).
"""
from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, ROOT)
os.environ.setdefault("MECHGEN_TIER", "compiled")

import mechgen  # noqa: E402
from mechgen.model.loader import load_models, pick_model  # noqa: E402
from mechgen.runtime.sensitivity.solve import of_sweep  # noqa: E402

MODELS = (("examples", "quick_return"), ("benchmarks", "strandbeest_params"))


def _mech(where, name, folder):
    m = pick_model(load_models(os.path.join(ROOT, where, name + ".py")), None)
    return mechgen.compile(m, outdir=folder)


def best(fn, rounds):
    out = []
    for _ in range(rounds):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return min(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100_000)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--level", default="position")
    args = ap.parse_args(argv)
    folder = tempfile.mkdtemp(prefix="mechgen-bench-sens-")
    print(f"{'model':14s} {'params':>6s} {'sweep ns/pt':>12s} {'+sens ns/pt':>12s} {'ratio':>6s}"
          f" {'pass ns/pt':>11s} {'ratio':>6s} {'solve us':>9s} {'+sens us':>9s} {'ratio':>6s}")
    for where, name in MODELS:
        mech = _mech(where, name, folder)
        params = list(mech.parameter_names)[:4]
        n = args.n
        mech.sweep(0, 1, 11, level=args.level, sensitivities=params)     # compile, warm
        of_sweep(mech, mech.sweep(0, 1, 11, level=args.level), params)
        plain = best(lambda: mech.sweep(0, 1, n, level=args.level), args.rounds)
        sens = best(lambda: mech.sweep(0, 1, n, level=args.level, sensitivities=params),
                    args.rounds)
        apart = best(lambda: of_sweep(mech, mech.sweep(0, 1, n, level=args.level), params),
                     args.rounds)
        ts = np.linspace(0.05, 0.95, 200)
        mech.solve(0.3, level=args.level, sensitivities=params)
        mech.solve(0.3, level=args.level)

        def solves(with_sens):
            for t in ts:
                mech.solve(float(t), guess=mech.last, level=args.level,
                           sensitivities=params if with_sens else None)
        s0 = best(lambda: solves(False), args.rounds) / len(ts)
        s1 = best(lambda: solves(True), args.rounds) / len(ts)
        print(f"{name:14s} {len(params):6d} {plain / n * 1e9:12.1f} {sens / n * 1e9:12.1f} "
              f"{sens / plain:6.2f} {apart / n * 1e9:11.1f} {apart / plain:6.2f} "
              f"{s0 * 1e6:9.1f} {s1 * 1e6:9.1f} {s1 / s0:6.2f}")


if __name__ == "__main__":
    main()
