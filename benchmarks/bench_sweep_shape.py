"""The fast sweep's two shapes, side by side: the position and derivative solvers written
out in its loop (the product's shape for a model of up to SHARE_MAX coordinates:
compiler.solver.sweep.written_step) against the loop calling position_sorted(),
derivatives_sorted() and dynamics_sorted() (the shape of a larger model; numba inlines
the calls at its IR, INLINE = "always"), and the call shape without numba's inlining
("call-noinline", INLINE = "never"). The other shapes are built from the same compiler by
patching it in the build's process: context.written_step made to return None, and for
"call-noinline" context.SHARE_MAX set to 0.

- speed: one process, every shape's module loaded (compiled tier, compiled before the
  timing); rounds alternate the shapes (the order turning each round); per shape the
  median ns per point of ``mech.sweep(0, 1, N, level=...)`` and of the raw module's
  sweep_fast (sweep_fast_forces, sweep_fast_statics where the module has them), and the
  median of each round's ratio to the written shape; the arrays (Q, QD, QDD, status, λ)
  compared bit for bit with the written shape's;
- compile (--compile): numba's compile CPU in fresh processes with an empty numba cache
  (benchmarks/bench_compile.py's child, its build patched as above): edit -> the first
  10^5-point acceleration sweep, and the whole module (the warm-up worker's work), with
  the functions that cost most; the median of --repeats processes.

    python benchmarks/bench_sweep_shape.py                        # speed, three models
    python benchmarks/bench_sweep_shape.py --compile --repeats 2  # and compile CPU
    python benchmarks/bench_sweep_shape.py --models quick_return --shapes written,call
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import bench_compile  # noqa: E402

MODELS = {"quick_return": ("examples/quick_return.py", "quick_return"),
          "quick_return_forces": ("examples/quick_return_forces.py", "quick_return_forces"),
          "strandbeest": ("examples/strandbeest.py", "strandbeest_leg")}
# code run in a build's process before the build: the shape's patch of the compiler
PATCH = {"written": "import mechgen.compiler.context as _c\n",
         "call": "import mechgen.compiler.context as _c\n"
                 "_c.written_step = lambda *a, **k: None\n",
         "call-noinline": "import mechgen.compiler.context as _c\n"
                          "_c.written_step = lambda *a, **k: None\n_c.SHARE_MAX = 0\n"}
LEVELS = {"quick_return_forces": ("position", "acceleration", "static", "dynamic")}
RAW = (("sweep_fast", "position"), ("sweep_fast", "acceleration"),
       ("sweep_fast_statics", "position"), ("sweep_fast_forces", "acceleration"))

BUILD = r'''
import sys
from mechgen.compiler.build import build
import mechgen
build(mechgen.load_model(sys.argv[1]), sys.argv[2])
'''

SPEED = r'''
import json, os, statistics, sys, time
import numpy as np
import mechgen
from mechgen.protocol import STATUS_COLUMNS
spec = json.loads(sys.argv[1])
N, rounds, out = spec["points"], spec["rounds"], {}


def raw_args(mod, mech, ts, lev):
    q0 = mech.solve(0.0).q.copy()
    n = len(q0)
    Q = np.empty((len(ts), n))
    QD = np.empty((len(ts) if lev else 0, n))
    QDD = np.empty((len(ts) if lev else 0, n))
    S = np.zeros((len(ts), STATUS_COLUMNS), dtype=np.int16)
    rows = len(getattr(mod, "DRIVER_ROWS", ()))
    extra = (np.empty((len(ts), mod.N_EQS)), np.empty((len(ts), rows)), np.empty(len(ts)))
    return q0, (Q, QD, QDD, S), extra


for model, (levels, raws) in spec["cases"].items():
    mechs = {s: mechgen.load(os.path.join(spec["dir"], s, model + ".py"), tier="compiled")
             for s in spec["shapes"]}
    ts = np.linspace(0.0, 1.0, N)
    cases = {}
    for level in levels:
        def call(mech, level=level):
            return mech.sweep(0.0, 1.0, N, level=level)
        cases["sweep " + level] = call
    for fn, level in raws:
        flag = {"sweep_fast_statics": "STATIC_FUSED", "sweep_fast_forces": "FORCE_FUSED"}
        absent = [s for s, m in mechs.items() if not hasattr(m.module, fn)
                  or not getattr(m.module, flag.get(fn, ""), True)]
        if absent and len(absent) < len(mechs):
            print(f"NOTE {model}: {fn} not in the module of {', '.join(absent)}", flush=True)
        if absent:
            continue
        lev = 2 if level == "acceleration" else 0
        prepared = {}

        def call(mech, fn=fn, lev=lev, prepared=prepared):
            if mech not in prepared:
                prepared[mech] = raw_args(mech.module, mech, ts, lev)
            q0, arrays, extra = prepared[mech]
            p = mech.state.p
            f = getattr(mech.module, fn)
            args = (ts, q0.copy(), p, 1e-10, 1e-10, 50, *arrays)
            got = f(*args, *extra) if fn != "sweep_fast" else f(*args)
            return arrays + (extra if fn != "sweep_fast" else ()) + (got,)
        cases[f"{fn} {level}"] = call
    for case, call in cases.items():
        first = {s: call(m) for s, m in mechs.items()}      # compiled here, not timed
        def arrays(r):
            if isinstance(r, tuple):
                return [np.asarray(a) for a in r]
            return [np.asarray(a) for a in (r.Q, r.QD, r.QDD, r.status,
                                            getattr(r, "LAM", None)) if a is not None]
        ref = arrays(first[spec["shapes"][0]])
        same = {s: all(np.array_equal(a, b) for a, b in zip(ref, arrays(r)))
                for s, r in first.items()}
        diff = {s: max((float(np.max(np.abs(a - b))) for a, b in zip(ref, arrays(r))
                        if a.dtype.kind == "f" and a.size), default=0.0)
                for s, r in first.items()}
        times = {s: [] for s in mechs}
        order = list(mechs)
        for k in range(rounds):
            for s in (order if k % 2 == 0 else order[::-1]):
                t0 = time.perf_counter()
                call(mechs[s])
                times[s].append((time.perf_counter() - t0) / N * 1e9)
        base = times[order[0]]
        count = {s: int(r[-1]) if isinstance(r, tuple) else N for s, r in first.items()}
        out[f"{model}: {case}"] = {
            s: dict(ns=statistics.median(v), best=min(v), same=same[s], diff=diff[s],
                    count=count[s],
                    ratio=statistics.median([x / y for x, y in zip(v, base)]))
            for s, v in times.items()}
        print("ROW " + json.dumps([f"{model}: {case}", out[f"{model}: {case}"]]), flush=True)
'''


def build_all(tmp, models, shapes):
    for shape in shapes:
        for name in models:
            src = os.path.join(ROOT, MODELS[name][0])
            res = subprocess.run([sys.executable, "-c", PATCH[shape] + BUILD, src,
                                  os.path.join(tmp, shape)], capture_output=True, text=True,
                                 env=dict(os.environ, PYTHONPATH=ROOT), cwd=tmp)
            if res.returncode:
                raise SystemExit(f"{name} ({shape}) did not build:\n{res.stderr[-3000:]}")


def speed(tmp, models, shapes, points, rounds):
    cases = {MODELS[m][1]: (LEVELS.get(m, ("position", "acceleration")), RAW)
             for m in models}
    spec = dict(dir=tmp, shapes=shapes, points=points, rounds=rounds, cases=cases)
    env = dict(os.environ, PYTHONPATH=ROOT, NUMBA_CACHE_DIR=os.path.join(tmp, "nc"),
               MECHGEN_TIER="compiled")
    proc = subprocess.Popen([sys.executable, "-c", SPEED, json.dumps(spec)], env=env,
                            cwd=tmp, stdout=subprocess.PIPE, text=True)
    print(f"ns per point, median of {rounds} alternating rounds of {points} points; "
          f"ratio: the median of each round's ratio to {shapes[0]}; same: arrays equal "
          f"bit for bit (else the largest difference)")
    print(f"{'case':<46}" + "".join(f"{s:>26}" for s in shapes))
    for line in proc.stdout:
        if line.startswith("NOTE "):
            print(line[5:], end="", flush=True)
        if line.startswith("ROW "):
            case, row = json.loads(line[4:])
            cells = "".join(
                f"{r['ns']:9.1f} {r['ratio']:6.3f} "
                f"{'same' if r['same'] else format(r['diff'], '.1e'):>9}"
                for r in (row[s] for s in shapes))
            short = [f"{s} {row[s]['count']}" for s in shapes if row[s]["count"] < points]
            print(f"{case:<46}{cells}" + (f"  (points the quick path took: {short})"
                                           if short else ""), flush=True)
    if proc.wait():
        raise SystemExit("the speed process failed")


def compile_cpu(models, shapes, repeats, top):
    base = bench_compile.CHILD
    print(f"numba compile CPU, fresh processes, empty numba cache (median of {repeats})")
    for name in models:
        for shape in shapes:
            bench_compile.CHILD = PATCH[shape] + base
            got = {}
            for mode in ("sweep", "whole"):
                runs = []
                for _ in range(repeats):
                    tmp = tempfile.mkdtemp(prefix=f"bench-shape-{name}-")
                    try:
                        runs.append(bench_compile.child(ROOT, mode, name, tmp))
                    finally:
                        shutil.rmtree(tmp, ignore_errors=True)
                got[mode] = runs
            sweep = statistics.median(r["sweep"] for r in got["sweep"])
            total = statistics.median(r["total"] for r in got["sweep"])
            whole = statistics.median(r["whole"] for r in got["whole"])
            lines = got["sweep"][0]["module_lines"]
            print(f"{name} [{shape}]: module {lines} lines; first 10^5 acceleration sweep "
                  f"{sweep:.2f} s ({total:.2f} s the whole process); whole module "
                  f"{whole:.2f} s", flush=True)
            funcs = {}
            for r in got["whole"]:
                for fn, (spent, n, _) in r["functions"].items():
                    funcs.setdefault(fn, ([], n))[0].append(spent)
            rows = sorted(((statistics.median(v), n, fn) for fn, (v, n) in funcs.items()),
                          reverse=True)
            print("    " + ", ".join(f"{fn} {s:.2f} s ({n} lines)" for s, n, fn in rows[:top]))
    bench_compile.CHILD = base


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--models", default=",".join(MODELS))
    ap.add_argument("--shapes", default="written,call,call-noinline")
    ap.add_argument("--points", type=int, default=10**5)
    ap.add_argument("--rounds", type=int, default=15)
    ap.add_argument("--no-speed", action="store_true")
    ap.add_argument("--compile", action="store_true", help="also numba's compile CPU")
    ap.add_argument("--repeats", type=int, default=1, help="compile processes (median of)")
    ap.add_argument("--functions", type=int, default=6)
    args = ap.parse_args()
    models, shapes = args.models.split(","), args.shapes.split(",")
    tmp = tempfile.mkdtemp(prefix="bench-shape-")
    try:
        if not args.no_speed:
            build_all(tmp, models, shapes)
            speed(tmp, models, shapes, args.points, args.rounds)
        if args.compile:
            compile_cpu(models, shapes, args.repeats, args.functions)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
