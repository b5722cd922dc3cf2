"""What numba compiles after an edit, and what it costs: per model, in fresh processes with
an empty numba cache and a fresh build folder (CPU time, the child's own and its children's):

- ``build``: load the model file and write its module (sympy and mechgen imported first,
  not counted; the best of --builds fresh processes);
- ``sweep``: edit -> the first compiled 10^5-point acceleration sweep: import, build, load
  with the compiled tier, ``mech.sweep(0, 1, 10**5, level="acceleration")`` (the whole
  child: what a user waits for);
- ``force_sweep``: edit -> the first 10^5-point sweep at level "dynamic" in the auto tier
  (a model with masses or loads; this process's CPU);
- ``table``: edit -> the first design table in the auto tier (the first parameter at 8
  values within 2 % of its default, 2001 times from 0 to 1, acceleration level; this
  process's CPU, not the worker's);
- ``force_table``: the same at level "dynamic", the first driver's effort reduced (a model
  with masses or loads: the design loops that solve the multipliers in their sweeps);
- ``whole``: the warm-up worker's work, every entry point compiled
  (mechgen.runtime.loading.warm, all stages) after the build;
- per emitted function: numba's compile CPU (its own, the functions it compiled on its way
  subtracted; numba's "numba:compile" events) and its size in lines, in the ``sweep``
  child (what the sweep needs) and the ``whole`` child.

    python benchmarks/bench_compile.py                          # all five models
    python benchmarks/bench_compile.py --models quick_return    # one, quickly
    python benchmarks/bench_compile.py --root /tmp/base         # another checkout's mechgen
    python benchmarks/bench_compile.py --functions 12 --json out.json

Models: quick_return, quick_return_forces, strandbeest (examples/strandbeest.py),
andrews_squeezer and chain50 (benchmarks/chain_model.py, 50 four-bars).
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
MODELS = {"quick_return": "examples/quick_return.py",
          "quick_return_forces": "examples/quick_return_forces.py",
          "strandbeest": "examples/strandbeest.py",
          "andrews_squeezer": "examples/andrews_squeezer.py",
          "chain50": "chain50"}

CHILD = r'''
import inspect, json, os, resource, sys, time
MODE, MODEL, OUT, CHAIN = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4]


def cpu():
    s, c = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return s.ru_utime + s.ru_stime + c.ru_utime + c.ru_stime


def model():
    if MODEL == "chain50":
        sys.path.insert(0, CHAIN)
        from chain_model import chain
        return chain(50)
    return mechgen.load_model(MODEL)


res = {}
compiles = {}
if MODE != "build":
    import numba.core.event as ev

    class Own(ev.Listener):
        """numba's compile events: each function's own CPU (nested compiles subtracted)."""
        stack = []

        def on_start(self, event):
            self.stack.append([time.process_time(), 0.0])

        def on_end(self, event):
            t0, inner = self.stack.pop()
            spent = time.process_time() - t0
            if self.stack:
                self.stack[-1][1] += spent
            fn = event.data["dispatcher"].py_func
            name = fn.__name__
            try:
                lines = len(inspect.getsourcelines(fn)[0])
            except (OSError, TypeError):
                lines = 0
            row = compiles.setdefault(name, [0.0, lines, 0])
            row[0] += spent - inner
            row[2] += 1

    ev.register("numba:compile", Own())
t0 = cpu()
import mechgen
if MODE == "build":
    import sympy  # noqa: F401 - the floor, not counted
    from mechgen.compiler.build import build
    t0 = cpu()
    m = model()
    res["load_model"] = cpu() - t0
    build(m, OUT)
    res["build"] = cpu() - t0
else:
    m = model()
    tier = "compiled" if MODE in ("sweep", "whole") else "auto"
    mech = mechgen.compile(m, outdir=OUT, tier=tier)
    res["build+load"] = cpu() - t0
    path = os.path.join(OUT, mech.name + ".py")
    res["module_lines"] = sum(1 for _ in open(path))
    if MODE in ("sweep", "auto"):
        t1 = cpu()
        sw = mech.sweep(0.0, 1.0, 10**5, level="acceleration")
        res[MODE] = cpu() - t1
        res["check"] = float(abs(sw.QDD).sum())
        if MODE == "auto":      # this process's own CPU: the worker it started is not ours
            own = resource.getrusage(resource.RUSAGE_SELF)
            res["total"] = own.ru_utime + own.ru_stime
            res["tier"] = mech.tier
            state = getattr(mech, "state", None)
            tiers = state.tiers if state is not None else getattr(mech, "_tiers", None)
            if tiers is not None:
                tiers.stop_worker()
    elif MODE in ("table", "force_table") and not mech.parameter_names or \
            MODE in ("force_table", "force_sweep") and not getattr(mech.module, "FORCES", False):
        res[MODE] = None
    elif MODE == "force_sweep":   # the auto tier, this process only, as "auto"
        import numpy as np
        t1 = cpu()
        sw = mech.sweep(0.0, 1.0, 10**5, level="dynamic")
        res[MODE] = cpu() - t1
        res["check"] = float(np.nansum(abs(sw.LAM)))
        own = resource.getrusage(resource.RUSAGE_SELF)
        res["total"] = own.ru_utime + own.ru_stime
        mech.state.tiers.stop_worker()
    elif MODE in ("table", "force_table"):   # the auto tier, this process only, as "auto"
        import numpy as np
        name, value = mech.parameter_names[0], float(mech.p[0])
        kw = {"level": "acceleration"}
        if MODE == "force_table":   # the first driver's effort, reduced: the fused sweeps
            driver = [c[0] for c in mech.module.CONSTRAINTS if c[4]][0]
            kw = {"level": "dynamic", "reduce": [driver]}
        t1 = cpu()
        tab = mech.design_sweep(0.0, 1.0, 2001, {name: value * np.linspace(0.98, 1.02, 8)},
                                on_fail="ignore", **kw)
        res[MODE] = cpu() - t1
        res["check"] = int(np.sum(tab.status == 0))
        own = resource.getrusage(resource.RUSAGE_SELF)
        res["total"] = own.ru_utime + own.ru_stime
        mech.state.tiers.stop_worker()
    else:
        from mechgen.runtime.loading.warm import STAGES, warm
        t1 = cpu()
        done = warm(mech, STAGES)
        res["whole"] = cpu() - t1
        res["stages"] = done
res.setdefault("total", cpu())
res["functions"] = compiles
print("BENCH " + json.dumps(res))
'''


def child(root, mode, name, tmp):
    """Run one fresh process: its JSON result."""
    out, cache = os.path.join(tmp, f"gen-{mode}"), os.path.join(tmp, f"nc-{mode}")
    for d in (out, cache):
        shutil.rmtree(d, ignore_errors=True)
    src = MODELS[name]
    model = src if src == "chain50" else os.path.join(root, src)
    env = dict(os.environ, PYTHONPATH=root, NUMBA_CACHE_DIR=cache,
               MECHGEN_CACHE=os.path.join(tmp, f"mg-{mode}"))
    env.pop("MECHGEN_TIER", None)
    res = subprocess.run([sys.executable, "-c", CHILD, mode, model, out, HERE],
                         capture_output=True, text=True, env=env, cwd=tmp)
    line = [x for x in res.stdout.splitlines() if x.startswith("BENCH ")]
    if res.returncode or not line:
        raise SystemExit(f"{name} {mode} failed:\n{res.stderr[-3000:]}")
    return json.loads(line[-1][6:])


def table(funcs, top):
    rows = sorted(funcs.items(), key=lambda kv: -kv[1][0])
    out = [f"      {'function':<28} {'CPU s':>7} {'lines':>6} {'sigs':>5}"]
    for name, (spent, lines, n) in rows[:top]:
        out.append(f"      {name:<28} {spent:7.2f} {lines:6d} {n:5d}")
    rest = rows[top:]
    if rest:
        out.append(f"      {f'({len(rest)} more)':<28} {sum(r[1][0] for r in rest):7.2f} "
                   f"{sum(r[1][1] for r in rest):6d}")
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--models", default=",".join(MODELS))
    ap.add_argument("--root", default=ROOT, help="the checkout whose mechgen runs")
    ap.add_argument("--modes", default="build,sweep,auto,whole",
                    help="of build, sweep, auto, force_sweep, table, force_table, whole")
    ap.add_argument("--builds", type=int, default=3, help="fresh build processes (best of)")
    ap.add_argument("--functions", type=int, default=10, help="rows of the per-function tables")
    ap.add_argument("--json", help="write every result here")
    args = ap.parse_args()
    root = os.path.abspath(args.root)
    commit = subprocess.run(["git", "-C", root, "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip() or "(no git)"
    dirty = subprocess.run(["git", "-C", root, "status", "--porcelain", "--", "mechgen",
                            "templates"], capture_output=True, text=True).stdout.strip()
    print(f"mechgen at {root} ({commit}{', modified' if dirty else ''}); CPU seconds")
    results = {}
    modes = args.modes.split(",")
    for name in args.models.split(","):
        tmp = tempfile.mkdtemp(prefix=f"bench-compile-{name}-")
        try:
            r = results[name] = {}
            if "build" in modes:
                builds = [child(root, "build", name, tmp) for _ in range(args.builds)]
                r["build"] = min(b["build"] for b in builds)
                r["load_model"] = min(b["load_model"] for b in builds)
                print(f"{name}: build {r['build']:.2f} s (load_model {r['load_model']:.2f}; "
                      f"best of {args.builds})", flush=True)
            for mode in ("sweep", "auto", "force_sweep", "table", "force_table", "whole"):
                if mode not in modes:
                    continue
                got = r[mode] = child(root, mode, name, tmp)
                if got[mode] is None:
                    print(f"{name}: {mode}: the model has no parameters (or, for a force "
                          "table, no masses or loads)", flush=True)
                    continue
                spent = sum(v[0] for v in got["functions"].values())
                what = {"sweep": "edit -> first 10^5-point acceleration sweep (compiled tier)",
                        "auto": "the same in the auto tier (this process only)",
                        "force_sweep": "edit -> first 10^5-point dynamic sweep (auto tier, "
                                       "this process only)",
                        "table": "edit -> first design table, 8 designs x 2001 times at "
                                 "acceleration level (auto tier, this process only)",
                        "force_table": "edit -> first dynamic design table reducing the "
                                       "driver's effort, 8 x 2001 (auto tier, this process)",
                        "whole": "whole module (warm-up worker)"}[mode]
                print(f"{name}: {what}: {got[mode]:.2f} s for that call, "
                      f"{got['total']:.2f} s the whole process (build+load "
                      f"{got['build+load']:.2f}); numba compiled {len(got['functions'])} "
                      f"functions, {spent:.2f} s; module {got['module_lines']} lines",
                      flush=True)
                print(table(got["functions"], args.functions), flush=True)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"root": root, "commit": commit, "results": results}, fh, indent=1)


if __name__ == "__main__":
    main()
