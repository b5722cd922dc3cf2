"""Force design tables whose reductions run on the GPU: ``reduce=["crank driver", ...]``
at level "dynamic" or "static" with ``backend="cuda"``, the driver's effort reduced while
each design is swept, so that no point leaves the GPU.

The module's fused quick path ``sweep_fast_forces`` (present where its FORCE_FUSED is
True: the multipliers written out in the sweep's own step) is translated with the rest of
the CUDA twin (mechgen.runtime.tables.cuda_twin): its LAM, FACTORS and FPIV rows are indexed
through the row mask like Q, so the reducing kernel keeps one thread-local row, and its
hook ``_cu_point_forces`` sees each accepted point once, as ``_cu_point`` does for
sweep_fast. A driver slot's value at a point is the driver's effort Σ λ_r ∂Φ_r/∂f from
that point's LAM and FACTORS rows (mechgen.runtime.forces.points.efforts); coordinate and
output slots are those of the kinematic kernels.

A static table runs the module's sweep_fast_statics (where it is written: the multipliers
at q̇ = q̈ = 0 after the position code) the same way, with the same hook; its kernel's
one-row QD and QDD make it take the derivatives at every point too (the position sweep's
predictor, which reads none, is for a QD without rows), which changes no position.

One kernel runs (one CUDA thread per design): sweep_fast_forces over every time. A design
it does not take to the end (a hard point: sweep() would go on), or that meets a point
whose multipliers must not be used (a block pivot below SING_RTOL, or a λ not finite:
the host solves those by the SVD, mechgen.runtime.tables.reduce.repaired) is marked ``done`` -1;
the caller (mechgen.runtime.tables.backends.run_cuda) computes those designs alone on the CPU
table and merges them in. Every other design's numbers are those of the CPU table,
whose sweep_designs_forces takes the same quick path with the same source.

numba.cuda is imported only through mechgen.runtime.tables.cuda, when a table is asked for.
"""
from __future__ import annotations

import numpy as np

from ...errors import MechgenError
from ...protocol import FUSED_PATHS, LEVEL
from ..forces.points import driver_rows
from .reduce import DRIVER
from .cuda import OUTPUT, STATUS_COLUMNS, THREADS, SIM_THREADS, flat_slots, numba_module, \
    require_cuda, simulated, table_inputs
from .cuda_twin import ROOTS, build_twin

# force level -> (the module's fused quick path, forces.lookup.FUSED_PATHS, the kernel
# that runs it: sweep_fast_forces -> _cu_forces_reduce)
KERNELS = {level: (fn, "_cu_" + fn.replace("sweep_fast_", "") + "_reduce")
           for level, (_, _, fn) in FUSED_PATHS.items()}
_TWINS = {}                     # (id(module), max_registers) -> (module, twin namespace)

# The hook, the per-design driver and the kernel, compiled into the twin's namespace.
SUPPORT = '''
_CU_NFAC = max(1, len(DRIVER_ROWS))


def _cu_point_forces(k, ts, Q, QD, QDD, S, LAM, FAC, FPIV, p, ctx):
    \"\"\"The hook of sweep_fast_forces() (as _cu_point for sweep_fast): the branch
    status, the running extremes of the slots (a negative slot -1 - j: the effort of
    the driver of row j of DRV), and F[2] = 1 where the point's multipliers must not be
    used (FPIV below SING_RTOL, a λ or an effort not finite): the host solves the design.\"\"\"
    SL, nsl, R, F, OUT, nord, mask, DRV = ctx
    row = k & mask
    bad = 0.0
    for j in range(N_EQS):
        bad += LAM[row, j] * 0.0
    if not (FPIV[row] >= SING_RTOL and bad == 0.0):
        F[2] = 1
    s = int(S[row, STATUS_CODE])
    if s == JUMP:
        F[0] = JUMP
    elif s == THROUGH_SINGULAR and F[0] != JUMP:
        F[0] = THROUGH_SINGULAR
    t = ts[k]
    if nord >= 1:
        outputs(Q[row], QD[row], QDD[row], t, p, OUT[0])
    if nord >= 2:
        outputs_d(Q[row], QD[row], QDD[row], t, p, OUT[1])
    if nord >= 3:
        outputs_dd(Q[row], QD[row], QDD[row], t, p, OUT[2])
    first = F[1] == 0
    width = (DRV.shape[1] - 1) // 2
    for i in range(nsl):
        c = SL[i]
        if c < 0:
            j = -1 - c
            v = 0.0
            for r in range(DRV[j, 0]):
                v += LAM[row, DRV[j, 1 + r]] * FAC[row, DRV[j, 1 + width + r]]
            if not v * 0.0 == 0.0:
                F[2] = 1
        else:
            v = _cu_value(c, row, Q, QD, QDD, OUT)
        if first or v < R[0, i]:
            R[0, i] = v
            R[2, i] = t
        if first or v > R[1, i]:
            R[1, i] = v
            R[3, i] = t
    F[1] = 1
'''

# The reducing kernel, once per fused sweep it runs (the names replaced)
KERNEL_SOURCE = '''
def _cu_forces_reduce(ts, Q0, P, tol, xtol, maxit, SL, nsl, nord, DRV, R, DONE, DSTATUS):
    \"\"\"One thread per design: sweep_fast_forces() over every time, one thread-local
    row of each array, the reductions R[design] = (min, max, tmin, tmax) of the slots SL.
    DONE[d]: the count of times, or -1 where the host must solve the design (the quick
    path stopped early, or a point's multipliers are not to be used).\"\"\"
    d = cuda.grid(1)
    if d >= P.shape[0]:
        return
    F = _cu_flags(cuda.local.array(3, _cu_i8))
    OUT = cuda.local.array((3, _CU_NOUT), _cu_f8)
    Q = cuda.local.array((1, N_COORDS), _cu_f8)
    QD = cuda.local.array((1, N_COORDS), _cu_f8)
    QDD = cuda.local.array((1, N_COORDS), _cu_f8)
    S = cuda.local.array((1, _CU_SCOLS), _cu_i2)
    LAM = cuda.local.array((1, N_EQS), _cu_f8)
    FAC = cuda.local.array((1, _CU_NFAC), _cu_f8)
    FPIV = cuda.local.array(1, _cu_f8)
    _cu_row(Q, QD, QDD, S)
    for j in range(N_EQS):
        LAM[0, j] = 0.0
    for j in range(_CU_NFAC):
        FAC[0, j] = 0.0
    FPIV[0] = 0.0
    ctx = (SL, nsl, R[d], F, OUT, nord, 0, DRV)
    n = sweep_fast_forces(ts, Q0[d], P[d], tol, xtol, maxit, Q, QD, QDD, S, LAM, FAC, FPIV, ctx)
    if n == ts.shape[0]:
        _cu_point_forces(n - 1, ts, Q, QD, QDD, S, LAM, FAC, FPIV, P[d], ctx)
    if n == ts.shape[0] and F[2] == 0:
        DONE[d] = n
        DSTATUS[d] = F[0]
    else:
        DONE[d] = -1
'''


def fused_levels(module):
    """The force levels whose fused quick path ``module`` has (its FUSED_PATHS flag)."""
    return [level for level in KERNELS if getattr(module, FUSED_PATHS[level][0], False)]


def twin(module, max_registers=None, cuda=None):
    """The CUDA twin of ``module`` with its fused quick paths and their kernels (``cuda``:
    numba.cuda, checked for a device where not given; benchmarks/cuda_ptx_check.py gives
    it to compile without one)."""
    key = (id(module), max_registers)
    hit = _TWINS.get(key)
    if hit is not None and hit[0] is module:
        return hit[1]
    cuda = cuda or require_cuda()
    paths = [KERNELS[level] for level in fused_levels(module)]
    support = SUPPORT + "".join(
        "\n\n" + KERNEL_SOURCE.replace("_cu_forces_reduce", kernel)
        .replace("sweep_fast_forces", fn) for fn, kernel in paths)
    ns = build_twin(module, cuda, STATUS_COLUMNS, max_registers,
                    roots=ROOTS + tuple(fn for fn, _ in paths), support=support,
                    kernels=tuple(kernel for _, kernel in paths))
    _TWINS[key] = (module, ns)
    return ns


def device_slots(mech, slots):
    """(flat, nord, DRV, names): the kernel's slot codes (a coordinate or output as
    mechgen.runtime.tables.cuda.flat_slots numbers it; -1 - j for a driver, described by row j
    of DRV: [count of rows, its rows of λ, their columns in FACTORS]), how many output
    orders to evaluate, and each slot's name."""
    arr = np.asarray(slots, dtype=np.int64)
    module = mech.module
    kin = arr[:, 0] != DRIVER
    flat = np.zeros(arr.shape[0], dtype=np.int64)
    nord = 0
    if kin.any():
        flat[kin], nord = flat_slots(mech, arr[kin], LEVEL["acceleration"])
    by_label = driver_rows(module)
    drivers, names = [], []
    for j, (kind, index, _) in enumerate(arr.tolist()):
        if kind != DRIVER:
            base = (mech.coordinates if kind != OUTPUT else mech.outputs)[index]
            names.append(base + "d" * int(arr[j, 2]))
            continue
        label = module.CONSTRAINTS[index][2]
        rows, cols = by_label[label]
        if cols is None:
            raise MechgenError(f"driver {label!r}: its effort is not defined (no driver row)")
        flat[j] = -1 - len(drivers)
        drivers.append((rows, cols))
        names.append(label)
    width = max(len(r) for r, _ in drivers)
    DRV = np.zeros((len(drivers), 1 + 2 * width), dtype=np.int64)
    for j, (rows, cols) in enumerate(drivers):
        DRV[j, 0] = len(rows)
        DRV[j, 1:1 + len(rows)] = rows
        DRV[j, 1 + width:1 + width + len(cols)] = cols
    return flat, nord, DRV, names


def run_forces_cuda(mech, ts, P, q0, tol, xtol, maxit, slots, threads=None,
                    max_registers=None, level="dynamic") -> dict:
    """The reductions of a force table at ``level`` ("dynamic" or "static") on the GPU
    (see the module docstring):
    ``min``, ``max``, ``tmin``, ``tmax`` (designs, slots; NaN for the designs left to
    the host), ``done`` (designs,) int64 (the count of times, -1 where the host must
    solve the design), ``status`` (designs,) int64 (meaningful where done >= 0), ``host``
    (the indices of the designs left to the host), ``slots`` and their ``names``. No
    point comes back: only these per-design arrays."""
    cuda = require_cuda()
    ts, P, Q0 = table_inputs(mech, ts, P, q0)
    flat, nord, DRV, names = device_slots(mech, slots)
    ns = twin(numba_module(mech), max_registers)
    D, nsl = P.shape[0], flat.size
    tpb = threads or (SIM_THREADS if simulated() else THREADS)
    d_R = cuda.to_device(np.full((D, 4, nsl), np.nan))
    d_done = cuda.to_device(np.zeros(D, dtype=np.int64))
    d_status = cuda.to_device(np.zeros(D, dtype=np.int64))
    ns[KERNELS[level][1]][-(-D // tpb), tpb](cuda.to_device(ts), cuda.to_device(Q0), cuda.to_device(P),
                                  float(tol), float(xtol), int(maxit), cuda.to_device(flat),
                                  nsl, nord, cuda.to_device(DRV), d_R, d_done, d_status)
    done = d_done.copy_to_host()
    R = d_R.copy_to_host()
    host = np.nonzero(done < 0)[0]
    R[host] = np.nan
    return {"min": R[:, 0], "max": R[:, 1], "tmin": R[:, 2], "tmax": R[:, 3],
            "done": done, "status": d_status.copy_to_host(), "host": host,
            "slots": np.array(slots, dtype=np.int64), "names": names}
