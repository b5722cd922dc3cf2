"""Path fitting three ways, side by side in one process on the same seeded problems:
four-bars recovered from 10 of their coupler points (tests/test_path_fitting.py's model,
problems and bounds; the points from its numpy closed form), with the timing free and
prescribed.

- ``fit``: mech.fit (design-table search, then Levenberg–Marquardt on the exact
  derivatives, then the defect check);
- ``optimize``: mech.optimize as before fit, differential evolution on design tables and
  a Nelder-Mead polish, its objective built from the table: prescribed, the squared
  distances at the given times; free, each target's squared distance from the nearest
  of the table's points over one cycle (129 of them);
- ``lsq-fd``: scipy's least_squares (trf, the same bounds) with finite-difference
  Jacobians ("2-point"), from the same start fit's least squares takes its first from
  (the best design of the global stage's first round), its residuals from mech.solve (each
  point from the last configuration solved), the same unknowns (the phases too when
  timing is free).

Each method's final error is measured the same way: the RMS distance from the targets, at
the given times (prescribed) or at each target's nearest point of the design's path
(free: the phase refined by exact solves about the nearest of 2001 points). Evaluations:
designs (a design table's, or a one-design table of Nelder-Mead's) or residual
evaluations (each one design at the 10 times; lsq-fd counts those of its differences too).

    python benchmarks/bench_fit.py                  # 5 problems, both timings
    python benchmarks/bench_fit.py --problems 10 --timing free
"""
from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
import warnings

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, ROOT)
sys.path.insert(0, os.path.join(ROOT, "tests"))
os.environ.setdefault("MECHGEN_TIER", "compiled")

import mechgen  # noqa: E402
from mechgen import MechgenError  # noqa: E402
from mechgen.runtime.fitting.problem import make_problem  # noqa: E402
from mechgen.runtime.fitting.search import GlobalStage  # noqa: E402

import test_path_fitting as tp  # noqa: E402

POINT = "coupler[3]"


def exact_error(design, xy, ts, free, start=None):
    """The RMS distance of ``design`` (a mechanism on its mode) from the targets (see the
    docstring); timing free, its path is swept over one cycle from ``start`` (t, q), or
    from t = 0 where None."""
    if start is not None:
        design = design.with_params()
        design.set_guess(start[1], t=start[0])
    k = design.point_names.index(POINT)
    if not free:
        try:
            pts = np.array([design.solve(t).points()[k] for t in ts])
        except MechgenError:
            return np.inf
        return float(np.sqrt(np.mean(np.sum((pts - xy) ** 2, axis=1))))
    from scipy.optimize import brentq
    from mechgen.runtime.sensitivity.values import point_velocity
    t0 = 0.0 if start is None else start[0]
    try:
        sw = design.sweep(t0, t0 + 1.0, 2001)
    except MechgenError as exc:
        sw = getattr(exc, "sweep", None)
        if sw is None or len(sw) < 3:
            return np.inf
    path = sw.points()[:, k]
    d2 = []
    for target in xy:
        j = int(np.argmin(np.sum((path - target) ** 2, axis=1)))
        best = float(np.sum((path[j] - target) ** 2))
        lo, hi = sw.t[max(j - 1, 0)], sw.t[min(j + 1, len(sw) - 1)]

        def at(t, j=j):
            s = design.solve(t, guess=sw.Q[j], level="velocity")
            return s.points()[k], point_velocity(design, s.q, s.qd, t, POINT)

        def slope(t):       # d/dt of half the squared distance: zero at the nearest point
            p, v = at(t)
            return float((p - target) @ v)
        try:
            if slope(lo) * slope(hi) < 0:
                t = brentq(slope, lo, hi, xtol=1e-16, rtol=4 * np.finfo(float).eps)
                best = min(best, float(np.sum((at(t)[0] - target) ** 2)))
        except MechgenError:
            pass
        d2.append(best)
    return float(np.sqrt(np.mean(d2)))


def by_fit(mech, point, xy, ts, free):
    fit = mech.fit(point, xy, tp.BOUNDS, timing=None if free else ts)
    return fit.mechanism, fit.evaluations, fit.designs, None


def by_optimize(mech, point, xy, ts, free):
    if free:
        n, t0, t1, times = 129, 0.0, 1.0, None
    else:
        n, t0, t1, times = len(ts), float(ts[0]), float(ts[-1]), ts

    def objective(tab):
        pts = np.stack([tab["px"], tab["py"]], axis=-1)             # (designs, n, 2)
        if free:
            d2 = np.sum((pts[:, :, None, :] - xy[None, None]) ** 2, axis=-1).min(axis=1)
        else:
            d2 = np.sum((pts - xy[None]) ** 2, axis=-1)
        return d2.mean(axis=1)
    best = mech.optimize(objective, tp.BOUNDS, t0, t1, n, times=times, seed=0, polish=True)
    return best.mechanism, best.evaluated, best.evaluated, None


def by_fd(mech, point, xy, ts, free):
    """scipy's least_squares with finite differences from the global stage's best
    first-round design (the start fit's least squares takes first)."""
    from scipy.optimize import least_squares
    problem = make_problem(mech, point, xy, tp.BOUNDS, None if free else ts, {})
    stage = GlobalStage(problem)
    stage.first()
    start = stage.best(1)[0]
    names, m = problem.names, len(problem.names)
    k = mech.point_names.index(POINT)
    state = {"Q": start.Q.copy(), "count": 0, "best": (np.inf, start.x, None)}

    def fun(z):
        r = residuals(z)
        cost = float(r @ r)
        if cost < state["best"][0]:
            first = int(np.argmin(z[m:])) if free else 0
            at = (float((z[m:] if free else ts)[first]), state["Q"][first].copy())
            state["best"] = (cost, z[:m].copy(), at)
        return r

    def residuals(z):
        state["count"] += 1
        times = z[m:] if free else ts
        try:
            design = start.reference.with_params(**dict(zip(names, z[:m])))
            sols = [design.solve(float(t), guess=q) for t, q in zip(times, state["Q"])]
        except (MechgenError, ValueError):
            return np.full(2 * len(xy), np.nan)
        state["Q"] = np.array([s.q for s in sols])
        return (np.array([s.points()[k] for s in sols]) - xy).reshape(-1)

    lo, hi = problem.lows, problem.highs
    x0 = np.clip(start.x, lo + 1e-12 * (hi - lo), hi - 1e-12 * (hi - lo))
    if free:
        x0 = np.concatenate([x0, start.times])
        inf = np.full(len(xy), np.inf)
        lo, hi = np.concatenate([lo, -inf]), np.concatenate([hi, inf])
    try:
        least_squares(fun, x0, jac="2-point", bounds=(lo, hi), method="trf", x_scale="jac",
                      ftol=1e-15, xtol=1e-15, gtol=1e-15, max_nfev=200)
    except ValueError:      # a difference across a design that does not solve: NaN in J
        print("  lsq-fd: stopped, a finite difference reached a design that does not solve")
    params = dict(zip(names, (float(v) for v in state["best"][1])))
    design = start.reference.with_params(**params)
    return design, stage.evaluated + state["count"], stage.evaluated, state["best"][2]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--problems", type=int, default=5)
    ap.add_argument("--timing", choices=("free", "prescribed", "both"), default="both")
    ap.add_argument("--methods", default="fit,optimize,lsq-fd")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    folder = tempfile.mkdtemp(prefix="mechgen-bench-fit-")
    model, coupler = tp.fourbar_model()
    mech = mechgen.compile(model, outdir=folder)
    point = coupler[3]
    run = {"fit": by_fit, "optimize": by_optimize, "lsq-fd": by_fd}
    methods = [m for m in args.methods.split(",") if m in run]
    timings = ("free", "prescribed") if args.timing == "both" else (args.timing,)
    # warm: numba compiles the module's table and sensitivity functions once
    truth, ts, xy = tp.problem(0)
    mech.fit(point, xy, tp.BOUNDS, timing=ts, samples=64, rounds=0)
    print(f"{'timing':10s} {'problem':>7s} {'method':9s} {'evaluations':>11s} "
          f"{'(global)':>9s} {'seconds':>8s} {'error':>9s}")
    totals = {}
    for timing in timings:
        free = timing == "free"
        for seed in range(args.problems):
            truth, ts, xy = tp.problem(seed)
            for name in methods:
                t0 = time.perf_counter()
                try:
                    design, evaluations, designs, at = run[name](mech, point, xy, ts, free)
                    seconds = time.perf_counter() - t0
                    error = exact_error(design, xy, ts, free, at)
                except MechgenError as exc:
                    seconds, evaluations, designs, error = time.perf_counter() - t0, 0, 0, np.inf
                    print(f"  {name}: {exc}")
                print(f"{timing:10s} {seed:7d} {name:9s} {evaluations:11d} {designs:9d} "
                      f"{seconds:8.2f} {error:9.2e}", flush=True)
                tot = totals.setdefault((timing, name), [0, 0.0, [], 0])
                tot[0] += evaluations
                tot[1] += seconds
                tot[2].append(error)
                tot[3] += error <= 1e-9
    print()
    print(f"{'timing':10s} {'method':9s} {'evaluations':>11s} {'seconds':>8s} "
          f"{'median error':>12s} {'<= 1e-9':>8s}   (means over the problems)")
    for (timing, name), (ev, sec, errs, ok) in totals.items():
        n = len(errs)
        print(f"{timing:10s} {name:9s} {ev / n:11.0f} {sec / n:8.2f} {np.median(errs):12.2e} "
              f"{ok:4d}/{n}")


if __name__ == "__main__":
    main()
