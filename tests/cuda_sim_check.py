"""Run by tests/test_cuda_sim.py in a subprocess with NUMBA_ENABLE_CUDASIM=1 (numba reads
it when first imported): the CUDA design tables of mechgen.runtime.cuda on numba's CUDA
simulator against the CPU design table, printed as one JSON line of differences."""
import json
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

CASES = {
    # a design that cannot assemble at t = 0 (longitud 6, anguloI -0.8), one that
    # solves, and the seed's own longitud 3
    "quick_return": ((0.0, 0.5, 6), {"longitud": [2.0, 3.0, 6.0], "anguloI": [-0.8, 0.0]},
                     ["X4", "X4d", "Th3dd", "stroke_x", "stroke_xdd"], ("position", "acceleration")),
    # a crank too long to turn: fails in mid-sweep (a = 3, b = 2.5); a = 1.5 passes a
    # singular configuration (status THROUGH_SINGULAR); b = 0.5 cannot assemble at all
    "fourbar": ((0.0, 0.5, 6), {"a": [0.8, 1.5, 3.0], "b": [2.5, 0.5]}, ["Th3", "Th4d", "X3dd"],
                ("acceleration",)),
}


def compare(name, span, params, quantities, levels):
    import mechgen
    from mechgen.runtime.cuda import (as_design_arrays, design_status, quantity_slots,
                                      run_table_cuda)
    from mechgen.runtime.design import DesignTable
    mech = mechgen.load(os.path.join(ROOT, "generated", name + ".py"))
    out = {}
    for level in levels:
        tab = mech.design_sweep(*span, params, level=level, on_fail="ignore")
        q0 = mech._start(None)
        gpu = run_table_cuda(mech, tab.t, tab.P, q0, level, mech.tol, mech.maxit)
        nt = len(tab.t)
        diff = 0.0
        info_same = True
        for d in range(len(tab)):
            k = int(tab.done[d])
            arrays = [(gpu["Q"], tab.Q)]
            if level == "acceleration":
                arrays += [(gpu["QD"], tab.QD), (gpu["QDD"], tab.QDD)]
            for a, b in arrays:
                if k:
                    diff = max(diff, float(np.max(np.abs(a[d, :k] - b[d, :k]))))
            rows = min(k + 1, nt)               # the failed row's status too
            info_same &= bool(np.array_equal(gpu["INFO"][d, :rows], tab.INFO[d, :rows]))
        cpu_status = design_status(tab.INFO, tab.done, nt)
        # the GPU's arrays as a DesignTable: the same quantities, NaN where unsolved
        gtab = DesignTable(mech, tab.names, tab.axes, tab.t, tab.P,
                           *as_design_arrays(gpu, level), level)
        table_same = all(np.allclose(gtab[q], tab[q], rtol=0, atol=1e-12, equal_nan=True)
                         for q in quantities if level == "acceleration" or not q.endswith("d"))
        names = [q for q in quantities if level == "acceleration" or
                 not q.endswith("d")]
        slots = quantity_slots(mech, names, level)
        red = run_table_cuda(mech, tab.t, tab.P, q0, level, mech.tol, mech.maxit,
                             reduce_slots=slots)
        rdiff = 0.0
        nan_ok = True
        for i, q in enumerate(names):
            vals = tab[q].reshape(len(tab), nt)
            ok = tab.done == nt
            for key, fn, arg in (("min", np.min, np.argmin), ("max", np.max, np.argmax)):
                got = red[key][:, i]
                nan_ok &= bool(np.all(np.isnan(got[~ok])))
                nan_ok &= bool(np.all(np.isnan(red["t" + key][~ok, i])))
                if ok.any():
                    rdiff = max(rdiff, float(np.max(np.abs(got[ok] - fn(vals[ok], axis=1)))))
                    want_t = tab.t[arg(vals[ok], axis=1)]
                    rdiff = max(rdiff, float(np.max(np.abs(red["t" + key][ok, i] - want_t))))
        out[level] = dict(diff=diff, info_same=info_same, second_pass=gpu["second_pass"],
                          table_same=bool(table_same),
                          designs=len(tab),
                          status=gpu["status"].tolist(), cpu_status=cpu_status.tolist(),
                          reduce_status=red["status"].tolist(),
                          done=gpu["done"].tolist(), cpu_done=tab.done.tolist(),
                          reduce_done=red["done"].tolist(), reduce_diff=rdiff, nan_ok=nan_ok,
                          failed=int(np.sum(tab.done < nt)), names=red["names"])
    return out


def bench():
    """benchmarks/bench_cuda.py's measure() at tiny sizes: it runs, and agrees."""
    sys.path.insert(0, os.path.join(ROOT, "benchmarks"))
    import bench_cuda
    r = bench_cuda.measure(designs=3, times=30, sample=3, rounds=1)
    return {k: r[k] for k in ("max_diff_gen_hand", "max_diff_gen_cpu", "status_mismatches",
                              "failed", "points", "simulated")}


def main():
    from numba.core import config
    assert config.ENABLE_CUDASIM, "run with NUMBA_ENABLE_CUDASIM=1"
    names = sys.argv[1:] or list(CASES) + ["bench"]
    print(json.dumps({n: bench() if n == "bench" else compare(n, *CASES[n]) for n in names}))


if __name__ == "__main__":
    main()
