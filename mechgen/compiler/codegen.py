"""What to emit: the render context of a generated module (routines with CSE done).

Each function body is a list of code lines; the template only lays them out.
"""
from __future__ import annotations

import hashlib
import math
import re

import sympy as sp

from ..protocol import FORMAT_VERSION, PIVOT_RTOL, SING_RTOL, TINY
from ..protocol import MECHGEN_VERSION as __version__
from .blocks import incidence, linear_in, sort_blocks
from ..errors import ModelError
from ..model.geometry import T, Point
from .printer import Assign, Guard, Line, Store, TempNames, emit, pycode
from ..model.symbolic import check_square, total_derivative

CHUNK_STORES = 48      # straight-line functions longer than this are split into parts
CHUNK_LINES = 160      # lines of the position solver per part, for large models
SWEEP_RESYNC = 8       # the fast sweep calls sin and cos afresh every this many points
SHARE_MAX = 40         # models up to this many coordinates share function calls across blocks


def _sym(name):
    return sp.Symbol(name, real=True)


def _unpack(names_in_use, vector, arg, comment=""):
    lines = []
    for k, s in enumerate(vector):
        if s in names_in_use:
            lines.append(f"{s.name} = {arg}[{k}]")
    return lines


def _replace(st, subs):
    """A statement with ``subs`` applied to its expression (xreplace)."""
    if isinstance(st, Assign):
        return Assign(st.target, sp.sympify(st.expr).xreplace(subs), st.comment)
    if isinstance(st, Store):
        return Store(st.lhs, sp.sympify(st.expr).xreplace(subs), st.comment)
    if isinstance(st, Guard):
        return Guard(st.value, sp.sympify(st.bound).xreplace(subs), st.status)
    return st


def _free(exprs):
    out = set()
    for e in exprs:
        out |= sp.sympify(e).free_symbols
    return out


class ModuleBuilder:
    """Collects everything the template needs for one model."""

    def __init__(self, model, sort=True, level="acceleration", outputs=None, cse=True,
                 closed_forms="cheap"):
        self.model = model
        # "all": every block of a standard form is solved in closed form; "cheap": only
        # where that removes all run-time trigonometry (a warm-started Newton is faster
        # than atan2 or a square root); "none": Newton everywhere
        if closed_forms is True:
            closed_forms = "all"
        if closed_forms not in ("all", "cheap", "none", False):
            raise ValueError(f"closed_forms must be all, cheap or none, got {closed_forms!r}")
        self.closed_forms = closed_forms if closed_forms else "none"
        self.eq = model.equations()
        check_square(model, self.eq)   # fewer equations than coordinates: refuse to build
        self.q = list(self.eq.q)
        self.qd = list(self.eq.qd)
        self.qdd = list(self.eq.qdd)
        self.params = model.param_symbols
        self.cse = cse
        self.level = {"position": 0, "velocity": 1, "acceleration": 2}[level]
        at = {s: v for s, v in zip(self.q, model.guess_vector())}
        at.update({sym: val for sym, val in model.params.values()})
        self.blocks = sort_blocks(self.eq.phi, self.eq.q, at) if sort else None
        self.solved = [True] * len(self.q)
        self.helpers = []      # parts of large functions, emitted before them
        if outputs is None:
            self.output_names = list(model.outputs)
        else:
            self.output_names = self._prune(list(outputs))

    def _prune(self, targets):
        """Demand-driven pruning: keep only the blocks the requested coordinates and outputs
        depend on (and, through ``level``, only the derivative levels asked for)."""
        names = {c.name: j for j, c in enumerate(self.q)}
        for j, c in enumerate(self.qd):
            names[c.name] = j
        for j, c in enumerate(self.qdd):
            names[c.name] = j
        need, outs = set(), []
        for name in targets:
            if name in self.model.outputs:
                outs.append(name)
                expr = self.model.outputs[name]
                syms = expr.free_symbols
                if (syms & set(self.qdd) and self.level < 2) or (syms & set(self.qd) and self.level < 1):
                    raise ModelError(f"output '{name}' needs a higher derivative level than "
                                     f"--level {('position', 'velocity', 'acceleration')[self.level]}")
                need |= {names[s.name] for s in syms if s.name in names}
            elif name in names:
                need.add(names[name])
            else:
                known = ", ".join(list(self.model.outputs) + [c.name for c in self.q])
                raise ModelError(f"--outputs: {name!r} is neither an output nor a coordinate of "
                                 f"model '{self.model.name}' (known: {known})")
        if self.blocks is None:
            return outs
        inc = incidence(self.eq.phi, self.eq.q)
        block_of = {v: k for k, b in enumerate(self.blocks) for v in b.vars}
        keep, stack = set(), [block_of[j] for j in need]
        while stack:
            k = stack.pop()
            if k in keep:
                continue
            keep.add(k)
            for e in self.blocks[k].eqs:
                stack.extend(block_of[v] for v in inc[e] if block_of[v] not in keep)
        self.blocks = [b for k, b in enumerate(self.blocks) if k in keep]
        kept = {v for b in self.blocks for v in b.vars}
        self.solved = [j in kept for j in range(len(self.q))]
        return outs

    # -- helpers --------------------------------------------------------------------
    def _prologue(self, exprs, with_qd=False, with_qdd=False, with_t=True):
        used = _free(exprs)
        lines = _unpack(used, self.q, "q")
        if with_qd:
            lines += _unpack(used, self.qd, "qd")
        if with_qdd:
            lines += _unpack(used, self.qdd, "qdd")
        lines += _unpack(used, self.params, "p")
        if with_t and T in used:
            lines.append("T = t")
        return lines

    def _function(self, statements, name=None, args="q, t, p, out", **kw):
        """Prologue and body of a straight-line function. Past CHUNK_STORES statements the
        work goes to helper functions ``_<name>_part<i>`` (each with its own CSE) that
        the function calls in turn: numba compiles small functions much faster."""
        if name is None or len(statements) <= CHUNK_STORES:
            exprs = [s.expr for s in statements if isinstance(s, (Assign, Store))]
            return self._prologue(exprs, **kw) + emit(statements, cse=self.cse)
        calls = []
        parts = [statements[i:i + CHUNK_STORES] for i in range(0, len(statements), CHUNK_STORES)]
        for i, part in enumerate(parts):
            helper = f"_{name}_part{i}"
            exprs = [s.expr for s in part if isinstance(s, (Assign, Store))]
            self.helpers.append(dict(name=helper, args=args,
                                     doc=f"{name}, part {i + 1} of {len(parts)}.",
                                     lines=self._prologue(exprs, **kw) + emit(part, cse=self.cse)))
            calls.append(f"{helper}({args})")
        return calls

    # -- the quantities -------------------------------------------------------------
    def phi_body(self):
        st = [Store(f"out[{i}]", self.eq.phi[i], self.eq.labels[i]) for i in range(self.eq.phi.rows)]
        return self._function(st, "phi")

    def phi_q_body(self):
        J = self.eq.phi_q
        st = []
        for i in range(J.rows):
            for j in range(J.cols):
                if J[i, j] != 0:
                    st.append(Store(f"out[{i}, {j}]", J[i, j], f"{self.eq.labels[i]} / d{self.q[j]}"))
        return self._function(st, "phi_q")

    def nu_body(self):
        st = [Store(f"out[{i}]", self.eq.nu[i], self.eq.labels[i])
              for i in range(self.eq.nu.rows) if self.eq.nu[i] != 0]
        return self._function(st, "nu")

    def gamma_body(self):
        if self.level < 2:
            return ["# not built: this module was built for a lower level than acceleration",
                    "for _i in range(out.shape[0]):", "    out[_i] = math.nan"]
        st = [Store(f"out[{i}]", self.eq.gamma[i], self.eq.labels[i])
              for i in range(self.eq.gamma.rows) if self.eq.gamma[i] != 0]
        return self._function(st, "gamma", "q, qd, t, p, out", with_qd=True)

    def point_list(self):
        """Every point of every body (its list, its origin) and every point the
        constraints use, in a stable order: [(label, body name, Point)]."""
        seen, out = set(), []

        def add(pt: Point):
            key = (pt.body.name, pt.local)
            if key not in seen:
                seen.add(key)
                out.append((pt.label, pt.body.name, pt))

        for body in self.model.bodies.values():
            if not body.is_ground:
                add(body[0])
            for k in range(1, len(body.points) + 1):
                add(body[k])
        for con in self.model.constraints:
            for pt in getattr(con, "points", ()):
                add(pt)
        return out

    def points_body(self, points):
        st = []
        for k, (label, _, pt) in enumerate(points):
            r = pt.r
            st.append(Store(f"out[{k}, 0]", r[0], label))
            st.append(Store(f"out[{k}, 1]", r[1]))
        return self._function(st, "points")

    def outputs_bodies(self):
        """Three bodies: the outputs, their first and second time derivatives."""
        names = self.output_names
        orders, levels = [], []
        for name in names:
            expr = self.model.outputs[name]
            syms = expr.free_symbols
            order = 2 if syms & set(self.qdd) else 1 if syms & set(self.qd) else 0
            orders.append(order)
        bodies = []
        for d in range(3):
            st = []
            for k, name in enumerate(names):
                if orders[k] + d > 2:
                    st.append(Store(f"out[{k}]", sp.nan, f"{name}: needs a third derivative"))
                    continue
                expr = total_derivative(self.model.outputs[name], self.q, d) if d else self.model.outputs[name]
                st.append(Store(f"out[{k}]", expr, name + ("'" * d)))
            name = ("outputs", "outputs_d", "outputs_dd")[d]
            bodies.append(self._function(st, name, "q, qd, qdd, t, p, out", with_qd=True,
                                         with_qdd=True) if st else ["pass"])
            levels.append(d)
        return bodies, orders

    # -- the sorted solvers -----------------------------------------------------------
    def _block_comment(self, b):
        names = ", ".join(str(self.q[v]) for v in b.vars)
        rows = "; ".join(self.eq.labels[e] for e in b.eqs)
        return f"# block: {names} from {rows}"

    def position_sorted_body(self):
        """The block-by-block Newton: explicit assignments, 1-unknown and torn Newtons.

        A large model's solver is split into parts of about CHUNK_LINES lines, each a
        function of its own (numba compiles many small functions much faster than one
        large one); the main function then runs them in order on a work copy of q."""
        phi, q = self.eq.phi, self.q
        # function calls of solved coordinates are shared across blocks, in models whose
        # solver stays one function (a split solver keeps its CSE per part)
        pieces = self._position_pieces(share=len(q) <= SHARE_MAX)
        if self._shared is not None and sum(len(x[0]) for x in pieces) > 2 * CHUNK_LINES:
            pieces = self._position_pieces(share=False)
        total = sum(len(x[0]) for x in pieces)
        if total <= 2 * CHUNK_LINES:
            self._step_ready = True
            used = _free(list(phi))
            lines = _unpack(set(q), q, "q") + _unpack(used, self.params, "p")
            if T in used:
                lines.append("T = t")
            lines.append("_iters = 0")
            for piece in pieces:
                lines += piece[0]
            lines += [f"q[{k}] = {s.name}" for k, s in enumerate(q)]
            return lines + ["info[0] = _iters", "return 0"]
        groups, current = [], []
        for piece in pieces:
            if current and sum(len(x[0]) for x in current) + len(piece[0]) > CHUNK_LINES:
                groups.append(current)
                current = []
            current.append(piece)
        groups.append(current)
        top = ["_w = q.copy()", "info[0] = 0"]
        for i, group in enumerate(groups):
            used = set().union(*(x[1] for x in group))
            solved = [s for x in group for s in x[2]]
            body = _unpack(used, q, "q") + _unpack(used, self.params, "p")
            if T in used:
                body.append("T = t")
            body.append("_iters = 0")
            for piece in group:
                body += piece[0]
            body += [f"q[{q.index(s)}] = {s.name}" for s in solved]
            body += ["info[0] = max(info[0], _iters)", "return 0"]
            name = f"_position_part{i}"
            names = ", ".join(s.name for s in solved)
            self.helpers.append(dict(name=name, args="q, t, p, tol, xtol, maxit, info",
                                     doc=f"Position solver, part {i + 1} of {len(groups)}: {names}.",
                                     lines=body))
            top += [f"_status = {name}(_w, t, p, tol, xtol, maxit, info)",
                    "if _status != 0:", "    return _status"]
        top += ["for _k in range(N_COORDS):", "    q[_k] = _w[_k]", "return 0"]
        return top

    def _position_pieces(self, share):
        """Code for each block of the position solver: (lines, symbols they use,
        coordinates they solve)."""
        phi, q = self.eq.phi, self.q
        temps = TempNames()
        self._known = {}
        self._shared = {} if share else None
        self._trig_pairs = []      # coordinates whose sin and cos the code calls as a pair
        self._avail = set(self.params) | {T}
        pieces = []
        for b in self.blocks:
            lines = [self._block_comment(b)]
            if b.kind == "explicit":
                st = self._explicit(b.explicit)
                lines += self._emit_shared(st, temps)
                value = st[-1].expr
                if value.is_number:    # a constant coordinate: substitute it forward
                    self._known[q[b.vars[0]]] = value
            else:
                lines += self._newton_block(b, temps)
            used = _free([phi[e] for e in b.eqs]) | {q[v] for v in b.vars}
            pieces.append((lines, used, [q[v] for v in b.vars]))
            self._avail |= {q[v] for v in b.vars}
        return pieces

    def _emit_shared(self, st, temps, variant=None):
        """emit() for the position solver, with function calls (sin, cos, atan2, ...) of
        coordinates solved by earlier blocks computed once for the whole function: each
        gets a name (``_f3``) defined before the first block that needs it."""
        shared = getattr(self, "_shared", None)
        if shared is None:
            return emit(st, temps, self.cse, variant=variant)
        avail = self._avail
        defs = []

        def swap(expr):
            expr = sp.sympify(expr)
            atoms = [a for a in expr.atoms(sp.Function)
                     if a in shared or (a.free_symbols and a.free_symbols <= avail)]
            if not atoms:
                return expr
            subs = {}
            for a in sorted(atoms, key=sp.default_sort_key):
                if a not in shared and isinstance(a, (sp.sin, sp.cos)) and a.args[0] in self.q:
                    defs.extend(self._trig_pair(a.args[0]))   # sin and cos of a coordinate
                elif a not in shared:
                    shared[a] = _sym(f"_f{len(shared)}")
                    defs.append(Assign(shared[a], a))
                subs[a] = shared[a]
            return expr.xreplace(subs)

        out = []
        for x in st:
            if isinstance(x, Assign):
                out.append(Assign(x.target, swap(x.expr), x.comment))
            elif isinstance(x, Store):
                out.append(Store(x.lhs, swap(x.expr), x.comment))
            elif isinstance(x, Guard):
                out.append(Guard(x.value, swap(x.bound), x.status))
            else:
                out.append(x)
        lines = emit(defs, temps, self.cse) if defs else []
        body = emit(out, temps, self.cse, variant=variant)
        if variant is None:
            return lines + body
        return lines + body[0], body[1]

    def _share_trig(self, y):
        """The names ``_sin_<y>``, ``_cos_<y>`` of the sin and cos of coordinate y, shared
        by later code when the solver shares calls."""
        sin_y, cos_y = _sym(f"_sin_{y.name}"), _sym(f"_cos_{y.name}")
        if self._shared is not None:
            self._shared[sp.sin(y)], self._shared[sp.cos(y)] = sin_y, cos_y
        return sin_y, cos_y

    def _trig_pair(self, y):
        """``_sin_<y> = math.sin(<y>)`` and ``_cos_<y> = ...`` as two lines, registered as
        shared; the fast sweep turns such pairs from the last point instead (sweep_step)."""
        sin_y, cos_y = self._share_trig(y)
        self._trig_pairs.append(y.name)
        return [Line(f"{sin_y.name} = math.sin({y.name})"),
                Line(f"{cos_y.name} = math.cos({y.name})")]

    def _rows(self):
        """Φ with the constant coordinates found so far substituted."""
        known = getattr(self, "_known", None)
        if not known:
            return self.eq.phi
        return _Subs(self.eq.phi, known)

    def _explicit(self, pairs, tears=()):
        """Statements for z = −rest/coef for each (eq, var), and optionally dz/dy."""
        phi, q = self._rows(), self.q
        st = []
        for e, v in pairs:
            z = q[v]
            coef, rest = linear_in(phi[e], z)
            den = _sym(f"_den_{z.name}")
            if coef.is_number:
                st.append(Assign(z, -rest / coef, f"row {e}: {self.eq.labels[e]}"))
            else:
                # a reciprocal, then a product: the reciprocal does not wait for the rest
                inv = _sym(f"_inv_{z.name}")
                st.append(Assign(den, coef))
                st.append(Guard(den, sp.Float(1e-12), "4"))
                st.append(Assign(inv, 1 / den))
                st.append(Assign(z, -rest * inv, f"row {e}: {self.eq.labels[e]}"))
            for y in tears:
                total = sp.diff(phi[e], q[y])
                for e2, v2 in pairs:
                    if (e2, v2) == (e, v):
                        break
                    total += sp.diff(phi[e], q[v2]) * _sym(f"_d{q[v2].name}_d{q[y].name}")
                dz = _sym(f"_d{z.name}_d{q[y].name}")
                st.append(Assign(dz, -total / coef if coef.is_number else -total * inv))
        return st

    def _closed_form(self, b, temps):
        """A block with one tear whose residual, once the explicit unknowns are substituted,
        has a standard form solved without iterating — a sin y + b cos y + c (a crank or
        lever angle) or A y² + B y + C (a two-circle intersection). Of the two roots, the
        one nearest the current value of y is kept, so the assembly mode is kept.
        Returns the code lines, or None when the residual has neither form."""
        phi, q = self._rows(), self.q
        y = q[b.tears[0]]
        subs = {}
        for e, v in b.explicit:
            coef, rest = linear_in(phi[e], q[v])
            subs[q[v]] = (-rest / coef).subs(subs)
        r = phi[b.residuals[0]].subs(subs)
        try:
            # clear denominators free of y: the same roots, fewer divisions at run time
            num, den = sp.fraction(sp.together(r))
            if not den.free_symbols & {y}:
                r = num
            ex = sp.expand(r)
        except Exception:  # noqa: BLE001 - an expression sympy cannot expand: keep Newton
            return None
        name = y.name
        st = []
        trig = _collect_form(ex, [sp.sin(y), sp.cos(y)])
        quad = None if trig else _collect_form(ex, [y ** 2, y])
        if trig and (sp.sin(y) in trig or sp.cos(y) in trig):
            ka, kb, kc = (sp.sympify(trig.get(sp.sin(y), 0)), sp.sympify(trig.get(sp.cos(y), 0)),
                          sp.sympify(trig.get(1, 0)))
            if self.closed_forms == "cheap" and not (ka.is_number and kb.is_number):
                return None
            st.append(Line(f"# closed form: a sin({name}) + b cos({name}) + c = 0, "
                           f"the root nearest {name}"))

            def value(label, expr):     # constants stay in the expressions (folded)
                if expr.is_number:
                    return expr
                sym = _sym(label)
                st.append(Assign(sym, expr))
                return sym
            a, bb = value("_ka", ka), value("_kb", kb)
            rad = value("_rad", sp.sqrt(a ** 2 + bb ** 2))
            if rad.is_number:
                if rad == 0:
                    return None
            else:
                st.append(Guard(rad, sp.Float(TINY), "4"))
            if kc == 0:
                u, asin = sp.Integer(0), sp.Integer(0)
            else:
                u = _sym("_u")
                st.append(Assign(u, -kc / rad))
                st.append(Line("if not abs(_u) <= 1.0 + 1e-12:  # no assembly here"))
                st.append(Line("    return 4"))
                st.append(Line("_u = min(1.0, max(-1.0, _u))"))
                asin = sp.asin(u)
            x1, x2 = _sym("_y1"), _sym("_y2")
            st.append(Assign(x1, asin - sp.atan2(bb, a)))
            st.append(Assign(x2, sp.pi - asin - sp.atan2(bb, a)))

            # the 2π-shift of each root nearest the current value (1/2π = 0.159...)
            st.append(Line(f"_y1 += 2.0 * math.pi * math.floor(({name} - _y1) * {1 / (2 * math.pi)!r} + 0.5)"))
            st.append(Line(f"_y2 += 2.0 * math.pi * math.floor(({name} - _y2) * {1 / (2 * math.pi)!r} + 0.5)"))
        elif quad and y ** 2 in quad and self.closed_forms != "cheap":
            qa, qb, qc = _sym("_qa"), _sym("_qb"), _sym("_qc")
            st += [Line(f"# closed form: A {name}^2 + B {name} + C = 0, the root nearest {name}"),
                   Assign(qa, quad[y ** 2]), Assign(qb, quad.get(y, 0)), Assign(qc, quad.get(1, 0))]
            st += [Line("_disc = _qb * _qb - 4.0 * _qa * _qc"),
                   Line("if _disc < 0.0:"),
                   Line("    if _disc < -1e-12 * _qb * _qb:  # no assembly here"),
                   Line("        return 4"),
                   Line("    _disc = 0.0"),
                   Line("_qq = -0.5 * (_qb + math.copysign(math.sqrt(_disc), _qb))"),
                   Line("if not abs(_qa) > 1e-300 or not abs(_qq) > 1e-300:"),
                   Line("    return 4"),
                   Line("_y1 = _qq / _qa"),
                   Line("_y2 = _qc / _qq")]
        else:
            return None
        if trig and self._shared is not None:
            # sin and cos of both roots from a, b and u alone (y + atan2(b, a) is asin u or
            # π − asin u), so that later code calls neither sin nor cos of y
            w = value("_w", sp.sqrt(1 - u ** 2))
            s1, c1, s2, c2 = (_sym(x) for x in ("_sin1", "_cos1", "_sin2", "_cos2"))
            st += [Assign(s1, (u * a - w * bb) / rad), Assign(c1, (w * a + u * bb) / rad),
                   Assign(s2, (u * a + w * bb) / rad), Assign(c2, (u * bb - w * a) / rad)]
            sin_y, cos_y = self._share_trig(y)
            st += [Line(f"if abs(_y1 - {name}) <= abs(_y2 - {name}):"),
                   Line(f"    {name}, {sin_y.name}, {cos_y.name} = _y1, {s1.name}, {c1.name}"),
                   Line("else:"),
                   Line(f"    {name}, {sin_y.name}, {cos_y.name} = _y2, {s2.name}, {c2.name}")]
        else:
            st.append(Line(f"{name} = _y1 if abs(_y1 - {name}) <= abs(_y2 - {name}) else _y2"))
        st += self._explicit(b.explicit)
        return self._emit_shared(st, temps)

    def _newton_block(self, b, temps):
        phi, q = self._rows(), self.q
        tears, res = b.tears, b.residuals
        k = len(tears)
        if k == 1 and self.closed_forms != "none":
            lines = self._closed_form(b, temps)
            if lines is not None:
                return lines
        st = self._explicit(b.explicit, tears=tears)
        explicit_vars = [v for _, v in b.explicit]
        R = [_sym(f"_r{i}") for i in range(k)]
        J = [[_sym(f"_J{i}{j}") for j in range(k)] for i in range(k)]
        for i, e in enumerate(res):
            st.append(Assign(R[i], phi[e], f"row {e}: {self.eq.labels[e]}"))
            for j, y in enumerate(tears):
                total = sp.diff(phi[e], q[y])
                for v in explicit_vars:
                    total += sp.diff(phi[e], q[v]) * _sym(f"_d{q[v].name}_d{q[y].name}")
                st.append(Assign(J[i][j], total))
        S = [_sym(f"_s{i}") for i in range(k)]
        if k == 1:
            st.append(Guard(J[0][0], sp.Float(TINY), "4"))
            st.append(Assign(S[0], R[0] / J[0][0]))
        elif k == 2:
            det = _sym("_det")
            st.append(Assign(det, J[0][0] * J[1][1] - J[0][1] * J[1][0]))
            st.append(Guard(det, sp.Float(PIVOT_RTOL) * (sp.Abs(J[0][0]) + sp.Abs(J[0][1]))
                            * (sp.Abs(J[1][0]) + sp.Abs(J[1][1])), "4"))
            st.append(Assign(S[0], (R[0] * J[1][1] - J[0][1] * R[1]) / det))
            st.append(Assign(S[1], (J[0][0] * R[1] - J[1][0] * R[0]) / det))
        # sin and cos of an angle unknown: called once before the loop, then turned by each
        # Newton step (a rotation, no new calls while the step is small); after the loop
        # they are the sin and cos of the solution, which later code shares
        turns = []
        used = set().union(*(sp.sympify(x.bound if isinstance(x, Guard) else x.expr)
                             .atoms(sp.sin, sp.cos) for x in st if not isinstance(x, Line)))
        for i, v in enumerate(tears):
            y = q[v]
            if sp.sin(y) in used or sp.cos(y) in used:
                turns.append((i, y, _sym(f"_sin_{y.name}"), _sym(f"_cos_{y.name}")))
        if turns:
            subs = {}
            for _, y, sin_y, cos_y in turns:
                subs[sp.sin(y)], subs[sp.cos(y)] = sin_y, cos_y
            st = [_replace(x, subs) for x in st]
        variant = {q[v] for v in b.vars} | {x for t in turns for x in t[2:]}
        before, body = self._emit_shared(st, temps, variant=variant)
        lines = []
        for _, y, sin_y, cos_y in turns:
            lines += [x.text for x in self._trig_pair(y)]
        lines += before   # loop-invariant subexpressions, computed once per block
        if k > 2:
            lines.append(f"_A = np.empty(({k}, {k}))")
            lines.append(f"_b = np.empty({k})")
            for i in range(k):
                for j in range(k):
                    body.append(f"_A[{i}, {j}] = {J[i][j].name}")
                body.append(f"_b[{i}] = {R[i].name}")
            body.append("if _gauss(_A, _b) < " + str(k) + ":")
            body.append("    return 4")
            for i in range(k):
                body.append(f"{S[i].name} = _b[{i}]")
        conv = []
        for i, y, sin_y, cos_y in turns:
            body.append(f"{sin_y.name}, {cos_y.name} = _turn({sin_y.name}, {cos_y.name}, "
                        f"{S[i].name}, {y.name} - {S[i].name})")
        for i, y in enumerate(tears):
            body.append(f"{q[y].name} -= {S[i].name}")
            conv.append(f"abs({R[i].name}) <= tol and abs({S[i].name}) <= xtol * (1.0 + abs({q[y].name}))")
        body.append("if " + " and ".join(conv) + ":")
        body.append("    break")
        lines.append("for _it in range(maxit):")
        lines += ["    " + x for x in body]
        lines.append("else:")
        lines += ["    " + x for x in self._singular_exit(b, turns)]
        lines.append("_iters = max(_iters, _it + 1)")
        if b.explicit:  # the explicit unknowns from the final tear values
            lines += self._emit_shared(self._explicit(b.explicit), temps)
        return lines

    def _singular_exit(self, b, turns):
        """The lines run when a block's Newton used up its iterations: status 1, except
        for one unknown at a singular configuration (a toggle reached exactly), where Φ
        holds but the steps along the lost direction are noise. There, as in
        newton_full, the last iterate is accepted once the residual is within tol and
        the pivot below SING_RTOL of its row's size (the caller flags it singular)."""
        if len(b.tears) != 1:
            return ["return 1"]
        J = self.eq.phi_q
        e, y = b.residuals[0], self.q[b.tears[0]].name
        # the row's size as the velocity pass measures it (Φ_q is already expanded)
        scale = sum(sp.Abs(J[e, j]) for j in range(J.cols) if J[e, j] != 0)
        known = dict(self._shared or {})
        for _, z, sin_z, cos_z in turns:
            known[sp.sin(z)], known[sp.cos(z)] = sin_z, cos_z
        scale = scale.xreplace(known)
        lines = [f"if not (abs(_r0) <= tol and not abs(_J00) > SING_RTOL * ({pycode(scale)})):",
                 "    return 1",
                 f"{y} += _s0  # singular here: back to the last iterate, where Φ holds"]
        for _, z, sin_z, cos_z in turns:
            lines.append(f"{sin_z.name}, {cos_z.name} = _turn({sin_z.name}, {cos_z.name}, -_s0, {y})")
        return lines

    def _linear_blocks(self, order, known=None):
        """The block forward substitution for Φ_q x = rhs, block by block: for each block
        (statements, unknowns). Unknowns that come out as constants (``X2d = 0``) are
        substituted forward so that nothing is multiplied by a known zero; only constants
        found inside the function are used, so it stays exact for any (q, q̇) it is given.
        Jacobian entries and right sides appear as symbols ``_j<i>_<j>``, ``_g<i>``."""
        J = self.eq.phi_q
        xs = self.qd if order == 1 else self.qdd
        jsym, consts, out = {}, {}, []
        for i in range(J.rows):
            for j in range(J.cols):
                if J[i, j] != 0:
                    jsym[i, j] = J[i, j] if J[i, j].is_number else _sym(f"_j{i}_{j}")
        rsym = self._rhs_symbols(order)
        rsym.update(known or {})      # right sides known to be constants
        for b in self.blocks:
            body = [Line(self._block_comment(b))]
            inside = set(b.vars)
            bvec = []
            for e in b.eqs:
                acc = rsym[e]
                for j in range(J.cols):
                    if (e, j) in jsym and j not in inside:
                        acc -= jsym[e, j] * consts.get(xs[j], xs[j])
                bvec.append(acc)
            A = [[jsym.get((e, v), sp.Integer(0)) for v in b.vars] for e in b.eqs]
            scale = [sum(sp.Abs(jsym[e, j]) for j in range(J.cols) if (e, j) in jsym) for e in b.eqs]
            k = b.size
            if k == 1:
                a, x = A[0][0], xs[b.vars[0]]
                if not a.is_number:
                    body.append(Guard(a, sp.Float(SING_RTOL) * scale[0], "2"))
                value = bvec[0] / a
                if value.is_number:
                    consts[x] = value
                body.append(Assign(x, value))
            elif k == 2:
                det = _sym(f"_det{b.eqs[0]}")
                body.append(Assign(det, A[0][0] * A[1][1] - A[0][1] * A[1][0]))
                body.append(Guard(det, sp.Float(SING_RTOL) * scale[0] * scale[1], "2"))
                body.append(Assign(xs[b.vars[0]], (bvec[0] * A[1][1] - A[0][1] * bvec[1]) / det))
                body.append(Assign(xs[b.vars[1]], (A[0][0] * bvec[1] - A[1][0] * bvec[0]) / det))
            else:
                bs = [_sym(f"_bb{i}") for i in range(k)]
                for i in range(k):
                    body.append(Assign(bs[i], bvec[i]))
                body.append(Line(f"_A = np.empty(({k}, {k}))"))
                body.append(Line(f"_b = np.empty({k})"))
                for i in range(k):
                    for j in range(k):
                        body.append(Store(f"_A[{i}, {j}]", A[i][j]))
                    body.append(Store(f"_b[{i}]", bs[i]))
                body.append(Line(f"if _gauss(_A, _b) < {k}:"))
                body.append(Line("    return 2"))
                for i, v in enumerate(b.vars):
                    body.append(Line(f"{xs[v].name} = _b[{i}]"))
            out.append((body, [xs[v] for v in b.vars]))
        self._constants = consts
        return out, jsym, rsym

    def _rhs_symbols(self, order):
        rhs = self.eq.nu if order == 1 else self.eq.gamma
        prefix = "_n" if order == 1 else "_g"
        return {i: rhs[i] if rhs[i].is_number else _sym(f"{prefix}{i}") for i in range(rhs.rows)}

    def derivatives_sorted_body(self):
        """Velocities and accelerations in one pass: the Jacobian entries are computed once
        and serve both forward substitutions (the sweep's inner loop). None for a model
        whose solvers are split into parts: it then calls the two of them."""
        parts = self._derivative_statements()
        if parts is None:
            return None
        st, tail = parts
        exprs = [x.expr for x in st if isinstance(x, (Assign, Store))]
        return self._prologue(exprs) + emit(st, TempNames(), self.cse) + tail + ["return 0"]

    def _derivative_statements(self):
        """The statements of the combined velocity and acceleration pass and the lines that
        store q̇ and q̈; None when they are too many for one function."""
        if hasattr(self, "_derivatives"):
            return self._derivatives
        self._derivatives = None
        vel, jsym, nsym = self._linear_blocks(1)
        vconst = self._constants        # X2d = 0, ...: exact here, computed just above
        # rows of γ that these constants make constant (a fixed angle's γ = 0, say)
        known, constant = {}, set(vconst)
        for i, g in enumerate(self.eq.gamma):
            if not g.is_number and g.free_symbols & constant:
                g = g.xreplace(vconst)
                if g.is_number:
                    known[i] = g
        acc, _, gsym = self._linear_blocks(2, known)
        vbody = [x for piece in vel for x in piece[0]]
        abody = [x for piece in acc for x in piece[0]]
        if len(vbody) + len(abody) > 3 * CHUNK_STORES:
            return None
        head = self._linear_head(1, vbody + abody, jsym, nsym)
        gamma = [Assign(x.target, x.expr.subs(vconst), x.comment)
                 for x in self._linear_head(2, abody, {}, gsym)]
        # det Φ_q up to a constant sign: the product of the block pivots (the fast sweep
        # watches its sign; NaN when a block of three or more unknowns hides its pivot)
        pivots = [x.value for x in vbody if isinstance(x, Guard)]
        big = any(b.size > 2 for b in self.blocks)
        det = [Store("piv[0]", sp.nan if big else sp.Mul(*pivots), "det Φ_q (up to sign)")]
        st = head + vbody + det + gamma + abody
        tail = []
        for k, (v, a) in enumerate(zip(self.qd, self.qdd)):
            if self.solved[k]:
                tail += [f"qd[{k}] = {v.name}", f"qdd[{k}] = {a.name}"]
            else:
                tail += [f"qd[{k}] = math.nan", f"qdd[{k}] = math.nan"]
        self._derivatives = st, tail
        return self._derivatives

    def sweep_step(self, position):
        """The position solve and the derivative pass as one piece of code, written into
        the fast sweep's loop (numba's own inlining of array functions costs refcount work
        at every return): the derivative code takes the sin and cos of solved coordinates
        from the position code instead of calling them again, and every failure status
        becomes ``return k``. None for a split solver."""
        if not getattr(self, "_step_ready", False) or self._shared is None:
            return None
        parts = self._derivative_statements()
        if parts is None:
            return None
        st, tail = parts
        st = [_replace(x, self._shared) for x in st]
        exprs = [x.expr for x in st if isinstance(x, (Assign, Store))]
        exprs += [x.bound for x in st if isinstance(x, Guard)]
        used, have = _free(exprs), _free(list(self.eq.phi))
        lines = position[:-1]               # all but its "return 0"
        lines += _unpack(used - have, self.params, "p")
        if T in used and T not in have:
            lines.append("T = t")
        lines += emit(st, TempNames("_v"), self.cse) + tail
        lines = [re.sub(r"^(\s*)return \d+$", r"\1return k", x) for x in lines]
        # sin and cos of each angle the step calls them for: turned from the last point
        # (a rotation by the change of the angle), called afresh every SWEEP_RESYNC points
        for y in self._trig_pairs:
            first = f"_sin_{y} = math.sin({y})"
            k = next(i for i, x in enumerate(lines) if x.strip() == first)
            pad = lines[k][:len(lines[k]) - len(first)]
            assert lines[k + 1].strip() == f"_cos_{y} = math.cos({y})"
            lines[k:k + 2] = [pad + x for x in (
                "if _sw_warm:",
                f"    _sin_{y}, _cos_{y} = _turn(_sw_sin_{y}, _sw_cos_{y}, _sw_{y} - {y}, {y})",
                "else:", "    " + first, f"    _cos_{y} = math.cos({y})")]
        return lines

    def sweep_memory(self):
        """The fast sweep's memory of each turned angle: (initial lines, lines that keep
        the values of an accepted point)."""
        init, keep = [], []
        for y in self._trig_pairs:
            init += [f"_sw_{y} = 0.0", f"_sw_sin_{y} = 0.0", f"_sw_cos_{y} = 1.0"]
            keep += [f"_sw_{y} = {y}", f"_sw_sin_{y} = _sin_{y}", f"_sw_cos_{y} = _cos_{y}"]
        return init, keep

    def _linear_head(self, order, body, jsym, rsym):
        """Assignments of the Jacobian entries and right sides that ``body`` uses."""
        J = self.eq.phi_q
        rhs = self.eq.nu if order == 1 else self.eq.gamma
        used = _free([x.expr for x in body if isinstance(x, (Assign, Store))] +
                     [x.bound for x in body if isinstance(x, Guard)] +
                     [x.value for x in body if isinstance(x, Guard)])
        head = [Assign(sym, J[i, j]) for (i, j), sym in jsym.items()
                if isinstance(sym, sp.Symbol) and sym in used]
        head += [Assign(sym, rhs[i], self.eq.labels[i])
                 for i, sym in rsym.items() if isinstance(sym, sp.Symbol) and sym in used]
        return head

    def linear_sorted_body(self, order):
        """Block forward substitution for Φ_q x = rhs (ν for order 1, γ for order 2); split
        into parts of about CHUNK_LINES lines for large models."""
        blocks, jsym, rsym = self._linear_blocks(order)
        xs = self.qd if order == 1 else self.qdd
        name = "velocity" if order == 1 else "acceleration"
        args = "q, t, p, out" if order == 1 else "q, qd, t, p, out"
        groups, current, size = [], [], 0
        for piece in blocks:
            if current and size + len(piece[0]) > CHUNK_STORES:
                groups.append(current)
                current, size = [], 0
            current.append(piece)
            size += len(piece[0])
        groups.append(current)
        if len(groups) <= 2:
            groups = [blocks]
        done = set()
        top = []
        for i, group in enumerate(groups):
            body = [x for piece in group for x in piece[0]]
            st = self._linear_head(order, body, jsym, rsym) + body
            exprs = [x.expr for x in st if isinstance(x, (Assign, Store))]
            lines = self._prologue(exprs, with_qd=(order == 2))
            used = _free(exprs + [x.bound for x in st if isinstance(x, Guard)])
            lines += [f"{x.name} = out[{xs.index(x)}]" for x in xs if x in done and x in used]
            lines += emit(st, TempNames(), self.cse)
            solved = [x for piece in group for x in piece[1]]
            done |= set(solved)
            if len(groups) == 1:
                lines += [f"out[{k}] = {s.name}" if self.solved[k] else
                          f"out[{k}] = math.nan  # {s.name}: not solved in this pruned build"
                          for k, s in enumerate(xs)]
                return lines + ["return 0"]
            lines += [f"out[{xs.index(x)}] = {x.name}" for x in solved] + ["return 0"]
            helper = f"_{name}_part{i}"
            self.helpers.append(dict(name=helper, args=args, lines=lines,
                                     doc=f"{name.capitalize()} solver, part {i + 1} of {len(groups)}: "
                                         + ", ".join(x.name for x in solved) + "."))
            top += [f"_status = {helper}({args})", "if _status != 0:", "    return _status"]
        top += [f"out[{k}] = math.nan  # {s.name}: not solved in this pruned build"
                for k, s in enumerate(xs) if not self.solved[k]]
        return top + ["return 0"]

    def jacobian_det_body(self):
        """det Φ_q as the product of the determinants of its diagonal blocks in the solving
        order (equal to det Φ_q up to the constant sign of the permutation): its sign
        changes exactly where Φ_q loses rank along a branch, which the sweep watches for."""
        J = self.eq.phi_q
        st, factors = [], []
        for b in self.blocks:
            A = [[J[e, v] for v in b.vars] for e in b.eqs]
            if b.size == 1:
                factors.append(A[0][0])
            elif b.size == 2:
                factors.append(A[0][0] * A[1][1] - A[0][1] * A[1][0])
            else:
                d = _sym(f"_det{b.eqs[0]}")
                st.append(Line(f"_A = np.empty(({b.size}, {b.size}))"))
                st += [Store(f"_A[{i}, {j}]", A[i][j]) for i in range(b.size) for j in range(b.size)]
                st.append(Line(f"{d.name} = _det(_A)"))
                factors.append(d)
        st.append(Store("_d", sp.Mul(*factors)))
        exprs = [x.expr for x in st if isinstance(x, Store)]
        return self._prologue(exprs) + emit(st, TempNames(), self.cse) + ["return _d"]

    # -- everything -----------------------------------------------------------------
    def context(self):
        model, eq = self.model, self.eq
        points = self.point_list()
        outputs, orders = self.outputs_bodies()
        ctx = dict(
            name=model.name,
            doc=(model.doc or "").strip(),
            mechgen_version=__version__,
            format_version=FORMAT_VERSION,
            n=len(self.q), m=eq.phi.rows,
            coordinates=[s.name for s in self.q],
            guess=[repr(float(x)) for x in model.guess_vector()],
            parameters=[(name, repr(float(v))) for name, v in model.param_defaults.items()],
            labels=list(eq.labels),
            constraints=[dict(number=c.number, kind=c.kind, label=c.label, rows=len(c.exprs),
                              driver=c.is_driver) for c in model.constraints],
            points=[(label, body) for label, body, _ in points],
            bodies=[(b.name, b.number, b.is_ground) for b in model.bodies.values()],
            outputs=self.output_names, output_orders=orders,
            phi=self.phi_body(), phi_q=self.phi_q_body(), nu=self.nu_body(),
            gamma=self.gamma_body(), points_code=self.points_body(points),
            outputs_code=outputs,
            sorted=self.blocks is not None,
            blocks=[], position_sorted=[], velocity_sorted=[], acceleration_sorted=[],
            derivatives_sorted=None, sweep_step=None,
            jacobian_det=[],
            pivot_rtol=repr(PIVOT_RTOL),
            sing_rtol=repr(SING_RTOL),
        )
        ctx.update(drawing_context(model, points))
        if self.blocks is not None:
            ctx["blocks"] = [dict(kind=b.kind, vars=[self.q[v].name for v in b.vars],
                                  rows=list(b.eqs), tears=[self.q[v].name for v in b.tears])
                             for b in self.blocks]
            ctx["position_sorted"] = self.position_sorted_body()
            ctx["jacobian_det"] = self.jacobian_det_body()
            if self.level >= 1:
                ctx["velocity_sorted"] = self.linear_sorted_body(1)
            if self.level >= 2:
                ctx["acceleration_sorted"] = self.linear_sorted_body(2)
                ctx["derivatives_sorted"] = self.derivatives_sorted_body()
        ctx["helpers"] = self.helpers
        # a small model's hot solvers are inlined into their callers (numba IR inlining):
        # a call between jitted functions passing arrays costs about as much as their work
        ctx["inline"] = self.blocks is not None and not self.helpers and len(self.q) <= SHARE_MAX
        if ctx["inline"] and self.level >= 2:
            ctx["sweep_step"] = self.sweep_step(ctx["position_sorted"])
            ctx["sweep_init"], ctx["sweep_keep"] = self.sweep_memory()
            ctx["sweep_resync"] = SWEEP_RESYNC
        ctx["level"] = self.level
        ctx["solved"] = self.solved
        ctx["pruned"] = not all(self.solved) or self.level < 2
        ctx["hash"] = model_hash(model, ctx)
        return ctx


class _Subs:
    """Rows of a matrix with a substitution applied on access (cached)."""

    def __init__(self, matrix, subs):
        self.matrix, self.subs, self.cache = matrix, dict(subs), {}

    def __getitem__(self, i):
        if i not in self.cache:
            self.cache[i] = self.matrix[i].subs(self.subs)
        return self.cache[i]


def _collect_form(expr, terms):
    """{term: coefficient} (and {1: the rest}) when expr is linear in the given terms with
    coefficients free of their variable, else None."""
    variable = set().union(*(t.free_symbols for t in terms))
    parts = sp.collect(expr, terms, evaluate=False)
    if not set(parts) <= set(terms) | {sp.Integer(1)}:
        return None
    if any(c.free_symbols & variable for c in parts.values()):
        return None
    return parts


def model_hash(model, ctx) -> str:
    """A stable digest of what the module computes (no timestamps: the same model, the
    same bytes)."""
    h = hashlib.sha256()
    for key in ("name", "coordinates", "guess", "parameters", "labels", "points", "outputs",
                "phi", "phi_q", "nu", "gamma", "points_code", "outputs_code", "position_sorted",
                "velocity_sorted", "acceleration_sorted", "mechgen_version", "format_version",
                "level", "solved", "helpers", "derivatives_sorted", "inline"):
        h.update(repr(ctx[key]).encode())
    return h.hexdigest()[:16]


def drawing_context(model, points):
    """What pictures need (mechgen.plot), as indices into POINTS: the points each constraint
    names, in argument order (an axis gives its first and second point), and for every body
    its origin (-1 for the ground, whose origin is the global one) and its points P1, P2, ..."""
    index = {(body, pt.local): k for k, (_, body, pt) in enumerate(points)}

    def at(pt):
        return index[(pt.body.name, pt.local)]

    joints = [(c.number, c.kind, [at(pt) for pt in getattr(c, "points", ())])
              for c in model.constraints]
    body_points = [(b.name, -1 if b.is_ground else at(b[0]),
                    [at(b[k]) for k in range(1, len(b.points) + 1)])
                   for b in model.bodies.values()]
    return dict(joints=joints, body_points=body_points)


__all__ = ["ModuleBuilder", "pycode"]
