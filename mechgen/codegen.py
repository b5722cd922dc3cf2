"""What to emit: the render context of a generated module (routines with CSE done).

Each function body is a list of code lines; the template only lays them out.
"""
from __future__ import annotations

import hashlib

import sympy as sp

from . import __version__  # noqa: F401
from .blocks import linear_in, sort_blocks
from .geometry import T, Point
from .printer import Assign, Guard, Line, Store, TempNames, emit, pycode
from .symbolic import total_derivative

FORMAT_VERSION = 1
PIVOT_RTOL = 1e-10     # a pivot below this fraction of its row's size counts as zero
TINY = 1e-300


def _sym(name):
    return sp.Symbol(name, real=True)


def _unpack(names_in_use, vector, arg, comment=""):
    lines = []
    for k, s in enumerate(vector):
        if s in names_in_use:
            lines.append(f"{s.name} = {arg}[{k}]")
    return lines


def _free(exprs):
    out = set()
    for e in exprs:
        out |= sp.sympify(e).free_symbols
    return out


class ModuleBuilder:
    """Collects everything the template needs for one model."""

    def __init__(self, model, sort=True, level="acceleration", outputs=None, cse=True):
        self.model = model
        self.eq = model.equations()
        self.q = list(self.eq.q)
        self.qd = list(self.eq.qd)
        self.qdd = list(self.eq.qdd)
        self.params = model.param_symbols
        self.cse = cse
        self.level = {"position": 0, "velocity": 1, "acceleration": 2}[level]
        at = {s: v for s, v in zip(self.q, model.guess_vector())}
        at.update({sym: val for sym, val in model.params.values()})
        self.blocks = sort_blocks(self.eq.phi, self.eq.q, at) if sort else None
        self.output_names = list(model.outputs) if outputs is None else list(outputs)

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

    def _function(self, statements, **kw):
        exprs = [s.expr for s in statements if isinstance(s, (Assign, Store))]
        body = emit(statements, cse=self.cse)
        return self._prologue(exprs, **kw) + body

    # -- the quantities -------------------------------------------------------------
    def phi_body(self):
        st = [Store(f"out[{i}]", self.eq.phi[i], self.eq.labels[i]) for i in range(self.eq.phi.rows)]
        return self._function(st)

    def phi_q_body(self):
        J = self.eq.phi_q
        st = []
        for i in range(J.rows):
            for j in range(J.cols):
                if J[i, j] != 0:
                    st.append(Store(f"out[{i}, {j}]", J[i, j], f"{self.eq.labels[i]} / d{self.q[j]}"))
        return self._function(st)

    def nu_body(self):
        st = [Store(f"out[{i}]", self.eq.nu[i], self.eq.labels[i])
              for i in range(self.eq.nu.rows) if self.eq.nu[i] != 0]
        return self._function(st)

    def gamma_body(self):
        st = [Store(f"out[{i}]", self.eq.gamma[i], self.eq.labels[i])
              for i in range(self.eq.gamma.rows) if self.eq.gamma[i] != 0]
        return self._function(st, with_qd=True)

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
        return self._function(st)

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
            bodies.append(self._function(st, with_qd=True, with_qdd=True) if st else ["pass"])
            levels.append(d)
        return bodies, orders

    # -- the sorted solvers -----------------------------------------------------------
    def _block_comment(self, b):
        names = ", ".join(str(self.q[v]) for v in b.vars)
        rows = "; ".join(self.eq.labels[e] for e in b.eqs)
        return f"# block: {names} from {rows}"

    def position_sorted_body(self):
        """The block-by-block Newton: explicit assignments, 1-unknown and torn Newtons."""
        phi, q = self.eq.phi, self.q
        temps = TempNames()
        lines = []
        used = _free(list(phi))
        lines += _unpack(set(q), q, "q")
        lines += _unpack(used, self.params, "p")
        if T in used:
            lines.append("T = t")
        lines.append("_iters = 0")
        for b in self.blocks:
            lines.append(self._block_comment(b))
            if b.kind == "explicit":
                lines += emit(self._explicit(b.explicit, derivs=()), temps, self.cse)
                continue
            lines += self._newton_block(b, temps)
        for k, s in enumerate(q):
            lines.append(f"q[{k}] = {s.name}")
        lines.append("info[0] = _iters")
        lines.append("return 0")
        return lines

    def _explicit(self, pairs, derivs, tears=()):
        """Statements for z = −rest/coef for each (eq, var), and optionally dz/dy."""
        phi, q = self.eq.phi, self.q
        st = []
        for e, v in pairs:
            z = q[v]
            coef, rest = linear_in(phi[e], z)
            den = _sym(f"_den_{z.name}")
            if coef.is_number:
                st.append(Assign(z, sp.simplify(-rest / coef), f"row {e}: {self.eq.labels[e]}"))
            else:
                st.append(Assign(den, coef))
                st.append(Guard(den, sp.Float(1e-12), "4"))
                st.append(Assign(z, -rest / den, f"row {e}: {self.eq.labels[e]}"))
            for y in tears:
                total = sp.diff(phi[e], q[y])
                for e2, v2 in pairs:
                    if (e2, v2) == (e, v):
                        break
                    total += sp.diff(phi[e], q[v2]) * _sym(f"_d{q[v2].name}_d{q[y].name}")
                dz = _sym(f"_d{z.name}_d{q[y].name}")
                st.append(Assign(dz, -total / (coef if coef.is_number else den)))
        return st

    def _newton_block(self, b, temps):
        phi, q = self.eq.phi, self.q
        tears, res = b.tears, b.residuals
        k = len(tears)
        st = self._explicit(b.explicit, b.tears, tears=tears)
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
        body = emit(st, temps, self.cse)
        lines = []
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
        for i, y in enumerate(tears):
            body.append(f"{q[y].name} -= {S[i].name}")
            conv.append(f"abs({R[i].name}) <= tol and abs({S[i].name}) <= xtol * (1.0 + abs({q[y].name}))")
        body.append("if " + " and ".join(conv) + ":")
        body.append("    break")
        lines.append("for _it in range(maxit):")
        lines += ["    " + x for x in body]
        lines.append("else:")
        lines.append("    return 1")
        lines.append("_iters = max(_iters, _it + 1)")
        if b.explicit:  # the explicit unknowns from the final tear values
            lines += emit(self._explicit(b.explicit, derivs=()), temps, self.cse)
        return lines

    def linear_sorted_body(self, order):
        """Block forward substitution for Φ_q x = rhs (ν for order 1, γ for order 2)."""
        eq, q = self.eq, self.q
        J = eq.phi_q
        rhs = eq.nu if order == 1 else eq.gamma
        xs = self.qd if order == 1 else self.qdd
        st = []
        jsym = {}
        for i in range(J.rows):
            for j in range(J.cols):
                if J[i, j] != 0:
                    jsym[i, j] = J[i, j] if J[i, j].is_number else _sym(f"_j{i}_{j}")
                    if not J[i, j].is_number:
                        st.append(Assign(jsym[i, j], J[i, j]))
        rsym = {}
        for i in range(J.rows):
            rsym[i] = rhs[i] if rhs[i].is_number else _sym(f"_g{i}")
            if not rhs[i].is_number:
                st.append(Assign(rsym[i], rhs[i], eq.labels[i]))
        for b in self.blocks:
            st.append(Line(self._block_comment(b)))
            inside = set(b.vars)
            bvec = []
            for e in b.eqs:
                acc = rsym[e]
                for j in range(J.cols):
                    if (e, j) in jsym and j not in inside:
                        acc -= jsym[e, j] * xs[j]
                bvec.append(acc)
            A = [[jsym.get((e, v), 0) for v in b.vars] for e in b.eqs]
            scale = [sum(sp.Abs(jsym[e, j]) for j in range(J.cols) if (e, j) in jsym) for e in b.eqs]
            k = b.size
            if k == 1:
                a = A[0][0]
                if a.is_number:
                    st.append(Assign(xs[b.vars[0]], bvec[0] / a))
                else:
                    st.append(Guard(a, sp.Float(PIVOT_RTOL) * scale[0], "2"))
                    st.append(Assign(xs[b.vars[0]], bvec[0] / a))
            elif k == 2:
                det = _sym(f"_det{b.eqs[0]}")
                st.append(Assign(det, A[0][0] * A[1][1] - A[0][1] * A[1][0]))
                st.append(Guard(det, sp.Float(PIVOT_RTOL) * scale[0] * scale[1], "2"))
                st.append(Assign(xs[b.vars[0]], (bvec[0] * A[1][1] - A[0][1] * bvec[1]) / det))
                st.append(Assign(xs[b.vars[1]], (A[0][0] * bvec[1] - A[1][0] * bvec[0]) / det))
            else:
                bs = [_sym(f"_bb{i}") for i in range(k)]
                for i in range(k):
                    st.append(Assign(bs[i], bvec[i]))
                st.append(Line(f"_A = np.empty(({k}, {k}))"))
                st.append(Line(f"_b = np.empty({k})"))
                fill = []
                for i in range(k):
                    for j in range(k):
                        fill.append(Store(f"_A[{i}, {j}]", A[i][j]))
                    fill.append(Store(f"_b[{i}]", bs[i]))
                st += fill
                st.append(Line(f"if _gauss(_A, _b) < {k}:"))
                st.append(Line("    return 2"))
                for i, v in enumerate(b.vars):
                    st.append(Line(f"{xs[v].name} = _b[{i}]"))
        exprs = [s.expr for s in st if isinstance(s, (Assign, Store))]
        lines = self._prologue(exprs, with_qd=(order == 2))
        lines += emit(st, TempNames(), self.cse)
        for k, s in enumerate(xs):
            lines.append(f"out[{k}] = {s.name}")
        lines.append("return 0")
        return lines

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
            pivot_rtol=repr(PIVOT_RTOL),
        )
        if self.blocks is not None:
            ctx["blocks"] = [dict(kind=b.kind, vars=[self.q[v].name for v in b.vars],
                                  rows=list(b.eqs), tears=[self.q[v].name for v in b.tears])
                             for b in self.blocks]
            ctx["position_sorted"] = self.position_sorted_body()
            ctx["velocity_sorted"] = self.linear_sorted_body(1)
            ctx["acceleration_sorted"] = self.linear_sorted_body(2)
        ctx["hash"] = model_hash(model, ctx)
        return ctx


def model_hash(model, ctx) -> str:
    """A stable digest of what the module computes (no timestamps: the same model, the
    same bytes)."""
    h = hashlib.sha256()
    for key in ("name", "coordinates", "guess", "parameters", "labels", "points", "outputs",
                "phi", "phi_q", "nu", "gamma", "points_code", "outputs_code", "position_sorted",
                "velocity_sorted", "acceleration_sorted", "mechgen_version", "format_version"):
        h.update(repr(ctx[key]).encode())
    return h.hexdigest()[:16]


__all__ = ["ModuleBuilder", "pycode"]
