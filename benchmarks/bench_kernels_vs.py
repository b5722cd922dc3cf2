"""A generated module's compiled loops, this tree's against an earlier commit's, side by
side in one process: the modules' texts are run as plain modules (numba, no cache), so
two module formats that no single runtime loads can be timed together.

    python benchmarks/bench_kernels_vs.py --baseline 326bb16 [--rounds 7]

Per module (quick-return, Strandbeest leg), ns a point: sweep_fast at all levels and at
positions (10^5 points), the careful sweep() at level acceleration (10^4), and the
design loop sweep_designs over 200 designs × 1,000 times at positions and all levels
(the baseline's from one start vector, this tree's from each design's: the guess's
row repeated, and start_designs' cost for the same designs timed on its own); with the
largest difference between the two results.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
import types

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODULES = {"quick_return": (0, 2.0, 3.5), "strandbeest_leg": None}


def load(name, text):
    mod = types.ModuleType(name)
    sys.modules[name] = mod
    exec(compile(text.replace("cache=True", "cache=False"), name, "exec"), mod.__dict__)
    return mod


def best(fn, rounds):
    out = np.inf
    for _ in range(rounds):
        t0 = time.perf_counter()
        fn()
        out = min(out, time.perf_counter() - t0)
    return out


def cases(m, designs):
    n = m.N_COORDS
    p, q0 = np.array(m.PARAMETER_DEFAULTS), np.array(m.GUESS)
    none = np.zeros((0, n))
    ts5, ts4, ts3 = (np.linspace(0.0, 1.0, k) for k in (100_000, 10_000, 1_000))
    A = {k: np.zeros((100_000, n)) for k in ("Q", "QD", "QDD")}
    S = np.zeros((100_000, 3), dtype=np.int16)
    R = np.zeros(m.REPORT_SIZE)
    out = {
        "sweep_fast all levels": (lambda: m.sweep_fast(ts5, q0, p, 1e-10, 1e-10, 50, A["Q"],
                                                       A["QD"], A["QDD"], S), 100_000, "Q"),
        "sweep_fast positions": (lambda: m.sweep_fast(ts5, q0, p, 1e-10, 1e-10, 50, A["Q"],
                                                      none, none, S), 100_000, "Q"),
        "sweep() acceleration": (lambda: m.sweep(ts4, q0, p, 2, 1e-10, 1e-10, 50, 1,
                                                 A["Q"][:10_000], A["QD"][:10_000],
                                                 A["QDD"][:10_000], S[:10_000], R),
                                 10_000, "Q"),
    }
    if designs is not None:
        col, lo, hi = designs
        P = np.tile(p, (200, 1))
        P[:, col] = np.linspace(lo, hi, 200)
        T = {k: np.zeros((200, 1000, n)) for k in ("Q", "QD", "QDD")}
        TS = np.zeros((200, 1000, 3), dtype=np.int16)
        new = hasattr(m, "start_designs")
        start = np.ascontiguousarray(np.tile(q0, (200, 1))) if new else q0
        for lev, name in ((0, "positions"), (2, "all levels")):
            out[f"sweep_designs {name}"] = (
                lambda lev=lev: m.sweep_designs(ts3, start, P, lev, 1e-10, 1e-10, 50, 0,
                                                T["Q"], T["QD"] if lev else none[None],
                                                T["QDD"] if lev else none[None], TS),
                200_000, "T")
        if new:
            Q0, S0 = np.zeros((200, n)), np.zeros(200, dtype=np.int64)
            ref = q0.copy()
            m.solve_point(ref, 0.0, p, 1e-10, 1e-10, 50, 0, np.zeros(m.POINT_INFO_SIZE))
            out["start_designs (per design)"] = (
                lambda: m.start_designs(ts3[:1], ref, q0, p, P, 1e-10, 1e-10, 50, 0, Q0, S0),
                200, "none")
    out["_arrays"] = (A, T if designs is not None else None)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--baseline", required=True)
    ap.add_argument("--rounds", type=int, default=7)
    args = ap.parse_args(argv)
    print("ns a point (start_designs: a design), best of interleaved rounds; now / before")
    for name, designs in MODULES.items():
        rel = f"generated/{name}.py"
        old_text = subprocess.run(["git", "-C", ROOT, "show", f"{args.baseline}:{rel}"],
                                  capture_output=True, text=True, check=True).stdout
        with open(os.path.join(ROOT, rel), encoding="utf-8") as fh:
            new_text = fh.read()
        mods = {"before": load(name + "_before", old_text), "now": load(name + "_now", new_text)}
        runs = {k: cases(m, designs) for k, m in mods.items()}
        arrays = {k: runs[k].pop("_arrays", None) for k in runs}
        for label in runs:
            for fn, _, _ in runs[label].values():
                fn()                    # compile
        got = {}
        times = {}
        for _ in range(args.rounds):
            for case in runs["now"]:
                for label in ("before", "now"):
                    if case not in runs[label]:
                        continue
                    fn, points, kind = runs[label][case]
                    dt = best(fn, 1)
                    times[label, case] = min(times.get((label, case), np.inf), dt / points * 1e9)
                    A, T = arrays[label]
                    got[label, case] = (A["Q"].copy() if kind == "Q" else
                                        T["Q"].copy() if kind == "T" else None)
        for case in runs["now"]:
            a = times["now", case]
            if ("before", case) not in times:
                print(f"{name:>16} {case:<28} now {a:9.1f}")
                continue
            b = times["before", case]
            if got["now", case] is None:        # (a case whose arrays are not compared)
                said = "max diff n/a"
            else:
                said = f"max diff {np.max(np.abs(got['now', case] - got['before', case])):.1e}"
            print(f"{name:>16} {case:<28} now {a:9.1f}  before {b:9.1f}  ratio {a / b:5.3f}  "
                  + said)


if __name__ == "__main__":
    main()
