"""Where a design table runs: ``backend="cpu"`` (chunks of designs on a pool of threads,
each chunk through the module's compiled sweep_designs, which releases the GIL),
``"dask"`` (chunks over a dask.distributed cluster, mechgen.runtime.tables.dask_backend) or
``"cuda"`` (a generated GPU kernel, mechgen.runtime.tables.cuda). Every backend returns a
TableData: the full arrays, or only the reductions when ``slots`` is given, and the
count of solved times and the status of every design. Each design is swept on its own
(the same warm-started continuation and branch keeping as a single sweep), so the
numbers do not depend on the backend's chunking or on the count of workers.
"""
from __future__ import annotations

import os
import sys
import threading
from concurrent.futures import ThreadPoolExecutor, as_completed

import numpy as np

from ...errors import MechgenError
from ...protocol import FORCE_LEVELS, JUMP, OK, STATUS_CODE, THROUGH_SINGULAR
from .chunks import (DESIGN_INFO_COLUMNS, DESIGN_INFO_DTYPE, Collector, TableData,
                     chunks, fused_level, guided_chunks, solve_chunk, sweep_chunk)
from .reduce import DRIVER, design_status

BACKENDS = ("cpu", "dask", "cuda")


def cpu_count() -> int:
    """The cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def check_workers(workers):
    """None (all cores) or a positive integer."""
    if workers is None:
        return None
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise ValueError(f"workers must be a positive integer or None (all cores), got {workers!r}")
    return int(workers)


def run_cpu(module, ts, Q0, P, lev, tol, xtol, maxit, meth, workers=None, slots=None,
            progress=None) -> TableData:
    """The table on this machine's cores: chunks of designs on ``workers`` threads (None:
    every core; 1: in this thread, one chunk after the other); Q0: each design's start
    (tables.starts)."""
    D, N, nq = P.shape[0], ts.shape[0], Q0.shape[1]
    if getattr(module, "__mechgen_tier__", "compiled") == "python":
        workers = 1         # the plain-Python tier holds the GIL: threads gain nothing
    workers = cpu_count() if workers is None else workers
    if workers == 1:
        spans = chunks(D, N, 50 if progress is not None else 1)
    else:           # big chunks first, small ones last: the threads finish together
        spans = guided_chunks(D, N, workers, None if progress is None else -(-D // 50))
    out = Collector(D, N, nq, slots, lev)
    local = threading.local()
    if slots is None:       # the chunks write straight into the table's arrays (no
        Q, QD, QDD, INFO = out.arrays       # derivative arrays above its level)

        def job(a, b):
            out.done[a:b] = sweep_chunk(module, ts, Q0[a:b], P[a:b], lev, tol, xtol, maxit, meth,
                                        Q[a:b], None if QD is None else QD[a:b],
                                        None if QDD is None else QDD[a:b], INFO[a:b])
            out.status[a:b] = design_status(INFO[a:b], out.done[a:b], N)
    else:
        def job(a, b):
            scratch = local.__dict__
            out.put(a, b, solve_chunk(module, ts, Q0[a:b], P[a:b], lev, tol, xtol, maxit, meth,
                                      slots, scratch))
    total = 0
    if workers == 1 or len(spans) == 1:
        for a, b in spans:
            job(a, b)
            total += b - a
            if progress is not None:
                progress(total, D)
    else:
        with ThreadPoolExecutor(max_workers=min(workers, len(spans))) as pool:
            futures = {pool.submit(job, a, b): b - a for a, b in spans}
            for fut in as_completed(futures):
                fut.result()
                total += futures[fut]
                if progress is not None:
                    progress(total, D)
    return out.table()


def gpu_force_level(mech, slots, lev, meth):
    """The force level ("dynamic", "static") whose driver efforts a CUDA table reducing
    ``slots`` reduces on the GPU (its every driver slot at that level, the module's fused
    quick path for it: chunks.fused_level); None where it cannot."""
    order = fused_level(mech.module, np.asarray(slots), lev, meth)
    return None if order is None else FORCE_LEVELS[order]


def cuda_keeps_points(mech, slots, lev, meth) -> bool:
    """Whether a CUDA table reducing ``slots`` needs every point back on the host (a
    driver's effort the GPU cannot reduce: method "full", a module without the fused
    quick path of its level; the design table then solves the multipliers here)."""
    if slots is None or not np.any(np.asarray(slots)[:, 0] == DRIVER):
        return False
    return gpu_force_level(mech, slots, lev, meth) is None


def run_cuda(mech, ts, Q0, P, lev, tol, maxit, slots, xtol=None, meth=None,
             workers=None) -> TableData:
    """The table as a generated GPU kernel (mechgen.runtime.tables.cuda.run_table_cuda); a
    driver's effort reduced on the GPU where it can (mechgen.runtime.tables.cuda_forces), the
    designs it leaves to the host solved by the CPU table (run_cpu) and merged in."""
    try:
        from .cuda import run_table_cuda
    except ImportError as exc:
        raise MechgenError("backend='cuda' is not available in this mechgen "
                           f"(mechgen.runtime.tables.cuda could not be imported: {exc})") from None
    if slots is not None and np.any(slots[:, 0] == DRIVER) and \
            not cuda_keeps_points(mech, slots, lev, meth):
        from .cuda_forces import run_forces_cuda
        res = run_forces_cuda(mech, ts, P, Q0, tol, mech.xtol if xtol is None else xtol,
                              maxit, slots, level=gpu_force_level(mech, slots, lev, meth))
        done, status, host = res["done"], res["status"], res["host"]
        red = tuple(res[k] for k in ("min", "max", "tmin", "tmax"))
        if host.size:
            part = run_cpu(mech.module, ts, Q0[host], P[host], lev, tol,
                           mech.xtol if xtol is None else xtol, maxit, meth, workers, slots)
            done[host], status[host] = part.done, part.status
            for arr, got in zip(red, part.red):
                arr[host] = got
        return TableData(None, None, None, None, done, status, red)
    res = run_table_cuda(mech, ts, P, Q0, lev, tol, maxit, slots)
    status = np.asarray(res["status"], dtype=np.int64)
    N = ts.shape[0]
    failed = ~np.isin(status, (OK, JUMP, THROUGH_SINGULAR))
    done = np.asarray(res["done"], dtype=np.int64) if "done" in res else \
        np.where(failed, 0, N).astype(np.int64)
    if slots is not None:
        red = tuple(np.asarray(res[k], dtype=np.float64) for k in ("min", "max", "tmin", "tmax"))
        for arr in red:
            arr[done == 0] = np.nan
        return TableData(None, None, None, None, done, status, red)
    D, nq = P.shape[0], Q0.shape[1]
    arrays = []
    for order, key in enumerate(("Q", "QD", "QDD")):
        arr = res.get(key)
        if order > lev:
            arrays.append(None)         # no derivative arrays above the table's level
        else:
            arrays.append(np.zeros((D, N, nq)) if arr is None else
                          np.asarray(arr, dtype=np.float64))
    INFO = np.zeros((D, N, DESIGN_INFO_COLUMNS), dtype=DESIGN_INFO_DTYPE)
    rows = res.get("STATUS")
    if rows is not None:    # each point's status code, as the kernels wrote it (the
        # points reached by a jump or through a singular configuration marked, as on the CPU)
        rows = np.asarray(rows)
        k = min(rows.shape[2], DESIGN_INFO_COLUMNS)
        INFO[:, :, :k] = rows[:, :, :k]
    bad = np.nonzero(done < N)[0]
    INFO[bad, done[bad], STATUS_CODE] = status[bad]
    return TableData(*arrays, INFO, done, status)


def run_backend(backend, mech, ts, Q0, P, lev, tol, xtol, maxit, meth, workers=None,
                client=None, slots=None, progress=None) -> TableData:
    """The table on the backend asked for (see the module's docstring)."""
    if backend not in BACKENDS:
        raise ValueError(f"backend must be one of {', '.join(map(repr, BACKENDS))}, got {backend!r}")
    workers = check_workers(workers)
    if backend == "cpu":
        if client is not None:
            raise ValueError("client= is for backend='dask'")
        return run_cpu(mech.module, ts, Q0, P, lev, tol, xtol, maxit, meth, workers, slots,
                       progress)
    if backend == "dask":
        from .dask_backend import run_dask
        return run_dask(mech.module, ts, Q0, P, lev, tol, xtol, maxit, meth, client, slots,
                        progress)
    return run_cuda(mech, ts, Q0, P, lev, tol, maxit, slots, xtol, meth, workers)


def progress_reporter(progress, total):
    """None (quiet), a callable progress(done, total), or a progress bar on stderr."""
    if progress is None or progress is False:
        return None
    if callable(progress):
        return progress
    return Bar(total)


class Bar:
    """A progress bar on stderr: ``designs solved: 512/1000 [#####.....] 51%``."""

    def __init__(self, total, width=30, stream=None):
        self.total, self.width = total, width
        self.stream = sys.stderr if stream is None else stream

    def __call__(self, done, total):
        fill = int(self.width * done / max(total, 1))
        self.stream.write(f"\rdesigns solved: {done}/{total} "
                          f"[{'#' * fill}{'.' * (self.width - fill)}] "
                          f"{100.0 * done / max(total, 1):.0f}%")
        if done >= total:
            self.stream.write("\n")
        self.stream.flush()
