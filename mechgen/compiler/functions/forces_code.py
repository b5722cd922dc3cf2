"""The force functions of a model with mass or loads (mechgen.model.forces.dynamics), emitted as
straight-line code like Φ and Φ_q:

- ``force_terms(q, qd, qdd, t, p, out)``: out (3 × N_COORDS), rows Q_a (applied), Q_c
  (conservative, −∂V/∂q) and I (inertial), so that Φ_qᵀ λ = Q_a + Q_c − I;
- ``energies(q, qd, t, p, out)``: kinetic energy, potential energy and ∂V/∂t;
- ``driver_factors(q, t, p, out)``: per driver row (DRIVER_ROWS), ∂Φ/∂f, f the driven
  quantity: the driver's effort is λ·factor;
- ``frame_loads(q, qd, t, p, out)``: Q_f, the part of Q_a + Q_c of the loads anchored on
  the frame (FRAME_LOADS; a stub writing zeros where there are none): the frame takes
  their opposite, which the shaking force adds to what the constraints pass it;
- ``load_constants(p, out)``: the springs' stiffnesses and free lengths, the dampers'
  coefficients and gravity's g and direction's length, those of them that are functions
  of the parameters (LOAD_CONSTANTS names them; only where there are some): the runtime
  refuses parameters that make one negative (the direction's length: zero), as the model
  refuses them at its defaults.

A model without mass or loads gets none of them (its module is what it was).
"""
from __future__ import annotations

import sympy as sp

from ...model.forces.dynamics import dynamics
from ...protocol import SING_RTOL
from ..codegen.inputs import prologue
from ..codegen.ir import Assign, Code, If, Store
from ..codegen.printer import Local
from ..codegen.schedule import emit
from .equations_code import TITLES, straight_line

TITLES.update(force_terms="Q_a, Q_c and I, their nonzero entries",
              mass_matrix="M of I = M q̈ + h, its nonzero entries",
              energies="Kinetic energy, potential energy, ∂V/∂t",
              driver_factors="∂Φ/∂f per driver row",
              frame_loads="Q_f, the loads anchored on the frame",
              load_constants="The loads' constants of LOAD_CONSTANTS")


def load_constant_table(model, eq) -> list:
    """[(the load's kind, its name, the quantity, its expression, "not negative" or
    "positive"), ...]: the
    springs' k and free length, the dampers' c, gravity's g and the length of its
    direction, those that read parameters and nothing else (a plain number the model
    checked already; one that reads coordinates, velocities or T is not a constant)."""
    params = set(eq.params)
    out = []

    def add(kind, name, what, expr, rule):
        used = sp.sympify(expr).free_symbols
        if used and used <= params:
            out.append((kind, name, what, expr, rule))

    parts = getattr(model, "gravity_parts", None)
    if parts is not None:
        add("gravity", "", "g", parts[0], "not negative")
        add("gravity", "", "the length of its direction", parts[1], "positive")
    for ld in getattr(model, "loads", ()):
        if ld.kind not in ("spring", "damper"):
            continue
        a, b = ld.points
        name = ld.name or f"{a.label}-{b.label}"
        if ld.kind == "spring":
            add("spring", name, "the stiffness k", ld.k, "not negative")
            add("spring", name, "the free length", ld.length, "not negative")
        else:
            add("damper", name, "the coefficient c", ld.c, "not negative")
    return out


def forces_bodies(plan, eq, model):
    """{key: (body, helpers)} of the force functions, and the DRIVER_ROWS table; ({}, [])
    for a model without mass or loads."""
    if not model.has_dynamics:
        return {}, []
    dyn = dynamics(model, eq)
    q = list(eq.q)
    st = []
    for r, (vec, title) in enumerate(((dyn.applied, "Q_a"), (dyn.conservative, "Q_c"),
                                      (dyn.inertial, "I"))):
        for j in range(len(q)):
            if vec[j] != 0:
                st.append(Store(f"out[{r}, {j}]", vec[j], f"{title} {q[j]}"))
    bodies = {}
    bodies["force_terms"] = straight_line(plan, eq, st, "force_terms",
                                          "q, qd, qdd, t, p, out", with_qd=True,
                                          with_qdd=True) if st else ([Code("pass")], [])
    mass = dyn.inertial.jacobian(list(eq.qdd))
    st = [Store(f"out[{i}, {j}]", mass[i, j], f"M {q[i]} {q[j]}")
          for i in range(len(q)) for j in range(len(q)) if mass[i, j] != 0]
    bodies["mass_matrix"] = straight_line(plan, eq, st, "mass_matrix") if st \
        else ([Code("pass")], [])
    energy = [Store("out[0]", dyn.kinetic, "kinetic"), Store("out[1]", dyn.potential, "potential"),
              Store("out[2]", dyn.potential_t, "∂V/∂t")]
    bodies["energies"] = straight_line(plan, eq, energy, "energies", "q, qd, t, p, out",
                                       with_qd=True)
    factors = [Store(f"out[{k}]", f, eq.labels[i]) for k, (i, f) in enumerate(dyn.drivers)]
    bodies["driver_factors"] = straight_line(plan, eq, factors, "driver_factors") \
        if factors else ([Code("pass")], [])
    frame = [Store(f"out[{j}]", x, f"Q_f {q[j]}") for j, x in enumerate(dyn.frame) if x != 0]
    if frame:
        bodies["frame_loads"] = straight_line(plan, eq, frame, "frame_loads",
                                              "q, qd, t, p, out", with_qd=True)
    constants = [Store(f"out[{k}]", expr, f"{kind} {name}".strip() + f": {what}")
                 for k, (kind, name, what, expr, _) in
                 enumerate(load_constant_table(model, eq))]
    if constants:
        bodies["load_constants"] = straight_line(plan, eq, constants, "load_constants",
                                                 "p, out")
    return bodies, [i for i, _ in dyn.drivers]


def force_blocks(plan, eq):
    """Φ_q's blocks in the solving order, flattened for the module's multipliers_sorted:
    (starts, rows, columns), block b holding rows[starts[b]:starts[b + 1]] and as many
    coordinate columns; None where the multipliers cannot go block by block (an unsorted
    or pruned build, more equations than coordinates)."""
    if not plan.sorted or not all(plan.solved) or eq.phi.rows != len(eq.q):
        return None
    starts, rows, cols = [0], [], []
    for b in plan.blocks:
        if len(b.rows) != len(b.vars):
            return None
        rows.extend(b.rows)
        cols.extend(b.vars)
        starts.append(len(rows))
    if sorted(rows) != list(range(eq.phi.rows)) or sorted(cols) != list(range(len(eq.q))):
        return None
    return dict(starts=starts, rows=rows, cols=cols)


# blocks up to this size get the multipliers written out (Cramer's rule on 2 × 2); a model
# with a larger block keeps multipliers_sorted's elimination on the whole Φ_q
POINT_BLOCK_MAX = 2


def multipliers_point_body(plan, eq, model):
    """(body, helpers) of ``multipliers_point(q, qd, qdd, t, p, lam)``: Φ_qᵀ λ = Q_a + Q_c
    − I at one point, written out block by block in the reverse solving order, with one
    CSE pass over the right side and the nonzero entries of Φ_q that the blocks read (the
    sines and cosines computed once). A block of one row: λ_i = (r_c − Σ Φ_q[i', c] λ_i')
    / Φ_q[i, c]; of two: Cramer's rule. Each pivot is measured as multipliers_sorted
    measures it (on rows scaled by their largest entry, partial pivoting): below
    SING_RTOL the function returns it at once and the runtime solves λ by the SVD.
    Returns the smallest pivot. None where a block is larger than POINT_BLOCK_MAX, or the
    model's multipliers do not go block by block."""
    made = multiplier_statements(plan, eq, model)
    if made is None:
        return None
    st, lam = made
    st += [Store(f"lam[{i}]", x) for i, x in enumerate(lam)]
    exprs = [x.expr for x in st if isinstance(x, (Assign, Store))]
    body = prologue(eq, exprs, with_qd=True, with_qdd=True) + emit(st, cse=plan.cse)
    return body + [Code("return _w")], []


def multiplier_statements(plan, eq, model, prefix="_", stop=True):
    """(statements, λ symbols) of the written-out multipliers (multipliers_point_body),
    before CSE; their locals start with ``prefix``. ``stop``: a pivot below SING_RTOL (or
    a row of Φ_q all zero) returns at once, and ``<prefix>w`` is the smallest pivot; else
    the statements go on to the end (the divisions then give inf or NaN: a caller
    compiled with numpy's error model), each pivot tested without a division (|a| >=
    SING_RTOL · s rather than |a| / s >= SING_RTOL), and ``<prefix>w`` is 1.0, or 0.0
    where one fell below. None where the multipliers are not written out."""
    blocks = force_blocks(plan, eq)
    if blocks is None or not model.has_dynamics:
        return None
    starts = blocks["starts"]
    spans = [(blocks["rows"][a:b], blocks["cols"][a:b]) for a, b in zip(starts, starts[1:])]
    if any(len(r) > POINT_BLOCK_MAX for r, _ in spans):
        return None
    dyn = dynamics(model, eq)
    J = eq.nonzeros
    rhs = [dyn.applied[j] + dyn.conservative[j] - dyn.inertial[j] for j in range(len(eq.q))]
    lam = [Local(f"{prefix}l{i}", real=True) for i in range(eq.phi.rows)]
    w = f"{prefix}w"

    def scale(i):           # the row's largest entry (multipliers_sorted's row scaling)
        entries = [sp.Abs(x) for (r, _), x in J.items() if r == i]
        return sp.Max(*entries) if len(entries) > 1 else entries[0]

    def right(c, rows):     # r_c less what the blocks solved already carry
        return rhs[c] - sp.Add(*[J[(i, c)] * lam[i] for (i, cc) in J if cc == c and i not in rows])

    st = [Code(f"{w} = 1.0")]

    def pivot(num, den, tag):
        """The pivot num / den (both ≥ 0) tested against SING_RTOL; its symbol (stop)."""
        value = num / den
        if value.is_number and value >= SING_RTOL:     # a constant pivot: nothing to test
            return value
        if not stop:                # (the sides as locals: CSE shares their terms)
            a, b = Local(f"{prefix}a{tag}", real=True), Local(f"{prefix}b{tag}", real=True)
            st.extend([Assign(a, num), Assign(b, den),
                       If(Code("not {0} >= SING_RTOL * {1}", (a, b)), (Code(f"{w} = 0.0"),))])
            return a
        p = Local(f"{prefix}p{tag}", real=True)
        st.extend([Assign(p, value), Code(f"{w} = min({w}, {{0}})", (p,)),
                   If(Code("not {0} >= SING_RTOL", (p,)), (Code("return {0}", (p,)),))])
        return p

    for rows, cols in reversed(spans):
        if not stop and len(rows) == 1 and _never_small(sp.Abs(J[(rows[0], cols[0])]),
                                                         scale(rows[0])):
            (i,), (c,) = rows, cols         # a constant pivot no scale of its row can
            st.append(Assign(lam[i], right(c, rows) / J[(i, c)]))    # dwarf: no test
            continue
        s = []
        for i in rows:
            value = scale(i)
            if value.is_number and value > 0:           # a constant row: its own scale
                s.append(value)
                continue
            s.append(Local(f"{prefix}s{i}", real=True))
            st.append(Assign(s[-1], value, eq.labels[i]))
            if not any(a.is_number and a > 0 for a in value.args):   # else never zero
                st.append(If(Code("not {0} > 0.0", (s[-1],)),
                             (Code("return 0.0") if stop else Code(f"{w} = 0.0"),)))
        if len(rows) == 1:
            (i,), (c,) = rows, cols
            pivot(sp.Abs(J[(i, c)]), s[0], i)
            st.append(Assign(lam[i], right(c, rows) / J[(i, c)]))
            continue
        (i0, i1), (c0, c1) = rows, cols
        m = {(a, e): J.get((i, c), sp.Integer(0)) for a, c in enumerate(cols)
             for e, i in enumerate(rows)}
        largest = sp.Max(sp.Abs(m[0, 0]), sp.Abs(m[1, 0]))
        first = pivot(largest, s[0], f"{i0}a")     # (without stop: the local of largest)
        det = Local(f"{prefix}d{i0}", real=True)
        st.append(Assign(det, m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0]))
        if stop:
            pivot(sp.Abs(det), s[0] * s[1] * first, f"{i0}b")
        else:                               # |det| / (s0 s1 (largest / s0))
            pivot(sp.Abs(det), s[1] * (largest if first.is_number else first), f"{i0}b")
        y0, y1 = right(c0, rows), right(c1, rows)
        st.append(Assign(lam[i0], (y0 * m[1, 1] - m[0, 1] * y1) / det))
        st.append(Assign(lam[i1], (m[0, 0] * y1 - m[1, 0] * y0) / det))
    return st, lam


def _never_small(pivot, scale):
    """Whether a constant ``pivot`` stays at or above SING_RTOL times its row's ``scale``
    wherever the coordinates are: the scale bounded with |sin|, |cos| <= 1 (_bound)."""
    if not (pivot.is_number and pivot > 0):
        return False
    bound = _bound(scale)
    return bound is not None and float(pivot) >= SING_RTOL * bound


def _bound(e):
    """An upper bound of |e| over all coordinates, times and parameters (None where e
    holds a symbol outside sin and cos: a coordinate's or a parameter's size is not
    bounded)."""
    if e.is_number:
        return abs(float(e))
    if isinstance(e, (sp.sin, sp.cos)):
        return 1.0
    if isinstance(e, sp.Abs):
        return _bound(e.args[0])
    if isinstance(e, sp.Pow) and e.exp.is_Integer and e.exp > 0:
        b = _bound(e.base)
        return None if b is None else b ** int(e.exp)
    if isinstance(e, (sp.Add, sp.Mul, sp.Max)):
        parts = [_bound(a) for a in e.args]
        if any(b is None for b in parts):
            return None
        if isinstance(e, sp.Add):
            return sum(parts)
        if isinstance(e, sp.Max):
            return max(parts)
        out = 1.0
        for b in parts:
            out *= b
        return out
    return None


# the lines that zero ``out`` before a function writes its nonzero entries
ZERO_ROWS = ("for _i in range(out.shape[0]):", "    for _j in range(out.shape[1]):",
             "        out[_i, _j] = 0.0")
ZERO = ("for _j in range(out.shape[0]):", "    out[_j] = 0.0")
# the force functions the template lays out, in order: (name, arguments, docstring lines,
# the lines that zero ``out`` first); their bodies are the emitted ones
FUNCTIONS = (
    ("force_terms", "q, qd, qdd, t, p, out",
     ("out[0] = Q_a (applied forces, moments, dampers), out[1] = Q_c = −∂V/∂q (gravity,",
      "springs), out[2] = I (inertial: Σ m J_Gᵀ a_G + J θ̈), each over the coordinates."),
     ZERO_ROWS),
    ("energies", "q, qd, t, p, out", ("out = (kinetic energy, potential energy, ∂V/∂t).",),
     ()),
    ("driver_factors", "q, t, p, out",
     ("∂Φ/∂f per row of DRIVER_ROWS (f the driven quantity; NaN: not defined).",), ()),
    ("frame_loads", "q, qd, t, p, out",
     ("Q_f: the part of Q_a + Q_c of the loads anchored on the frame (a moment between a",
      "body and the ground, a spring or a damper with one end on it), over the",
      "coordinates: the frame takes their opposite."), ZERO),
    ("mass_matrix", "q, t, p, out",
     ("M of the inertial terms I = M q̈ + h, over the coordinates (a body's block couples",
      "its X, Y with its angle where its centroid is off its origin)."), ZERO_ROWS),
    ("multipliers_point", "q, qd, qdd, t, p, lam",
     ("Φ_qᵀ λ = Q_a + Q_c − I at one point, written out block by block in the reverse of",
      "the solving order (Φ_qᵀ is block upper-triangular in it): a block of one row by one",
      "division, of two by Cramer's rule, the right side and the entries of Φ_q sharing",
      "their terms. Each pivot is measured on rows scaled by their largest entry (partial",
      "pivoting, as multipliers_sorted): below SING_RTOL it is returned at once (the caller",
      "solves Φ_q's rank instead: lam is then not to be used). Returns the smallest pivot."),
     ()),
    ("load_constants", "p, out",
     ("out[k] = the value of LOAD_CONSTANTS[k] at the parameters p (the runtime refuses",
      "parameters that make one negative, or a direction's length zero)."), ()),
)
FUSED_STUB = ("Not written for this model (its multipliers are not written out, or its",
              "derivative pass is too long for one function): FORCE_FUSED is False and a",
              "dynamic sweep solves the multipliers after its kinematics (force_rows).")
STATIC_STUB = ("Not written for this model (its position solver is not written into the",
               "sweep, or its multipliers are not written out): STATIC_FUSED is False and a",
               "static sweep solves the multipliers after its positions (force_rows).")
FRAME_STUB = ("No load is anchored on the frame in this model (FRAME_LOADS is False): Q_f = 0.",)
POINT_STUB = ("Not written out for this model (a block of three or more rows, or no sorted",
              "build): FORCE_POINT is False and force_rows solves the multipliers otherwise.")


def force_functions(text, fused=()) -> list:
    """The template's force functions: dict(name, args, doc, zero (the lines zeroing out
    first), lines, options), the
    lines of each from ``text(name)`` (multipliers_point a stub that returns 0.0 where it
    is not written out); then ``fused``: (name, args, doc lines) of the functions of
    dynamics_code that the model has (numpy's error model; sweep_fast_forces and
    sweep_fast_statics stubs that accept no point where the model has not them,
    FORCE_FUSED and STATIC_FUSED False)."""
    out = []
    for name, args, doc, zero in FUNCTIONS:
        lines = text(name)
        if lines is None and name == "load_constants":
            continue                                # (only with constants to check)
        if lines is None and name == "frame_loads":
            doc, lines = FRAME_STUB, []             # (zeroed: Q_f = 0)
        elif lines is None:
            doc, lines = POINT_STUB, ["return 0.0"]
        out.append(dict(name=name, args=args, doc="\n    ".join(doc), zero=zero,
                        lines=lines, options=""))
    for name, args, doc in fused:
        lines = text(name)
        if lines is None and name == "sweep_fast_forces":   # the library names them
            doc, lines = FUSED_STUB, ["return 0"]
        if lines is None and name == "sweep_fast_statics":
            doc, lines = STATIC_STUB, ["return 0"]
        if lines is not None:
            out.append(dict(name=name, args=args, doc="\n    ".join(doc), zero=(),
                            lines=lines, options=', error_model="numpy"'))
    return out
