"""Evaluate any symbolic quantity on a solved configuration or a whole sweep.

This is the only runtime path that touches sympy, and only for mechanisms built with
``mechgen.compile(model)``, which keep the model: the expression is lambdified once (numpy
backend) in the symbols it uses, then called on whole columns of a sweep at once.

Symbols are matched by name against the mechanism's coordinates (``X4``), velocities
(``X4d``), accelerations (``X4dd``), parameters (values from ``mech.p``, so
``with_params`` is honoured) and the time ``T``.
"""
from __future__ import annotations

import numpy as np
import sympy as sp

from .errors import ModelError
from .runtime.results import Solution, Sweep

_LEVELS = ("position", "velocity", "acceleration")


def _slots(mech):
    """name -> (kind, index): kind 0/1/2 for q/qd/qdd, 'p' for a parameter, 't' for T."""
    table = {"T": ("t", 0)}
    for name, k in mech._param_index.items():
        table[name] = ("p", k)
    for k, c in enumerate(mech.coordinates):
        table[c] = (0, k)
        table[c + "d"] = (1, k)
        table[c + "dd"] = (2, k)
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


def _needed_level(slots):
    return max((kind for kind, _ in slots if isinstance(kind, int)), default=0)


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
        missing = sorted({mech.coordinates[k] + ("d" if kind == 1 else "dd")
                          for kind, k in slots if isinstance(kind, int) and kind >= 1
                          and vectors[kind] is None})
        what = "solution" if npts is None else "sweep"
        raise ValueError(
            f"evaluate(): the expression needs {', '.join(missing)}, but this {what} is at level "
            f"{target.level}: {'solve' if npts is None else 'sweep'} with "
            f"level={_LEVELS[need]!r} or higher")
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


def compile_model(model, outdir=None, **kwargs):
    """``mechgen.compile``: build ``model`` into a cache folder (``$MECHGEN_CACHE``, else
    ``~/.cache/mechgen``; ``outdir=`` to choose) and load it, keeping the symbolic model so
    that ``mech.evaluate(expr, solution_or_sweep)`` works."""
    import os

    from .compiler.build import build
    from .runtime.mechanism import load
    if outdir is None:
        outdir = os.environ.get("MECHGEN_CACHE") or os.path.join(
            os.path.expanduser("~"), ".cache", "mechgen")
    mech = load(build(model, outdir, **kwargs))
    mech.model = model
    return mech
