"""The force functions of a model with mass or loads (mechgen.model.dynamics), emitted as
straight-line code like Φ and Φ_q:

- ``force_terms(q, qd, qdd, t, p, out)``: out (3 × N_COORDS), rows Q_a (applied), Q_c
  (conservative, −∂V/∂q) and I (inertial), so that Φ_qᵀ λ = Q_a + Q_c − I;
- ``energies(q, qd, t, p, out)``: kinetic energy, potential energy and ∂V/∂t;
- ``driver_factors(q, t, p, out)``: per driver row (DRIVER_ROWS), ∂Φ/∂f, f the driven
  quantity: the driver's effort is λ·factor.

A model without mass or loads gets none of them (its module is what it was).
"""
from __future__ import annotations

from ..model.dynamics import dynamics
from .equations_code import TITLES, straight_line
from .ir import Code, Store

TITLES.update(force_terms="Q_a, Q_c and I, their nonzero entries",
              energies="Kinetic energy, potential energy, ∂V/∂t",
              driver_factors="∂Φ/∂f per driver row")


def forces_bodies(plan, eq, model):
    """{key: (body, helpers)} of the force functions, and the DRIVER_ROWS table; ({}, [])
    for a model without mass or loads."""
    if not model.has_dynamics:
        return {}, []
    dyn = dynamics(model, eq)
    q = list(eq.q)
    st = []
    for r, (vec, title) in enumerate(((dyn.applied, "Q_a"), (dyn.conservative, "Q_c"),
                                      (dyn.inertial, "I"))):
        for j in range(len(q)):
            if vec[j] != 0:
                st.append(Store(f"out[{r}, {j}]", vec[j], f"{title} {q[j]}"))
    bodies = {}
    bodies["force_terms"] = straight_line(plan, eq, st, "force_terms",
                                          "q, qd, qdd, t, p, out", with_qd=True,
                                          with_qdd=True) if st else ([Code("pass")], [])
    energy = [Store("out[0]", dyn.kinetic, "kinetic"), Store("out[1]", dyn.potential, "potential"),
              Store("out[2]", dyn.potential_t, "∂V/∂t")]
    bodies["energies"] = straight_line(plan, eq, energy, "energies", "q, qd, t, p, out",
                                       with_qd=True)
    factors = [Store(f"out[{k}]", f, eq.labels[i]) for k, (i, f) in enumerate(dyn.drivers)]
    bodies["driver_factors"] = straight_line(plan, eq, factors, "driver_factors") \
        if factors else ([Code("pass")], [])
    return bodies, [i for i, _ in dyn.drivers]


def force_blocks(plan, eq):
    """Φ_q's blocks in the solving order, flattened for the module's multipliers_sorted:
    (starts, rows, columns), block b holding rows[starts[b]:starts[b + 1]] and as many
    coordinate columns; None where the multipliers cannot go block by block (an unsorted
    or pruned build, more equations than coordinates)."""
    if not plan.sorted or not all(plan.solved) or eq.phi.rows != len(eq.q):
        return None
    starts, rows, cols = [0], [], []
    for b in plan.blocks:
        if len(b.rows) != len(b.vars):
            return None
        rows.extend(b.rows)
        cols.extend(b.vars)
        starts.append(len(rows))
    if sorted(rows) != list(range(eq.phi.rows)) or sorted(cols) != list(range(len(eq.q))):
        return None
    return dict(starts=starts, rows=rows, cols=cols)
