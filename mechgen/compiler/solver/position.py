"""The sorted position solver: block by block, explicit assignments, closed forms and
Newton iterations (1 unknown, or torn: a few tears with the other unknowns explicit).

``position_code`` writes the statements of every block once (the plan keeps them, with the
names under which calls are shared); ``position_body`` lays them out as one function or,
for a large model, as parts. Names made from model names (``_sin_<y>``, ``_den_<z>``,
``_d<z>_d<y>``) are printer.Derived symbols, so that they print with the mapped names.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import sympy as sp

from ...model.geometry import T
from ...protocol import PIVOT_RTOL, TINY
from ..codegen.inputs import free, sym, time_local, unpack
from ..codegen.ir import (Assign, Break, Code, Comment, Guard, Helper, If, Loop, Return, Store,
                 TrigPair, Variant, count_lines, replaced)
from ..codegen.printer import Derived
from ..codegen.schedule import TempNames, emit
from .blocks import CLOSED_FORM_TRIG, DYAD_RRR, EXPLICIT, NEWTON, linear_in
from .dyads import guess_free, quadratic_statements, rrr_statements, signed, trig_statements

GAVE_UP = 4            # status: the sorted solver gave up (the full Newton takes over)


def trig_pair(y):
    return TrigPair(y, Derived("_sin_", y), Derived("_cos_", y),
                    (Derived("_sw_", y), Derived("_sw_sin_", y), Derived("_sw_cos_", y)))


def block_comment(eq, b):
    names = ", ".join(str(eq.q[v]) for v in b.vars)
    rows = "; ".join(eq.labels[e] for e in b.rows)
    return Comment(f"block: {names} from {rows}")


class Rows:
    """Φ's rows with the coordinates found constant so far substituted, each computed once
    for the whole planning pass (the plan and the position code read the same rows)."""

    def __init__(self, eq):
        self.phi, self.cache, self._symbols = eq.phi, {}, {}

    def symbols(self, e):
        """The free symbols of row e (computed once)."""
        if e not in self._symbols:
            self._symbols[e] = self.phi[e].free_symbols
        return self._symbols[e]

    def at(self, known):
        return _RowsAt(self, dict(known))


class _RowsAt:
    def __init__(self, rows, known):
        self.rows, self.known, self.key = rows, known, tuple(known)

    def __getitem__(self, e):
        row = self.rows.phi[e]
        if not self.known:
            return row
        # only the constants this row holds: most rows hold none, and a row's substituted
        # form is then shared by every later block (the same result as substituting all)
        mine = tuple(s for s in self.key if s in self.rows.symbols(e))
        if not mine:
            return row
        cache = self.rows.cache
        if (e, mine) not in cache:
            cache[e, mine] = row.subs({s: self.known[s] for s in mine})
        return cache[e, mine]


@dataclass(frozen=True)
class Piece:
    """The code of one block: its statements, the symbols its rows read, the coordinates
    it solves, how many lines it prints, and whether it keeps a reach margin (_mc:
    dyads.guess_free)."""
    statements: tuple
    used: frozenset
    solved: tuple
    lines: int
    watched: bool = False


@dataclass(frozen=True)
class PositionCode:
    """The position solver's code per block; ``shared``: (call, name) pairs of the calls
    shared across blocks (None when not shared); ``trig_pairs``: the angles whose sin and
    cos the code calls as a pair (the fast sweep turns those instead)."""
    pieces: tuple
    shared: tuple | None
    trig_pairs: tuple
    signs: tuple = ()           # the first angle of each RRR dyad (its sign is _sg_<angle>)

    @property
    def lines(self):
        return sum(p.lines for p in self.pieces)

    @property
    def shared_map(self):
        return dict(self.shared or ())


def position_code(plan, eq, share: bool, rows: Rows | None = None) -> PositionCode:
    """The statements of every block of ``plan`` (blocks, known constants, cse)."""
    return _Writer(plan, eq, share, rows or Rows(eq)).code()


class _Writer:
    """Writes the blocks in order. What one block leaves for the next (the calls shared so
    far, the coordinates solved so far, the constants found) is state of this one pass."""

    def __init__(self, plan, eq, share, rows):
        self.plan, self.eq, self.q, self.rows = plan, eq, list(eq.q), rows
        self.cse = plan.cse
        self.known = {}
        self.shared = {} if share else None
        self.trig_pairs = []
        self.signs = []
        self.avail = set(eq.params) | {T}
        self.temps = TempNames()

    def code(self):
        q, phi, pieces = self.q, self.eq.phi, []
        known_all = self.plan.known_values
        for b in self.plan.blocks:
            st = [block_comment(self.eq, b)]
            if b.method == EXPLICIT:
                st += self.shared_emit(self.explicit(b.explicit))
                z = q[b.vars[0]]
                if z in known_all:
                    self.known[z] = known_all[z]
            elif b.method == NEWTON:
                st += self.newton(b)
            elif b.method == DYAD_RRR:
                st += self.dyad(b)
            else:
                st += self.closed_form(b)
            used = free([phi[e] for e in b.rows]) | {q[v] for v in b.vars}
            pieces.append(Piece(tuple(st), frozenset(used), tuple(q[v] for v in b.vars),
                                count_lines(st), guess_free(b)))
            self.avail |= {q[v] for v in b.vars}
        shared = None if self.shared is None else tuple(self.shared.items())
        return PositionCode(tuple(pieces), shared, tuple(self.trig_pairs), tuple(self.signs))

    # -- shared calls -------------------------------------------------------------------
    def shared_emit(self, st, variant=None):
        """emit(), with function calls (sin, cos, atan2, ...) of coordinates solved by
        earlier blocks computed once for the whole function: each gets a name (``_f3``)
        defined before the first block that needs it."""
        if self.shared is None:
            return emit(st, self.temps, self.cse, variant=variant)
        shared, defs = self.shared, []

        def swap(expr):
            expr = sp.sympify(expr)
            atoms = [a for a in expr.atoms(sp.Function)
                     if a in shared or (a.free_symbols and a.free_symbols <= self.avail)]
            if not atoms:
                return expr
            subs = {}
            for a in sorted(atoms, key=sp.default_sort_key):
                if a not in shared and isinstance(a, (sp.sin, sp.cos)) and a.args[0] in self.q:
                    defs.append(self.pair(a.args[0]))   # sin and cos of a coordinate
                elif a not in shared:
                    shared[a] = sym(f"_f{len(shared)}")
                    defs.append(Assign(shared[a], a))
                subs[a] = shared[a]
            return expr.xreplace(subs)

        out = [replaced(x, swap) for x in st]
        head = emit(defs, self.temps, self.cse) if defs else []
        body = emit(out, self.temps, self.cse, variant=variant)
        if variant is None:
            return head + body
        return head + body[0], body[1]

    def share_trig(self, y):
        """The names of the sin and cos of coordinate y, registered as shared."""
        pair = trig_pair(y)
        if self.shared is not None:
            self.shared[sp.sin(y)], self.shared[sp.cos(y)] = pair.sin, pair.cos
        return pair

    def pair(self, y):
        """sin and cos of y called as a pair, shared by later code; the fast sweep turns
        such pairs from the last point instead."""
        self.trig_pairs.append(y)
        return self.share_trig(y)

    # -- explicit unknowns ----------------------------------------------------------------
    def explicit(self, pairs, tears=()):
        """Statements for z = −rest/coef for each (row, unknown), and optionally dz/dy."""
        phi, q = self.rows.at(self.known), self.q
        st = []
        for e, v in pairs:
            z = q[v]
            coef, rest = linear_in(phi[e], z)
            den = Derived("_den_", z)
            if coef.is_number:
                st.append(Assign(z, -rest / coef, f"row {e}: {self.eq.labels[e]}"))
            else:
                # a reciprocal, then a product: the reciprocal does not wait for the rest
                inv = Derived("_inv_", z)
                st.append(Assign(den, coef))
                st.append(Guard(den, sp.Float(1e-12), GAVE_UP))
                st.append(Assign(inv, 1 / den))
                st.append(Assign(z, -rest * inv, f"row {e}: {self.eq.labels[e]}"))
            for y in tears:
                total = sp.diff(phi[e], q[y])
                for e2, v2 in pairs:
                    if (e2, v2) == (e, v):
                        break
                    total += sp.diff(phi[e], q[v2]) * Derived("_d", q[v2], "_d", q[y])
                dz = Derived("_d", z, "_d", q[y])
                st.append(Assign(dz, -total / coef if coef.is_number else -total * inv))
        return st

    # -- closed forms -----------------------------------------------------------------------
    def closed_form(self, b):
        """The block's tear from its closed form (plan.form): of the two roots, the one
        nearest the current value of y is kept, so the assembly mode is kept; where the
        form picks its root by a sign (dyads.signed), the root of the guess's sign."""
        y = self.q[b.tears[0]]
        if signed(b.method, b.form):
            self.signs.append(y)
            if b.method == CLOSED_FORM_TRIG:
                pair = self.share_trig(y)
                self.trig_pairs.append(y)
                st = trig_statements(y, b.form, pair)
            else:
                st = quadratic_statements(y, b.form)
            return self.shared_emit(st + self.explicit(b.explicit))
        name = str(y)
        st = []

        def value(label, expr):     # constants stay in the expressions (folded)
            if expr.is_number:
                return expr
            s = sym(label)
            st.append(Assign(s, expr))
            return s

        turn = 1 / (2 * math.pi)         # the 2π-shift of each root nearest the current value
        if b.method == CLOSED_FORM_TRIG:
            ka, kb, kc = b.form
            st.append(Comment(f"closed form: a sin({name}) + b cos({name}) + c = 0, "
                              f"the root nearest {name}"))
            a, bb = value("_ka", ka), value("_kb", kb)
            rad = value("_rad", sp.sqrt(a ** 2 + bb ** 2))
            if not rad.is_number:
                st.append(Guard(rad, sp.Float(TINY), GAVE_UP))
            if kc == 0:
                u, asin = sp.Integer(0), sp.Integer(0)
            else:
                u = sym("_u")
                st.append(Assign(u, -kc / rad))
                st.append(If(Code("not abs(_u) <= 1.0 + 1e-12"), (Return(GAVE_UP),),
                             tail="  # no assembly here"))
                st.append(Code("_u = min(1.0, max(-1.0, _u))"))
                asin = sp.asin(u)
            st.append(Assign(sym("_y1"), asin - sp.atan2(bb, a)))
            st.append(Assign(sym("_y2"), sp.pi - asin - sp.atan2(bb, a)))
        else:
            qa, qb, qc = b.form
            st += [Comment(f"closed form: A {name}^2 + B {name} + C = 0, the root nearest {name}"),
                   Assign(sym("_qa"), qa), Assign(sym("_qb"), qb), Assign(sym("_qc"), qc),
                   Code("_disc = _qb * _qb - 4.0 * _qa * _qc"),
                   If(Code("_disc < 0.0"),
                      (If(Code("_disc < -1e-12 * _qb * _qb"), (Return(GAVE_UP),),
                          tail="  # no assembly here"), Code("_disc = 0.0"))),
                   Code("_qq = -0.5 * (_qb + math.copysign(math.sqrt(_disc), _qb))"),
                   If(Code("not abs(_qa) > 1e-300 or not abs(_qq) > 1e-300"), (Return(GAVE_UP),))]
            turn = None
        if turn is not None:
            for root in ("_y1", "_y2"):
                st.append(Code(f"{root} += 2.0 * math.pi * math.floor(({{0}} - {root}) * "
                               f"{turn!r} + 0.5)", (y,)))
        else:
            st += [Code("_y1 = _qq / _qa"), Code("_y2 = _qc / _qq")]
        if b.method == CLOSED_FORM_TRIG and self.shared is not None:
            # sin and cos of both roots from a, b and u alone (y + atan2(b, a) is asin u or
            # π − asin u), so that later code calls neither sin nor cos of y
            w = value("_w", sp.sqrt(1 - u ** 2))
            s1, c1, s2, c2 = (sym(x) for x in ("_sin1", "_cos1", "_sin2", "_cos2"))
            st += [Assign(s1, (u * a - w * bb) / rad), Assign(c1, (w * a + u * bb) / rad),
                   Assign(s2, (u * a + w * bb) / rad), Assign(c2, (u * bb - w * a) / rad)]
            pair = self.share_trig(y)
            st.append(If(Code("abs(_y1 - {0}) <= abs(_y2 - {0})", (y,)),
                         (Code("{0}, {1}, {2} = _y1, _sin1, _cos1", (y, pair.sin, pair.cos)),),
                         (Code("{0}, {1}, {2} = _y2, _sin2, _cos2", (y, pair.sin, pair.cos)),)))
        else:
            st.append(Code("{0} = _y1 if abs(_y1 - {0}) <= abs(_y2 - {0}) else _y2", (y,)))
        st += self.explicit(b.explicit)
        return self.shared_emit(st)

    # -- RRR dyads ---------------------------------------------------------------------------
    def dyad(self, b):
        """The dyad's two angles in closed form (mechgen.compiler.solver.dyads); their sin and cos
        come with them, shared by later code. The sign is kept in a sweep (signs)."""
        pairs = [self.share_trig(self.q[v]) for v in b.tears]
        self.trig_pairs += [self.q[v] for v in b.tears]    # the sweep's memory of them
        self.signs.append(self.q[b.tears[0]])
        return self.shared_emit(rrr_statements(b, self.eq, pairs))

    # -- Newton ------------------------------------------------------------------------------
    def newton(self, b):
        phi, q = self.rows.at(self.known), self.q
        tears, k = b.tears, len(b.tears)
        st = self.explicit(b.explicit, tears=tears)
        R = [sym(f"_r{i}") for i in range(k)]
        J = [[sym(f"_J{i}{j}") for j in range(k)] for i in range(k)]
        for i, e in enumerate(b.residuals):
            st.append(Assign(R[i], phi[e], f"row {e}: {self.eq.labels[e]}"))
            for j, y in enumerate(tears):
                total = sp.diff(phi[e], q[y])
                for _, v in b.explicit:
                    total += sp.diff(phi[e], q[v]) * Derived("_d", q[v], "_d", q[y])
                st.append(Assign(J[i][j], total))
        S = [sym(f"_s{i}") for i in range(k)]
        if k == 1:
            st.append(Guard(J[0][0], sp.Float(TINY), GAVE_UP))
            st.append(Assign(S[0], R[0] / J[0][0]))
        elif k == 2:
            det = sym("_det")
            st.append(Assign(det, J[0][0] * J[1][1] - J[0][1] * J[1][0]))
            st.append(Guard(det, sp.Float(PIVOT_RTOL) * (sp.Abs(J[0][0]) + sp.Abs(J[0][1]))
                            * (sp.Abs(J[1][0]) + sp.Abs(J[1][1])), GAVE_UP))
            st.append(Assign(S[0], (R[0] * J[1][1] - J[0][1] * R[1]) / det))
            st.append(Assign(S[1], (J[0][0] * R[1] - J[1][0] * R[0]) / det))
        # sin and cos of an angle unknown: called once before the loop, then turned by each
        # Newton step (a rotation, no new calls while the step is small); after the loop
        # they are the sin and cos of the solution, which later code shares
        used = set().union(*(sp.sympify(x.bound if isinstance(x, Guard) else x.expr)
                             .atoms(sp.sin, sp.cos) for x in st))
        turns = [(i, trig_pair(q[v])) for i, v in enumerate(tears)
                 if sp.sin(q[v]) in used or sp.cos(q[v]) in used]
        if turns:
            subs = {}
            for _, pair in turns:
                subs[sp.sin(pair.angle)], subs[sp.cos(pair.angle)] = pair.sin, pair.cos
            st = [replaced(x, lambda e: sp.sympify(e).xreplace(subs)) for x in st]
        variant = {q[v] for v in b.vars} | {s for _, p in turns for s in (p.sin, p.cos)}
        before, body = self.shared_emit(st, variant=variant)
        out = [self.pair(pair.angle) for _, pair in turns]
        out += before   # loop-invariant subexpressions, computed once per block
        if k > 2:
            out += [Code(f"_A = np.empty(({k}, {k}))"), Code(f"_b = np.empty({k})")]
            for i in range(k):
                body += [Code(f"_A[{i}, {j}] = {{0}}", (J[i][j],)) for j in range(k)]
                body.append(Code(f"_b[{i}] = {{0}}", (R[i],)))
            body.append(If(Code(f"_gauss(_A, _b) < {k}"), (Return(GAVE_UP),)))
            body += [Code(f"{{0}} = _b[{i}]", (S[i],)) for i in range(k)]
        for i, pair in turns:
            body.append(Code("{0}, {1} = _turn({0}, {1}, {2}, {3} - {2})",
                             (pair.sin, pair.cos, S[i], pair.angle)))
        conv = []
        for i, y in enumerate(tears):
            body.append(Code("{0} -= {1}", (q[y], S[i])))
            conv.append(f"abs({{{3 * i}}}) <= tol and abs({{{3 * i + 1}}}) <= "
                        f"xtol * (1.0 + abs({{{3 * i + 2}}}))")
        args = tuple(x for i, y in enumerate(tears) for x in (R[i], S[i], q[y]))
        body.append(If(Code(" and ".join(conv), args), (Break(),)))
        out.append(Loop(Code("for _it in range(maxit)"), tuple(body),
                        tuple(self.singular_exit(b, [p for _, p in turns]))))
        out.append(Code("_iters = max(_iters, _it + 1)"))
        if b.explicit:  # the explicit unknowns from the final tear values
            out += self.shared_emit(self.explicit(b.explicit))
        return out

    def singular_exit(self, b, turns):
        """What runs when a block's Newton used up its iterations: status 1, except for one
        unknown at a singular configuration (a toggle reached exactly), where Φ holds but
        the steps along the lost direction are noise. There, as in newton_full, the last
        iterate is accepted once the residual is within tol and the pivot below SING_RTOL
        of its row's size (the caller flags it singular)."""
        if len(b.tears) != 1:
            return [Return(1)]
        J = self.eq.nonzeros
        e, y = b.residuals[0], self.q[b.tears[0]]
        # the row's size as the velocity pass measures it (Φ_q is already expanded)
        scale = sum(sp.Abs(J[e, j]) for j in self.eq.row_columns[e])
        known = dict(self.shared or {})
        for pair in turns:
            known[sp.sin(pair.angle)], known[sp.cos(pair.angle)] = pair.sin, pair.cos
        scale = scale.xreplace(known)
        out = [If(Code("not (abs(_r0) <= tol and not abs(_J00) > SING_RTOL * ({0}))",
                       (scale,)), (Return(1),)),
               Code("{0} += _s0  # singular here: back to the last iterate, where Φ holds",
                    (y,))]
        out += [Code("{0}, {1} = _turn({0}, {1}, -_s0, {2})", (p.sin, p.cos, y)) for p in turns]
        return out


def position_body(plan, eq):
    """The body of position_sorted and its parts (Helper); one function while the
    solver is small (plan.position_parts empty)."""
    q, params, pieces = list(eq.q), list(eq.params), plan.position.pieces
    if not plan.position_parts:
        used = free(list(eq.phi))
        st = unpack(set(q), q, "q") + unpack(used, params, "p")
        return st + _one_point(eq, pieces) + [Return(0)], []
    top, helpers = [Code("_w = q.copy()"), Code("info[0] = 0")], []
    top += _margin_end(pieces, "1.0")
    where = {s: k for k, s in enumerate(q)}
    for i, group in enumerate(plan.position_parts):
        used = set().union(*(pieces[k].used for k in group))
        solved = [s for k in group for s in pieces[k].solved]
        body = unpack(used, q, "q") + unpack(used, params, "p")
        if T in used:
            body.append(time_local())
        body.append(Code("_iters = 0"))
        part = [pieces[k] for k in group]
        body += _margin_start(part)
        for k in group:
            body += pieces[k].statements
        body += [Store(f"q[{where[s]}]", s) for s in solved]
        body += _margin_end(part, "min(info[INFO_REACH], _mc)")
        body += [Code("info[0] = max(info[0], _iters)"), Return(0)]
        name = f"_position_part{i}"
        doc = (f"Position solver, part {i + 1} of {len(plan.position_parts)}: "
               f"{', '.join(s.name for s in solved)}.")
        helpers.append(Helper(name, "q, t, p, tol, xtol, maxit, info", doc, tuple(body)))
        top += [Code(f"_status = {name}(_w, t, p, tol, xtol, maxit, info)"),
                If(Code("_status != 0"), (Return(sym("_status")),))]
    top += [Loop(Code("for _k in range(N_COORDS)"), (Code("q[_k] = _w[_k]"),)), Return(0)]
    return top, helpers


def _one_point(eq, pieces):
    """The statements that solve ``pieces`` at one point, after the loads of the
    coordinates and parameters: the time, the blocks' code, q stored whole, the reach
    margin handed over."""
    st = [time_local()] if T in free(list(eq.phi)) else []
    st.append(Code("_iters = 0"))
    st += _margin_start(pieces)
    for piece in pieces:
        st += piece.statements
    st += [Store(f"q[{k}]", s) for k, s in enumerate(eq.q)]
    st += _margin_end(pieces, "_mc")
    return st + [Code("info[0] = _iters")]


def _once(plan):
    """How many leading blocks the fast sweep solves once, before its loop."""
    pieces, n = plan.position.pieces, 0
    while n < plan.steady and not pieces[n].watched:
        n += 1
    return n


def solved_once(plan):
    """The coordinates the fast sweep solves once, before its loop (position_in_sweep)."""
    return {s for p in plan.position.pieces[:_once(plan)] for s in p.solved}


def position_in_sweep(plan, eq):
    """(before, each): the position solver as the fast sweep writes it into its loop (one
    function's solver, plan.position_parts empty). ``before``, run once before the loop:
    the parameters' loads (a sweep does not change them) and the leading blocks that stay
    the same at every point (plan.steady; up to the first that keeps a reach margin, whose
    sign the loop takes at its first point), from the guess in q; ``each``, run at every
    point: the other blocks, from the loads of the coordinates they read."""
    q, params, pieces = list(eq.q), list(eq.params), plan.position.pieces
    n = _once(plan)
    once = solved_once(plan)
    before = [Comment("the parameters, and the blocks that stay the same at every point: "
                      "once")]
    before += unpack(free(list(eq.phi)), params, "p")
    if n:
        guessed = {q[v] for b in plan.blocks[:n] if b.method != EXPLICIT for v in b.vars}
        before += unpack(guessed, q, "q")
        if any(isinstance(x, TrigPair) for p in pieces[:n] for x in p.statements):
            before.append(Code("_sw_warm = False   # (sin and cos called, not turned)"))
        if any(b.method == NEWTON for b in plan.blocks[:n]):
            before.append(Code("_iters = 0"))
        for piece in pieces[:n]:
            before += piece.statements
    each = unpack(set(q) - once, q, "q") + _one_point(eq, pieces[n:])
    return before, each


def _margin_start(pieces):
    """_mc (in the fast sweep _sw_mc: sweep.reach_check), the smallest reach margin of the
    blocks that keep one (none: no statement)."""
    if not any(p.watched for p in pieces):
        return []
    return [Variant((Code("_mc = 1.0  # the smallest reach margin of the blocks below"),),
                    (Code("_sw_mc = 1.0  # the smallest reach margin of the blocks below"),))]


def _margin_end(pieces, value):
    """info[INFO_REACH] = ``value`` where the caller's info is long enough (sweep()'s is:
    it reads the margin there instead of calling reach()); no statement where no block
    keeps a margin."""
    if not any(p.watched for p in pieces):
        return []
    return [Variant((If(Code("info.shape[0] > INFO_REACH"), (Code(f"info[INFO_REACH] = {value}"),),
                        tail="  # the margin, for sweep()"),), ())]


__all__ = ["position_code", "position_body", "position_in_sweep", "solved_once",
           "PositionCode", "Piece", "Rows", "trig_pair", "block_comment", "NEWTON"]
