"""The straight-line functions of a sensitivity module: the derivatives of Φ, of the
velocity and acceleration equations, of the points and of the outputs with respect to
the parameters (mechgen.compiler.sensitivities lays them out).

With D the derivatives of the coordinates with respect to the parameters (one column per
parameter), the implicit-function theorem gives, the drivers' laws held:

    Φ_q Dq   = −Φ_p                                   (position)
    Φ_q Dq̇  = (ν − Φ_q q̇)_q Dq + (ν − Φ_q q̇)_p        (velocity)
    Φ_q Dq̈  = (γ − Φ_q q̈)_q Dq + (γ − Φ_q q̈)_q̇ Dq̇ + (γ − Φ_q q̈)_p   (acceleration)

the right sides are emitted here, symbolically differentiated once at build time, and
solved on Φ_q's blocks by the library (library/sensitivity.py). A quantity r(q, q̇, q̈, p)
(a point, an output) has the total derivative r_q Dq + r_q̇ Dq̇ + r_q̈ Dq̈ + r_p.
"""
from __future__ import annotations

import sympy as sp

from ...errors import ModelError
from ...model.rates import almost_everywhere
from ...model.symbolic import total_derivative
from ..codegen.inputs import free, prologue, sym
from ..codegen.ir import Assign, Code, If, Loop, Store, expressions, replaced, walk
from ..codegen.schedule import TempNames, emit

# the loop over the parameters' columns and the names the loop reads
COLUMN = "_c"


def _diff(expr, x):
    """∂expr/∂x with the rates of piecewise functions as numbers (model.rates)."""
    return almost_everywhere(sp.diff(expr, x))


def _refuse_unknown(model, exprs):
    """A derivative sympy cannot write out (of an opaque function without a rate: a
    profile's third derivative) cannot be emitted: say so at build time."""
    for e in exprs:
        if isinstance(e, sp.Basic) and e.has(sp.Derivative, sp.Subs):
            found = next(iter(e.atoms(sp.Derivative) or e.atoms(sp.Subs)))
            raise ModelError(f"model '{model.name}': its sensitivities need {found}, a "
                             "derivative the model's functions do not provide", where=None)


def _zero_fill(shape_loops):
    return Loop(Code("for _i in range(out.shape[0])"),
                (Loop(Code("for _j in range(out.shape[1])"), (Code("out[_i, _j] = 0.0"),)),)) \
        if shape_loops == 2 else Loop(Code("for _i in range(out.shape[0])"),
                                      (Code("out[_i] = 0.0"),))


def _directional(model, rows, wrt, labels, with_qd, with_qdd, eq, target="out"):
    """The body computing, for every selected column c (``sel``), ``target[i, c]`` =
    Σ_k ∂rows[i]/∂x_k · D_x[k, c] + ∂rows[i]/∂p_c over the pairs (x, D) of ``wrt``
    (a list of (symbols, array name)). ``rows`` are expressions; ``labels`` name them."""
    params = list(eq.params)
    head, loop = [], []
    dsyms = {}
    for xs, array in wrt:
        for k, x in enumerate(xs):
            dsyms[(array, k)] = sym(f"_d{array.lower()}{k}")
    used_d = set()
    stores_p = []
    derivs = []
    nans = []
    for i, r in enumerate(rows):
        if r is sp.nan or (isinstance(r, sp.Basic) and r.has(sp.nan)):
            nans.append(Loop(Code("for _j in range(out.shape[1])"),
                             (Code(f"{target}[{i}, _j] = math.nan  # {labels[i]}"),)))
            loop.append((i, sp.S.Zero))
            continue
        acc = sp.S.Zero
        for xs, array in wrt:
            for k, x in enumerate(xs):
                if x in r.free_symbols:
                    d = _diff(r, x)
                    if d != 0:
                        acc += d * dsyms[(array, k)]
                        used_d.add((array, k))
                        derivs.append(d)
        loop.append((i, acc))
        for j, pj in enumerate(params):
            if pj in r.free_symbols:
                d = _diff(r, pj)
                if d != 0:
                    stores_p.append(Store(f"{target}[{i}, {j}]", d, labels[i]))
                    derivs.append(d)
    _refuse_unknown(model, derivs)
    # Φ_p-like part first (every entry, zeros written), then the loop adds the rest
    head.append(_zero_fill(2))
    reads = [Code(f"{{0}} = {array}[{k}, {COLUMN}]", (dsyms[(array, k)],))
             for (array, k) in sorted(used_d)]
    sums = [Assign(sym(f"_r{i}"), acc) for i, acc in loop if acc != 0]
    adds = [Code(f"{target}[{i}, {COLUMN}] += {{0}}", (sym(f"_r{i}"),))
            for i, acc in loop if acc != 0]
    variant = {dsyms[key] for key in used_d}
    exprs = [s.expr for s in stores_p] + [a.expr for a in sums]
    inputs = prologue(eq, exprs, with_qd=with_qd, with_qdd=with_qdd)
    before_p = emit(stores_p, TempNames("_s"), True) if stores_p else []
    if sums:
        hoisted, inside = emit(sums, TempNames(), True, variant=variant)
        body = reads + inside + adds
        loop_st = [Loop(Code("for _k in range(sel.shape[0])"),
                        (Code(f"{COLUMN} = sel[_k]"),) + tuple(body))]
    else:
        hoisted, loop_st = [], []
    return inputs + head + before_p + hoisted + loop_st + nans


def phi_p_body(model, eq):
    """∂Φ/∂p: ``out[i, j]`` (zeros written first)."""
    return _directional(model, list(eq.phi), [], eq.labels, False, False, eq)


def velocity_rhs_body(model, eq):
    """The right sides of Φ_q Dq̇ = (ν − Φ_q q̇)_q Dq + (ν − Φ_q q̇)_p."""
    qd = list(eq.qd)
    rows = [eq.nu[i] - sum((eq.phi_q[i, j] * qd[j] for j in range(len(qd))
                            if eq.phi_q[i, j] != 0), sp.S.Zero) for i in range(eq.phi.rows)]
    return _directional(model, rows, [(list(eq.q), "DQ")], eq.labels, True, False, eq)


def acceleration_rhs_body(model, eq):
    """The right sides of Φ_q Dq̈ = (γ − Φ_q q̈)_q Dq + (γ − Φ_q q̈)_q̇ Dq̇ + (γ − Φ_q q̈)_p."""
    qdd = list(eq.qdd)
    rows = [eq.gamma[i] - sum((eq.phi_q[i, j] * qdd[j] for j in range(len(qdd))
                               if eq.phi_q[i, j] != 0), sp.S.Zero)
            for i in range(eq.phi.rows)]
    return _directional(model, rows, [(list(eq.q), "DQ"), (list(eq.qd), "DQD")], eq.labels,
                        True, True, eq)


def points_p_body(model, eq, points):
    """The points' derivatives: ``out[2 k + d, j]`` for point k's coordinate d."""
    rows, labels = [], []
    for label, _, pt in points:
        rows += [sp.sympify(pt.r[0]), sp.sympify(pt.r[1])]
        labels += [label, ""]
    return _directional(model, rows, [(list(eq.q), "DQ")], labels, False, False, eq)


def points_d_body(eq, points):
    """The points' velocities ``out[k, d]`` (d/dT of their positions)."""
    st = []
    for k, (label, _, pt) in enumerate(points):
        for d in range(2):
            st.append(Store(f"out[{k}, {d}]",
                            almost_everywhere(total_derivative(sp.sympify(pt.r[d]),
                                                               list(eq.q), 1)),
                            label if d == 0 else ""))
    exprs = [s.expr for s in st]
    return prologue(eq, exprs, with_qd=True) + emit(st, TempNames(), True)


def outputs_p_body(model, eq, names, order):
    """The derivatives of the outputs (order 0), or of their first or second rates."""
    rows, labels = [], []
    for name in names:
        expr = model.outputs[name]
        try:
            expr = total_derivative(expr, list(eq.q), order) if order else expr
        except ModelError:
            expr = sp.nan                 # a third derivative: not available
        rows.append(almost_everywhere(sp.sympify(expr)))
        labels.append(name + "'" * order)
    wrt = [(list(eq.q), "DQ"), (list(eq.qd), "DQD"), (list(eq.qdd), "DQDD")]
    return _directional(model, rows, wrt, labels, True, True, eq)




def solve_sorted_body(plan, eq):
    """Φ_q X = B on the columns ``sel`` by block forward substitution in the plan's
    solving order (the module's): Φ_q's entries and each block's singularity test once,
    then per column the substitution (a block of three or more unknowns by _gauss).
    Returns 2 (SINGULAR) where a block's pivot is below SING_RTOL of its scale."""
    from ..solver.linear import linear_code
    m = eq.phi.rows
    rhs = {i: sym(f"_b{i}") for i in range(m)}
    code = linear_code(plan, eq, 1, known=rhs)
    body = [st for piece in code.blocks for st in piece[0]]
    used = set()
    for st in body:
        for e in _exprs(st):
            used |= sp.sympify(e).free_symbols
    head = [Assign(s, eq.nonzeros[i, j]) for (i, j), s in code.jsym.items()
            if isinstance(s, sp.Symbol) and s in used]
    reads = [Code(f"{{0}} = B[{i}, {COLUMN}]", (rhs[i],)) for i in range(m) if rhs[i] in used]
    writes = [Store(f"X[{k}, {COLUMN}]", x) for k, x in enumerate(eq.qd)]
    exprs = [a.expr for a in head]
    inputs = prologue(eq, exprs)
    before = emit(head, TempNames("_s"), plan.cse)
    variant = set(rhs.values()) | set(eq.qd)
    hoisted, inside = emit(body, TempNames(), plan.cse, variant=variant)
    loop = Loop(Code("for _k in range(sel.shape[0])"),
                (Code(f"{COLUMN} = sel[_k]"),) + tuple(reads) + tuple(inside) + tuple(writes))
    return inputs + before + hoisted + [loop, Code("return 0")]


def _exprs(st):
    from ..codegen.ir import Guard
    if isinstance(st, (Assign, Store)):
        return [st.expr]
    if isinstance(st, Guard):
        return [st.value, st.bound]
    if isinstance(st, Code):
        return list(st.args)
    return []


def force_rhs_body(model, eq):
    """For a model with mass or loads: the right sides of Φ_qᵀ Dλ = (F − Φ_qᵀ λ)_q Dq +
    (…)_q̇ Dq̇ + (…)_q̈ Dq̈ + (…)_p, F = Q_a + Q_c − I (mechgen.model.forces.dynamics), λ
    held; one row per coordinate."""
    from ...model.forces.dynamics import dynamics
    dyn = dynamics(model, eq)
    lam = [sym(f"_lam{i}") for i in range(eq.phi.rows)]
    rows = []
    for j in range(len(eq.q)):
        f = dyn.applied[j] + dyn.conservative[j] - dyn.inertial[j]
        rows.append(f - sum((eq.phi_q[i, j] * lam[i] for i in range(eq.phi.rows)
                             if eq.phi_q[i, j] != 0), sp.S.Zero))
    labels = [f"{q.name}: Q_a + Q_c − I − Φ_qᵀλ" for q in eq.q]
    body = _directional(model, rows, [(list(eq.q), "DQ"), (list(eq.qd), "DQD"),
                                      (list(eq.qdd), "DQDD")], labels, True, True, eq)
    used = set()
    for st in walk(body):
        for e in expressions(st):
            used |= sp.sympify(e).free_symbols
    loads = [Code(f"{{0}} = lam[{i}]", (x,)) for i, x in enumerate(lam) if x in used]
    return loads + body


def driver_factors_p_body(model, eq):
    """The derivatives of the driver factors ∂Φ/∂f (DRIVER_ROWS' order)."""
    from ...model.forces.dynamics import dynamics
    dyn = dynamics(model, eq)
    rows = [sp.sympify(f) for _, f in dyn.drivers]
    labels = [eq.labels[i] for i, _ in dyn.drivers]
    if not rows:
        return [Code("pass")]
    return _directional(model, rows, [(list(eq.q), "DQ")], labels, False, False, eq)


def position_sensitivities_body(model, plan, eq) -> tuple:
    """position_sensitivity_parts as the function's statements: Dq = −Φ_q⁻¹ Φ_p into
    X[:, j] for the parameters with ``want[j]``, the sin and cos of the coordinates TURNED
    read from ``sc``. Returns (statements, TURNED)."""
    parts = position_sensitivity_parts(model, plan, eq)
    if parts is None:
        return [Code("return -1")], ()
    head, common, per, trig = parts
    exprs = [a.expr for a in head] + [st.expr for _, b, s in per for st in b + s]
    exprs += [e for st in common for e in _exprs(st)]
    read = free(exprs)
    loads, turned = [], []
    for k, x in enumerate(eq.q):
        for row, fn in enumerate((sp.sin, sp.cos)):
            if trig[fn(x)] in read:
                loads.append(Code(f"{{0}} = sc[{row}, {k}]", (trig[fn(x)],)))
        if trig[sp.sin(x)] in read or trig[sp.cos(x)] in read:
            turned.append(k)
    out = prologue(eq, exprs) + loads + emit(head + common, TempNames("_s"), plan.cse)
    temps = TempNames()
    for j, body, stores in per:
        out.append(If(Code(f"want[{j}]"), tuple(emit(body + stores, temps, plan.cse)),
                      tail=f"  # ∂/∂{eq.params[j].name}"))
    return out + [Code("return 0")], tuple(turned)


def position_sensitivity_parts(model, plan, eq, target="X[{k}, {j}]"):
    """Dq = −Φ_q⁻¹ Φ_p in one pass for the parameters j with ``want[j]`` (into X[:, j]):
    Φ_q's entries, Φ_p's and each block's singularity test once, common subexpressions
    shared, then per parameter the block forward substitution of its own right side, whose
    zeros are carried forward symbolically (a parameter that moves one loop touches only
    that loop's unknowns). Returns 2 where a block's pivot is below SING_RTOL of its
    scale; -1 in a model with a block of three or more unknowns (the library then solves
    on solve_sorted). Returns (head: Φ_q's and Φ_p's entries, common: the blocks'
    determinants, pivot guards and reciprocals, per: [(j, body, stores into ``target``)],
    trig: {sin(x): _sin_x, cos(x): _cos_x} the symbols that stand for the calls), or None
    where a block has three or more unknowns."""
    from ..codegen.ir import Guard
    from ..solver.linear import linear_code
    if any(b.size > 2 for b in plan.blocks):
        return None
    m, params = eq.phi.rows, list(eq.params)
    entries, derivs = {}, []
    for i in range(m):
        row = sp.sympify(eq.phi[i])
        for j, pj in enumerate(params):
            if pj in row.free_symbols:
                d = _diff(row, pj)
                if d != 0:
                    entries[i, j] = (sym(f"_p{i}_{j}"), -d)
                    derivs.append(d)
    _refuse_unknown(model, derivs)
    generic = linear_code(plan, eq, 1, known={i: sym(f"_b{i}") for i in range(m)})

    def shared(st):
        return isinstance(st, Guard) or (isinstance(st, Assign)
                                         and str(st.target).startswith("_det"))
    common = [st for piece in generic.blocks for st in piece[0] if shared(st)]
    per = []
    for j, pj in enumerate(params):
        rhs = {i: entries[i, j][0] if (i, j) in entries else sp.S.Zero for i in range(m)}
        code = linear_code(plan, eq, 1, known=rhs)
        known, body = {}, []
        for piece in code.blocks:
            for st in piece[0]:
                if shared(st) or not isinstance(st, Assign):
                    continue
                value = sp.sympify(st.expr).xreplace(known)
                if value.is_number:
                    known[st.target] = value
                else:
                    body.append(Assign(st.target, value))
        stores = [Store(target.format(k=k, j=j), known.get(x, x), f"∂{eq.q[k].name}/∂{pj.name}"
                        if k == 0 else "") for k, x in enumerate(eq.qd)]
        per.append((j, body, stores))
    # each pivot's reciprocal once, in place of a division per parameter
    pivots = set(generic.jsym.values()) | {st.target for st in common if isinstance(st, Assign)}
    inverse = {}
    for _, body, stores in per:
        for st in body + stores:
            for pw in sp.sympify(st.expr).atoms(sp.Pow):
                if pw.exp == -1 and pw.base in pivots and pw not in inverse:
                    inverse[pw] = sym(f"_inv{str(pw.base).lstrip('_')}")
    per = [(j, [replaced(st, lambda e: sp.sympify(e).xreplace(inverse)) for st in body],
            [replaced(st, lambda e: sp.sympify(e).xreplace(inverse)) for st in stores])
           for j, body, stores in per]
    common += [Assign(s_, 1 / pw.base) for pw, s_ in sorted(inverse.items(), key=str)]
    used = set()
    for _, body, stores in per:
        for st in body + stores:
            used |= sp.sympify(st.expr).free_symbols
    for st in common:
        used |= set().union(*(sp.sympify(e).free_symbols for e in _exprs(st)))
    head = [Assign(s, eq.nonzeros[i, j]) for (i, j), s in generic.jsym.items()
            if isinstance(s, sp.Symbol) and s in used]
    head += [Assign(s, d, eq.labels[i]) for (i, _), (s, d) in sorted(entries.items())
             if s in used]
    # sin and cos of a coordinate read from ``sc`` (the caller turns them from the last
    # point of a sweep, as the fast sweep does, instead of calling them again)
    trig = {}
    for k, x in enumerate(eq.q):
        trig[sp.sin(x)] = sym(f"_sin_{x.name}")
        trig[sp.cos(x)] = sym(f"_cos_{x.name}")

    def turned(st):
        return replaced(st, lambda e: sp.sympify(e).xreplace(trig))
    head = [turned(st) for st in head]
    common = [turned(st) for st in common]
    per = [(j, [turned(st) for st in body], [turned(st) for st in stores])
           for j, body, stores in per]
    return head, common, per, trig
