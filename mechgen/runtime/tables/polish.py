"""mech.optimize's sum-of-squares objective and its gradient polish
(docs/reference/sensitivities.md).

An objective given as {quantity: targets at the table's n times} is Σ over quantities and
times of (value − target)²: on a design table (the evolution's generations) the values
are ``tab[name]``; the polish (``polish="gradient"``) is Levenberg–Marquardt (scipy's
trust-region reflective least_squares, the bounds respected) on the residuals value −
target of one design's sweep, its Jacobian the exact sensitivities
(``sw.sensitivity(name, p)`` of a sweep with ``sensitivities=``), never finite
differences. Each sweep starts where the tables' designs start (the guess's mode, carried
to the design's parameters); one that cannot be solved at every time, or passes a branch
jump or a singular configuration, is not a value (NaN residuals: the trust region
shrinks).
"""
from __future__ import annotations

import numpy as np

from ...errors import MechgenError
from ...protocol import OK

POLISHES = (True, False, "gradient", "nelder-mead")


class SumOfSquares:
    """The objective {name: targets} (``targets`` arrays of the table's n times): called
    on a design table, one number per design."""

    def __init__(self, mech, objective, n_times):
        if not objective:
            raise ValueError("objective: give at least one {quantity: targets} pair")
        self.names = []
        self.targets = []
        for name, target in objective.items():
            if not isinstance(name, str):
                raise ValueError(f"objective: quantity names must be strings, got {name!r}")
            arr = np.asarray(target, dtype=np.float64).reshape(-1)
            if arr.shape[0] != n_times:
                raise ValueError(f"objective[{name!r}]: {arr.shape[0]} targets for the "
                                 f"table's {n_times} times")
            if not np.all(np.isfinite(arr)):
                raise ValueError(f"objective[{name!r}]: the targets must be finite")
            self.names.append(name)
            self.targets.append(arr)

    def __call__(self, tab) -> np.ndarray:
        total = np.zeros(len(tab))
        for name, target in zip(self.names, self.targets):
            r = np.asarray(tab[name], dtype=np.float64).reshape(len(tab), -1) - target
            total += np.sum(r * r, axis=1)
        return total

    def residuals(self, sw) -> np.ndarray:
        """value − target of every quantity at every time of a sweep, one vector."""
        return np.concatenate([sw[name] - target
                               for name, target in zip(self.names, self.targets)])

    def jacobian(self, sw, params) -> np.ndarray:
        """∂residuals/∂params: (residuals, parameters), from the sweep's sensitivities."""
        return np.column_stack([np.concatenate([sw.sensitivity(name, p) for name in self.names])
                                for p in params])


def polish_choice(objective, polish):
    """The polish to run: None (the default) is "gradient" for a sum of squares, True
    (Nelder-Mead) for a callable; "gradient" needs a sum of squares."""
    if polish is None:
        return "gradient" if isinstance(objective, dict) else True
    if isinstance(polish, str):
        polish = polish.lower()
    if polish not in POLISHES:
        raise ValueError(f"polish must be 'gradient', True (Nelder-Mead) or False, got "
                         f"{polish!r}")
    if polish == "nelder-mead":
        return True
    if polish == "gradient" and not isinstance(objective, dict):
        raise ValueError("polish='gradient' needs the objective as a sum of squares, "
                         "{quantity: targets at the n times}: a function of a design table "
                         "has no derivatives to follow (polish=True polishes it by "
                         "Nelder-Mead)")
    return polish


def gradient_polish(origin, objective, names, x, lows, highs, sweep_args, max_nfev=100):
    """(x, Σr², evaluations, message): Levenberg–Marquardt from ``x`` on the designs of
    ``origin`` (the mechanism whose guess the tables started from), the sweeps made as
    the tables' (``sweep_args``: t0, t1, n, level, times)."""
    from scipy.optimize import least_squares
    args = dict(sweep_args)
    state = {"evaluations": 0, "last": None}
    lo, hi = np.asarray(lows, dtype=np.float64), np.asarray(highs, dtype=np.float64)
    size = len(np.concatenate(objective.targets))

    def evaluate(z):
        last = state["last"]
        if last is not None and np.array_equal(last[0], z):
            return last[1]
        state["evaluations"] += 1
        try:
            mech = origin.with_params(**{n: float(v) for n, v in zip(names, z)})
            sw = mech.sweep(args["t0"], args["t1"], args["n"], level=args["level"],
                            times=args["times"], sensitivities=list(names))
            if not np.all(sw.status == OK):
                raise MechgenError("a branch jump or a singular configuration")
            out = (objective.residuals(sw), objective.jacobian(sw, names))
            if not (np.all(np.isfinite(out[0])) and np.all(np.isfinite(out[1]))):
                out = None
        except MechgenError:
            out = None
        state["last"] = (np.array(z, dtype=np.float64), out)
        return out

    def fun(z):
        out = evaluate(z)
        return np.full(size, np.nan) if out is None else out[0]

    def jac(z):
        out = evaluate(z)
        return np.zeros((size, len(names))) if out is None else out[1]

    x0 = np.clip(np.asarray(x, dtype=np.float64), lo + 1e-12 * (hi - lo), hi - 1e-12 * (hi - lo))
    if evaluate(x0) is None:
        return np.asarray(x, dtype=np.float64), np.inf, state["evaluations"], \
            "polish (gradient): the evolution's best design could not be swept again"
    res = least_squares(fun, x0, jac=jac, bounds=(lo, hi), method="trf", x_scale="jac",
                        ftol=1e-15, xtol=1e-15, gtol=1e-15, max_nfev=max_nfev)
    r = fun(res.x)
    cost = float(r @ r) if np.all(np.isfinite(r)) else np.inf
    return (np.asarray(res.x, dtype=np.float64), cost, state["evaluations"],
            f"polish (gradient): {res.message}")
