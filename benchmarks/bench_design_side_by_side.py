"""Design tables of this tree against an older commit's, side by side: each tree builds the
quick-return's module with its own compiler and sweeps the same tables with its own
runtime (compiled tier), in fresh processes taken in turn (the old tree extracted by
``git archive``; each tree keeps its own numba cache, so only the first process of each
compiles). Per case: the table's arrays (Q, QD, QDD, status) compared bit for bit, and the
time per (design, time) point, the best of --repeat tables in each process, as medians
over the processes of each tree and the median of the ratios of their pairs.

    python benchmarks/bench_design_side_by_side.py --old 4835ad8 --rounds 5

Cases: crank lengths that all assemble (every design takes the quick path alone) and
lengths of which some cannot reach every time (the careful rest of the sweep runs, and
fails), at position and acceleration level, on one thread (workers=1) and on every core.
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
         ("hard", (3.5, 4.5), "acceleration", 1), ("easy", (3.5, 4.1), "acceleration", None))

CHILD = r'''
import json, sys, time, warnings
import numpy as np
import mechgen
root, out, arrays, designs, times, repeat = sys.argv[1:7]
cases = json.loads(sys.argv[7])
warnings.simplefilter("ignore")
mech = mechgen.compile(mechgen.load_model(root + "/examples/quick_return.py"), outdir=out,
                       tier="compiled")
res, keep = [], {}
for i, (kind, (lo, hi), level, workers) in enumerate(cases):
    P = {"longitud": np.linspace(lo, hi, int(designs))}
    run = lambda: mech.design_sweep(0.0, 1.0, int(times), P, level=level, workers=workers,
                                    on_fail="ignore")
    tab = run()
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


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--old", required=True, help="the commit to compare with")
    ap.add_argument("--rounds", type=int, default=5, help="processes of each tree, in turn")
    ap.add_argument("--designs", type=int, default=200)
    ap.add_argument("--times", type=int, default=1000)
    ap.add_argument("--repeat", type=int, default=3, help="tables timed in each process")
    args = ap.parse_args()
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
