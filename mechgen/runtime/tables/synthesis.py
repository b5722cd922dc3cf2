"""Dimensional synthesis on top of design tables (``mech.optimize``): scipy's
differential evolution, vectorised, each generation one design table of listed designs
on the chosen backend, then a polish from the best design: polish=True, Nelder-Mead, each
step a one-design table in this process (the same numbers as every CPU backend gives);
polish="gradient", Levenberg–Marquardt on the exact sensitivities (mechgen.runtime.tables.
polish).

The objective takes a DesignTable (``tab.extremes``, ``tab.reduced``, ``tab["X4"]``,
``tab.design_params()``) and returns one number per design; or it is a sum of squares,
{quantity: targets at the table's n times}, Σ (value − target)², whose polish defaults to
"gradient" (a callable's to Nelder-Mead). A design that cannot be
solved at every time of the table, or that was solved through a branch jump or a singular
configuration (status JUMP or THROUGH_SINGULAR: after it, it may move in another assembly
mode, as a real one may jam or turn over there), is rejected: the objective never sees it
(it gets the table of the others, DesignTable.take), and it scores +inf (as does a
non-finite score), so it can never be chosen.
"""
from __future__ import annotations

import time

import numpy as np

from ...errors import MechgenError
from ...protocol import JUMP, THROUGH_SINGULAR
from ..guards import sweep_times
from .polish import SumOfSquares, gradient_polish, polish_choice
from .starts import guess_reference


class OptimizeResult:
    """What ``mech.optimize`` found: ``params`` (the best design's varied parameters),
    ``x`` (the same, in the order of ``names``), ``fun`` (its objective), ``mechanism``
    (the mechanism with those parameters), ``evaluated`` (designs evaluated, rejected ones
    included), ``rejected`` (designs that could not be solved at every time, or passed a
    singular configuration),
    ``generations`` (of the evolution), ``seconds`` (wall time), ``success`` and
    ``message`` (scipy's, of the evolution and the polish)."""

    def __init__(self, **fields):
        self.__dict__.update(fields)

    def __repr__(self):
        values = ", ".join(f"{k}={v:.12g}" for k, v in self.params.items())
        return (f"<OptimizeResult {values}: objective {self.fun:.6g}, {self.evaluated} designs "
                f"evaluated ({self.rejected} rejected) in {self.seconds:.2f} s>")


class _Stop(Exception):
    """Carries an error of a generation's table or of the objective through scipy's
    differential_evolution, which replaces a TypeError or ValueError of the function it
    calls by a RuntimeError of its own ("The map-like callable must be of the form ...")."""


class _Scorer:
    """The objective over a batch of designs: one design table, rejected designs +inf."""

    def __init__(self, mech, objective, names, sweep_args):
        self.mech, self.objective, self.names = mech, objective, names
        self.sweep_args = sweep_args
        self.evaluated = 0
        self.rejected = 0
        self.error = None

    def __call__(self, X, sweep_args=None):
        try:
            return self._score(X, sweep_args)
        except (TypeError, ValueError) as exc:
            self.error = exc
            raise _Stop() from exc

    def _score(self, X, sweep_args=None):
        X = np.atleast_2d(np.asarray(X, dtype=np.float64))     # (designs, parameters)
        params = {n: X[:, j] for j, n in enumerate(self.names)}
        tab = self.mech.design_sweep(params=params, grid=False, on_fail="ignore",
                                     **(sweep_args or self.sweep_args))
        self.evaluated += len(tab)
        ok = tab.ok.reshape(-1) & ~np.isin(tab.status.reshape(-1), (JUMP, THROUGH_SINGULAR))
        self.rejected += int(np.count_nonzero(~ok))
        score = np.full(len(tab), np.inf)
        if ok.any():
            good = tab if ok.all() else tab.take(ok)        # the objective sees only these
            values = np.asarray(self.objective(good), dtype=np.float64).reshape(-1)
            if values.shape != (len(good),):
                raise MechgenError(f"the objective must return one number per design "
                                   f"({len(good)}), got shape {values.shape}")
            score[ok] = values
        score[~np.isfinite(score)] = np.inf
        return score


def optimize(mech, objective, bounds, t0, t1, n, backend="cpu", level="position",
             workers=None, client=None, guess=None, times=None, popsize=15, maxiter=100,
             tol=0.01, seed=None, polish=None, polish_tol=1e-15, polish_nfev=100,
             **evolution):
    """See Mechanism.optimize. ``polish``: None (the default: "gradient" for a sum of
    squares, True for a callable), "gradient", True (Nelder-Mead) or False;
    ``polish_nfev``: the gradient polish's evaluations at most."""
    from scipy.optimize import differential_evolution, minimize
    polish = polish_choice(objective, polish)
    squares = None
    if isinstance(objective, dict):
        squares = objective = SumOfSquares(mech, objective, len(sweep_times(t0, t1, n, times)))
    elif not callable(objective):
        raise TypeError("objective must be a function of a design table or {quantity: "
                        f"targets}}, got {type(objective).__name__}")
    if not isinstance(bounds, dict) or not bounds:
        raise ValueError("bounds must be a dict of parameter names to (low, high)")
    names = list(bounds)
    lows, highs = [], []
    for name in names:
        if name not in mech.parameter_names:
            raise ValueError(f"model '{mech.name}' has no parameter {name!r} "
                             f"(parameters: {', '.join(mech.parameter_names)})")
        try:
            lo, hi = (float(v) for v in bounds[name])
        except (TypeError, ValueError):
            raise ValueError(f"bounds[{name!r}] must be (low, high), got {bounds[name]!r}") from None
        if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
            raise ValueError(f"bounds[{name!r}] = ({lo}, {hi}): give finite low < high")
        lows.append(lo)
        highs.append(hi)
    score = _Scorer(mech, objective, names,
                    dict(t0=t0, t1=t1, n=n, level=level, guess=guess, times=times,
                         backend=backend, workers=workers, client=client))
    start = time.perf_counter()
    try:
        de = differential_evolution(lambda X: score(X.T), list(zip(lows, highs)),
                                    popsize=popsize, maxiter=maxiter, tol=tol, seed=seed,
                                    polish=False, vectorized=True, updating="deferred",
                                    **evolution)
    except _Stop:
        raise score.error from None     # the table's or the objective's own error
    x, fun, message = np.asarray(de.x, dtype=np.float64), float(de.fun), [de.message]
    if not np.isfinite(fun):
        raise MechgenError(f"optimize: no design within the bounds could be solved at every "
                           f"time ({score.evaluated} designs evaluated)")
    origin = guess_reference(mech, sweep_times(t0, t1, n, times)[0], guess)
    if polish == "gradient":
        sweep_args = dict(t0=t0, t1=t1, n=n, level=level, times=times)
        px, pfun, count, note = gradient_polish(origin, squares, names, x, lows, highs,
                                                sweep_args, polish_nfev)
        score.evaluated += count
        if pfun <= fun:
            x, fun = px, pfun
        message.append(note)
    elif polish:
        lo, hi = np.array(lows), np.array(highs)

        # one design a step: in this process (backend "cpu", one thread), whatever the
        # backend of the generations (a cluster's or a GPU's round trip buys nothing here)
        single = dict(score.sweep_args, backend="cpu", workers=1, client=None)

        def one(v):
            if np.any(v < lo) or np.any(v > hi):
                return np.inf
            try:
                return float(score(v[None, :], single)[0])
            except _Stop:
                raise score.error from None
        res = minimize(one, x, method="Nelder-Mead",
                       options={"xatol": 1e-13 * max(1.0, float(np.max(np.abs(x)))),
                                "fatol": polish_tol, "maxiter": 4000})
        if res.fun <= fun:
            x, fun = np.asarray(res.x, dtype=np.float64), float(res.fun)
        message.append(f"polish (Nelder-Mead): {res.message}")
    params = {n: float(v) for n, v in zip(names, x)}
    # the best design on the mode its tables gave it: from the guess they started from
    return OptimizeResult(params=params, x=x, names=tuple(names), fun=fun,
                          mechanism=origin.with_params(**params), evaluated=score.evaluated,
                          rejected=score.rejected, generations=int(de.nit),
                          seconds=time.perf_counter() - start, success=bool(de.success),
                          message="; ".join(str(m) for m in message), backend=backend)
