"""The one bridge between the runtime and sympy: ``mechgen.compile`` and the symbolic side
it attaches to a Mechanism, to evaluate any symbolic quantity on a solved configuration
or a whole sweep.

The runtime never imports this module (nor sympy): ``compile_model`` builds and loads a
module, then ``attach`` sets ``mech.model`` and ``mech.symbolic`` (a :class:`Symbolic`),
which the runtime calls for ``mech.evaluate(expr, s)`` and for the time derivative and
level of a symbolic quantity (interpolation, extremes, roots). The expression is
lambdified once (numpy backend) in the symbols it uses, then called on whole columns of
a sweep at once.

Symbols are matched by name against the mechanism's coordinates (``X4``), velocities
(``X4d``), accelerations (``X4dd``), parameters (values from ``mech.p``, so
``with_params`` is honoured) and the time ``T``.
"""
from __future__ import annotations

import os

import numpy as np
import sympy as sp

from .compiler.build import build_if_changed as _build_if_changed
from .errors import ModelError
from .model.quantities import dt
from .protocol import LEVEL, LEVELS
from .runtime import load
from .runtime.results import Solution, Sweep


def _slots(mech):
    """name -> (kind, index): kind the level (an index into LEVELS: q, qd, qdd) for a
    coordinate and its derivatives, 'p' for a parameter, 't' for T."""
    table = {"T": ("t", 0)}
    for k, name in enumerate(mech.parameter_names):
        table[name] = ("p", k)
    for k, c in enumerate(mech.coordinates):
        table[c] = (LEVEL["position"], k)
        table[c + "d"] = (LEVEL["velocity"], k)
        table[c + "dd"] = (LEVEL["acceleration"], k)
    return table


def _compiled(mech, expr):
    """(function, symbols, shape) for ``expr``, cached on the mechanism."""
    cache = mech.__dict__.setdefault("_evaluate_cache", {})
    if isinstance(expr, (list, tuple)):
        expr = sp.Matrix(expr)
    if isinstance(expr, sp.MatrixBase):
        expr = sp.ImmutableMatrix(expr)
    else:
        try:
            expr = sp.sympify(expr)
        except (sp.SympifyError, TypeError):
            raise TypeError(f"evaluate() takes a sympy expression or Matrix, got {expr!r}") from None
        if not isinstance(expr, sp.Expr):
            raise TypeError(f"evaluate() takes a sympy expression or Matrix, got {expr!r}")
    hit = cache.get(expr)
    if hit is not None:
        return hit
    table = _slots(mech)
    syms = sorted(expr.free_symbols, key=lambda s: s.name)
    unknown = [s.name for s in syms if s.name not in table]
    if unknown:
        raise ModelError(
            f"evaluate(): {', '.join(unknown)} {'is' if len(unknown) == 1 else 'are'} not a "
            f"coordinate (or its d/dd derivative), parameter or T of '{mech.name}'",
            where="")
    if isinstance(expr, sp.MatrixBase):
        shape = expr.shape
        entries = list(expr)
    else:
        shape = None
        entries = [expr]
    fn = sp.lambdify(syms, entries, modules="numpy")
    hit = (fn, [table[s.name] for s in syms], shape)
    cache[expr] = hit
    return hit


def _needed_level(slots) -> int:
    return max((kind for kind, _ in slots if isinstance(kind, int)), default=LEVEL["position"])


def evaluate(mech, expr, solution_or_sweep):
    """The value of ``expr`` at a :class:`Solution` (a float, or an array shaped like the
    Matrix with column vectors flattened) or along a :class:`Sweep` (the same with a
    leading axis of length ``len(sweep)``)."""
    target = solution_or_sweep
    if not isinstance(target, (Solution, Sweep)):
        raise TypeError("evaluate() needs a Solution or a Sweep (from mech.solve or mech.sweep), "
                        f"got {type(target).__name__}")
    if tuple(target.mechanism.coordinates) != tuple(mech.coordinates):
        raise ValueError(f"evaluate(): the solution belongs to '{target.mechanism.name}', "
                         f"not to '{mech.name}'")
    fn, slots, shape = _compiled(mech, expr)
    need = _needed_level(slots)
    if isinstance(target, Solution):
        vectors = (target.q, target.qd, target.qdd)
        t = target.t
        npts = None
    else:
        vectors = (target.Q, target.QD, target.QDD)
        t = target.t
        npts = len(target)
    if vectors[need] is None:
        missing = sorted({mech.coordinates[k] + "d" * kind
                          for kind, k in slots if isinstance(kind, int)
                          and kind >= LEVEL["velocity"] and vectors[kind] is None})
        what = "solution" if npts is None else "sweep"
        raise ValueError(
            f"evaluate(): the expression needs {', '.join(missing)}, but this {what} is at level "
            f"{target.level}: {'solve' if npts is None else 'sweep'} with "
            f"level={LEVELS[need]!r} or higher")
    args = []
    for kind, k in slots:
        if kind == "t":
            args.append(t)
        elif kind == "p":
            args.append(float(mech.p[k]))
        elif npts is None:
            args.append(float(vectors[kind][k]))
        else:
            args.append(vectors[kind][:, k])
    with np.errstate(all="ignore"):
        values = fn(*args)
    if npts is None:
        out = np.array([float(v) for v in values])
    else:
        out = np.stack([np.broadcast_to(np.asarray(v, dtype=np.float64), (npts,))
                        for v in values], axis=-1) if values else np.zeros((npts, 0))
    if shape is None:
        return float(out[0]) if npts is None else out[..., 0].copy()
    if shape[1] == 1:      # a column vector (a point, a direction): flat
        return out
    return out.reshape(out.shape[:-1] + shape)


class Symbolic:
    """The symbolic side of a mechanism built by ``mechgen.compile``: what the runtime
    calls (through ``mech.symbolic``) for a quantity given as a sympy expression."""

    def __init__(self, model):
        self.model = model

    def evaluate(self, mech, expr, solution_or_sweep):
        """The value of ``expr`` on a Solution or along a Sweep (see :func:`evaluate`)."""
        return evaluate(mech, expr, solution_or_sweep)

    def derivative(self, expr):
        """The total time derivative of ``expr`` (coordinates move, so do the drivers)."""
        return dt(expr, model=self.model)

    def level(self, mech, expr) -> int:
        """The solve level ``expr`` needs (an index into LEVELS): velocity when it holds a
        velocity symbol (X4d), acceleration when it holds an acceleration (X4dd)."""
        names = {s.name for s in getattr(expr, "free_symbols", ())}
        coords = mech.coordinates
        if any(c + "dd" in names for c in coords):
            return LEVEL["acceleration"]
        if any(c + "d" in names for c in coords):
            return LEVEL["velocity"]
        return LEVEL["position"]


def attach(mech, model):
    """Give a loaded mechanism its symbolic side: ``mech.model`` and ``mech.symbolic``, so
    that ``mech.evaluate(expr, s)`` and symbolic quantities in interpolate/extrema/roots
    work. ``model`` must be the model the mechanism's module was built from."""
    mech.model = model
    mech.symbolic = Symbolic(model)
    return mech


def cache_folder() -> str:
    """Where ``mechgen.compile`` writes modules by default: ``$MECHGEN_CACHE``, else
    ``~/.cache/mechgen``."""
    return os.environ.get("MECHGEN_CACHE") or os.path.join(
        os.path.expanduser("~"), ".cache", "mechgen")


def build_if_changed(model, outdir, **kwargs) -> str:
    """Write ``outdir/<name>.py`` unless it already holds this model's module (see
    mechgen.compiler.build.build_if_changed: an unchanged model is not rendered again)."""
    return _build_if_changed(model, outdir, **kwargs)


def compile_model(model, outdir=None, **kwargs):
    """``mechgen.compile``: build ``model`` into a folder (``outdir``, default
    :func:`cache_folder`; rewritten only when its text changed) and load it, keeping the
    symbolic model so that ``mech.evaluate(expr, solution_or_sweep)`` works."""
    if outdir is None:
        outdir = cache_folder()
    return attach(load(build_if_changed(model, outdir, **kwargs)), model)
