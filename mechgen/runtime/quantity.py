"""What a name means on a mechanism: a coordinate (``"X4"``), its derivatives (``"X4d"``,
``"X4dd"``), a declared output (``"stroke_x"``, ``"stroke_xd"``) or, on a mechanism built by
``mechgen.compile``, a symbolic expression (evaluated by the symbolic side the bridge
attaches; the runtime itself never touches sympy).

The lowest module of the runtime's analysis: results, interpolation and events read
quantities through it, and it imports none of them.
"""
from __future__ import annotations

import numpy as np

from ..errors import ModelError
from ..protocol import LEVEL, LEVELS

# The suffix of a name's k-th time derivative: "X4", "X4d", "X4dd".
SUFFIXES = ("", "d", "dd")


def level_needed(label, need, have, what) -> str:
    """Why a solve or sweep (``what``) at level ``have`` cannot give ``label``, which
    needs derivatives of order ``need``: a higher level, or none at all where it would
    take the rate of accelerations (the derivative of an output holding q̈)."""
    if need > LEVEL["acceleration"]:
        return (f"{label!r} is not available: it is the rate of a quantity that holds "
                "accelerations, and mechgen solves no third derivative (jerk)")
    return (f"{label!r} needs a {what} at level {LEVELS[need]} (this {what} is at level "
            f"{LEVELS[have]})")


def level_of(qd, qdd) -> int:
    """The level (an index into LEVELS) of a solution or sweep holding these derivatives."""
    return LEVEL["position"] if qd is None else \
        LEVEL["velocity"] if qdd is None else LEVEL["acceleration"]


def lookup(mech, name):
    """(kind, index, order) for a name: a coordinate ("q"), its derivative or an output
    ("out"); order is the number of d's it carries."""
    kind, k, order = _find(mech, name)
    if kind == "q" and not mech.solved[k]:
        raise KeyError(f"{mech.coordinates[k]!r} is not solved by this build of '{mech.name}' "
                       "(pruned with --outputs): rebuild without --outputs to get it")
    return kind, k, order


def _find(mech, name):
    if not isinstance(name, str):
        raise TypeError(f"index with a coordinate or output name, got {name!r}")
    index = mech.state.index
    if name in index:
        return "q", index[name], 0
    for order in (2, 1):            # "dd" before "d": X4dd is not the d of "X4d"
        suffix = SUFFIXES[order]
        if name.endswith(suffix) and name[: -len(suffix)] in index:
            return "q", index[name[: -len(suffix)]], order
    outs = mech.outputs
    if name in outs:
        return "out", outs.index(name), 0
    for order in (2, 1):
        suffix = SUFFIXES[order]
        if name.endswith(suffix) and name[: -len(suffix)] in outs:
            return "out", outs.index(name[: -len(suffix)]), order
    known = ", ".join(mech.coordinates + mech.outputs)
    raise KeyError(f"{name!r} is neither a coordinate nor an output of '{mech.name}' "
                   f"(known: {known}; add d or dd for derivatives)")


def solved_names(mech) -> list:
    """The coordinates this build solves, in order."""
    return [c for c, ok in zip(mech.coordinates, mech.solved) if ok]


def column_names(mech, have, coordinates=None) -> list:
    """The coordinates (and their derivatives) and outputs a table at level ``have``
    provides, in the order of a sweep's columns."""
    coords = solved_names(mech) if coordinates is None else list(coordinates)
    names = list(coords)
    for order in range(1, have + 1):
        names += [c + SUFFIXES[order] for c in coords]
    for k, o in enumerate(mech.outputs):
        names += [o + SUFFIXES[d] for d in range(len(SUFFIXES))
                  if mech.output_orders[k] + d <= have]
    return names


def symbolic_side(mech, what="a symbolic quantity"):
    """The evaluator that ``mechgen.compile`` attaches (``mech.symbolic``), or a clear
    error without one."""
    if mech.symbolic is None:
        raise ModelError(
            f"{what} needs the symbolic model: build the mechanism with "
            "mechgen.compile(model) rather than mechgen.load(path)"
            + (" (setting mech.model alone does not attach it; mechgen.bridge.attach(mech, "
               "model) does)" if mech.model is not None else ""))
    return mech.symbolic


class Quantity:
    """What a name or expression means on a mechanism: its values on a sweep or a
    solution, the level each derivative needs, and how to take one more derivative."""

    def __init__(self, mech, what):
        self.mech = mech
        self.what = what
        if isinstance(what, str):
            kind, k, order = lookup(mech, what)
            self.kind, self.k = kind, k
            base = mech.coordinates[k] if kind == "q" else mech.outputs[k]
            self.base = base
            own = 0 if kind == "q" else mech.output_orders[k]
            self.level = own + order          # solve level the value needs
            self.order = order                # how many d's the name carries
            self.label = what
        else:
            self.kind, self.k = "expr", None
            self.expr = what
            self.level = symbolic_side(mech).level(mech, what)
            self.order = 0
            self.label = _short(what)

    def derivative(self):
        """The quantity's time derivative, or None when it needs a third derivative."""
        if self.level >= LEVEL["acceleration"]:
            return None
        if self.kind == "expr":
            return Quantity(self.mech, symbolic_side(self.mech).derivative(self.expr))
        name = self.base + SUFFIXES[self.order + 1]
        return Quantity(self.mech, name)

    def needs(self, have):
        """Raise KeyError unless a sweep at level ``have`` yields this quantity."""
        if self.level > have:
            raise KeyError(level_needed(self.label, self.level, have, "sweep"))

    def on_sweep(self, sw) -> np.ndarray:
        if self.kind == "expr":
            values = np.asarray(self.mech.evaluate(self.expr, sw), dtype=np.float64)
            if values.shape != (len(sw),):
                raise ValueError(f"{self.label} is not a scalar quantity (values of shape "
                                 f"{values.shape} on a sweep of {len(sw)} points); take one "
                                 "component, e.g. location(p)[0]")
            return values
        return sw[self.what]

    def on_solution(self, s) -> float:
        if self.kind == "expr":
            return float(np.asarray(self.mech.evaluate(self.expr, s), dtype=np.float64).ravel()[0])
        return s[self.what]


def _short(expr) -> str:
    text = str(expr)
    return text if len(text) <= 40 else text[:37] + "..."
