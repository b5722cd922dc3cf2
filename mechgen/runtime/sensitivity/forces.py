"""The derivatives of the multipliers and of the drivers' efforts with respect to the
parameters, on a force solution or sweep (level "static" or "dynamic") that carries the
kinematic sensitivities: Φ_qᵀ Dλ = (F − Φ_qᵀ λ)_q Dq + (…)_q̇ Dq̇ + (…)_q̈ Dq̈ + (…)_p with
F = Q_a + Q_c − I, the right side emitted in the sensitivity module (force_rhs_p), solved
on Φ_qᵀ; an effort λ·factor then moves by Dλ·factor + λ·Dfactor (driver_factors_p).
A static result holds q̇ = q̈ = 0 whatever the parameters."""
from __future__ import annotations

import numpy as np

from ...errors import MechgenError
from ..forces.lookup import tables
from ..forces.solution import effort
from .companion import companion


class ForceSensitivities:
    """``dlam`` (rows × all parameters, or points × rows × parameters) and the driver
    factors' derivatives ``dfactors``; answers the efforts' derivatives by name."""

    def __init__(self, result, dlam, dfactors, factors, lam):
        self.result, self.dlam, self.dfactors = result, dlam, dfactors
        self.factors, self.lam = factors, lam

    def knows(self, name) -> bool:
        """Whether ``name`` names a driver of the model (its effort has a derivative)."""
        mech = self.result.mechanism
        entry = tables(mech).find(name, mech)
        return entry is not None and bool(entry[2])

    def value(self, name, param):
        """∂(name's effort)/∂param."""
        sens = self.result.sensitivities
        j = int(sens.columns[sens.params.index(param)])
        mech = self.result.mechanism
        out = effort(mech, name, self.dlam[..., j], self.factors) + \
            effort(mech, name, self.lam, self.dfactors[..., j])
        return float(out) if np.ndim(out) == 0 else out


def attach_forces(mech, result):
    """Give a force Solution or ForceSweep carrying sensitivities its multipliers' and
    efforts' derivatives (``result.force_sensitivity``)."""
    comp, blocks = companion(mech)
    if not getattr(comp, "FORCES", False):
        return result
    if not blocks.square:
        raise MechgenError(f"the efforts' sensitivities of '{mech.name}' need as many "
                           "equations as coordinates (its multipliers are not unique)")
    sens = result.sensitivities
    n, m, npar = mech.n, mech.m, len(mech.parameter_names)
    static = result.force_level == "static"
    sweep = "Q" in result.__dict__
    Q = result.Q if sweep else result.q[None]
    t = result.solved_t if sweep else np.array([result.t])
    lam = result.LAM if sweep else result.lam[None]
    QD, QDD = (result.QD, result.QDD) if sweep else (result.qd, result.qdd)
    full = [None if D is None else (D if sweep else D[None]) for D in sens.full]
    N = Q.shape[0]
    zeros, zero = np.zeros((n, npar)), np.zeros(n)
    nd = len(tables(mech).driver_rows)
    dlam = np.full((N, m, npar), np.nan)
    dfac = np.full((N, nd, npar), np.nan)
    fac = np.empty((N, nd))
    rhs, J, fp = np.empty((n, npar)), np.empty((m, n)), np.empty((nd, npar))
    p = np.asarray(mech.p, dtype=np.float64)
    cols = sens.columns
    for k in range(N):
        if not np.all(np.isfinite(full[0][k][:, cols])) or not np.all(np.isfinite(lam[k])):
            continue
        qd = zero if static or QD is None else (QD[k] if sweep else QD)
        qdd = zero if static or QDD is None else (QDD[k] if sweep else QDD)
        dqd = zeros if static or full[1] is None else full[1][k]
        dqdd = zeros if static or full[2] is None else full[2][k]
        comp.force_rhs_p(Q[k], qd, qdd, float(t[k]), p, np.ascontiguousarray(lam[k]),
                         np.ascontiguousarray(full[0][k]), np.ascontiguousarray(dqd),
                         np.ascontiguousarray(dqdd), cols, rhs)
        comp.phi_q(Q[k], float(t[k]), p, J)
        dlam[k][:, cols] = np.linalg.solve(J.T, rhs[:, cols])
        if nd:
            comp.driver_factors_p(Q[k], float(t[k]), p, np.ascontiguousarray(full[0][k]),
                                  cols, fp)
            dfac[k][:, cols] = fp[:, cols]
            mech.module.driver_factors(Q[k], float(t[k]), p, fac[k])
    if not sweep:
        dlam, dfac, fac, lam = dlam[0], dfac[0], fac[0], lam[0]
    result.force_sensitivity = ForceSensitivities(result, dlam, dfac, fac, lam)
    return result
