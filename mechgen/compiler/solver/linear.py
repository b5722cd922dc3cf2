"""The linear passes of the sorted solver: Φ_q q̇ = ν and Φ_q q̈ = γ by block forward
substitution (velocity_sorted, acceleration_sorted, both in one pass for derivatives_sorted)
and det Φ_q as the product of the diagonal blocks' determinants (jacobian_det).
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ...protocol import SING_RTOL
from ..codegen.inputs import free, prologue, sym, unpack
from ..codegen.ir import Assign, Code, Guard, Helper, If, Return, Store
from ..codegen.schedule import TempNames, emit
from .position import block_comment

SINGULAR = 2           # status: Φ_q lost rank, the derivatives are not determined


@dataclass(frozen=True)
class LinearCode:
    """The forward substitution block by block: per block (statements, unknowns), the
    symbols standing for Φ_q's entries (``_j<i>_<j>``) and the right sides (``_n<i>``,
    ``_g<i>``), the unknowns that come out constant ({symbol: value}) and each block's
    determinant (a symbol or expression; None where it is a constant: its sign never
    changes), which the fast sweep watches (a block of three or more unknowns has one only
    when asked for: ``dets``)."""
    blocks: tuple
    jsym: dict
    rsym: dict
    constants: dict
    dets: tuple = ()


def _rhs_symbols(eq, order):
    rhs = eq.nu if order == 1 else eq.gamma
    prefix = "_n" if order == 1 else "_g"
    return {i: rhs[i] if rhs[i].is_number else sym(f"{prefix}{i}") for i in range(rhs.rows)}


_LAST = {}      # the passes of the last (plan, eq) without ``known``, by order: the velocity
                # pass is laid out for velocity_sorted and again for derivatives_sorted


def linear_blocks(plan, eq, order, known=None) -> LinearCode:
    """linear_code, its results without ``known`` kept for the last plan and equations
    (the same objects) and reused."""
    if known:
        return linear_code(plan, eq, order, known)
    last = _LAST.get("for")
    if last is None or last[0] is not plan or last[1] is not eq:
        _LAST.clear()
        _LAST["for"] = (plan, eq)
    if order not in _LAST:
        _LAST[order] = linear_code(plan, eq, order)
    return _LAST[order]


def linear_code(plan, eq, order, known=None, dets=False) -> LinearCode:
    """The block forward substitution for Φ_q x = rhs (ν for order 1, γ for order 2).
    Unknowns that come out as constants (``X2d = 0``) are substituted forward so that
    nothing is multiplied by a known zero; only constants found here are used, so it stays
    exact for any (q, q̇) it is given. ``known``: rows of the right side known constant.
    ``dets``: a block of three or more unknowns also takes its determinant from its
    elimination (``_det<row> = _diag_product(_A)``)."""
    xs = list(eq.qd if order == 1 else eq.qdd)
    jsym, consts, out, block_dets = {}, {}, [], []
    for (i, j), x in eq.nonzeros.items():
        jsym[i, j] = x if x.is_number else sym(f"_j{i}_{j}")
    cols = eq.row_columns
    rsym = _rhs_symbols(eq, order)
    rsym.update(known or {})      # right sides known to be constants
    for b in plan.blocks:
        body = [block_comment(eq, b)]
        inside = set(b.vars)
        bvec = []
        for e in b.rows:
            acc = rsym[e]
            for j in cols[e]:
                if j not in inside:
                    acc -= jsym[e, j] * consts.get(xs[j], xs[j])
            bvec.append(acc)
        A = [[jsym.get((e, v), sp.Integer(0)) for v in b.vars] for e in b.rows]
        scale = [sum(sp.Abs(jsym[e, j]) for j in cols[e]) for e in b.rows]
        k = b.size
        if k == 1:
            a, x = A[0][0], xs[b.vars[0]]
            if not a.is_number:
                body.append(Guard(a, sp.Float(SING_RTOL) * scale[0], SINGULAR))
            block_dets.append(None if a.is_number else a)
            value = bvec[0] / a
            if value.is_number:
                consts[x] = value
            body.append(Assign(x, value))
        elif k == 2:
            det = sym(f"_det{b.rows[0]}")
            body.append(Assign(det, A[0][0] * A[1][1] - A[0][1] * A[1][0]))
            body.append(Guard(det, sp.Float(SING_RTOL) * scale[0] * scale[1], SINGULAR))
            block_dets.append(det)
            body.append(Assign(xs[b.vars[0]], (bvec[0] * A[1][1] - A[0][1] * bvec[1]) / det))
            body.append(Assign(xs[b.vars[1]], (A[0][0] * bvec[1] - A[1][0] * bvec[0]) / det))
        else:
            bs = [sym(f"_bb{i}") for i in range(k)]
            body += [Assign(bs[i], bvec[i]) for i in range(k)]
            body += [Code(f"_A = np.empty(({k}, {k}))"), Code(f"_b = np.empty({k})")]
            for i in range(k):
                body += [Store(f"_A[{i}, {j}]", A[i][j]) for j in range(k)]
                body.append(Store(f"_b[{i}]", bs[i]))
            body.append(If(Code(f"_gauss(_A, _b) < {k}"), (Return(SINGULAR),)))
            if dets:
                det = sym(f"_det{b.rows[0]}")
                body.append(Code("{0} = _diag_product(_A)", (det,)))
                block_dets.append(det)
            else:
                block_dets.append(sp.nan)
            body += [Code(f"{{0}} = _b[{i}]", (xs[v],)) for i, v in enumerate(b.vars)]
        out.append((tuple(body), tuple(xs[v] for v in b.vars)))
    return LinearCode(tuple(out), jsym, rsym, consts, tuple(block_dets))


def _guards_and_exprs(body):
    return ([x.expr for x in body if isinstance(x, (Assign, Store))] +
            [x.bound for x in body if isinstance(x, Guard)] +
            [x.value for x in body if isinstance(x, Guard)])


def linear_head(eq, order, body, jsym, rsym):
    """Assignments of the Jacobian entries and right sides that ``body`` uses."""
    J = eq.nonzeros
    rhs = eq.nu if order == 1 else eq.gamma
    used = free(_guards_and_exprs(body))
    head = [Assign(s, J[i, j]) for (i, j), s in jsym.items()
            if isinstance(s, sp.Symbol) and s in used]
    head += [Assign(s, rhs[i], eq.labels[i])
             for i, s in rsym.items() if isinstance(s, sp.Symbol) and s in used]
    return head


def linear_sorted_body(plan, eq, order):
    """(body, helpers) of velocity_sorted (order 1) or acceleration_sorted (order 2); split
    into parts of about plan.chunk_stores statements for large models."""
    code = linear_blocks(plan, eq, order)
    xs = list(eq.qd if order == 1 else eq.qdd)
    name = "velocity" if order == 1 else "acceleration"
    args = "q, t, p, out" if order == 1 else "q, qd, t, p, out"
    groups, current, size = [], [], 0
    for piece in code.blocks:
        if current and size + len(piece[0]) > plan.chunk_stores:
            groups.append(current)
            current, size = [], 0
        current.append(piece)
        size += len(piece[0])
    groups.append(current)
    if len(groups) <= 2:
        groups = [list(code.blocks)]
    done, top, helpers = set(), [], []
    where = {x: k for k, x in enumerate(xs)}
    for i, group in enumerate(groups):
        body = [x for piece in group for x in piece[0]]
        st = linear_head(eq, order, body, code.jsym, code.rsym) + body
        exprs = [x.expr for x in st if isinstance(x, (Assign, Store))]
        lines = prologue(eq, exprs, with_qd=(order == 2))
        used = free(exprs + [x.bound for x in st if isinstance(x, Guard)])
        lines += [x for x in unpack(used & done, xs, "out")]
        lines += emit(st, TempNames(), plan.cse)
        solved = [x for piece in group for x in piece[1]]
        done |= set(solved)
        if len(groups) == 1:
            lines += [Store(f"out[{k}]", s) if plan.solved[k] else _not_solved("out", k, s)
                      for k, s in enumerate(xs)]
            return lines + [Return(0)], []
        lines += [Store(f"out[{where[x]}]", x) for x in solved] + [Return(0)]
        helper = f"_{name}_part{i}"
        doc = (f"{name.capitalize()} solver, part {i + 1} of {len(groups)}: "
               + ", ".join(x.name for x in solved) + ".")
        helpers.append(Helper(helper, args, doc, tuple(lines)))
        top += [Code(f"_status = {helper}({args})"),
                If(Code("_status != 0"), (Return(sym("_status")),))]
    top += [_not_solved("out", k, s) for k, s in enumerate(xs) if not plan.solved[k]]
    return top + [Return(0)], helpers


def _not_solved(array, k, s):
    return Code(f"{array}[{k}] = math.nan  # {s.name}: not solved in this pruned build")


@dataclass(frozen=True)
class DerivativeCode:
    """The statements of the combined velocity and acceleration pass, and the stores of q̇
    and q̈ after them."""
    statements: tuple
    tail: tuple


def derivative_code(plan, eq):
    """The combined pass; None when it is too long for one function (a split model then
    calls velocity_sorted and acceleration_sorted)."""
    vel = linear_blocks(plan, eq, 1)
    vconst = vel.constants          # X2d = 0, ...: exact here, computed just above
    # rows of γ that these constants make constant (a fixed angle's γ = 0, say)
    known, constant = {}, set(vconst)
    for i, g in enumerate(eq.gamma):
        if not g.is_number and g.free_symbols & constant:
            g = g.xreplace(vconst)
            if g.is_number:
                known[i] = g
    acc = linear_blocks(plan, eq, 2, known)
    vbody = [x for piece in vel.blocks for x in piece[0]]
    abody = [x for piece in acc.blocks for x in piece[0]]
    if len(vbody) + len(abody) > 3 * plan.chunk_stores:
        return None
    head = linear_head(eq, 1, vbody + abody, vel.jsym, vel.rsym)
    gamma = [Assign(x.target, x.expr.subs(vconst), x.comment)
             for x in linear_head(eq, 2, abody, {}, acc.rsym)]
    # det Φ_q up to a constant sign (the product of the block determinants) and the
    # pattern of their signs: the fast sweep watches both (a branch is their signs)
    vdets = linear_code(plan, eq, 1, dets=True)
    vbody = [x for piece in vdets.blocks for x in piece[0]]
    det = branch_code(vdets.dets, "piv")
    tail = []
    for k, (v, a) in enumerate(zip(eq.qd, eq.qdd)):
        if plan.solved[k]:
            tail += [Store(f"qd[{k}]", v), Store(f"qdd[{k}]", a)]
        else:
            tail += [Code(f"qd[{k}] = math.nan"), Code(f"qdd[{k}] = math.nan")]
    return DerivativeCode(tuple(head + vbody + det + gamma + abody), tuple(tail))


def derivatives_sorted_body(plan, eq, code):
    """The body of derivatives_sorted from derivative_code (None when that is None)."""
    if code is None:
        return None
    exprs = [x.expr for x in code.statements if isinstance(x, (Assign, Store))]
    return (prologue(eq, exprs) + emit(code.statements, TempNames(), plan.cse)
            + list(code.tail) + [Return(0)])


def branch_code(dets, array):
    """``array[0] = `` the product of the block determinants ``dets`` (det Φ_q up to a
    constant sign), ``array[1] = `` the pattern of their signs: the sum of 2**i over the
    blocks i (constant ones left out, i modulo 52) whose determinant is negative. Along a
    branch neither changes sign nor pattern; a step to another assembly mode flips at
    least one block, also where two flips would leave the product's sign as it was."""
    watched = [d for d in dets if d is not None]
    st = [Store(f"{array}[0]", sp.Mul(*watched), "det Φ_q (up to sign)"),
          Code(f"{array}[1] = 0.0  # the pattern of the blocks' signs")]
    for i, d in enumerate(watched):
        st.append(Code(f"{array}[1] += {float(2 ** (i % 52))!r} * ({{0}} < 0.0)", (d,)))
    return st


def jacobian_det_body(plan, eq):
    """det Φ_q as the product of the determinants of its diagonal blocks in the solving
    order (equal to det Φ_q up to the constant sign of the permutation): its sign changes
    exactly where Φ_q loses rank along a branch, which the sweep watches for. It goes to
    piv[0] and is returned; piv[1] receives the pattern of the blocks' signs
    (branch_code)."""
    st = jacobian_det_statements(plan, eq)
    exprs = [x.expr for x in st if isinstance(x, (Assign, Store))]
    return prologue(eq, exprs) + emit(st, TempNames(), plan.cse) + [Code("return piv[0]")]


def jacobian_det_statements(plan, eq):
    """jacobian_det's statements before their CSE, which read the coordinates by name
    (the fast sweep writes them into its loop: sweep.in_loop)."""
    J = eq.phi_q
    st, factors = [], []
    for b in plan.blocks:
        A = [[J[e, v] for v in b.vars] for e in b.rows]
        d = sym(f"_det{b.rows[0]}")
        if b.size == 1:
            value = A[0][0]
        elif b.size == 2:
            value = A[0][0] * A[1][1] - A[0][1] * A[1][0]
        else:
            st.append(Code(f"_A = np.empty(({b.size}, {b.size}))"))
            st += [Store(f"_A[{i}, {j}]", A[i][j]) for i in range(b.size) for j in range(b.size)]
            st.append(Code("{0} = _det(_A)", (d,)))
            factors.append(d)
            continue
        if value.is_number:
            factors.append(None if value != 0 else value)
        else:
            st.append(Assign(d, value))
            factors.append(d)
    return st + branch_code(factors, "piv")
