"""Statics and inverse dynamics on a solved configuration (levels "static" and "dynamic").

The generated module of a model with mass or loads holds ``force_terms`` (Q_a, Q_c, I),
``energies`` and ``driver_factors`` (mechgen.compiler.forces_code); at every solved point
the multipliers solve Φ_qᵀ λ = Q_a + Q_c − I (q̇ = q̈ = 0 at level "static"). A model
without mass or loads has no such functions: its right side is zero, so are its λ.

A sorted square build solves the multipliers in the module, block by block in the
reverse solving order (multipliers_sorted, through force_rows); where a block's scaled
pivot is below SING_RTOL, or the module has no blocks (a batched numpy solve where its
pivot ratio allows), or Φ_q has more rows than columns, numpy's SVD of Φ_q decides: its
rank on the row-equilibrated Φ_q at SING_RTOL, as the kinematic solves read it. Below
full row rank (redundant constraints) λ is the minimum-norm solution and
``indeterminate`` names the constraints whose multipliers are not unique; where
Φ_qᵀ λ = Q has no solution (a lock or toggle position with a load that would move it)
the solve raises SingularError (a sweep: NaN and ``force_singular`` at those points).

What a constraint applies to the bodies is −Φ_q[rows]ᵀ λ[rows]: its entries on a body's
X, Y, Th are the force and the moment about the body's origin. numpy only, never sympy.

The package, bottom up: ``lookup`` (constraint and body names), ``points`` (λ at many
points from the module alone: sweeps, design tables' chunks on threads and dask workers),
``contact`` (the scalar force a cam, gear, rack or joint transmits, from Φ_q, λ and the
points the module lists), ``contact_loss`` (where a cam follower would need a pulling
contact), ``solution`` (one point), ``sweep`` (a sweep's efforts, reactions, contact
forces, power, shaking, flywheel) and ``table`` (design tables at the force levels,
``reduce=`` on drivers).
"""
from .contact import CONTACT_KINDS, contact_values
from .contact_loss import ContactLoss
from .lookup import FORCE_LEVELS, is_force_level, tables
from .points import solve_points
from .solution import ForceSolution, force_solve
from .sweep import ForceSweep, attach, force_sweep

__all__ = ["CONTACT_KINDS", "ContactLoss", "FORCE_LEVELS", "ForceSolution", "ForceSweep",
           "attach", "contact_values", "force_solve", "force_sweep", "is_force_level",
           "solve_points", "tables"]
