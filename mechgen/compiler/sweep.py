"""The fast sweep: the whole body of ``sweep_fast(ts, q0, p, tol, xtol, maxit, Q, QD, QDD,
STATUS)``, the quick path of a sweep for the stretches where nothing is hard. It stores
what the caller gives arrays for: QD and QDD with no rows (a position sweep) are not
written, nor the STATUS columns it does not have (protocol.STATUS_*).

Per point: a Taylor predictor from the last point's velocity and acceleration, the sorted
position solve and the combined velocity/acceleration pass, then sweep()'s branch test.
For a small model the two solvers are written out in the loop as one piece (numba's own
inlining of array functions costs refcount work at every return): the derivative code
takes the sin and cos of solved coordinates from the position code, each failure status
prints as ``return k`` (the count of points accepted) and the sin and cos the position
code calls as a pair are turned from the last point instead (ir.Options).
"""
from __future__ import annotations

from .inputs import free, time_local, unpack
from .ir import Assign, Code, Comment, Guard, If, Loop, Options, Return, Store, replaced
from ..model.geometry import T
from .schedule import TempNames, emit

SWEEP_RESYNC = 8       # the fast sweep calls sin and cos afresh every this many points


def options(names) -> Options:
    """How the body prints: failures return the count of points accepted, sin and cos
    pairs turned from the last point."""
    return Options(names=names, failure="k", turn=True)


def written_step(plan, eq, position, derivatives):
    """position_sorted() and derivatives_sorted() as one piece: ``position`` the body of
    the one-function position solver, ``derivatives`` linear.derivative_code. The
    derivative code reads the sin and cos (and other calls) the position code shares."""
    shared = plan.position.shared_map
    st = [replaced(x, lambda e: e.xreplace(shared)) for x in derivatives.statements]
    exprs = [x.expr for x in st if isinstance(x, (Assign, Store))]
    exprs += [x.bound for x in st if isinstance(x, Guard)]
    used, have = free(exprs), free(list(eq.phi))
    if position[-1] != Return(0):
        raise ValueError("a position solver in parts cannot be written out in the sweep")
    out = list(position[:-1])                   # all but its "return 0"
    out += unpack(used - have, eq.params, "p")
    if T in used and T not in have:
        out.append(time_local())
    return out + emit(st, TempNames("_v"), plan.cse) + list(derivatives.tail)


def _memory(pairs):
    """The loop's memory of each turned angle: (initial values, keeping an accepted point)."""
    init, keep = [], []
    for pair in pairs:
        last, last_sin, last_cos = pair.memory
        init += [Code("{0} = 0.0", (last,)), Code("{0} = 0.0", (last_sin,)),
                 Code("{0} = 1.0", (last_cos,))]
        keep += [Code("{0} = {1}", (last, pair.angle)), Code("{0} = {1}", (last_sin, pair.sin)),
                 Code("{0} = {1}", (last_cos, pair.cos))]
    return init, keep


def sweep_fast_body(step=None, pairs=()):
    """The statements of sweep_fast's body: with ``step`` (written_step) the solvers
    written out, else calls of position_sorted and derivatives_sorted. ``pairs``: the
    TrigPairs the step turns."""
    init, keep = _memory(pairs) if step is not None else ([], [])
    predictor = If(Code("k > 0"), (
        Code("_sw_h = t - ts[k - 1]"),
        Code("_sw_move = 0.0"),
        Code("_sw_size = 0.0"),
        Loop(Code("for j in range(N_COORDS)"), (
            Code("_sw_dq = _sw_h * (qd[j] + 0.5 * _sw_h * qdd[j])"),
            Code("_sw_move = max(_sw_move, abs(_sw_dq))"),
            Code("_sw_size = max(_sw_size, abs(q[j]))"),
            Code("q[j] += _sw_dq"),
            Code("_sw_qp[j] = q[j]"))),
    ))
    if step is not None:
        solve = [Comment("position_sorted() and derivatives_sorted() written out here as one "
                         "piece, the"),
                 Comment("sin and cos of solved coordinates computed once for both; a failure "
                         "ends the"),
                 Comment("quick path at this point")] + list(step)
        warm = [Code(f"_sw_warm = k % {SWEEP_RESYNC} != 0   # turn sin and cos from the last "
                     "point")]
    else:
        solve = [If(Code("position_sorted(q, t, p, tol, xtol, maxit, info) != 0"),
                    (Code("return k"),)),
                 If(Code("derivatives_sorted(q, t, p, qd, qdd, piv) != 0"), (Code("return k"),))]
        warm = []
    checks = [
        Code("_sw_corr = 0.0"),
        Code("_sw_bad = 0.0          # x * 0 is 0 for every finite x, NaN for inf and NaN"),
        Loop(Code("for j in range(N_COORDS)"), (
            Code("_sw_bad += (q[j] + qd[j] + qdd[j]) * 0.0"),
            Code("_sw_corr = max(_sw_corr, abs(q[j] - _sw_qp[j]))"))),
        If(Code("_sw_bad != 0.0"), (Code("return k"),)),
        If(Code("k > 0"), (
            If(Code("_sw_corr > BRANCH_RATIO * _sw_move + BRANCH_ATOL * (1.0 + _sw_size)"),
               (Code("return k"),)),
            If(Code("piv[0] * _sw_det <= 0.0"), (Code("return k"),),
               tail="        # a sign change: a singular point between"))),
        Code("_sw_det = piv[0]"),
        Loop(Code("for j in range(N_COORDS)"), (Code("Q[k, j] = q[j]"),)),
        If(Code("_sw_keep_d"), (
            Loop(Code("for j in range(N_COORDS)"), (Code("QD[k, j] = qd[j]"),)),)),
        If(Code("_sw_keep_dd"), (
            Loop(Code("for j in range(N_COORDS)"), (Code("QDD[k, j] = qdd[j]"),)),)),
        Code("STATUS[k, STATUS_CODE] = OK"),
        If(Code("_sw_iterations"), (
            Code("STATUS[k, STATUS_ITERATIONS] = min(info[0], STATUS_MAX)"),)),
        If(Code("_sw_substeps"), (Code("STATUS[k, STATUS_SUBSTEPS] = 0"),)),
    ]
    loop = Loop(Code("for k in range(ts.shape[0])"),
                tuple([Code("t = ts[k]")] + warm + [predictor] + solve + checks + keep))
    return [
        Comment("(the loop's own names start with _sw: the solver code written into it uses "
                "others)"),
        Code("q = q0.copy()           # the last accepted point, then the prediction for the "
             "next"),
        Code("qd = np.zeros(N_COORDS)"),
        Code("qdd = np.zeros(N_COORDS)"),
        Code("piv = np.zeros(1)"),
        Code("info = np.zeros(4)"),
        Code("_sw_qp = q0.copy()"),
        Code("_sw_det = 0.0"),
        Code("_sw_move = 0.0"),
        Code("_sw_size = 0.0"),
        Code("_sw_keep_d = QD.shape[0] > 0       # velocities stored (no rows: a position "
             "sweep)"),
        Code("_sw_keep_dd = QDD.shape[0] > 0"),
        Code("_sw_iterations = STATUS.shape[1] > STATUS_ITERATIONS"),
        Code("_sw_substeps = STATUS.shape[1] > STATUS_SUBSTEPS"),
        *init,
        loop,
        Code("return ts.shape[0]"),
    ]
