"""The render context of a generated module: everything the template lays out about the
model and its solvers (mechgen.compiler.render adds the header constants and the library).

``module_context`` is the compiler's one entry point from a model to that dict: it plans
the solver once (mechgen.compiler.solver.plan), has the emitters write each function body as
statements (mechgen.compiler.codegen.ir), chooses the identifiers of the model's symbols against
every name the module uses (mechgen.compiler.codegen.names) and prints the bodies as lines.
"""
from __future__ import annotations

import hashlib
import json
import re
import unicodedata

import sympy as sp

from ..model.forces.holds import held
from ..model.geometry import T
from ..model.stages import constraint_table, stages_context
from ..model.symbolic import check_square
from ..protocol import FORMAT_VERSION, PIVOT_RTOL, SING_RTOL
from ..protocol import MECHGEN_VERSION as __version__
from .codegen.ir import Options, code_words, render, symbols
from .codegen.names import Names, emitter_symbols, identifiers, module_words
from .codegen.printer import Derived
from .functions.dynamics_code import FUSED, dynamics_sorted_body, written_forces
from .functions.equations_code import (gamma_body, mesh_turns_body, nu_body, outputs_bodies,
                                       phi_body, phi_q_body, point_list, points_body)
from .functions.forces_code import (force_blocks, force_functions, forces_bodies,
                                    load_constant_table, multipliers_point_body)
from .functions.profiles_code import profile_helpers
from .solver.blocks import EXPLICIT
from .solver.dyads import reach_body
from .solver.linear import (derivative_code, derivatives_sorted_body, jacobian_det_body,
                            linear_sorted_body)
from .solver.plan import SHARE_MAX, make_plan, summary
from .solver.position import position_body, solved_once, trig_pair
from .solver.scratch import scalar_scratch, scratch_names
from .solver.sweep import options as sweep_options
from .solver.sweep import sweep_fast_body, written_det, written_step


def module_context(model, sort=True, level="acceleration", outputs=None, cse=True,
                   closed_forms="cheap") -> dict:
    """The render context of ``model``'s module for the given build options."""
    model = held(model)       # masses or loads and no driver: its free coordinates held
    eq = model.equations()
    check_square(model, eq)   # fewer equations than coordinates: refuse to build
    plan = make_plan(model, eq, sort=sort, level=level, outputs=outputs, cse=cse,
                     closed_forms=closed_forms)
    points = point_list(model)
    helpers, bodies = profile_helpers(model, eq, cse), {}    # cam profiles' functions
    profiles = bool(helpers)

    def put(key, made):
        body, parts = made
        helpers.extend(parts)
        bodies[key] = body

    made_outputs, orders = outputs_bodies(plan, eq, model)
    for k, made in enumerate(made_outputs):
        put(("outputs", k), made)
    force_parts, driver_rows = forces_bodies(plan, eq, model)  # only with mass or loads
    for key, made in force_parts.items():
        put(key, made)
    if force_parts:
        made = multipliers_point_body(plan, eq, model)
        if made is not None:
            put("multipliers_point", made)
    put("phi", phi_body(plan, eq))
    put("phi_q", phi_q_body(plan, eq))
    put("nu", nu_body(plan, eq))
    put("gamma", gamma_body(plan, eq))
    put("points_code", points_body(plan, eq, points))
    meshes = mesh_turns_body(plan, eq)
    if meshes is not None:
        put("mesh_turns", meshes[:2])
    derivatives = None
    if plan.sorted:
        put("position_sorted", position_body(plan, eq))
        put("jacobian_det", (jacobian_det_body(plan, eq), []))
        watched = reach_body(plan, eq)
        if watched is not None:
            put("reach", (watched, []))
        if plan.level >= 1:
            put("velocity_sorted", linear_sorted_body(plan, eq, 1))
        if plan.level >= 2:
            put("acceleration_sorted", linear_sorted_body(plan, eq, 2))
            derivatives = derivative_code(plan, eq)
            bodies["derivatives_sorted"] = derivatives_sorted_body(plan, eq, derivatives)
    # a small model's hot solvers are inlined into their callers (numba IR inlining): a
    # call between jitted functions passing arrays costs about as much as their work
    inline = plan.sorted and not helpers and len(eq.q) <= SHARE_MAX
    step = None                 # (the solvers written out in the fast sweep's loop)
    if plan.sorted and plan.level >= 2:
        # the solvers written out in the fast sweep's loop: a small model's, whether or
        # not long functions it does not call there (Φ_q, Φ) are split into parts
        written = plan.sorted and not profiles and len(eq.q) <= SHARE_MAX
        if written and plan.share and not plan.position_parts and derivatives is not None:
            step = written_step(plan, eq, derivatives)
        pairs, signs, guessed, tangent, watch, angles, checked, det = \
            sweep_arguments(model, plan, eq, step, "reach" in bodies)
        bodies["sweep_fast"] = sweep_fast_body(step, pairs, signs, guessed, tangent, watch,
                                               angles, checked=checked, det=det)
        # a dynamic solve's derivatives and multipliers in one pass, and the dynamic
        # sweep's quick path with the multipliers in its step (dynamics_code)
        made = dynamics_sorted_body(plan, eq, model, derivatives) if force_parts else None
        if made is not None:
            put("dynamics_sorted", made)
            forces, statics = written_forces(plan, eq, model) if step is not None else \
                (True, None)
            bodies["sweep_fast_forces"] = sweep_fast_body(step, pairs, signs, guessed, tangent,
                                                          watch, angles, forces, checked)
            if statics is not None:     # a static sweep's quick path with the multipliers
                bodies["sweep_fast_statics"] = sweep_fast_body(
                    step, pairs, signs, guessed, tangent, watch, angles, checked=checked,
                    det=det, statics=statics)

    names = name_map(model, eq, list(bodies.values()) + [h.body for h in helpers],
                     [h.args for h in helpers] + ([scratch_names(len(eq.q))] if step else []))
    plain = Options(names=names)

    def text(key):
        body = bodies.get(key)
        if body is None:
            return None
        fast = key in ("sweep_fast", "sweep_fast_forces", "sweep_fast_statics")
        lines = render(body, sweep_options(names) if fast else plain)
        if fast and step is not None:   # the solvers written out: the scratch as locals
            lines = scalar_scratch(lines, len(eq.q))
        return lines

    ctx = dict(
        name=model.name,
        doc=docstring_text(model.doc),
        mechgen_version=__version__,
        format_version=FORMAT_VERSION,
        n=len(eq.q), m=eq.phi.rows, row_wraps=row_wraps(eq),
        coordinates=[s.name for s in eq.q],
        guess=[repr(float(x)) for x in model.guess_vector()],
        parameters=[(name, repr(float(v))) for name, v in model.param_defaults.items()],
        labels=list(eq.labels),
        constraints=constraint_table(model),
        stages=stages_context(model), switch_times=[repr(t) for t in model.switch_times],
        points=[(label, body) for label, body, _ in points],
        bodies=[(b.name, b.number, b.is_ground) for b in model.bodies.values()],
        outputs=list(plan.outputs), output_orders=orders,
        phi=text("phi"), phi_q=text("phi_q"), nu=text("nu"), gamma=text("gamma"),
        points_code=text("points_code"),
        mesh_turns=text("mesh_turns"), mesh_rows=meshes[2] if meshes else [],
        outputs_code=[text(("outputs", k)) for k in range(3)],
        sorted=plan.sorted,
        blocks=[dict(kind=b.kind, method=b.method, summary=summary(b, eq.q),
                     vars=[eq.q[v].name for v in b.vars], rows=list(b.rows),
                     tears=[eq.q[v].name for v in b.tears]) for b in plan.blocks],
        position_sorted=text("position_sorted") or [],
        velocity_sorted=text("velocity_sorted") or [],
        acceleration_sorted=text("acceleration_sorted") or [],
        derivatives_sorted=text("derivatives_sorted"),
        jacobian_det=text("jacobian_det") or [],
        reach=text("reach") or ["return 1.0"],
        sweep_fast=text("sweep_fast"),
        helpers=[dict(name=h.name, args=h.args, doc=h.doc, lines=render(h.body, plain))
                 for h in helpers],
        inline=inline,
        forces=dict(functions=force_functions(text, FUSED), driver_rows=driver_rows,
                    point=text("multipliers_point") is not None,
                    frame=text("frame_loads") is not None,
                    fused=text("sweep_fast_forces") is not None,
                    static=text("sweep_fast_statics") is not None,
                    blocks=force_blocks(plan, eq),
                    **load_constants_context(model, eq))
        if force_parts else None,
        pivot_rtol=repr(PIVOT_RTOL),
        sing_rtol=repr(SING_RTOL),
        level=plan.level,
        solved=list(plan.solved),
        pruned=not all(plan.solved) or plan.level < 2,
    )
    ctx.update(drawing_context(model, points))
    ctx["hash"] = model_hash(ctx)
    return ctx


def sweep_arguments(model, plan, eq, step, reach) -> tuple:
    """What sweep_fast_body takes besides the step (its docstring): (pairs, signs, guessed,
    tangent, watch, angles, checked, det) of a sorted plan; ``step``: written_step's
    pieces or None, ``reach``: whether the module has a reach() (dyads.reach_body)."""
    pairs = [trig_pair(y) for y in plan.position.trig_pairs]
    signs = [Derived("_sg_", y) for y in plan.position.signs]
    # the coordinates a block solves other than explicitly (Newton's tears, closed
    # forms', dyads'): predicted, and their corrections watched: a dyad's or a signed
    # form's result does not depend on its guess, but a coarse step over a window where
    # it does not assemble shows as a correction its sign alone cannot see; the
    # tangent at a position sweep's first point predicts its second
    # (not those it solves once, before its loop: position.solved_once)
    once = solved_once(plan) if step is not None else set()
    guessed = sorted({v for b in plan.blocks if b.method != EXPLICIT for v in b.tears
                      if eq.q[v] not in once})
    tangent = bool(guessed)
    # the reach margins of the blocks solved whatever the guess (dyads.reach_body):
    # kept by the written-out solver's blocks, else from reach()
    watch = None if not reach else "written" if step else "call"
    rotations = {f"Th{b.number}" for b in model.bodies.values() if not b.is_ground}
    angles = [j for j, y in enumerate(eq.q) if y.name in rotations and y not in once]
    # the coordinates that come out a constant number are finite at every point
    constant = {y for y, v in plan.known_values.items() if v.is_number and v.is_finite}
    checked = [j for j, y in enumerate(eq.q) if y not in constant]
    det = written_det(plan, eq) if step is not None else None
    return pairs, signs, guessed, tangent, watch, angles, checked, det


def load_constants_context(model, eq) -> dict:
    """{"constants": the lines of the module's LOAD_CONSTANTS} (the template writes them
    as they are), or {} where the model has none (its module and its hash are then what
    they were)."""
    table = load_constant_table(model, eq)
    if not table:
        return {}
    lines = ["# the loads' constants that load_constants(p, out) writes, in order: (the "
             "load's kind, its",
             "# name, the quantity, its expression in the parameters, what it must be); "
             "the runtime refuses",
             "# parameters that break one", "LOAD_CONSTANTS = ("]
    for kind, name, what, expr, rule in table:
        text = ", ".join(json.dumps(x, ensure_ascii=False) for x in
                         (kind, name, what, sp.sstr(expr, full_prec=False), rule))
        lines.append(f"    ({text}),")
    return dict(constants="\n".join(lines + [")"]) + "\n")


def docstring_text(doc) -> str:
    """The model's documentation as the module's docstring writes it: its lines as
    given, with what would end or break the triple-quoted string escaped (backslashes,
    runs of double quotes) and control characters (a NUL, a carriage return) left out,
    so that Python reads back the model's text."""
    text = str(doc or "").replace("\r\n", "\n").replace("\r", "\n")
    text = "".join(c for c in text if c in "\n\t" or not unicodedata.category(c).startswith("C")
                   or unicodedata.category(c) == "Cf").strip()
    text = text.replace("\\", "\\\\")
    return re.sub(r'"{2,}', lambda m: '\\"' * len(m.group()), text)


def row_wraps(eq) -> list:
    """Whether each row of Φ counts whole turns of a wrapped angle (a function that
    ``wraps``: a gear's mesh_angle): the library's unwrap_turns never takes such a row
    for a driver."""
    return [any(getattr(f, "wraps", False) for f in eq.phi[i].atoms(sp.Function))
            for i in range(eq.phi.rows)]


def name_map(model, eq, bodies, extra_code=()) -> Names:
    """The identifiers of the model's symbols in a module whose function bodies are
    ``bodies`` (statement lists), against every name the module uses itself."""
    model_symbols = [*eq.params, *eq.q, *eq.qd, *eq.qdd, T]
    everything = [st for body in bodies if body is not None for st in body]
    derived, plain = emitter_symbols(symbols(everything))
    used = set(module_words())
    used |= identifiers("\n".join(sorted(set(code_words(everything)) | set(extra_code))))
    used |= plain
    return Names(model_symbols, used, derived)


def model_hash(ctx) -> str:
    """A stable digest of what the module computes (no timestamps: the same model, the
    same bytes)."""
    h = hashlib.sha256()
    for key in ("name", "coordinates", "guess", "parameters", "labels", "points", "outputs",
                "phi", "phi_q", "nu", "gamma", "points_code", "outputs_code", "position_sorted",
                "velocity_sorted", "acceleration_sorted", "mechgen_version", "format_version",
                "level", "solved", "helpers", "derivatives_sorted", "inline", "jacobian_det",
                "reach", "sweep_fast", "blocks"):
        h.update(repr(ctx[key]).encode())
    if ctx.get("forces"):       # only a model with mass or loads: the others' hash stays
        h.update(repr(ctx["forces"]).encode())
    return h.hexdigest()[:16]


def drawing_context(model, points):
    """What pictures need (mechgen.plot), as indices into POINTS: the points each
    constraint names, in argument order (an axis gives its first and second point), and
    for every body its origin (-1 for the ground, whose origin is the global one) and its
    points P1, P2, ..."""
    index = {(body, pt.local): k for k, (_, body, pt) in enumerate(points)}

    def at(pt):
        return index[(pt.body.name, pt.local)]

    joints = [(c.number, c.kind, [at(pt) for pt in getattr(c, "points", ())])
              for c in model.constraints]
    # the points a constraint places: a point it takes as such, not an axis' end (a body
    # turned half a turn that moves one is another assembly: runtime.analysis.assembly)
    placed = sorted({at(pt) for c in model.constraints for pt in getattr(c, "placed", ())
                     if (pt.body.name, pt.local) in index})
    body_points = [(b.name, -1 if b.is_ground else at(b[0]),
                    [at(b[k]) for k in range(1, len(b.points) + 1)])
                   for b in model.bodies.values()]
    # springs and dampers, drawn between their points (the pictures of a model with loads)
    loads = [(ld.name or ld.kind, ld.kind, [at(pt) for pt in ld.points])
             for ld in getattr(model, "loads", ()) if ld.kind in ("spring", "damper")]
    return dict(joints=joints, body_points=body_points, loads=loads, placed=placed)
