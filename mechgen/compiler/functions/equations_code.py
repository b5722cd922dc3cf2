"""The straight-line functions: Φ, Φ_q, ν, γ, the points and the outputs.

Each is a list of stores into ``out`` with one CSE pass over the whole function; past
plan.chunk_stores statements the work goes to parts ``_<name>_part<i>`` (each with its own
CSE) that the function calls in turn: numba compiles small functions much faster.
"""
from __future__ import annotations

import sympy as sp

from ...model.symbolic import total_derivative
from ..codegen.inputs import prologue
from ..codegen.ir import Assign, Code, Comment, Helper, Loop, Store
from ..codegen.schedule import emit

ARGS = "q, t, p, out"
OUTPUT_ARGS = "q, qd, qdd, t, p, out"


# what each straight-line function writes (the heading of its outputs)
TITLES = {"phi": "Φ, a row per constraint equation", "phi_q": "Φ_q, its nonzero entries",
          "nu": "ν, its nonzero rows", "gamma": "γ, its nonzero rows",
          "points": "The points, (x, y) each", "outputs": "The outputs",
          "outputs_d": "Their first time derivatives",
          "outputs_dd": "Their second time derivatives",
          "mesh_turns": "The mesh counts, a gear row each (MESH_ROWS)"}


def _sections(name, inputs, body):
    """A straight-line function's inputs and outputs, each under a heading (SymForce's
    ``# Input arrays``, ``# Output terms``) where the function is long enough for
    headings to help; the count of intermediate terms, each assigned before first use."""
    temps = sum(1 for x in body if isinstance(x, Assign))
    if len(inputs) + len(body) < 8:
        return inputs + body
    terms = f" ({temps} intermediate term{'s' if temps != 1 else ''})" if temps else ""
    return [Comment("Inputs")] + inputs + [Comment(f"{TITLES[name]}{terms}")] + body


def straight_line(plan, eq, statements, name, args=ARGS, **kw):
    """(body, helpers) of a straight-line function of ``statements``."""
    if len(statements) <= plan.chunk_stores:
        exprs = [s.expr for s in statements]
        return _sections(name, prologue(eq, exprs, **kw), emit(statements, cse=plan.cse)), []
    calls, helpers = [], []
    parts = [statements[i:i + plan.chunk_stores]
             for i in range(0, len(statements), plan.chunk_stores)]
    for i, part in enumerate(parts):
        helper = f"_{name}_part{i}"
        exprs = [s.expr for s in part]
        body = _sections(name, prologue(eq, exprs, **kw), emit(part, cse=plan.cse))
        helpers.append(Helper(helper, args, f"{name}, part {i + 1} of {len(parts)}.",
                              tuple(body)))
        calls.append(Code(f"{helper}({args})"))
    return calls, helpers


def phi_body(plan, eq):
    st = [Store(f"out[{i}]", eq.phi[i], eq.labels[i]) for i in range(eq.phi.rows)]
    return straight_line(plan, eq, st, "phi")


def phi_q_body(plan, eq):
    """Φ_q's nonzero entries, each row labelled once (on its first entry)."""
    st, last = [], None
    for (i, j), x in eq.nonzeros.items():
        st.append(Store(f"out[{i}, {j}]", x, eq.labels[i] if i != last else ""))
        last = i
    return straight_line(plan, eq, st, "phi_q")


def nu_body(plan, eq):
    st = [Store(f"out[{i}]", eq.nu[i], eq.labels[i]) for i in range(eq.nu.rows) if eq.nu[i] != 0]
    return straight_line(plan, eq, st, "nu")


def gamma_body(plan, eq):
    if plan.level < 2:
        return [Comment("not built: this module was built for a lower level than acceleration"),
                Loop(Code("for _i in range(out.shape[0])"), (Code("out[_i] = math.nan"),))], []
    st = [Store(f"out[{i}]", eq.gamma[i], eq.labels[i])
          for i in range(eq.gamma.rows) if eq.gamma[i] != 0]
    return straight_line(plan, eq, st, "gamma", "q, qd, t, p, out", with_qd=True)


def point_list(model):
    """Every point of every body (its list, its origin) and every point the constraints
    use, in a stable order: [(label, body name, Point)]."""
    seen, out = set(), []

    def add(pt):
        key = (pt.body.name, pt.local)
        if key not in seen:
            seen.add(key)
            out.append((pt.label, pt.body.name, pt))

    for body in model.bodies.values():
        if not body.is_ground:
            add(body[0])
        for k in range(1, len(body.points) + 1):
            add(body[k])
    for con in model.constraints:
        for pt in getattr(con, "points", ()):
            add(pt)
    for load in getattr(model, "loads", ()):
        if load.kind in ("spring", "damper"):     # drawn between their points
            for pt in load.points:
                add(pt)
    return out


def points_body(plan, eq, points):
    st = []
    for k, (label, _, pt) in enumerate(points):
        st.append(Store(f"out[{k}, 0]", pt.r[0], label))
        st.append(Store(f"out[{k}, 1]", pt.r[1]))
    return straight_line(plan, eq, st, "points")


def output_orders(model, eq, names):
    """Per output, the highest derivative of q it reads (0, 1 or 2)."""
    qd, qdd = set(eq.qd), set(eq.qdd)
    orders = []
    for name in names:
        syms = model.outputs[name].free_symbols
        orders.append(2 if syms & qdd else 1 if syms & qd else 0)
    return orders


def outputs_bodies(plan, eq, model):
    """Three (body, helpers): the outputs, their first and second time derivatives."""
    names = list(plan.outputs)
    orders = output_orders(model, eq, names)
    bodies = []
    for d in range(3):
        st = []
        for k, name in enumerate(names):
            if orders[k] + d > 2:
                st.append(Store(f"out[{k}]", sp.nan, f"{name}: needs a third derivative"))
                continue
            expr = model.outputs[name]
            if d:
                expr = total_derivative(expr, list(eq.q), d)
            st.append(Store(f"out[{k}]", expr, name + ("'" * d)))
        fn = ("outputs", "outputs_d", "outputs_dd")[d]
        bodies.append(straight_line(plan, eq, st, fn, OUTPUT_ARGS, with_qd=True, with_qdd=True)
                      if st else ([Code("pass")], []))
    return bodies, orders


def mesh_turns_body(plan, eq):
    """(body, helpers, rows) of ``mesh_turns(q, t, p, out)``: for each row of Φ holding a
    gear's wrapped rolling relation (mesh_angle(ux, uy, ψ, k)), (ψ − β)/2π unwrapped, β
    the angle of k u: the whole turns of the centre line the gears have rolled through,
    which the wrapped row cannot tell (it vanishes on every one). None without gears."""
    counts = mesh_counts(eq)
    if not counts:
        return None
    st = [Store(f"out[{k}]", expr, eq.labels[i]) for k, (i, expr) in enumerate(counts)]
    body, helpers = straight_line(plan, eq, st, "mesh_turns")
    return body, helpers, [i for i, _ in counts]


def mesh_counts(eq) -> list:
    """[(row, (ψ − β)/2π)] for every row of Φ holding a gear's wrapped rolling relation
    (mesh_angle(ux, uy, ψ, k), β the angle of k u): mechgen.turns' mesh counts."""
    out = []
    for i in range(eq.phi.rows):
        found = [f for f in eq.phi[i].atoms(sp.Function) if getattr(f, "wraps", False)]
        if found:
            ux, uy, psi, k = found[0].args
            out.append((i, (psi - sp.atan2(k * uy, k * ux)) / (2 * sp.pi)))
    return out
