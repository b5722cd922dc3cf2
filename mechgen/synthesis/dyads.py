"""``synthesis.dyads``: the dyads that guide a body through 3, 4 or 5 poses."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from .burmester import five_poses
from .curves import fixed_for, four_poses, moving_for, three_poses
from .poses import as_poses, circle_residual, local, place, positions
from .sliders import slider_dyads


@dataclass(frozen=True)
class Dyad:
    """A dyad: ``fixed`` (x, y) in the ground frame, ``moving`` (x, y) in the poses' frame
    (the moving body's own), ``kind`` "RR", "RP" or "PR" (the ground's joint first).
    For "PR", ``fixed`` is a point of the guide on the ground and ``direction`` its unit
    direction (ground frame); for "RP", ``moving`` is a point of the body's line and
    ``direction`` its unit direction in the body's frame. ``residual``: the largest
    departure over the poses from the dyad's condition (equal distances for RR)."""
    fixed: tuple
    moving: tuple
    kind: str = "RR"
    direction: Optional[tuple] = None
    residual: float = 0.0

    def radius(self, poses) -> float:
        """The crank's length (RR): the distance from the fixed pivot to the moving
        pivot's position in the first pose."""
        return float(np.linalg.norm(place(np.asarray(poses, float)[0], self.moving)
                                    - np.asarray(self.fixed)))


def _rr(poses, G, u) -> Dyad:
    G, u = np.asarray(G, float), np.asarray(u, float)
    return Dyad(tuple(float(v) for v in G), tuple(float(v) for v in u), "RR",
                residual=circle_residual(poses, G, u))


def dyads(poses, samples=40, *, fixed=None, moving=None, sliders=None):
    """Every RR dyad through the poses (a list of :class:`Dyad`).

    3 poses: a two-parameter family, ``samples`` of it (moving pivots spread over the body
    about its origin); 4 poses: ``samples`` points of the centre-point curve near the
    poses; 5 poses: every real Burmester pair, exactly (a quartic, see burmester.py), each
    meeting the equal-distance equations to 1e-10 of the poses' spread.
    ``fixed=[(x, y), ...]`` (ground frame) or ``moving=[(x, y), ...]`` (the body's frame)
    choose the pivots instead of sampling: each must lie on the centre-point (circle-point)
    curve for four poses, and give one solution for five. ``sliders``: True adds the
    slider dyads (PR: a body point whose positions are collinear; RP: a body line through
    one fixed point); None (default) adds them only for five poses, where the poses ask for
    one exactly (a Burmester point at infinity); False never."""
    poses = as_poses(poses, 3, 5)
    n = len(poses)
    try:
        samples = int(samples)
    except (TypeError, ValueError):
        raise ValueError(f"samples: expected a whole number, got {samples!r}") from None
    if samples < 1:
        raise ValueError(f"samples: expected at least 1, got {samples}")
    out = []
    if fixed is not None or moving is not None:
        for G in _points(fixed, "fixed"):
            u = moving_for(poses, G)
            if u is None:
                raise ValueError(f"fixed={tuple(G)}: no moving pivot guides the body through "
                                 f"these {n} poses about it (not on the centre-point curve)")
            out.append(_rr(poses, G, u))
        for u in _points(moving, "moving"):
            G = fixed_for(poses, u)
            if G is None:
                raise ValueError(f"moving={tuple(u)}: its {n} positions are not on one circle "
                                 f"(not on the circle-point curve, or collinear: a slider)")
            out.append(_rr(poses, G, u))
    elif n == 3:
        out = [_rr(poses, G, u) for G, u in three_poses(poses, samples)]
    elif n == 4:
        out = [_rr(poses, G, u) for G, u in four_poses(poses, samples)]
    else:
        out = [_rr(poses, G, u) for G, u in five_poses(poses)]
    if sliders or (sliders is None and n == 5):
        for kind, f, m, d in slider_dyads(poses, max(4, samples // 4)):
            out.append(Dyad(tuple(float(v) for v in f), tuple(float(v) for v in m), kind,
                            tuple(float(v) for v in d), _off_line(poses, kind, f, m, d)))
    return out



def _off_line(poses, kind, fixed, moving, direction) -> float:
    """The largest distance of a slider's pin from its line over the poses: the body
    point's positions from the ground's guide (PR), the fixed pivot from the body's line,
    in the body's frame (RP)."""
    if kind == "PR":
        pts, origin = positions(poses, moving), np.asarray(fixed, float)
    else:
        pts = np.array([local(p, fixed) for p in poses])
        origin = np.asarray(moving, float)
    rel = pts - origin
    return float(np.max(np.abs(rel[:, 0] * direction[1] - rel[:, 1] * direction[0])))


def _points(values, name):
    if values is None:
        return []
    arr = np.asarray(values, dtype=float)
    if arr.shape == (2,):
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != 2 or not np.all(np.isfinite(arr)):
        raise ValueError(f"{name}: expected finite (x, y) points, got {values!r}")
    return list(arr)
