"""The design-table loops of a generated module with masses or loads that solve the
multipliers in the tables' own sweeps: each design's quick path solves them on its way
(sweep_fast_forces, sweep_fast_statics), the careful rest of it by force_rows after
sweep(). Each loop comes in two steps, as designs.py's sweep_designs does: the quick
paths of every design (``*_fast``), then the careful rests (``*_rest``), which the runtime
calls only where a design's quick path stopped early, so that a table of easy designs
never compiles the careful sweep; ``sweep_designs_forces`` and ``sweep_designs_statics``
make the two calls in one, for a user's own code.

The renderer copies the body below the marker into a module built with mass or loads,
after forces.py's; toy.py stands for the module's names here (see forces.py).
"""
import numpy as np

from .designs import sweep_on
from .forces import force_rows
from .toy import N_COORDS, REPORT_SIZE, njit, sweep_fast_forces, sweep_fast_statics

# -- module body: below this line, the text as a generated module holds it --
# ---------------------------------------------------------------------------------------
# Design tables solving the multipliers in their own sweeps
# ---------------------------------------------------------------------------------------
@njit(cache=True, nogil=True)
def sweep_designs_forces(ts, Q0, P, method, tol, xtol, maxit, Q, QD, QDD, STATUS, FACTORS,
                         PIV, LAM):
    """sweep_designs at level acceleration with the multipliers of a dynamic table: each
    design's quick path solves them on its way (sweep_fast_forces), the careful rest of
    it by force_rows after sweep(). Row d of FACTORS, PIV and LAM receives design d's at
    the times it solved (PIV below SING_RTOL: that λ is not to be used, the runtime
    solves it by the SVD). Only for a module that has sweep_fast_forces (its multipliers
    written out). Returns the count of solved times of each design; releases the GIL.
    (sweep_designs_forces_fast, then sweep_designs_forces_rest.)"""
    start = np.zeros(P.shape[0], dtype=np.int64)
    sweep_designs_forces_fast(ts, Q0, P, tol, xtol, maxit, Q, QD, QDD, STATUS, FACTORS, PIV,
                              LAM, start)
    return sweep_designs_forces_rest(ts, Q0, P, method, tol, xtol, maxit, Q, QD, QDD, STATUS,
                                     FACTORS, PIV, LAM, start)


@njit(cache=True, nogil=True)
def sweep_designs_forces_fast(ts, Q0, P, tol, xtol, maxit, Q, QD, QDD, STATUS, FACTORS, PIV,
                              LAM, START):
    """The quick path of every design of a dynamic table, the multipliers solved on its
    way (sweep_fast_forces): START[d] the count of times it accepted. Releases the GIL."""
    for d in range(P.shape[0]):
        START[d] = sweep_fast_forces(ts, Q0[d], P[d], tol, xtol, maxit, Q[d], QD[d], QDD[d],
                                     STATUS[d], LAM[d], FACTORS[d], PIV[d])


@njit(cache=True, nogil=True)
def sweep_designs_forces_rest(ts, Q0, P, method, tol, xtol, maxit, Q, QD, QDD, STATUS,
                              FACTORS, PIV, LAM, START):
    """The careful rest of every design of a dynamic table after its quick path accepted
    START[d] points: sweep() from the last of them, then force_rows over what it solved.
    Returns the count of solved times of each design; releases the GIL."""
    done = np.zeros(P.shape[0], dtype=np.int64)
    report = np.zeros(REPORT_SIZE)
    _jac = np.empty((1, LAM.shape[2], N_COORDS))
    _terms = np.empty((0, 3, N_COORDS))
    _nu = np.empty((0, LAM.shape[2]))
    _energy = np.empty((0, 3))
    for d in range(P.shape[0]):
        fast = START[d]
        k = sweep_on(ts, Q0[d], P[d], np.int64(2), tol, xtol, maxit, method, Q[d], QD[d], QDD[d],
                     STATUS[d], fast, report)
        done[d] = k
        start = max(fast - 1, 0)            # where sweep() went on (its points: not yet)
        if fast < ts.shape[0] and k > start:
            force_rows(ts[start:k], Q[d, start:k], QD[d, start:k], QDD[d, start:k], P[d],
                       _jac, _terms, _nu, _energy, FACTORS[d, start:k], PIV[d, start:k],
                       LAM[d, start:k])
    return done


@njit(cache=True, nogil=True)
def sweep_designs_statics(ts, Q0, P, method, tol, xtol, maxit, Q, STATUS, FACTORS, PIV, LAM):
    """sweep_designs at level position with the multipliers of a static table: each
    design's quick path solves them on its way (sweep_fast_statics), the careful rest of
    it by force_rows (q̇ = q̈ = 0) after sweep(); rows as sweep_designs_forces'. Only for
    a module whose STATIC_FUSED is True. Returns the count of solved times of each
    design; releases the GIL. (sweep_designs_statics_fast, then
    sweep_designs_statics_rest.)"""
    start = np.zeros(P.shape[0], dtype=np.int64)
    sweep_designs_statics_fast(ts, Q0, P, tol, xtol, maxit, Q, STATUS, FACTORS, PIV, LAM,
                               start)
    return sweep_designs_statics_rest(ts, Q0, P, method, tol, xtol, maxit, Q, STATUS, FACTORS,
                                      PIV, LAM, start)


@njit(cache=True, nogil=True)
def sweep_designs_statics_fast(ts, Q0, P, tol, xtol, maxit, Q, STATUS, FACTORS, PIV, LAM,
                               START):
    """The position quick path of every design of a static table, the multipliers at rest
    solved on its way (sweep_fast_statics): START[d] the count of times it accepted.
    Releases the GIL."""
    _none = np.zeros((0, N_COORDS))         # a position sweep: no derivative rows
    for d in range(P.shape[0]):
        START[d] = sweep_fast_statics(ts, Q0[d], P[d], tol, xtol, maxit, Q[d], _none, _none,
                                      STATUS[d], LAM[d], FACTORS[d], PIV[d])


@njit(cache=True, nogil=True)
def sweep_designs_statics_rest(ts, Q0, P, method, tol, xtol, maxit, Q, STATUS, FACTORS, PIV,
                               LAM, START):
    """The careful rest of every design of a static table after its quick path accepted
    START[d] points: a position sweep() from the last of them, then force_rows (q̇ = q̈ = 0)
    over what it solved. Returns the count of solved times of each design; releases the
    GIL."""
    done = np.zeros(P.shape[0], dtype=np.int64)
    report = np.zeros(REPORT_SIZE)
    _none = np.zeros((0, N_COORDS))         # a position sweep: no derivative rows
    _still = np.zeros((ts.shape[0], N_COORDS))
    _jac = np.empty((1, LAM.shape[2], N_COORDS))
    _terms = np.empty((0, 3, N_COORDS))
    _nu = np.empty((0, LAM.shape[2]))
    _energy = np.empty((0, 3))
    for d in range(P.shape[0]):
        fast = START[d]
        k = sweep_on(ts, Q0[d], P[d], np.int64(0), tol, xtol, maxit, method, Q[d], _none,
                     _none, STATUS[d], fast, report)
        done[d] = k
        start = max(fast - 1, 0)            # where sweep() went on (its points: not yet)
        if fast < ts.shape[0] and k > start:
            force_rows(ts[start:k], Q[d, start:k], _still[start:k], _still[start:k], P[d],
                       _jac, _terms, _nu, _energy, FACTORS[d, start:k], PIV[d, start:k],
                       LAM[d, start:k])
    return done
