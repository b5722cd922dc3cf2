"""Speed against error on the quick-return of seed 001: Newton tolerances and sweep
densities, then the stroke's extremes from the interpolant against exact refinement.
Errors are against a 50-digit mpmath reference (closed form, benchmarks/baselines.py).

    python benchmarks/bench_tradeoff.py                 # tables, and a plot
    python benchmarks/bench_tradeoff.py --quick         # fewer cases
    python benchmarks/bench_tradeoff.py --plot out.png  # where the plot goes
"""
from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

import mpmath
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)

import baselines  # noqa: E402

import mechgen  # noqa: E402
from mechgen.compiler.build import build  # noqa: E402
from mechgen.model.loader import load_models  # noqa: E402
from mechgen.runtime import Mechanism  # noqa: E402


def best_time(fn, repeats):
    """The fastest of a few runs (seconds), and the last result."""
    best, out = float("inf"), None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def sweep_errors(sw, samples):
    """Largest error of Th3 and X4 (position, velocity, acceleration) at sample rows."""
    worst = [0.0, 0.0, 0.0]
    names = (("Th3", "X4"), ("Th3d", "X4d"), ("Th3dd", "X4dd"))
    for k in samples:
        ref = baselines.reference(float(sw.t[k]))
        for lev in range(3):
            for i, name in enumerate(names[lev]):
                worst[lev] = max(worst[lev], abs(float(sw[name][k]) - ref[2 * lev + i]))
    return worst


def exact_extremes():
    """(t, X4) of the stroke's minimum and maximum, to 50 digits."""
    out = []
    with mpmath.workdps(50):
        for t0 in (0.6024, 0.8976):
            t = mpmath.findroot(lambda s: mpmath.diff(lambda u: baselines._closed(u)[1], s), t0)
            out.append((float(t), float(baselines._closed(t)[1])))
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--plot", default=os.path.join(tempfile.gettempdir(), "mechgen_tradeoff.png"))
    args = ap.parse_args()
    model = load_models(os.path.join(ROOT, "examples", "quick_return.py"))[0]
    module = mechgen.load(build(model, tempfile.mkdtemp(prefix="mechgen-bench-"))).module
    tols = (1e-4, 1e-8, 1e-12) if args.quick else (1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14)
    sizes = (20, 200, 20_000) if args.quick else (20, 200, 2_000, 20_000, 200_000)
    repeats = 3 if args.quick else 5

    # -- Newton tolerance x sweep density ----------------------------------------------
    print("A. quick-return sweep over T in [0, 1], positions, velocities and accelerations")
    print(f"{'tol = xtol':>10s} {'points':>8s} {'ns/point':>9s} {'iters':>6s} "
          f"{'err pos':>9s} {'err vel':>9s} {'err acc':>9s}")
    rows = []
    for tol in tols:
        mech = Mechanism(module, tol=tol, xtol=tol)
        mech.sweep(0.0, 1.0, 5, level="acceleration")
        for n in sizes:
            mech.sweep(0.0, 1.0, n, level="acceleration")      # fresh memory touched once
            secs, sw = best_time(lambda: mech.sweep(0.0, 1.0, n, level="acceleration"), repeats)
            samples = np.unique(np.linspace(0, n - 1, min(n, 40)).astype(int))
            err = sweep_errors(sw, samples)
            iters = float(np.mean(sw.info[:, 0])) if hasattr(sw, "info") else float("nan")
            rows.append((tol, n, secs / n * 1e9, err))
            print(f"{tol:10.0e} {n:8d} {secs / n * 1e9:9.0f} {iters:6.2f} "
                  f"{err[0]:9.1e} {err[1]:9.1e} {err[2]:9.1e}")
    print("ns/point: one mech.sweep call (Python entry, allocation and the compiled loop) over "
          "its points; iters: mean Newton iterations of the slowest block per point.")

    # -- extremes of the stroke: interpolant against exact refinement --------------------
    print("\nB. the stroke's extremes (X4 min and max): interpolated against refined by exact solves")
    exact = exact_extremes()
    print(f"{'points':>8s} {'interpolant':>20s} {'sweep ms':>9s} {'extrema ms':>11s} {'solves':>7s} "
          f"{'interp t err':>13s} {'interp X4 err':>14s} {'exact t err':>12s} {'exact X4 err':>13s}")
    mech = Mechanism(module)
    mech.sweep(0.0, 1.0, 20, level="acceleration").extrema("X4")   # compile what it uses
    for n in ((20, 50, 2_000) if args.quick else (20, 50, 200, 2_000, 20_000)):
        secs, sw = best_time(lambda: mech.sweep(0.0, 1.0, n, level="acceleration"), repeats)
        for method in ("auto", "lagrange"):
            ex_secs, ev = best_time(lambda: sw.extrema("X4", method=method), 1)
            ev = sorted(ev, key=lambda e: e.t)
            e_ti = max(abs(e.t_interp - r[0]) for e, r in zip(ev, exact))
            e_vi = max(abs(e.value_interp - r[1]) for e, r in zip(ev, exact))
            e_t = max(abs(e.t - r[0]) for e, r in zip(ev, exact))
            e_v = max(abs(e.value - r[1]) for e, r in zip(ev, exact))
            solves = sum(e.solves for e in ev)
            print(f"{n:8d} {ev[0].method:>20s} {secs * 1e3:9.2f} {ex_secs * 1e3:11.2f} {solves:7d} "
                  f"{e_ti:13.1e} {e_vi:14.1e} {e_t:12.1e} {e_v:13.1e}")
    print("interp: the root of the interpolated derivative (Mech's FindRoot on TimeInterpolate) "
          "and the interpolant's value there;\nexact: Brent's method on exactly solved "
          "derivatives from the sweep's bracket (extrema ms covers both).")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for tol in tols:
        pts = [(r[2], max(r[3][0], 1e-17)) for r in rows if r[0] == tol]
        ax.loglog(*zip(*pts), "o-", label=f"tol {tol:.0e}")
    for r in rows:
        if r[0] == tols[-1]:
            ax.annotate(f"{r[1]}", (r[2], max(r[3][0], 1e-17)), fontsize=7,
                        textcoords="offset points", xytext=(3, 3))
    ax.set_xlabel("time per point, ns (mech.sweep; labels: points per sweep)")
    ax.set_ylabel("largest position error vs mpmath")
    ax.set_title("quick-return sweep: speed against error")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.plot, dpi=110)
    print(f"\nplot: {args.plot}")


if __name__ == "__main__":
    main()
