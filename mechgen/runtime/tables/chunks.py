"""Chunks of a design table: the generated module's sweep_designs over a slice of the
designs (its two steps, each releasing the GIL: the careful one only where a design
needs it), its designs' statuses and, when asked, its
reductions, and the table the chunks are gathered into. Shared by the backends that run
the compiled loop (mechgen.runtime.tables.backends' threads, mechgen.runtime.tables.dask_backend's
workers).
"""
from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from ...protocol import FORCE_LEVELS, METHOD, OK, STATUS_CODE, fused_path
from ..kinematics.entry import module_attr
from .reduce import DRIVER, design_status, reduce_chunk, repaired

# A design table's per-point record: the first column of a sweep's STATUS rows (int16: the
# status code, protocol.STATUS_*), 2 bytes a point; INFO is its name in a DesignTable. The
# generated sweep writes the STATUS columns its array has.
DESIGN_INFO_COLUMNS = STATUS_CODE + 1
DESIGN_INFO_DTYPE = np.int16
# solved points (designs x times) per chunk: big enough that a call's overhead vanishes,
# small enough that a reduced table's buffers stay small and progress moves
CHUNK_POINTS = 100_000
# a design table reducing a driver's effort sweeps and reduces this many points at a time
# (some tens of designs): few enough that the points are still in the cache when their
# multipliers read them, many enough that the Python between two compiled calls (holding
# the GIL) is small beside them. On 16 cores of the GPU machine (benchmarks/
# bench_force_threads.py) 4,000 scaled to 1.65x one thread, 16,000 to 3.4x, 64,000 to
# 6.5x (the kinematic table: 6.4x), one thread as fast at each
FORCE_POINTS = 64_000
# the smallest chunk of a guided split (guided_chunks): a call's overhead still small
TAIL_POINTS = 5_000


class TableData:
    """What a backend returns: Q, QD, QDD (designs, times, coordinates; QD, QDD None above
    the table's level) and INFO (designs, times, DESIGN_INFO_COLUMNS; int16), or None each
    when only reductions were kept; ``red``: (min, max, tmin, tmax), each (designs,
    slots), or None; ``done``: solved times per design; ``status``: per design
    (mechgen.runtime.tables.reduce.design_status)."""

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


def guided_chunks(D, N, workers, most=None):
    """[(a, b)] splitting D designs for ``workers`` threads taking chunks in turn: each
    chunk a share of the designs still to go (OpenMP's guided schedule), at most about
    CHUNK_POINTS points (and at most ``most`` designs), none under about TAIL_POINTS
    points: big chunks first, so that calls are few, then smaller and smaller ones, so
    that the threads run out of work together instead of one finishing a big chunk
    alone."""
    cap = max(1, CHUNK_POINTS // max(N, 1))
    if most is not None:
        cap = max(1, min(cap, most))
    least = max(1, min(cap, TAIL_POINTS // max(N, 1), -(-D // (2 * max(workers, 1)))))
    out, a = [], 0
    while a < D:
        size = min(cap, max(least, -(-(D - a) // (2 * max(workers, 1)))))
        out.append((a, min(D, a + size)))
        a += size
    return out


def scratch_arrays(scratch, D, N, nq, names):
    """Arrays of ``names`` (Q, QD, QDD: (D, N, nq); INFO: (D, N, DESIGN_INFO_COLUMNS),
    int16) lent from ``scratch`` (a dict kept by the caller, one per thread) again and
    again, so that a chunk's arrays that are read back only partly, or not at all, need no
    fresh pages."""
    out = []
    for name in names:
        info = name == "INFO"
        cols = DESIGN_INFO_COLUMNS if info else nq
        have = scratch.get(name)
        if have is None or have.shape[0] < D or have.shape[1:] != (N, cols):
            have = scratch[name] = np.zeros((D, N, cols),
                                            dtype=DESIGN_INFO_DTYPE if info else np.float64)
        out.append(have[:D])
    return out


def no_rows(D, nq) -> np.ndarray:
    """The derivative array of a chunk above the table's level: no rows per design (the
    generated sweep writes QD only at level >= 1, QDD only at level 2)."""
    return np.zeros((D, 0, nq))


def new_arrays(D, N, nq, lev):
    """[Q, QD, QDD, INFO] of D designs at level ``lev`` (QD, QDD None above it)."""
    return [np.zeros((D, N, nq)),
            np.zeros((D, N, nq)) if lev >= 1 else None,
            np.zeros((D, N, nq)) if lev >= 2 else None,
            np.zeros((D, N, DESIGN_INFO_COLUMNS), dtype=DESIGN_INFO_DTYPE)]


def sweep_chunk(module, ts, Q0, P, lev, tol, xtol, maxit, meth, Q, QD, QDD, INFO):
    """The module's sweep_designs over one chunk (Q0: each design's start; QD, QDD None
    above the level): the count of solved times per design. Its two steps are called
    one by one: the careful rest (sweep_designs_rest) only where a design's quick path
    (sweep_designs_fast) stopped early, so that a table of easy designs never compiles
    the careful sweep."""
    D, nq = P.shape[0], Q0.shape[1]
    QD = no_rows(D, nq) if QD is None else QD
    QDD = no_rows(D, nq) if QDD is None else QDD
    fast = module_attr(module, "sweep_designs_fast")
    if fast is None:            # a module built before the two steps were split
        return np.asarray(module.sweep_designs(ts, Q0, P, lev, tol, xtol, maxit, meth, Q, QD,
                                               QDD, INFO), dtype=np.int64)
    start = np.zeros(D, dtype=np.int64)
    fast(ts, Q0, P, tol, xtol, maxit, meth, Q, QD, QDD, INFO, start)
    if (start == ts.shape[0]).all():
        return start
    return np.asarray(module.sweep_designs_rest(ts, Q0, P, lev, tol, xtol, maxit, meth, Q, QD,
                                                QDD, INFO, start), dtype=np.int64)


def two_steps(module, name, ts, Q0, P, meth, tol, xtol, maxit, *arrays):
    """The module's design loop ``name`` (sweep_designs_forces, sweep_designs_statics:
    arguments as there) in its two steps, as sweep_chunk makes sweep_designs: every
    design's quick path (``name``_fast), then the careful rest (``name``_rest) only where
    a quick path stopped early; the count of solved times per design."""
    fast = module_attr(module, name + "_fast")
    if fast is None:            # a module built before the two steps were split
        return getattr(module, name)(ts, Q0, P, meth, tol, xtol, maxit, *arrays)
    start = np.zeros(P.shape[0], dtype=np.int64)
    fast(ts, Q0, P, tol, xtol, maxit, *arrays, start)
    if (start == ts.shape[0]).all():
        return start
    return getattr(module, name + "_rest")(ts, Q0, P, meth, tol, xtol, maxit, *arrays, start)


def solve_chunk(module, ts, Q0, P, lev, tol, xtol, maxit, meth, slots, scratch=None):
    """One chunk of designs through the compiled sweep_designs: (done, status, Q, QD, QDD,
    INFO) with the full arrays (QD, QDD None above the table's level), or (done, status,
    min, max, tmin, tmax) with ``slots``. ``scratch`` (see scratch_arrays) lends the
    arrays not returned: only the rows a design solved are read back."""
    D, N, nq = P.shape[0], ts.shape[0], Q0.shape[1]
    if slots is None:
        Q, QD, QDD, INFO = new_arrays(D, N, nq, lev)
    else:
        names = ("Q", "INFO") + (("QD",) if lev >= 1 else ()) + (("QDD",) if lev >= 2 else ())
        lent = dict(zip(names, scratch_arrays({} if scratch is None else scratch, D, N, nq,
                                              names)))
        Q, QD, QDD, INFO = (lent.get(k) for k in ("Q", "QD", "QDD", "INFO"))
    if slots is not None and np.any(slots[:, 0] == DRIVER):
        return _solve_forces(module, ts, Q0, P, lev, tol, xtol, maxit, meth, slots,
                             Q, QD, QDD, INFO)
    done = sweep_chunk(module, ts, Q0, P, lev, tol, xtol, maxit, meth, Q, QD, QDD, INFO)
    status = design_status(INFO, done, N)
    if slots is None:
        return done, status, Q, QD, QDD, INFO
    return (done, status) + reduce_chunk(module, slots, ts, P, Q, QD, QDD, done)


def _solve_forces(module, ts, Q0, P, lev, tol, xtol, maxit, meth, slots, Q, QD, QDD, INFO):
    """solve_chunk with a driver's effort among the reductions: a few designs at a time
    (about FORCE_POINTS points), each reduced while its points are still in the cache
    (the multipliers read every coordinate, velocity and acceleration again)."""
    D, N = P.shape[0], ts.shape[0]
    step = max(1, FORCE_POINTS // max(N, 1))
    done = np.zeros(D, dtype=np.int64)
    status = np.zeros(D, dtype=np.int64)
    red = [np.empty((D, slots.shape[0])) for _ in range(4)]
    fused = fused_level(module, slots, lev, meth)
    for a in range(0, D, step):
        b = min(D, a + step)
        part = [None if x is None else x[:b - a] for x in (Q, QD, QDD, INFO)]
        forces = None
        if fused is not None:       # the multipliers in the sweep's own step
            LAM = np.empty((b - a, N, int(module.N_EQS)))
            FACTORS = np.empty((b - a, N, len(module.DRIVER_ROWS)))
            PIV = np.empty((b - a, N))
            if FORCE_LEVELS[fused] == "dynamic":
                done[a:b] = two_steps(module, "sweep_designs_forces", ts, Q0[a:b], P[a:b],
                                      meth, tol, xtol, maxit, *part, FACTORS, PIV, LAM)
            else:                   # static: a position sweep, λ at q̇ = q̈ = 0
                done[a:b] = two_steps(module, "sweep_designs_statics", ts, Q0[a:b], P[a:b],
                                      meth, tol, xtol, maxit, part[0], part[3], FACTORS, PIV,
                                      LAM)
            forces = {fused: repaired(module, ts, P[a:b], *part[:3], done[a:b], LAM, FACTORS,
                                      PIV)}
        else:
            done[a:b] = sweep_chunk(module, ts, Q0[a:b], P[a:b], lev, tol, xtol, maxit, meth,
                                    *part)
        status[a:b] = design_status(part[3], done[a:b], N)
        for arr, got in zip(red, reduce_chunk(module, slots, ts, P[a:b], *part[:3], done[a:b],
                                              forces)):
            arr[a:b] = got
    return (done, status) + tuple(red)


def fused_level(module, slots, lev, meth):
    """The FORCE_LEVELS index of the force level every driver slot asks for where the
    module's quick path at it can solve the multipliers on its way in a table at
    kinematic level ``lev`` (forces.lookup.fused_path: "dynamic" in an acceleration table,
    sweep_designs_forces; "static" in a position one, sweep_designs_statics); else None."""
    orders = {int(order) for kind, _, order in slots if kind == DRIVER}
    if len(orders) != 1 or meth == METHOD["full"] or not (module.SORTED and module.LEVEL >= 2):
        return None
    order = orders.pop()
    return order if fused_path(module, FORCE_LEVELS[order], lev) is not None else None


class Collector:
    """Gathers the chunks' results into one TableData (full arrays or reductions)."""

    def __init__(self, D, N, nq, slots, lev=2):
        self.slots = slots
        self.done = np.zeros(D, dtype=np.int64)
        self.status = np.full(D, OK, dtype=np.int64)
        if slots is None:   # no derivative arrays above the table's level
            self.arrays = new_arrays(D, N, nq, lev)
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


def reduce_threads(module, slots, ts, P, Q, QD, QDD, done, workers=None):
    """reduce_chunk over every design of a solved table (a GPU's, whose points came back
    to the host for the multipliers), a few designs at a time on ``workers`` threads (None:
    every core): the compiled force loop releases the GIL, and a chunk's points stay in
    the cache while its multipliers are solved."""
    D, N = Q.shape[0], ts.shape[0]
    step = max(1, FORCE_POINTS // max(N, 1))
    spans = [(a, min(D, a + step)) for a in range(0, D, step)]
    workers = (os.cpu_count() or 1) if workers is None else workers
    if getattr(module, "__mechgen_tier__", "compiled") == "python" or len(spans) < 2:
        workers = 1

    def job(span):
        a, b = span
        return reduce_chunk(module, slots, ts, P[a:b], Q[a:b],
                            None if QD is None else QD[a:b],
                            None if QDD is None else QDD[a:b], done[a:b])
    if workers == 1:
        parts = [job(span) for span in spans]
    else:
        with ThreadPoolExecutor(max_workers=min(workers, len(spans))) as pool:
            parts = list(pool.map(job, spans))
    if not parts:
        return reduce_chunk(module, slots, ts, P, Q, QD, QDD, done)
    return tuple(np.concatenate([part[i] for part in parts]) for i in range(4))
