"""RRR dyads: two bodies joined to each other, each also joined to a point already known.

Their block of Φ has two rows and two angles θ1, θ2 (the block's tears, nothing explicit)
and, once the known coordinates are in, the form of a closed vector loop

    c + R(θ1) u1 + R(θ2) u2 = 0          (R(θ) the rotation by θ; c, u1, u2 free of θ)

in its two rows, as x and y (or y and x). That is a circle–circle intersection: w1 = R(θ1)
u1 lies on the circle |w1| = |u1| and on |d − w1| = |u2| about d = −c, so it is found
without iterating, and of its two solutions the assembly mode picks one by a sign: that of
w1 × w2, the block's Jacobian determinant up to the constant sign of the rows' order
(jacobian_det's block sign). The sign is taken from the guess (a sweep: from its first
point, kept along it); where the two circles do not meet the block gives up as a Newton
would fail, and where they touch (a toggle) it is solved there and flagged singular by
the caller, as today.

``rrr_form`` recognises the form (conservatively: anything else stays Newton);
``rrr_statements`` writes the solution.
"""
from __future__ import annotations

import math

import sympy as sp

from ...protocol import GAVE_UP, PIVOT_RTOL, TINY
from ..codegen.inputs import prologue, sym
from ..codegen.ir import Assign, Code, Comment, Guard, If, Return, Variant
from ..codegen.printer import Derived
from ..codegen.schedule import TempNames, emit
from .blocks import CLOSED_FORM_QUADRATIC, CLOSED_FORM_TRIG, DYAD_RRR


def rrr_form(b, eq, rows):
    """(cx, cy, u1x, u1y, u2x, u2y) of a block of two angle tears whose residual rows have
    the vector-loop form (module docstring), or None. ``rows``: Φ with the coordinates
    known constant substituted."""
    if len(b.vars) != 2 or len(b.tears) != 2 or b.explicit or len(b.residuals) != 2:
        return None
    th = [eq.q[v] for v in b.tears]
    terms = [sp.cos(th[0]), sp.sin(th[0]), sp.cos(th[1]), sp.sin(th[1])]
    coef = []
    for e in b.residuals:
        row = rows[e]
        if row.has(sp.Piecewise) or any(getattr(f, "wraps", False) for f in row.atoms(sp.Function)):
            return None
        try:
            parts = sp.collect(sp.expand(row), terms, evaluate=False)
        except Exception:  # noqa: BLE001 - an expression sympy cannot expand: keep Newton
            return None
        if not set(parts) <= set(terms) | {sp.Integer(1)}:
            return None
        if any(c.free_symbols & set(th) for c in parts.values()):
            return None
        coef.append([sp.sympify(parts.get(t, 0)) for t in terms] + [sp.sympify(parts.get(1, 0))])
    (a1, b1, a2, b2, c0), (a1_, b1_, a2_, b2_, c1) = coef

    def zero(x):
        return sp.expand(x) == 0

    # x then y: R(θ)u = (ux cos − uy sin, ux sin + uy cos)
    if all(zero(x) for x in (a1_ + b1, b1_ - a1, a2_ + b2, b2_ - a2)):
        form = (c0, c1, a1, a1_, a2, a2_)
    # y then x
    elif all(zero(x) for x in (a1 + b1_, b1 - a1_, a2 + b2_, b2 - a2_)):
        form = (c1, c0, a1_, a1, a2_, a2)
    else:
        return None
    if all(zero(x) for x in form[2:4]) or all(zero(x) for x in form[4:6]):
        return None
    return form


def sign_at(form, b, eq, at):
    """The block's determinant sign at the values ``at`` (the model's guess): +1 or −1,
    0 where it is zero or cannot be evaluated (jacobian_det's sign of the block)."""
    J = eq.phi_q
    A = sp.Matrix([[J[e, v] for v in b.vars] for e in b.rows])
    try:
        value = float(A.det().subs(at).evalf())
    except (TypeError, ValueError):
        return 0
    return 1 if value > 0 else -1 if value < 0 else 0


def rrr_statements(b, eq, pairs):
    """The statements solving the dyad block ``b`` (method DYAD_RRR, form (c, u1, u2)):
    the sign from the guess's angles, the intersection, then θ1 and θ2 with their sin and
    cos into ``pairs`` (the TrigPair of each tear: later code shares them, and the fast
    sweep keeps them as its memory of the last point). In the fast sweep (ir.Variant) the
    sign is kept from its first point and each angle follows from the last point's by
    the arcsine series of its small change, without calls."""
    th1, th2 = (eq.q[v] for v in b.tears)
    cx, cy, u1x, u1y, u2x, u2y = b.form
    # numbers and single symbols go straight into the expressions, the others get a name
    U = [e if (e.is_number or e.is_Symbol) else sym(x)
         for x, e in zip(("_u1x", "_u1y", "_u2x", "_u2y"), (u1x, u1y, u2x, u2y))]
    dx, dy, r1, r2, dd, aa, disc, rt, h = (sym(x) for x in (
        "_dx", "_dy", "_r1s", "_r2s", "_dd", "_aa", "_disc", "_rt", "_h"))
    w1x, w1y, w2x, w2y = (sym(x) for x in ("_w1x", "_w1y", "_w2x", "_w2y"))
    sg = Derived("_sg_", th1)
    st = [Comment(f"RRR dyad: c + R({th1}) u1 + R({th2}) u2 = 0, a circle-circle "
                  f"intersection; the assembly sign from the guess")]
    st += [Assign(s, e) for s, e in zip(U, (u1x, u1y, u2x, u2y)) if s != e]
    st += [Assign(r1, U[0] ** 2 + U[1] ** 2), Assign(r2, U[2] ** 2 + U[3] ** 2)]
    st += [Guard(r, sp.Float(TINY), GAVE_UP) for r, e in ((r1, st[-2].expr), (r2, st[-1].expr))
           if not e.is_number]
    # the sign of w1 × w2 at the guess, |u1||u2| sin(θ2 − θ1 + β) with β the angle from
    # u1 to u2: + where θ2 − θ1 + β lies in (0, π) modulo 2π (no call of sin)
    beta = sp.atan2(U[0] * U[3] - U[1] * U[2], U[0] * U[2] + U[1] * U[3])
    beta = sp.Float(float(beta)) if beta.is_number else beta
    sign = (
        Code("_f = ({0} - {1} + {2}) * {3}", (th2, th1, beta, sp.Float(1 / (2 * math.pi)))),
        Code("_f -= math.floor(_f)"),
        If(Code("not min(_f, abs(_f - 0.5), 1.0 - _f) > {0}",
                (sp.Float(PIVOT_RTOL / (2 * math.pi)),)),
           (Return(GAVE_UP),), tail="  # the guess at a toggle: no mode to keep"),
        Code("{0} = 1.0 if _f < 0.5 else -1.0", (sg,)))
    st.append(Variant(sign, (If(Code("k == 0"), sign, tail="  # kept from the first point"),)))
    st += [Assign(dx, -cx), Assign(dy, -cy), Assign(dd, dx ** 2 + dy ** 2),
           Guard(dd, sp.Float(TINY), GAVE_UP),
           Assign(aa, r1 - r2 + dd), Assign(disc, 4 * dd * r1 - aa ** 2),
           If(Code("{0} < 0.0", (disc,)), (
               If(Code("{0} < -1e-12 * 4.0 * {1} * {2}", (disc, dd, r1)), (Return(GAVE_UP),),
                  tail="  # the circles do not meet: no assembly here"),
               Code("{0} = 0.0  # they touch: a toggle", (disc,)))),
           Code("{0} = {1} * math.sqrt({2})", (rt, sg, disc)),
           Assign(h, sp.Rational(1, 2) / dd),
           _watched("0.5 * {0} * {1} / {2}", (disc, h, r1)),
           Assign(w1x, h * (aa * dx + rt * dy)), Assign(w1y, h * (aa * dy - rt * dx)),
           Assign(w2x, dx - w1x), Assign(w2y, dy - w1y)]
    for pair, (ux, uy), w, r in ((pairs[0], U[:2], (w1x, w1y), r1),
                                 (pairs[1], U[2:], (w2x, w2y), r2)):
        th, s, c = pair.angle, pair.sin, pair.cos
        st += [Assign(c, (ux * w[0] + uy * w[1]) / r), Assign(s, (ux * w[1] - uy * w[0]) / r),
               Variant(_angle(th, s, c), _angle_turned(th, s, c, pair.memory))]
    return st


_TURN = repr(1 / (2 * math.pi))


def _angle(th, s, c):
    """θ from its sin and cos: the 2π-representative nearest the guess (θ's value)."""
    return (Code("_y1 = math.atan2({0}, {1})", (s, c)),
            Code("{0} = _y1 + 2.0 * math.pi * math.floor(({0} - _y1) * " + _TURN + " + 0.5)",
                 (th,)))


def _angle_turned(th, s, c, memory):
    """θ in the fast sweep: the last point's angle plus the change whose sine is
    sin(θ − last) (arcsine series to the ninth power, below 1e-23 for a change under
    0.01); elsewhere, and every SWEEP_RESYNC-th point (where the loop calls sin and cos
    afresh: the changes' roundings do not add up), as _angle. The guess within 1 of the
    last point makes the representative the same as _angle's."""
    last, last_sin, last_cos = memory
    return (Code("_sd = {0} * {3} - {1} * {2}", (s, c, last_sin, last_cos)),
            If(Code("_sw_warm and abs(_sd) < 0.01 and {0} * {3} + {1} * {2} > 0.0 and "
                    "abs({4} - {5}) < 1.0", (c, s, last_sin, last_cos, th, last)), (
                Code("_s2 = _sd * _sd"),
                Code("{0} = {1} + _sd * (1.0 + _s2 * (1.0 / 6.0 + _s2 * (3.0 / 40.0 + _s2 * "
                     "(5.0 / 112.0 + _s2 * (35.0 / 1152.0)))))", (th, last))),
               _angle(th, s, c)))


def signed(method, form):
    """Whether a one-tear closed form (plan.form) picks its root by a sign: a quadratic
    (a slider's x on a guide at a distance from a known point: circle-line), or
    a sin y + b cos y + c with coefficients that vary (a lever through a moving point).
    A form with constant a and b (a body kept parallel to a guide) keeps the root nearest
    the guess instead, its two roots a fixed half turn apart."""
    if method == CLOSED_FORM_QUADRATIC:
        return True
    return method == CLOSED_FORM_TRIG and not (form[0].is_number and form[1].is_number)


def _watched(margin, args):
    """The block's reach margin (margin's, from its own numbers) into the smallest of the
    point: _sw_mc in the fast sweep (sweep.reach_check), _mc in position_sorted, which
    hands it to sweep() in info[INFO_REACH] (position.position_body)."""
    return Variant((Code(f"_mc = min(_mc, {margin})", args),),
                   (Code(f"_sw_mc = min(_sw_mc, {margin})", args),))


def _sign(sg, value, bound, what):
    """The assembly sign ``sg`` from ``value`` at the guess (GAVE_UP where it is within
    ``bound`` of zero: a guess at a toggle), kept from a fast sweep's first point."""
    body = (Code("_o = {0}", (value,)),
            If(Code("not abs(_o) > {0}", (bound,)), (Return(GAVE_UP),),
               tail=f"  # the guess at a toggle: no mode to keep ({what})"),
            Code("{0} = 1.0 if _o > 0.0 else -1.0", (sg,)))
    return Variant(body, (If(Code("k == 0"), body, tail="  # kept from the first point"),))


def trig_statements(y, form, pair):
    """a sin y + b cos y + c = 0 by the sign of the block's derivative a cos y − b sin y
    (w |(a, b)| at the root (sin, cos) = ((u a − w b), (w a + u b)) / |(a, b)|, u = −c /
    |(a, b)|, w = ±√(1 − u²)): the root whose derivative has the guess's sign; sin and
    cos of y into ``pair``, y itself as an RRR dyad's angles."""
    ka, kb, kc = form
    a, bb, rad, u, w = (sym(x) for x in ("_ka", "_kb", "_rad", "_u", "_w"))
    sg = Derived("_sg_", y)
    st = [Comment(f"closed form: a sin({y}) + b cos({y}) + c = 0, the root of the guess's "
                  f"sign of a cos({y}) - b sin({y})"),
          Assign(a, ka), Assign(bb, kb), Assign(rad, sp.sqrt(a ** 2 + bb ** 2)),
          Guard(rad, sp.Float(TINY), GAVE_UP), Assign(u, -kc / rad),
          *([] if kc == 0 else      # u = 0: it always assembles
            [If(Code("not abs({0}) <= 1.0 + 1e-12", (u,)), (Return(GAVE_UP),),
                tail="  # no assembly here")]),
          _watched("1.0 - {0} * {0}", (u,)),
          Code("{0} = min(1.0, max(-1.0, {0}))", (u,)),
          _sign(sg, a * sp.cos(y) - bb * sp.sin(y), sp.Float(PIVOT_RTOL) * rad, "a lock"),
          Code("{0} = {1} * math.sqrt(1.0 - {2} * {2})", (w, sg, u)),
          Assign(pair.sin, (u * a - w * bb) / rad), Assign(pair.cos, (w * a + u * bb) / rad),
          Variant(_angle(y, pair.sin, pair.cos),
                  _angle_turned(y, pair.sin, pair.cos, pair.memory))]
    return st


def quadratic_statements(y, form):
    """A y² + B y + C = 0 by the sign of its derivative 2 A y + B (±√disc at the roots):
    the root whose derivative has the guess's sign (q / A has −sign(B), C / q has
    sign(B), q = −(B + sign(B) √disc) / 2)."""
    qa, qb, qc = form
    sg = Derived("_sg_", y)
    A, B, C = sym("_qa"), sym("_qb"), sym("_qc")
    return [Comment(f"closed form: A {y}^2 + B {y} + C = 0, the root of the guess's sign "
                    f"of 2 A {y} + B"),
            Assign(A, qa), Assign(B, qb), Assign(C, qc),
            Code("_disc = _qb * _qb - 4.0 * _qa * _qc"),
            _watched("_disc / max(_qb * _qb + 4.0 * abs(_qa * _qc), TINY)", ()),  # B = AC = 0: 0
            If(Code("_disc < 0.0"),
               (If(Code("_disc < -1e-12 * _qb * _qb"), (Return(GAVE_UP),),
                   tail="  # no assembly here"), Code("_disc = 0.0  # a toggle"))),
            _sign(sg, 2 * A * y + B, sp.Float(PIVOT_RTOL) * (sp.Abs(2 * A * y) + sp.Abs(B)),
                  "a lock"),
            Code("_qq = -0.5 * (_qb + math.copysign(math.sqrt(_disc), _qb))"),
            If(Code("not abs(_qa) > 1e-300 or not abs(_qq) > 1e-300"), (Return(GAVE_UP),)),
            Code("{0} = _qq / _qa if {1} * math.copysign(1.0, _qb) < 0.0 else _qc / _qq",
                 (y, sg))]


def guess_free(b):
    """Whether the block's solution does not depend on its guess (an RRR dyad, a form
    whose root a sign picks): its reach margin is watched along a sweep (reach_body)."""
    return b.method == DYAD_RRR or signed(b.method, b.form)


def margin(b):
    """The block's reach margin, a number in (−∞, 1] that is positive where the block
    assembles, zero where its two solutions meet (a toggle) and negative where it has none,
    and that crosses zero at a simple root of its discriminant (linearly in time): an RRR
    dyad's sin² of the angle between d and w1 (1 − a²/(4 d² r1²)), a trig form's
    1 − c²/(a² + b²), a quadratic's (B² − 4AC)/(B² + 4|AC|). Each denominator is kept from
    zero (TINY): a quadratic with B = AC = 0 (x² = 0, a toggle) has the margin 0, not 0/0."""
    tiny = sp.Float(TINY)

    def floored(x):     # Max(x, tiny): left unevaluated (sympy's comparisons cost 0.1 s a
        return sp.Max(x, tiny, evaluate=not x.free_symbols)   # build), a number compared
    if b.method == DYAD_RRR:
        cx, cy, u1x, u1y, u2x, u2y = b.form
        r1, r2, dd = u1x ** 2 + u1y ** 2, u2x ** 2 + u2y ** 2, cx ** 2 + cy ** 2
        return 1 - (r1 - r2 + dd) ** 2 / floored(4 * dd * r1)
    if b.method == CLOSED_FORM_TRIG:
        ka, kb, kc = b.form
        return 1 - kc ** 2 / floored(ka ** 2 + kb ** 2)
    qa, qb, qc = b.form
    return (qb ** 2 - 4 * qa * qc) / floored(qb ** 2 + 4 * sp.Abs(qa * qc))


def reach_body(plan, eq):
    """The body of reach(q, t, p): the smallest reach margin (margin) of the blocks whose
    solution does not depend on the guess, at a solved configuration; None where the plan
    has none. The sweeps watch it as they watch det Φ_q: a closed form finds the far side
    of a stretch where it cannot assemble as readily as the near side, in the same mode,
    and only the margin's dip below zero in between tells them apart (det Φ_q, a product
    of all blocks, can hide one block's dip behind another's growth)."""
    margins = [margin(b) for b in plan.blocks if guess_free(b)]
    if not margins:
        return None
    names = [sym(f"_rm{i}") for i in range(len(margins))]
    st = [Assign(n, m) for n, m in zip(names, margins)]
    body = prologue(eq, margins) + emit(st, TempNames("_r"), plan.cse)
    if len(names) == 1:
        return body + [Code("return {0}", (names[0],))]
    return body + [Code("return min(" + ", ".join("{%d}" % i for i in range(len(names))) + ")",
                        tuple(names))]


__all__ = ["guess_free", "margin", "reach_body", "rrr_form", "rrr_statements", "sign_at", "signed", "trig_statements",
           "quadratic_statements"]
