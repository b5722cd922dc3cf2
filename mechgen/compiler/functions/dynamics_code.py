"""The dynamic sweep's step: the velocities, the accelerations and the multipliers of one
point in one pass, their sines and cosines computed once (a model with mass or loads whose
multipliers are written out, forces_code.multiplier_statements).

- ``dynamics_sorted(q, t, p, qd, qdd, piv, lam, factors)``: derivatives_sorted's pass,
  then Φ_qᵀ λ = Q_a + Q_c − I block by block and the driver factors, one CSE over both;
  piv[2] = 1.0, or 0.0 where a pivot of the multipliers fell below SING_RTOL (tested
  without a division) or a λ is not finite: the runtime then solves that point by the
  SVD. Compiled with numpy's error model: the multipliers are not stopped at a small
  pivot, their divisions give inf or NaN instead.
- ``sweep_fast_forces(..., LAM, FACTORS, FPIV)``: sweep_fast (compiler.solver.sweep) with that
  step at every point; a small model's written-out loop has the multipliers written into
  it, reading the sin and cos the position code turned from the last point.
- ``sweep_fast_statics(...)``: the same for a static sweep (a small model's written-out
  loop only): a position sweep with Φ_qᵀ λ = Q_a + Q_c at every point, the multipliers'
  code with q̇ = q̈ = 0 put in (its inertia and velocity terms vanish before CSE).

A dynamic sweep then costs its kinematics and the arithmetic of λ, not a second pass over
the points with the trigonometry again (runtime/forces/sweep.py).
"""
from __future__ import annotations

import sympy as sp

from ...model.forces.dynamics import dynamics
from ..codegen.inputs import prologue
from ..codegen.ir import Assign, Code, Guard, If, Return, Store, replaced
from ..codegen.schedule import TempNames, emit
from ..solver.sweep import in_loop
from .forces_code import multiplier_statements


def force_step(plan, eq, model, lam="lam[{}]", factors="factors[{}]", pivot="piv[2]"):
    """The multipliers (not stopped at a small pivot, locals ``_f...``), then stores of
    λ, the driver factors and the pivots' verdict (1.0 or 0.0) into the slots the formats
    name. None
    where the multipliers are not written out."""
    made = multiplier_statements(plan, eq, model, prefix="_f", stop=False)
    if made is None:
        return None
    st, lams = made
    total = " + ".join(f"{{{i}}}" for i in range(len(lams)))
    st.append(If(Code(f"not ({total}) * 0.0 == 0.0", tuple(lams)), (Code("_fw = 0.0"),),
                 tail="      # a λ not finite: the runtime solves the point again"))
    st += [Store(lam.format(i), x) for i, x in enumerate(lams)]
    st += [Store(factors.format(k), f, eq.labels[i])
           for k, (i, f) in enumerate(dynamics(model, eq).drivers)]
    return st + [Code(f"{pivot} = _fw")]


def dynamics_sorted_body(plan, eq, model, derivatives):
    """(body, helpers) of dynamics_sorted from linear.derivative_code; None where either
    part is missing."""
    step = force_step(plan, eq, model) if derivatives is not None else None
    if step is None:
        return None
    st = list(derivatives.statements) + step
    exprs = [x.expr for x in st if isinstance(x, (Assign, Store))]
    exprs += [x.bound for x in st if isinstance(x, Guard)]
    body = prologue(eq, exprs) + emit(st, TempNames(), plan.cse)
    return body + list(derivatives.tail) + [Return(0)], []


def written_forces(plan, eq, model):
    """(dynamic, static): the multipliers written into the fast sweep's loop, the sin and
    cos (and other calls) of the position code shared, the parameters it does not read
    loaded, λ, the factors and the pivots' verdict stored into row k of LAM, FACTORS,
    FPIV. ``dynamic`` after the derivative code, ``static`` the same step at q̇ = q̈ = 0
    (a static sweep's, after its position code at every point: nothing of the derivative
    code read). (None, None) where the multipliers are not written out."""
    step = force_step(plan, eq, model, "LAM[k, {}]", "FACTORS[k, {}]", "FPIV[k]")
    if step is None:
        return None, None
    still = {s: sp.Integer(0) for s in (*eq.qd, *eq.qdd)}
    rest = [replaced(x, lambda e: sp.sympify(e).xreplace(still)) for x in step]
    return (in_loop(plan, eq, step, "_fm", known=(*eq.qd, *eq.qdd)),
            in_loop(plan, eq, rest, "_fm"))


# (name, arguments, docstring lines) of the functions above, for the template
FUSED = (
    ("dynamics_sorted", "q, t, p, qd, qdd, piv, lam, factors", (
        "derivatives_sorted's pass, then Φ_qᵀ λ = Q_a + Q_c − I written out as in",
        "multipliers_point and the driver factors, one CSE over both (the sines and cosines",
        "computed once). piv[2] = 1.0, or 0.0 where a pivot of the multipliers fell below",
        "SING_RTOL or a λ is not finite (lam is then not to be used). Returns",
        "derivatives_sorted's status.")),
    ("sweep_fast_forces",
     "ts, q0, p, tol, xtol, maxit, Q, QD, QDD, STATUS, LAM, FACTORS, FPIV", (
        "sweep_fast with the multipliers at every point: row k of LAM, FACTORS (per",
        "DRIVER_ROWS) and FPIV (1.0, or 0.0 where a pivot fell below SING_RTOL: λ not to",
        "be used) receives point k's, computed from its velocities and accelerations in",
        "the same step. A dynamic sweep's quick path; the careful rest is solved by",
        "force_rows.")),
    ("sweep_fast_statics",
     "ts, q0, p, tol, xtol, maxit, Q, QD, QDD, STATUS, LAM, FACTORS, FPIV", (
        "sweep_fast_forces for a static sweep (QD and QDD without rows): a position sweep",
        "with the multipliers at q̇ = q̈ = 0 at every point, from the same step's sines",
        "and cosines. A static sweep's quick path; the careful rest is solved by",
        "force_rows.")),
)
