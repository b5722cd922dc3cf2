"""A model that moves under its forces alone: its free coordinates held at the guess.

docs/reference/simulation.md: "A model with no driver is simulated from its guess." The kinematics
needs as many equations as coordinates (a square Φ_q: the block-sorted solvers, the sweeps, the
multiplier solve), so a model with masses or loads and fewer equations than coordinates gets one
``hold`` row per missing equation, q_j − (its guess) = 0, on coordinates that the equations leave
free at the guess. They are drivers that stand still: ``mech.solve`` gives the guess's configuration
and, at level "static", the effort that holds it there; ``mech.simulate`` releases them all unless
``free=`` names others. A model without mass or loads still has to name its drivers (the build
refuses it, as before).
"""
from __future__ import annotations

import copy

import sympy as sp

from ...errors import ModelError
from ..constraints import Constraint


class Hold(Constraint):
    """``hold(q, value)``: coordinate q stays at value (q − value = 0), a driver that
    stands still (its effort is the generalized force that holds q)."""

    kind = "hold"

    def build(self, coord, value):
        self.exprs = [coord - sp.Float(value)]
        return f"{coord}, {float(value)!r}"

    @property
    def is_driver(self) -> bool:
        return True


def held(model):
    """``model`` itself when it is square or has no masses or loads; else a copy with
    ``hold`` rows on free coordinates (the user's model is left as it was)."""
    from ..symbolic import numeric_jacobian
    if not model.has_dynamics:
        return model
    eq = model.equations()
    m, n = eq.phi.rows, len(eq.q)
    if m >= n:
        return model
    import numpy as np
    guess = model.guess_vector()
    params = list(model.param_defaults.values())
    J = np.zeros((0, n)) if m == 0 else numeric_jacobian(eq, guess, params)
    chosen = _free_columns(J, n - m, [str(c) for c in eq.q])
    if chosen is None:
        return model        # the equations are dependent at the guess: check_square says so
    out = copy.copy(model)
    out.constraints = list(model.constraints)
    out._equations = None
    for j in chosen:
        coord = eq.q[j]
        con = Hold(out, len(out.constraints) + 1, f"hold {coord}", "",
                   getattr(model, "_where", None))
        con.args_text = con.build(coord, guess[j])
        con.points = ()
        out.constraints.append(con)
    return out


def _free_columns(J, k, names):
    """k coordinates whose unit rows complete J's rank, angles first (a body turning about
    a pin is held by its angle), else None when J itself is short of rank."""
    import numpy as np
    rank = np.linalg.matrix_rank(J) if J.shape[0] else 0
    if rank < J.shape[0]:
        return None
    order = sorted(range(len(names)), key=lambda j: (not names[j].startswith("Th"), j))
    rows, chosen = J, []
    for j in order:
        unit = np.zeros((1, J.shape[1]))
        unit[0, j] = 1.0
        trial = np.vstack([rows, unit])
        if np.linalg.matrix_rank(trial) == trial.shape[0]:
            rows = trial
            chosen.append(j)
            if len(chosen) == k:
                return chosen
    raise ModelError("could not choose the coordinates to hold")  # unreachable: J full rank
