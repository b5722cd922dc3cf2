"""The sensitivity module of a model: ``<name>_sensitivities.py`` beside ``<name>.py``,
built only when sensitivities are asked for (``mechgen build --sensitivities``,
``mechgen.compile(..., sensitivities=True)``, or the first call that asks for them on a
mechanism that knows its model), so that a model or a call that does not ask pays
nothing: its module is the one it was.

It holds Φ_q again, the derivatives of Φ, of the velocity and acceleration equations, of
the points and of the outputs with respect to every parameter
(functions/sensitivity_code.py), the library's block solve (library/sensitivity.py)
and, where the module's fast sweep writes its solvers out, a position sweep's quick path
with the derivatives in its loop (sensitivity_sweep.py: SWEEP_FUSED).
It imports only math, numpy and numba, as every generated module, and states the
MODEL_HASH of the module it belongs to.
"""
from __future__ import annotations

import json
import os
import re
from types import SimpleNamespace

import sympy

from ..errors import MechgenError
from ..model.forces.holds import held
from ..model.geometry import T
from ..model.symbolic import check_square
from ..protocol import (MECHGEN_VERSION, SENSITIVITY_FORMAT, SING_RTOL, STAMP, TINY,
                        content_digest)
from .build import write_module
from .codegen.ir import (Code, Loop, Options, code_words, expressions, render, symbols,
                         walk)
from .codegen.names import Names, emitter_symbols, identifiers, module_level_names, module_words
from .functions.equations_code import phi_q_body, point_list
from .functions.profiles_code import profile_helpers
from .functions.sensitivity_code import (acceleration_rhs_body, driver_factors_p_body,
                                         force_rhs_body, outputs_p_body, phi_p_body,
                                         points_d_body, points_p_body,
                                         position_sensitivities_body, solve_sorted_body,
                                         velocity_rhs_body)
from .library import body as library_body
from .sensitivity_sweep import DOC as SWEEP_DOC
from .sensitivity_sweep import SIGNATURE as SWEEP_SIGNATURE
from .sensitivity_sweep import constants as fused_constants
from .sensitivity_sweep import fused_bodies
from .sensitivity_sweep import library as fused_library
from .solver.plan import CHUNK_STORES, make_plan
from .solver.scratch import scalar_scratch, scratch_names
from .solver.sweep import options as sweep_options
from .render import environment

SUFFIX = "_sensitivities"
_HASH = re.compile(r'^MODEL_HASH = "([0-9a-f]+)"$', re.M)

# (name, arguments, docstring) of the functions, in the module's order
SIGNATURES = (
    ("phi_q", "q, t, p, out", "Jacobian Φ_q (as in the module)."),
    ("phi_p", "q, t, p, out", "∂Φ/∂p (N_EQS × N_PARAMS)."),
    ("velocity_rhs_p", "q, qd, t, p, DQ, sel, out",
     "(ν − Φ_q q̇)_q DQ + (ν − Φ_q q̇)_p on the columns sel: Φ_q DQD's right side."),
    ("acceleration_rhs_p", "q, qd, qdd, t, p, DQ, DQD, sel, out",
     "(γ − Φ_q q̈)_q DQ + (γ − Φ_q q̈)_q̇ DQD + (γ − Φ_q q̈)_p on the columns sel: "
     "Φ_q DQDD's right side."),
    ("points_p", "q, t, p, DQ, sel, out",
     "The points' derivatives: out[2 k + d, c] of point k's coordinate d (POINTS' order)."),
    ("points_d", "q, qd, t, p, out", "The points' velocities out[k, d]."),
    ("solve_sorted", "q, t, p, B, sel, X",
     "Φ_q X = B on the columns sel, block by block in the module's solving order "
     "(0, or 2 where Φ_q has lost rank)."),
    ("position_sensitivities", "q, sc, t, p, want, X",
     "Dq = −Φ_q⁻¹ Φ_p into X[:, j] for the parameters with want[j], in one pass, the sin "
     "and cos of the coordinates TURNED read from sc[0], sc[1] (0; 2 where Φ_q has lost "
     "rank; -1 where the module has no such pass: solve_sorted)."),
    ("force_rhs_p", "q, qd, qdd, t, p, lam, DQ, DQD, DQDD, sel, out",
     "Φ_qᵀ Dλ's right side (N_COORDS × N_PARAMS), λ held (a model with mass or loads)."),
    ("driver_factors_p", "q, t, p, DQ, sel, out",
     "The derivatives of the driver factors ∂Φ/∂f (the module's DRIVER_ROWS)."),
    ("outputs_p", "q, qd, qdd, t, p, DQ, DQD, DQDD, sel, out",
     "The outputs' derivatives out[k, c]."),
    ("outputs_d_p", "q, qd, qdd, t, p, DQ, DQD, DQDD, sel, out",
     "The derivatives of the outputs' first rates."),
    ("outputs_dd_p", "q, qd, qdd, t, p, DQ, DQD, DQDD, sel, out",
     "The derivatives of the outputs' second rates."),
)


DOC = """The derivatives of the coordinates with respect to the parameters, the drivers' laws
held (the implicit-function theorem at a solved configuration):

    Φ_q Dq   = −Φ_p
    Φ_q Dq̇  = (ν − Φ_q q̇)_q Dq + (ν − Φ_q q̇)_p
    Φ_q Dq̈  = (γ − Φ_q q̈)_q Dq + (γ − Φ_q q̈)_q̇ Dq̇ + (γ − Φ_q q̈)_p

Right sides differentiated symbolically at build time, solved on Φ_q's blocks in the
module's solving order (solve_columns). D arrays are N_COORDS × N_PARAMS, a column per
parameter; ``sel`` (int64) lists the columns to compute."""


def _tuple(names) -> str:
    return "(" + "".join(json.dumps(n) + ", " for n in names) + ")"


def companion_path(module_path: str) -> str:
    """Where the sensitivity module of the module at ``module_path`` lives."""
    root, ext = os.path.splitext(module_path)
    return root + SUFFIX + (ext or ".py")


def module_hash_of(module_path: str) -> str:
    """The MODEL_HASH a generated module states in its header."""
    with open(module_path, encoding="utf-8") as fh:
        found = _HASH.search(fh.read())
    if not found:
        raise MechgenError(f"{module_path} states no MODEL_HASH: not a module mechgen generated")
    return found.group(1)


def render_sensitivities(model, module_hash: str, sort=True, fuse=True) -> str:
    """The text of ``model``'s sensitivity module, for the module whose MODEL_HASH is
    ``module_hash`` (``sort``: whether that module is sorted; its Φ_q is then solved on
    the same blocks, written out: solve_sorted; ``fuse``: whether that module is the
    default build, whose fast sweep sweep_fast_sensitivities copies)."""
    model = held(model)
    eq = model.equations()
    check_square(model, eq)
    plan = SimpleNamespace(chunk_stores=CHUNK_STORES, cse=True)
    solver = make_plan(model, eq, sort=sort) if eq.phi.rows == len(eq.q) else None
    sorted_ = solver is not None and solver.sorted
    points = point_list(model)
    outputs = list(model.outputs)
    jq, helpers = phi_q_body(plan, eq)
    one_pass, turned = position_sensitivities_body(model, solver, eq) if sorted_ \
        else ([Code("return -1")], ())
    zero = Loop(Code("for _i in range(out.shape[0])"),
                (Loop(Code("for _j in range(out.shape[1])"), (Code("out[_i, _j] = 0.0"),)),))
    bodies = {
        "phi_q": [zero] + list(jq),
        "phi_p": phi_p_body(model, eq),
        "velocity_rhs_p": velocity_rhs_body(model, eq),
        "acceleration_rhs_p": acceleration_rhs_body(model, eq),
        "points_p": points_p_body(model, eq, points),
        "points_d": points_d_body(eq, points),
        "solve_sorted": solve_sorted_body(solver, eq) if sorted_ else [Code("return -1")],
        "position_sensitivities": one_pass,
        "force_rhs_p": force_rhs_body(model, eq) if model.has_dynamics else [Code("pass")],
        "driver_factors_p": driver_factors_p_body(model, eq) if model.has_dynamics
        else [Code("pass")],
    }
    for order, name in enumerate(("outputs_p", "outputs_d_p", "outputs_dd_p")):
        bodies[name] = outputs_p_body(model, eq, outputs, order) if outputs else [Code("pass")]
    # a cam profile's functions (and their derivatives in parameters) as helpers
    used = [e for b in bodies.values() for st in walk(b) for e in expressions(st)]
    profiles = profile_helpers(model, eq, extra=used)
    helpers = profiles + list(helpers)
    # a position sweep's quick path with the derivatives in its loop (sensitivity_sweep)
    fused = fuse and fused_bodies(model, eq, solver if sorted_ else None, bool(profiles)) or {}
    library = library_body("linalg.py") + "\n\n" + library_body("sensitivity.py")
    if fused:
        library += "\n\n" + fused_library()
    everything = [st for b in list(bodies.values()) + list(fused.values()) for st in b] + \
        [st for h in helpers for st in h.body]
    derived, plain = emitter_symbols(symbols(everything))
    used = set(module_words()) | module_level_names(library) | plain
    words = set(code_words(everything)) | {a for _, a2, _ in SIGNATURES for a in a2.split(", ")}
    words |= {name for name, _, _ in SIGNATURES} | set(fused)
    if fused:
        words |= set(SWEEP_SIGNATURE.split(", ")) | set(scratch_names(len(eq.q)).split())
    used |= identifiers("\n".join(sorted(words)))
    names = Names([*eq.params, *eq.q, *eq.qd, *eq.qdd, T], used, derived)
    options = Options(names=names)
    # the one-pass derivatives inlined into the loops that call them (their arrays' views
    # then cost no call: 51 against 62 ns a point on the quick-return)
    inline = {"position_sensitivities": ', inline="always"'}
    functions = [dict(name=fn, args=args, doc=doc, lines=render(bodies[fn], options),
                      options=inline.get(fn, "")) for fn, args, doc in SIGNATURES]
    helpers = [dict(name=h.name, args=h.args, doc=h.doc, lines=render(h.body, options),
                    options="") for h in helpers]
    if fused:
        functions += fused_functions(fused, names, options, len(eq.q))
    constants = [("MODEL_NAME", json.dumps(model.name)), ("MODULE_HASH", json.dumps(module_hash)),
                 ("COMPANION", '"sensitivities"'), ("SENSITIVITY_FORMAT", str(SENSITIVITY_FORMAT)),
                 ("N_COORDS", str(len(eq.q))),
                 ("N_EQS", str(eq.phi.rows)), ("N_PARAMS", str(len(eq.params))),
                 ("COORDINATES", _tuple(s.name for s in eq.q)),
                 ("PARAMETERS", _tuple(s.name for s in eq.params)),
                 ("N_POINTS", str(len(points))), ("OUTPUTS", _tuple(outputs)),
                 ("SING_RTOL", repr(SING_RTOL)), ("TINY", repr(TINY)),
                 ("SORTED", str(sorted_)), ("FORCES", str(bool(model.has_dynamics))),
                 ("TURNED", "np.array(%s, dtype=np.int64)" % _tuple(turned).replace('"', "")),
                 ("SWEEP_FUSED", str(bool(fused)))] + (fused_constants() if fused else [])
    ctx = dict(name=model.name, module_name=model.name + SUFFIX, doc=DOC,
               mechgen_version=MECHGEN_VERSION, coordinates=[s.name for s in eq.q],
               parameters=[s.name for s in eq.params], constants=constants,
               functions=helpers + functions, library=library)
    body = environment().get_template("sensitivities.py.j2").render(**ctx)
    head = (f"# Generated by mechgen {MECHGEN_VERSION} -- do not edit.\n"
            f"# sympy {sympy.__version__}\n")
    text = head + body
    compile(text, f"{model.name}{SUFFIX}.py", "exec", dont_inherit=True)
    return STAMP.format(digest=content_digest(text)) + text


def fused_functions(fused, names, options, n) -> list:
    """The function dicts of the fused quick path (sensitivity_sweep) and of the module
    functions its loop calls, as the template writes them."""
    sweep = scalar_scratch(render(fused["sweep_fast_sensitivities"], sweep_options(names)), n)
    doc = {"jacobian_det": "det Φ_q up to a constant sign into piv[0] (as in the module), "
                           "the pattern of its blocks' signs into piv[1].",
           "reach": "The smallest reach margin of the blocks solved whatever the guess "
                    "(as in the module; 1.0: none)."}
    return [dict(name="jacobian_det", args="q, t, p, piv", doc=doc["jacobian_det"],
                 lines=render(fused["jacobian_det"], options), options=""),
            dict(name="reach", args="q, t, p", doc=doc["reach"],
                 lines=render(fused["reach"], options), options=""),
            dict(name="sweep_fast_sensitivities", args=SWEEP_SIGNATURE, doc=SWEEP_DOC,
                 lines=sweep, options="")]


def _function_text(text: str, name: str):
    """The text of module-level function ``name`` in a module's ``text`` (from its def
    line to the next decorator or definition), or None."""
    start = text.find(f"\ndef {name}(")
    if start < 0:
        return None
    end = re.search(r"\n(@|def |class )", text[start + 1:])
    return text[start:start + 1 + end.start()] if end else text[start:]


def _default_fast_sweep(model, module_text: str) -> bool:
    """Whether the module's sweep_fast is the one a default build writes (the fused quick
    path's copy holds only then: a build with --level, --closed-forms, --outputs or
    without CSE solves another way)."""
    import warnings
    from .render import render as render_module
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")     # (the module's build said them already)
        default = render_module(model)
    mine = _function_text(module_text, "sweep_fast")
    return mine is not None and mine == _function_text(default, "sweep_fast")


def build_sensitivities(model, module_path: str) -> str:
    """Write the sensitivity module of ``model`` beside its module at ``module_path``
    (unless the file there already holds the same text); returns its path."""
    path = companion_path(module_path)
    with open(module_path, encoding="utf-8") as fh:
        module = fh.read()
    sort = "\nSORTED = True\n" in module
    # the fused quick path copies the fast sweep of a default build (make_plan's options):
    # written only where the module's own sweep_fast is that build's, word for word
    fuse = _default_fast_sweep(model, module)
    text = render_sensitivities(model, module_hash_of(module_path), sort, fuse)
    try:
        with open(path, encoding="utf-8") as fh:
            if fh.read() == text:
                return path
    except OSError:
        pass
    return write_module(text, path)


__all__ = ["SUFFIX", "build_sensitivities", "companion_path", "module_hash_of",
           "render_sensitivities"]
