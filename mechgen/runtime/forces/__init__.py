"""Statics and inverse dynamics on a solved configuration (levels "static" and "dynamic").

The generated module of a model with mass or loads holds ``force_terms`` (Q_a, Q_c, I),
``energies`` and ``driver_factors`` (mechgen.compiler.functions.forces_code); at every solved point
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
``reduce=`` on drivers). Each name below is imported from its submodule when first used.
"""
from importlib import import_module

# name -> the submodule defining it, imported on first use (PEP 562): importing
# ``forces.lookup`` (is_force_level, as every solve asks) does not load the rest
_WHERE = {"CONTACT_KINDS": "contact", "contact_values": "contact",
          "ContactLoss": "contact_loss", "FORCE_LEVELS": "lookup",
          "is_force_level": "lookup", "tables": "lookup", "solve_points": "points",
          "ForceSolution": "solution", "force_solve": "solution", "ForceSweep": "sweep",
          "attach": "sweep", "force_sweep": "sweep"}

__all__ = sorted(_WHERE)


def __getattr__(name):
    where = _WHERE.get(name)
    if where is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(import_module(f"{__name__}.{where}"), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_WHERE))
