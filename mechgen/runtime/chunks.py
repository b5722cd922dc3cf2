"""Chunks of a design table: one call of the generated module's sweep_designs over a
slice of the designs (it releases the GIL), its designs' statuses and, when asked, its
reductions, and the table the chunks are gathered into. Shared by the backends that run
the compiled loop (mechgen.runtime.backends' threads, mechgen.runtime.dask_backend's
workers).
"""
from __future__ import annotations

import numpy as np

from ..protocol import INFO_SUBSTEPS, OK
from .reduce import design_status, reduce_chunk

# A design table's info keeps the columns before INFO_SUBSTEPS (iterations, residual,
# rank, method, status): the generated sweep writes the substep and jump columns only
# where its INFO is wide enough for them.
DESIGN_INFO_COLUMNS = INFO_SUBSTEPS
# solved points (designs x times) per chunk: big enough that a call's overhead vanishes,
# small enough that a reduced table's buffers stay small and progress moves
CHUNK_POINTS = 100_000


class TableData:
    """What a backend returns: Q, QD, QDD (designs, times, coordinates) and INFO (designs,
    times, DESIGN_INFO_COLUMNS), or None each when only reductions were kept; ``red``:
    (min, max, tmin, tmax), each (designs, slots), or None; ``done``: solved times per
    design; ``status``: per design (mechgen.runtime.reduce.design_status)."""

    def __init__(self, Q, QD, QDD, INFO, done, status, red=None):
        self.Q, self.QD, self.QDD, self.INFO = Q, QD, QDD, INFO
        self.done, self.status, self.red = done, status, red


def chunks(D, N, parts, least=0):
    """[(a, b)] splitting D designs into chunks of at most about CHUNK_POINTS points, at
    least ``parts`` of them (when there are that many designs), none under ``least``
    points (where a chunk's round trip costs: a cluster's task)."""
    size = max(1, min(-(-D // max(parts, 1)), CHUNK_POINTS // max(N, 1)))
    size = max(size, min(D, -(-least // max(N, 1))))
    return [(a, min(D, a + size)) for a in range(0, D, size)]


def scratch_arrays(scratch, D, N, nq, names):
    """Arrays of ``names`` (Q, QD, QDD: (D, N, nq); INFO: (D, N, DESIGN_INFO_COLUMNS)) lent
    from ``scratch`` (a dict kept by the caller, one per thread) again and again, so that a
    chunk's arrays that are read back only partly, or not at all, need no fresh pages."""
    out = []
    for name in names:
        cols = DESIGN_INFO_COLUMNS if name == "INFO" else nq
        have = scratch.get(name)
        if have is None or have.shape[0] < D or have.shape[1:] != (N, cols):
            have = scratch[name] = np.zeros((D, N, cols))
        out.append(have[:D])
    return out


def solve_chunk(module, ts, q0, P, lev, tol, xtol, maxit, meth, slots, scratch=None):
    """One chunk of designs through the compiled sweep_designs: (done, status, Q, QD, QDD,
    INFO) with the full arrays (QD, QDD None above the table's level), or (done, status,
    min, max, tmin, tmax) with ``slots``. ``scratch`` (see scratch_arrays) lends the
    arrays not returned: only the rows a design solved are read back."""
    D, N, nq = P.shape[0], ts.shape[0], q0.shape[0]
    if scratch is None:
        scratch = {}
    keep = () if slots is not None else \
        ("Q", "INFO") + (("QD",) if lev >= 1 else ()) + (("QDD",) if lev >= 2 else ())
    arrays = {}
    for name in ("Q", "QD", "QDD", "INFO"):
        if name in keep:
            arrays[name] = np.zeros((D, N, DESIGN_INFO_COLUMNS if name == "INFO" else nq))
        else:
            arrays[name], = scratch_arrays(scratch, D, N, nq, (name,))
    Q, QD, QDD, INFO = (arrays[k] for k in ("Q", "QD", "QDD", "INFO"))
    done = np.asarray(module.sweep_designs(ts, q0, P, lev, tol, xtol, maxit, meth,
                                           Q, QD, QDD, INFO), dtype=np.int64)
    status = design_status(INFO, done, N)
    if slots is None:       # derivatives above the level asked for are not kept
        return done, status, Q, QD if lev >= 1 else None, QDD if lev >= 2 else None, INFO
    return (done, status) + reduce_chunk(module, slots, ts, P, Q, QD, QDD, done)


class Collector:
    """Gathers the chunks' results into one TableData (full arrays or reductions)."""

    def __init__(self, D, N, nq, slots, lev=2):
        self.slots = slots
        self.done = np.zeros(D, dtype=np.int64)
        self.status = np.full(D, OK, dtype=np.int64)
        if slots is None:   # no derivative arrays above the table's level
            self.arrays = [np.zeros((D, N, nq)),
                           np.zeros((D, N, nq)) if lev >= 1 else None,
                           np.zeros((D, N, nq)) if lev >= 2 else None,
                           np.zeros((D, N, DESIGN_INFO_COLUMNS))]
        else:
            self.arrays = [np.full((D, slots.shape[0]), np.nan) for _ in range(4)]

    def put(self, a, b, result):
        self.done[a:b], self.status[a:b] = result[0], result[1]
        for arr, part in zip(self.arrays, result[2:]):
            if part is not None and arr is not None:
                arr[a:b] = part

    def table(self) -> TableData:
        if self.slots is None:
            return TableData(*self.arrays, self.done, self.status)
        return TableData(None, None, None, None, self.done, self.status, tuple(self.arrays))
