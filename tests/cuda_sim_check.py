"""Run by tests/test_cuda_sim.py in a subprocess with NUMBA_ENABLE_CUDASIM=1 (numba reads
it when first imported): the CUDA design tables of mechgen.runtime.tables.cuda on numba's CUDA
simulator against the CPU design table (mech.sweep(..., params=...)), printed as one JSON
line of differences."""
import inspect
import json
import os
import sys
import warnings

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

CASES = {
    # (steps the fast sweep takes: less than BRANCH_TURN of the crank) a design that
    # cannot assemble at t = 0 (longitud 6, anguloI -0.8), one that
    # solves, and the seed's own longitud 3
    "quick_return": ((0.0, 0.5, 11), {"longitud": [2.0, 3.0, 6.0], "anguloI": [-0.8, 0.0]},
                     ["X4", "X4d", "Th3", "stroke_x", "stroke_xd"], ("position", "velocity")),
    # a crank too long to turn: fails in mid-sweep (a = 3, b = 2.5); a = 1.5 passes a
    # singular configuration (status THROUGH_SINGULAR); b = 0.5 cannot assemble at all
    "fourbar": ((0.0, 0.5, 11), {"a": [0.8, 1.5, 3.0], "b": [2.5, 0.5]}, ["Th3", "Th4d", "X3dd"],
                ("acceleration",)),
}
ORDER = {"position": 0, "velocity": 1, "acceleration": 2}


def _cpu_table(mech, span, params, level, **extra):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")     # the designs that fail are meant to
        return mech.sweep(*span, params=params, level=level, **extra)


def _rows(tab):
    """The CPU table's per-point STATUS rows (design, time, columns; STATUS_CODE first)."""
    rows = getattr(tab, "STATUS", None)
    return tab.INFO if rows is None else rows


def _cpu_status(tab, nt):
    """The CPU table's per-design status: its own where it has one, else the rule of
    mechgen.runtime.tables.cuda.design_status from its per-point STATUS rows."""
    from mechgen.runtime.tables.cuda import design_status
    own = getattr(tab, "status", None)
    if own is not None:
        return np.asarray(own).reshape(-1).astype(np.int64)
    return design_status(_rows(tab), tab.done, nt)


def _starts(mech, tab):
    """Each design's start as the CPU table's (the guess's mode carried to its
    parameters: mechgen.runtime.tables.starts; the guess itself where it cannot be)."""
    from mechgen.runtime.tables.starts import design_starts
    return design_starts(mech, tab.t, tab.P, mech.tol, mech.maxit, 0)[0]


def _needs(mech, name):
    from mechgen.runtime.quantity import lookup
    kind, k, order = lookup(mech, name)
    return order if kind == "q" else mech.output_orders[k] + order


def compare(name, span, params, quantities, levels):
    import mechgen
    from mechgen.protocol import STATUS_CODE
    from mechgen.runtime.tables.cuda import quantity_slots, run_table_cuda
    mech = mechgen.load(os.path.join(ROOT, "generated", name + ".py"))
    out = {}
    for level in levels:
        lev = ORDER[level]
        tab = _cpu_table(mech, span, params, level)
        q0 = _starts(mech, tab)
        nt = len(tab.t)
        gpu = run_table_cuda(mech, tab.t, tab.P, q0, lev, mech.tol, mech.maxit)
        diff = 0.0
        rows_same = True
        for d in range(len(tab)):
            k = int(tab.done[d])
            rows = min(k + 1, nt)           # the failed row (the last configuration reached)
            pairs = [(gpu["Q"], tab.Q)] + [(gpu[key], getattr(tab, key))
                                           for key in ("QD", "QDD")[:lev]]
            for a, b in pairs:
                diff = max(diff, float(np.max(np.abs(a[d, :rows] - b[d, :rows]))))
            rows_same &= bool(np.array_equal(gpu["STATUS"][d, :rows, 0],
                                             _rows(tab)[d, :rows, STATUS_CODE]))
        below_none = all(gpu[key] is None for key in ("QD", "QDD")[lev:])
        names = [q for q in quantities if _needs(mech, q) <= lev]
        slots = quantity_slots(mech, names, lev)
        red = run_table_cuda(mech, tab.t, tab.P, q0, level, mech.tol, mech.maxit, slots)
        rdiff = 0.0
        nan_ok = True
        for i, q in enumerate(names):
            vals = tab[q].reshape(len(tab), nt)        # NaN where a design did not solve
            for d in range(len(tab)):
                k = int(tab.done[d])
                for key, fn in (("min", np.argmin), ("max", np.argmax)):
                    got, when = red[key][d, i], red["t" + key][d, i]
                    if k == 0:                  # solved no time: NaN, never numbers
                        nan_ok &= bool(np.isnan(got) and np.isnan(when))
                        continue
                    j = int(fn(vals[d, :k]))    # over the times it solved (first extreme)
                    rdiff = max(rdiff, abs(got - vals[d, j]), abs(when - tab.t[j]))
        r = dict(diff=diff, rows_same=rows_same, below_none=below_none,
                 second_pass=gpu["second_pass"], designs=len(tab),
                 status=gpu["status"].tolist(), cpu_status=_cpu_status(tab, nt).tolist(),
                 reduce_status=red["status"].tolist(), done=gpu["done"].tolist(),
                 cpu_done=tab.done.tolist(), reduce_done=red["done"].tolist(),
                 reduce_diff=float(rdiff), nan_ok=nan_ok, names=red["names"], asked=names,
                 failed=int(np.sum(tab.done < nt)),
                 partial=int(np.sum((tab.done > 0) & (tab.done < nt))))
        r["dispatch"] = dispatch(mech, span, params, level, tab)
        if name == "fourbar":
            r["full_same"] = full_method(mech, span, params, level)
        out[level] = r
    return out


def full_method(mech, span, params, level):
    """method="full" (no sweep_fast: every design goes to the second kernel) as on the CPU."""
    from mechgen.runtime.tables.cuda import run_table_cuda
    cpu = _cpu_table(mech, span, params, level, method="full")
    gpu = run_table_cuda(mech, cpu.t, cpu.P, _starts(mech, cpu), level, mech.tol, mech.maxit,
                         method="full")
    ok = gpu["second_pass"] == len(cpu) and np.array_equal(gpu["done"], cpu.done) and \
        np.array_equal(gpu["status"], _cpu_status(cpu, len(cpu.t)))
    for d in range(len(cpu)):
        k = min(int(cpu.done[d]) + 1, len(cpu.t))
        ok = ok and np.allclose(gpu["Q"][d, :k], cpu.Q[d, :k], rtol=0, atol=1e-12)
    return bool(ok)


def dispatch(mech, span, params, level, cpu):
    """Where mech.sweep takes backend= (the design-table dispatch): its CUDA table equals
    the CPU one; None where this mechgen has no such argument."""
    if "backend" not in inspect.signature(mech.sweep).parameters:
        return None
    tab = _cpu_table(mech, span, params, level, backend="cuda")
    ok = np.array_equal(tab.done, cpu.done)
    for d in range(len(cpu)):
        k = int(cpu.done[d])
        ok = ok and np.allclose(tab.Q[d, :k], cpu.Q[d, :k], rtol=0, atol=1e-12)
    return bool(ok)


def python_tier():
    """A mechanism answering in the plain-Python tier: its CUDA table is translated from
    the same file's numba functions, and equals the compiled tier's."""
    import mechgen
    from mechgen.runtime.tables.cuda import run_table_cuda
    path = os.path.join(ROOT, "generated", "quick_return.py")
    plain = mechgen.load(path, tier="python")
    P = np.tile(plain.p, (2, 1))
    P[1, 0] = 2.0
    ts = np.linspace(0.0, 0.2, 3)
    got = run_table_cuda(plain, ts, P, plain.guess, 0, plain.tol, plain.maxit)
    want = run_table_cuda(mechgen.load(path, tier="compiled"), ts, P, plain.guess, 0,
                          plain.tol, plain.maxit)
    return {"tier": plain.tier, "same": bool(np.array_equal(got["Q"], want["Q"]) and
                                             np.array_equal(got["done"], want["done"])),
            "done": got["done"].tolist()}


def contract():
    """mech.sweep(..., params=..., backend="cuda") end to end (the design-table dispatch of
    mechgen.runtime.tables.backends into mechgen.runtime.tables.cuda, the real kernels on the simulator)
    against backend="cpu": full tables and reductions, with a design that cannot turn
    (longitud 6 at velocidad 2π: it fails in mid-sweep) among them."""
    import math
    import mechgen
    mech = mechgen.load(os.path.join(ROOT, "generated", "quick_return.py"))
    span = (0.0, 1.0, 8)
    params = {"longitud": [1.0, 2.25, 3.5, 6.0], "velocidad": [2 * math.pi, 3.0]}
    cpu = _cpu_table(mech, span, params, "velocity", on_fail="ignore")
    gpu = _cpu_table(mech, span, params, "velocity", on_fail="ignore", backend="cuda")
    nt = len(cpu.t)
    done = cpu.done.reshape(cpu.shape)
    out = {"ok": cpu.ok.tolist(), "done": done.tolist(),
           "status_same": bool(np.array_equal(gpu.status, cpu.status)),
           "ok_same": bool(np.array_equal(gpu.ok, cpu.ok)),
           "done_same": bool(np.array_equal(gpu.done, cpu.done))}

    def diff(a, b):
        """max |a - b| where b has numbers; inf where NaN does not match NaN."""
        a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        if not np.array_equal(np.isnan(a), np.isnan(b)):
            return math.inf
        return float(np.max(np.abs(a - b)[~np.isnan(b)], initial=0.0))

    for name in ("X4", "X4d", "Th3", "stroke_xd"):
        out["diff_" + name] = diff(gpu[name], cpu[name])
    # past the failed time of a failed design: NaN, never numbers; before it: its points
    bad = ~cpu.ok
    out["failed_nan_after"] = bool(all(np.all(np.isnan(gpu["X4"][i][int(done[i]):])) and
                                       np.all(np.isfinite(gpu["X4"][i][:int(done[i])]))
                                       for i in zip(*np.nonzero(bad)))) and bool(bad.any())
    out["failed_partial"] = bool(any(0 < int(done[i]) < nt for i in zip(*np.nonzero(bad))))
    names = ["X4", "stroke_x"]
    red_cpu = _cpu_table(mech, span, params, "velocity", on_fail="ignore", reduce=names)
    red_gpu = _cpu_table(mech, span, params, "velocity", on_fail="ignore", reduce=names,
                         backend="cuda")
    out["reduce_status_same"] = bool(np.array_equal(red_gpu.status, red_cpu.status))
    out["reduce_done_same"] = bool(np.array_equal(red_gpu.done, red_cpu.done))
    out["reduce_diff"] = max(diff(getattr(red_gpu.reduced(n), w), getattr(red_cpu.reduced(n), w))
                             for n in names for w in ("min", "max", "tmin", "tmax"))
    # and the reductions are those of the full table (the first extreme, over solved times)
    full = cpu["X4"]
    out["reduce_vs_full"] = diff(red_gpu.reduced("X4").max, np.nanmax(full, axis=-1))
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
    names = sys.argv[1:] or list(CASES) + ["bench", "python_tier"]
    extra = {"bench": bench, "python_tier": python_tier, "contract": contract}
    print(json.dumps({n: extra[n]() if n in extra else compare(n, *CASES[n]) for n in names}))


if __name__ == "__main__":
    main()
