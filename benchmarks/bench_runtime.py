"""The runtime, measured: time per position solve and per sweep point, accuracy, compile time.

Run from anywhere:  python benchmarks/bench_runtime.py [--quick]

The quick-return of seed 001 (examples/quick_return.py, 9 coordinates), T in [0, 1]. In one
process, interleaved rounds, medians per point:

- ``mech.solve(t)``: one call of the runtime from Python, from the model's guess (cold),
  with the guards, the error checks and the Solution object: what a user's loop pays.
- the compiled sweep (``mech.sweep``), positions only, and positions + velocities +
  accelerations; with the sorted solver and with ``method="full"`` (Newton on all 9
  coordinates), and the ``--no-sort`` build (``render(model, sort=False)``).
- ``sympy.lambdify`` + ``scipy.optimize.fsolve(fprime=J)`` per point, warm-started from the
  previous point, as users write it (default tolerances, and xtol=1e-13).

Errors are against a 50-digit reference: ``mpmath.findroot`` on Φ lambdified with mpmath
(the same float parameters and times), velocities and accelerations from mpmath LU solves of
Φ_q q̇ = ν and Φ_q q̈ = γ. Compile times come from fresh subprocesses: a module built into a
new folder (numba has no cache for it) and the same again (numba's cache now on disk).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import textwrap
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
EXAMPLE = os.path.join(ROOT, "examples", "quick_return.py")
sys.path.insert(0, ROOT)


def median_per_point(fn, npoints, rounds):
    """fn() runs npoints solves; the median over rounds of its time per point, in ns."""
    times = []
    for _ in range(rounds):
        t0 = time.perf_counter()
        fn()
        times.append((time.perf_counter() - t0) / npoints * 1e9)
    return statistics.median(times)


# -- the 50-digit reference ---------------------------------------------------------------
class Reference:
    def __init__(self, model, params):
        import mpmath
        import sympy as sp
        mpmath.mp.dps = 50
        self.mp = mpmath
        eq = model.equations()
        syms = [sym for sym, _ in model.params.values()]
        self.q, self.qd = list(eq.q), list(eq.qd)
        args = [*eq.q, *eq.qd, eq.T, *syms]
        self.p = [mpmath.mpf(float(v)) for v in params]        # the module's own floats
        self.f_phi = sp.lambdify(args, list(eq.phi), modules="mpmath")
        self.f_J = sp.lambdify(args, eq.phi_q.tolist(), modules="mpmath")
        self.f_nu = sp.lambdify(args, list(eq.nu), modules="mpmath")
        self.f_gamma = sp.lambdify(args, list(eq.gamma), modules="mpmath")
        self.n = len(self.q)

    def solve(self, t, start):
        """(q, qd, qdd) at float t as mpmath numbers, Newton from ``start``."""
        mp, n = self.mp, self.n
        t = mp.mpf(float(t))
        zero = [mp.mpf(0)] * n
        f = lambda *x: self.f_phi(*x, *zero, t, *self.p)          # noqa: E731
        J = lambda *x: self.f_J(*x, *zero, t, *self.p)            # noqa: E731
        q = mp.findroot(f, [mp.mpf(float(x)) for x in start], J=J, tol=mp.mpf(10) ** -45)
        q = [q[i] for i in range(n)]
        A = mp.matrix(self.f_J(*q, *zero, t, *self.p))
        qd = mp.lu_solve(A, mp.matrix(self.f_nu(*q, *zero, t, *self.p)))
        qd = [qd[i] for i in range(n)]
        qdd = mp.lu_solve(A, mp.matrix(self.f_gamma(*q, *qd, t, *self.p)))
        return q, qd, [qdd[i] for i in range(n)]


def max_error(values, exact):
    return max(abs(float(v) - float(e)) if e == e else 0.0 for v, e in zip(values, exact))


# -- lambdify + fsolve, as users write it -----------------------------------------------------
def lambdify_fsolve(model, params, xtol=None):
    import sympy as sp
    from scipy.optimize import fsolve
    eq = model.equations()
    subs = {sym: float(v) for (sym, _), v in zip(model.params.values(), params)}
    phi = eq.phi.subs(subs)
    jac = eq.phi_q.subs(subs)
    q = list(eq.q)
    f = sp.lambdify((q, eq.T), phi, "numpy")
    J = sp.lambdify((q, eq.T), jac, "numpy")
    kw = {} if xtol is None else {"xtol": xtol}

    def sweep(ts, q0):
        out = np.empty((len(ts), len(q)))
        x = np.array(q0, dtype=np.float64)
        for k, t in enumerate(ts):
            x = fsolve(lambda y: f(y, t).ravel(), x, fprime=lambda y: J(y, t), **kw)
            out[k] = x
        return out
    return sweep


# -- compile time, in fresh processes ------------------------------------------------------------
FIRST_USE = textwrap.dedent("""
    import json, sys, time
    t0 = time.perf_counter()
    import numba, numpy
    t1 = time.perf_counter()
    import mechgen
    mech = mechgen.load({path!r})
    t2 = time.perf_counter()
    mech.solve(0.15)
    t3 = time.perf_counter()
    mech.solve(0.15, level="acceleration")
    t4 = time.perf_counter()
    mech.sweep(0.0, 1.0, 101, level="acceleration")
    t5 = time.perf_counter()
    print(json.dumps(dict(numba_import=t1 - t0, load=t2 - t1, first_solve=t3 - t2,
                          first_acc=t4 - t3, first_sweep=t5 - t4, total=t5 - t0,
                          sympy="sympy" in sys.modules)))
""")

STANDALONE = textwrap.dedent("""
    import json, sys, time
    t0 = time.perf_counter()
    sys.path.insert(0, {folder!r})
    import numpy as np
    import quick_return as m
    t1 = time.perf_counter()
    q = np.array(m.GUESS); p = np.array(m.PARAMETER_DEFAULTS); info = np.zeros(4)
    m.solve_position(q, 0.15, p, 1e-10, 1e-10, 50, 0, info)
    t2 = time.perf_counter()
    print(json.dumps(dict(import_=t1 - t0, first_solve=t2 - t1, mechgen="mechgen" in sys.modules)))
""")


def run_child(code):
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          cwd=tempfile.gettempdir())
    if proc.returncode:
        raise RuntimeError(proc.stderr)
    return json.loads(proc.stdout.strip().splitlines()[-1])


def compile_times(model):
    from mechgen.compiler.build import build
    folder = tempfile.mkdtemp(prefix="mechgen-bench-")
    t0 = time.perf_counter()
    path = build(model, folder)
    t_build = time.perf_counter() - t0
    fresh = run_child(FIRST_USE.format(path=path))
    cached = run_child(FIRST_USE.format(path=path))
    alone = run_child(STANDALONE.format(folder=folder))
    return t_build, fresh, cached, alone


# -- main ------------------------------------------------------------------------------------------
def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="fewer points and rounds")
    args = ap.parse_args(argv)
    n_fast, n_slow, rounds = (20_000, 300, 5) if args.quick else (100_000, 2000, 11)

    import mechgen
    from mechgen.compiler.build import build
    from mechgen.model.loader import load_models
    t0 = time.perf_counter()
    model = load_models(EXAMPLE)[0]
    model.equations()
    t_sym = time.perf_counter() - t0

    print("compile times (fresh subprocesses) ...", flush=True)
    t_build, fresh, cached, alone = compile_times(model)

    tmp = tempfile.mkdtemp(prefix="mechgen-bench-")
    mech = mechgen.load(build(model, os.path.join(tmp, "sorted")))
    nosort = mechgen.load(build(model, os.path.join(tmp, "nosort"), sort=False))
    p = mech.p.copy()
    fs_default = lambdify_fsolve(model, p)
    fs_tight = lambdify_fsolve(model, p, xtol=1e-13)

    ts_slow = np.linspace(0.0, 1.0, n_slow)
    ts_calls = np.linspace(0.0, 1.0, 2000)
    guess = mech.guess.copy()

    def calls(level, method=None):
        def run():
            for t in ts_calls:
                mech.solve(t, level=level, method=method)
        return run

    def module_calls():
        mod, q0, info = mech.module, mech.guess, np.zeros(4)

        def run():
            for t in ts_calls:
                q = q0.copy()
                mod.solve_position(q, t, p, 1e-10, 1e-10, 50, 0, info)
        return run

    def sweep(m, level, method=None):
        return lambda: m.sweep(0.0, 1.0, n_fast, level=level, method=method)

    methods = {
        "mech.solve(t), sorted": (calls("position"), len(ts_calls)),
        "mech.solve(t, level=acc), sorted": (calls("acceleration"), len(ts_calls)),
        "mech.solve(t, method=full)": (calls("position", "full"), len(ts_calls)),
        "module.solve_position (no wrapper)": (module_calls(), len(ts_calls)),
        "sweep, sorted, positions": (sweep(mech, "position"), n_fast),
        "sweep, sorted, pos+vel+acc": (sweep(mech, "acceleration"), n_fast),
        "sweep, method=full, positions": (sweep(mech, "position", "full"), n_fast),
        "sweep, method=full, pos+vel+acc": (sweep(mech, "acceleration", "full"), n_fast),
        "sweep, --no-sort build, positions": (sweep(nosort, "position"), n_fast),
        "sweep, --no-sort build, pos+vel+acc": (sweep(nosort, "acceleration"), n_fast),
        "lambdify + fsolve (defaults)": (lambda: fs_default(ts_slow, guess), n_slow),
        "lambdify + fsolve (xtol=1e-13)": (lambda: fs_tight(ts_slow, guess), n_slow),
    }
    print("warming up (numba compiles the solvers) ...", flush=True)
    t0 = time.perf_counter()
    for fn, _ in methods.values():
        fn()
    t_warm = time.perf_counter() - t0
    print(f"timing {rounds} interleaved rounds ...", flush=True)
    samples = {k: [] for k in methods}
    for _ in range(rounds):
        for name, (fn, npts) in methods.items():
            samples[name].append(median_per_point(fn, npts, 1))
    med = {k: statistics.median(v) for k, v in samples.items()}
    base = med["lambdify + fsolve (defaults)"]

    # -- accuracy against 50 digits --------------------------------------------------------
    print("50-digit references ...", flush=True)
    ref = Reference(model, p)
    probe = [0.15, 0.37, 0.5, 0.85, 0.93]
    idx_fast = [int(round(t * (n_fast - 1))) for t in probe]
    idx_slow = [int(round(t * (n_slow - 1))) for t in probe]
    exact = {}

    def ref_at(t, start):
        if t not in exact:
            exact[t] = ref.solve(t, start)
        return exact[t]

    errors = {k: [0.0, float("nan"), float("nan")] for k in methods}
    for t in probe:
        for name, method in (("mech.solve(t), sorted", None), ("mech.solve(t, level=acc), sorted", None),
                             ("mech.solve(t, method=full)", "full")):
            s = mech.solve(t, level="acceleration", method=method)
            q, qd, qdd = ref_at(s.t, s.q)
            e = errors[name]
            e[0] = max(e[0], max_error(s.q, q))
            if "acc" in name or "full" in name:
                e[1] = np.nanmax([e[1], max_error(s.qd, qd)])
                e[2] = np.nanmax([e[2], max_error(s.qdd, qdd)])
    errors["module.solve_position (no wrapper)"] = [errors["mech.solve(t), sorted"][0],
                                                     float("nan"), float("nan")]
    for name, m, method in (("sorted", mech, None), ("method=full", mech, "full"),
                            ("--no-sort build", nosort, None)):
        sw = m.sweep(0.0, 1.0, n_fast, level="acceleration", method=method)
        e = [0.0, 0.0, 0.0]
        for k in idx_fast:
            q, qd, qdd = ref_at(float(sw.t[k]), sw.Q[k])
            e = [max(e[0], max_error(sw.Q[k], q)), max(e[1], max_error(sw.QD[k], qd)),
                 max(e[2], max_error(sw.QDD[k], qdd))]
        errors[f"sweep, {name}, pos+vel+acc"] = e
        sw = m.sweep(0.0, 1.0, n_fast, level="position", method=method)
        errors[f"sweep, {name}, positions"] = [
            max(max_error(sw.Q[k], ref_at(float(sw.t[k]), sw.Q[k])[0]) for k in idx_fast),
            float("nan"), float("nan")]
    for name, fn in (("lambdify + fsolve (defaults)", fs_default),
                     ("lambdify + fsolve (xtol=1e-13)", fs_tight)):
        Q = fn(ts_slow, guess)
        errors[name] = [max(max_error(Q[k], ref_at(float(ts_slow[k]), Q[k])[0]) for k in idx_slow),
                        float("nan"), float("nan")]

    # -- the table ----------------------------------------------------------------------------
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print()
    print(f"quick_return (9 coordinates), T in [0, 1]; {rounds} rounds; sweeps of {n_fast} points, "
          f"fsolve {n_slow}, solve() calls 2000; load average {load:.1f} on {os.cpu_count()} CPUs")
    head = (f"{'method':38s} {'ns/point':>11s} {'vs fsolve':>10s}   "
            f"{'err q':>8s} {'err qd':>8s} {'err qdd':>8s}")
    print(head)
    print("-" * len(head))
    fmt = lambda x: "       -" if x != x else f"{x:8.1e}"   # noqa: E731
    for name in methods:
        e = errors[name]
        print(f"{name:38s} {med[name]:11,.0f} {base / med[name]:9.0f}x   "
              f"{fmt(e[0])} {fmt(e[1])} {fmt(e[2])}")
    print()
    print("vs fsolve: how many times faster per point than sympy.lambdify + scipy fsolve "
          "(defaults) in this process.")
    print(f"errors: max |value − 50-digit mpmath| over T = {', '.join(map(str, probe))} "
          "(nearest sweep point).")
    print()
    print(f"symbolic expansion (model file + equations): {t_sym:.2f} s; render + write module: "
          f"{t_build:.2f} s; warm-up of all solvers in this process: {t_warm:.1f} s")
    print("first use in a fresh process (no numba cache):   "
          f"import numba {fresh['numba_import']:.2f} s, mechgen.load {fresh['load']:.2f} s, "
          f"first solve {fresh['first_solve']:.2f} s, first acceleration solve "
          f"{fresh['first_acc']:.2f} s, first sweep {fresh['first_sweep']:.2f} s; total "
          f"{fresh['total']:.2f} s")
    print("again, numba cache on disk (cached import):       "
          f"import numba {cached['numba_import']:.2f} s, mechgen.load {cached['load']:.2f} s, "
          f"first solve {cached['first_solve']:.3f} s, first acceleration solve "
          f"{cached['first_acc']:.3f} s, first sweep {cached['first_sweep']:.3f} s; total "
          f"{cached['total']:.2f} s")
    print(f"the module alone (no mechgen), cached: import {alone['import_']:.2f} s, first "
          f"solve_position {alone['first_solve']:.3f} s; sympy loaded by the runtime: "
          f"{fresh['sympy'] or cached['sympy']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
