"""What one ``mech.solve`` costs in Python, this tree against an older commit side by side
in one process: the older runtime is extracted by ``git archive`` into a temporary folder
as the package ``mechgen_old`` (its imports are relative) and its Mechanism wraps the same
loaded module object, so both call the same compiled functions. Rounds alternate between
the two; each figure is the best round's time per call.

Cases, at levels position, acceleration, dynamic and static (quick_return_forces, a
mechanism with mass and a fused dynamic path; press_motor, whose multipliers are solved
by force_rows): ``solve(t)`` over a turn (2000 times, the way kept after the first),
``solve(t)`` at the same t again, and ``solve(t, guess=g)`` over a turn. Before timing,
every case's results are compared field by field, bit for bit: q, qd, qdd, the
multipliers, iterations, residual, singular, method.

    python benchmarks/bench_solve_overhead.py [--old 18ab078] [--rounds 5]
"""
from __future__ import annotations

import argparse
import importlib
import os
import shutil
import subprocess
import sys
import tempfile
import timeit

import numpy as np

import mechgen

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CASES = (("quick_return", ("position", "acceleration")),
         ("quick_return_forces", ("position", "acceleration", "dynamic", "static")),
         ("press_motor", ("dynamic", "static")))


def old_runtime(rev):
    """The Mechanism class of mechgen at ``rev``, imported as mechgen_old."""
    where = tempfile.mkdtemp(prefix="mechgen-old-")
    archive = subprocess.run(["git", "-C", ROOT, "archive", rev, "mechgen"], check=True,
                             capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", where], input=archive, check=True)
    shutil.move(os.path.join(where, "mechgen"), os.path.join(where, "mechgen_old"))
    sys.path.insert(0, where)
    return importlib.import_module("mechgen_old.runtime.mechanism").Mechanism


def fields(s):
    """What a solution says, as bytes and plain values (a bit-for-bit comparison)."""
    arrays = [None if a is None else np.asarray(a).tobytes() for a in (s.q, s.qd, s.qdd)]
    lam = getattr(s, "lam", None)
    return (s.t, *arrays, None if lam is None else lam.tobytes(), s.iterations,
            repr(s.residual), s.singular, s.method, getattr(s, "indeterminate", None))


def best(fn, rounds):
    return min(timeit.repeat(fn, number=1, repeat=rounds))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--old", default="18ab078", help="the commit to compare with")
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args()
    Old = old_runtime(args.old)
    ts = [float(t) for t in np.linspace(0.0, 1.0, 2000)]
    print(f"per call, µs (best of {args.rounds} alternating rounds); old = {args.old}, "
          f"new = this tree")
    print(f"{'model':<21}{'level':<14}{'case':<22}{'old':>9}{'new':>9}{'new/old':>9}")
    for name, levels in CASES:
        new = mechgen.load(os.path.join(ROOT, "generated", name + ".py"), tier="compiled")
        old = Old(new.module)           # the same module object: the same compiled code
        g = new.guess.copy()
        for level in levels:
            cases = (("solve(t) over a turn", lambda m: [m.solve(t, level=level) for t in ts]),
                     ("solve(0.37) again", lambda m: [m.solve(0.37, level=level)
                                                      for _ in range(len(ts))]),
                     ("guess= over a turn", lambda m: [m.solve(t, level=level, guess=g)
                                                       for t in ts]))
            for label, run in cases:
                a, b = run(old), run(new)          # (also the first calls: compiled here)
                if [fields(s) for s in a] != [fields(s) for s in b]:
                    raise SystemExit(f"{name} {level} {label}: old and new results differ")
                times = {"old": [], "new": []}
                for _ in range(args.rounds):
                    for key, mech in (("old", old), ("new", new)):
                        times[key].append(best(lambda: run(mech), 1) / len(ts))
                o, n = min(times["old"]) * 1e6, min(times["new"]) * 1e6
                print(f"{name:<21}{level:<14}{label:<22}{o:>9.2f}{n:>9.2f}{n / o:>9.2f}")
    print("(results compared bit for bit before timing: identical)")


if __name__ == "__main__":
    main()
