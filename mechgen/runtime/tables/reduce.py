"""Reductions of a design table: per design, the minimum and maximum of chosen quantities
over the solved times and the times they occur at, and the design's status, without
keeping every point (``mech.sweep(..., params=..., reduce=["X4", "X4d"])``), and at the
force levels the efforts of drivers (``reduce=["crank driver"]``: peak torque per design).

Every backend computes the same numbers from the same points: the CPU and Dask backends
reduce each chunk of designs as soon as it is solved (reduce_chunk, then its arrays are
dropped), the CUDA backend inside its kernel. numpy only.
"""
from __future__ import annotations

import numpy as np

from ...protocol import (FORCE_LEVELS, JUMP, OK, SING_RTOL, STATUS_CODE, STATUS_NAMES,
                         THROUGH_SINGULAR)
from ..forces.directions import load_ends, mark
from ..forces.lookup import tables
from ..forces.points import (by_blocks, driver_rows, efforts, has_forces, solve_points,
                            svd_point)
from ..quantity import lookup

# A reduction slot: [kind, index, order]; kind COORDINATE (index into the coordinates,
# order 0/1/2: Q, QD, QDD), OUTPUT (index into the outputs, order: which derivative) or
# DRIVER (index into the module's CONSTRAINTS, order: FORCE_LEVELS' index, its effort).
COORDINATE, OUTPUT, DRIVER = 0, 1, 2


def driver_slot(mech, name, force_level):
    """The slot of a driver's effort, or None when ``name`` names no driver."""
    tab = tables(mech)
    entry = tab.find(name, mech) if isinstance(name, (str, int)) else None
    if entry is None or not entry[2]:
        return None
    if force_level not in FORCE_LEVELS:
        raise ValueError(f"reduce: {name!r} is a driver: its effort needs a table at level "
                         "'static' or 'dynamic' (pass level=...)")
    label = entry[0]
    if has_forces(mech.module) and driver_rows(mech.module)[label][1] is None:
        raise ValueError(f"reduce: driver {label!r}: its effort is not defined (no driver "
                         "row)")
    k = next(i for i, c in enumerate(mech.module.CONSTRAINTS) if c[2] == label)
    return (DRIVER, k, FORCE_LEVELS.index(force_level))


def reduce_slots(mech, names, have, force_level=None):
    """(names, slots): the quantity names to reduce, checked against the mechanism and the
    table's level ``have`` (and ``force_level``, "static" or "dynamic", where drivers'
    efforts may be reduced: a driver's name), and their slots (an int64 array of rows
    [kind, index, order])."""
    if isinstance(names, str):
        names = [names]
    names = list(dict.fromkeys(names))
    if not names:
        raise ValueError("reduce: give at least one quantity name (reduce=['X4'])")
    slots = np.zeros((len(names), 3), dtype=np.int64)
    for j, name in enumerate(names):
        # a coordinate or output first, as the tables name their columns: a driver named
        # like one (a coordinate phi driven by the constraint "phi") is "phi effort" there
        try:
            kind, k, order = lookup(mech, name)
        except (KeyError, TypeError) as exc:
            slot = driver_slot(mech, name, force_level)
            if slot is None and isinstance(name, str) and name.endswith(" effort"):
                slot = driver_slot(mech, name[:-len(" effort")], force_level)
            if slot is not None:
                slots[j] = slot
                continue
            raise ValueError(f"reduce: {exc.args[0]}") from None
        need = order if kind == "q" else mech.output_orders[k] + order
        if need > have:
            raise ValueError(f"reduce: {name!r} needs a table at level "
                             f"{('position', 'velocity', 'acceleration')[min(need, 2)]} "
                             "(pass level=...)")
        slots[j] = (COORDINATE if kind == "q" else OUTPUT, k, order)
    return names, slots


def design_status(INFO, done, N) -> np.ndarray:
    """Per design (INFO: the table's int16 status rows, (designs, times, columns)): the status of the point it failed at, or, when it solved every time,
    JUMP if a point was reached by a branch jump, THROUGH_SINGULAR if one was reached
    through a singular configuration, else OK."""
    D = done.shape[0]
    status = np.full(D, OK, dtype=np.int64)
    if D == 0 or N == 0:
        return status
    st = INFO[:, :, STATUS_CODE]
    solved = np.arange(N)[None, :] < done[:, None]
    status[np.any(solved & (st == THROUGH_SINGULAR), axis=1)] = THROUGH_SINGULAR
    status[np.any(solved & (st == JUMP), axis=1)] = JUMP
    bad = np.nonzero(done < N)[0]
    status[bad] = st[bad, done[bad]].astype(np.int64)
    return status


def reduce_chunk(module, slots, ts, P, Q, QD, QDD, done, forces=None):
    """(min, max, tmin, tmax), each (designs, len(slots)), of a solved chunk of designs:
    over the times each design solved (the first occurrence of equal extremes); NaN for a
    design that solved no time. ``forces``: {force level's index: (LAM, FACTORS)} solved
    already (the sweep's own step, chunks._solve_forces)."""
    D, N = Q.shape[0], ts.shape[0]
    k = slots.shape[0]
    mn, mx = np.full((D, k), np.nan), np.full((D, k), np.nan)
    tmn, tmx = np.full((D, k), np.nan), np.full((D, k), np.nan)
    if D == 0 or N == 0:
        return mn, mx, tmn, tmx
    solved = np.arange(N)[None, :] < done[:, None]
    outs, forces = {}, dict(forces or {})
    for j, (kind, index, order) in enumerate(slots):
        if kind == COORDINATE:
            vals = (Q, QD, QDD)[order][:, :, index]
        elif kind == DRIVER:
            if order not in forces:
                forces[order] = _forces(module, ts, P, Q, QD, QDD, done, FORCE_LEVELS[order])
            vals = _efforts(module, forces[order], index, D, N)
        else:
            if order not in outs:
                outs[order] = _outputs(module, ts, P, Q, QD, QDD, done, order)
            vals = outs[order][:, :, index]
        counted = solved & np.isfinite(vals)    # (an effort is NaN where no force balance)
        anyp = counted.any(axis=1)
        lo = np.where(counted, vals, np.inf)
        hi = np.where(counted, vals, -np.inf)
        a, b = np.argmin(lo, axis=1), np.argmax(hi, axis=1)
        rows = np.arange(D)
        mn[anyp, j] = vals[rows, a][anyp]
        mx[anyp, j] = vals[rows, b][anyp]
        tmn[anyp, j] = ts[a][anyp]
        tmx[anyp, j] = ts[b][anyp]
    return mn, mx, tmn, tmx


def driver_efforts(module, ts, P, Q, QD, QDD, done, index, level) -> np.ndarray:
    """(designs, times): the effort of the driver CONSTRAINTS[index] at every point the
    designs solved, at force level ``level`` (NaN elsewhere)."""
    return _efforts(module, _forces(module, ts, P, Q, QD, QDD, done, level), index,
                    Q.shape[0], ts.shape[0])


def _forces(module, ts, P, Q, QD, QDD, done, level):
    """forces.points.solve_points for every design over the times it solved (None for a
    design that solved none); a module with force_rows_designs (a sorted build with mass
    or loads) solves the chunk in one compiled call instead (_forces_batch)."""
    if has_forces(module) and by_blocks(module) and hasattr(module, "force_rows_designs"):
        return _forces_batch(module, ts, P, np.ascontiguousarray(Q), QD, QDD,
                             np.ascontiguousarray(done, dtype=np.int64), level)
    return [solve_points(module, ts[:k], Q[d, :k], None if QD is None else QD[d, :k],
                         None if QDD is None else QDD[d, :k], P[d], level, extras=False)
            if k else None
            for d, k in enumerate(int(x) for x in done)]


def _forces_batch(module, ts, P, Q, QD, QDD, done, level):
    """(LAM, FACTORS), (designs, times, ·), of a chunk of designs by the module's compiled
    force_rows_designs (one call, the GIL released); the points whose block pivot falls
    below SING_RTOL solved by the SVD as solve_points does (NaN where no force balance)."""
    D, N, n = Q.shape
    m = int(module.N_EQS)
    if level == "static" or QD is None:
        QD = np.zeros_like(Q)
    if level == "static" or QDD is None:
        QDD = np.zeros_like(Q)
    LAM = np.full((D, N, m), np.nan)
    FACTORS = np.zeros((D, N, len(getattr(module, "DRIVER_ROWS", ()))))
    PIV = np.zeros((D, N))
    module.force_rows_designs(ts, Q, QD, QDD, P, done, FACTORS, PIV, LAM)
    return repaired(module, ts, P, Q, QD, QDD, done, LAM, FACTORS, PIV)


def repaired(module, ts, P, Q, QD, QDD, done, LAM, FACTORS, PIV):
    """(LAM, FACTORS) of a chunk whose multipliers a compiled loop solved, PIV the pivots'
    verdict per point: those below SING_RTOL (or not finite) solved by the SVD as
    solve_points does (NaN where no force balance), NaN at the times a design did not
    solve."""
    D, N, n = Q.shape
    m = LAM.shape[2]
    if QD is None:                  # a static table: at rest
        QD = QDD = np.zeros((D, N, n))
    solved = np.arange(N)[None, :] < done[:, None]
    LAM[~solved] = np.nan
    weak = solved & ~((PIV >= SING_RTOL) & np.all(np.isfinite(LAM), axis=2))
    if weak.any():
        J, terms = np.empty((m, n)), np.empty((3, n))
        for d, k in zip(*np.nonzero(weak)):
            lam, _, consistent = svd_point(module, Q[d, k], QD[d, k], QDD[d, k], ts[k],
                                           P[d], J, terms)
            LAM[d, k] = lam if consistent else np.nan
    for d in np.flatnonzero(done) if load_ends(module) else ():   # springs without direction
        mark(module, ts[:done[d]], Q[d, :done[d]], P[d], LAM[d, :done[d]])
    return LAM, FACTORS


def _efforts(module, forces, index, D, N):
    """(D, N): the effort of the driver CONSTRAINTS[index] at every solved point (NaN
    elsewhere, and where the force balance has no solution)."""
    rows, cols = driver_rows(module)[module.CONSTRAINTS[index][2]]
    if isinstance(forces, tuple):                   # _forces_batch's arrays
        LAM, FACTORS = forces
        if cols is None:
            return np.full((D, N), np.nan)
        return efforts(LAM, FACTORS, rows, cols)    # NaN already where not solved
    vals = np.full((D, N), np.nan)
    for d, pts in enumerate(forces):
        if pts is None:
            continue
        k = pts.LAM.shape[0]
        if not has_forces(module):
            vals[d, :k] = 0.0           # no mass, no loads: every λ is zero
        elif cols is not None:
            vals[d, :k] = efforts(pts.LAM, pts.FACTORS, rows, cols)
    return vals


def _outputs(module, ts, P, Q, QD, QDD, done, order):
    n_out = len(module.OUTPUTS)
    out = np.zeros((Q.shape[0], ts.shape[0], n_out))
    zero = np.zeros(Q.shape[1:])        # derivatives a table below their level lacks
    for d in range(Q.shape[0]):
        if done[d]:
            module.eval_outputs(Q[d], zero if QD is None else QD[d],
                                zero if QDD is None else QDD[d], ts, P[d], order, out[d])
    return out


class Reduction:
    """One reduced quantity of a design table: arrays indexed like the table's designs
    (``tab.shape``). ``min``/``max``: the smallest and largest value over the times a
    design solved, ``tmin``/``tmax``: the (first) times they occur at (grid times of the
    table; ``tab.extremes`` refines them exactly), ``ok``: designs solved at every time,
    ``status``: each design's status (mechgen.protocol codes; see design_status). A
    design that solved no time has NaN; a design that failed part way has the extremes of
    the part it solved, and ok False: check ``ok`` before trusting them."""

    def __init__(self, name, mn, mx, tmn, tmx, ok, status):
        self.name = name
        self.min, self.max, self.tmin, self.tmax = mn, mx, tmn, tmx
        self.ok = ok
        self.status = status

    @property
    def range(self) -> np.ndarray:
        """max - min per design."""
        return self.max - self.min

    def __repr__(self):
        bad = int(np.size(self.ok) - np.count_nonzero(self.ok))
        return (f"<Reduction {self.name!r} of {np.size(self.ok)} designs"
                f"{f', {bad} failed' if bad else ''}: min in [{np.nanmin(self.min):.6g}, "
                f"{np.nanmax(self.min):.6g}], max in [{np.nanmin(self.max):.6g}, "
                f"{np.nanmax(self.max):.6g}]>" if np.any(np.isfinite(self.min)) else
                f"<Reduction {self.name!r} of {np.size(self.ok)} designs, none solved>")


def status_name(code) -> str:
    """A status code in words (a failed velocity or acceleration solve says so)."""
    code = int(code)
    if code >= 20:
        return f"acceleration solve: {STATUS_NAMES.get(code - 20, code - 20)}"
    if code >= 10:
        return f"velocity solve: {STATUS_NAMES.get(code - 10, code - 10)}"
    return STATUS_NAMES.get(code, str(code))
