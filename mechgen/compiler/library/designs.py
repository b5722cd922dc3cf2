"""Where each design of a design table starts, and its sweep: the guess's configuration
carried to the design's parameters along its assembly mode (a continuation in the
parameters at the guess's time), then to the table's first time (a careful sweep), and
every design swept from its own start.

Everything below the marker line goes verbatim into every generated module; the imports
above it stand for what a generated module defines (the toy model's here).
"""
import numpy as np

from .continuation import angle_mask, sweep
from .linalg import _fp_solve
from .solve import _fin, pivot_ratio, solve_position
from .toy import (BRANCH_ATOL, BRANCH_NEAR, BRANCH_RATIO, BRANCH_TURN, CARRY_HMIN,
                  CARRY_MAXIT, JUMP, LEVEL, METHOD_FULL, N_COORDS, N_EQS, OK, PIVOT_RTOL,
                  POINT_INFO_SIZE, REACH, REPORT_SIZE, SORTED, STATUS_CODE, THROUGH_SINGULAR,
                  jacobian_det, njit, phi, phi_q, reach, sweep_fast)

# -- module body: below this line, the text as a generated module holds it --
# ---------------------------------------------------------------------------------------
# Design tables
# ---------------------------------------------------------------------------------------
@njit(cache=True, nogil=True, error_model="numpy")
def carry_params(q, t, p0, p1, tol, xtol, maxit, method, info):
    """Carry q, a solved configuration at time t with parameters p0, in place to the one
    its assembly mode reaches at parameters p1: the parameters move along the straight
    line from p0 to p1 in steps, each one predicted along the tangent (a Newton step from
    the last configuration at the step's parameters), solved, and accepted when it keeps
    the branch as a sweep's steps do: the solve corrects the prediction by at most
    BRANCH_RATIO times the move, no angle turns by more than BRANCH_TURN, the signs of
    Φ_q's block determinants stay (jacobian_det), and neither |det Φ_q| nor the reach
    margin (reach(), where REACH) falls below half of itself. A step that fails them is
    halved, down to CARRY_HMIN of the way; the first step tries the whole way. A step's
    Newton has CARRY_MAXIT iterations at most: from its prediction it needs few.

    Returns OK (q at p1), or, q then holding the last configuration reached:
    THROUGH_SINGULAR where the way passes a singular configuration (a sign changed, or
    the tests failed next to one at the smallest step), JUMP where no step could be taken
    (the mechanism does not assemble somewhere on the way)."""
    piv = np.zeros(2)
    da = jacobian_det(q, t, p0, piv)
    return _carry(q, t, p0, p1, tol, xtol, maxit, method, info, angle_mask(q, t, p0), da,
                  piv[1], reach(q, t, p0) if REACH else 1.0)


@njit(cache=True, nogil=True, error_model="numpy")
def _carry(q, t, p0, p1, tol, xtol, maxit, method, info, angle, da, sa, ma):
    """carry_params from q's angles, det Φ_q, its sign pattern and reach margin at p0
    (the same for every design of a table: computed once)."""
    n = N_COORDS
    same = True
    for i in range(p0.shape[0]):
        if p0[i] != p1[i]:
            same = False
    if same:
        return OK
    p = p0.copy()
    qa = q.copy()
    qp = np.empty(n)
    dq = np.empty(n)
    r = np.empty(N_EQS)
    J = np.empty((N_EQS, n))
    piv = np.zeros(2)
    mc = ma
    dc = da
    s = 0.0
    h = 1.0
    while s < 1.0:
        sc = 1.0 if s + h >= 1.0 else s + h
        for i in range(p.shape[0]):
            p[i] = p1[i] if sc == 1.0 else p0[i] + sc * (p1[i] - p0[i])
        phi(qa, t, p, r)
        phi_q(qa, t, p, J)
        for i in range(N_EQS):
            r[i] = -r[i]
        for j in range(n):
            dq[j] = 0.0
        _fp_solve(J, r, dq, PIVOT_RTOL)
        for j in range(n):
            qp[j] = qa[j] + _fin(dq[j])
            q[j] = qp[j]
        status = solve_position(q, t, p, tol, xtol, min(maxit, CARRY_MAXIT), method, info)
        ok = status == OK
        flip = False
        if ok:
            dc = jacobian_det(q, t, p, piv)
            flip = not dc * da > 0.0 or piv[1] != sa or abs(dc) < 0.5 * abs(da)
            if REACH:
                mc = reach(q, t, p)
                flip = flip or mc < 0.5 * ma
            corr = 0.0
            move = 0.0
            went = 0.0
            size = 0.0
            turn = 0.0
            for j in range(n):
                corr = max(corr, abs(q[j] - qp[j]))
                move = max(move, abs(qp[j] - qa[j]))
                went = max(went, abs(q[j] - qa[j]))
                size = max(size, abs(qa[j]))
                if angle[j]:
                    turn = max(turn, abs(q[j] - qa[j]))
            ok = corr <= BRANCH_RATIO * min(move, went) + BRANCH_ATOL * (1.0 + size) and \
                turn <= BRANCH_TURN
        if ok and not flip:
            for j in range(n):
                qa[j] = q[j]
            da = dc
            sa = piv[1]
            ma = mc
            s = sc
            h *= 2.0
            continue
        if h > CARRY_HMIN:
            h *= 0.5
            continue
        for j in range(n):
            q[j] = qa[j]
        for i in range(p.shape[0]):
            p[i] = p0[i] + s * (p1[i] - p0[i])
        if (ok and flip) or pivot_ratio(qa, t, p) < BRANCH_NEAR:
            return THROUGH_SINGULAR
        return JUMP
    for j in range(n):
        q[j] = qa[j]
    return OK


@njit(cache=True, nogil=True, error_model="numpy")
def start_designs(tw, q, g, p0, P, tol, xtol, maxit, method, Q0, S0):
    """Where each design (row d of P) starts, into Q0[d] and S0[d]: q, a solved
    configuration at time tw[0] with parameters p0, carried to the design's parameters
    (carry_designs), then along the times tw (walk_designs: tw[-1] is the table's first
    time; one time: none). The runtime makes the two calls itself, so that a table
    starting at its guess's time never compiles the careful sweep. Releases the GIL."""
    carry_designs(tw[0], q, g, p0, P, tol, xtol, maxit, method, Q0, S0)
    if tw.shape[0] > 1:
        walk_designs(tw, P, tol, xtol, maxit, method, Q0, S0)


@njit(cache=True, nogil=True, error_model="numpy")
def carry_designs(t, q, g, p0, P, tol, xtol, maxit, method, Q0, S0):
    """q, a solved configuration at time t with parameters p0, carried to each design's
    parameters (row d of P; carry_params) into Q0[d]. S0[d] is OK, or JUMP or
    THROUGH_SINGULAR where the parameters could not be carried: the design then starts
    from g, the guess, as a table without a known start does, and is flagged with it.
    Releases the GIL."""
    info = np.zeros(POINT_INFO_SIZE)
    piv = np.zeros(2)
    da = jacobian_det(q, t, p0, piv)
    angle = angle_mask(q, t, p0)
    ma = reach(q, t, p0) if REACH else 1.0
    for d in range(P.shape[0]):
        qd = Q0[d]
        for j in range(N_COORDS):
            qd[j] = q[j]
        status = _carry(qd, t, p0, P[d], tol, xtol, maxit, method, info, angle, da,
                        piv[1], ma)
        if status != OK:
            for j in range(N_COORDS):
                qd[j] = g[j]
        S0[d] = status


@njit(cache=True, nogil=True, error_model="numpy")
def walk_designs(tw, P, tol, xtol, maxit, method, Q0, S0):
    """Each design carried at time tw[0] (S0[d] OK) taken along the times tw by a careful
    position sweep, Q0[d] from its configuration there to the one at tw[-1], the table's
    first time. S0[d] becomes the status of the sweep's failed solve where the design
    cannot get there (it is then not solved). Releases the GIL."""
    m = tw.shape[0]
    Qw = np.empty((m, N_COORDS))
    Sw = np.zeros((m, 1), dtype=np.int16)
    none = np.empty((0, N_COORDS))
    report = np.zeros(REPORT_SIZE)
    for d in range(P.shape[0]):
        if S0[d] != OK:
            continue
        qd = Q0[d]
        # (the level as an int64, not the literal 0: numba would compile sweep() again
        # for Literal[int](0), some 5 s, beside the int64 one every sweep uses)
        k = sweep(tw, qd, P[d], np.int64(0), tol, xtol, maxit, method, Qw, none, none, Sw,
                  report)
        if k < m:
            S0[d] = Sw[k, STATUS_CODE]
            continue
        for j in range(N_COORDS):
            qd[j] = Qw[m - 1, j]
        for i in range(m):
            if Sw[i, STATUS_CODE] != OK:
                S0[d] = Sw[i, STATUS_CODE]


@njit(cache=True, nogil=True)
def sweep_designs(ts, Q0, P, level, tol, xtol, maxit, method, Q, QD, QDD, STATUS):
    """sweep() for every design: row d of P is a parameter vector and Q0[d] its start (a
    configuration near ts[0]: start_designs), and Q[d], QD[d], QDD[d], STATUS[d] receive
    its sweep (as sweep() fills them: QD and QDD may have no rows below the levels that
    need them). Each design goes as a single sweep does in mechgen: sweep_fast() while
    nothing is hard (sweep_designs_fast), then sweep() from its last accepted point
    (sweep_designs_rest). Returns the count of solved times of each design. The runtime
    makes the two calls itself, the second only where a design needs it, so that a
    table whose designs are all easy never compiles the careful sweep."""
    start = np.zeros(P.shape[0], dtype=np.int64)
    sweep_designs_fast(ts, Q0, P, tol, xtol, maxit, method, Q, QD, QDD, STATUS, start)
    return sweep_designs_rest(ts, Q0, P, level, tol, xtol, maxit, method, Q, QD, QDD, STATUS,
                              start)


@njit(cache=True, nogil=True)
def sweep_designs_fast(ts, Q0, P, tol, xtol, maxit, method, Q, QD, QDD, STATUS, START):
    """The quick path of every design (sweep_fast(), arrays as sweep_designs fills them):
    START[d] the count of times it accepted, ts.shape[0] where it swept them all; 0 where
    the module has none or the method is METHOD_FULL. It releases the GIL (nogil): the
    runtime runs chunks of designs on several threads at once, each design on its own."""
    for d in range(P.shape[0]):
        START[d] = 0
        if SORTED and LEVEL >= 2 and method != METHOD_FULL:
            START[d] = sweep_fast(ts, Q0[d], P[d], tol, xtol, maxit, Q[d], QD[d], QDD[d],
                                  STATUS[d])


@njit(cache=True, nogil=True)
def sweep_designs_rest(ts, Q0, P, level, tol, xtol, maxit, method, Q, QD, QDD, STATUS,
                       START):
    """The careful rest of every design after its quick path accepted START[d] points
    (sweep_designs_fast): sweep() from the last of them (sweep_on); a design swept whole
    is left as it is. Returns the count of solved times of each design; releases the
    GIL."""
    done = np.zeros(P.shape[0], dtype=np.int64)
    report = np.zeros(REPORT_SIZE)
    for d in range(P.shape[0]):
        done[d] = sweep_on(ts, Q0[d], P[d], level, tol, xtol, maxit, method, Q[d], QD[d],
                           QDD[d], STATUS[d], START[d], report)
    return done


@njit(cache=True, nogil=True, inline="always")
def sweep_on(ts, q0, p, level, tol, xtol, maxit, method, Q, QD, QDD, STATUS, start, report):
    """One design after its quick path accepted ``start`` points: sweep() from the last of
    them (from q0 where there is none) over the rest; the count of solved times. (Inlined
    into its callers: a function of its own would be optimized by LLVM with all of
    sweep() linked in, once more.)"""
    if start == ts.shape[0]:
        return start
    start = max(start - 1, 0)
    q_start = q0
    if start > 0:
        q_start = Q[start].copy()
    return start + sweep(ts[start:], q_start, p, level, tol, xtol, maxit, method, Q[start:],
                         QD[start:], QDD[start:], STATUS[start:], report)
