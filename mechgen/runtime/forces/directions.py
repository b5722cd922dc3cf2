"""Springs and dampers without a direction: where a spring's or damper's two ends meet, its
force (along the line through them) has no direction. Exactly met, the module's force
terms divide by zero (lookup.loads_guarded); met within round-off (ends a few 1e-17 of the
model's size apart, their "direction" that of the round-off), the terms come back finite
and wrong, a number that depends on how the position was reached (a sweep's step). Here
such points are found from the positions alone: the two ends closer than DIRECTION_RTOL
times the model's size at that configuration (its largest point coordinate), and a
solve raises, a sweep or a design table marks them as it marks a lock (NaN multipliers,
``force_singular``). numpy only.

The positions come from the module's ``points`` once per parameter vector (each point's
coordinates in its body's frame), then for every configuration by numpy: a design table
of many designs and times costs a call per design."""
from __future__ import annotations

import numpy as np

from ..kinematics.entry import module_attr

DIRECTION_RTOL = 1e-9      # ends closer than this times the model's size: no direction
_KINDS = ("spring", "damper")


def load_ends(module) -> tuple:
    """((name, kind, i, j), ...): the springs and dampers of the module, the indices into
    POINTS of their ends (LOADS); () where it has none or does not list them."""
    out = []
    for name, kind, used in module_attr(module, "LOADS", ()) or ():
        if kind in _KINDS and len(used) == 2:
            out.append((name or kind, kind, int(used[0]), int(used[1])))
    return tuple(out)


class _Frames:
    """Each point's body coordinates (indices of X, Y, Th; None on the ground) and its
    coordinates in its body's frame at one parameter vector."""

    def __init__(self, module, q, t, p):
        index = {c: k for k, c in enumerate(module.COORDINATES)}
        bodies = {}
        for name, number, ground in module.BODIES:
            bodies[name] = None if ground else (index[f"X{number}"], index[f"Y{number}"],
                                                index[f"Th{number}"])
        xy = np.zeros((len(module.POINTS), 2))
        module.points(np.asarray(q, dtype=np.float64), float(t), p, xy)
        self.fixed = np.array([bodies.get(body) is None for _, body in module.POINTS])
        self.idx = np.array([bodies.get(body) or (0, 0, 0) for _, body in module.POINTS],
                            dtype=np.int64).reshape(-1, 3)
        local = xy.copy()
        moving = ~self.fixed
        if moving.any():
            X = q[self.idx[moving, 0]]
            Y = q[self.idx[moving, 1]]
            th = q[self.idx[moving, 2]]
            dx, dy = xy[moving, 0] - X, xy[moving, 1] - Y
            c, s = np.cos(th), np.sin(th)
            local[moving, 0] = c * dx + s * dy
            local[moving, 1] = -s * dx + c * dy
        self.local = local

    def positions(self, Q) -> np.ndarray:
        """(N, points, 2): the global positions at the configurations Q (N, coordinates)."""
        N = Q.shape[0]
        out = np.broadcast_to(self.local, (N,) + self.local.shape).copy()
        moving = ~self.fixed
        if moving.any():
            X = Q[:, self.idx[moving, 0]]
            Y = Q[:, self.idx[moving, 1]]
            th = Q[:, self.idx[moving, 2]]
            c, s = np.cos(th), np.sin(th)
            u, v = self.local[moving, 0], self.local[moving, 1]
            out[:, moving, 0] = X + c * u - s * v
            out[:, moving, 1] = Y + s * u + c * v
        return out


def no_direction(module, ts, Q, p) -> np.ndarray:
    """(N,) bool: the configurations Q (N, coordinates) at times ts where a spring or
    damper has its ends within DIRECTION_RTOL of the model's size."""
    Q = np.asarray(Q, dtype=np.float64).reshape(-1, len(module.COORDINATES))
    N = Q.shape[0]
    ends = load_ends(module)
    if not ends or N == 0 or module_attr(module, "points") is None:
        return np.zeros(N, dtype=bool)
    good = np.all(np.isfinite(Q), axis=1)
    out = np.zeros(N, dtype=bool)
    if not good.any():
        return out
    first = int(np.flatnonzero(good)[0])
    xy = _Frames(module, Q[first], np.asarray(ts).reshape(-1)[first], p).positions(Q[good])
    size = np.max(np.abs(xy), axis=(1, 2))
    near = np.zeros(xy.shape[0], dtype=bool)
    for _, _, i, j in ends:
        gap = np.hypot(xy[:, i, 0] - xy[:, j, 0], xy[:, i, 1] - xy[:, j, 1])
        near |= gap <= DIRECTION_RTOL * size
    out[good] = near
    return out


def which(module, q, t, p) -> str:
    """The springs and dampers whose ends meet at one configuration, as a phrase."""
    q = np.asarray(q, dtype=np.float64)
    xy = _Frames(module, q, t, p).positions(q[None])[0]
    size = float(np.max(np.abs(xy)))
    names = []
    for name, kind, i, j in load_ends(module):
        gap = float(np.hypot(*(xy[i] - xy[j])))
        if gap <= DIRECTION_RTOL * size:
            names.append(f"{kind} '{name}' (its ends {gap:.3g} apart, the model's size "
                         f"{size:.3g})")
    return "; ".join(names)


def mark(module, ts, Q, p, LAM, singular=None) -> np.ndarray:
    """NaN into LAM's rows (and True into ``singular``) at the points where a spring or
    damper has no direction; returns those points' mask."""
    bad = no_direction(module, ts, Q, p)
    if bad.any():
        LAM[bad] = np.nan
        if singular is not None:
            singular[bad] = True
    return bad


def singular_error(mech, s):
    """The SingularError of a single solve at a configuration where a spring or damper
    has no direction, or None where every one has."""
    state = mech.state                  # (its fields: a solve's cost, not properties')
    mod = state.tiers.module
    if not load_ends(mod) or not no_direction(mod, [s.t], s.q[None], state.p)[0]:
        return None
    from ...errors import SingularError
    from .lookup import division_error
    said = str(division_error(mech, f"at t={s.t:.10g}", s.t))
    return SingularError(f"{said}. Here: {which(mod, s.q, s.t, mech.p)} meet (within "
                         f"round-off), so it has no direction, and neither has its force",
                         t=s.t)
