"""Assembly modes: every distinct real configuration of a mechanism at one time (Mech's
SolveMech from several guesses), and which coordinates are angles (equal modulo 2π).

numpy on the generated module's functions; never sympy.
"""
from __future__ import annotations

import math
import weakref

import numpy as np

from ...protocol import OK, POINT_INFO_SIZE
from ...turns import meshed_alike, turn_coefficients
from ..guards import all_finite

# angle_coordinates() of each mechanism, with the module and parameters it was found for
_ANGLES: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()

_PRIMES = (2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61, 67, 71, 73,
           79, 83, 89, 97, 101, 103, 107, 109, 113)


def _halton(k, dim):
    """Point k (k >= 1) of the Halton sequence in [0, 1)^dim: deterministic and even."""
    out = np.empty(dim)
    for d in range(dim):
        base = _PRIMES[d % len(_PRIMES)]
        f, r, i = 1.0, 0.0, k + d // len(_PRIMES) * 7919
        while i > 0:
            f /= base
            r += f * (i % base)
            i //= base
        out[d] = r
    return out


def angle_coordinates(mech) -> tuple:
    """Indices of the coordinates in which Φ is 2π-periodic (angles equal modulo 2π are
    the same configuration). A driven angle (Th2 − ωT) is not: its value is fixed."""
    cached = _ANGLES.get(mech)
    if cached is not None and cached[0] is mech.module and (
            _same_bytes(cached, mech.p) or np.array_equal(cached[1], mech.p)):
        return cached[2]
    n, m = mech.n, mech.m
    base = np.asarray(mech.guess, dtype=np.float64)
    mod, p = mech.module, mech.p
    # Φ at three trial configurations (the same for every coordinate: solved once), then
    # each coordinate turned by 2π there; Python floats for the comparisons (a numpy
    # reduction on a few numbers costs microseconds; the numbers compared are the same)
    trials = []
    for trial in range(3):
        q = base + 0.37 * (trial + 1) * np.cos(np.arange(n) * 1.7 + trial)
        t = 0.1234 + 0.31 * trial
        r0 = np.empty(m)
        mod.phi(q, t, p, r0)
        trials.append((q, t, r0, all_finite(r0)))
    r1 = np.empty(m)
    found = []
    for j in range(n):
        periodic = True
        for q, t, r0, finite0 in trials:
            if not finite0:
                periodic = False
                break
            q2 = q.copy()
            q2[j] += 2 * math.pi
            mod.phi(q2, t, p, r1)
            if not all_finite(r1) or _moved(r1, r0):
                periodic = False
                break
        if periodic:
            found.append(j)
    result = tuple(found)
    p = mech.p.copy()
    _ANGLES[mech] = (mech.module, p, result, _finite_bytes(p))
    return result


def _moved(r1, r0) -> bool:
    """max |r1 − r0| > 1e-9 (1 + max |r0|) (finite residuals; r1 − r0 by numpy, which
    warns where it overflows)."""
    if not r0.shape[0]:         # no equations: numpy's reduction (and its error), as ever
        return np.max(np.abs(r1 - r0)) > 1e-9 * (1.0 + np.max(np.abs(r0)))
    return max(map(abs, (r1 - r0).tolist())) > 1e-9 * (1.0 + max(map(abs, r0.tolist())))


def _finite_bytes(p):
    """The bytes of a 1-D float64 array of finite numbers (equal bytes: equal arrays), else
    None."""
    if p.__class__ is not np.ndarray or p.dtype != np.float64 or p.ndim != 1:
        return None
    return p.tobytes() if all_finite(p) else None


def _same_bytes(cached, p) -> bool:
    """Whether p is the cached parameters by their bytes (a solve's quick look: a numpy
    comparison costs microseconds); False sends the caller to np.array_equal."""
    return cached[3] is not None and p.__class__ is np.ndarray and p.dtype == np.float64 \
        and p.shape == cached[1].shape and p.tobytes() == cached[3]


def body_angles(mech) -> tuple:
    """Indices of the bodies' rotations Th<n> in q: a body's pose is its rotation modulo
    2π even where Φ is not 2π-periodic in it (a gear's rolling row reads Th1 through
    (r1 Th1 + r2 Th2 − c)/(r1 + r2): Th1 + 2π with Th2 − 2π r1/r2 is the same pose)."""
    index = {name: j for j, name in enumerate(mech.coordinates)}
    return tuple(index[f"Th{number}"] for _, number, ground in mech.module.BODIES
                 if not ground and f"Th{number}" in index)


def same_pose(a, b, turns, same):
    """Whether a and b are one pose: equal within ``same``, the coordinates in ``turns``
    modulo 2π."""
    d = np.asarray(b, dtype=np.float64) - a
    for j in turns:
        d[j] = math.remainder(d[j], 2 * math.pi)
    return bool(np.max(np.abs(d), initial=0.0) <= same)


def _wrap(q, angles):
    q = q.copy()
    for j in angles:
        w = math.remainder(q[j], 2 * math.pi)   # in [-π, π]
        q[j] = math.pi if w == -math.pi else w
    return q


def _meshed_like(mech, t, q, ref, turns):
    """Whether solution q meshes its gears as ref does (mechgen.turns): whole turns of the
    angles, the drivers still holding, take ref's mesh counts to q's."""
    mod = mech.module
    counts_of = (lambda v: _mesh_counts(mod, v, t, mech.p))
    C = turn_coefficients(counts_of, ref, turns)
    J = mech.jacobian(ref, t)
    rows, row = [], 0
    for _, _, _, count, driver in mod.CONSTRAINTS:
        if driver:
            rows.extend(range(row, row + count))
        row += count
    D = J[np.ix_(rows, list(turns))] if rows else np.zeros((0, len(turns)))
    return meshed_alike(counts_of(ref), counts_of(q), C, D)


def _mesh_counts(mod, q, t, p):
    out = np.empty(len(mod.MESH_ROWS))
    mod.mesh_turns(q, t, p, out)
    return out


def _in_range(w, unwrapped, turns, same, solved):
    """w with its bodies' rotations that Φ reads unwrapped (a rack's in rack_ratio's rolling
    row r (θ_pinion − θ_rack)) brought into (−π, π] where a solution is there with every
    body turned as in w: a rack turned a whole turn solves Φ with its travel a pinion's
    circumference further on, the same meshing teeth further on (as mechgen.turns says of
    gears), reported as the one whose angles lie in (−π, π]."""
    out = w
    for j in unwrapped:
        r = math.remainder(out[j], 2 * math.pi)
        r = math.pi if r == -math.pi else r
        if r == out[j]:
            continue
        v = out.copy()
        v[j] = r
        if solved(v) and abs(math.remainder(v[j], 2 * math.pi) - r) <= same and \
                all(abs(math.remainder(v[k] - out[k], 2 * math.pi)) <= same for k in turns):
            v[j] = r
            out = v
    return out


def _flip_of(a, b, angles, same):
    """True when b is a turned half a turn in some angle coordinates and equal elsewhere:
    the mirror root of a parallel or point-on-line condition (a slider reversed on its
    guide), not a different assembly of the mechanism."""
    flipped = False
    for j in range(a.shape[0]):
        d = b[j] - a[j]
        if j in angles:
            d = math.remainder(d, 2 * math.pi)
            if abs(abs(d) - math.pi) <= same:
                flipped = True
                continue
        if abs(d) > same:
            return False
    return flipped


def assemblies(mech, t, q_guess, starts, level, tol, method, flips=False):
    """Every distinct real assembly mode at time t (a list of Solution, each solved at
    ``level``): the compiled solver run from the guess q_guess
    and from ``starts`` quasi-random starts (angles over [−π, π), positions within the
    mechanism's size of the guess). Poses equal modulo 2π in the angles (the coordinates
    in which Φ is 2π-periodic, and every body's rotation) count once; the periodic angles
    come back in (−π, π] (a gear's rotation, which Φ reads through its rolling relation,
    as solved); the mode the plain guess reaches comes first.

    A body turned half a turn with every other coordinate unchanged (a slider reversed on
    its guide: u1 × u2 = 0 holds for opposite directions too) is the same mode unless
    ``flips=True``, where it leaves in place every point a constraint places (the module's
    PLACED: a point a constraint takes as such, not an axis' end): a rod half-turned about
    its crank pin, its end on the guide on the other side, is another assembly. The
    representative kept is the one nearest the guess's angles.

    The arguments come checked (Mechanism.assemblies): t a float, starts a count, tol
    and method (an index into protocol.METHODS) as the solvers take them.
    """
    mod = mech.module
    angles = angle_coordinates(mech)
    turns = tuple(sorted(set(angles) | set(body_angles(mech))))   # compared modulo 2π
    others = [j for j in range(mech.n) if j not in angles]
    unwrapped = [j for j in turns if j not in angles]   # a rack's rotation in its rolling row
    pts = mech.points_at(q_guess, t)
    finite = pts[np.isfinite(pts)]
    size = max([1.0] + [abs(float(q_guess[j])) for j in others] +
               ([float(np.max(np.abs(finite)))] if finite.size else []))
    same = 1e-7 * (1.0 + size)
    info = np.zeros(POINT_INFO_SIZE)
    found = []

    def solved(q):
        status = mod.solve_position(q, t, mech.p, tol, mech.xtol, mech.maxit, method, info)
        return status == OK and bool(np.all(np.isfinite(q))) and mech.residual(q, t) <= tol

    def attempt(q):
        if not solved(q):
            return
        w = _in_range(_wrap(q, angles), unwrapped, turns, same, solved)
        if not any(same_pose(other, w, turns, same) for other in found):
            found.append(w)

    attempt(q_guess.copy())
    guess_mode = found[0] if found else None
    for k in range(1, int(starts) + 1):
        u = _halton(k, mech.n)
        q = q_guess.copy()
        for j in angles:
            q[j] = -math.pi + 2 * math.pi * u[j]
        if k % 2 == 0:  # every other start also moves the positions
            for j in others:
                q[j] = q_guess[j] + size * (2 * u[j] - 1)
        attempt(q)
    if guess_mode is not None and hasattr(mod, "mesh_turns"):
        found = [w for w in found if w is guess_mode or
                 _meshed_like(mech, t, w, guess_mode, turns)]
    if not flips and found:
        target = _wrap(q_guess, angles)

        def distance(w):   # to the guess, over the angles
            return sum(abs(math.remainder(w[j] - target[j], 2 * math.pi)) for j in angles)

        placed = list(getattr(mod, "PLACED", ()))

        def moves(a, b):    # a point that a constraint places is elsewhere
            if not placed:
                return False
            d = mech.points_at(a, t)[placed] - mech.points_at(b, t)[placed]
            return bool(np.max(np.abs(d)) > same)

        groups = []
        for w in found:
            for g in groups:
                if _flip_of(g[0], w, angles, same) and not moves(g[0], w):
                    g.append(w)
                    break
            else:
                groups.append([w])
        found = [g[0] if g[0] is guess_mode else min(g, key=distance) for g in groups]
    last = mech.last
    try:
        sols = []
        for q in found:
            s = mech.solve(t, guess=q, level=level, tol=tol)
            s.q[:] = _wrap(s.q, angles)  # Newton's last step may leave the range by an ulp
            if not any(same_pose(o.q, s.q, turns, same) for o in sols):
                sols.append(s)           # (solved again, a mode must still be new)
    finally:
        mech.last = last
    return sols


