"""The fast sweep: the whole body of ``sweep_fast(ts, q0, p, tol, xtol, maxit, Q, QD, QDD,
STATUS)``, the quick path of a sweep for the stretches where nothing is hard. It stores
what the caller gives arrays for: QD and QDD with no rows (a position sweep) are not
written, nor the STATUS columns it does not have (protocol.STATUS_*).

Per point of a sweep with derivatives: a Taylor predictor from the last point's velocity
and acceleration, the sorted position solve and the combined velocity/acceleration pass,
then sweep()'s branch test and the signs of Φ_q's blocks (det Φ_q, the product of the
velocity pass's block determinants, and the pattern of their signs) at every point, and
sweep()'s limit on det Φ_q where it could reach zero (a change by half of itself at most:
a step from the near side of a lock never lands past it, on the same signs).
A position sweep does position work: it predicts by the polynomial through the points
it has (the quadratic through its last three, as sweep() does at level 0; derivatives
at its first point only where Newton blocks need a tangent to predict the second), only
the coordinates whose guess the solve reads, keeps its dyads' assembly signs from its
first point, and evaluates det Φ_q (jacobian_det) where its sign could have changed:
every BRANCH_DET_EVERY-th point, after a hard solve, and where its rate of change since
the last evaluation says it could reach zero (sweep()'s rule). A block's sign change sends the
sweep back to the point evaluated last: the function then returns the count of points
up to that one, and sweep() goes on from it.

For a small model (up to SHARE_MAX coordinates) the two solvers are written out in the
loop: the derivative code takes the sin and cos of solved coordinates from the position
code, each failure status prints as ``return _sw_good`` (the count of points the loop
vouches for) and the sin and cos the position code calls as a pair are turned from the
last point instead (ir.Options). What a sweep does not change is computed once, before
the loop (position.position_in_sweep): the parameters' loads and the blocks that stay the
same at every point (plan.steady: a slider's angle fixed by its guide, ground points), so
that everything computed from them alone is loop-invariant for LLVM too; those
coordinates are neither predicted nor watched for turns.

Why written out: measured against the same loop calling position_sorted,
derivatives_sorted and dynamics_sorted (a larger model's shape), with numba inlining them
(INLINE "always") or not, side by side over 10^5 points (medians of 21 alternating
rounds), the calls take 2.3x the time per point of an acceleration sweep on the
quick-return (59 -> 135 ns), 2.6x on the Strandbeest (103 -> 262 ns), 2.6x and 2.0x of a
position sweep (37 -> 98, 82 -> 159 ns), 2.9x of a dynamic sweep (81 -> 232 ns), 3.4x of
a static one (no fused statics there); and their numbers differ in the last bits (sin
and cos called afresh, not turned: 1e-14 in q, 4e-12 in q̈, 2e-10 in λ). What the copies
cost is numba's compile, in a fresh process with an empty cache: the Strandbeest's first
10^5-point acceleration sweep 10.6 s of CPU against 7.6 (sweep_fast 4.6 s against 1.9),
the quick-return's 7.4 against 7.0, the forces quick-return's whole module 27.9 against
27.3 (23.9 without inlining): ``python benchmarks/bench_sweep_shape.py --compile``.
"""
from __future__ import annotations

from ...model.geometry import T
from ..codegen.inputs import free, time_local, unpack
from ..codegen.ir import Assign, Code, Comment, Guard, If, Loop, Options, Store, replaced
from ..codegen.schedule import TempNames, emit
from .linear import jacobian_det_statements
from .position import position_in_sweep

SWEEP_RESYNC = 8       # the fast sweep calls sin and cos afresh every this many points


def options(names) -> Options:
    """How the body prints: failures return the count of points the loop vouches for
    (_sw_good), sin and cos pairs turned from the last point."""
    return Options(names=names, failure="_sw_good", turn=True)


def written_step(plan, eq, derivatives):
    """position_sorted() and derivatives_sorted() written out as three pieces, (before,
    position, derivatives): ``before`` what the loop computes once (position_in_sweep:
    the parameters, the blocks that stay the same at every point), ``position`` the
    position solver's code for one point, ``derivatives`` linear.derivative_code's. The
    derivative code reads the sin and cos (and other calls) the position code shares."""
    if plan.position_parts:
        raise ValueError("a position solver in parts cannot be written out in the sweep")
    before, position = position_in_sweep(plan, eq)
    return (before, position,
            in_loop(plan, eq, derivatives.statements, "_v") + list(derivatives.tail))


def in_loop(plan, eq, statements, prefix, known=()):
    """``statements`` as the fast sweep's loop writes them after the position code: the
    sin and cos (and other calls) that code shares read from it, the parameters and the
    time it does not read loaded first (``known``: other symbols defined before them),
    one CSE pass with temporaries named ``prefix``0, ..."""
    shared = plan.position.shared_map
    st = [replaced(x, lambda e: e.xreplace(shared)) for x in statements]
    exprs = [x.expr for x in st if isinstance(x, (Assign, Store))]
    exprs += [x.bound for x in st if isinstance(x, Guard)]
    used, have = free(exprs), free(list(eq.phi)) | set(known)
    head = unpack(used - have, eq.params, "p")
    if T in used and T not in have:
        head.append(time_local())
    return head + emit(st, TempNames(prefix), plan.cse)


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


UNROLL = 16            # up to this many predicted coordinates, their loops written out


def _each(coords, lines):
    """``lines`` (text with ``{j}`` for the coordinate's index) for each coordinate of
    ``coords``: written out for a few, else a loop over all (coords None: all)."""
    if coords is not None and len(coords) <= UNROLL:
        return [Code(line.format(j=j)) for j in coords for line in lines]
    return [Loop(Code("for j in range(N_COORDS)"), tuple(Code(line.format(j="j"))
                                                         for line in lines))]


def _predictors(coords=None, tangent=True):
    """The predictor of point k > 0: Taylor from the derivatives at the last point (a sweep
    with derivatives, and the second point of a position sweep of a model with Newton
    blocks: ``tangent``), else the polynomial through the last points the sweep has (the
    quadratic through three; the line through two at its third point, the constant at
    its second: a position sweep takes no derivative pass; no motion predicted where two
    of their times coincide; equal steps, to 1e-9 of one, take the quadratic's weights
    3, −3, 1 without computing them). _sw_move: the predicted move, _sw_size: the size of q.
    ``coords``: the coordinates whose guess the position solve reads (Newton's tears,
    closed forms' and dyads' angles; every other one follows from them and the time):
    only those are predicted, and the branch test watches only their corrections (None:
    all)."""
    start = (Code("_sw_move = 0.0"), Code("_sw_size = 0.0"))
    shift = ("_sw_q2[{j}] = _sw_q1[{j}]", "_sw_q1[{j}] = q[{j}]")
    weights = (
        Code("_sw_ta = ts[k - 1]"),
        Code("_sw_wa = 1.0"),
        Code("_sw_wb = 0.0"),
        Code("_sw_wc = 0.0"),
        If(Code("k == 2 and ts[k - 2] != _sw_ta"), (
            Code("_sw_wa = (t - ts[k - 2]) / (_sw_ta - ts[k - 2])"),
            Code("_sw_wb = 1.0 - _sw_wa"))),
        If(Code("k > 2"), (
            Code("_sw_tb = ts[k - 2]"),
            Code("_sw_tc = ts[k - 3]"),
            Code("_sw_h = t - _sw_ta"),
            If(Code("abs(_sw_h - (_sw_ta - _sw_tb)) < 1e-9 * abs(_sw_h) and "
                    "abs(_sw_h - (_sw_tb - _sw_tc)) < 1e-9 * abs(_sw_h)"), (
                Code("_sw_wa = 3.0"),
                Code("_sw_wb = -3.0"),
                Code("_sw_wc = 1.0")),
               orelse=(If(Code("(_sw_ta - _sw_tb) * (_sw_ta - _sw_tc) * (_sw_tb - _sw_tc) != 0.0"), (
                   Code("_sw_wa = (t - _sw_tb) * (t - _sw_tc) / ((_sw_ta - _sw_tb) * (_sw_ta - _sw_tc))"),
                   Code("_sw_wb = (t - _sw_ta) * (t - _sw_tc) / ((_sw_tb - _sw_ta) * (_sw_tb - _sw_tc))"),
                   Code("_sw_wc = (t - _sw_ta) * (t - _sw_tb) / ((_sw_tc - _sw_ta) * (_sw_tc - _sw_tb))"))),),
               tail="  # equal steps (to 1e-9 of one): 3, -3, 1"))))
    taylor = If(Code("k > 0 and (_sw_all or k == 1)" if tangent else "k > 0 and _sw_all"),
                start + (
        Code("_sw_h = t - ts[k - 1]"),
        *([If(Code("not _sw_all"), tuple(_each(coords, shift)))] if coords != [] else []),
        *_each(coords, (
            "_sw_dq = _sw_h * (qd[{j}] + 0.5 * _sw_h * qdd[{j}])",
            "_sw_move = max(_sw_move, abs(_sw_dq))",
            "_sw_size = max(_sw_size, abs(q[{j}]))",
            "q[{j}] += _sw_dq",
            "_sw_qp[{j}] = q[{j}]"))),
        orelse=(If(Code("k > 0"), start + weights + tuple(_each(coords, (
            "_sw_x = _sw_wa * q[{j}] + _sw_wb * _sw_q1[{j}] + _sw_wc * _sw_q2[{j}]",
            "_sw_move = max(_sw_move, abs(_sw_x - q[{j}]))",
            "_sw_size = max(_sw_size, abs(q[{j}]))",
            *shift,
            "q[{j}] = _sw_x",
            "_sw_qp[{j}] = _sw_x")))),))
    return taylor


# sweep()'s rule on det Φ_q where it could reach zero (within eight steps at the rate it
# changed last, or at the first step): it may change by half of itself at most, so that a
# step never leaps from the near side of a lock (a fold) to a configuration past it
_NEAR = ("abs(_sw_det) <= 8.0 * _sw_rate * abs(t - _sw_tk) and "
         "abs({d} - _sw_det) > 0.5 * min(abs({d}), abs(_sw_det))")


def written_det(plan, eq):
    """jacobian_det() written into the fast sweep's loop after the position code, reading
    the sin and cos that code turned (in_loop) instead of calling them afresh; None where
    a block is larger than 2 × 2 (its determinant a call of the library's _det, a name
    the loop's Newton code uses for a number)."""
    if any(b.size > 2 for b in plan.blocks):
        return None
    return in_loop(plan, eq, jacobian_det_statements(plan, eq), "_dj")


def _position_det(det=None):
    """A position sweep's watch on det Φ_q: evaluated where its sign could have changed
    since the point evaluated last (_sw_good - 1, at time _sw_tk); a change sends the
    sweep back there (see the module's docstring). ``det``: jacobian_det's statements
    written out (written_det), else a call."""
    due = ("k < 2 or k + 1 - _sw_good >= BRANCH_DET_EVERY or info[INFO_ITERATIONS] > 2 or "
           "abs(_sw_det) <= 8.0 * _sw_rate * abs(t - _sw_tk)")
    evaluate = [Code("_sw_d = jacobian_det(q, t, p, piv)")] if det is None else \
        [*det, Code("_sw_d = piv[0]")]
    return If(Code(due), (
        *evaluate,
        If(Code("k > 0"), (
            If(Code("not _sw_d * _sw_det > 0.0 or piv[1] != _sw_sig"), (Code("return _sw_good"),),
               tail="      # a block's sign changed: sweep() goes on from the last evaluated"),
            If(Code(_NEAR.format(d="_sw_d")), (Code("return _sw_good"),),
               tail="      # det Φ_q could reach zero and changed by more than half"),
            If(Code("t != _sw_tk"), (
                Code("_sw_rate = abs(_sw_d - _sw_det) / abs(t - _sw_tk)"),)))),
        Code("_sw_det = _sw_d"),
        Code("_sw_sig = piv[1]"),
        Code("_sw_good = k + 1"),
        Code("_sw_tk = t")))


def reach_check(watch, tangent=True):
    """The fast sweep's watch on the reach margin of the blocks solved whatever the guess
    (sweep()'s test (5), library reach_kept): the margin of point k in _sw_mc (``watch``
    "call": from reach(); "written": the written-out solver's blocks kept their smallest
    in it), compared with the last point's (_sw_m at _sw_mt, changing by _sw_ms per unit
    of time: at the first point along its tangent, library reach_slope); a step that may
    pass a stretch where a block cannot assemble ends the quick path (sweep() goes on from
    the last point it vouches for). No statements for None."""
    if watch is None:
        return []
    st = [Code("_sw_mc = reach(q, t, p)")] if watch == "call" else []
    return st + [
        If(Code("k > 0"), (
            If(Code("not reach_kept(_sw_mc, _sw_m, _sw_ms, t - _sw_mt)"),
               (Code("return _sw_good"),),
               tail="  # a block's reach margin could have dipped below zero"),
            If(Code("t != _sw_mt"), (Code("_sw_ms = (_sw_mc - _sw_m) / abs(t - _sw_mt)"),)))),
        If(Code("k == 0 and ts.shape[0] > 1" + ("" if tangent else " and _sw_all")), (
            Code("_sw_ms = reach_slope(q, qd, t, ts[1] - t, p, _sw_mc)"),),
           tail="  # the first step: along the tangent"),
        Code("_sw_m = _sw_mc"),
        Code("_sw_mt = t")]


def turn_check(angles):
    """sweep()'s test (3) in the fast sweep: a step that turns a body's angle (``angles``,
    their indices in q) by more than BRANCH_TURN from the last point (Q[k - 1]) ends the
    quick path, as sweep() would take it in substeps. A coarse step can pass a whole
    stretch where the mechanism does not assemble, and land in its own mode beyond it,
    with nothing at either end to tell."""
    if not angles:
        return []
    test = " or ".join(f"abs(q[{j}] - Q[k - 1, {j}]) > BRANCH_TURN" for j in angles)
    return [If(Code(f"k > 0 and ({test})"), (Code("return _sw_good"),),
               tail="  # a body turned too far in one step")]


def _sum_tree(terms):
    """``terms`` added by halves, (a + b) + (c + d): a short chain of dependent additions."""
    if len(terms) == 1:
        return terms[0]
    half = (len(terms) + 1) // 2
    return " + ".join(t[0] if len(t) == 1 else f"({_sum_tree(t)})"
                      for t in (terms[:half], terms[half:]))


def _finite_check(checked):
    """_sw_bad: NaN where a coordinate, velocity or acceleration of the point is not finite
    (x * 0 is 0 for every finite x, NaN for inf and NaN; a sum past 1e308, inf, counts as
    not finite too). ``checked``: the indices of the coordinates that can be (those that
    come out a constant number are finite, their derivatives zero), written out as one
    sum; None: all, in a loop."""
    if checked is None or len(checked) > UNROLL:
        return [
            Code("_sw_bad = 0.0          # x * 0 is 0 for every finite x, NaN for inf and NaN"),
            If(Code("_sw_all"), (Loop(Code("for j in range(N_COORDS)"), (
                Code("_sw_bad += (q[j] + qd[j] + qdd[j]) * 0.0"),)),),
               orelse=(Loop(Code("for j in range(N_COORDS)"), (Code("_sw_bad += q[j] * 0.0"),)),))]
    if not checked:
        return [Code("_sw_bad = 0.0          # (every coordinate a constant number)")]
    both = _sum_tree([f"(q[{j}] + qd[{j}] + qdd[{j}])" for j in checked])
    one = _sum_tree([f"q[{j}]" for j in checked])
    return [Comment("x * 0 is 0 for every finite x, NaN for inf and NaN (the coordinates "
                    "that are not constant)"),
            If(Code("_sw_all"), (Code(f"_sw_bad = ({both}) * 0.0"),),
               orelse=(Code(f"_sw_bad = ({one}) * 0.0"),))]


def _rows(step, name, out):
    """Row k of ``out`` (Q, QD, QDD) from the point's values: with a written ``step``,
    straight from the numbers it stored into ``name`` (q, qd, qdd) when it stored every
    one (numba then keeps them in registers rather than reading the array back), else
    copied from ``name``."""
    if step is not None:
        stored = {x.lhs: x.expr for x in (*step[1], *step[2]) if isinstance(x, Store)}
        n = sum(lhs.startswith("q[") for lhs in stored)    # the position code stores all
        values = [stored.get(f"{name}[{j}]") for j in range(n)]
        if n and all(v is not None for v in values):
            return [Store(f"{out}[k, {j}]", v) for j, v in enumerate(values)]
    return [Loop(Code("for j in range(N_COORDS)"), (Code(f"{out}[k, j] = {name}[j]"),))]


def sweep_fast_body(step=None, pairs=(), signs=(), guessed=None, tangent=True, watch=None,
                    angles=(), forces=None, checked=None, det=None, statics=None):
    """The statements of sweep_fast's body: with ``step`` (written_step: the position and
    the derivative statements) the solvers written out, else calls of position_sorted and
    derivatives_sorted. ``pairs``: the TrigPairs the step turns; ``signs``: the assembly
    signs of its dyads, taken at the first point and kept (ir.Variant); ``guessed``: the
    coordinates whose guess the position solve reads, ``tangent``: whether a position
    sweep takes the derivatives at its first point (where Newton blocks need a tangent to
    predict the second; _predictors); ``watch``: how its reach margins are watched
    (reach_check); ``angles``: the indices of the bodies' angles (turn_check); ``checked``:
    those of the coordinates that can come out not finite (_finite_check; None: all);
    ``det``: jacobian_det written out for a position sweep's watch (written_det; None:
    a call).
    ``forces``: the body of sweep_fast_forces instead, the multipliers after the
    derivatives at every point (with ``step``: the statements of
    dynamics_code.written_forces; else True: a call of dynamics_sorted). ``statics``: the
    body of sweep_fast_statics instead (with ``step``), the multipliers at q̇ = q̈ = 0
    after the position code at every point (dynamics_code.written_forces)."""
    init, keep = _memory(pairs) if step is not None else ([], [])
    if step is not None:
        init += [Code("{0} = 1.0  # a dyad's assembly sign, from the first point", (s,))
                 for s in signs]
        before, position, derivatives = step
        derivatives = list(derivatives) + list(forces or ())
        solve = [Comment("position_sorted() and derivatives_sorted() written out here, the "
                         "sin and cos"),
                 Comment("of solved coordinates computed once for both; a failure ends the "
                         "quick path at"),
                 Comment("this point")] + list(position)
        warm = [Code(f"_sw_warm = k % {SWEEP_RESYNC} != 0   # turn sin and cos from the last "
                     "point")]
    else:
        solve = [If(Code("position_sorted(q, t, p, tol, xtol, maxit, info) != 0"),
                    (Code("return _sw_good"),))]
        derivatives = [If(Code("derivatives_sorted(q, t, p, qd, qdd, piv) != 0"),
                          (Code("return _sw_good"),))]
        if forces:
            derivatives = [If(Code("dynamics_sorted(q, t, p, qd, qdd, piv, LAM[k], FACTORS[k]) "
                                   "!= 0"), (Code("return _sw_good"),)),
                           Code("FPIV[k] = piv[2]")]
        warm, before = [], []
    solve.append(If(Code("_sw_all or k == 0" if tangent else "_sw_all"), tuple(derivatives)))
    solve += list(statics or ())
    checks = [
        *turn_check(angles),
        *reach_check(watch, tangent),
        Code("_sw_corr = 0.0"),
        *_finite_check(checked),
        *_each(guessed, ("_sw_corr = max(_sw_corr, abs(q[{j}] - _sw_qp[{j}]))",)),
        If(Code("_sw_bad != 0.0"), (Code("return _sw_good"),)),
        If(Code("k > 0" if tangent else "k > 1 or k == 1 and _sw_all"), (
            If(Code("_sw_corr > BRANCH_RATIO * _sw_move + BRANCH_ATOL * (1.0 + _sw_size)"),
               (Code("return _sw_good"),)),),
           tail="" if tangent else
           "  # (a position sweep's second point, predicted constant: its signs alone)"),
        If(Code("_sw_all"), (
            If(Code("k > 0 and (not piv[0] * _sw_det > 0.0 or piv[1] != _sw_sig)"),
               (Code("return _sw_good"),),
               tail="        # a block's sign changed: another branch, or a singular point"),
            If(Code("k > 0"), (
                If(Code(_NEAR.format(d="piv[0]")), (Code("return _sw_good"),),
                   tail="      # det Φ_q could reach zero and changed by more than half"),
                If(Code("t != _sw_tk"), (
                    Code("_sw_rate = abs(piv[0] - _sw_det) / abs(t - _sw_tk)"),)))),
            Code("_sw_det = piv[0]"),
            Code("_sw_sig = piv[1]"),
            Code("_sw_tk = t"),
            Code("_sw_good = k + 1")),
           orelse=(_position_det(det),)),
        *_rows(step, "q", "Q"),
        If(Code("_sw_keep_d"), tuple(_rows(step, "qd", "QD"))),
        If(Code("_sw_keep_dd"), tuple(_rows(step, "qdd", "QDD"))),
        Code("STATUS[k, STATUS_CODE] = OK"),
        If(Code("_sw_iterations"), (
            Code("STATUS[k, STATUS_ITERATIONS] = min(info[INFO_ITERATIONS], STATUS_MAX)"),)),
        If(Code("_sw_substeps"), (Code("STATUS[k, STATUS_SUBSTEPS] = 0"),)),
    ]
    loop = Loop(Code("for k in range(ts.shape[0])"),
                tuple([Code("t = ts[k]")] + warm + [_predictors(guessed, tangent)] + solve + checks + keep))
    last = If(Code("_sw_good < ts.shape[0]"), (
        If(Code("not jacobian_det(q, ts[ts.shape[0] - 1], p, piv) * _sw_det > 0.0 or "
                "piv[1] != _sw_sig"),
           (Code("return _sw_good"),)),), tail="     # a position sweep: the last point's det Φ_q")
    return [
        Comment("(the loop's own names start with _sw: the solver code written into it uses "
                "others)"),
        Code("q = q0.copy()           # the last accepted point, then the prediction for the "
             "next"),
        Code("qd = np.zeros(N_COORDS)"),
        Code("qdd = np.zeros(N_COORDS)"),
        Code("piv = np.zeros(3)         # det Φ_q, the pattern of its blocks' signs, the "
             "multipliers' pivot") if forces else
        Code("piv = np.zeros(2)         # det Φ_q and the pattern of its blocks' signs"),
        Code("info = np.zeros(POSITION_INFO_SIZE)"),
        Code("_sw_qp = q0.copy()"),
        Code("_sw_q1 = q0.copy()      # a position sweep: the two points before the last"),
        Code("_sw_q2 = q0.copy()"),
        Code("_sw_det = 0.0"),
        Code("_sw_sig = 0.0"),
        Code("_sw_good = 0            # points vouched for: accepted, det Φ_q's sign seen up "
             "to there"),
        Code("_sw_tk = 0.0            # the time det Φ_q was evaluated last, and how fast it "
             "changed"),
        Code("_sw_rate = np.inf         # (unknown at the start: the first step is tested)"),
        *([Code("_sw_m = 1.0              # the reach margin at _sw_mt, changing by _sw_ms"),
           Code("_sw_mt = 0.0"),
           Code("_sw_ms = np.nan           # per unit of time (unknown at the start)"),
           Code("_sw_mc = 1.0")] if watch else []),
        Code("_sw_move = 0.0"),
        Code("_sw_size = 0.0"),
        Code("_sw_keep_d = QD.shape[0] > 0       # velocities stored (no rows: a position "
             "sweep)"),
        Code("_sw_keep_dd = QDD.shape[0] > 0"),
        Code("_sw_all = _sw_keep_d or _sw_keep_dd   # derivatives at every point"),
        Code("_sw_iterations = STATUS.shape[1] > STATUS_ITERATIONS"),
        Code("_sw_substeps = STATUS.shape[1] > STATUS_SUBSTEPS"),
        *init,
        *before,
        loop,
        last,
        Code("return ts.shape[0]"),
    ]
