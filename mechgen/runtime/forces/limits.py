"""The loads' constants at parameter values: a spring's stiffness or free length, a damper's
coefficient or gravity's g made negative at run time (``with_params``, ``load(...,
params=)``, a design table's fixed values), or gravity's direction made of zero length, is
refused as the model refuses it at its defaults. The module's ``load_constants`` writes
those of them that are functions of the parameters and ``LOAD_CONSTANTS`` names them
(compiler/functions/forces_code.py); a module without them has none to check. numpy only."""
from __future__ import annotations

import numpy as np

from ..kinematics.entry import module_attr


def refused_constant(module, p):
    """A sentence naming the first load constant that parameters ``p`` make negative (a
    direction's length: zero or less), with its expression in the parameters; None where
    every one is allowed (or the module has none)."""
    table = module_attr(module, "LOAD_CONSTANTS", ()) or ()
    load_constants = module_attr(module, "load_constants")
    if not table or load_constants is None:
        return None
    out = np.zeros(len(table))
    load_constants(np.asarray(p, dtype=np.float64), out)
    for (kind, name, what, expr, rule), value in zip(table, out):
        load = f"{kind} '{name}'" if name else kind
        value = float(value)
        if rule == "positive" and not value > 0.0:
            why = (f"is zero: {load} has no direction (no spring or damper is to blame)"
                   if value == 0.0 else "is not a number")
            return f"{load}: {what} ({expr} = {value:g}) {why}"
        if rule != "positive" and not value >= 0.0:
            why = "is negative" if value < 0.0 else "is not a number"
            return f"{load}: {what} {expr} = {value:g} {why}; it must be not negative"
    return None


def refused_design(P, names, index, refused):
    """The sentence for the first design of a table (a row of ``P``, its parameters) that
    ``refused(p)`` (masses.negative_mass: a negative mass or inertia, a refused load
    constant) names, with its index and varied values (``names``, their columns
    ``index``): "design 3 (kk=-100): spring 'spr': the stiffness k kk = -100 is negative";
    None where every design is allowed."""
    for d in range(P.shape[0]):
        why = refused(P[d])
        if why:
            values = ", ".join(f"{n}={float(P[d, index[n]]):g}" for n in names)
            return f"design {d} ({values}): {why}"
    return None
