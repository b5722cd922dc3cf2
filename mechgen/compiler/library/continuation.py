"""The continuation sweep (a whole time series along one assembly mode, with step control
that halves its way past hard stretches and reports jumps and singular crossings), the
evaluation of points and outputs along a sweep (a sweep per design: designs.py).

Everything below the marker line goes verbatim into every generated module; the imports
above it stand for what a generated module defines (the toy model's here).
"""
import math

import numpy as np

from .solve import _fin, pivot_ratio, solve_position, solve_velocity, solve_acceleration
from .toy import (ACCELERATION, BRANCH_ATOL, BRANCH_HMIN, BRANCH_NEAR, BRANCH_RATIO,
                  BRANCH_TURN, INFO_ITERATIONS, INFO_METHOD, INFO_REACH, JUMP, LEVEL,
                  METHOD_FULL, N_COORDS, N_EQS, OK, POINT_INFO_SIZE, POSITION_INFO_SIZE,
                  REPORT_FAILED, REPORT_JUMP, REPORT_REACHED,
                  REPORT_SIZE, REPORT_STATUS, SORTED, STATUS_CODE, STATUS_ITERATIONS,
                  STATUS_MAX, STATUS_SUBSTEPS, THROUGH_SINGULAR, TINY, VELOCITY, REACH,
                  derivatives_sorted, jacobian_det, outputs, outputs_d, outputs_dd, phi,
                  points, reach, njit)

# -- module body: below this line, the text as a generated module holds it --
# ---------------------------------------------------------------------------------------
# Sweeps
# ---------------------------------------------------------------------------------------
@njit(cache=True)
def angle_mask(q0, t, p):
    """The angles of q0: the coordinates that Φ does not see turned by a full turn (at
    time t, parameters p)."""
    n = N_COORDS
    angle = np.zeros(n, dtype=np.bool_)
    q = q0.copy()
    r0 = np.empty(N_EQS)
    r1 = np.empty(N_EQS)
    phi(q0, t, p, r0)
    for j in range(n):
        q[j] += 2.0 * math.pi
        phi(q, t, p, r1)
        q[j] = q0[j]
        angle[j] = True
        for i in range(N_EQS):
            if not abs(r1[i] - r0[i]) <= 1e-9 * (1.0 + abs(r0[i])):
                angle[j] = False
    return angle


@njit(cache=True, error_model="numpy")
def sweep(ts, q0, p, level, tol, xtol, maxit, method, Q, QD, QDD, STATUS, REPORT):
    """Solve at every time of ts by continuation along the assembly mode of the first point.

    Each point starts from a predictor: Taylor with velocity and acceleration (level 2), a
    quadratic through the velocity at the last point and the point before (level 1), or
    through the last three points (level 0); the tangent at the last point when they
    crowd together (after the smallest substeps) or are too few. A step is accepted
    when its solve succeeds and (1) corrects the predictor by at most BRANCH_RATIO times
    the smaller of the predicted and the actual move, (2) at level >= 1, moves as the
    trapezoidal rule on the velocities at both ends says to the same fraction (both plus
    BRANCH_ATOL times the size of q), (3) turns no angle (a coordinate Φ does not see
    turned by 2π) by more than BRANCH_TURN, and (4) keeps the sign of every block
    determinant of Φ_q (det Φ_q's sign and the pattern of its blocks' signs, jacobian_det:
    tested at every point) and, where det Φ_q could reach zero, changes it by at most half
    of itself, and (5) keeps the reach margin of the blocks solved whatever the guess
    (reach(), where REACH) as reach_kept() says. A block in closed form lands as readily
    on the far side of a stretch where it cannot assemble as on the near side, in the same
    mode: the correction test (1) is applied to every step of such a model, not only after
    a hard Newton (more than two iterations). A jump
    towards another assembly mode, or across a stretch where the mechanism does not
    assemble, fails them: the step is then halved, down to BRANCH_HMIN of the sweep's
    step, and the way is taken in substeps (not recorded) that grow again as they pass.

    Rows of Q (QD at level >= 1, QDD at level 2: below it they may have no rows) and
    STATUS are filled up to the returned count: STATUS[k, STATUS_CODE] the point's status
    and, where STATUS has those columns, STATUS[k, STATUS_ITERATIONS] its Newton iterations
    and STATUS[k, STATUS_SUBSTEPS] the substeps taken on the way to it.
    Status JUMP marks a point reached by a jump the step control could not avoid (the
    first jump's size goes to REPORT[REPORT_JUMP]), THROUGH_SINGULAR a point reached at or
    through a singular configuration (det Φ_q changed sign, or the tests failed next to
    one, even at the smallest step: a dead centre, lock or branch point; or leaving the
    last point, where the mechanism stood at one). A count below
    len(ts) means the solve at ts[count] failed: its status goes to STATUS[count] and
    REPORT[REPORT_STATUS], the info vector of that solve to REPORT[:POSITION_INFO_SIZE],
    Q[count] (QD, QDD) then hold the last configuration reached on the way,
    REPORT[REPORT_REACHED] its time and REPORT[REPORT_FAILED] the time that failed."""
    n = N_COORDS
    iterations = STATUS.shape[1] > STATUS_ITERATIONS
    substeps_kept = STATUS.shape[1] > STATUS_SUBSTEPS
    for j in range(REPORT_SIZE):
        REPORT[j] = 0.0
    q = q0.copy()
    qd = np.zeros(n)
    qdd = np.zeros(n)
    qp = np.zeros(n)
    qa = q0.copy()              # the last configuration reached, at time ta
    qda = np.zeros(n)
    qdda = np.zeros(n)
    qb = q0.copy()              # the two before it, at times tb and tc0
    qc = q0.copy()
    ta = 0.0
    tb = 0.0
    tc0 = 0.0
    db = 0.0                    # det Φ_q at ta (its sign pattern: sa)
    da = 0.0                    # det Φ_q at td, the last time its change was limited, and
    td = 0.0                    # how fast it changes: the change is limited again only
    rate = 0.0                  # where it could reach zero, after a hard solve (more than
    skipped = 0                 # two Newton iterations) and every 16th point
    have = 0                    # configurations reached so far
    va = False                  # qda holds the velocity at ta
    fresh = False               # ta was reached by a jump: predict no motion from it
    info = np.zeros(POINT_INFO_SIZE)     # (long enough for the position's reach margin)
    piv = np.zeros(2)           # det Φ_q and its blocks' sign pattern at tc (jacobian_det)
    sa = 0.0                    # the sign pattern at ta
    ma = 1.0                    # the reach margin at ta (REACH), and its change per unit
    mslope = np.nan             # of time from tb to ta (NaN: not known)
    mc = 1.0
    # the angles: coordinates Φ does not see turned by a full turn
    angle = angle_mask(q0, ts[0], p) if ts.shape[0] > 1 else np.zeros(n, dtype=np.bool_)
    for k in range(ts.shape[0]):
        target = ts[k]
        h = target - ta
        hmin = abs(h) * BRANCH_HMIN
        full = True
        substeps = 0
        jump = 0.0
        crossed = False
        leaping = False
        wild = False
        while True:
            tc = target if full or have == 0 else ta + h
            dt = tc - ta
            # the history spreads enough for a quadratic (after the smallest substeps it
            # does not, and the tangent at ta predicts instead)
            far_b = have >= 2 and abs(ta - tb) >= 0.25 * abs(dt)
            far_c = far_b and have >= 3 and abs(tb - tc0) >= 0.25 * abs(dt)
            if have > 0 and not va and not far_c and not fresh:
                va = solve_velocity(qa, ta, p, method, qda) == OK
            if have == 0:
                for j in range(n):
                    q[j] = qa[j]
            elif va and level >= 2:
                for j in range(n):
                    q[j] = qa[j] + dt * (_fin(qda[j]) + 0.5 * dt * _fin(qdda[j]))
            elif va and far_b:
                e = tb - ta             # the quadratic with the velocity at ta through qb
                for j in range(n):
                    v = _fin(qda[j])
                    q[j] = qa[j] + dt * (v + dt * (qb[j] - qa[j] - e * v) / (e * e))
            elif va:
                for j in range(n):
                    q[j] = qa[j] + dt * _fin(qda[j])
            elif far_c:
                wa = (tc - tb) * (tc - tc0) / ((ta - tb) * (ta - tc0))
                wb = (tc - ta) * (tc - tc0) / ((tb - ta) * (tb - tc0))
                wc = (tc - ta) * (tc - tb) / ((tc0 - ta) * (tc0 - tb))
                for j in range(n):
                    q[j] = wa * qa[j] + wb * qb[j] + wc * qc[j]
            elif far_b:
                f = dt / (ta - tb)
                for j in range(n):
                    q[j] = qa[j] + f * (qa[j] - qb[j])
            else:
                for j in range(n):
                    q[j] = qa[j]
            turn = 0.0
            for j in range(n):
                qp[j] = q[j]
                if angle[j]:
                    turn = max(turn, abs(q[j] - qa[j]))
            if have > 0 and turn > BRANCH_TURN and abs(h) > hmin and not leaping and \
                    ta + 0.5 * h != ta:
                h *= 0.5                # the predictor turns an angle too far: halve first
                full = False
                continue
            # position, velocity, acceleration (written out: a call costs here)
            status = solve_position(q, tc, p, tol, xtol, maxit, method, info)
            both = False                # det Φ_q and its pattern came with the derivatives
            if SORTED and LEVEL >= 2 and status == OK and level >= 2 and \
                    method != METHOD_FULL and derivatives_sorted(q, tc, p, qd, qdd, piv) == OK:
                both = True             # both in one pass; else one by one, with fallbacks
            elif status == OK and level >= 1:
                status = solve_velocity(q, tc, p, method, qd)
                if status != OK:
                    status += VELOCITY
                elif level >= 2:
                    status = solve_acceleration(q, qd, tc, p, method, qdd)
                    if status != OK:
                        status += ACCELERATION
            corr = 0.0
            flip = False
            dc = da
            ok = status == OK
            checked = False
            seen = both                 # piv holds det Φ_q and its pattern at (q, tc)
            if ok and have > 0:
                # the branch: every accepted point keeps the signs of the blocks of Φ_q
                # (det Φ_q's sign and the pattern of its blocks' signs) of the point before
                if not both:
                    jacobian_det(q, tc, p, piv)
                    seen = True
                flip = not piv[0] * db > 0.0 or piv[1] != sa
            if ok and have > 0 and (skipped >= 15 or rate == 0.0 or info[INFO_ITERATIONS] > 2 or
                                    abs(da) <= 8.0 * rate * abs(tc - td)):
                dc = piv[0]
                if td != ta:            # compare with det Φ_q at the last point reached
                    d0 = db
                    rate = abs(d0 - da) / abs(ta - td)
                    da = d0
                    td = ta
                # det Φ_q may change by half of itself in a step at most: near a singular
                # configuration the steps shrink, and a sign change is never stepped over
                flip = flip or abs(dc - da) > 0.5 * min(abs(da), abs(dc))
                checked = True
            if REACH and status == OK:
                # the margin the sorted solver's blocks kept, else computed afresh
                mc = info[INFO_REACH] if info[INFO_METHOD] == 0.0 else reach(q, tc, p)
                if have > 0 and mslope != mslope and va:
                    mslope = reach_slope(qa, qda, ta, dt, p, ma)    # the first step
                if have > 0 and not reach_kept(mc, ma, mslope, dt):
                    flip = True         # the step may pass a stretch where a block cannot
                                        # assemble: halved, as a sign change
            if ok and have > 0 and jump == 0.0:
                for j in range(n):
                    if angle[j]:
                        turn = max(turn, abs(q[j] - qa[j]))
                if turn > BRANCH_TURN:
                    ok = False
                    corr = turn
            # (a Newton that converged within two iterations started within ~1e-5 of the
            # solution: the predictor was right, nothing more to test)
            if ok and jump == 0.0 and have > 0 and (va or far_b) and \
                    (info[INFO_ITERATIONS] > 2 or REACH):
                move = 0.0
                went = 0.0
                trap = 0.0
                size = 0.0
                for j in range(n):
                    corr = max(corr, abs(q[j] - qp[j]))
                    move = max(move, abs(qp[j] - qa[j]))
                    went = max(went, abs(q[j] - qa[j]))
                    size = max(size, abs(qa[j]))
                    if va and level >= 1:
                        trap = max(trap, abs(q[j] - qa[j] - 0.5 * dt * (qda[j] + qd[j])))
                atol = BRANCH_ATOL * (1.0 + size)
                ok = corr <= BRANCH_RATIO * min(move, went) + atol and \
                    trap <= BRANCH_RATIO * went + atol
                corr = max(corr, trap)
            if ok and flip and not crossed:
                ok = False
            if leaping and status == OK:
                ok = False              # accepted below, as through a singular configuration
            if not ok:
                if leaping:
                    if status >= VELOCITY and not full:
                        # still on the singular configuration: leap further
                        if 2.0 * abs(h) >= abs(target - ta):
                            h = target - ta
                            full = True
                        else:
                            h *= 2.0
                        continue
                elif have > 0 and abs(h) > hmin and ta + 0.5 * h != ta:
                    # (a half step the time cannot resolve would never move: two times
                    # 1e-12 apart across a stage switch, whose tests fail at any step)
                    h *= 0.5
                    full = False
                    continue
                elif status >= VELOCITY and not full:
                    # a singular configuration (the velocities undetermined) between ta and
                    # the target, whose position solves: leap over it
                    leaping = True
                    h *= 2.0
                    continue
                if status != OK:
                    for j in range(POSITION_INFO_SIZE):
                        REPORT[j] = info[j]
                    REPORT[REPORT_STATUS] = status
                    REPORT[REPORT_REACHED] = ta
                    REPORT[REPORT_FAILED] = tc
                    STATUS[k, STATUS_CODE] = status
                    if iterations:
                        STATUS[k, STATUS_ITERATIONS] = min(info[INFO_ITERATIONS], STATUS_MAX)
                    if substeps_kept:
                        STATUS[k, STATUS_SUBSTEPS] = min(substeps, STATUS_MAX)
                    for j in range(n):
                        Q[k, j] = qa[j]
                    if level >= 1:
                        for j in range(n):
                            QD[k, j] = qda[j]
                    if level >= 2:
                        for j in range(n):
                            QDD[k, j] = qdda[j]
                    return k
                near = leaping or pivot_ratio(q, tc, p) < BRANCH_NEAR or \
                    pivot_ratio(qa, ta, p) < BRANCH_NEAR
                if not near and k > 0:
                    # leaving a singular configuration (a dead centre at the last point):
                    # its branches part as the square root of time, which no step follows
                    for j in range(n):
                        qp[j] = Q[k - 1, j]     # (qp is predicted again before its use)
                    near = pivot_ratio(qp, ts[k - 1], p) < BRANCH_NEAR
                if near:
                    crossed = True      # at, through or out of a singular configuration
                else:
                    jump = max(jump, corr, TINY)  # a jump the smallest step could not avoid
                    wild = True
            if REACH:
                if have > 0 and tc != ta:
                    mslope = (mc - ma) / abs(tc - ta)
                ma = mc
            tc0 = tb
            tb = ta
            ta = tc
            # the configuration reached becomes qa, the older ones move down (no copies)
            qc, qb, qa, q = qb, qa, q, qc
            qda, qd = qd, qda
            qdda, qdd = qdd, qdda
            if not seen:                # accepted without the test (first point, a jump or
                jacobian_det(qa, ta, p, piv)    # a singular configuration passed)
            db = piv[0]
            sa = piv[1]
            if checked:
                if dc != 0.0:
                    if tc != td:
                        rate = abs(dc - da) / abs(tc - td)
                    da = dc
                    td = tc
                skipped = 0
            else:
                skipped += 1
            va = level >= 1 and not wild   # at level 0 the tangent is solved when needed
            leaping = False
            have += 1
            fresh = wild
            if wild:                    # after a jump the history predicts nothing: the next
                have = 1                # step starts from the configuration reached
                wild = False
            if have == 1:
                da = db
                td = ta
                mslope = np.nan
            if full:
                break
            substeps += 1
            rest = target - ta
            if 2.0 * abs(h) >= abs(rest):
                h = rest
                full = True
            else:
                h *= 2.0
        if jump > 0.0 and REPORT[REPORT_JUMP] == 0.0:
            REPORT[REPORT_JUMP] = jump
        STATUS[k, STATUS_CODE] = JUMP if jump > 0.0 else THROUGH_SINGULAR if crossed else OK
        if iterations:
            STATUS[k, STATUS_ITERATIONS] = min(info[INFO_ITERATIONS], STATUS_MAX)
        if substeps_kept:
            STATUS[k, STATUS_SUBSTEPS] = min(substeps, STATUS_MAX)
        for j in range(n):
            Q[k, j] = qa[j]
        if level >= 1:
            for j in range(n):
                QD[k, j] = qda[j]
        if level >= 2:
            for j in range(n):
                QDD[k, j] = qdda[j]
    return ts.shape[0]


@njit(cache=True)
def reach_kept(mc, ma, slope, dt):
    """Whether a step of dt from a point whose reach margin (reach()) is ma, changing by
    ``slope`` per unit of time since the point before (NaN: not known, the first step), to
    one whose margin is mc keeps clear of a stretch where a block cannot assemble: mc is
    positive and, where the margin could reach zero within eight such steps at its last
    rate (or that rate is not known), it changes by half of itself at most and, falling,
    the step would not take it more than half of its way to zero at that rate. The far
    side of such a stretch has a positive margin too, and near it a margin of the same
    size as the near side's: only the rate the margin fell at before tells a step over
    the stretch from one that stays on the near side (sweep() and sweep_fast())."""
    if not mc > 0.0:
        return False
    h = abs(dt)
    if slope == slope and ma > 8.0 * abs(slope) * h:
        return True
    if abs(mc - ma) > 0.5 * min(mc, ma):
        return False
    return not (slope < 0.0 and ma + slope * h < 0.5 * ma)


@njit(cache=True)
def reach_slope(q, qd, t, h, p, m):
    """The rate of change of reach() (m at (q, t)) along the tangent qd, per unit of time
    in the direction of the step h: a difference over a millionth of h. A sweep's first
    step has no earlier point to tell how fast the margin falls; the tangent does."""
    e = 1e-6 * h
    if e == 0.0:
        return np.nan
    qe = np.empty(N_COORDS)
    for j in range(N_COORDS):
        qe[j] = q[j] + e * qd[j]
    return (reach(qe, t + e, p) - m) / abs(e)


@njit(cache=True)
def eval_points(Q, ts, p, OUT):
    """points() at every row of a sweep."""
    for k in range(Q.shape[0]):
        points(Q[k], ts[k], p, OUT[k])


@njit(cache=True)
def eval_outputs(Q, QD, QDD, ts, p, order, OUT):
    """outputs() (order 0), outputs_d() (1) or outputs_dd() (2) at every row of a sweep."""
    for k in range(Q.shape[0]):
        if order == 0:
            outputs(Q[k], QD[k], QDD[k], ts[k], p, OUT[k])
        elif order == 1:
            outputs_d(Q[k], QD[k], QDD[k], ts[k], p, OUT[k])
        else:
            outputs_dd(Q[k], QD[k], QDD[k], ts[k], p, OUT[k])
