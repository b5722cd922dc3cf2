"""The GPU check a session runs when it is lent a device (one process, one script):
backend="cuda" design tables of the quick-return beside the hand-written kernel of
benchmarks/bench_cuda.py, at 10^5 designs × 10^3 times, positions and all levels, then
10^6 designs × 10^3 times in positions; each with its difference from the hand kernel
and from the CPU design table on a sample of designs. Then a force table: the peak crank
torque of 10^4 designs of examples/quick_return_forces.py × 10^3 times at level
"dynamic" (the effort reduced in the kernel, mechgen.runtime.tables.cuda_forces; the designs it
leaves to the host solved there) beside the same table on the CPU's cores, their largest
difference, and the kernel alone at a few block sizes (how many designs it left to the
host).

    PYTHONPATH=. MECHGEN_TIER=compiled python3 benchmarks/device_cuda.py [--quick]
    PYTHONPATH=. MECHGEN_TIER=compiled python3 benchmarks/device_cuda.py --forces [--old]
    PYTHONPATH=. MECHGEN_TIER=compiled python3 benchmarks/device_cuda.py --static [--old]
        (the same force table at level "static": sweep_fast_statics in the kernel;
        --old: beside the path that brought every point back to the host)
    NUMBA_ENABLE_CUDASIM=1 PYTHONPATH=. python3 benchmarks/device_cuda.py --forces-sim
        (the force part, both levels, at 8 designs × 40 times on numba's simulator)
"""
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.dirname(HERE))

import numpy as np  # noqa: E402

if not hasattr(np, "row_stack"):
    # the device image's numba-cuda (0.68's) still registers np.row_stack, which numpy 2.5
    # removed: its first kernel compile fails without this alias
    np.row_stack = np.vstack

import bench_cuda  # noqa: E402


def forces(designs=10_000, times=1000, level="dynamic"):
    """backend="cuda" against backend="cpu" for reduce= on the crank driver at ``level``
    ("dynamic", or "static": sweep_fast_statics in the kernel)."""
    import mechgen
    mech = mechgen.load(os.path.join(os.path.dirname(HERE), "generated",
                                     "quick_return_forces.py"))
    kw = dict(params={"longitud": np.linspace(2.2, 3.5, designs)}, level=level,
              reduce=["crank driver", "X4"], on_fail="ignore")
    mech.sweep(0.0, 1.0, 8, backend="cuda", **dict(kw, params={"longitud": [2.5, 3.0]}))
    mech.sweep(0.0, 1.0, 8, **dict(kw, params={"longitud": [2.5, 3.0]}))
    out = {}
    for backend in ("cuda", "cpu"):
        t0 = time.perf_counter()
        out[backend] = mech.sweep(0.0, 1.0, times, backend=backend, **kw)
        out[backend + "_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    one = mech.sweep(0.0, 1.0, times, workers=1, **dict(kw, params={"longitud": np.linspace(
        2.2, 3.5, designs)[: designs // 8]}))
    single = (time.perf_counter() - t0) * 8     # an eighth of the designs, on one thread
    assert len(one.status)
    a, b = out["cuda"], out["cpu"]
    diff = {n: max(float(np.nanmax(np.abs(getattr(a.reduced(n), w) - getattr(b.reduced(n), w))))
                   for w in ("min", "max")) for n in kw["reduce"]}
    tdiff = max(float(np.nanmax(np.abs(getattr(a.reduced(n), w) - getattr(b.reduced(n), w))))
                for n in kw["reduce"] for w in ("tmin", "tmax"))
    scale = float(np.nanmax(np.abs(b.reduced("crank driver").max)))
    pts = designs * times
    print(f"{designs} designs x {times} times, {level}, reduce crank driver: cuda "
          f"{out['cuda_s']:.3g} s ({pts / out['cuda_s']:.3g} points/s), cpu "
          f"{out['cpu_s']:.3g} s ({pts / out['cpu_s']:.3g} points/s, {os.cpu_count()} cores), "
          f"cpu/cuda time {out['cpu_s'] / out['cuda_s']:.3g}; one thread {single:.3g} s "
          f"(all cores {single / out['cpu_s']:.3g}x faster); max|cuda-cpu| torque "
          f"{diff['crank driver']:.3g} on a scale of {scale:.3g}, X4 {diff['X4']:.3g}, "
          f"times {tdiff:.3g}; statuses differing {int(np.sum(a.status != b.status))}, "
          f"done differing {int(np.sum(a.done != b.done))}", flush=True)
    kernel(mech, a.t, a.P, kw["reduce"], level)
    mixed(mech, times=times, level=level)
    if "--old" in sys.argv:
        kept_points(mech, times, kw, out["cuda_s"], a)


def kept_points(mech, times, kw, new_s, new):
    """The same table the way it ran before the force kernel: the kinematic kernel keeps
    every point, the host solves the multipliers (the path level "static" still takes)."""
    import mechgen.runtime.tables.design as design
    keep = design.cuda_keeps_points
    design.cuda_keeps_points = lambda *a: True
    try:
        mech.sweep(0.0, 1.0, 8, backend="cuda", **dict(kw, params={"longitud": [2.5, 3.0]}))
        t0 = time.perf_counter()
        old = mech.sweep(0.0, 1.0, times, backend="cuda", **kw)
        old_s = time.perf_counter() - t0
    finally:
        design.cuda_keeps_points = keep
    d = float(np.nanmax(np.abs(old.reduced("crank driver").max - new.reduced("crank driver").max)))
    print(f"  every point back (before): {old_s:.3g} s; force kernel {new_s:.3g} s: "
          f"{old_s / new_s:.3g}x faster; max|old-new| torque {d:.3g}", flush=True)


def mixed(mech, designs=256, times=1000, level="dynamic"):
    """Designs that cannot turn (longitud above about 4: the host solves them) among ones
    that can, cuda against cpu: the largest relative difference of each design's torque
    extremes, of X4's and of the times, the statuses and solved counts that differ."""
    kw = dict(params={"longitud": np.linspace(1.0, 6.0, designs)}, level=level,
              reduce=["crank driver", "X4"], on_fail="ignore")
    a = mech.sweep(0.0, 1.0, times, backend="cuda", **kw)
    b = mech.sweep(0.0, 1.0, times, **kw)
    rel = max(float(np.nanmax(np.abs(getattr(a.reduced("crank driver"), w) -
                                     getattr(b.reduced("crank driver"), w)) /
                              np.maximum(np.abs(getattr(b.reduced("crank driver"), w)), 1.0)))
              for w in ("min", "max"))
    x4 = max(float(np.nanmax(np.abs(getattr(a.reduced("X4"), w) - getattr(b.reduced("X4"), w))))
             for w in ("min", "max"))
    tt = max(float(np.nanmax(np.abs(getattr(a.reduced(n), w) - getattr(b.reduced(n), w))))
             for n in ("crank driver", "X4") for w in ("tmin", "tmax"))
    print(f"  mixed: {designs} designs (longitud 1 to 6) x {times} times, {int(np.sum(~b.ok))} "
          f"failing: max relative |cuda-cpu| torque {rel:.3g}, X4 {x4:.3g}, times {tt:.3g}; "
          f"statuses differing {int(np.sum(a.status != b.status))}, done differing "
          f"{int(np.sum(a.done != b.done))}", flush=True)


def kernel(mech, ts, P, names, level="dynamic"):
    """The force kernel alone (mechgen.runtime.tables.cuda_forces.run_forces_cuda) at a few block
    sizes: its time and how many designs it left to the host."""
    from mechgen.runtime.tables.cuda_forces import run_forces_cuda
    from mechgen.runtime.tables.reduce import reduce_slots
    slots = reduce_slots(mech, names, 2 if level == "dynamic" else 0, level)[1]
    args = (mech, ts, P, mech.guess.copy(), mech.tol, mech.xtol, mech.maxit, slots)
    for tpb in (128, 64, 32):
        t0 = time.perf_counter()
        r = run_forces_cuda(*args, threads=tpb, level=level)
        dt = time.perf_counter() - t0
        print(f"  force kernel, {tpb} threads a block: {dt:.3g} s "
              f"({P.shape[0] * ts.shape[0] / dt:.3g} points/s), {r['host'].size} of "
              f"{P.shape[0]} designs left to the host", flush=True)


def main():
    runs = [(100_000, 1000, "position"), (100_000, 1000, "acceleration"),
            (1_000_000, 1000, "position")]
    if "--quick" in sys.argv:
        runs = runs[:2]
    if "--forces-sim" in sys.argv:
        forces(designs=8, times=40)
        forces(designs=8, times=40, level="static")
        return 0
    if "--static" in sys.argv:            # the static force table alone
        forces(level="static")
        return 0
    if "--forces" in sys.argv:
        runs = []
    for i, (designs, times, level) in enumerate(runs):
        t0 = time.perf_counter()
        r = bench_cuda.measure(designs, times, sample=300, rounds=3, level=level)
        if r is None:
            print("no CUDA GPU here")
            return 1
        print(f"{designs} designs x {times} times, {level}: generated "
              f"{r['gen_points_per_s']:.3g} points/s ({r['gen_s']:.3g} s), hand "
              f"{r['hand_points_per_s']:.3g} points/s ({r['hand_s']:.3g} s), "
              f"generated/hand time {r['ratio']:.3g}; second kernel for {r['second_pass']} "
              f"designs; compile {r['compile_gen_s']:.3g} s (hand {r['compile_hand_s']:.3g} s); "
              f"max|gen-hand| {r['max_diff_gen_hand']:.3g}; max|gen-CPU| "
              f"{r['max_diff_gen_cpu']:.3g} on {r['sampled']} designs, statuses differing "
              f"{r['status_mismatches']}, failed {r['failed']}; "
              f"wall {time.perf_counter() - t0:.1f} s", flush=True)
        if i == 1:
            forces()
    if not runs:
        forces()
    return 0


if __name__ == "__main__":
    sys.exit(main())
