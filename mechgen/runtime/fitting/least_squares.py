"""The least-squares stage of mech.fit: Levenberg–Marquardt (scipy's trust-region
reflective least_squares, the bounds respected) on the exact derivatives, from a global
stage's candidate.

Unknowns: the chosen parameters, and with timing free the k phases. Residuals: the
point at t_i minus target i, 2k of them. Jacobian: ∂point/∂p from the sensitivity module
(point_sensitivity at a solve with sensitivities) and, for the phases, ∂point/∂t
(point_velocity: the point's rate under the drivers), one column a phase, non-zero only
in its own two rows. Each t_i is solved by Newton from the best iterate so far,
predicted to first order (q + dq/dp·Δp + q̇·Δt), on the assembly mode the candidate
started in: a configuration in another mode (a different pattern of signs of Φ_q's
blocks, mechgen's assembly mode), a failed or singular solve is not a value (NaN
residuals, on which the trust region shrinks).
"""
from __future__ import annotations

import numpy as np

from ...errors import MechgenError
from ..sensitivity.values import point_sensitivity, point_velocity


class Iterate:
    """One evaluated design: ``z`` (the unknowns), ``times``, ``Q``, ``QD`` (k,
    coordinates), ``DQ`` (k, coordinates, chosen parameters), ``positions`` (k, 2),
    ``r`` (2k residuals), ``J`` (2k, unknowns), ``cost`` (Σr²)."""

    __slots__ = ("z", "times", "Q", "QD", "DQ", "positions", "r", "J", "cost")

    def __init__(self, **fields):
        for name, value in fields.items():
            setattr(self, name, value)

    @property
    def error(self) -> float:
        """The RMS distance of the point from the targets."""
        return float(np.sqrt(self.cost / (self.r.shape[0] // 2)))


def mode_of(mech, q, t) -> float:
    """The assembly mode of (q, t): the pattern of the signs of Φ_q's blocks in the
    solving order (the module's jacobian_det), the same along a branch."""
    piv = np.zeros(2)
    mech.module.jacobian_det(q, float(t), mech.p, piv)
    return float(piv[1])


class Evaluator:
    """The residuals and Jacobian of a problem's designs on one assembly mode, each
    evaluation solved from the best iterate so far (``best``); ``evaluations`` counts
    the designs solved."""

    def __init__(self, problem, candidate):
        self.problem = problem
        self.reference = candidate.reference
        self.m = len(problem.names)
        k, n = problem.k, problem.mech.n
        self.best = Iterate(z=self.unknowns(candidate), times=candidate.times.copy(),
                            Q=candidate.Q.copy(), QD=np.zeros((k, n)),
                            DQ=np.zeros((k, n, self.m)), cost=np.inf)
        self.mode = None
        self.evaluations = 0
        self._last = None

    def unknowns(self, candidate) -> np.ndarray:
        """The start vector: the parameters, then (timing free) the phases."""
        x = np.asarray(candidate.x, dtype=np.float64)
        lo, hi = self.problem.lows, self.problem.highs
        x = np.clip(x, lo + 1e-12 * (hi - lo), hi - 1e-12 * (hi - lo))    # strictly inside
        return np.concatenate([x, candidate.times]) if self.problem.free else x

    def bounds(self):
        """(lows, highs) of the unknowns: the parameters' bounds, phases unbounded."""
        lo, hi = self.problem.lows, self.problem.highs
        if not self.problem.free:
            return lo, hi
        inf = np.full(self.problem.k, np.inf)
        return np.concatenate([lo, -inf]), np.concatenate([hi, inf])

    def evaluate(self, z):
        """The Iterate at ``z``, or None where a point cannot be solved on the mode."""
        z = np.asarray(z, dtype=np.float64)
        if self._last is not None and np.array_equal(self._last[0], z):
            return self._last[1]
        it = self._solve(z)
        self._last = (z.copy(), it)
        if it is not None and it.cost < self.best.cost:
            self.best = it
        return it

    def _solve(self, z):
        problem, m, best = self.problem, self.m, self.best
        x = z[:m]
        times = z[m:] if problem.free else problem.timing
        self.evaluations += 1
        try:
            mech = self.reference.with_params(**problem.params_of(x))
        except ValueError:
            return None
        k, n = problem.k, mech.n
        Q, QD = np.empty((k, n)), np.empty((k, n))
        DQ = np.empty((k, n, m))
        positions = np.empty((k, 2))
        J = np.zeros((2 * k, z.shape[0]))
        dx = x - best.z[:m]
        for i in range(k):
            t = float(times[i])
            guess = best.Q[i] + best.DQ[i] @ dx + best.QD[i] * (t - best.times[i])
            try:
                s = mech.solve(t, guess=guess, level="velocity", sensitivities=problem.names)
            except MechgenError:
                return None
            if s.singular or not np.all(np.isfinite(s.qd)):
                return None
            mode = mode_of(mech, s.q, t)
            if self.mode is None:
                self.mode = mode
            elif mode != self.mode:
                return None
            Q[i], QD[i], DQ[i] = s.q, s.qd, s.dq_dp
            positions[i] = mech.points_at(s.q, t)[problem.point]
            J[2 * i:2 * i + 2, :m] = point_sensitivity(s, problem.point)
            if problem.free:
                J[2 * i:2 * i + 2, m + i] = point_velocity(mech, s.q, s.qd, t, problem.point)
        r = (positions - problem.targets).reshape(-1)
        if not (np.all(np.isfinite(r)) and np.all(np.isfinite(J))):
            return None
        return Iterate(z=z.copy(), times=np.array(times, dtype=np.float64), Q=Q, QD=QD,
                       DQ=DQ, positions=positions, r=r, J=J, cost=float(r @ r))


def refine(problem, candidate):
    """(the best Iterate reached from ``candidate``, or None where its start cannot be
    solved on one mode; the designs evaluated; scipy's message).

    With timing free, least squares may stop where a target is held on the wrong part
    of the path (a thin curve passes near it twice): a local minimum in the phases. A
    solution that does not pass the targets is then refined again from other phases on
    the design's path over a cycle: each target's nearest point (assigned again), then,
    for the targets furthest off, each other part of the path that comes near it (a
    local minimum of its distance), while that brings it closer."""
    it, evaluations, message = _refine_once(problem, candidate)
    if it is None or not problem.free:
        return it, evaluations, message
    best = it
    for _ in range(MOVES):
        if best.error <= problem.enough:
            break
        path = Path(problem, candidate.reference, best)
        evaluations += 1
        if not path.ok:
            break
        better = None
        for start in path.starts(best):
            it, count, msg = _refine_once(problem, start)
            evaluations += count
            if it is not None and it.cost < best.cost * (1 - 1e-6):
                better, message = it, msg
                break
        if better is None:
            break
        best = better
    return best, evaluations, message


MOVES = 2           # rounds of phases moved (timing free)
FURTHEST = 2        # targets, furthest off first, whose phases a round tries to move
OTHERS = 1          # other parts of the path tried for each


class Path:
    """An iterate's design swept over one cycle from its earliest phase (on its mode):
    where its point passes near each target, to start least squares again from."""

    def __init__(self, problem, reference, it):
        self.problem, self.reference = problem, reference
        mech = reference.with_params(**problem.params_of(it.z))
        first = int(np.argmin(it.times))
        t0 = float(it.times[first])
        try:
            sw = mech.sweep(t0, t0 + problem.period, 4 * problem.options["n"],
                            guess=it.Q[first].copy())
        except MechgenError as exc:
            sw = getattr(exc, "sweep", None)
        self.ok = sw is not None and len(sw) >= 2
        if not self.ok:
            return
        bad = np.nonzero(sw.status != 0)[0]
        N = int(bad[0]) if bad.size else len(sw)
        self.ok = N >= 3
        from .search import segment_distances
        self.t, self.Q = sw.t[:N], sw.Q[:N]
        d2, f = segment_distances(sw.points()[None, :N, problem.point], problem.targets)
        self.d2, self.f = d2[0], f[0]           # (segments, k)

    def at(self, it, segments):
        """A Candidate at ``it``'s parameters with each target at its nearest point on
        the segment ``segments[i]``."""
        from .search import Candidate
        k = np.arange(self.problem.k)
        f = self.f[segments, k]
        t, Q = self.t, self.Q
        times = t[segments] + f * (t[segments + 1] - t[segments])
        Q = Q[segments] + f[:, None] * (Q[segments + 1] - Q[segments])
        score = float(np.sqrt(np.mean(self.d2[segments, k])))
        return Candidate(it.z[:len(self.problem.names)].copy(), times, Q, score,
                         self.reference)

    def starts(self, it):
        """Candidates to refine again: every target at its nearest point (where that
        moves one), then each target furthest off moved to another part of the path."""
        last = self.d2.shape[0] - 1
        now = np.clip(np.searchsorted(self.t, it.times, side="right") - 1, 0, last)
        nearest = np.argmin(self.d2, axis=0)
        if np.any(np.abs(nearest - now) > 2):
            yield self.at(it, nearest)
        off = np.argsort(-np.sum(it.r.reshape(-1, 2) ** 2, axis=1))[:FURTHEST]
        for i in off:
            d = self.d2[:, i]
            low = np.nonzero((d <= np.roll(d, 1)) & (d <= np.roll(d, -1)))[0]
            low = low[np.argsort(d[low])]
            for j in low[np.abs(low - now[i]) > 2][:OTHERS]:
                segments = now.copy()
                segments[i] = j
                yield self.at(it, segments)


def _refine_once(problem, candidate):
    """refine's least squares from one start."""
    from scipy.optimize import least_squares
    ev = Evaluator(problem, candidate)
    z0 = ev.best.z.copy()
    start = ev.evaluate(z0)
    if start is None:
        return None, ev.evaluations, "the start could not be solved on one assembly mode"
    nan = np.full(2 * problem.k, np.nan)

    def fun(z):
        it = ev.evaluate(z)
        return nan if it is None else it.r

    def jac(z):
        it = ev.evaluate(z)
        return np.zeros((2 * problem.k, z.shape[0])) if it is None else it.J

    if start.cost <= problem.enough ** 2 * problem.k:
        return start, ev.evaluations, "the start passes the targets"
    res = least_squares(fun, z0, jac=jac, bounds=ev.bounds(), method="trf", x_scale="jac",
                        ftol=1e-15, xtol=1e-15, gtol=1e-15,
                        max_nfev=problem.options["max_nfev"])
    return ev.best, ev.evaluations, str(res.message)
