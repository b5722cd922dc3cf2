"""Poses of a moving body (a coupler frame): (x, y, angle) each, checked, and what they
define: the displacement from one pose to another, its pole, the map of a body point to
its positions, and a frame of reference (centre, scale) in which the algebra is well
conditioned.

A pose (x, y, th) places the body's frame: its origin at (x, y), its x axis at the angle
th (radians, counter-clockwise). A point u of the body (in its own frame) is at
R(th) u + (x, y) in that pose."""
from __future__ import annotations

import math

import numpy as np

SAME_POSE = 1e-9        # two poses closer than this (relative to the poses' spread) repeat


def as_poses(poses, least=3, most=None, what="poses") -> np.ndarray:
    """``poses`` as an (n, 3) float array, or a ValueError naming what is wrong: too few
    (or too many), not three numbers each, not finite, or one pose repeated."""
    try:
        rows = [tuple(p) for p in poses]
    except TypeError:
        raise ValueError(f"{what}: expected a list of (x, y, angle), got {poses!r}") from None
    for k, row in enumerate(rows):
        if len(row) != 3:
            raise ValueError(f"{what}: pose {k + 1} is {row!r}, not (x, y, angle)")
    try:
        arr = np.array(rows, dtype=float).reshape(-1, 3)
    except (TypeError, ValueError):
        raise ValueError(f"{what}: every pose must be three numbers (x, y, angle)") from None
    n = arr.shape[0]
    if n < least:
        raise ValueError(f"{what}: {n} given, at least {least} needed")
    if most is not None and n > most:
        raise ValueError(f"{what}: {n} given, at most {most} can be met exactly")
    bad = np.argwhere(~np.isfinite(arr))
    if bad.size:
        k, c = bad[0]
        raise ValueError(f"{what}: pose {k + 1} has a non-finite {('x', 'y', 'angle')[c]} "
                         f"({arr[k, c]})")
    scale = spread(arr)
    for i in range(n):
        for j in range(i + 1, n):
            dxy = math.hypot(*(arr[j, :2] - arr[i, :2]))
            dth = abs(math.remainder(arr[j, 2] - arr[i, 2], 2 * math.pi))
            if dxy <= SAME_POSE * scale and dth <= SAME_POSE:
                raise ValueError(f"{what}: pose {j + 1} repeats pose {i + 1} "
                                 f"({tuple(float(v) for v in arr[j])})")
    return arr


def spread(poses) -> float:
    """A length for the poses: the RMS distance of their origins from their mean (1 where
    they all share one origin)."""
    xy = np.asarray(poses, dtype=float)[:, :2]
    s = float(np.sqrt(np.mean(np.sum((xy - xy.mean(axis=0)) ** 2, axis=1))))
    return s if s > 0 else 1.0


def rotation(th) -> np.ndarray:
    c, s = math.cos(th), math.sin(th)
    return np.array([[c, -s], [s, c]])


def place(pose, u) -> np.ndarray:
    """The global position of body point ``u`` (its own frame) in ``pose``."""
    return rotation(pose[2]) @ np.asarray(u, dtype=float) + np.asarray(pose[:2], dtype=float)


def positions(poses, u) -> np.ndarray:
    """(n, 2): the positions of body point ``u`` in every pose."""
    u = np.asarray(u, dtype=float)
    return np.array([place(p, u) for p in poses])


def local(pose, xy) -> np.ndarray:
    """The body coordinates of global point ``xy`` in ``pose`` (place's inverse)."""
    return rotation(pose[2]).T @ (np.asarray(xy, dtype=float) - np.asarray(pose[:2], float))


def displacement(poses, i, j) -> np.ndarray:
    """3×3 homogeneous matrix D with D [r; 1] = [r'; 1]: a body point at r in pose i is at
    r' in pose j (0-based indices)."""
    pi, pj = np.asarray(poses[i], float), np.asarray(poses[j], float)
    R = rotation(pj[2] - pi[2])
    D = np.eye(3)
    D[:2, :2] = R
    D[:2, 2] = pj[:2] - R @ pi[:2]
    return D


def pole(poses, i, j):
    """The pole of the displacement from pose i to pose j: the one point of the plane
    that the body keeps in place (None for a pure translation)."""
    D = displacement(poses, i, j)
    A = np.eye(2) - D[:2, :2]
    if abs(np.linalg.det(A)) < 1e-14:
        return None
    return np.linalg.solve(A, D[:2, 2])


class Frame:
    """A frame of reference for the algebra: positions measured from ``centre`` in units
    of ``scale`` (the poses' spread). ``to(poses)`` gives the poses in it; ``fixed_back``
    and ``moving_back`` carry a fixed and a moving point back to the caller's units."""

    def __init__(self, poses):
        poses = np.asarray(poses, dtype=float)
        self.centre = poses[:, :2].mean(axis=0)
        self.scale = spread(poses)

    def to(self, poses) -> np.ndarray:
        out = np.array(poses, dtype=float)
        out[:, :2] = (out[:, :2] - self.centre) / self.scale
        return out

    def fixed_in(self, xy) -> np.ndarray:
        return (np.asarray(xy, dtype=float) - self.centre) / self.scale

    def moving_in(self, u) -> np.ndarray:
        return np.asarray(u, dtype=float) / self.scale

    def fixed_back(self, xy) -> np.ndarray:
        return np.asarray(xy, dtype=float) * self.scale + self.centre

    def moving_back(self, u) -> np.ndarray:
        return np.asarray(u, dtype=float) * self.scale


def equal_distance_rows(poses, G) -> np.ndarray:
    """(n - 1, 3): the rows r_j with r_j · [u, 1] = |P_j(u) − G|² − |P_1(u) − G|², j ≥ 2:
    a body point u is a moving pivot about the fixed pivot G when they all vanish."""
    poses = np.asarray(poses, dtype=float)
    G = np.asarray(G, dtype=float)
    R1, d1 = rotation(poses[0, 2]), poses[0, :2]
    rows = []
    for p in poses[1:]:
        Rj, dj = rotation(p[2]), p[:2]
        lin = 2 * (Rj.T @ dj - R1.T @ d1) - 2 * (Rj - R1).T @ G
        const = dj @ dj - d1 @ d1 - 2 * G @ (dj - d1)
        rows.append([lin[0], lin[1], const])
    return np.array(rows)


def row_pencil(poses) -> np.ndarray:
    """(n - 1, 3, 3): equal_distance_rows as a + gx b + gy c, stacked [a, b, c] per row."""
    a = equal_distance_rows(poses, (0.0, 0.0))
    b = equal_distance_rows(poses, (1.0, 0.0)) - a
    c = equal_distance_rows(poses, (0.0, 1.0)) - a
    return np.stack([a, b, c], axis=1)


def circle_residual(poses, fixed, moving) -> float:
    """max_j | |P_j − G| − |P_1 − G| |: how far body point ``moving`` is from keeping one
    distance to ``fixed`` over the poses."""
    r = np.linalg.norm(positions(poses, moving) - np.asarray(fixed, dtype=float), axis=1)
    return float(np.max(np.abs(r - r[0])))
