"""What watching the branch at every point costs: this tree's generated modules against
an earlier commit's, side by side in one process (interleaved rounds, best of each).

    python benchmarks/bench_branch_cost.py --baseline 72cbf0c
    python benchmarks/bench_branch_cost.py --baseline 72cbf0c --quick

Per module (quick-return, Strandbeest leg): ns per point of
- the quick path, sweep_fast, with derivatives (full) and positions only, at 10^5 points;
- the careful continuation, sweep(), at level acceleration (method sorted), 10^4 points;
- a design table through mech.sweep(params=...) on one thread (workers=1), 200 designs
  × 1,000 times, positions and all levels;
and the ratio now / before, with the largest difference between the two results.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, ROOT)

import mechgen  # noqa: E402
from mechgen.protocol import METHOD_SORTED, REPORT_SIZE  # noqa: E402

MODULES = ("quick_return", "strandbeest_leg")
TABLE_PARAM = {"quick_return": ("longitud", 2.0, 3.5, "X4"), "strandbeest_leg": None}


def _files(name, baseline, folder):
    if os.path.isdir(baseline):         # a folder holding that commit's modules
        with open(os.path.join(baseline, f"{name}.py")) as fh:
            before = fh.read()
    else:
        before = subprocess.run(["git", "-C", ROOT, "show", f"{baseline}:generated/{name}.py"],
                                capture_output=True, text=True, check=True).stdout
    texts = {"now": open(os.path.join(ROOT, "generated", f"{name}.py")).read(), "before": before}
    out = {}
    for label, text in texts.items():
        path = os.path.join(folder, f"{label}_{name}.py")
        with open(path, "w") as fh:
            fh.write(text)
        out[label] = path
    return out


def _timed(fn, reps):
    t0 = time.perf_counter()
    for _ in range(reps):
        r = fn()
    return (time.perf_counter() - t0) / reps, r


def cases(mech, name, quick):
    """{case: (callable returning an array to compare, points)}."""
    mod, p = mech.module, mech.p
    n = len(mech.coordinates)
    q0 = np.array(mod.GUESS, dtype=float)
    out = {}
    N = 10**4 if quick else 10**5
    ts = np.linspace(0.0, 1.0, N)
    Q, QD, QDD = np.zeros((N, n)), np.zeros((N, n)), np.zeros((N, n))
    S, none = np.zeros((N, 3), dtype=np.int16), np.zeros((0, n))

    def fast(qd, qdd):
        def run():
            done = mod.sweep_fast(ts, q0, p, 1e-10, 1e-10, 50, Q, qd, qdd, S)
            assert done == N, done
            return Q.copy()
        return run
    out["sweep_fast full"] = (fast(QD, QDD), N)
    out["sweep_fast position"] = (fast(none, none), N)
    M = 10**3 if quick else 10**4
    tm = np.linspace(0.0, 1.0, M)
    Qm, QDm, QDDm = np.zeros((M, n)), np.zeros((M, n)), np.zeros((M, n))
    Sm, rep = np.zeros((M, 3), dtype=np.int16), np.zeros(REPORT_SIZE)

    def careful():
        done = mod.sweep(tm, q0, p, 2, 1e-10, 1e-10, 50, METHOD_SORTED, Qm, QDm, QDDm, Sm, rep)
        assert done == M, done
        return Qm.copy()
    out["sweep() acceleration"] = (careful, M)
    spec = TABLE_PARAM.get(name)
    if spec:
        key, lo, hi, column = spec
        D, nt = (50 if quick else 200), 1000
        values = np.linspace(lo, hi, D)
        for level in ("position", "acceleration"):
            def table(level=level):
                tab = mech.sweep(0.0, 1.0, nt, params={key: values}, level=level, workers=1)
                return np.asarray(tab[column], dtype=float).copy()
            out[f"table {level}"] = (table, D * nt)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--baseline", required=True,
                    help="a commit whose generated modules to run beside (or a folder of them)")
    ap.add_argument("--modules", default=",".join(MODULES))
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    folder = tempfile.mkdtemp(prefix="mechgen-branch-")
    print("ns per point, best of interleaved rounds; now / before")
    for name in args.modules.split(","):
        mechs = {label: mechgen.load(path, tier="compiled")
                 for label, path in _files(name, args.baseline, folder).items()}
        runs = {label: cases(m, name, args.quick) for label, m in mechs.items()}
        best, last = {}, {}
        for label in runs:                      # compile (or load numba's cache) first
            for fn, _ in runs[label].values():
                fn()
        for _ in range(args.rounds):
            for case in runs["now"]:
                for label in ("before", "now"):
                    fn, points = runs[label][case]
                    dt, r = _timed(fn, 1)
                    best[label, case] = min(best.get((label, case), np.inf), dt / points * 1e9)
                    last[label, case] = r
        for case in runs["now"]:
            a, b = best["now", case], best["before", case]
            diff = float(np.nanmax(np.abs(last["now", case] - last["before", case])))
            print(f"{name:>16} {case:<22} now {a:8.1f}  before {b:8.1f}  ratio {a / b:5.3f}  "
                  f"max diff {diff:.1e}")


if __name__ == "__main__":
    main()
