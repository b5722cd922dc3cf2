"""Edit -> first answers for the seed's quick-return, in fresh processes: before (the
checkout named by --old, load_model + compile) and now (mechgen.compile(path): the
plain-Python tier answers while numba compiles in the background), with an empty numba
cache and build folder (cold), then again (warm); and a 10^6-point sweep in a cold
process. Run: python benchmarks/tiers_first_answers.py --old /work/old
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

STEPS = r'''
import json, sys, time
t0 = time.perf_counter()
import mechgen
mark = {}
try:
    from mechgen.bridge import compile_file   # noqa: F401 - the tiers exist
    mech = mechgen.compile(MODEL, outdir=OUT)
except ImportError:
    mech = mechgen.compile(mechgen.load_model(MODEL), outdir=OUT)
mark["build+load"] = time.perf_counter() - t0
if BIG:     # a process that only runs a 10^6-point sweep
    t = time.perf_counter(); big = mech.sweep(0, 1, 10**6, level="acceleration")
    mark["sweep1e6"] = time.perf_counter() - t
    a, sw = big[150000], big
else:
    t = time.perf_counter(); s = mech.solve(0.15); mark["position"] = time.perf_counter() - t
    t = time.perf_counter(); a = mech.solve(0.15, level="acceleration"); mark["acceleration"] = time.perf_counter() - t
    t = time.perf_counter(); sw = mech.sweep(0, 1, 101, level="acceleration"); mark["sweep101"] = time.perf_counter() - t
mark["total"] = time.perf_counter() - t0
mark["tier"] = getattr(mech, "tier", "compiled")
mark["sympy"] = "sympy" in sys.modules
mark["numba"] = "numba" in sys.modules
mark["X4dd"] = float(a["X4dd"])
mark["sweepX4"] = float(sw["X4"].sum())
print(json.dumps(mark))
'''


def run(root, model, out, cache, big):
    code = STEPS.replace("MODEL", repr(model)).replace("OUT", repr(out)).replace("BIG", repr(big))
    env = dict(os.environ, PYTHONPATH=root, NUMBA_CACHE_DIR=cache, MECHGEN_CACHE=cache + "-mg")
    env.pop("MECHGEN_TIER", None)
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                         cwd=root)
    if res.returncode:
        raise SystemExit(res.stderr)
    return json.loads(res.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--old", default="/work/old")
    ap.add_argument("--big", action="store_true", help="also a 10^6-point sweep, cold")
    ap.add_argument("--only-big", action="store_true", help="only the 10^6-point sweep")
    args = ap.parse_args()
    rows = []
    for label, root in (("before", args.old), ("now", HERE)):
        tmp = tempfile.mkdtemp(prefix="tiers-bench-")
        model = os.path.join(tmp, "quick_return.py")
        shutil.copy(os.path.join(HERE, "examples", "quick_return.py"), model)
        out, cache = os.path.join(tmp, "gen"), os.path.join(tmp, "nc")
        if not args.only_big:
            rows.append((label, "cold", run(root, model, out, cache, False)))
        if label == "now" and not args.only_big:          # let the background worker finish its cache
            subprocess.run([sys.executable, "-m", "mechgen.runtime.loading.warmup",
                            os.path.join(out, "quick_return.py")],
                           env=dict(os.environ, PYTHONPATH=root, NUMBA_CACHE_DIR=cache))
        if not args.only_big:
            rows.append((label, "warm", run(root, model, out, cache, False)))
        if args.big or args.only_big:
            shutil.rmtree(out, ignore_errors=True)
            shutil.rmtree(cache, ignore_errors=True)
            shutil.rmtree(cache + "-mg", ignore_errors=True)
            rows.append((label, "cold 1e6", run(root, model, out, cache, True)))
        shutil.rmtree(tmp, ignore_errors=True)
    keys = ("build+load", "position", "acceleration", "sweep101", "sweep1e6", "total")
    print(f"{'':8}{'':10}" + "".join(f"{k:>13}" for k in keys) + "  tier      sympy numba")
    for label, case, m in rows:
        print(f"{label:8}{case:10}" + "".join(f"{m[k]:13.3f}" if k in m else f"{'':13}" for k in keys)
              + f"  {m['tier']:9} {m['sympy']!s:5} {m['numba']!s:5}")
    same = {(r[2]["X4dd"], r[2]["sweepX4"]) for r in rows if r[1] != "cold 1e6"}
    same_big = {(r[2]["X4dd"], r[2]["sweepX4"]) for r in rows if r[1] == "cold 1e6"}
    print("10^6 sweeps identical:", len(same_big) <= 1)
    print("answers identical across runs:", len(same) <= 1, same if len(same) > 1 else "")


if __name__ == "__main__":
    main()
