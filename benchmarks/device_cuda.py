"""The GPU check a session runs when it is lent a device (one process, one script):
backend="cuda" design tables of the quick-return beside the hand-written kernel of
benchmarks/bench_cuda.py, at 10^5 designs × 10^3 times, positions and all levels, then
10^6 designs × 10^3 times in positions; each with its difference from the hand kernel
and from the CPU design table on a sample of designs.

    PYTHONPATH=. MECHGEN_TIER=compiled python3 benchmarks/device_cuda.py [--quick]
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


def main():
    runs = [(100_000, 1000, "position"), (100_000, 1000, "acceleration"),
            (1_000_000, 1000, "position")]
    if "--quick" in sys.argv:
        runs = runs[:2]
    for designs, times, level in runs:
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
    return 0


if __name__ == "__main__":
    sys.exit(main())
