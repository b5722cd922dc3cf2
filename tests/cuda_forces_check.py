"""Run by tests/test_cuda_forces.py in a subprocess with NUMBA_ENABLE_CUDASIM=1 (numba reads
it when first imported): force design tables reducing a driver's effort with
backend="cuda" (mechgen.runtime.tables.cuda_forces: the effort reduced in the kernel) on numba's
CUDA simulator, against backend="cpu" and against closed forms; printed as one JSON line.

    NUMBA_ENABLE_CUDASIM=1 PYTHONPATH=. python3 tests/cuda_forces_check.py [case ...]
"""
import json
import math
import os
import sys
import tempfile
import warnings

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests"))

# the quick-return with masses over 40 times (steps of 0.16 rad of the crank): longitud 1,
# 2, 2.5 go through the quick path; 3 needs the careful sweep (a hard point: the host);
# 4.5 and 6 cannot turn and fail in mid-sweep (the host too)
QR_LONGITUD = [1.0, 2.0, 2.5, 3.0, 4.5, 6.0]
QR_GPU = [0, 1, 2]
QR_REDUCE = ["crank driver", "X4", "Th3d"]
WHAT = ("min", "max", "tmin", "tmax")


def _table(mech, n, params, level, reduce=None, **extra):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")     # the designs that fail are meant to
        return mech.sweep(0.0, 1.0, n, params=params, level=level, reduce=reduce,
                          on_fail="ignore", **extra)


def _diff(a, b, rel=False):
    """max |a - b| (relative to max |b| with ``rel``); inf where NaN does not match NaN."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if not np.array_equal(np.isnan(a), np.isnan(b)):
        return math.inf
    d = float(np.max(np.abs(a - b)[~np.isnan(b)], initial=0.0))
    return d / max(float(np.nanmax(np.abs(b), initial=0.0)), 1e-300) if rel else d


def _compare(gpu, cpu, names, rel=("crank driver",)):
    out = {"status": gpu.status.reshape(-1).tolist(), "cpu_status": cpu.status.reshape(-1).tolist(),
           "done": gpu.done.tolist(), "cpu_done": cpu.done.tolist(), "kept_points": gpu.kept_points}
    for n in names:
        out["diff_" + n] = max(_diff(getattr(gpu.reduced(n), w), getattr(cpu.reduced(n), w),
                                     rel=n in rel and w in ("min", "max")) for w in WHAT)
    return out


class _Watch:
    """Records what the CUDA dispatch calls: run_forces_cuda's results; the kinematic
    kernels (run_table_cuda, every point back) and the host's multipliers of a GPU's
    points (design.reduce_threads) refused outright."""

    def __init__(self, refuse_points=True):
        import mechgen.runtime.tables.cuda as cu
        import mechgen.runtime.tables.cuda_forces as cf
        import mechgen.runtime.tables.design as design
        self.results = []
        self.saved = [(cu, "run_table_cuda", cu.run_table_cuda),
                      (design, "reduce_threads", design.reduce_threads),
                      (cf, "run_forces_cuda", cf.run_forces_cuda)]
        run = cf.run_forces_cuda

        def refuse(*a, **k):
            raise AssertionError("every point brought back to the host")

        def record(*a, **k):
            res = run(*a, **k)
            self.results.append({key: (v.tolist() if isinstance(v, np.ndarray) else v)
                                 for key, v in res.items()})
            return res
        if refuse_points:
            cu.run_table_cuda = refuse
            design.reduce_threads = refuse
        cf.run_forces_cuda = record

    def close(self):
        for mod, name, fn in self.saved:
            setattr(mod, name, fn)


def quick_return():
    """The quick-return with masses: reductions of a driver, a coordinate and a velocity
    on the GPU, the designs the quick path does not finish on the host."""
    import mechgen
    mech = mechgen.load(os.path.join(ROOT, "generated", "quick_return_forces.py"))
    params = {"longitud": QR_LONGITUD}
    cpu = _table(mech, 40, params, "dynamic", QR_REDUCE)
    watch = _Watch()
    try:
        gpu = _table(mech, 40, params, "dynamic", QR_REDUCE, backend="cuda")
    finally:
        watch.close()
    out = _compare(gpu, cpu, QR_REDUCE)
    res = watch.results
    out["calls"] = len(res)
    out["keys"] = sorted(res[0]) if res else []
    out["host"] = res[0]["host"] if res else None
    out["gpu_done"] = res[0]["done"] if res else None
    # the efforts of the full CPU table (every point, tab.driver): their extremes
    full = _table(mech, 40, params, "dynamic")
    tau = full.driver("crank driver")
    out["vs_full"] = max(_diff(gpu.reduced("crank driver").max, np.nanmax(tau, axis=1), True),
                         _diff(gpu.reduced("crank driver").min, np.nanmin(tau, axis=1), True))
    return out


def weak_pivots():
    """Every point's multipliers marked not to be used (SING_RTOL above the fused path's
    verdicts, 0 or 1, in a fresh twin): every design goes to the host, the same numbers."""
    import mechgen
    import mechgen.runtime.tables.cuda_forces as cf
    mech = mechgen.load(os.path.join(ROOT, "generated", "quick_return_forces.py"))
    cf._TWINS.clear()                   # a fresh twin, dropped afterwards
    ns = cf.twin(cf.numba_module(mech))
    ns["SING_RTOL"] = 2.0               # read by the device code when first launched
    run = cf.run_forces_cuda
    got = []

    def record(*a, **k):
        res = run(*a, **k)
        got.append(res["host"].tolist())
        return res
    cf.run_forces_cuda = record
    try:
        params = {"longitud": QR_LONGITUD[:3]}
        gpu = _table(mech, 40, params, "dynamic", QR_REDUCE, backend="cuda")
    finally:
        cf.run_forces_cuda = run
        cf._TWINS.clear()
    cpu = _table(mech, 40, params, "dynamic", QR_REDUCE)
    out = _compare(gpu, cpu, QR_REDUCE)
    out["host"] = got[0] if got else None
    return out


def static():
    """Level "static": the kernel runs sweep_fast_statics and reduces the driver (no point
    back), the designs it leaves solved on the host; against the CPU table."""
    import mechgen
    mech = mechgen.load(os.path.join(ROOT, "generated", "quick_return_forces.py"))
    params = {"longitud": QR_LONGITUD}
    names = ["crank driver", "X4"]
    cpu = _table(mech, 40, params, "static", names)
    watch = _Watch()
    try:
        gpu = _table(mech, 40, params, "static", names, backend="cuda")
    finally:
        watch.close()
    out = _compare(gpu, cpu, names)
    res = watch.results
    out["calls"] = len(res)
    out["host"] = res[0]["host"] if res else None
    full = _table(mech, 40, params, "static")
    tau = full.driver("crank driver")
    out["vs_full"] = max(_diff(gpu.reduced("crank driver").max, np.nanmax(tau, axis=1), True),
                         _diff(gpu.reduced("crank driver").min, np.nanmin(tau, axis=1), True))
    return out


def static_unfused():
    """A static table of a module without sweep_fast_statics (method "full": no quick
    path): the kernel keeps the points, the host solves λ."""
    import mechgen
    mech = mechgen.load(os.path.join(ROOT, "generated", "quick_return_forces.py"))
    params = {"longitud": [2.0, 3.0]}
    names = ["crank driver", "X4"]
    watch = _Watch(refuse_points=False)
    try:
        gpu = _table(mech, 20, params, "static", names, backend="cuda", method="full")
    finally:
        watch.close()
    out = _compare(gpu, _table(mech, 20, params, "static", names, method="full"), names)
    out["calls"] = len(watch.results)
    return out


def outputs():
    """The quick-return with masses and an output (the slider's far pin's x: X4 + 2, its
    guide level) reduced beside the driver on the GPU."""
    import mechgen
    from mechgen import location
    from conftest import example_model
    m = example_model("quick_return_forces")
    m.output("tip_x", location(m["deslizadera"][2])[0])
    mech = mechgen.compile(m, outdir=tempfile.mkdtemp(prefix="cufo"), tier="python")
    params = {"longitud": QR_LONGITUD[1:4]}
    names = ["crank driver", "tip_x", "tip_xd", "X4", "X4d"]
    watch = _Watch()
    try:
        gpu = _table(mech, 40, params, "dynamic", names, backend="cuda")
    finally:
        watch.close()
    out = _compare(gpu, _table(mech, 40, params, "dynamic", names), names)
    out["host"] = watch.results[0]["host"] if watch.results else None
    out["tip_vs_X4"] = max(_diff(getattr(gpu.reduced("tip_x"), w),
                                 getattr(gpu.reduced("X4"), w) + (2.0 if w in ("min", "max") else 0.0))
                           for w in WHAT)
    out["tipd_vs_X4d"] = max(_diff(getattr(gpu.reduced("tip_xd"), w), getattr(gpu.reduced("X4d"), w))
                             for w in WHAT)
    return out


def slider_crank():
    """The slider-crank of tests/test_forces (its multipliers not written out: no fused
    quick path, the kernel keeps the points and the host solves λ), the slider's mass
    varied: the peak torque per design against the closed form (its power form,
    tests/test_force_tables.torque) and the CPU table."""
    import mechgen
    from test_force_tables import PERIOD, torque
    from test_forces import slider_crank as model
    mech = mechgen.compile(model(), outdir=tempfile.mkdtemp(prefix="cufo"), tier="python")
    masses = [0.5, 2.0, 5.5]
    names = ["crank driver", "X4"]
    kw = dict(params={"mass4": masses}, level="dynamic", reduce=names, on_fail="ignore")
    watch = _Watch(refuse_points=False)
    try:
        gpu = mech.sweep(0.0, PERIOD, 36, backend="cuda", **kw)
    finally:
        watch.close()
    cpu = mech.sweep(0.0, PERIOD, 36, **kw)
    out = _compare(gpu, cpu, names)
    out["gpu_calls"] = len(watch.results)
    ts = gpu.t
    tau = np.array([[torque(t, mass) for t in ts] for mass in masses])
    red = gpu.reduced("crank driver")
    out["torque_vs_closed"] = max(_diff(red.max, tau.max(axis=1), True),
                                  _diff(red.min, tau.min(axis=1), True))
    out["tmax_vs_closed"] = _diff(red.tmax, ts[np.argmax(tau, axis=1)])
    return out


def main():
    from numba.core import config
    assert config.ENABLE_CUDASIM, "run with NUMBA_ENABLE_CUDASIM=1"
    cases = {"quick_return": quick_return, "weak_pivots": weak_pivots, "static": static,
             "static_unfused": static_unfused,
             "outputs": outputs, "slider_crank": slider_crank}
    names = sys.argv[1:] or list(cases)
    print(json.dumps({n: cases[n]() for n in names}))


if __name__ == "__main__":
    main()
