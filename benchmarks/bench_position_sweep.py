"""A position sweep against a full one, in the generated module's own quick path
(sweep_fast, preallocated arrays), and against the same module of an earlier commit.

    python benchmarks/bench_position_sweep.py                       # quick-return, Strandbeest leg
    python benchmarks/bench_position_sweep.py --baseline 414988d    # ... and that commit's modules

Per module and size (10^3 .. 10^6 points over T in [0, 1]), best of interleaved rounds,
ns per point of sweep_fast with QD, QDD rows (full) and without (position), the ratio
position / full, and with --baseline the same for the modules of that commit (git show
COMMIT:generated/NAME.py), all in one process; then the largest difference between the
position sweep's Q and the full sweep's.
"""
from __future__ import annotations

import argparse
import importlib
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
MODULES = ("quick_return", "strandbeest_leg")
SIZES = (10**3, 10**4, 10**5, 10**6)


def _modules(name, baseline, folder):
    """{label: module}: this tree's generated module and, with a baseline, that commit's
    (copied under other names, so that both import, and compile, side by side)."""
    out = {}
    texts = {"now": open(os.path.join(ROOT, "generated", f"{name}.py")).read()}
    if baseline:
        texts["before"] = subprocess.run(["git", "-C", ROOT, "show", f"{baseline}:generated/{name}.py"],
                                         capture_output=True, text=True, check=True).stdout
    for label, text in texts.items():
        with open(os.path.join(folder, f"{label}_{name}.py"), "w") as fh:
            fh.write(text)
        out[label] = importlib.import_module(f"{label}_{name}")
    return out


def measure(mods, N, rounds=7):
    some = next(iter(mods.values()))
    n = some.N_COORDS
    p, q0 = np.array(some.PARAMETER_DEFAULTS), np.array(some.GUESS, dtype=float)
    ts = np.linspace(0.0, 1.0, N)
    Q, QD, QDD = np.zeros((N, n)), np.zeros((N, n)), np.zeros((N, n))
    S, none = np.zeros((N, 3), dtype=np.int16), np.zeros((0, n))
    reps = max(1, 20_000 // N)
    best, Qs = {}, {}
    for _ in range(rounds):
        for label, mod in mods.items():
            for level, (qd, qdd) in (("full", (QD, QDD)), ("position", (none, none))):
                t0 = time.perf_counter()
                for _ in range(reps):
                    done = mod.sweep_fast(ts, q0, p, 1e-10, 1e-10, 50, Q, qd, qdd, S)
                ns = (time.perf_counter() - t0) / (reps * N) * 1e9
                if done != N:
                    raise RuntimeError(f"{label} {level}: sweep_fast stopped at {done} of {N}")
                best[label, level] = min(best.get((label, level), np.inf), ns)
                Qs[label, level] = Q.copy()
    diff = float(np.abs(Qs["now", "position"] - Qs["now", "full"]).max())
    return best, diff


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--baseline", help="a commit whose generated modules to run beside")
    ap.add_argument("--modules", default=",".join(MODULES))
    ap.add_argument("--quick", action="store_true", help="up to 10^5 points, 3 rounds")
    args = ap.parse_args(argv)
    folder = tempfile.mkdtemp(prefix="mechgen-bench-")
    sys.path.insert(0, folder)
    sizes = SIZES[:3] if args.quick else SIZES
    print("sweep_fast, ns per point (best of interleaved rounds); position / full")
    for name in args.modules.split(","):
        mods = _modules(name, args.baseline, folder)
        for N in sizes:
            best, diff = measure(mods, N, 3 if args.quick else 7)
            cells = [f"{label}: full {best[label, 'full']:6.1f} position "
                     f"{best[label, 'position']:6.1f} ({best[label, 'position'] / best[label, 'full']:.2f})"
                     for label in mods]
            print(f"{name:>16} {N:>8}  " + " | ".join(cells) + f" | max |Q pos - Q full| {diff:.1e}")


if __name__ == "__main__":
    main()
