"""Path fitting (``mech.fit``, docs/reference/sensitivities.md): the parameters that take a point of
the mechanism through k target points, with the timing free (path generation: the driver's phase at
each target is an unknown, in any order) or prescribed (the k times given).

Three stages, each its own module, a ``Problem`` (``problem``: the checked arguments)
passed to each:

1. ``search``: the global stage on design tables: designs sampled within the bounds,
   each swept over one cycle (or through the given times) on every assembly mode,
   scored by the targets' distances from its traced path;
2. ``least_squares``: Levenberg–Marquardt on the exact derivatives from the best few,
   unknowns the parameters (and the phases), Jacobian columns ∂point/∂p (the
   sensitivity module) and ∂point/∂t (the point's rate), each point solved from the
   previous iterate on the same assembly mode;
3. ``checks``: every design returned passes all k points in one assembly mode with no
   singular configuration or branch jump between them (a sweep between its fitted
   times); where no candidate does, a MechgenError says so.
"""
from __future__ import annotations

import time
import warnings

import numpy as np

from ...errors import BranchJumpWarning, MechgenError
from .checks import check, wrap_times
from .least_squares import refine
from .problem import DEFAULTS, make_problem
from .result import FitResult
from .search import GlobalStage

__all__ = ["fit", "FitResult", "DEFAULTS"]


def fit(mech, point, target, params, timing=None, **options) -> FitResult:
    """Mechanism.fit: ``point`` (a model Point, a label such as "coupler[3]" or an index
    into mech.point_names) through ``target`` ((k, 2) points), choosing the parameters
    ``params`` ({name: (low, high)}) within their bounds; ``timing`` None (phases free)
    or the k times (prescribed timing). The other parameters keep ``mech``'s values.

    Options: ``samples`` (designs of the global stage's first round, a scrambled Sobol
    sequence from ``seed``, on every assembly mode found at its first time, or the guess's
    alone with ``modes="guess"``), ``n`` (the times each design is swept at: one cycle, or
    from the first given time to the last), ``rounds`` (rounds that sample again about the
    best distinct designs so far, narrower each round), ``starts`` (candidates refined by
    least squares after each round, best first; the search stops at the first that passes
    the targets within ``enough``, default 1e-12·(1 + the targets' size)), ``max_nfev``
    (evaluations of one least-squares run), ``period`` and ``t0`` (timing free: one cycle
    of the drivers, found where a body turns once in it, and its start, the guess's time),
    ``check_points`` (the defect check's sweep), ``tol`` (None: the best design that passes
    the defect check is returned, however far from the targets, its RMS error in
    ``.error``; a number: designs further off count as not passing), ``backend`` and
    ``workers`` (the global stage's tables).

    Returns a FitResult (mechgen.runtime.fitting.result). Raises MechgenError where no
    design within the bounds assembles along the targets, or none that least squares
    reaches passes them in one mode without a singular configuration between them (or
    within ``tol``)."""
    with warnings.catch_warnings():     # the designs tried that jump or pass a lock
        warnings.simplefilter("ignore", BranchJumpWarning)     # are rejected, not warned
        return _fit(mech, point, target, params, timing, options)


def _fit(mech, point, target, params, timing, options) -> FitResult:
    started = time.perf_counter()
    problem = make_problem(mech, point, target, params, timing, options)
    stage = GlobalStage(problem)
    stage.first()
    if not stage.found:
        raise MechgenError(
            f"fit: none of the {stage.evaluated} designs sampled within the bounds reaches "
            f"the {'phases' if problem.free else 'given times'} of its motion in one piece "
            f"on any assembly mode of '{mech.name}' (every one fails to assemble, or passes "
            "a singular configuration); widen the bounds or check the targets")
    search = Search(problem)
    for round in range(problem.options["rounds"] + 1):
        if round:
            stage.zoom()
        for candidate in stage.best(problem.options["starts"], search.tried):
            if search.attempt(candidate):
                break
        if search.done:
            break
    tol = problem.options["tol"]
    best = search.best
    if best is None or (tol is not None and best[0].error > tol):
        raise MechgenError(_none_passes(problem, stage.evaluated, search, tol))
    it, fitted, verdict, message = best
    return _result(problem, it, fitted, verdict, message, stage.evaluated + search.evaluations,
                   stage.evaluated, len(search.tried), time.perf_counter() - started)


class Search:
    """The least-squares stage and the defect check over the candidates given it:
    ``best`` (Iterate, fitted mechanism, Verdict, message) of those that pass the defect
    check, ``done`` once one passes the targets within ``enough``."""

    def __init__(self, problem):
        self.problem = problem
        self.tried, self.rejected = [], []
        self.best = None
        self.evaluations = 0
        self.done = False

    def attempt(self, candidate) -> bool:
        """Refine and check ``candidate``; True once the search is done."""
        problem = self.problem
        self.tried.append(candidate)
        it, count, message = refine(problem, candidate)
        self.evaluations += count
        if it is None:
            self.rejected.append(message)
            return False
        fitted = candidate.reference.with_params(**problem.params_of(it.z))
        verdict = check(problem, fitted, it.times, it.Q, it.positions)
        if not verdict.ok:
            self.rejected.append(f"error {it.error:.3g}: {verdict.reason}")
            return False
        if self.best is None or it.error < self.best[0].error:
            self.best = (it, fitted, verdict, message)
        self.done = it.error <= problem.enough
        return self.done


def _none_passes(problem, designs, search, tol) -> str:
    best, tried = search.best, len(search.tried)
    why = "; ".join(dict.fromkeys(search.rejected[:4])) or "none"
    head = (f"fit: no design within the bounds passes the {problem.k} targets of "
            f"'{problem.label}' in one assembly mode without a singular configuration "
            f"between them")
    if best is not None:
        head += (f" within tol={tol:g} (the best reached an RMS error of "
                 f"{best[0].error:.3g})")
    return (f"{head}: {designs} designs searched, the best {tried} refined by least squares "
            f"({why})")


def _result(problem, it, fitted, verdict, message, evaluations, designs, tried, seconds):
    times = verdict.times
    start = verdict.start
    if problem.free:            # the earliest phase in [t0, t0 + period)
        shifted = wrap_times(times, problem.t0, problem.period)
        shift = float(shifted[0] - times[0])
        if shift:
            start = fitted.solve(start.t + shift, guess=start.q)
        times = shifted
    fitted.set_guess(start)         # its solves and sweeps on the mode that passes them
    params = dict(problem.params_of(it.z))
    return FitResult(params=params, error=it.error, times=np.asarray(times, dtype=np.float64),
                     positions=it.positions.copy(), targets=problem.targets.copy(),
                     mechanism=fitted, evaluations=int(evaluations), designs=int(designs),
                     starts=int(tried), seconds=float(seconds),
                     timing="free" if problem.free else "prescribed", message=message)
