"""Slider dyads: where the poses ask for a straight guide instead of a fixed pivot.

PR (a prismatic joint on the ground, a revolute on the body): a body point whose positions
are collinear; the guide is the line through them. For three poses such points fill a
circle of the body (cross(P2 − P1, P3 − P1) = c|u|² + g·u + h = 0, the form being conformal);
for four, two such circles meet at the pole P12 (trivially collinear) and at one more point:
the slider point. RP (a revolute on the ground, a prismatic joint on the body): a line of the
body that passes through one fixed point in every pose, the same construction on the
inverted motion (the ground seen from the body). Five poses have one only where the
four-pose one also meets the fifth."""
from __future__ import annotations

import math

import numpy as np

from .poses import Frame, local, pole, positions

COLLINEAR = 1e-9        # relative distance of a position from the guide line


def inverted(poses) -> np.ndarray:
    """The poses of the ground's frame seen from the body's."""
    out = []
    for x, y, th in np.asarray(poses, dtype=float):
        c, s = math.cos(th), math.sin(th)
        out.append((-(c * x + s * y), -(-s * x + c * y), -th))
    return np.array(out)


def _circle(poses, j, k):
    """(c, g, h): cross(P_j − P_1, P_k − P_1) = c|u|² + g·u + h (0-based j, k)."""
    def f(u):
        P = positions(poses[[0, j, k]], u)
        a, b = P[1] - P[0], P[2] - P[0]
        return a[0] * b[1] - a[1] * b[0]
    h = f((0.0, 0.0))
    fp, fm = f((1.0, 0.0)), f((-1.0, 0.0))
    c = (fp + fm) / 2 - h
    g = np.array([(fp - fm) / 2, f((0.0, 1.0)) - c - h])
    return c, g, h


def collinear_points(poses, count=8):
    """Body points (in the poses' units) whose positions are collinear: ``count`` points
    of the circle for three poses, the one point for four or five (where it exists)."""
    poses = np.asarray(poses, dtype=float)
    frame = Frame(poses)
    normal = frame.to(poses)
    c, g, h = _circle(normal, 1, 2)
    if abs(c) < 1e-12:
        return []
    centre = -g / (2 * c)
    rr = centre @ centre - h / c
    if rr <= 0:
        return []
    if len(poses) == 3:
        r = math.sqrt(rr)
        return [frame.moving_back(centre + r * np.array([math.cos(a), math.sin(a)]))
                for a in 2 * math.pi * (np.arange(count) + 0.5) / count]
    c4, g4, h4 = _circle(normal, 1, 3)
    P12 = pole(normal, 0, 1)
    if P12 is None or abs(c4) < 1e-12:
        return []
    # the radical line n·u = m meets the first circle at P12's body point and at the answer
    n = g / c - g4 / c4
    m = -(h / c - h4 / c4)
    known = local(normal[0], P12)
    if n @ n < 1e-24:
        return []
    # second intersection of the line through `known` along the line with the circle
    t_dir = np.array([-n[1], n[0]]) / math.sqrt(n @ n)
    base = known + (m - n @ known) / (n @ n) * n
    # |base + s t − centre|² = rr: s² + 2 s t·(base − centre) + |base − centre|² − rr = 0
    off = base - centre
    roots = np.roots([1.0, 2 * t_dir @ off, off @ off - rr])
    out = []
    for s in roots:
        if abs(s.imag) > 1e-9:
            continue
        u = base + s.real * t_dir
        if np.linalg.norm(u - known) > 1e-6 and _on_line(positions(normal, u)):
            out.append(frame.moving_back(u))
    return out


def _on_line(P):
    """Whether the points P (n, 2) lie on one line (to COLLINEAR of their spread)."""
    Q = P - P.mean(axis=0)
    sv = np.linalg.svd(Q, compute_uv=False)
    return sv[0] > 0 and sv[-1] <= COLLINEAR * max(sv[0], 1.0)


def guide(points):
    """(a point, unit direction) of the line through the points P (n, 2)."""
    P = np.asarray(points, dtype=float)
    _, _, vt = np.linalg.svd(P - P.mean(axis=0))
    d = vt[0] / np.linalg.norm(vt[0])
    return P[0], d


def slider_dyads(poses, count=8):
    """[(kind, fixed, moving, direction)]: PR (fixed: a point of the guide on the ground,
    direction in the ground frame; moving: the body point) and RP (fixed: the pivot;
    moving: a point of the body's line, direction in the body frame)."""
    poses = np.asarray(poses, dtype=float)
    out = []
    for u in collinear_points(poses, count):
        point, direction = guide(positions(poses, u))
        out.append(("PR", point, np.asarray(u), direction))
    inv = inverted(poses)
    for G in collinear_points(inv, count):
        point, direction = guide(positions(inv, G))
        out.append(("RP", np.asarray(G), point, direction))
    return out
