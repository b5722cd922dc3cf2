"""The solvers of one configuration: the full Newton and the full velocity/acceleration
solves (rank-revealing, for any model), and the entry points that try the model's sorted
block solvers first (solve_position, solve_velocity, solve_acceleration, solve_point,
solve_point_derivatives).

Everything below the marker line goes verbatim into every generated module; the imports
above it stand for what a generated module defines (the toy model's here). The sorted
solvers are used only where the module built them: SORTED and LEVEL are constants of the
module, which numba compiles in, so the branches of a module without them cost nothing.
"""

import math

import numpy as np

from .linalg import _det, _fp_eliminate, _fp_solve, _consistent, _max_abs
from .toy import (ACCELERATION, ALL_SOLVED, INFO_ITERATIONS, INFO_METHOD, INFO_RANK,
                  INFO_RESIDUAL, METHOD_FULL, METHOD_SORTED, LEVEL, N_COORDS, N_EQS,
                  ROW_WRAPS,
                  NO_CONVERGENCE, NOT_FINITE, OK, PIVOT_RTOL, POINT_PIVOT, POINT_RESIDUAL,
                  SING_RTOL, SINGULAR, SORTED, VELOCITY, acceleration_sorted, gamma,
                  jacobian_det, nu, phi, phi_q, position_sorted, velocity_sorted, njit)

# -- module body: below this line, the text as a generated module holds it --
# ---------------------------------------------------------------------------------------
# Solvers
# ---------------------------------------------------------------------------------------
@njit(cache=True)
def pivot_ratio(q, t, p):
    """How far Φ_q(q, t) is from losing rank: the smallest pivot of the full-pivoting
    elimination of the row-equilibrated Φ_q (each row scaled to 1), 0.0 when its rank is
    below N_COORDS. Below SING_RTOL the configuration is singular (toggle, dead centre):
    velocities and accelerations are then not determined by the constraints."""
    J = np.empty((N_EQS, N_COORDS))
    b = np.zeros(N_EQS)
    phi_q(q, t, p, J)
    rank, small = _fp_eliminate(J, b, np.arange(N_COORDS), 0.0)
    if rank < N_COORDS:
        return 0.0
    return small


@njit(cache=True)
def newton_full(q, t, p, tol, xtol, maxit, info):
    """Newton on all coordinates with a rank-revealing solve and step halving.
    info = [iterations, residual, rank, method]. It stops where the step is within xtol
    and max|Φ| within tol, or within the rounding of Φ's rows where that is larger
    (64 eps Σ_j |∂Φ_i/∂q_j| (1 + |q_j|): rows such as ‖r1 − r2‖² − d² grow with the
    square of the unit of length, and a model in micrometres cannot meet tol = 1e-10)."""
    r = np.empty(N_EQS)
    rt = np.empty(N_EQS)
    J = np.empty((N_EQS, N_COORDS))
    dx = np.empty(N_COORDS)
    qt = np.empty(N_COORDS)
    phi(q, t, p, r)
    res = _max_abs(r)
    rank = N_COORDS
    for it in range(maxit):
        if not res < np.inf:
            info[INFO_ITERATIONS] = it
            info[INFO_RESIDUAL] = res
            return NOT_FINITE
        phi_q(q, t, p, J)
        floor = 0.0             # the rounding of Φ's rows at q
        for i in range(N_EQS):
            s = 0.0
            for j in range(N_COORDS):
                s += abs(J[i, j]) * (1.0 + abs(q[j]))
            floor = max(floor, s)
        near = res <= tol or res <= 64.0 * 2.220446049250313e-16 * floor
        rank = _fp_solve(J, r.copy(), dx, PIVOT_RTOL)
        step = 0.0
        for j in range(N_COORDS):
            step = max(step, abs(dx[j]) / (1.0 + abs(q[j])))
        if near and step > xtol:
            # At a singular configuration (a toggle reached exactly) the residual is within
            # tol but the step along the lost direction is noise: judge the step on the
            # directions Φ_q still determines (pivots above SING_RTOL).
            phi_q(q, t, p, J)
            srank = _fp_solve(J, r.copy(), dx, SING_RTOL)
            if srank < N_COORDS:
                rank = srank
                step = 0.0
                for j in range(N_COORDS):
                    step = max(step, abs(dx[j]) / (1.0 + abs(q[j])))
        if near and step <= xtol:
            for j in range(N_COORDS):
                q[j] -= dx[j]
            info[INFO_ITERATIONS] = it + 1
            info[INFO_RESIDUAL] = res
            info[INFO_RANK] = rank
            return OK
        lam = 1.0
        for _half in range(12):
            for j in range(N_COORDS):
                qt[j] = q[j] - lam * dx[j]
            phi(qt, t, p, rt)
            rest = _max_abs(rt)
            if rest < res or near or lam < 1.0 / 1000.0:
                break
            lam *= 0.5
        for j in range(N_COORDS):
            q[j] = qt[j]
        for i in range(N_EQS):
            r[i] = rt[i]
        res = rest
    info[INFO_ITERATIONS] = maxit
    info[INFO_RESIDUAL] = res
    info[INFO_RANK] = rank
    return NO_CONVERGENCE


@njit(cache=True)
def velocity_full(q, t, p, out):
    """Φ_q q̇ = ν by the rank-revealing solve; SINGULAR when Φ_q has lost rank (a pivot
    below SING_RTOL) or redundant equations disagree: the constraints do not determine q̇."""
    J = np.empty((N_EQS, N_COORDS))
    b = np.empty(N_EQS)
    phi_q(q, t, p, J)
    nu(q, t, p, b)
    rank = _fp_solve(J, b, out, SING_RTOL)
    if rank < N_COORDS or not _consistent(b, rank, out):
        return SINGULAR
    return OK


@njit(cache=True)
def acceleration_full(q, qd, t, p, out):
    """Φ_q q̈ = γ by the rank-revealing solve; SINGULAR when Φ_q has lost rank (a pivot
    below SING_RTOL) or redundant equations disagree: the constraints do not determine q̈."""
    J = np.empty((N_EQS, N_COORDS))
    b = np.empty(N_EQS)
    phi_q(q, t, p, J)
    gamma(q, qd, t, p, b)
    rank = _fp_solve(J, b, out, SING_RTOL)
    if rank < N_COORDS or not _consistent(b, rank, out):
        return SINGULAR
    return OK


@njit(cache=True, inline="always")
def derivatives_in_turn(q, t, p, qd, qdd, piv):
    """velocity_sorted(), then acceleration_sorted(): the combined pass of a model whose
    solvers are too large for one function. piv: as jacobian_det's (no det Φ_q on the
    way)."""
    jacobian_det(q, t, p, piv)
    status = velocity_sorted(q, t, p, qd)
    if status != OK:
        return status
    return acceleration_sorted(q, qd, t, p, qdd)


@njit(cache=True, inline="always")
def jacobian_det_full(q, t, p):
    """det Φ_q by elimination of the whole Jacobian (a module without block structure);
    1.0 when Φ_q is not square."""
    if N_EQS != N_COORDS:
        return 1.0
    J = np.empty((N_EQS, N_COORDS))
    phi_q(q, t, p, J)
    return _det(J)


@njit(cache=True)
def unwrap_turns(q, t, p):
    """Turn the guess's angles by whole turns, in place, so that the rows linear in them
    (drivers, relative rotations) hold as nearly as they can: a guess is the same
    configuration whatever multiple of 2π its angles carry, and Newton must start from
    the one the drivers ask for (else its first step turns the driven angle by 2π and
    drags the other coordinates into another assembly mode). An angle here is a
    coordinate that Φ sees only through periodic rows (unchanged when it turns by 2π,
    as sweep() tests) and rows linear in it (changed by 2π times their derivative).

    A gear's rolling row (ROW_WRAPS) counts turns of a wrapped angle: it never decides
    a driven angle, and a gear's angle that no driver reads is turned afterwards, from
    the driven end of the train: by the whole turns (up to three either way) that bring
    its rolling rows nearest to 0, once every other angle those rows read is settled.
    Returns the count of coordinates turned."""
    r0 = np.empty(N_EQS)
    r1 = np.empty(N_EQS)
    r2 = np.empty(N_EQS)
    d = np.empty(N_EQS)
    J = np.empty((N_EQS, N_COORDS))
    geared = np.zeros(N_COORDS, dtype=np.bool_)     # an angle only turn counts decide
    phi(q, t, p, r0)
    if not _max_abs(r0) < np.inf:
        return 0
    phi_q(q, t, p, J)
    turned = 0
    for j in range(N_COORDS):
        qj = q[j]
        q[j] = qj + 2.0 * math.pi
        phi(q, t, p, r1)
        q[j] = qj - 2.0 * math.pi       # a row linear in it changes by as much the other
        phi(q, t, p, r2)                # way (a gear's rolling row, with its jump, may not)
        q[j] = qj
        seen = False            # a periodic row depends on it: it is an angle
        linear = False          # a row it enters linearly: a whole turn changes it
        other = False           # a row neither (a gear's rolling row counts its turns)
        for i in range(N_EQS):
            d[i] = r1[i] - r0[i]
            if ROW_WRAPS[i] and (J[i, j] != 0.0 or d[i] != 0.0):
                other = True    # a sawtooth may look linear over one turn: never asked
                d[i] = 0.0
            elif abs(d[i]) <= 1e-9 * (1.0 + abs(r0[i])):
                d[i] = 0.0
                if J[i, j] != 0.0:
                    seen = True
            elif abs(d[i] - 2.0 * math.pi * J[i, j]) <= 1e-9 * (1.0 + abs(d[i]) + abs(r0[i])) \
                    and abs(r0[i] - r2[i] - d[i]) <= 1e-9 * (1.0 + abs(d[i]) + abs(r0[i])):
                linear = True
            else:
                other = True    # left out of the linear rows' reckoning below
                d[i] = 0.0
        if seen and other and not linear:
            geared[j] = True    # after the driven angles: below
            continue
        if not (seen and linear):
            continue
        best = 0.0              # the whole turns that bring the linear rows nearest to 0
        worst0 = 0.0
        for i in range(N_EQS):
            if d[i] != 0.0:
                worst0 = max(worst0, abs(r0[i]))
        least = worst0
        for i in range(N_EQS):
            if d[i] == 0.0:
                continue
            k = float(round(-r0[i] / d[i]))
            if k == 0.0 or k == best:
                continue
            worst = 0.0
            for l in range(N_EQS):
                if d[l] != 0.0:
                    worst = max(worst, abs(r0[l] + k * d[l]))
            if worst < least:
                least = worst
                best = k
        if best != 0.0 and least < worst0:
            q[j] = qj + 2.0 * math.pi * best
            phi(q, t, p, r0)        # afresh: a row that is not linear changed too
            turned += 1
    return turned + _unwrap_geared(q, t, p, J, geared, r0, r1)


@njit(cache=True)
def _unwrap_geared(q, t, p, J, geared, r0, r1):
    """unwrap_turns' second pass: each gear angle (geared) by the whole turns, three at
    most either way, that bring the rows it is read by nearest to 0 — first the rolling
    rows whose other angles are settled (a driven gear's mate, then its mate...), the
    rows of a loop of gears last, all rows at once. Returns the count turned."""
    turned = 0
    left = 0
    for j in range(N_COORDS):
        if geared[j]:
            left += 1
    rows = np.zeros(N_EQS, dtype=np.bool_)
    loose = False           # no gear's rows are all settled: take what is left at once
    while left > 0:
        moved = False
        for j in range(N_COORDS):
            if not geared[j]:
                continue
            ready = False
            for i in range(N_EQS):
                rows[i] = False
                if not ROW_WRAPS[i] or J[i, j] == 0.0:
                    continue
                settled = True
                for l in range(N_COORDS):
                    if l != j and geared[l] and J[i, l] != 0.0:
                        settled = False
                rows[i] = settled or loose
                ready = ready or rows[i]
            if loose:
                rows[:] = True
                ready = True
            if not ready:
                continue
            phi(q, t, p, r0)
            qj = q[j]
            least = 0.0
            for i in range(N_EQS):
                if rows[i]:
                    least = max(least, abs(r0[i]))
            best = 0.0
            for step in range(1, 7):        # 1, −1, 2, −2, 3, −3: the fewest turns of
                k = (step + 1) // 2         # equals (a gear turned whole turns by its
                if step % 2 == 0:           # mate's: the same pose) is taken
                    k = -k
                q[j] = qj + 2.0 * math.pi * k
                phi(q, t, p, r1)
                worst = 0.0
                for i in range(N_EQS):
                    if rows[i]:
                        worst = max(worst, abs(r1[i]))
                if worst < least - 1e-9 * (1.0 + least):
                    least = worst
                    best = float(k)
            q[j] = qj + 2.0 * math.pi * best
            if best != 0.0:
                turned += 1
            geared[j] = False
            left -= 1
            moved = True
        if not moved:
            loose = True
    return turned


@njit(cache=True)
def solve_position(q, t, p, tol, xtol, maxit, method, info):
    """Position solve in place. method METHOD_AUTO: sorted blocks, full Newton if they fail;
    METHOD_SORTED: sorted only; METHOD_FULL: full Newton only (a module without block
    structure always solves by the full Newton). info = [iterations, residual, rank,
    method]."""
    info[INFO_ITERATIONS] = 0.0
    info[INFO_RESIDUAL] = 0.0
    info[INFO_RANK] = N_COORDS
    info[INFO_METHOD] = 0.0
    if SORTED and method != METHOD_FULL:
        status = position_sorted(q, t, p, tol, xtol, maxit, info)
        if status == OK and not _max_abs(q) < np.inf:
            status = NOT_FINITE  # an explicit block gave NaN (no real configuration)
        if status == OK or method == METHOD_SORTED:
            return status
    info[INFO_METHOD] = 1.0
    return newton_full(q, t, p, tol, xtol, maxit, info)


@njit(cache=True)
def solve_velocity(q, t, p, method, out):
    """Velocities q̇ at a solved position."""
    if SORTED and LEVEL >= 1 and method != METHOD_FULL:
        status = velocity_sorted(q, t, p, out)
        if status == OK or method == METHOD_SORTED:
            return status
    return velocity_full(q, t, p, out)


@njit(cache=True)
def solve_acceleration(q, qd, t, p, method, out):
    """Accelerations q̈ at a solved position and velocity."""
    if SORTED and LEVEL >= 2 and method != METHOD_FULL:
        status = acceleration_sorted(q, qd, t, p, out)
        if status == OK or method == METHOD_SORTED:
            return status
    return acceleration_full(q, qd, t, p, out)


@njit(cache=True)
def solve_point(q, t, p, tol, xtol, maxit, method, info):
    """One position solve as Mechanism.solve() makes it, in one call: the position in
    place (solve_position; info[0:4] as there), then info[POINT_RESIDUAL] = max|Φ| and
    info[POINT_PIVOT] = pivot_ratio. Returns the position status (OK: 0)."""
    unwrap_turns(q, t, p)
    status = solve_position(q, t, p, tol, xtol, maxit, method, info)
    if status != OK:
        return status
    r = np.empty(N_EQS)
    phi(q, t, p, r)
    info[POINT_RESIDUAL] = _max_abs(r)
    info[POINT_PIVOT] = pivot_ratio(q, t, p)
    return OK


@njit(cache=True)
def solve_point_sorted(q, t, p, tol, xtol, maxit, info):
    """solve_point() with method METHOD_SORTED, in a function of its own: what a first
    solve compiles is the sorted solver and the checks, not the full Newton (the runtime
    calls solve_point_full only when this gives up and the method allows it)."""
    info[INFO_ITERATIONS] = 0.0
    info[INFO_RESIDUAL] = 0.0
    info[INFO_RANK] = N_COORDS
    info[INFO_METHOD] = 0.0
    unwrap_turns(q, t, p)
    status = position_sorted(q, t, p, tol, xtol, maxit, info)
    if status == OK and not _max_abs(q) < np.inf:
        status = NOT_FINITE  # an explicit block gave NaN (no real configuration)
    if status != OK:
        return status
    r = np.empty(N_EQS)
    phi(q, t, p, r)
    info[POINT_RESIDUAL] = _max_abs(r)
    info[POINT_PIVOT] = pivot_ratio(q, t, p)
    return OK


@njit(cache=True)
def solve_point_full(q, t, p, tol, xtol, maxit, info):
    """solve_point() with method METHOD_FULL (full Newton only), in a function of its own;
    also the fallback of method METHOD_AUTO after solve_point_sorted gave up, from the q it
    left (the same numbers as solve_point with METHOD_AUTO)."""
    info[INFO_ITERATIONS] = 0.0
    info[INFO_RESIDUAL] = 0.0
    info[INFO_RANK] = N_COORDS
    info[INFO_METHOD] = 1.0
    unwrap_turns(q, t, p)
    status = newton_full(q, t, p, tol, xtol, maxit, info)
    if status != OK:
        return status
    r = np.empty(N_EQS)
    phi(q, t, p, r)
    info[POINT_RESIDUAL] = _max_abs(r)
    info[POINT_PIVOT] = pivot_ratio(q, t, p)
    return OK


@njit(cache=True)
def solve_derivatives_sorted(q, t, p, qd, qdd):
    """The sorted velocity and acceleration passes at a solved position, in one call
    without the full solves (the runtime calls velocity_full / acceleration_full only where
    a sorted pass gave up). Returns OK, or VELOCITY + the velocity status, or
    ACCELERATION + the acceleration status. For a module built to acceleration level."""
    status = velocity_sorted(q, t, p, qd)
    if status != OK:
        return VELOCITY + status
    status = acceleration_sorted(q, qd, t, p, qdd)
    if status != OK:
        return ACCELERATION + status
    return OK


@njit(cache=True)
def solve_point_derivatives(q, t, p, tol, xtol, maxit, method, level, qd, qdd, info):
    """solve_point(), then the velocities into qd (not tried at a singular position) and,
    with level >= 2, the accelerations into qdd. Returns the position status (OK: 0), or
    VELOCITY + the velocity status, or ACCELERATION + the acceleration status. (A function
    of its own, so that position-only use never compiles the derivative solvers.)"""
    status = solve_point(q, t, p, tol, xtol, maxit, method, info)
    if status != OK:
        return status
    if level >= 1:
        if info[INFO_RANK] < N_COORDS or not info[POINT_PIVOT] >= SING_RTOL:
            return VELOCITY + SINGULAR
        status = solve_velocity(q, t, p, method, qd)
        if status != OK:
            return VELOCITY + status
    if level >= 2:
        status = solve_acceleration(q, qd, t, p, method, qdd)
        if status != OK:
            return ACCELERATION + status
    return OK


@njit(cache=True)
def _fin(x):
    """x, or 0.0 when it is not finite (a derivative a pruned build does not solve)."""
    if ALL_SOLVED:
        return x
    return x if abs(x) < np.inf else 0.0
