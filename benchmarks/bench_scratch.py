"""The written fast sweep with its scratch in locals (mechgen.compiler.solver.scratch)
against the same module built without that pass, side by side in one process: ns a point
of sweep_fast (positions, all levels) and, for a model with masses, sweep_fast_forces
and sweep_fast_statics; every array compared bit for bit first.

    python benchmarks/bench_scratch.py [MODEL.py ...] [--points 100000] [--rounds 7]
    (default: the quick-return with forces and the Strandbeest leg with masses)
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
import types

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

import mechgen.compiler.context as context          # noqa: E402
from mechgen.compiler.build import build             # noqa: E402
from mechgen.model.loader import load_models         # noqa: E402

MODELS = (os.path.join(ROOT, "examples", "quick_return_forces.py"),
          os.path.join(ROOT, "benchmarks", "strandbeest_forces.py"))


def built(path, folder):
    """The module text of the model at ``path``, with and without the pass."""
    model = load_models(path)[0]
    new = build(model, os.path.join(folder, "locals"))
    keep = context.scalar_scratch
    context.scalar_scratch = lambda lines, n: lines
    try:
        old = build(model, os.path.join(folder, "arrays"))
    finally:
        context.scalar_scratch = keep
    return old, new


def load(name, path):
    """The module compiled in this process (numba's cache left alone)."""
    with open(path, encoding="utf-8") as fh:
        text = fh.read().replace("cache=True", "cache=False")
    mod = types.ModuleType(name)
    sys.modules[name] = mod
    exec(compile(text, path, "exec"), mod.__dict__)
    return mod


def runs(m, ts):
    """name -> (call, arrays it fills) of each sweep the module writes out."""
    N, n = ts.shape[0], m.N_COORDS
    p, q0 = np.array(m.PARAMETER_DEFAULTS, float), np.array(m.GUESS, float)
    none = np.zeros((0, n))

    def kin(full):
        a = [np.zeros((N, n)), np.zeros((N, n)) if full else none,
             np.zeros((N, n)) if full else none, np.zeros((N, 3), np.int16)]
        return (lambda: m.sweep_fast(ts, q0, p, 1e-10, 1e-10, 50, *a)), a

    def forces(fn, full):
        nf = max(1, len(getattr(m, "DRIVER_ROWS", ())))
        a = [np.zeros((N, n)), np.zeros((N, n)) if full else none,
             np.zeros((N, n)) if full else none, np.zeros((N, 3), np.int16),
             np.zeros((N, m.N_EQS)), np.zeros((N, nf)), np.zeros(N)]
        return (lambda: getattr(m, fn)(ts, q0, p, 1e-10, 1e-10, 50, *a)), a
    out = {"position": kin(False), "all levels": kin(True)}
    if getattr(m, "FORCE_FUSED", False):
        out["dynamic"] = forces("sweep_fast_forces", True)
    if getattr(m, "STATIC_FUSED", False):
        out["static"] = forces("sweep_fast_statics", False)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("models", nargs="*", default=MODELS)
    ap.add_argument("--points", type=int, default=100_000)
    ap.add_argument("--rounds", type=int, default=7)
    args = ap.parse_args()
    ts = np.linspace(0.0, 1.0, args.points, endpoint=False)
    folder = tempfile.mkdtemp(prefix="mechgen-scratch-")
    print(f"ns a point at {args.points} points, medians of {args.rounds} interleaved rounds")
    for path in args.models:
        old, new = built(path, os.path.join(folder, os.path.basename(path)[:-3]))
        name = os.path.basename(path)[:-3]
        sides = {"arrays": runs(load(name + "_arrays", old), ts),
                 "locals": runs(load(name + "_locals", new), ts)}
        for kind, (call, arrays) in sides["arrays"].items():
            done = call(), sides["locals"][kind][0]()
            same = done[0] == done[1] and all(
                np.array_equal(a, b, equal_nan=True)
                for a, b in zip(arrays, sides["locals"][kind][1]))
            if not same:
                raise SystemExit(f"{name} {kind}: the two modules differ")
        times = {(side, kind): [] for side in sides for kind in sides[side]}
        for _ in range(args.rounds):
            for side, table in sides.items():
                for kind, (call, _) in table.items():
                    t0 = time.perf_counter()
                    call()
                    times[side, kind].append((time.perf_counter() - t0) / args.points * 1e9)
        for kind in sides["arrays"]:
            a = statistics.median(times["arrays", kind])
            b = statistics.median(times["locals", kind])
            print(f"{name:22s} {kind:11s} arrays {a:7.1f}  locals {b:7.1f}  ratio {b / a:.3f}"
                  "  (same bits)")


if __name__ == "__main__":
    main()
