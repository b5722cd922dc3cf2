"""The bodies' masses and inertias at parameter values: a negative one given at run time
(``with_params``, ``load(..., params=)``, a design table's fixed values) is refused, as
the build refuses it in the model's defaults (a ModelError naming the body); so is a load
constant the model refuses (forces.limits: a negative stiffness, free length, damping or
g, gravity's direction of zero length)."""
from __future__ import annotations

import numpy as np

from ..kinematics.entry import module_attr
from .limits import refused_constant
from .lookup import tables


def negative_mass(mech, p):
    """A sentence naming the first body whose mass, or polar inertia about its centroid,
    is negative at parameters ``p``, else the first load constant refused there
    (limits.refused_constant); None where none is (or the module has no masses).

    Read from the module's mass matrix: a body's block over its (X, Y, Th) is
    m [[1, 0, −c_y], [0, 1, c_x], [−c_y, c_x, |c|²]] + J e₃e₃ᵀ (c its centroid, turned), so
    m is its first entry and J its Th entry less (its X–Th and Y–Th entries)² / m."""
    mass_matrix = module_attr(mech.module, "mass_matrix")
    if mass_matrix is None:
        return None
    M = np.zeros((mech.n, mech.n))
    mass_matrix(np.array(mech.module.GUESS, dtype=np.float64), 0.0, p, M)
    for name, idx in tables(mech).bodies.items():
        if idx is None:
            continue
        x, y, th = idx
        m = float(M[x, x])
        turning = float(M[th, th])
        inertia = turning - (M[x, th] ** 2 + M[y, th] ** 2) / m if m > 0.0 else turning
        if m < 0.0:
            return f"body '{name}' has a negative mass ({m:g})"
        if inertia < -1e-12 * abs(turning):
            return f"body '{name}' has a negative inertia ({inertia:g})"
    return refused_constant(mech.module, p)
