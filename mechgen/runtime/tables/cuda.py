"""Design tables on an NVIDIA GPU (``backend="cuda"``): one CUDA thread per design,
sweeping its times warm-started exactly as the CPU design table does (the module's
sweep_designs(): sweep_fast(), then sweep() from its last accepted point: two kernels,
the second only for the designs the first left unfinished), with the module's own solver
functions compiled for the GPU (mechgen.runtime.tables.cuda_twin).

:func:`run_table_cuda` runs it two ways:

- every point back: ``Q``, ``QD``, ``QDD`` (design, time, coordinate; QD, QDD None below
  the table's level) and ``STATUS`` (design, time, 1: each point's status code, int16),
  as the CPU table holds them;
- reductions only (``slots``): per design and quantity the minimum, the maximum and the
  (first) times they are reached, computed on the GPU while the design is swept, so that
  10^6 designs × 1,000 times never leave the GPU as points.

A quantity slot is a row ``[kind, index, order]`` (the design table's reduction slots,
mechgen.runtime.tables.reduce): kind 0 a coordinate (index into the coordinates, order 0, 1, 2:
position, velocity, acceleration), kind 1 an output (index into the outputs, order: which
time derivative). :func:`quantity_slots` makes them from names ("X4", "X4d", "stroke_x");
:func:`slot_names` is the inverse.

Per design ``status`` (int64, protocol codes): the failure status of the first time that
could not be solved (then ``done`` < len(ts)); else JUMP when some point was reached by a
branch jump, else THROUGH_SINGULAR when one was reached through a singular configuration,
else OK. A design's extremes are over the times it solved (NaN when it solved none), as
the CPU's reductions are.

numba.cuda is imported only here, only when a CUDA table is asked for; without a GPU
(and outside numba's simulator, NUMBA_ENABLE_CUDASIM=1) :func:`require_cuda` raises.
"""
from __future__ import annotations

import numpy as np

from ...errors import MechgenError
from ...protocol import JUMP, LEVEL, LEVELS, OK, STATUS_CODE, THROUGH_SINGULAR
from ..quantity import lookup

# A slot's kind (the design table's reduction slots, mechgen.runtime.tables.reduce)
COORDINATE, OUTPUT = 0, 1
# columns of the per-point STATUS a CUDA table keeps: the status code only (2 bytes a point)
STATUS_COLUMNS = STATUS_CODE + 1
THREADS = 128                   # threads per block on a GPU
SIM_THREADS = 8                 # ... and under the simulator (a Python thread each)

_TWINS = {}                     # (id(module), max_registers) -> (module, twin namespace)


def require_cuda():
    """numba.cuda, or one clear MechgenError when no GPU can run the kernels."""
    if not hasattr(np, "row_stack"):
        # numba-cuda 0.2x registers an overload of np.row_stack, which numpy 2.5 removed:
        # its first kernel compile then fails (seen on a GPU machine with numba 0.68 and
        # numpy 2.5.2). row_stack was always an alias of vstack.
        np.row_stack = np.vstack
    try:
        from numba import cuda
    except Exception as exc:                        # pragma: no cover - numba always has it
        raise MechgenError(f"backend='cuda' needs numba.cuda, which cannot be imported: {exc}")
    if not cuda.is_available():
        raise MechgenError(
            "backend='cuda' needs an NVIDIA GPU with CUDA: numba.cuda.is_available() is False "
            "(no GPU, no CUDA driver, or numba cannot find the CUDA toolkit's NVVM: "
            "pip install nvidia-cuda-nvcc-cu12 or set CUDA_HOME). Use backend='cpu', or set "
            "NUMBA_ENABLE_CUDASIM=1 to run the kernels, very slowly, on numba's simulator.")
    return cuda


def simulated() -> bool:
    """Whether numba.cuda is its simulator (NUMBA_ENABLE_CUDASIM=1)."""
    from numba.core import config
    return bool(config.ENABLE_CUDASIM)


def numba_module(mech):
    """The generated module whose numba functions the twin translates: the mechanism's
    own, or, while it answers in the plain-Python tier (mechgen.runtime.loading.tiers), the same
    file imported with numba (nothing is compiled for the CPU by that)."""
    module = mech.module
    if getattr(getattr(module, "sweep", None), "py_func", None) is not None:
        return module
    path = mech.state.tiers.path or \
        getattr(module, "__file__", None)
    if not path:
        raise MechgenError(f"backend='cuda' translates the numba functions of '{mech.name}''s "
                           "generated module, and this mechanism has neither them nor the "
                           "module's file: load it from its path")
    from ..loading.loader import check_version, import_path
    compiled = import_path(path)
    check_version(compiled)
    return compiled


def twin(module, max_registers=None):
    """The CUDA twin of a generated module (translated once per module; numba compiles
    each kernel at its first launch)."""
    key = (id(module), max_registers)
    hit = _TWINS.get(key)
    if hit is not None and hit[0] is module:
        return hit[1]
    cuda = require_cuda()
    from .cuda_twin import build_twin
    ns = build_twin(module, cuda, STATUS_COLUMNS, max_registers)
    _TWINS[key] = (module, ns)
    return ns


def _level_of(level) -> int:
    if isinstance(level, str):
        if level not in LEVEL:
            raise ValueError(f"level must be one of {', '.join(LEVELS)}, got {level!r}")
        return LEVEL[level]
    if isinstance(level, bool) or not isinstance(level, (int, np.integer)) or \
            not 0 <= level < len(LEVELS):
        raise ValueError(f"level must be one of {', '.join(LEVELS)} or 0, 1, 2, got {level!r}")
    return int(level)


def quantity_slots(mech, names, level) -> np.ndarray:
    """Slots (int64 rows [kind, index, order]) of quantity names ("X4", "X4d", "X4dd",
    an output "stroke_x", "stroke_xd"), checked against the table's level (a name or
    0, 1, 2)."""
    lev = _level_of(level)
    if isinstance(names, str):
        names = [names]
    slots = np.zeros((len(names), 3), dtype=np.int64)
    for j, name in enumerate(names):
        kind, k, order = lookup(mech, name)
        need = order if kind == "q" else mech.output_orders[k] + order
        if need > lev:
            raise MechgenError(f"{name!r} needs a table at level "
                               f"{LEVELS[min(need, LEVEL['acceleration'])]}, not {LEVELS[lev]}")
        slots[j] = (COORDINATE if kind == "q" else OUTPUT, k, order)
    return slots


def slot_names(mech, slots) -> list:
    """The quantity name of each slot row [kind, index, order] (quantity_slots' inverse)."""
    names = []
    for kind, index, order in np.asarray(slots, dtype=np.int64).reshape(-1, 3):
        base = (mech.coordinates if kind == COORDINATE else mech.outputs)[index]
        names.append(base + "d" * int(order))
    return names


def flat_slots(mech, slots, lev):
    """(flat, nord): the kernels' numbering of slot rows [kind, index, order], checked
    against the mechanism and the level: with n coordinates and m outputs, ``order*n +
    index`` for a coordinate, ``3n + order*m + index`` for an output; nord is how many
    output orders the kernels evaluate (0: none)."""
    n, m = len(mech.coordinates), len(mech.outputs)
    arr = np.asarray(slots)
    if arr.dtype.kind not in "iu" or arr.ndim != 2 or arr.shape[1] != 3 or arr.shape[0] == 0:
        raise MechgenError("slots: give a non-empty int64 array of rows [kind, index, order] "
                           "(see mechgen.runtime.tables.cuda.quantity_slots)")
    flat = np.zeros(arr.shape[0], dtype=np.int64)
    nord = 0
    for j, (kind, index, order) in enumerate(arr.tolist()):
        size = n if kind == COORDINATE else m if kind == OUTPUT else -1
        if size < 0 or not 0 <= index < size or not 0 <= order <= 2:
            raise MechgenError(f"slots: row {j} [{kind}, {index}, {order}] is not a quantity "
                               f"of '{mech.name}' (kind 0: {n} coordinates, kind 1: {m} "
                               "outputs; order 0, 1 or 2)")
        need = order if kind == COORDINATE else mech.output_orders[index] + order
        if need > lev:
            raise MechgenError(f"slots: {slot_names(mech, [[kind, index, order]])[0]!r} needs "
                               f"a table at level {LEVELS[min(need, 2)]}, not {LEVELS[lev]}")
        if kind == COORDINATE:
            flat[j] = order * n + index
        else:
            flat[j] = 3 * n + order * m + index
            nord = max(nord, order + 1)
    return flat, nord


def table_inputs(mech, ts, P, q0):
    """(ts, P, Q0) as a kernel takes them (contiguous float64), or a MechgenError that
    says which is not: ts a non-empty 1-D array of times, P designs × parameters, q0 the
    coordinates (every design's start) or designs × coordinates (each design's: Q0), all
    finite."""
    ts = np.ascontiguousarray(ts, dtype=np.float64)
    P = np.ascontiguousarray(np.atleast_2d(P), dtype=np.float64)
    q0 = np.ascontiguousarray(q0, dtype=np.float64)
    if ts.ndim != 1 or ts.size == 0:
        raise MechgenError("ts: give a non-empty 1-D array of times")
    if P.ndim != 2 or P.shape[1] != len(mech.parameter_names) or P.shape[0] == 0:
        raise MechgenError(f"P: give an array of designs × {len(mech.parameter_names)} "
                           f"parameters ({', '.join(mech.parameter_names)}), got {P.shape}")
    n = len(mech.coordinates)
    if q0.shape == (n,):
        q0 = np.ascontiguousarray(np.broadcast_to(q0, (P.shape[0], n)))
    if q0.shape != (P.shape[0], n):
        raise MechgenError(f"q0: give {n} coordinates, or designs × {n}, got {q0.shape}")
    if not (np.all(np.isfinite(P)) and np.all(np.isfinite(ts)) and np.all(np.isfinite(q0))):
        raise MechgenError("ts, P and q0 must be finite")
    return ts, P, q0


def run_table_cuda(mech, ts, P, q0, lev, tol, maxit, slots=None, method=None, threads=None,
                   max_registers=None) -> dict:
    """A design table on the GPU: row d of ``P`` (designs × parameters) swept over ``ts``
    from ``q0`` at level ``lev`` (0, 1, 2 or a name), one CUDA thread per design, as the
    module's sweep_designs() sweeps it on the CPU (``q0``: every design's start, or designs ×
    coordinates, each design's).

    Two kernels run: the first sweeps every design with sweep_fast(), the second, only
    where the first stopped early, goes on with sweep() (sweep_designs' two steps; the
    first kernel stays small, the careful sweep's registers do not slow it).

    Returns a dict with ``status`` (designs,) int64 (a failure's status, else JUMP, else
    THROUGH_SINGULAR, else OK), ``done`` (designs,) int64 (times solved), ``passes`` (1 or
    2) and ``second_pass`` (how many designs needed the careful sweep), and either
    (``slots`` None) ``Q``, ``QD``, ``QDD`` (designs, times, coordinates; QD and QDD None
    below the level) and ``STATUS`` (designs, times, 1; int16 status codes), or (``slots``
    an int64 array of rows [kind, index, order], see quantity_slots) ``min``, ``max``,
    ``tmin``, ``tmax`` (designs, slots: over the times each design solved, NaN where it
    solved none), with ``slots`` and their ``names``.

    method: as Mechanism.sweep (None: the mechanism's); threads: per block (default 128);
    max_registers: a cap on the kernels' registers per thread (numba.cuda.jit's option;
    fewer registers, more threads resident, some values spilled)."""
    cuda = require_cuda()
    lev = mech.state.level_of(LEVELS[_level_of(lev)])
    meth = mech.state.method_of(method)
    ts, P, Q0 = table_inputs(mech, ts, P, q0)
    D, N, n = P.shape[0], ts.shape[0], Q0.shape[1]
    reducing = slots is not None
    if reducing:
        flat, nord = flat_slots(mech, slots, lev)
        rows = np.array(slots, dtype=np.int64)
    else:
        flat, nord = np.zeros(1, dtype=np.int64), 0
    nsl = flat.size if reducing else 0
    ns = twin(numba_module(mech), max_registers)
    tpb = threads or (SIM_THREADS if simulated() else THREADS)
    d_ts, d_Q0, d_P, d_sl = (cuda.to_device(a) for a in (ts, Q0, P, flat))
    d_R = cuda.to_device(np.full((D, 4, max(nsl, 1)), np.nan))
    d_done = cuda.to_device(np.zeros(D, dtype=np.int64))
    d_status = cuda.to_device(np.zeros(D, dtype=np.int64))
    d_QS = cuda.device_array((D, n))                # where the second pass resumes
    d_FL = cuda.device_array((D, 3), dtype=np.int64)
    common = (float(tol), float(mech.xtol), int(maxit), d_sl, nsl, nord)
    tail = (d_R, d_QS, d_FL, d_done, d_status)
    if reducing:
        arrays = ()
        kind = "reduce"
    else:
        # derivatives below the level: arrays with no rows (the sweeps do not write them)
        arrays = tuple(cuda.to_device(np.zeros((D, N if lev >= order else 0, n)))
                       for order in range(3)) + \
            (cuda.to_device(np.zeros((D, N, STATUS_COLUMNS), dtype=np.int16)),)
        kind = "table"
    # first pass: sweep_fast() for every design (a small kernel, no careful sweep in it)
    ns["_cu_fast_" + kind][-(-D // tpb), tpb](d_ts, d_Q0, d_P, meth, *common, *arrays, *tail)
    done = d_done.copy_to_host()
    pending = np.nonzero(done < 0)[0]
    if pending.size:
        # second pass, only for the designs the first left unfinished: sweep() from there
        d_idx = cuda.to_device(pending.astype(np.int64))
        ns["_cu_careful_" + kind][-(-pending.size // tpb), tpb](
            d_ts, d_P, d_idx, lev, meth, *common, *arrays, *tail)
        done = d_done.copy_to_host()
    out = {"passes": 2 if pending.size else 1, "second_pass": int(pending.size)}
    if reducing:
        R = d_R.copy_to_host()
        out.update(min=R[:, 0], max=R[:, 1], tmin=R[:, 2], tmax=R[:, 3],
                   slots=rows, names=slot_names(mech, rows))
    else:
        d_Q, d_QD, d_QDD, d_ST = arrays
        out.update(Q=d_Q.copy_to_host(),
                   QD=d_QD.copy_to_host() if lev >= 1 else None,
                   QDD=d_QDD.copy_to_host() if lev >= 2 else None,
                   STATUS=d_ST.copy_to_host())
    out["done"] = done
    out["status"] = d_status.copy_to_host()
    return out


def design_status(STATUS, done, nt) -> np.ndarray:
    """Per design, from a table's per-point status rows (STATUS[d, k, STATUS_CODE]) and
    done, the status run_table_cuda reports (the same rule: a failure's status, else JUMP,
    else THROUGH_SINGULAR, else OK); int64."""
    D = STATUS.shape[0]
    status = np.full(D, OK, dtype=np.int64)
    for d in range(D):
        k = int(done[d])
        col = STATUS[d, :, STATUS_CODE]
        if k < nt:
            status[d] = int(col[k])
        elif np.any(col[:k] == JUMP):
            status[d] = JUMP
        elif np.any(col[:k] == THROUGH_SINGULAR):
            status[d] = THROUGH_SINGULAR
    return status
