"""A tiny hand-written model that stands for a generated module, so that the library can
be imported, linted and tested on its own: a crank-slider.

    coordinates q = (th, ph, x): crank angle, rod angle, slider position
    parameters  p = (a, b, w):   crank length, rod length, crank speed
    Φ = (a cos th + b cos ph − x,  a sin th + b sin ph,  th − w t)

It defines every module-level name a generated module gives the library (``__all__``):
the header constants (from mechgen.protocol, as the renderer writes them), the model
constants (N_COORDS, SORTED, LEVEL, ...) and the model functions (phi, phi_q, ...,
position_sorted, derivatives_sorted, jacobian_det, sweep_fast). Its sorted solver takes
th from the driver, ph by Newton on the second row and x from the first: with a < b the
crank turns fully (cos ph > 0 throughout), with a > b the mechanism locks where
|sin th| = b / a (det Φ_q = b cos ph = 0).

``njit`` here, which the library files import too, is numba's without the on-disk cache:
numba's cache of a library function would not notice a change to these constants, which
live in another file. (A generated module has all of them in one file, and caches.)
"""
import math

import numba
import numpy as np

from ...protocol import (ACCELERATION, BRANCH_ATOL, BRANCH_DET_EVERY, BRANCH_HMIN,
                         BRANCH_NEAR, BRANCH_RATIO, BRANCH_TURN, CARRY_HMIN, CARRY_MAXIT,
                         GAVE_UP, INFO_ITERATIONS,
                         INFO_METHOD, INFO_RANK, INFO_REACH,
                         INFO_RESIDUAL, JUMP, METHOD_AUTO, METHOD_FULL, METHOD_SORTED,
                         NO_CONVERGENCE, NOT_FINITE, OK, PIVOT_RTOL, POINT_INFO_SIZE,
                         POINT_PIVOT, POINT_RESIDUAL, POSITION_INFO_SIZE, REPORT_FAILED,
                         REPORT_JUMP, REPORT_REACHED, REPORT_SIZE, REPORT_STATUS, SING_RTOL,
                         SINGULAR, STATUS_CODE, STATUS_COLUMNS, STATUS_ITERATIONS, STATUS_MAX,
                         STATUS_SUBSTEPS,
                         THROUGH_SINGULAR, TINY, VELOCITY)

__all__ = [
    # the header constants
    "ACCELERATION", "BRANCH_ATOL", "BRANCH_DET_EVERY", "BRANCH_HMIN", "BRANCH_NEAR",
    "BRANCH_RATIO", "BRANCH_TURN", "CARRY_HMIN", "CARRY_MAXIT",
    "GAVE_UP", "INFO_ITERATIONS", "INFO_METHOD", "INFO_RANK", "INFO_REACH", "INFO_RESIDUAL",
    "JUMP",
    "METHOD_AUTO", "METHOD_FULL", "METHOD_SORTED", "NO_CONVERGENCE", "NOT_FINITE", "OK",
    "PIVOT_RTOL", "POINT_INFO_SIZE", "POINT_PIVOT", "POINT_RESIDUAL", "POSITION_INFO_SIZE",
    "REPORT_FAILED", "REPORT_JUMP", "REPORT_REACHED", "REPORT_SIZE", "REPORT_STATUS",
    "SING_RTOL", "SINGULAR", "STATUS_CODE", "STATUS_COLUMNS", "STATUS_ITERATIONS",
    "STATUS_MAX", "STATUS_SUBSTEPS", "THROUGH_SINGULAR", "TINY", "VELOCITY",
    # the model constants
    "N_COORDS", "N_EQS", "ROW_WRAPS", "SORTED", "LEVEL", "ALL_SOLVED", "REACH", "INLINE",
    # the model functions
    "njit", "phi", "phi_q", "nu", "gamma", "points", "outputs", "outputs_d", "outputs_dd",
    "position_sorted", "velocity_sorted", "acceleration_sorted", "derivatives_sorted",
    "jacobian_det", "reach", "sweep_fast",
]
# what a module built with mass or loads defines besides (library/forces.py reads them)
FORCE_NAMES = [
    "FORCE_SORTED", "FORCE_POINT", "FORCE_BLOCK_START", "FORCE_BLOCK_ROWS",
    "FORCE_BLOCK_COLS", "force_terms", "energies", "driver_factors", "mass_matrix",
    "multipliers_point", "sweep_fast_forces", "sweep_fast_statics",
]
__all__ += FORCE_NAMES
# what a sensitivity module defines (library/sensitivity.py reads them with N_COORDS,
# N_EQS, phi_q, SING_RTOL and TINY); not in __all__: a module does not define them
SENSITIVITY_NAMES = ["N_PARAMS", "phi_p", "velocity_rhs_p", "acceleration_rhs_p",
                     "solve_sorted", "position_sensitivities", "TURNED"]


def njit(*args, **options):
    """numba.njit, less the on-disk cache (see the module docstring)."""
    options.pop("cache", None)
    return numba.njit(*args, **options)


# -- module body: below this line, the text as a generated module holds it --
N_COORDS = 3
N_EQS = 3
ROW_WRAPS = (False, False, False)
COORDINATES = ("th", "ph", "x")
PARAMETERS = ("a", "b", "w")
PARAMETER_DEFAULTS = (1.0, 2.0, 1.0)
GUESS = (0.0, 0.1, 2.5)
SORTED = True
LEVEL = 2
ALL_SOLVED = True
REACH = False
INLINE = "never"


@njit(cache=True)
def phi(q, t, p, out):
    """Constraint residuals Φ(q, t)."""
    a, b, w = p[0], p[1], p[2]
    out[0] = a * math.cos(q[0]) + b * math.cos(q[1]) - q[2]
    out[1] = a * math.sin(q[0]) + b * math.sin(q[1])
    out[2] = q[0] - w * t


@njit(cache=True)
def phi_q(q, t, p, out):
    """Jacobian Φ_q."""
    a, b = p[0], p[1]
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            out[i, j] = 0.0
    out[0, 0] = -a * math.sin(q[0])
    out[0, 1] = -b * math.sin(q[1])
    out[0, 2] = -1.0
    out[1, 0] = a * math.cos(q[0])
    out[1, 1] = b * math.cos(q[1])
    out[2, 0] = 1.0


@njit(cache=True)
def nu(q, t, p, out):
    """Velocity right side ν = −Φ_t."""
    out[0] = 0.0
    out[1] = 0.0
    out[2] = p[2]


@njit(cache=True)
def gamma(q, qd, t, p, out):
    """Acceleration right side γ = −(Φ_q q̇)_q q̇ (Φ_qt = Φ_tt = 0)."""
    a, b = p[0], p[1]
    out[0] = a * math.cos(q[0]) * qd[0] ** 2 + b * math.cos(q[1]) * qd[1] ** 2
    out[1] = a * math.sin(q[0]) * qd[0] ** 2 + b * math.sin(q[1]) * qd[1] ** 2
    out[2] = 0.0


@njit(cache=True)
def points(q, t, p, out):
    """The crank's pivot, the crank pin, the slider."""
    out[0, 0] = 0.0
    out[0, 1] = 0.0
    out[1, 0] = p[0] * math.cos(q[0])
    out[1, 1] = p[0] * math.sin(q[0])
    out[2, 0] = q[2]
    out[2, 1] = 0.0


@njit(cache=True)
def outputs(q, qd, qdd, t, p, out):
    """The slider position."""
    out[0] = q[2]


@njit(cache=True)
def outputs_d(q, qd, qdd, t, p, out):
    """Its velocity."""
    out[0] = qd[2]


@njit(cache=True)
def outputs_dd(q, qd, qdd, t, p, out):
    """Its acceleration."""
    out[0] = qdd[2]


@njit(cache=True, inline=INLINE)
def position_sorted(q, t, p, tol, xtol, maxit, info):
    """th from the driver, ph by Newton on row 1, x from row 0; q written on success."""
    a, b, w = p[0], p[1], p[2]
    th = w * t
    ph = q[1]
    for it in range(maxit):
        r = a * math.sin(th) + b * math.sin(ph)
        d = b * math.cos(ph)
        if not abs(d) > PIVOT_RTOL * abs(b):
            return GAVE_UP
        s = r / d
        ph -= s
        if abs(r) <= tol and abs(s) <= xtol * (1.0 + abs(ph)):
            break
    else:
        return NO_CONVERGENCE
    q[0] = th
    q[1] = ph
    q[2] = a * math.cos(th) + b * math.cos(ph)
    info[INFO_ITERATIONS] = it + 1
    return OK


@njit(cache=True)
def velocity_sorted(q, t, p, out):
    """Φ_q q̇ = ν block by block."""
    a, b, w = p[0], p[1], p[2]
    d = b * math.cos(q[1])
    if not abs(d) > SING_RTOL * abs(b):
        return SINGULAR
    out[0] = w
    out[1] = -a * math.cos(q[0]) * out[0] / d
    out[2] = -a * math.sin(q[0]) * out[0] - b * math.sin(q[1]) * out[1]
    return OK


@njit(cache=True)
def acceleration_sorted(q, qd, t, p, out):
    """Φ_q q̈ = γ block by block."""
    a, b = p[0], p[1]
    d = b * math.cos(q[1])
    if not abs(d) > SING_RTOL * abs(b):
        return SINGULAR
    s0, c0, s1, c1 = math.sin(q[0]), math.cos(q[0]), math.sin(q[1]), math.cos(q[1])
    out[0] = 0.0
    out[1] = (a * s0 * qd[0] ** 2 + b * s1 * qd[1] ** 2 - a * c0 * out[0]) / d
    out[2] = -a * s0 * out[0] - b * s1 * out[1] - a * c0 * qd[0] ** 2 - b * c1 * qd[1] ** 2
    return OK


@njit(cache=True)
def jacobian_det(q, t, p, piv):
    """det Φ_q = b cos ph into piv[0] (returned), the pattern of its sign into piv[1]."""
    piv[0] = p[1] * math.cos(q[1])
    piv[1] = 1.0 if piv[0] < 0.0 else 0.0
    return piv[0]


@njit(cache=True)
def reach(q, t, p):
    """No block solved whatever its guess (REACH False): 1.0."""
    return 1.0


@njit(cache=True, inline=INLINE)
def derivatives_sorted(q, t, p, qd, qdd, piv):
    """Velocities and accelerations; piv as jacobian_det's."""
    jacobian_det(q, t, p, piv)
    status = velocity_sorted(q, t, p, qd)
    if status != OK:
        return status
    return acceleration_sorted(q, qd, t, p, qdd)


@njit(cache=True)
def sweep_fast(ts, q0, p, tol, xtol, maxit, Q, QD, QDD, STATUS):
    """The quick path: a Taylor predictor, the sorted solvers; the count of points
    accepted before the first that fails, corrects its predictor too much or changes
    the sign of det Φ_q. QD and QDD with no rows are not written, nor STATUS's
    iterations when it has one column."""
    q = q0.copy()
    qd = np.zeros(N_COORDS)
    qdd = np.zeros(N_COORDS)
    qp = q0.copy()
    piv = np.zeros(2)
    info = np.zeros(POSITION_INFO_SIZE)
    det = 0.0
    sig = 0.0
    for k in range(ts.shape[0]):
        move = 0.0
        size = 0.0
        if k > 0:
            h = ts[k] - ts[k - 1]
            for j in range(N_COORDS):
                dq = h * (qd[j] + 0.5 * h * qdd[j])
                move = max(move, abs(dq))
                size = max(size, abs(q[j]))
                q[j] += dq
                qp[j] = q[j]
        if position_sorted(q, ts[k], p, tol, xtol, maxit, info) != OK:
            return k
        if derivatives_sorted(q, ts[k], p, qd, qdd, piv) != OK:
            return k
        corr = 0.0
        for j in range(N_COORDS):
            corr = max(corr, abs(q[j] - qp[j]))
        if k > 0 and (corr > BRANCH_RATIO * move + BRANCH_ATOL * (1.0 + size) or
                      not piv[0] * det > 0.0 or piv[1] != sig):
            return k
        det = piv[0]
        sig = piv[1]
        for j in range(N_COORDS):
            Q[k, j] = q[j]
        if QD.shape[0] > 0:
            for j in range(N_COORDS):
                QD[k, j] = qd[j]
        if QDD.shape[0] > 0:
            for j in range(N_COORDS):
                QDD[k, j] = qdd[j]
        STATUS[k, STATUS_CODE] = OK
        if STATUS.shape[1] > STATUS_ITERATIONS:
            STATUS[k, STATUS_ITERATIONS] = min(info[INFO_ITERATIONS], STATUS_MAX)
        if STATUS.shape[1] > STATUS_SUBSTEPS:
            STATUS[k, STATUS_SUBSTEPS] = 0
    return ts.shape[0]


# -- the force functions of a module built with mass or loads (library/forces.py): the toy
# has neither, so every force is zero; its blocks in the solving order are th (row 2, the
# driver), ph (row 1), x (row 0)
FORCE_SORTED = True
FORCE_POINT = False
FORCE_BLOCK_START = np.array((0, 1, 2, 3), dtype=np.int64)
FORCE_BLOCK_ROWS = np.array((2, 1, 0), dtype=np.int64)
FORCE_BLOCK_COLS = np.array((0, 1, 2), dtype=np.int64)


@njit(cache=True)
def force_terms(q, qd, qdd, t, p, out):
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            out[i, j] = 0.0


@njit(cache=True)
def energies(q, qd, t, p, out):
    for i in range(out.shape[0]):
        out[i] = 0.0


@njit(cache=True)
def driver_factors(q, t, p, out):
    out[0] = -1.0


@njit(cache=True)
def mass_matrix(q, t, p, out):
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            out[i, j] = 0.0


@njit(cache=True)
def multipliers_point(q, qd, qdd, t, p, lam):
    return 0.0


@njit(cache=True)
def sweep_fast_forces(ts, q0, p, tol, xtol, maxit, Q, QD, QDD, STATUS, LAM, FACTORS, FPIV):
    """sweep_fast with the multipliers of every point it accepts (FPIV 1.0, or 0.0 where
    a pivot fell below SING_RTOL), as a module whose multipliers are written out has it."""
    done = sweep_fast(ts, q0, p, tol, xtol, maxit, Q, QD, QDD, STATUS)
    for k in range(done):
        driver_factors(Q[k], ts[k], p, FACTORS[k])
        piv = multipliers_point(Q[k], QD[k], QDD[k], ts[k], p, LAM[k])
        FPIV[k] = 1.0 if piv >= SING_RTOL else 0.0
    return done


@njit(cache=True)
def sweep_fast_statics(ts, q0, p, tol, xtol, maxit, Q, QD, QDD, STATUS, LAM, FACTORS, FPIV):
    """sweep_fast_forces for a static sweep (QD, QDD without rows): the multipliers at
    q̇ = q̈ = 0 of every point it accepts."""
    done = sweep_fast(ts, q0, p, tol, xtol, maxit, Q, QD, QDD, STATUS)
    zero = np.zeros(Q.shape[1])
    for k in range(done):
        driver_factors(Q[k], ts[k], p, FACTORS[k])
        piv = multipliers_point(Q[k], zero, zero, ts[k], p, LAM[k])
        FPIV[k] = 1.0 if piv >= SING_RTOL else 0.0
    return done


# -- what a sensitivity module defines (library/sensitivity.py reads them) ------------------
N_PARAMS = 3


@njit(cache=True)
def phi_p(q, t, p, out):
    """∂Φ/∂p (the columns a, b, w)."""
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            out[i, j] = 0.0
    out[0, 0] = math.cos(q[0])
    out[0, 1] = math.cos(q[1])
    out[1, 0] = math.sin(q[0])
    out[1, 1] = math.sin(q[1])
    out[2, 2] = -t


@njit(cache=True)
def velocity_rhs_p(q, qd, t, p, DQ, sel, out):
    """(ν − Φ_q q̇)_q DQ + (ν − Φ_q q̇)_p on the columns sel."""
    a, b = p[0], p[1]
    c0, s0, c1, s1 = math.cos(q[0]), math.sin(q[0]), math.cos(q[1]), math.sin(q[1])
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            out[i, j] = 0.0
    out[0, 0] = s0 * qd[0]
    out[0, 1] = s1 * qd[1]
    out[1, 0] = -c0 * qd[0]
    out[1, 1] = -c1 * qd[1]
    out[2, 2] = 1.0
    for k in range(sel.shape[0]):
        c = sel[k]
        out[0, c] += a * c0 * qd[0] * DQ[0, c] + b * c1 * qd[1] * DQ[1, c]
        out[1, c] += a * s0 * qd[0] * DQ[0, c] + b * s1 * qd[1] * DQ[1, c]


@njit(cache=True)
def acceleration_rhs_p(q, qd, qdd, t, p, DQ, DQD, sel, out):
    """(γ − Φ_q q̈)_q DQ + (γ − Φ_q q̈)_q̇ DQD + (γ − Φ_q q̈)_p on the columns sel."""
    a, b = p[0], p[1]
    c0, s0, c1, s1 = math.cos(q[0]), math.sin(q[0]), math.cos(q[1]), math.sin(q[1])
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            out[i, j] = 0.0
    out[0, 0] = c0 * qd[0] ** 2 + s0 * qdd[0]
    out[0, 1] = c1 * qd[1] ** 2 + s1 * qdd[1]
    out[1, 0] = s0 * qd[0] ** 2 - c0 * qdd[0]
    out[1, 1] = s1 * qd[1] ** 2 - c1 * qdd[1]
    for k in range(sel.shape[0]):
        c = sel[k]
        out[0, c] += (a * (-s0 * qd[0] ** 2 + c0 * qdd[0]) * DQ[0, c]
                      + b * (-s1 * qd[1] ** 2 + c1 * qdd[1]) * DQ[1, c]
                      + 2 * a * c0 * qd[0] * DQD[0, c] + 2 * b * c1 * qd[1] * DQD[1, c])
        out[1, c] += (a * (c0 * qd[0] ** 2 + s0 * qdd[0]) * DQ[0, c]
                      + b * (c1 * qd[1] ** 2 + s1 * qdd[1]) * DQ[1, c]
                      + 2 * a * s0 * qd[0] * DQD[0, c] + 2 * b * s1 * qd[1] * DQD[1, c])


@njit(cache=True)
def solve_sorted(q, t, p, B, sel, X):
    """Φ_q X = B on the columns sel in the toy's solving order: th (row 2), ph (row 1), x
    (row 0)."""
    a, b = p[0], p[1]
    j10, j11 = a * math.cos(q[0]), b * math.cos(q[1])
    j00, j01 = -a * math.sin(q[0]), -b * math.sin(q[1])
    if not abs(j11) > SING_RTOL * (abs(j10) + abs(j11)):
        return 2
    for k in range(sel.shape[0]):
        c = sel[k]
        th = B[2, c]
        ph = (B[1, c] - j10 * th) / j11
        X[0, c] = th
        X[1, c] = ph
        X[2, c] = -(B[0, c] - j00 * th - j01 * ph)
    return 0


TURNED = np.array((0, 1), dtype=np.int64)      # th, ph: their sin and cos read from sc


@njit(cache=True)
def position_sensitivities(q, sc, t, p, want, X):
    """Dq = −Φ_q⁻¹ Φ_p for the columns with want[j], in one pass (the module's is written
    out from the plan): th, then ph, then x, as solve_sorted; sin and cos from sc."""
    a, b = p[0], p[1]
    c0, s0, c1, s1 = sc[1, 0], sc[0, 0], sc[1, 1], sc[0, 1]
    j10, j11 = a * c0, b * c1
    j00, j01 = -a * s0, -b * s1
    if not abs(j11) > SING_RTOL * (abs(j10) + abs(j11)):
        return 2
    rhs = ((-c0, -s0, 0.0), (-c1, -s1, 0.0), (0.0, 0.0, t))    # −Φ_p's columns
    for c in range(3):
        if want[c]:
            b0, b1, b2 = rhs[c]
            th = b2
            ph = (b1 - j10 * th) / j11
            X[0, c] = th
            X[1, c] = ph
            X[2, c] = -(b0 - j00 * th - j01 * ph)
    return 0
