"""Design tables on an NVIDIA GPU (``backend="cuda"``): one CUDA thread per design,
sweeping its times warm-started exactly as the CPU design table does (the module's
sweep_fast(), then sweep() from its last accepted point: two kernels, the second only
for the designs the first left unfinished), with the module's own solver functions
compiled for the GPU (mechgen.runtime.cuda_twin).

Two ways to run, both through :func:`run_table_cuda`:

- every point back: ``Q``, ``QD``, ``QDD`` (design, time, coordinate) and ``INFO``, as
  the CPU table holds them;
- reductions only (``reduce_slots``): per design and quantity slot the minimum, the
  maximum and the times they are reached, computed on the GPU while the design is swept,
  so that 10^6 designs × 1,000 times never leave the GPU as points.

Quantity slots (the numbering of ``reduce_slots``), with n coordinates and m outputs:
``0 .. n-1`` the coordinates, ``n .. 2n-1`` their velocities, ``2n .. 3n-1`` their
accelerations, ``3n .. 3n+m-1`` the outputs, then the outputs' first and second
derivatives (``3n + m*order + j``). :func:`quantity_slots` maps names ("X4", "X4d",
"stroke_x") to slots; :func:`slot_names` is the inverse.

Per design ``status`` (int32, protocol codes): OK; JUMP or THROUGH_SINGULAR when some
point was reached by a branch jump or through a singular configuration (JUMP wins);
otherwise the failure status of the first time that could not be solved (then ``done``
< len(ts) and the design's reductions are NaN, never numbers).

numba.cuda is imported only here, only when a CUDA table is asked for; without a GPU
(and outside numba's simulator, NUMBA_ENABLE_CUDASIM=1) :func:`require_cuda` raises.
"""
from __future__ import annotations

import numpy as np

from ..errors import MechgenError
from ..protocol import INFO_STATUS, INFO_SUBSTEPS, LEVEL, LEVELS
from .quantity import _lookup

# the design table's INFO columns (iterations, residual, rank, method, status)
INFO_COLUMNS = INFO_SUBSTEPS
THREADS = 128                   # threads per block on a GPU
SIM_THREADS = 8                 # ... and under the simulator (a Python thread each)

_TWINS = {}                     # (id(module), max_registers) -> (module, twin namespace)


def require_cuda():
    """numba.cuda, or one clear MechgenError when no GPU can run the kernels."""
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


def twin(module, max_registers=None):
    """The CUDA twin of a generated module (translated once per module; numba compiles
    each kernel at its first launch)."""
    key = (id(module), max_registers)
    hit = _TWINS.get(key)
    if hit is not None and hit[0] is module:
        return hit[1]
    cuda = require_cuda()
    from .cuda_twin import build_twin
    ns = build_twin(module, cuda, INFO_COLUMNS, max_registers)
    _TWINS[key] = (module, ns)
    return ns


def slot_names(mech) -> list:
    """The name of every quantity slot, in slot order (see the module docstring)."""
    n = list(mech.coordinates)
    out = list(mech.outputs)
    return (n + [c + "d" for c in n] + [c + "dd" for c in n] + out +
            [o + "d" for o in out] + [o + "dd" for o in out])


def quantity_slots(mech, names, level) -> np.ndarray:
    """Slots (int64) of quantity names ("X4", "X4d", "X4dd", an output "stroke_x",
    "stroke_xd"), checked against the table's level (a name or 0, 1, 2)."""
    lev = LEVEL[level] if isinstance(level, str) else int(level)
    if isinstance(names, str):
        names = [names]
    n, m = len(mech.coordinates), len(mech.outputs)
    slots = []
    for name in names:
        kind, k, order = _lookup(mech, name)
        need = order if kind == "q" else mech.output_orders[k] + order
        if need > lev:
            raise MechgenError(f"{name!r} needs a table at level "
                               f"{LEVELS[min(need, LEVEL['acceleration'])]}, not {LEVELS[lev]}")
        slots.append(order * n + k if kind == "q" else 3 * n + order * m + k)
    return np.asarray(slots, dtype=np.int64)


def _check_slots(mech, slots, lev):
    n, m = len(mech.coordinates), len(mech.outputs)
    slots = np.atleast_1d(np.asarray(slots))
    if slots.ndim != 1 or slots.size == 0 or slots.dtype.kind not in "iu":
        raise MechgenError("reduce_slots: give a non-empty 1-D sequence of integer slots "
                           "(see mechgen.runtime.cuda.quantity_slots)")
    names = slot_names(mech)
    for s in slots:
        if not 0 <= s < len(names):
            raise MechgenError(f"reduce_slots: {int(s)} is not a quantity slot of "
                               f"'{mech.name}' (0 .. {len(names) - 1})")
        if s < 3 * n:
            need = s // n
        else:
            order, j = divmod(int(s) - 3 * n, m)
            need = mech.output_orders[j] + order
        if need > lev:
            raise MechgenError(f"reduce_slots: {names[s]!r} (slot {int(s)}) needs a table at "
                               f"level {LEVELS[min(need, 2)]}, not {LEVELS[lev]}")
    nord = 0
    for s in slots:
        if s >= 3 * n:
            nord = max(nord, (int(s) - 3 * n) // m + 1)
    return slots.astype(np.int64), nord


def run_table_cuda(mech, ts, P, q0, level, tol, maxit, reduce_slots=None, method=None,
                   threads=None, max_registers=None) -> dict:
    """A design table on the GPU: row d of ``P`` (designs × parameters) swept over ``ts``
    from ``q0`` at ``level`` (a name or 0, 1, 2), one CUDA thread per design.

    Two kernels run: the first sweeps every design with sweep_fast(), the second, only
    where the first stopped early, goes on with sweep() (sweep_designs' two steps; the
    first kernel stays small, the careful sweep's registers do not slow it).

    Returns a dict with ``status`` (designs,) int32, ``done`` (designs,) int64 (times
    solved), ``second_pass`` (how many designs needed the careful sweep), and either (reduce_slots None) ``Q``, ``QD``, ``QDD`` (designs, times,
    coordinates; QD and QDD None below their level) and ``INFO`` (designs, times, 5), or
    ``min``, ``max``, ``tmin``, ``tmax`` (designs, slots), NaN for a failed design, with
    ``slots`` and their ``names``.

    method: as Mechanism.sweep (None: the mechanism's); threads: per block (default 128);
    max_registers: a cap on the kernels' registers per thread (numba.cuda.jit's option;
    fewer registers, more threads resident, some values spilled)."""
    cuda = require_cuda()
    lev = mech._level(LEVELS[level] if isinstance(level, (int, np.integer)) else level)
    meth = mech._method(method)
    ts = np.ascontiguousarray(ts, dtype=np.float64)
    P = np.ascontiguousarray(np.atleast_2d(P), dtype=np.float64)
    q0 = np.ascontiguousarray(q0, dtype=np.float64)
    if ts.ndim != 1 or ts.size == 0:
        raise MechgenError("ts: give a non-empty 1-D array of times")
    if P.shape[1] != len(mech.parameter_names) or P.shape[0] == 0:
        raise MechgenError(f"P: give an array of designs × {len(mech.parameter_names)} "
                           f"parameters ({', '.join(mech.parameter_names)}), got {P.shape}")
    if not (np.all(np.isfinite(P)) and np.all(np.isfinite(ts)) and np.all(np.isfinite(q0))):
        raise MechgenError("ts, P and q0 must be finite")
    D, N, n = P.shape[0], ts.shape[0], q0.shape[0]
    reducing = reduce_slots is not None
    if reducing:
        slots, nord = _check_slots(mech, reduce_slots, lev)
    else:
        slots, nord = np.zeros(1, dtype=np.int64), 0
    nsl = slots.size if reducing else 0
    ns = twin(mech.module, max_registers)
    tpb = threads or (SIM_THREADS if simulated() else THREADS)
    d_ts, d_q0, d_P, d_sl = (cuda.to_device(a) for a in (ts, q0, P, slots))
    d_R = cuda.to_device(np.full((D, 4, max(nsl, 1)), np.nan))
    d_done = cuda.to_device(np.zeros(D, dtype=np.int64))
    d_status = cuda.to_device(np.zeros(D, dtype=np.int32))
    d_QS = cuda.device_array((D, n))                # where the second pass resumes
    d_FL = cuda.device_array((D, 3), dtype=np.int64)
    common = (float(tol), float(mech.xtol), int(maxit), d_sl, nsl, nord)
    tail = (d_R, d_QS, d_FL, d_done, d_status)
    if reducing:
        rows = ()
        kind = "reduce"
    else:
        zeros = np.zeros((D, N, n))
        rows = tuple(cuda.to_device(zeros) for _ in range(3)) + \
            (cuda.to_device(np.zeros((D, N, INFO_COLUMNS))),)
        kind = "table"
    # first pass: sweep_fast() for every design (a small kernel, no careful sweep in it)
    ns["_cu_fast_" + kind][-(-D // tpb), tpb](d_ts, d_q0, d_P, meth, *common, *rows, *tail)
    done = d_done.copy_to_host()
    pending = np.nonzero(done < 0)[0]
    if pending.size:
        # second pass, only for the designs the first left unfinished: sweep() from there
        d_idx = cuda.to_device(pending.astype(np.int64))
        ns["_cu_careful_" + kind][-(-pending.size // tpb), tpb](
            d_ts, d_P, d_idx, lev, meth, *common, *rows, *tail)
        done = d_done.copy_to_host()
    out = {"passes": 2 if pending.size else 1, "second_pass": int(pending.size)}
    if reducing:
        R = d_R.copy_to_host()
        out.update(min=R[:, 0], max=R[:, 1], tmin=R[:, 2], tmax=R[:, 3],
                   slots=slots, names=[slot_names(mech)[s] for s in slots])
    else:
        d_Q, d_QD, d_QDD, d_INFO = rows
        out.update(Q=d_Q.copy_to_host(),
                   QD=d_QD.copy_to_host() if lev >= 1 else None,
                   QDD=d_QDD.copy_to_host() if lev >= 2 else None,
                   INFO=d_INFO.copy_to_host())
    out["done"] = done
    out["status"] = d_status.copy_to_host()
    return out


def design_status(INFO, done, nt) -> np.ndarray:
    """The per-design status run_table_cuda reports, from a CPU table's INFO and done
    (the same rule: a failure's status, else JUMP, else THROUGH_SINGULAR, else OK)."""
    from ..protocol import JUMP, OK, THROUGH_SINGULAR
    D = INFO.shape[0]
    status = np.full(D, OK, dtype=np.int32)
    for d in range(D):
        k = int(done[d])
        if k < nt:
            status[d] = int(INFO[d, k, INFO_STATUS])
            continue
        col = INFO[d, :, INFO_STATUS]
        if np.any(col == JUMP):
            status[d] = JUMP
        elif np.any(col == THROUGH_SINGULAR):
            status[d] = THROUGH_SINGULAR
    return status


def as_design_arrays(out, level):
    """(Q, QD, QDD, INFO, done) of a full run_table_cuda result, as
    mechgen.runtime.design.run_designs returns them (zeros where a level is not solved),
    ready for DesignTable."""
    Q = out["Q"]
    lev = LEVEL[level] if isinstance(level, str) else int(level)
    QD = out["QD"] if lev >= 1 else np.zeros_like(Q)
    QDD = out["QDD"] if lev >= 2 else np.zeros_like(Q)
    return Q, QD, QDD, out["INFO"], out["done"]
