"""Design tables of this tree against an older commit's, side by side: each tree builds the
quick-return's module with its own compiler and sweeps the same tables with its own
runtime (compiled tier), in fresh processes taken in turn (the old tree extracted by
``git archive``; each tree keeps its own numba cache, so only the first process of each
compiles). Per case: the table's arrays (Q, QD, QDD, status) compared bit for bit, and the
time per (design, time) point, the best of --repeat tables in each process, as medians
over the processes of each tree and the median of the ratios of their pairs.

    python benchmarks/bench_design_side_by_side.py --old 4835ad8 --rounds 5
    python benchmarks/bench_design_side_by_side.py --old 4835ad8 --loops

--loops: the compiled design loops alone, in one process: the old commit's generated
quick-return module (git show COMMIT:generated/quick_return.py) calling its
sweep_designs, and this tree's calling its two steps as the runtime does
(sweep_designs_fast, then sweep_designs_rest only where a design stopped early), on the
same arrays, interleaved rounds (best and median ns per point), at position and
acceleration level; the arrays compared bit for bit.

Cases: crank lengths that all assemble (every design takes the quick path alone) and
lengths of which some cannot reach every time (the careful rest of the sweep runs, and
fails), at position and acceleration level, on one thread (workers=1) and on every core;
and at the force levels ("dynamic", "static": the quick-return with forces, the crank
driver's effort reduced, the multipliers solved in the sweeps' own step).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

CASES = (("easy", (3.5, 4.1), "position", 1), ("easy", (3.5, 4.1), "acceleration", 1),
         ("hard", (3.5, 4.5), "acceleration", 1), ("easy", (3.5, 4.1), "acceleration", None),
         ("easy", (3.5, 4.1), "dynamic", 1), ("hard", (3.5, 4.5), "dynamic", 1),
         ("hard", (3.5, 4.5), "static", 1))

CHILD = r'''
import json, sys, time, warnings
import numpy as np
import mechgen
root, out, arrays, designs, times, repeat = sys.argv[1:7]
cases = json.loads(sys.argv[7])
warnings.simplefilter("ignore")
mechs = {f: mechgen.compile(mechgen.load_model(root + "/examples/" + f + ".py"), outdir=out,
                            tier="compiled") for f in ("quick_return", "quick_return_forces")}
res, keep = [], {}
for i, (kind, (lo, hi), level, workers) in enumerate(cases):
    P = {"longitud": np.linspace(lo, hi, int(designs))}
    forces = level in ("static", "dynamic")
    mech = mechs["quick_return_forces" if forces else "quick_return"]
    kw = {"reduce": ["crank driver"]} if forces else {}
    run = lambda: mech.design_sweep(0.0, 1.0, int(times), P, level=level, workers=workers,
                                    on_fail="ignore", **kw)
    tab = run()
    if forces:
        r = tab.reduced("crank driver")
        for part in ("min", "max", "tmin", "tmax"):
            keep[f"{i}_{part}"] = np.asarray(getattr(r, part))
    best = []
    for _ in range(int(repeat)):
        t0 = time.perf_counter()
        run()
        best.append(time.perf_counter() - t0)
    res.append(min(best) / (int(designs) * int(times)) * 1e9)
    for name in ("Q", "QD", "QDD", "status"):
        a = getattr(tab, name, None)
        if a is not None:
            keep[f"{i}_{name}"] = np.asarray(a)
np.savez(arrays, **keep)
print("BENCH " + json.dumps(res))
'''


def child(tree, out, arrays, args):
    env = dict(os.environ, PYTHONPATH=tree, NUMBA_CACHE_DIR=os.path.join(out, "nc"))
    env.pop("MECHGEN_TIER", None)
    res = subprocess.run([sys.executable, "-c", CHILD, tree, out, arrays, str(args.designs),
                          str(args.times), str(args.repeat), json.dumps(CASES)],
                         capture_output=True, text=True, env=env, cwd=out)
    line = [x for x in res.stdout.splitlines() if x.startswith("BENCH ")]
    if res.returncode or not line:
        raise SystemExit(f"{tree} failed:\n{res.stderr[-3000:]}")
    return json.loads(line[-1][6:])


LOOPS = r'''
import importlib, json, statistics, sys, time
import numpy as np
folder, D, N, rounds = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
sys.path.insert(0, folder)
new = importlib.import_module("quick_return")      # (a module puts itself in sys.modules
old = importlib.import_module("old_quick_return")  # under its model's name: this one first)
ts = np.linspace(0.0, 1.0, N)
P = np.tile(np.array(new.PARAMETER_DEFAULTS, dtype=float), (D, 1))
P[:, 0] = np.linspace(3.5, 4.5, D)          # the longest cannot turn: the rest runs
Q0 = np.tile(np.array(new.GUESS, dtype=float), (D, 1))
n = new.N_COORDS


def arrays(level):
    rows = N if level else 0
    return (np.zeros((D, N, n)), np.zeros((D, rows, n)), np.zeros((D, rows, n)),
            np.zeros((D, N, 1), dtype=np.int16))


def run_old(level, A):
    return old.sweep_designs(ts, Q0, P, level, 1e-10, 1e-10, 50, 0, *A)


def run_new(level, A):
    start = np.zeros(D, dtype=np.int64)
    new.sweep_designs_fast(ts, Q0, P, 1e-10, 1e-10, 50, 0, *A, start)
    if (start == N).all():
        return start
    return new.sweep_designs_rest(ts, Q0, P, level, 1e-10, 1e-10, 50, 0, *A, start)


out = {}
for level in (0, 2):
    A, B = arrays(level), arrays(level)
    same = np.array_equal(run_old(level, A), run_new(level, B)) and all(
        a.tobytes() == b.tobytes() for a, b in zip(A, B))
    t = {"old": [], "new": []}
    for r in range(rounds):
        for k in (("old", "new") if r % 2 == 0 else ("new", "old")):
            t0 = time.perf_counter()
            (run_old if k == "old" else run_new)(level, A if k == "old" else B)
            t[k].append((time.perf_counter() - t0) / (D * N) * 1e9)
    out[level] = {"same": bool(same), "old": [min(t["old"]), statistics.median(t["old"])],
                  "new": [min(t["new"]), statistics.median(t["new"])]}
print("BENCH " + json.dumps(out))
'''


def loops(args):
    """--loops: the compiled loops of both modules side by side in one process."""
    folder = tempfile.mkdtemp(prefix="bench-design-loops-")
    text = subprocess.run(["git", "-C", ROOT, "show", f"{args.old}:generated/quick_return.py"],
                          capture_output=True, text=True, check=True).stdout
    with open(os.path.join(folder, "old_quick_return.py"), "w") as fh:
        fh.write(text)
    with open(os.path.join(ROOT, "generated", "quick_return.py")) as src, \
            open(os.path.join(folder, "quick_return.py"), "w") as fh:
        fh.write(src.read())
    env = dict(os.environ, NUMBA_CACHE_DIR=os.path.join(folder, "nc"))
    res = subprocess.run([sys.executable, "-c", LOOPS, folder, str(args.designs),
                          str(args.times), str(max(args.rounds, 9))],
                         capture_output=True, text=True, env=env, cwd=folder)
    line = [x for x in res.stdout.splitlines() if x.startswith("BENCH ")]
    if res.returncode or not line:
        raise SystemExit(res.stderr[-3000:])
    got = json.loads(line[-1][6:])
    print(f"compiled design loops, {args.old}'s module against this tree's, one process "
          f"({args.designs} designs x {args.times} times; ns per point, best / median)")
    for level, r in got.items():
        name = {"0": "position", "2": "acceleration"}[level]
        print(f"  {name:<13} old {r['old'][0]:6.1f} / {r['old'][1]:6.1f}   new {r['new'][0]:6.1f}"
              f" / {r['new'][1]:6.1f}   ratio of bests {r['new'][0] / r['old'][0]:.3f}   "
              f"bit-identical: {r['same']}")
    return 0 if all(r["same"] for r in got.values()) else 1


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--old", required=True, help="the commit to compare with")
    ap.add_argument("--rounds", type=int, default=5, help="processes of each tree, in turn")
    ap.add_argument("--designs", type=int, default=200)
    ap.add_argument("--times", type=int, default=1000)
    ap.add_argument("--repeat", type=int, default=3, help="tables timed in each process")
    ap.add_argument("--loops", action="store_true", help="the compiled loops alone, in one "
                    "process (see the module's docstring)")
    args = ap.parse_args()
    if args.loops:
        return loops(args)
    tmp = tempfile.mkdtemp(prefix="bench-design-sbs-")
    old = os.path.join(tmp, "old")
    os.makedirs(old)
    subprocess.run(f"git -C {ROOT} archive {args.old} | tar -x -C {old}", shell=True,
                   check=True)
    trees = {"old": old, "new": ROOT}
    outs = {k: tempfile.mkdtemp(dir=tmp, prefix=k) for k in trees}
    got = {k: [] for k in trees}
    for r in range(args.rounds):
        order = ("old", "new") if r % 2 == 0 else ("new", "old")
        for k in order:
            got[k].append(child(trees[k], outs[k], os.path.join(outs[k], f"a{r}.npz"), args))
    a = np.load(os.path.join(outs["old"], "a0.npz"))
    b = np.load(os.path.join(outs["new"], "a0.npz"))
    same = sorted(a.files) == sorted(b.files) and all(
        a[f].dtype == b[f].dtype and a[f].tobytes() == b[f].tobytes() for f in a.files)
    print(f"{args.old} against this tree: {args.designs} designs x {args.times} times, "
          f"{args.rounds} processes each; arrays bit-identical: {same}")
    print(f"{'case':<34} {'old ns/pt':>10} {'new ns/pt':>10} {'ratio':>7}")
    for i, (kind, (lo, hi), level, workers) in enumerate(CASES):
        o = [g[i] for g in got["old"]]
        n = [g[i] for g in got["new"]]
        ratio = statistics.median(y / x for x, y in zip(o, n))
        name = f"{kind} {lo}-{hi} {level} w={workers or 'all'}"
        print(f"{name:<34} {statistics.median(o):10.1f} {statistics.median(n):10.1f} "
              f"{ratio:7.3f}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
