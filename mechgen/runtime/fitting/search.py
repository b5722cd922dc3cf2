"""The global stage of mech.fit: designs sampled within the bounds (a scrambled Sobol
sequence, scipy.stats.qmc; the mechanism's own parameters first where they lie within
them), each swept as a design table of listed designs on every assembly mode found at the
table's first time, and scored by fitting the targets to its traced path:

- timing free: one cycle of the drivers; each target's nearest point on the path (the
  polyline through the sampled points) gives its distance and its phase, in any order;
- prescribed timing: through the given times (with the sampled times between them, so
  that the table follows the motion from one to the next); the point at each time.

Only the points a design reached in one piece count: those before its first failure,
branch jump or singular configuration (the table's per-point statuses). The best designs
become the least-squares stage's starts (Candidate): their parameters, the phases and the
configurations at them, the mode's mechanism.
"""
from __future__ import annotations

import warnings

import numpy as np

from ...errors import BranchJumpWarning, MechgenError
from ...protocol import OK
from ..tables.starts import guess_reference

CHUNK = 256         # designs scored at a time (the distance arrays are designs × segments × k)


class Candidate:
    """A start of the least-squares stage: ``x`` (the chosen parameters, Problem.names'
    order), ``times`` (k), ``Q`` (k, coordinates: the configurations there), ``score``
    (the RMS distance the table gave), ``reference`` (a mechanism whose guess is on the
    candidate's mode: its ``with_params`` is a design on that mode), ``mode`` (which of
    the modes found at the table's first time), ``q0`` (its configuration there)."""

    __slots__ = ("x", "times", "Q", "score", "reference", "mode", "q0")

    def __init__(self, x, times, Q, score, reference, mode=0, q0=None):
        self.x, self.times, self.Q, self.score = x, times, Q, score
        self.reference, self.mode, self.q0 = reference, mode, q0


def sample(problem) -> np.ndarray:
    """The designs of the global stage: (samples, chosen parameters), the mechanism's own
    values first where every one lies within the bounds."""
    from scipy.stats import qmc
    count, lo, hi = problem.options["samples"], problem.lows, problem.highs
    m = len(problem.names)
    with warnings.catch_warnings():     # a count that is not a power of two is fine here
        warnings.simplefilter("ignore", UserWarning)
        u = qmc.Sobol(m, scramble=True, seed=problem.options["seed"]).random(count)
    X = lo + u * (hi - lo)
    own = np.array([problem.mech.parameters[n] for n in problem.names])
    if np.all(own >= lo) and np.all(own <= hi):
        X[0] = own
    return X


def table_times(problem) -> np.ndarray:
    """The times each design is swept at: one cycle (timing free), or the given times
    with n sampled times from the first to the last between them (prescribed)."""
    n = problem.options["n"]
    if problem.free:
        return np.linspace(problem.t0, problem.t0 + problem.period, n)
    given = problem.timing
    lo, hi = float(given.min()), float(given.max())
    return np.unique(np.concatenate([given, np.linspace(lo, hi, n) if hi > lo else []]))


def modes(problem, t_first) -> list:
    """The guesses a table starts from: every assembly mode of the mechanism at the
    table's first time (modes="all"), or its own guess alone (None)."""
    if problem.options["modes"] == "guess":
        return [None]
    try:
        found = problem.mech.assemblies(t_first)
    except MechgenError:
        found = []
    return list(found) or [None]


def reached(tab) -> np.ndarray:
    """Per design, how many of its first points it reached in one piece: up to its
    first failure, branch jump or singular configuration."""
    N = len(tab.t)
    bad = tab.INFO[:, :, 0] != OK
    first = np.where(bad.any(axis=1), np.argmax(bad, axis=1), N)
    return np.minimum(first, tab.done.reshape(-1))


def traced(mech, tab, point) -> np.ndarray:
    """The point's path on every design: (designs, times, 2), NaN where not solved."""
    D, N = tab.P.shape[0], len(tab.t)
    out = np.full((D, N, 2), np.nan)
    buf = np.empty((N, len(mech.point_names), 2))
    done = tab.done.reshape(-1)
    for d in range(D):
        k = int(done[d])
        if k:
            mech.module.eval_points(tab.Q[d, :k], tab.t[:k], tab.P[d], buf[:k])
            out[d, :k] = buf[:k, point]
    return out


def segment_distances(paths, targets):
    """Each target's squared distance from each segment of each path and the fraction
    along the segment of the nearest point: two arrays (designs, segments, k)."""
    A = paths[:, :-1, None, :]                          # (D, N-1, 1, 2)
    AB = paths[:, 1:, None, :] - A
    AT = targets[None, None, :, :] - A                  # (D, N-1, k, 2)
    ab2 = np.sum(AB * AB, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        f = np.clip(np.sum(AT * AB, axis=-1) / ab2, 0.0, 1.0)
    f = np.where(ab2 > 0, f, 0.0)
    r = AT - f[..., None] * AB
    return np.sum(r * r, axis=-1), f


def nearest_on_paths(paths, lengths, targets):
    """Each target's nearest point on each design's polyline (the first ``lengths[d]``
    points of paths[d]): (dist² (D, k), segment (D, k), fraction along it (D, k));
    dist² inf where a design has fewer than two points."""
    D, N, _ = paths.shape
    k = targets.shape[0]
    d2 = np.full((D, k), np.inf)
    seg = np.zeros((D, k), dtype=np.int64)
    lam = np.zeros((D, k))
    if N < 2:
        return d2, seg, lam
    valid = np.arange(N - 1)[None, :] < (lengths[:, None] - 1)         # (D, N-1)
    for a in range(0, D, CHUNK):
        b = min(D, a + CHUNK)
        dist, f = segment_distances(paths[a:b], targets)
        dist = np.where(valid[a:b, :, None] & np.isfinite(dist), dist, np.inf)
        j = np.argmin(dist, axis=1)                     # (c, k)
        d2[a:b] = np.take_along_axis(dist, j[:, None, :], axis=1)[:, 0, :]
        seg[a:b] = j
        lam[a:b] = np.take_along_axis(f, j[:, None, :], axis=1)[:, 0, :]
    return d2, seg, lam


def score_free(problem, tab, source, found):
    """Timing free: each design's RMS distance of the targets from its path; the best
    KEEP designs, with the phases and configurations at the nearest points, appended to
    ``found`` (``source``: (reference, mode) of the table)."""
    n_reached = reached(tab)
    paths = traced(problem.mech, tab, problem.point)
    d2, seg, lam = nearest_on_paths(paths, n_reached, problem.targets)
    score = np.sqrt(np.mean(d2, axis=1))
    X = tab.design_params()
    t = tab.t
    for d in _best(score):
        j, f = seg[d], lam[d]
        times = t[j] + f * (t[j + 1] - t[j])
        Q = tab.Q[d, j] + f[:, None] * (tab.Q[d, j + 1] - tab.Q[d, j])
        found.append(Candidate(X[d].copy(), times, Q, float(score[d]), *source,
                               q0=tab.Q[d, 0].copy()))


def score_timed(problem, tab, source, found):
    """Prescribed timing: each design's RMS distance from the targets at the given
    times; the best KEEP, with their configurations there, appended to ``found``."""
    n_reached = reached(tab)
    idx = np.searchsorted(tab.t, problem.timing)
    paths = traced(problem.mech, tab, problem.point)
    r = paths[:, idx] - problem.targets[None]
    score = np.sqrt(np.mean(np.sum(r * r, axis=2), axis=1))
    score[n_reached <= idx.max()] = np.inf
    X = tab.design_params()
    for d in _best(score):
        found.append(Candidate(X[d].copy(), problem.timing.copy(), tab.Q[d, idx].copy(),
                               float(score[d]), *source, q0=tab.Q[d, 0].copy()))


KEEP = 64           # the best designs of each table kept as candidates


def _best(score) -> np.ndarray:
    """The indices of the best KEEP finite scores."""
    good = np.nonzero(np.isfinite(score))[0]
    if good.size > KEEP:
        good = good[np.argpartition(score[good], KEEP)[:KEEP]]
    return good


def table(problem, source, X, ts, found) -> int:
    """One design table of the designs ``X`` from ``source`` = (reference, mode): the
    mechanism whose guess they start from, on that mode; scored into ``found``. Returns
    the designs evaluated."""
    opts = problem.options
    params = {n: X[:, j] for j, n in enumerate(problem.names)}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BranchJumpWarning)
        tab = source[0].design_sweep(float(ts[0]), float(ts[-1]), len(ts), params=params,
                                     times=ts, grid=False, on_fail="ignore",
                                     backend=opts["backend"], workers=opts["workers"])
    (score_free if problem.free else score_timed)(problem, tab, source, found)
    return len(tab)


def around(problem, centre, count, width, rng) -> np.ndarray:
    """``count`` designs about ``centre`` (parameters), normally distributed with σ =
    ``width`` × each bound's span, reflected into the bounds."""
    lo, hi = problem.lows, problem.highs
    span = hi - lo
    X = centre[None, :] + rng.standard_normal((count, centre.shape[0])) * (width * span)
    X = lo + np.abs(np.mod(X - lo + span, 2 * span) - span)       # reflected at the bounds
    return np.clip(X, lo, hi)


class GlobalStage:
    """The global stage, a round at a time: ``first()`` the sampled designs on every
    mode, then each ``zoom()`` samples about the ELITE best distinct designs so far,
    each from its own configuration (its table's designs carried from it), narrower
    each round; ``best(count, tried)`` the best distinct candidates not yet tried;
    ``evaluated`` the designs swept."""

    def __init__(self, problem):
        self.problem = problem
        self.ts = table_times(problem)
        self.found = []
        self.evaluated = 0
        self.width = ZOOM
        self.rng = np.random.default_rng(problem.options["seed"])

    def first(self):
        problem, ts = self.problem, self.ts
        X = sample(problem)
        for mode, guess in enumerate(modes(problem, float(ts[0]))):
            reference = guess_reference(problem.mech, float(ts[0]), guess)
            self.evaluated += table(problem, (reference, mode), X, ts, self.found)

    def zoom(self):
        problem, ts = self.problem, self.ts
        elite = distinct(problem, self.found, ELITE)
        per = max(1, problem.options["samples"] // (2 * max(1, len(elite))))
        for c in elite:
            reference = c.reference.with_params(**problem.params_of(c.x))
            reference.set_guess(c.q0, t=float(ts[0]))
            X = around(problem, c.x, per, self.width, self.rng)
            self.evaluated += table(problem, (reference, c.mode), X, ts, self.found)
        self.width *= 0.7

    def best(self, count, tried=()) -> list:
        return distinct(self.problem, [c for c in self.found if c not in tried], count)


def distinct(problem, found, count) -> list:
    """The best ``count`` candidates of ``found``, best first, each on another mode or
    at least APART (a fraction of the bounds' spans, the largest parameter's) from those
    before it: designs in one basin of the least-squares stage count once."""
    found.sort(key=lambda c: c.score)
    span = problem.highs - problem.lows
    picked = []
    for c in found:
        if len(picked) == count:
            break
        u = c.x / span
        if all(p.mode != c.mode or np.max(np.abs(p.x / span - u)) > APART for p in picked):
            picked.append(c)
    return picked


APART = 0.15        # candidates nearer than this (a fraction of each span) count as one
ELITE = 16          # the designs each round of the global stage samples about
ZOOM = 0.08         # its first round's σ, a fraction of each bound's span (halved a round)
