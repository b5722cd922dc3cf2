"""Whether a GPU design table's kernels come from numba's on-disk cache in a later
process (mechgen.runtime.tables.cuda_twin.source_file): run it twice, each in a fresh process;
the first compiles the kinematic and the force kernels (tens of seconds each), the second
should load them (about a second).

    PYTHONPATH=. MECHGEN_TIER=compiled python3 benchmarks/cuda_cache_check.py first
    PYTHONPATH=. MECHGEN_TIER=compiled python3 benchmarks/cuda_cache_check.py second
"""
import os
import sys
import time

import numpy as np

if not hasattr(np, "row_stack"):    # numba-cuda 0.2x's overload of np.row_stack (cuda.py)
    np.row_stack = np.vstack

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)


def main():
    import mechgen
    label = sys.argv[1] if len(sys.argv) > 1 else "run"
    designs = {"longitud": np.linspace(2.2, 3.5, 1000)}
    mech = mechgen.load(os.path.join(ROOT, "generated", "quick_return.py"))
    t0 = time.perf_counter()
    tab = mech.sweep(0.0, 1.0, 200, params=designs, backend="cuda", reduce=["X4"])
    t1 = time.perf_counter()
    forces = mechgen.load(os.path.join(ROOT, "generated", "quick_return_forces.py"))
    ftab = forces.sweep(0.0, 1.0, 200, params=designs, level="dynamic", backend="cuda",
                        reduce=["crank driver"], on_fail="ignore")
    t2 = time.perf_counter()
    print(f"{label}: first kinematic table {t1 - t0:.2f} s (X4 max {np.nanmax(tab.reduced('X4').max):.6g}), "
          f"first force table {t2 - t1:.2f} s (torque max "
          f"{np.nanmax(ftab.reduced('crank driver').max):.6g})", flush=True)


if __name__ == "__main__":
    main()
