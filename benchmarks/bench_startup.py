"""Time to the first answers (issue 12): each step a user waits for, in a fresh process.

For each model (the seed's quick-return, Jansen's Strandbeest leg, chains of 10 and 50
four-bar loops from chain_model.py), a new Python process with an empty numba cache
(a temporary NUMBA_CACHE_DIR) and an empty module folder runs, timing each step:

    import   import mechgen
    model    run the model file (builds the Model: imports sympy)
    build    expand, plan, render and write the module (mechgen.compile: build + load)
    load     import the generated module (mechgen.load)
    solve    the first position solve, mech.solve(0.15)
    acc      the first acceleration solve, mech.solve(0.15, level="acceleration")
    sweep    the first 101-point acceleration sweep, mech.sweep(0, 1, 101, ...)
    total    all of the above (what a user waits for from the edit to the first answers)
    process  the whole process, measured from outside: the interpreter's own start
             (site, .pth files) and exit too

then the same again in a second process ("warm": the module and numba's cache from the
first, and the background compile it started finished). Wall-clock seconds; ``--json``
prints every figure, CPU seconds included. ``--repeat N`` runs N cold processes (each in
an empty folder) and N warm ones and reports each step's median: the figures issue 24
names are the median warm and cold ``total`` of quick_return with ``--api file``:

    python benchmarks/bench_startup.py quick_return --repeat 7 --baseline /work/main

Python writes no bytecode where PYTHONDONTWRITEBYTECODE is set (this machine sets it):
mechgen's own modules are then compiled from source by every process (about 30 ms of a
warm start, 0.25 s of a cold one); ``--bytecode`` runs copies of the checkouts with their
bytecode compiled, as an installed mechgen has it.

    python benchmarks/bench_startup.py                        # all four models
    python benchmarks/bench_startup.py quick_return chain10   # chosen ones
    python benchmarks/bench_startup.py --baseline /work/old   # the same steps on another
                                                              # checkout (PYTHONPATH=PATH)
    python benchmarks/bench_startup.py --api compile          # mechgen.compile(model)
    MECHGEN_TIER=... python benchmarks/bench_startup.py       # passed through, as is
    python benchmarks/bench_startup.py --tier python          # sets MECHGEN_TIER
    python benchmarks/bench_startup.py --repeat 7             # medians of 7 processes each
    python benchmarks/bench_startup.py --bytecode             # checkouts with .pyc files

``--api file`` (the default) calls ``mechgen.compile("MODEL.py")``, as ``mechgen solve
MODEL.py`` does: the plain-Python tier answers at once while numba compiles in a background
process, and an unchanged file loads without sympy. ``--api path`` builds the model file's module when its text changed (as
``mechgen solve MODEL.py`` does) and loads it; ``--api compile`` calls
``mechgen.compile(model, outdir=...)`` (build and load in one step, reported as build).
Every process runs one model; a baseline run uses the same model files and steps.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
STEPS = ("import", "model", "build", "load", "solve", "acc", "sweep", "total", "process")
MODELS = ("quick_return", "strandbeest", "chain10", "chain50")

# one process: the steps, each timed (wall and CPU), printed as one JSON line
CHILD = r"""
import json, os, sys, time
api, model_file, outdir = sys.argv[1:4]
wall, cpu, out = time.perf_counter, time.process_time, {}
w0, c0 = wall(), cpu()
last = [w0, c0]

def step(name):
    w, c = wall(), cpu()
    out[name] = w - last[0]
    out[name + "_cpu"] = c - last[1]
    last[:] = [w, c]

import mechgen
step("import")
if api == "file":
    # mechgen.compile(path): an unchanged model file loads without sympy (its manifest);
    # a checkout without it (a baseline) runs the model file and compiles the Model
    out["model"] = out["model_cpu"] = out["load"] = out["load_cpu"] = 0.0
    try:
        from mechgen.bridge import compile_file  # noqa: F401
        mech = mechgen.compile(model_file, outdir=outdir)
    except ImportError:
        mech = mechgen.compile(mechgen.load_model(model_file), outdir=outdir)
    step("build")
    model = None
else:
    from mechgen.model.loader import load_model
    model = load_model(model_file)
    step("model")
if model is None:
    pass
elif api == "compile":
    mech = mechgen.compile(model, outdir=outdir)
    step("build")
    out["load"] = out["load_cpu"] = 0.0
else:
    from mechgen.bridge import build_if_changed
    path = build_if_changed(model, outdir)
    step("build")
    mech = mechgen.load(path)
    step("load")
s = mech.solve(0.15)
step("solve")
a = mech.solve(0.15, level="acceleration")
step("acc")
sw = mech.sweep(0.0, 1.0, 101, level="acceleration")
step("sweep")
out["total"], out["total_cpu"] = wall() - w0, cpu() - c0
out["check"] = [float(s.q.sum()), float(a.qdd.sum()), float(sw.Q.sum()), float(sw.QDD.sum())]
print("BENCH " + json.dumps(out))
"""

# a model file for a chain (chain_model.py builds it; the file just calls it)
CHAIN_FILE = """import sys
sys.path.insert(0, {here!r})
from chain_model import chain
m = chain({n})
"""


def model_file(name: str, folder: str) -> str:
    """The model file of a benchmark model (a chain's is written into ``folder``)."""
    if name.startswith("chain"):
        path = os.path.join(folder, f"{name}_model.py")
        with open(path, "w", encoding="utf-8") as fh:
            fh.write(CHAIN_FILE.format(here=HERE, n=int(name[5:])))
        return path
    path = os.path.join(ROOT, "examples", f"{name}.py")
    if not os.path.isfile(path):
        raise SystemExit(f"bench_startup: no model {name!r} (examples/{name}.py)")
    return path


def _children_cpu() -> float:
    """CPU seconds of this process's children that have ended (and were waited for)."""
    import resource
    use = resource.getrusage(resource.RUSAGE_CHILDREN)
    return use.ru_utime + use.ru_stime


def run_once(code_root, api, path, outdir, cache, tier=None, timeout=900) -> dict:
    """One fresh process: the steps' times (a dict), or {"error": text}."""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache, MECHGEN_CACHE=outdir,
               PYTHONPATH=code_root + os.pathsep + os.environ.get("PYTHONPATH", ""))
    if tier is not None:
        env["MECHGEN_TIER"] = tier
    start, used = time.perf_counter(), _children_cpu()
    try:
        done = subprocess.run([sys.executable, "-c", CHILD, api, path, outdir], env=env,
                              capture_output=True, text=True, timeout=timeout, cwd=outdir)
    except subprocess.TimeoutExpired:
        return {"error": f"timed out after {timeout} s"}
    process = time.perf_counter() - start
    for line in done.stdout.splitlines()[::-1]:
        if line.startswith("BENCH "):
            return dict(json.loads(line[6:]), process=process,
                        process_cpu=_children_cpu() - used)
    return {"error": (done.stderr.strip().splitlines() or ["no output"])[-1]}


def wait_for_workers(limit=600.0, stop_in=None):
    """Wait until no background compile worker (python -m mechgen.runtime.loading.warmup, started
    by a cold run in the auto tier) is running, so that the next run is neither slowed by
    it nor finds a half-written cache. ``stop_in``: a folder of ours whose workers (their
    module is in it) are stopped instead, by their process id (a cold run repeated: its
    cache is thrown away)."""
    end = time.monotonic() + limit
    while time.monotonic() < end:
        found = subprocess.run(["pgrep", "-f", "mechgen.runtime.loading.warmup"], capture_output=True,
                               text=True)
        if found.returncode != 0:
            return
        if stop_in is not None:
            for pid in found.stdout.split():
                try:
                    with open(f"/proc/{pid}/cmdline", "rb") as fh:
                        ours = os.fsencode(stop_in) in fh.read()
                    if ours:
                        os.kill(int(pid), signal.SIGTERM)
                except (OSError, ValueError):
                    pass
        time.sleep(0.5)


def median_run(runs) -> dict:
    """Each figure's median over ``runs`` (the first error, if any run failed)."""
    for r in runs:
        if "error" in r:
            return r
    out = {}
    for key, value in runs[0].items():
        if isinstance(value, (int, float)):
            out[key] = statistics.median(r[key] for r in runs)
        else:
            out[key] = value
    out["runs"] = len(runs)
    return out


def measure(name, code_root, api, tier, keep=False, repeat=1) -> dict:
    """Cold (empty cache and folder) then warm (the same again) for one model: the median
    of ``repeat`` processes each (every cold one in a folder of its own)."""
    work = tempfile.mkdtemp(prefix=f"bench-startup-{name}-")
    try:
        colds = []
        for k in range(repeat):
            folder = os.path.join(work, f"run{k}")
            os.makedirs(folder)
            path = model_file(name, folder)
            outdir, cache = os.path.join(folder, "modules"), os.path.join(folder, "numba")
            os.makedirs(outdir)
            colds.append(run_once(code_root, api, path, outdir, cache, tier))
            last = k == repeat - 1      # the last one's cache is kept, for the warm runs
            wait_for_workers(stop_in=None if last else folder)
        warms = []
        for _ in range(repeat):
            warms.append(run_once(code_root, api, path, outdir, cache, tier))
            wait_for_workers()
        return {"cold": median_run(colds), "warm": median_run(warms)}
    finally:
        if not keep:
            shutil.rmtree(work, ignore_errors=True)


def with_bytecode(root, work) -> str:
    """A copy of the checkout at ``root`` (mechgen/ and templates/) in ``work``, its
    modules compiled to bytecode: mechgen as installed (pip compiles what it installs)."""
    dst = os.path.join(work, os.path.basename(os.path.normpath(root)) or "checkout")
    for sub in ("mechgen", "templates"):
        if os.path.isdir(os.path.join(root, sub)):
            shutil.copytree(os.path.join(root, sub), os.path.join(dst, sub),
                            ignore=shutil.ignore_patterns("__pycache__"))
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    subprocess.run([sys.executable, "-m", "compileall", "-q", os.path.join(dst, "mechgen")],
                   env=env, check=True)
    return dst


def table(rows, cpu=False) -> str:
    """rows: (model, code, run, figures) -> a text table of the steps' wall seconds (or,
    with ``cpu``, the CPU seconds of the process)."""
    head = f"{'model':14s} {'code':9s} {'run':5s} " + " ".join(f"{s:>7s}" for s in STEPS)
    lines = [head, "-" * len(head)]
    for model, code, run, fig in rows:
        if "error" in fig:
            lines.append(f"{model:14s} {code:9s} {run:5s} error: {fig['error']}")
            continue
        lines.append(f"{model:14s} {code:9s} {run:5s} " +
                     " ".join(f"{fig.get(s + ('_cpu' if cpu else ''), float('nan')):7.2f}"
                              for s in STEPS))
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("models", nargs="*", default=list(MODELS),
                    help=f"which models (default: {' '.join(MODELS)}); chainN for any N")
    ap.add_argument("--api", choices=("file", "path", "compile"), default="file",
                    help="mechgen.compile(MODEL.py), what `mechgen solve MODEL.py` does (file: "
                         "no sympy when the file is unchanged); the model file run and its "
                         "module built when changed and loaded (path); or "
                         "mechgen.compile(model) (compile)")
    ap.add_argument("--baseline", metavar="PATH",
                    help="also run every step with PYTHONPATH=PATH (another checkout)")
    ap.add_argument("--tier", help="MECHGEN_TIER for the child processes (else inherited)")
    ap.add_argument("--json", action="store_true", help="print JSON instead of a table")
    ap.add_argument("--cpu", action="store_true",
                    help="the table in CPU seconds of each process (steadier than wall-clock "
                         "time on a busy machine; numba compiles in the process)")
    ap.add_argument("--keep", action="store_true", help="keep the temporary folders")
    ap.add_argument("--repeat", type=int, default=1, metavar="N",
                    help="N cold and N warm processes per model and checkout: the medians")
    ap.add_argument("--bytecode", action="store_true",
                    help="run copies of the checkouts with their modules compiled to "
                         "bytecode (as installed), whatever PYTHONDONTWRITEBYTECODE says")
    args = ap.parse_args(argv)
    if args.repeat < 1:
        ap.error("--repeat must be at least 1")
    codes = [("this", ROOT)] + ([("baseline", os.path.abspath(args.baseline))]
                                if args.baseline else [])
    if args.bytecode:
        copies = tempfile.mkdtemp(prefix="bench-startup-bytecode-")
        codes = [(code, with_bytecode(root, os.path.join(copies, code))) for code, root in codes]
    rows, result = [], {}
    if not args.json:
        print(("CPU seconds" if args.cpu else "wall-clock seconds") +
              (f", medians of {args.repeat} processes" if args.repeat > 1 else "") +
              (", checkouts with bytecode" if args.bytecode else "") + "\n" +
              "\n".join(table([]).splitlines()[:2]), flush=True)
    for name in args.models:
        for code, root in codes:
            got = measure(name, root, args.api, args.tier, args.keep, args.repeat)
            result.setdefault(name, {})[code] = got
            for run in ("cold", "warm"):
                rows.append((name, code, run, got[run]))
                if not args.json:        # each row as soon as it is measured
                    print(table(rows[-1:], args.cpu).splitlines()[-1], flush=True)
    if args.json:
        print(json.dumps({"api": args.api, "tier": args.tier or os.environ.get("MECHGEN_TIER"),
                          "repeat": args.repeat, "bytecode": args.bytecode,
                          "results": result}, indent=1))
        return
    if args.baseline:
        print(f"\nratios baseline / this ({'CPU' if args.cpu else 'wall'}, total):")
        for name in args.models:
            r = result[name]
            for run in ("cold", "warm"):
                key = "total_cpu" if args.cpu else "total"
                a, b = r["baseline"][run].get(key), r["this"][run].get(key)
                if a and b:
                    print(f"  {name:14s} {run:5s} {a:7.2f} s / {b:7.2f} s = {a / b:5.2f}x")
        for name in args.models:
            r = result[name]
            ca = r["baseline"]["cold"].get("check")
            cb = r["this"]["cold"].get("check")
            if ca and cb:
                diff = max(abs(x - y) / (1.0 + abs(x)) for x, y in zip(ca, cb))
                print(f"  {name:14s} largest relative difference of the answers: {diff:.2e}")


if __name__ == "__main__":
    main()
