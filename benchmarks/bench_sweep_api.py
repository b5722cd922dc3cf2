"""What ``mech.sweep`` costs around its compiled loop (issue 12).

Run from anywhere:  python benchmarks/bench_sweep_api.py [--quick] [--json FILE]
                    python benchmarks/bench_sweep_api.py --module generated/strandbeest_leg.py

The quick-return of seed 001 (generated/quick_return.py, 9 coordinates), T in [0, 1], at
10^3, 10^4, 10^5 and 10^6 points, positions only and all levels. In one process, in
interleaved rounds (every method at both levels once per round, in turn), the best (with --median: the
median) time per point of:

- ``api``: ``mech.sweep(0.0, 1.0, N, level=...)``, fresh result arrays each call (the
  result dropped after the call, as a user's loop drops the one before);
- ``api_held``: the same while the previous result is still held (``sw =
  mech.sweep(...)`` in a loop: its memory cannot be reused, the new result's pages are
  fresh);
- ``api_out``: the same writing into the arrays of the previous result
  (``mech.sweep(..., out=sw)``);
- ``compiled``: the module's own loop, ``sweep_fast(ts, q0, p, ...)`` writing into
  preallocated arrays (Q, and QD, QDD for all levels; a position sweep passes them with
  no rows, as mech.sweep does);
- ``hand``: the hand-written sorted numba sweep of benchmarks/baselines.py (Th3, X4 and
  their derivatives only), also into a preallocated array.

It reports ns per point, the ratios to ``compiled``, the ratio position/all levels of
``api``, and the largest difference between the methods' numbers (api, api_out and
compiled should agree exactly; hand to about 1e-12). ``main()`` returns the rows and
prints the table (benchmarks/bench_startup.py calls it).
"""
from __future__ import annotations

import argparse
import gc
import json
import os
import statistics
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, ROOT)
sys.path.insert(0, HERE)

MODULE = os.path.join(ROOT, "generated", "quick_return.py")
SIZES = (10**3, 10**4, 10**5, 10**6)
LEVELS = ("position", "acceleration")
METHODS = ("api", "api_held", "api_out", "compiled", "hand")


def _methods(mech, N, level):
    """The four ways to run the sweep: name -> fn() returning what it computed as
    (Q, QD or None, QDD or None), plus a check that the compiled loop took every point."""
    import baselines
    from mechgen.protocol import LEVEL, STATUS_COLUMNS

    mod, n = mech.module, mech.n
    lev = LEVEL[level]
    ts = np.linspace(0.0, 1.0, N)
    q0 = mech.guess.copy()
    Q = np.empty((N, n))
    QD = np.empty((N, n) if lev >= 1 else (0, n))
    QDD = np.empty((N, n) if lev >= 2 else (0, n))
    S = np.empty((N, STATUS_COLUMNS), dtype=np.int16)
    H = np.empty((N, 6))
    keep = {"out": mech.sweep(0.0, 1.0, N, level=level)}

    def api():
        sw = mech.sweep(0.0, 1.0, N, level=level)
        return sw.Q, sw.QD, sw.QDD

    def api_held():
        keep["held"] = sw = mech.sweep(0.0, 1.0, N, level=level)
        return sw.Q, sw.QD, sw.QDD

    def api_out():
        sw = mech.sweep(0.0, 1.0, N, level=level, out=keep["out"])
        return sw.Q, sw.QD, sw.QDD

    def compiled():
        done = mod.sweep_fast(ts, q0, mech.p, mech.tol, mech.xtol, mech.maxit, Q, QD, QDD, S)
        if done != N:
            raise RuntimeError(f"sweep_fast stopped at point {done} of {N}")
        return Q, QD if lev >= 1 else None, QDD if lev >= 2 else None

    def hand():
        baselines.hand_sorted_sweep(ts, lev, mech.tol, H)
        return H

    out = {"api": api, "api_held": api_held, "api_out": api_out, "compiled": compiled}
    if mech.name == "quick_return":     # the hand-written baseline is the quick-return's
        out["hand"] = hand
    return out


def _differences(mech, results):
    """Largest |difference| of each method's numbers from the compiled loop's."""
    Q, QD, QDD = results["compiled"]
    out = {}
    for name in ("api", "api_held", "api_out"):
        q, qd, qdd = results[name]
        d = float(np.abs(q - Q).max())
        for a, b in ((qd, QD), (qdd, QDD)):
            if a is not None:
                d = max(d, float(np.abs(a - b).max()))
        out[name] = d
    H = results.get("hand")
    if H is None:
        out["hand"] = float("nan")
        return out
    th3, x4 = mech.coordinates.index("Th3"), mech.coordinates.index("X4")
    d = max(float(np.abs(H[:, 0] - Q[:, th3]).max()), float(np.abs(H[:, 1] - Q[:, x4]).max()))
    if QD is not None:
        d = max(d, float(np.abs(H[:, 2] - QD[:, th3]).max() / (1 + np.abs(QD).max())),
                float(np.abs(H[:, 3] - QD[:, x4]).max() / (1 + np.abs(QD).max())))
    out["hand"] = d
    return out


def measure(mech, N, rounds, stat=min):
    """For each level: {method: ns per point (``stat`` of the rounds)} and {method: max
    difference from compiled}; both levels' methods interleaved in every round."""
    fns, diffs = {}, {}
    for level in LEVELS:
        these = _methods(mech, N, level)
        results = {name: fn() for name, fn in these.items()}   # warm: compile, first touch
        diffs[level] = _differences(mech, results)
        del results
        fns.update({(level, name): fn for name, fn in these.items()})
    reps = max(1, 20_000 // N)          # timing samples of at least ~20,000 points
    times = {key: [] for key in fns}
    # api_held in rounds of its own: the result it holds would keep api from reusing the
    # memory of the one it dropped (a Mechanism keeps one large block for reuse)
    for group in ([k for k in fns if k[1] != "api_held"], [k for k in fns if k[1] == "api_held"]):
        for _ in range(rounds):
            for key in group:
                fn = fns[key]
                gc.collect()
                t0 = time.perf_counter()
                for _ in range(reps):
                    r = fn()
                    del r               # a fresh result is dropped before the next call
                times[key].append((time.perf_counter() - t0) / (reps * N) * 1e9)
    ns = {level: {name: stat(times[(level, name)]) if times.get((level, name)) else float("nan")
                  for name in METHODS} for level in LEVELS}
    return ns, diffs


def main(argv=None, sizes=SIZES, rounds=None, quiet=False):
    """Measure and print the table; returns a list of rows (dicts)."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer rounds, up to 10^5 points")
    ap.add_argument("--json", help="write the rows to this file")
    ap.add_argument("--median", action="store_true",
                    help="the median of the rounds (default: the best, less sensitive to "
                         "other work on a shared machine)")
    ap.add_argument("--module", default=MODULE,
                    help="the generated module to sweep (default: generated/quick_return.py; "
                         "the hand-written baseline is the quick-return's only)")
    args = ap.parse_args([] if argv is None else argv)
    import mechgen
    mech = mechgen.load(args.module)
    if args.quick:
        sizes = tuple(s for s in sizes if s <= 10**5)
    rows = []
    say = (lambda *a: None) if quiet else print
    stat = statistics.median if args.median else min
    say(f"mech.sweep against its compiled loop: {os.path.basename(args.module)}, ns per point "
        f"({'median' if args.median else 'best'} of interleaved rounds)")
    say(f"{'points':>8} {'level':>12} " + " ".join(f"{m:>9}" for m in METHODS) +
        f" {'api/comp':>9} {'held/comp':>9} {'out/comp':>9} {'hand/comp':>9}"
        "  max |diff| api, held, out, hand")
    for N in sizes:
        r = rounds or (3 if args.quick else (5 if N >= 10**6 else 9))
        per_level, all_diffs = measure(mech, N, r, stat)
        for level in LEVELS:
            ns, diffs = per_level[level], all_diffs[level]
            row = dict(points=N, level=level, ns=ns, diffs=diffs,
                       api_ratio=ns["api"] / ns["compiled"],
                       held_ratio=ns["api_held"] / ns["compiled"],
                       out_ratio=ns["api_out"] / ns["compiled"],
                       hand_ratio=ns["hand"] / ns["compiled"])
            rows.append(row)
            say(f"{N:>8} {level:>12} " + " ".join(f"{ns[m]:9.1f}" for m in METHODS) +
                f" {row['api_ratio']:9.2f} {row['held_ratio']:9.2f} {row['out_ratio']:9.2f}"
                f" {row['hand_ratio']:9.2f}  {diffs['api']:.1e}, {diffs['api_held']:.1e}, "
                f"{diffs['api_out']:.1e}, {diffs['hand']:.1e}")
        pos, full = per_level["position"]["api"], per_level["acceleration"]["api"]
        hpos, hfull = per_level["position"]["api_held"], per_level["acceleration"]["api_held"]
        rows.append(dict(points=N, position_over_full=pos / full,
                         held_position_over_full=hpos / hfull))
        say(f"{N:>8} {'position / all levels:':>30} api {pos / full:.2f}, "
            f"api_held {hpos / hfull:.2f}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=1)
    return rows


if __name__ == "__main__":
    main(sys.argv[1:])
