"""A sweep with sensitivities (``mech.sweep(..., sensitivities=)``): at position level, where
the sensitivity module has it (SWEEP_FUSED), the sweep's quick path is the module's
``sweep_fast_sensitivities`` (mechgen/compiler/sensitivity_sweep.py): the model module's
fast sweep with Dq = −Φ_q⁻¹ Φ_p written after its position code, run by the kinematics in
place of sweep_fast (kinematics.sweeping.compiled's ``quick``). The points it vouches for
take their derivatives from it; the careful continuation's points (and the seven before
them, so that the pass's sin and cos start where the pass over the whole sweep would
have started them afresh) take them from sensitivities_rows, as a sweep without the
fused path does (solve.of_sweep). Elsewhere: the sweep, then of_sweep."""
from __future__ import annotations

import numpy as np

from ..kinematics.solving import sweep as sweep_once
from .companion import companion
from .solve import Sensitivities, parameter_columns

TURN_EVERY = 8      # sensitivities_rows' trig_pairs computes sin and cos afresh this often


def sweep_with(mech, which, t0, t1, n, level, guess, method, tol, maxit, times, params, out,
               backend, workers, client, reduce, table_options):
    """Mechanism.sweep(...) with ``sensitivities=which``: the fused quick path where it
    applies, else the sweep and then its sensitivities (sensitivity.attach)."""
    if params is None and level.__class__ is str and level == "position" and \
            backend == "cpu" and workers is None and client is None and reduce is None \
            and not table_options:
        comp, blocks = companion(mech)
        if blocks.square and getattr(comp, "SWEEP_FUSED", False):
            return fused_sweep(mech, which, comp, blocks, t0, t1, n, guess, method, tol,
                               maxit, times, out)
    result = mech.sweep(t0, t1, n, level, guess, method, tol, maxit, times, params, out,
                        backend, workers, client, reduce, **table_options)
    from . import attach
    return attach(mech, result, which)


def fused_sweep(mech, which, comp, blocks, t0, t1, n, guess, method, tol, maxit, times, out):
    """A position sweep whose quick path solves the derivatives on its way."""
    names, cols = parameter_columns(mech, which)
    npar = len(mech.parameter_names)
    want = np.zeros(npar, dtype=np.bool_)
    want[cols] = True
    box = {}

    def quick(ts, q0, p, tol, xtol, maxit, Q, QD, QDD, S):
        N = ts.shape[0]
        # every selected column of a point is written; the others NaN (as of_sweep)
        DQ = np.empty((N, mech.n, npar)) if len(cols) == npar else \
            np.full((N, mech.n, npar), np.nan)
        box.update(DQ=DQ, DSTATUS=np.zeros(N, dtype=np.int64))
        box["count"] = count = comp.sweep_fast_sensitivities(
            ts, q0, p, tol, xtol, maxit, Q, QD, QDD, S, want, DQ, box["DSTATUS"])
        return count
    sw = sweep_once(mech.state, t0, t1, n, "position", guess=guess, method=method, tol=tol,
                    maxit=maxit, times=times, out=out, quick=quick)
    sw.sensitivities = of_fused(mech, sw, names, cols, comp, blocks, box)
    return sw


def of_fused(mech, sw, names, cols, comp, blocks, box) -> Sensitivities:
    """The Sensitivities of a position sweep from its fused quick path (``box``: its DQ,
    DSTATUS and the count it returned; empty where it did not run), the other points
    by sensitivities_rows."""
    N, n, npar = len(sw), mech.n, len(mech.parameter_names)
    if "DQ" not in box:
        from .solve import of_sweep
        return of_sweep(mech, sw, list(names))
    count = box.get("count", 0)
    vouched = count if count >= N else max(count - 1, 0)    # (compiled() resumes there)
    DQ = box["DQ"][:N]
    status = np.zeros(N, dtype=np.int64)
    status[:vouched] = box["DSTATUS"][:vouched]
    bad = np.flatnonzero(status)
    if bad.size:
        DQ[bad[:, None], :, cols[None, :]] = np.nan
    if vouched < N:
        start = vouched - vouched % TURN_EVERY
        ts = np.ascontiguousarray(sw.solved_t[start:], dtype=np.float64)
        Q = np.ascontiguousarray(sw.Q[start:], dtype=np.float64)
        none = np.zeros((1, n))
        comp.sensitivities_rows(ts, Q, none, none, np.asarray(mech.p, dtype=np.float64), 0,
                                blocks.brow, blocks.bvar, blocks.bstart, cols, DQ[start:],
                                np.empty((1, n, npar)), np.empty((1, n, npar)),
                                status[start:])
    return Sensitivities(names, cols, (DQ, None, None), status != 0)
