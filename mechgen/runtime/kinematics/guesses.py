"""Where a solve or a sweep starts: the guess a user gives (a dict of some coordinates, a
Solution, an array of all of them; None: the mechanism's own guess) checked and made the
coordinate vector, and, after Newton from it, the angles it threw whole turns away turned
back near it."""
from __future__ import annotations

import math

import numpy as np

from ..guards import all_finite, finite
from ..results import Solution

_ANGLES = []


def start_vector(mech, guess) -> np.ndarray:
    """A new coordinate vector from ``guess``: the mechanism's guess with a dict's
    coordinates put in, a Solution's q, or an array of all of them; ValueError naming
    what is wrong (an unknown coordinate, a value that is not a finite number, a shape)."""
    if guess is None:
        return mech.guess.copy()
    if isinstance(guess, Solution):
        return guess.q.copy()
    if isinstance(guess, dict):
        base = mech.guess.copy()
        for name, value in guess.items():
            if name not in mech.state.index:
                raise ValueError(f"guess: {name!r} is not a coordinate of '{mech.name}' "
                                 f"(coordinates: {', '.join(mech.coordinates)})")
            base[mech.state.index[name]] = finite(value, f"guess for {name}")
        return base
    try:
        arr = np.asarray(guess, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"guess must be a dict of coordinates, a Solution or an array of "
                         f"{mech.n} numbers, got {_short(guess)}") from None
    if arr.shape != (mech.n,):
        raise ValueError(f"guess must be a dict of coordinates or an array of shape ({mech.n},), "
                         f"got shape {arr.shape}")
    if not all_finite(arr):
        raise ValueError("guess holds NaN or infinite values")
    return arr.copy()


def guess_at(mech, guess, t) -> np.ndarray:
    """The Newton start at t of ``guess`` (start_vector): a dict that gives some
    coordinates has the others fitted to them first (fit_given), so that the mode the
    given ones point at is the one Newton starts in, not the mode the mechanism's own
    guess (a configuration at another time, perhaps of another mode) fills in around
    them: an offset slider-crank with ``guess={"X4": x}``, x next to the slider's left
    position, came back with the slider on the right, the rod's angle of the model's guess
    deciding the mode."""
    q = start_vector(mech, guess)
    if isinstance(guess, dict) and 0 < len(guess) < mech.n:
        fit_given(mech, q, float(t), {mech.state.index[name] for name in guess})
    return q


def fit_given(mech, q, t, given, iterations=30):
    """Gauss-Newton on the coordinates not in ``given`` (indices) towards Φ(q, t) = 0, the
    given ones held, in place; each step halved until the residual decreases (never a
    worse start than q), the minimum-norm step where Φ_q's columns are dependent. The rows
    are weighted by their largest Jacobian entry at q (row equilibration), so that a row
    whose size grows with the square of the unit of length (‖r1 − r2‖² − d²) does not
    outweigh a revolute's: unweighted, the quick-return in units 1e5 times the seed's had
    its ground pivots moved off to ease its distance row and Newton could not start."""
    free = [j for j in range(mech.n) if j not in given]
    mod, p = mech.module, mech.p
    r = np.empty(mech.m)
    J = np.empty((mech.m, mech.n))
    mod.phi(q, t, p, r)
    mod.phi_q(q, t, p, J)
    top = np.max(np.abs(J), axis=1)
    w = np.where(np.isfinite(top) & (top > 0.0), 1.0 / np.where(top > 0.0, top, 1.0), 1.0)
    size = float(np.linalg.norm(w * r))
    for k in range(iterations):
        if not math.isfinite(size) or np.max(np.abs(r)) <= mech.tol:
            return
        if k:
            mod.phi_q(q, t, p, J)
        step = np.linalg.lstsq(w[:, None] * J[:, free], -w * r, rcond=None)[0]
        if not np.all(np.isfinite(step)):
            return
        scale = 1.0
        while scale >= 1.0 / 1024:
            trial = q.copy()
            trial[free] += scale * step
            mod.phi(trial, t, p, r)
            new = float(np.linalg.norm(w * r))
            if new < size:
                break
            scale /= 2
        else:
            return          # no decrease: q is the nearest the given values let it be
        done = new > size * (1.0 - 1e-6)
        q[:] = trial
        size = new
        if done:
            return


def turned_home(mech, q, start) -> bool:
    """Turn each angle of q (a coordinate Φ is 2π-periodic in) that ended more than a
    turn from its start by whole turns back to the start's, in place: whether any was."""
    turned = False
    d = q - start
    if d.dot(d) <= math.pi * math.pi:
        return False            # the common case (no coordinate moved π): nothing to do
    d = d.tolist()              # (Python floats: no numpy reduction for 9 numbers)
    if not any(abs(x) > math.pi for x in d):
        return False
    for j in _angle_coordinates()(mech):
        k = round(d[j] / (2 * math.pi))
        if k:
            q[j] -= 2 * math.pi * k
            turned = True
    return turned


def _angle_coordinates():
    """mechgen.runtime.analysis.assembly.angle_coordinates, imported when a solve from a
    guess first moved a coordinate half a turn (and kept: an import statement costs a
    solve a microsecond)."""
    if not _ANGLES:
        from ..analysis.assembly import angle_coordinates
        _ANGLES.append(angle_coordinates)
    return _ANGLES[0]


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."
