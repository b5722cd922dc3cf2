"""The fused quick path of a position sweep with sensitivities, written into the sensitivity
module (``sweep_fast_sensitivities``): the model module's own fast sweep (solver/sweep.py,
the same statements as its ``sweep_fast``), with Dq = −Φ_q⁻¹ Φ_p written after the
position code at every point (functions/sensitivity_code.position_sensitivity_parts), as
the static force sweep writes its multipliers there (``statics``). It reads the
coordinates and the sin and cos the position code holds (no second pass over the sweep's
points, no array views, no trig_pairs), writes DQ[k, i, j] for the parameters with
``want[j]`` and DSTATUS[k] (0, or 2 where a block of Φ_q has lost rank: that point's
derivatives are not written, the quick path goes on: a singular point changes nothing of
the sweep itself).

Only where the fast sweep has its solvers written out (a small model, no cam profile, no
Newton block: a Newton tear's sin and cos in the loop are its last iterate's); elsewhere
the module states SWEEP_FUSED = False and the runtime computes the derivatives after the
sweep (sensitivities_rows). The model's own module is not touched: a model that does not
ask for sensitivities pays nothing.
"""
from __future__ import annotations

import re

import sympy as sp

from .. import protocol
from ..model.geometry import T
from .codegen.inputs import free, time_local, unpack
from .codegen.ir import Assign, Code, Guard, If, replaced
from .codegen.schedule import TempNames, emit
from .context import sweep_arguments
from .functions.sensitivity_code import position_sensitivity_parts
from .library import body as library_body
from .solver.blocks import NEWTON
from .solver.dyads import reach_body
from .solver.linear import derivative_code, jacobian_det_body
from .solver.plan import SHARE_MAX
from .solver.sweep import sweep_fast_body, written_step

SIGNATURE = "ts, q0, p, tol, xtol, maxit, Q, QD, QDD, STATUS, want, DQ, DSTATUS"
DOC = ("The model module's sweep_fast (a position sweep: QD and QDD with no rows) with "
       "Dq = −Φ_q⁻¹ Φ_p at every point: DQ[k, :, j] for the parameters with want[j], "
       "DSTATUS[k] 0 (2 where Φ_q has lost rank, DQ[k] not written); returns the count of "
       "points it vouches for (mechgen/compiler/sensitivity_sweep.py).")
# what the loop reads of the header constants and of the library (continuation.py)
CONSTANTS = ("OK", "INFO_ITERATIONS", "POSITION_INFO_SIZE", "STATUS_CODE",
             "STATUS_ITERATIONS", "STATUS_SUBSTEPS", "STATUS_MAX", "BRANCH_RATIO",
             "BRANCH_ATOL", "BRANCH_TURN", "BRANCH_DET_EVERY")
LIBRARY = ("reach_kept", "reach_slope")


def fused_statements(model, plan, eq):
    """Dq = −Φ_q⁻¹ Φ_p as the fast sweep's loop writes it after the position code (k the
    point): the coordinates, parameters and time as the loop's locals, sin and cos of a
    coordinate the loop's own where the position code shares the pair (else called),
    a lost pivot setting _sw_sens = 2 instead of returning; None where the one-pass
    derivatives do not exist (a block of three or more unknowns)."""
    parts = position_sensitivity_parts(model, plan, eq, target="DQ[k, {k}, {j}]")
    if parts is None:
        return None
    head, common, per, trig = parts
    back = {s: call for call, s in trig.items()}
    shared = plan.position.shared_map

    def loop(st):
        return replaced(st, lambda e: sp.sympify(e).xreplace(back).xreplace(shared))
    def reciprocal(st):
        return isinstance(st, Assign) and str(st.target).startswith("_inv")
    inverse = [loop(st) for st in common if reciprocal(st)]
    common = [loop(st) for st in common if not reciprocal(st)]
    head = [loop(st) for st in head]
    per = [(j, [loop(st) for st in body], [loop(st) for st in stores])
           for j, body, stores in per]
    exprs = [st.expr for st in head + inverse] + [st.expr for _, b, s in per for st in b + s]
    exprs += [x for st in common for x in ((st.value, st.bound) if isinstance(st, Guard)
                                            else (st.expr,))]
    used, have = free(exprs), free(list(eq.phi))
    out = [Code("_sw_sens = 0")] + unpack(used - have, eq.params, "p")
    if T in used and T not in have:
        out.append(time_local())
    for st in emit(head + common, TempNames("_ds"), plan.cse):
        if isinstance(st, Guard):       # a lost pivot: no derivatives here, the sweep goes on
            st = If(Code("not abs({0}) > {1}", (st.value, st.bound)),
                    (Code("_sw_sens = 2"),))
        out.append(st)
    temps = TempNames("_dt")
    inner = list(emit(inverse, temps, plan.cse))
    for j, body, stores in per:
        inner.append(If(Code(f"want[{j}]"), tuple(emit(body + stores, temps, plan.cse)),
                        tail=f"  # ∂/∂{eq.params[j].name}"))
    return out + [If(Code("_sw_sens == 0"), tuple(inner)), Code("DSTATUS[k] = _sw_sens")]


def fused_bodies(model, eq, plan, profiles):
    """{name: statements} of sweep_fast_sensitivities and of the module functions its loop
    calls (jacobian_det, reach), or None where the module's fast sweep does not write its
    solvers out (``profiles``: the model has cam profiles) or has a Newton block. ``plan``:
    make_plan's with its defaults (the module's own build)."""
    if plan is None or profiles or len(eq.q) > SHARE_MAX or \
            not (plan.sorted and plan.level >= 2 and plan.share and not plan.position_parts) \
            or any(b.method == NEWTON for b in plan.blocks):
        return None
    statics = fused_statements(model, plan, eq)
    if statics is None:
        return None
    step = written_step(plan, eq, derivative_code(plan, eq))
    reach = reach_body(plan, eq)
    pairs, signs, guessed, tangent, watch, angles, checked, det = \
        sweep_arguments(model, plan, eq, step, reach is not None)
    sweep = sweep_fast_body(step, pairs, signs, guessed, tangent, watch, angles,
                            checked=checked, det=det, statics=statics)
    return {"sweep_fast_sensitivities": sweep, "jacobian_det": jacobian_det_body(plan, eq),
            "reach": reach or [Code("return 1.0")]}


def constants() -> list:
    """(name, value) of the header constants the loop reads."""
    return [(name, repr(getattr(protocol, name))) for name in CONSTANTS]


def library() -> str:
    """The library functions the loop calls (continuation.py), as every module holds them."""
    text = library_body("continuation.py")
    found = []
    for name in LIBRARY:
        m = re.search(r"^@njit\([^\n]*\)\ndef " + name + r"\(.*?(?=\n\n\n|\Z)", text,
                      re.S | re.M)
        if m is None:
            raise ValueError(f"the library has no {name}")
        found.append(m.group(0).rstrip("\n"))
    return "\n\n\n".join(found) + "\n"
