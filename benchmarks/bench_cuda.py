"""backend="cuda" design tables against a hand-written CUDA kernel, same process, same
designs: the quick-return of seed 001, a table of crank lengths (longitud) × times, each
design reduced on the GPU to the minimum and maximum of X4 (the slider) and their times.

    python benchmarks/bench_cuda.py                          # 10^6 designs × 1,000 times
    python benchmarks/bench_cuda.py --designs 20000 --times 200
    python benchmarks/bench_cuda.py --sim                    # tiny, on numba's simulator

Reports points (design, time) a second for the generated kernel (mechgen.runtime.tables.cuda,
the module's own solvers translated for the GPU) and the hand-written one
(``hand_kernel``: the sorted algorithm of benchmarks/baselines.py, one thread per design,
Taylor-predicted warm starts), their ratio, the largest difference between the two, and
the largest difference of the generated kernel from the CPU design table
(mech.sweep with params=) on a sample of the designs, with the count of designs whose
status or count of solved times differs.
Both GPU timings include sending the designs and fetching the four reductions.
Without a GPU (and without --sim) it says so and exits 0. ``measure()`` is the same as a
function (for benchmarks/bench_design.py).
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import time
import warnings

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
if "--sim" in sys.argv:
    os.environ["NUMBA_ENABLE_CUDASIM"] = "1"      # before numba is imported
sys.path.insert(0, ROOT)

import numpy as np  # noqa: E402
from numba import cuda  # noqa: E402  (the simulator swaps this global in its kernels)

MODULE = os.path.join(ROOT, "generated", "quick_return.py")
_HAND = {}


def hand_kernel():
    """The hand-written kernel (compiled on first use): thread d sweeps design P[d]
    (longitud, velocidad, anguloI) over ts and writes min, max, tmin, tmax of X4 to R[d]
    (NaN when a Newton fails), as the sorted algorithm of benchmarks/baselines.py."""
    if "k" in _HAND:
        return _HAND["k"]

    @cuda.jit
    def kernel(ts, P, tol, maxit, R):
        d = cuda.grid(1)
        if d >= P.shape[0]:
            return
        L, w, a0 = P[d, 0], P[d, 1], P[d, 2]
        th3, x4 = -0.5, 6.0
        th3d = x4d = th3dd = x4dd = 0.0
        lo = hi = tlo = thi = 0.0
        for k in range(ts.shape[0]):
            t = ts[k]
            if k > 0:
                h = t - ts[k - 1]
                th3 += h * (th3d + 0.5 * h * th3dd)
                x4 += h * (x4d + 0.5 * h * x4dd)
            th2 = w * t + a0
            c2, s2 = math.cos(th2), math.sin(th2)
            px, py = L * c2, 5.0 + L * s2          # crank pin from the colisa's pivot
            ok = False
            for _ in range(maxit):                  # point on line: -9 px c3 - 9 py s3 = 0
                c3, s3 = math.cos(th3), math.sin(th3)
                r = -9.0 * px * c3 - 9.0 * py * s3
                j = 9.0 * px * s3 - 9.0 * py * c3
                s = r / j
                th3 -= s
                if abs(r) <= tol and abs(s) <= tol * (1.0 + abs(th3)):
                    ok = True
                    break
            c3, s3 = math.cos(th3), math.sin(th3)
            cx, cy = -9.0 * s3, 9.0 * c3            # the colisa's far point; Th4 = 0
            for _ in range(maxit):                  # distance 5 on the guide y4 = 10
                r = (cx - x4) ** 2 + (cy - 10.0) ** 2 - 25.0
                j = -2.0 * (cx - x4)
                s = r / j
                x4 -= s
                if abs(r) <= tol and abs(s) <= tol * (1.0 + abs(x4)):
                    ok = ok and True
                    break
            else:
                ok = False
            if not ok or not abs(x4) < math.inf:
                R[d, 0] = R[d, 1] = R[d, 2] = R[d, 3] = math.nan
                return
            pxd, pyd = -L * s2 * w, L * c2 * w
            a = 9.0 * px * s3 - 9.0 * py * c3
            th3d = -(-9.0 * pxd * c3 - 9.0 * pyd * s3) / a
            cxd, cyd = -9.0 * c3 * th3d, -9.0 * s3 * th3d
            x4d = cxd + (cy - 10.0) * cyd / (cx - x4)
            pxdd, pydd = -L * c2 * w * w, -L * s2 * w * w
            ad = 9.0 * pxd * s3 + 9.0 * px * c3 * th3d - 9.0 * pyd * c3 + 9.0 * py * s3 * th3d
            bd = (-9.0 * pxdd * c3 + 9.0 * pxd * s3 * th3d - 9.0 * pydd * s3
                  - 9.0 * pyd * c3 * th3d)
            th3dd = -(ad * th3d + bd) / a
            cxdd = 9.0 * s3 * th3d * th3d - 9.0 * c3 * th3dd
            cydd = -9.0 * c3 * th3d * th3d - 9.0 * s3 * th3dd
            x4dd = cxdd + ((cxd - x4d) ** 2 + cyd * cyd + (cy - 10.0) * cydd) / (cx - x4)
            if k == 0 or x4 < lo:
                lo, tlo = x4, t
            if k == 0 or x4 > hi:
                hi, thi = x4, t
        R[d, 0] = lo
        R[d, 1] = hi
        R[d, 2] = tlo
        R[d, 3] = thi

    _HAND["k"] = kernel
    return kernel


def run_hand(ts, P, tol, maxit, threads=128):
    """The hand kernel on designs P: R (designs, 4) = min, max, tmin, tmax of X4."""
    kernel = hand_kernel()
    d_ts, d_P = cuda.to_device(ts), cuda.to_device(P)
    d_R = cuda.device_array((P.shape[0], 4))
    kernel[-(-P.shape[0] // threads), threads](d_ts, d_P, tol, maxit, d_R)
    return d_R.copy_to_host()


def _best(fn, rounds):
    best = math.inf
    out = None
    for _ in range(rounds):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def measure(designs=1_000_000, times=1000, sample=2000, rounds=3, threads=None,
            max_registers=None, level="position"):
    """The comparison as a dict (see the module docstring); None without a GPU."""
    import mechgen
    from mechgen.runtime.tables.cuda import design_status, quantity_slots, run_table_cuda, simulated
    if not (cuda.is_available() or simulated()):
        return None
    mech = mechgen.load(MODULE)
    ts = np.linspace(0.0, 1.0, times)
    P = np.tile(mech.p, (designs, 1))
    P[:, 0] = np.linspace(1.5, 4.0, designs)
    q0 = mech.guess.copy()
    slots = quantity_slots(mech, ["X4"], "position")   # [[0, index of X4, 0]]
    tpb = threads or (8 if simulated() else 128)

    def gen(PP=P):
        return run_table_cuda(mech, ts, PP, q0, level, mech.tol, mech.maxit, slots,
                              threads=tpb, max_registers=max_registers)

    def hand(PP=P):
        return run_hand(ts, PP, mech.tol, mech.maxit, threads=tpb)

    warm = P[: min(designs, 64)]
    t0 = time.perf_counter()
    gen(warm)
    # method="full" sends every design to the second kernel: both are compiled before timing
    run_table_cuda(mech, ts[:5], P[:2], q0, level, mech.tol, mech.maxit, slots,
                   method="full", threads=tpb, max_registers=max_registers)
    compile_gen = time.perf_counter() - t0
    t0 = time.perf_counter()
    hand(warm)
    compile_hand = time.perf_counter() - t0
    t_gen, g = _best(gen, rounds)
    t_hand, h = _best(hand, rounds)
    G = np.stack([g["min"][:, 0], g["max"][:, 0], g["tmin"][:, 0], g["tmax"][:, 0]], axis=1)
    both = np.isfinite(G[:, 0]) & np.isfinite(h[:, 0])
    gh = float(np.max(np.abs(G[both, :2] - h[both, :2]))) if both.any() else math.nan
    # the CPU design table on a sample of the designs (spread over the range)
    idx = np.unique(np.linspace(0, designs - 1, min(sample, designs)).astype(int))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")         # designs that fail are counted below
        tab = mech.sweep(0.0, 1.0, times, params={"longitud": P[idx, 0]}, level=level)
    X4 = tab["X4"]
    ok = tab.done == times
    cpu = np.stack([X4.min(axis=1), X4.max(axis=1)], axis=1)
    gs = G[idx]
    cpu_diff = float(np.max(np.abs(gs[ok, :2] - cpu[ok]))) if ok.any() else math.nan
    cpu_status = getattr(tab, "status", None)
    cpu_status = design_status(tab.INFO, tab.done, times) if cpu_status is None else \
        np.asarray(cpu_status).reshape(-1)
    bad_status = int(np.sum((g["done"][idx] != tab.done) | (g["status"][idx] != cpu_status)))
    points = designs * times
    return dict(designs=designs, times=times, points=points, level=level,
                second_pass=g["second_pass"],
                gen_points_per_s=points / t_gen, hand_points_per_s=points / t_hand,
                ratio=t_gen / t_hand, gen_s=t_gen, hand_s=t_hand,
                compile_gen_s=compile_gen, compile_hand_s=compile_hand,
                max_diff_gen_hand=gh, max_diff_gen_cpu=cpu_diff, sampled=len(idx),
                status_mismatches=bad_status, failed=int(np.sum(g["done"] < times)),
                simulated=simulated())


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=int, default=None)
    ap.add_argument("--times", type=int, default=None)
    ap.add_argument("--sample", type=int, default=2000, help="designs checked on the CPU")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=None, help="threads per block")
    ap.add_argument("--max-registers", type=int, default=None,
                    help="cap the generated kernel's registers per thread (numba's max_registers)")
    ap.add_argument("--level", default="position",
                    help="position, velocity or acceleration (the hand kernel always does all)")
    ap.add_argument("--sim", action="store_true", help="numba's CUDA simulator, tiny sizes")
    args = ap.parse_args(argv)
    designs = args.designs or (4 if args.sim else 1_000_000)
    times = args.times or (40 if args.sim else 1000)
    rounds = 1 if args.sim else args.rounds
    r = measure(designs, times, args.sample, rounds, args.threads, args.max_registers,
                args.level)
    if r is None:
        print("bench_cuda: no CUDA GPU here (numba.cuda.is_available() is False): skipped")
        return 0
    where = "numba's CUDA simulator (timings mean nothing)" if r["simulated"] else "GPU"
    print(f"quick-return, {r['designs']} designs × {r['times']} times = {r['points']:.3g} "
          f"points, level {r['level']}, on {where}")
    print(f"  generated (backend='cuda'): {r['gen_points_per_s']:.3g} points/s "
          f"({r['gen_s']:.3g} s; {r['second_pass']} designs needed the second kernel; "
          f"compiling both kernels {r['compile_gen_s']:.3g} s)")
    print(f"  hand-written kernel:        {r['hand_points_per_s']:.3g} points/s "
          f"({r['hand_s']:.3g} s; compile {r['compile_hand_s']:.3g} s)")
    print(f"  generated / hand time: {r['ratio']:.3g}")
    print(f"  max |generated - hand| (min, max of X4): {r['max_diff_gen_hand']:.3g}")
    print(f"  max |generated - CPU table| on {r['sampled']} designs: "
          f"{r['max_diff_gen_cpu']:.3g}; statuses differing: {r['status_mismatches']}; "
          f"failed designs: {r['failed']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
