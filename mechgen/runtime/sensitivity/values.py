"""The derivative of a named quantity with respect to a parameter, on a solution or a
sweep that carries sensitivities: a coordinate and its rates (read off Dq, Dq̇, Dq̈), a
declared output and its rates (the sensitivity module's outputs_p), a symbolic quantity
(Mech's output functions: the symbolic side differentiates it), a driver effort (the
force solution's own sensitivities)."""
from __future__ import annotations

import numpy as np

from ..quantity import Quantity, symbolic_side
from .companion import companion

_OUTPUT_FUNCTIONS = ("outputs_p", "outputs_d_p", "outputs_dd_p")


def column(sens, param) -> int:
    """The index of ``param`` among the columns a result carries."""
    if param not in sens.params:
        raise KeyError(f"{param!r}: this result carries the sensitivities to "
                       f"{', '.join(sens.params)} (ask for it with sensitivities=[...])")
    return int(sens.columns[sens.params.index(param)])


def sensitivity(result, what, param):
    """∂what/∂param on ``result`` (a Solution: a float; a Sweep: an array over its
    points; a vector quantity gains a last axis)."""
    sens = result.sensitivities
    mech = result.mechanism
    j = column(sens, param)
    forces = result.__dict__.get("force_sensitivity")
    if forces is not None and isinstance(what, str) and forces.knows(what):
        return forces.value(what, param)
    quantity = Quantity(mech, what)
    have = len([d for d in sens.full if d is not None]) - 1
    quantity.needs(have) if hasattr(result, "Q") else _needs_solution(quantity, have)
    if quantity.kind == "q":
        D = sens.full[quantity.order]
        return float(D[quantity.k, j]) if D.ndim == 2 else D[:, quantity.k, j].copy()
    if quantity.kind == "out":
        return _output(mech, result, sens, quantity, j)
    return symbolic_side(mech, "the sensitivity of a symbolic quantity").sensitivity(
        mech, quantity.expr, result, param, sens)


def _needs_solution(quantity, have):
    if quantity.level > have:
        raise KeyError(f"{quantity.label!r} needs a solve at a higher level for its "
                       "sensitivity")


def _output(mech, result, sens, quantity, j):
    comp, _ = companion(mech)
    fn = getattr(comp, _OUTPUT_FUNCTIONS[quantity.order])
    n, npar = mech.n, len(mech.parameter_names)
    sel = np.array([j], dtype=np.int64)
    out = np.empty((len(mech.outputs), npar))
    zero, zeros = np.zeros(n), np.zeros((n, npar))
    p = np.asarray(mech.p, dtype=np.float64)

    def at(q, qd, qdd, t, D):
        fn(q, zero if qd is None else qd, zero if qdd is None else qdd, float(t), p,
           D[0], zeros if D[1] is None else D[1], zeros if D[2] is None else D[2], sel, out)
        return float(out[quantity.k, j])

    if not hasattr(result, "Q"):
        return at(result.q, result.qd, result.qdd, result.t, sens.full)
    values = np.empty(len(result))
    ts = result.solved_t
    for k in range(len(result)):
        D = [None if d is None else d[k] for d in sens.full]
        values[k] = at(result.Q[k], None if result.QD is None else result.QD[k],
                       None if result.QDD is None else result.QDD[k], ts[k], D)
    return values


def point_index(mech, point) -> int:
    """The index in mech.point_names of ``point``: an index, a label (``"coupler[3]"``)
    or a model Point (its label)."""
    if isinstance(point, (int, np.integer)) and not isinstance(point, bool):
        if not 0 <= int(point) < len(mech.point_names):
            raise IndexError(f"point index {point} out of range (0..{len(mech.point_names) - 1})")
        return int(point)
    label = point if isinstance(point, str) else getattr(point, "label", None)
    if label not in mech.point_names:
        raise KeyError(f"{label or point!r} is not a point of '{mech.name}' "
                       f"(its points: {', '.join(mech.point_names)})")
    return mech.point_names.index(label)


def point_sensitivity(result, point) -> np.ndarray:
    """∂(x, y)/∂p of a point on a result carrying sensitivities: (2, parameters asked)
    on a Solution, (points, 2, parameters asked) on a Sweep, columns in
    ``result.sensitivity_params`` order."""
    sens = result.sensitivities
    mech = result.mechanism
    k = point_index(mech, point)
    comp, _ = companion(mech)
    npts, npar = len(mech.point_names), len(mech.parameter_names)
    out = np.empty((2 * npts, npar))
    p = np.asarray(mech.p, dtype=np.float64)
    cols = sens.columns
    if not hasattr(result, "Q"):
        comp.points_p(result.q, float(result.t), p, sens.full[0], cols, out)
        return out[2 * k:2 * k + 2][:, cols].copy()
    values = np.empty((len(result), 2, len(cols)))
    ts = result.solved_t
    for i in range(len(result)):
        comp.points_p(result.Q[i], float(ts[i]), p, sens.full[0][i], cols, out)
        values[i] = out[2 * k:2 * k + 2][:, cols]
    return values


def point_velocity(mech, q, qd, t, point) -> np.ndarray:
    """d(x, y)/dT of a point at (q, q̇, t): the sensitivity module's points_d."""
    comp, _ = companion(mech)
    out = np.empty((len(mech.point_names), 2))
    comp.points_d(np.asarray(q, dtype=np.float64), np.asarray(qd, dtype=np.float64), float(t),
                  np.asarray(mech.p, dtype=np.float64), out)
    return out[point_index(mech, point)].copy()
