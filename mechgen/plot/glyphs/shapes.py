"""Plane geometry of the glyphs (rotation, convex hull, rounded outlines, hatching) and the
custom shapes a user fixes in a body's frame (the seed's Disk, Bar, Edge; a Plate)."""
from __future__ import annotations

import math

import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, Polygon

from ...errors import MechgenError
from ..style import INK


def rot(th):
    """The 2x2 rotation by angle th."""
    c, s = math.cos(th), math.sin(th)
    return np.array([[c, -s], [s, c]])


# -- plane geometry of the shapes ------------------------------------------------------
def hull(pts):
    """Convex hull, counter-clockwise (Andrew's monotone chain)."""
    pts = sorted(set(map(tuple, np.round(pts, 12))))
    if len(pts) <= 2:
        return np.array(pts)

    def half(seq):
        out = []
        for p in seq:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                                     - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])) <= 0:
                out.pop()
            out.append(p)
        return out

    lower, upper = half(pts), half(reversed(pts))
    return np.array(lower[:-1] + upper[:-1])


def rounded(pts, r, n=24):
    """The convex hull of discs of radius r around the points: a bar, or a rounded plate."""
    a = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    ring = r * np.column_stack([np.cos(a), np.sin(a)])
    return hull((np.asarray(pts)[:, None, :] + ring[None]).reshape(-1, 2))


def hatch(path, spacing, length, side=1.0):
    """Hatch ticks along a polyline, on its right side (side=1) or left (side=-1)."""
    segs = []
    path = np.asarray(path, dtype=float)
    for a, b in zip(path[:-1], path[1:]):
        d = b - a
        L = math.hypot(*d)
        if L == 0:
            continue
        d /= L
        nrm = side * np.array([d[1], -d[0]])
        tick = length * (nrm - d) / math.sqrt(2)
        for s in np.arange(spacing / 2, L, spacing):
            p = a + s * d
            segs.append([p, p + tick])
    return segs


# -- custom shapes in a body's frame (the seed's Disk, Bar, Edge) ---------------------------
class Shape:
    """A custom drawing fixed in a body, in its local frame; points are numbered like the
    body's (0 its origin, 1 its P1, ...). ``artists(local, w, fill, edge)`` returns
    matplotlib artists in local coordinates; the drawing moves them with the body."""

    zorder = 1.8

    @staticmethod
    def _at(local, item):
        if isinstance(item, (int, np.integer)):
            if int(item) not in local:
                raise MechgenError(f"shape: the body has no point {item} "
                                   f"(points 0..{max(local)})")
            return np.asarray(local[int(item)], dtype=float)
        return np.asarray(item, dtype=float)

    def artists(self, local, w, fill, edge):  # pragma: no cover - the interface
        raise NotImplementedError


class Disk(Shape):
    """Mech's Disk[Location[body, point], radius]: a filled disc centred on a point."""

    def __init__(self, point=0, radius=1.0, color=None, alpha=None):
        self.point, self.radius, self.color, self.alpha = point, float(radius), color, alpha

    def artists(self, local, w, fill, edge):
        return [Circle(self._at(local, self.point), self.radius, facecolor=self.color or fill,
                       edgecolor=edge, linewidth=1.0, alpha=self.alpha, zorder=self.zorder)]


class Bar(Shape):
    """Mech's Bar[Line[body, i, j], left, right]: a rectangle along the axis from point i
    to point j, ``left`` wide on its left and ``right`` on its right."""

    def __init__(self, i, j, left=None, right=None, color=None):
        self.i, self.j, self.left, self.right, self.color = i, j, left, right, color

    def artists(self, local, w, fill, edge):
        a, b = self._at(local, self.i), self._at(local, self.j)
        d = b - a
        n = np.array([-d[1], d[0]]) / (math.hypot(*d) or 1.0)
        lw = w if self.left is None else float(self.left)
        rw = w if self.right is None else float(self.right)
        xy = [a - rw * n, b - rw * n, b + lw * n, a + lw * n]
        return [Polygon(xy, closed=True, facecolor=self.color or fill, edgecolor=edge,
                        linewidth=1.0, zorder=self.zorder + 0.05)]


class Edge(Shape):
    """Mech's Edge[body, {path}]: a polyline through body points (numbers) and local
    (x, y) pairs, hatched on its right (``side="left"`` for the other side)."""

    def __init__(self, path, hatch=True, side="right", color=INK, linewidth=1.6):
        if side not in ("right", "left"):
            raise ValueError(f"Edge side must be 'right' or 'left', got {side!r}")
        self.path, self.hatch, self.side, self.color, self.linewidth = \
            list(path), hatch, side, color, linewidth

    def artists(self, local, w, fill, edge):
        xy = np.array([self._at(local, item) for item in self.path])
        out = [Line2D(xy[:, 0], xy[:, 1], color=self.color, linewidth=self.linewidth,
                      solid_capstyle="round", zorder=self.zorder)]
        if self.hatch:
            segs = hatch(xy, 1.1 * w, 1.5 * w, 1.0 if self.side == "right" else -1.0)
            out.append(LineCollection(segs, colors=self.color, linewidths=0.8,
                                      zorder=self.zorder))
        return out


class Plate(Shape):
    """A filled polygon through body points and local (x, y) pairs."""

    def __init__(self, path, color=None, alpha=None):
        self.path, self.color, self.alpha = list(path), color, alpha

    def artists(self, local, w, fill, edge):
        xy = np.array([self._at(local, item) for item in self.path])
        return [Polygon(xy, closed=True, facecolor=self.color or fill, edgecolor=edge,
                        linewidth=1.0, alpha=self.alpha, zorder=self.zorder)]


AUTO = "auto"   # in a body's artists list: keep the automatic bar/plate as well
