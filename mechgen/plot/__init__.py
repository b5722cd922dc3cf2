"""Pictures of a mechanism with matplotlib: one instant drawn, a sweep animated, quantities
plotted against time or each other, assembly modes side by side.

Everything is computed from the generated module (``POINTS``, ``BODIES``, ``JOINTS``,
``BODY_POINTS`` and its compiled ``points``) and from solved coordinates: numpy and
matplotlib only, never sympy. Every function takes ``ax=None`` (a new figure when None)
and returns what it drew.

What a drawing shows, read off the constraints:

- every moving body as a bar (two points) or a rounded plate (more) through its points,
  in its own colour;
- revolute joints as pins; a pin on the ground gets a pivot triangle on a hatched base;
- ``point_on_line``: a slot cut along the axis body (over the travel the point makes) and a
  block sliding in it; on the ground, a hatched guide;
- ``translate``: the sliding body as a box along its axis on a hatched guide (ground) or a
  slot (another body);
- ``relative_distance``: a connecting rod between its two points;
- optionally the point labels P1, P2, ... and each body's local axes, as in seed 001's
  "DEFINICION GRAFICA" pages.

Custom artists per body (the seed's Disk, Bar, Edge) go in ``artists={"manivela":
Disk(1, 4.0)}``: shapes in the body's local frame, numbered like its points (0 the origin).
"""
from __future__ import annotations

import math
import os

import numpy as np
from matplotlib.collections import Collection, LineCollection
from matplotlib.colors import to_rgb
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, FancyArrow, Patch, Polygon, Rectangle
from matplotlib.transforms import Affine2D

from ..errors import MechgenError
from ..runtime.results import Solution, Sweep, _lookup

BAR = 0.014          # bar half-width as a fraction of the frame's larger side
MARGIN = 0.05        # blank border around the motion, fraction of the larger side
MOTION_POINTS = 41   # solves of the sweep that frames a single drawing
PALETTE = (          # (fill, edge) per moving body, in body order: seed 001's pink, green, blue
    ("#ff9e9e", "#c0392b"), ("#8ddc8d", "#1e8449"), ("#a6a6ff", "#2e3fa8"),
    ("#ffd27f", "#b9770e"), ("#d9a8f0", "#7d3c98"), ("#8fe0e6", "#117a80"),
    ("#e2c395", "#7b5a2e"), ("#c8c8c8", "#4d4d4d"),
)
INK = "#222222"


# -- the structure a module states --------------------------------------------------
class _Body:
    def __init__(self, name, number, ground, origin, pts, every, th, color):
        self.name, self.number, self.ground = name, number, ground
        self.origin = origin        # index into POINTS of body[0], -1 for the ground
        self.pts = pts              # indices of P1, P2, ...
        self.every = every          # every POINTS index of this body
        self.th = th                # index of Th<n> in q, None for the ground
        self.fill, self.edge = color


class _Structure:
    """Bodies, points and joints of a loaded mechanism, from its generated module."""

    def __init__(self, mech, colors=None):
        mod = mech.module
        self.name = mech.name
        self.labels = [label for label, _ in mod.POINTS]
        owner = [body for _, body in mod.POINTS]
        self.owner = owner
        stated = {name: (origin, tuple(pts))
                  for name, origin, pts in getattr(mod, "BODY_POINTS", ())}
        self.joints = [(n, kind, tuple(used)) for n, kind, used in getattr(mod, "JOINTS", ())]
        self.bodies, self.by_name = [], {}
        colors = dict(colors or {})
        moving = 0
        for name, number, ground in mod.BODIES:
            every = [k for k, b in enumerate(owner) if b == name]
            if name in stated:
                origin, pts = stated[name]
            else:  # a module without BODY_POINTS: its labels are all we have
                tag = f"{name}[0]"
                origin = -1 if ground else self.labels.index(tag) if tag in self.labels else -1
                pts = tuple(k for k in every if k != origin)
            th = None if ground else mech._index.get(f"Th{number}")
            if ground:
                color = ("#d9d9d9", INK)
            else:
                color = PALETTE[moving % len(PALETTE)]
                moving += 1
            if name in colors:
                color = _tints(colors.pop(name))
            body = _Body(name, number, bool(ground), origin, pts, every, th, color)
            self.bodies.append(body)
            self.by_name[name] = body
        if colors:
            raise MechgenError(f"colors: no body named {', '.join(map(repr, colors))} in "
                               f"'{self.name}' (bodies: {', '.join(self.by_name)})")
        if not self.labels:
            raise MechgenError(f"'{self.name}' has no bodies with points to draw (a model "
                               "written in coordinates only, such as a loop-closure model, "
                               "has no geometry; plot its quantities with plot())")

    def point(self, label) -> int:
        """The POINTS index of a label: a POINTS label, or ``body[k]`` (P-number k)."""
        if isinstance(label, (int, np.integer)):
            if 0 <= label < len(self.labels):
                return int(label)
            raise MechgenError(f"point index {label} out of range ({len(self.labels)} points)")
        if label in self.labels:
            return self.labels.index(label)
        name, _, rest = str(label).partition("[")
        if name in self.by_name and rest.endswith("]") and rest[:-1].isdigit():
            body, k = self.by_name[name], int(rest[:-1])
            if k == 0 and body.origin >= 0:
                return body.origin
            if 1 <= k <= len(body.pts):
                return body.pts[k - 1]
        raise MechgenError(f"'{self.name}' has no point {label!r} (points: "
                           f"{', '.join(self.labels)}; or body[k] for its k-th point)")

    def poses(self, P, Q):
        """Origins (F, nb, 2) and angles (F, nb) of every body over frames P (F, N, 2)."""
        F = P.shape[0]
        org = np.zeros((F, len(self.bodies), 2))
        ang = np.zeros((F, len(self.bodies)))
        for i, b in enumerate(self.bodies):
            if b.ground:
                continue
            if b.origin >= 0:
                org[:, i] = P[:, b.origin]
            if b.th is not None:
                ang[:, i] = Q[:, b.th]
        return org, ang


def _tints(color):
    rgb = np.array(to_rgb(color))
    fill = 1.0 - 0.45 * (1.0 - rgb)
    return tuple(fill), tuple(rgb)


def _rot(th):
    c, s = math.cos(th), math.sin(th)
    return np.array([[c, -s], [s, c]])


# -- plane geometry of the shapes ------------------------------------------------------
def _hull(pts):
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


def _rounded(pts, r, n=24):
    """The convex hull of discs of radius r around the points: a bar, or a rounded plate."""
    a = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    ring = r * np.column_stack([np.cos(a), np.sin(a)])
    return _hull((np.asarray(pts)[:, None, :] + ring[None]).reshape(-1, 2))


def _hatch(path, spacing, length, side=1.0):
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
            segs = _hatch(xy, 1.1 * w, 1.5 * w, 1.0 if self.side == "right" else -1.0)
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


# -- the drawing ---------------------------------------------------------------------------
def _vertices(artist):
    """An artist's vertices in its own coordinates (for the frame), or None."""
    if isinstance(artist, Patch):
        return artist.get_path().transformed(artist.get_patch_transform()).vertices
    if isinstance(artist, Line2D):
        return np.asarray(artist.get_xydata(), dtype=float)
    if isinstance(artist, LineCollection):
        segs = artist.get_segments()
        return np.concatenate(segs) if segs else None
    return None


class Drawing:
    """What draw() drew: ``ax``, ``artists`` (by body name; ``"joints"`` for pins, blocks
    and rods), ``frame`` (xmin, xmax, ymin, ymax), ``size`` (a bar's half-width, the unit
    of every detail) and ``update(solution)`` to move it."""

    def __init__(self, ax, mech, structure):
        self.ax = ax
        self.mechanism = mech
        self.structure = structure
        self.artists = {b.name: [] for b in structure.bodies}
        self.artists["joints"] = []
        self.frame = None
        self.size = None
        self.title = None
        self._tf = {}
        self._dynamic = []
        self._redrawn = set()     # bodies drawn by user functions, redrawn at each update

    @property
    def figure(self):
        return self.ax.figure

    def all_artists(self):
        return [a for group in self.artists.values() for a in group]

    def update(self, solution):
        """Move the drawing to another configuration (a Solution of the same mechanism)."""
        self.set_state(solution.points(), solution.q, solution.t)

    def set_state(self, P, q, t):
        """Move every artist to points P (npoints, 2), coordinates q, time t, in place."""
        for b in self.structure.bodies:
            tf = self._tf.get(b.name)
            if tf is None:
                continue
            o = P[b.origin] if b.origin >= 0 else (0.0, 0.0)
            th = q[b.th] if b.th is not None else 0.0
            c, s = math.cos(th), math.sin(th)
            tf.set_matrix(np.array([[c, -s, o[0]], [s, c, o[1]], [0.0, 0.0, 1.0]]))
        for fn in self._dynamic:
            fn(P, q, t)


class _Builder:
    """Builds a Drawing at configuration (P0, q0), sized and framed by the motion (P, Q)."""

    def __init__(self, ax, mech, st, P0, q0, t0, P, Q):
        self.ax, self.st = ax, st
        self.d = Drawing(ax, mech, st)
        self.P0, self.q0, self.P, self.Q = P0, q0, P, Q
        lo, hi = P.reshape(-1, 2).min(axis=0), P.reshape(-1, 2).max(axis=0)
        self.center = (lo + hi) / 2
        self.span = float(max(hi - lo)) or 1.0
        self.w = BAR * self.span
        self.d.size = self.w
        self.org0, self.ang0 = st.poses(P0[None], q0[None])
        self.org0, self.ang0 = self.org0[0], self.ang0[0]
        self.bi = {b.name: i for i, b in enumerate(st.bodies)}
        for b in st.bodies:
            if not b.ground:
                self.d._tf[b.name] = Affine2D()
        self.d.set_state(P0, q0, t0)
        self.slotted = set()
        self.boxed = {}
        self.obstacles = []       # global spots labels keep away from (pivots, axes)

    # frames and local coordinates
    def trans(self, body):
        tf = self.d._tf.get(body.name)
        return self.ax.transData if tf is None else tf + self.ax.transData

    def local(self, body, k, P=None):
        """Point k (POINTS index) in body's frame, at the drawn configuration."""
        i = self.bi[body.name]
        R = _rot(self.ang0[i])
        return R.T @ ((self.P0 if P is None else P)[k] - self.org0[i])

    def local_motion(self, body, k):
        """Point k in body's frame at every frame of the motion: (F, 2)."""
        i = self.bi[body.name]
        org, ang = self.st.poses(self.P, self.Q)
        rel = self.P[:, k] - org[:, i]
        c, s = np.cos(ang[:, i]), np.sin(ang[:, i])
        return np.column_stack([c * rel[:, 0] + s * rel[:, 1], -s * rel[:, 0] + c * rel[:, 1]])

    def add(self, group, artist, body=None):
        if body is not None:
            artist.set_transform(self.trans(body))
        if isinstance(artist, Collection):
            self.ax.add_collection(artist, autolim=False)
        elif isinstance(artist, Patch):
            self.ax.add_patch(artist)
        elif isinstance(artist, Line2D):
            self.ax.add_line(artist)
        else:
            self.ax.add_artist(artist)
        self.d.artists[group].append(artist)
        return artist

    def body_of(self, k):
        return self.st.by_name[self.st.owner[k]]

    # the joints
    def pin(self, body, k, r=None, group="joints"):
        r = 0.85 * self.w if r is None else r
        self.add(group, Circle(self.local(body, k), r, facecolor="white", edgecolor=INK,
                               linewidth=1.2, zorder=5), body)

    def pivot(self, k):
        """A ground pivot: triangle standing on a hatched base below the point."""
        x, y = self.P0[k]
        w = self.w
        h, half, foot = 3.0 * w, 1.9 * w, 3.0 * w
        self.obstacles += [(x, y - 1.5 * w), (x, y - h), (x - half, y - h), (x + half, y - h)]
        ground = self.st.by_name[self.st.owner[k]]
        self.add(ground.name, Polygon([(x, y), (x - half, y - h), (x + half, y - h)],
                                      closed=True, facecolor="#e6e6e6", edgecolor=INK,
                                      linewidth=1.0, zorder=1.2))
        base = np.array([(x - foot, y - h), (x + foot, y - h)])
        self.add(ground.name, Line2D(base[:, 0], base[:, 1], color=INK, linewidth=1.4,
                                     zorder=1.2))
        self.add(ground.name, LineCollection(_hatch(base, 1.1 * w, 1.3 * w), colors=INK,
                                             linewidths=0.8, zorder=1.2))

    def revolute(self, k1, k2):
        b1, b2 = self.body_of(k1), self.body_of(k2)
        if b1.ground and b2.ground:
            return
        if b1.ground or b2.ground:
            self.pivot(k1 if b1.ground else k2)
        self.pin(b2 if not b2.ground else b1, k2 if not b2.ground else k1)

    def rail(self, ground, a1, a2, extent_pts, side):
        """A hatched guide on the ground along axis a1->a2 covering extent_pts (global)."""
        A, B = self.P0[a1], self.P0[a2]
        u = B - A
        L = math.hypot(*u)
        if L == 0:
            return
        u = u / L
        s = np.concatenate([(np.asarray(extent_pts) - A) @ u, [0.0, L]])
        s0, s1 = s.min() - 1.5 * self.w, s.max() + 1.5 * self.w
        path = np.array([A + s0 * u, A + s1 * u])
        nrm = np.array([u[1], -u[0]])            # the right of the axis
        hatch_side = 1.0 if side @ nrm < 0 else -1.0   # ticks away from the sliding body
        self.add(ground.name, Line2D(path[:, 0], path[:, 1], color=INK, linewidth=1.6,
                                     solid_capstyle="butt", zorder=1.2))
        self.add(ground.name, LineCollection(_hatch(path, 1.1 * self.w, 1.4 * self.w,
                                                    hatch_side), colors=INK, linewidths=0.8,
                                             zorder=1.2))

    def slot(self, body, a1, a2, travel):
        """A slot cut in body along its axis a1->a2 over the travel (local points)."""
        A, B = self.local(body, a1), self.local(body, a2)
        u = B - A
        L = math.hypot(*u)
        if L == 0:
            return
        u = u / L
        s = (np.asarray(travel) - A) @ u
        hs = 0.6 * self.w
        ext = 1.7 * self.w - hs
        ends = [A + (s.min() - ext) * u, A + (s.max() + ext) * u]
        self.add(body.name, Polygon(_rounded(ends, hs), closed=True, facecolor="white",
                                    edgecolor=body.edge, linewidth=1.0, zorder=3), body)
        self.slotted.add(body.name)

    def block(self, k, a1, a2, body):
        """A block of body (the point's) at point k, aligned with the axis a1->a2."""
        w = self.w
        tf = Affine2D()
        rect = Rectangle((-1.7 * w, -0.6 * w), 3.4 * w, 1.2 * w, facecolor=body.fill,
                         edgecolor=body.edge, linewidth=1.0, zorder=3.5)
        pin = Circle((0.0, 0.0), 0.42 * w, facecolor="white", edgecolor=INK, linewidth=1.0,
                     zorder=5)
        for art in (rect, pin):
            art.set_transform(tf + self.ax.transData)
            self.add("joints", art)

        def move(P, q, t, tf=tf):
            d = P[a2] - P[a1]
            th = math.atan2(d[1], d[0])
            c, s = math.cos(th), math.sin(th)
            tf.set_matrix(np.array([[c, -s, P[k, 0]], [s, c, P[k, 1]], [0, 0, 1.0]]))
        move(self.P0, self.q0, 0.0)
        self.d._dynamic.append(move)

    def point_on_line(self, k, a1, a2):
        pb, ab = self.body_of(k), self.body_of(a1)
        if self.body_of(a2) is not ab:
            self.pin(pb, k) if not pb.ground else None
            return
        if ab.ground:
            self.rail(ab, a1, a2, self.P[:, k], self.center - self.P0[k])
        else:
            self.slot(ab, a1, a2, self.local_motion(ab, k))
        self.block(k, a1, a2, pb if not pb.ground else ab)

    def translate(self, a1, a2, b1, b2):
        g, s = self.body_of(a1), self.body_of(b1)
        if self.body_of(a2) is not g or self.body_of(b2) is not s or g is s:
            return
        if s.ground:                       # the sliding body is the moving one
            g, s, a1, a2, b1, b2 = s, g, b1, b2, a1, a2
        if s.ground:
            return
        A, B = self.local(s, b1), self.local(s, b2)
        u = B - A
        L = math.hypot(*u)
        if L == 0:
            return
        u = u / L
        n = np.array([-u[1], u[0]])
        on = [self.local(s, k) for k in s.every if k != s.origin or k in s.pts]
        proj = np.array([(p - A) @ u for p in on])
        off = np.array([(p - A) @ n for p in on])
        s0, s1 = proj.min(), proj.max()
        if s1 - s0 < 2 * self.w:
            s0, s1 = (s0 + s1) / 2 - 2 * self.w, (s0 + s1) / 2 + 2 * self.w
        h = 3.2 * self.w
        if g.ground:                       # the box sits on the guide, away from the middle
            R = _rot(self.ang0[self.bi[s.name]])
            outward = (self.P0[b1] - self.center) @ (R @ n)
            sign = 1.0 if outward >= 0 else -1.0
            lo, hi = (0.0, h) if sign > 0 else (-h, 0.0)
        else:
            lo, hi = -h / 2, h / 2
        self.boxed[s.name] = bool(np.all(np.abs(off) < 1e-9 * max(1.0, self.span)))
        corners = [A + s0 * u + lo * n, A + s1 * u + lo * n, A + s1 * u + hi * n,
                   A + s0 * u + hi * n]
        self.add(s.name, Polygon(corners, closed=True, facecolor=s.fill, edgecolor=s.edge,
                                 linewidth=1.2, zorder=2.5), s)
        if g.ground:
            # the corners over the motion, to cover the travel with the guide
            org, ang = self.st.poses(self.P, self.Q)
            i = self.bi[s.name]
            ext = []
            for c in (corners[0], corners[1]):
                for f in range(self.P.shape[0]):
                    ext.append(org[f, i] + _rot(ang[f, i]) @ c)
            R = _rot(self.ang0[i])
            self.rail(g, a1, a2, np.array(ext), R @ (n * (hi + lo)))
        else:
            self.slot(g, a1, a2, [self.local(g, b1), self.local(g, b2)])

    def rod(self, k1, k2):
        """A connecting rod between two points (relative_distance)."""
        r = 0.55 * self.w
        poly = self.add("joints", Polygon(_rounded([self.P0[k1], self.P0[k2]], r, 12),
                                          closed=True, facecolor="#555555", edgecolor=INK,
                                          linewidth=1.0, zorder=4))
        ring = [(r * math.cos(a), r * math.sin(a)) for a in np.linspace(0, 2 * math.pi, 12,
                                                                          endpoint=False)]
        ring = np.array(ring)

        def move(P, q, t, poly=poly):
            poly.set_xy(_hull(np.concatenate([P[k1] + ring, P[k2] + ring])))
        self.d._dynamic.append(move)
        for k in (k1, k2):
            b = self.body_of(k)
            if b.ground:
                self.pivot(k)
            self.pin(b, k, 0.6 * self.w)

    # bodies
    def body_shape(self, b):
        keep = [k for k in b.every if k != b.origin or k in b.pts or
                any(k in used for _, _, used in self.st.joints)]
        if not keep:
            keep = [b.origin]
        pts = np.array([self.local(b, k) for k in keep])
        r = (1.45 if b.name in self.slotted else 1.0) * self.w
        self.add(b.name, Polygon(_rounded(pts, r), closed=True, facecolor=b.fill,
                                 edgecolor=b.edge, linewidth=1.2,
                                 zorder=2 + 0.01 * b.number), b)

    def custom(self, b, shapes):
        local = {k: self.local(b, idx) for k, idx in enumerate(b.pts, start=1)}
        local[0] = np.zeros(2) if b.origin < 0 else self.local(b, b.origin)
        auto = False
        for shape in shapes:
            if isinstance(shape, str) and shape == AUTO:
                auto = True
            elif isinstance(shape, Shape):
                for art in shape.artists(local, self.w, b.fill, b.edge):
                    self.add(b.name, art, b)
            elif callable(shape):
                self.callable(b, shape)
            else:
                raise MechgenError(f"artists[{b.name!r}]: expected a Shape (Disk, Bar, Edge, "
                                   f"Plate), a function (ax, xy) or 'auto', got {shape!r}")
        return auto

    def callable(self, b, fn):
        """A user function fn(ax, xy) -> artists, xy = origin, P1, P2, ... (global); it is
        called again (and its artists replaced) at every update."""
        idx = [b.origin] + list(b.pts)
        drawn = []
        self.d._redrawn.add(b.name)

        def move(P, q, t):
            for art in drawn:
                art.remove()
                if art in self.d.artists[b.name]:
                    self.d.artists[b.name].remove(art)
            xy = np.array([P[k] if k >= 0 else (0.0, 0.0) for k in idx], dtype=float)
            made = fn(self.ax, xy) or []
            made = list(made) if isinstance(made, (list, tuple)) else [made]
            drawn[:] = made
            self.d.artists[b.name].extend(made)
        move(self.P0, self.q0, 0.0)
        self.d._dynamic.append(move)

    def labels(self, bodies, fontsize):
        """P1, P2, ... next to each point, away from its body's middle and from labels
        already placed (checked on screen at the drawn configuration)."""
        self.ax.apply_aspect()
        to_px = self.ax.transData.transform
        px_per_pt = self.ax.figure.dpi / 72.0
        off, gap = 13.0, 1.9 * fontsize * px_per_pt
        taken = [to_px(xy) for xy in self.obstacles]
        turns = [math.radians(a) for a in (0, 40, -40, 80, -80, 120, -120, 180)]
        for b in bodies:
            if not b.pts:
                continue
            pts = np.array([self.P0[k] for k in b.pts])
            mid = pts.mean(axis=0)
            for n, k in enumerate(b.pts, start=1):
                d0 = self.P0[k] - mid
                if math.hypot(*d0) < 1e-9 * self.span:
                    d0 = np.array([1.0, 1.0])
                d0 = d0 / math.hypot(*d0)
                at = to_px(self.P0[k])
                best = None
                for a in turns:      # the first free direction, else the least crowded
                    d = _rot(a) @ d0
                    spot = at + off * px_per_pt * d
                    room = min((math.hypot(*(spot - t)) for t in taken), default=math.inf)
                    if best is None or room > best[0]:
                        best = (room, d, spot)
                    if room > gap:
                        break
                _, d, spot = best
                taken.append(spot)
                ann = self.ax.annotate(f"P{n}", xy=self.local(b, k), xycoords=self.trans(b),
                                       xytext=(off * d[0], off * d[1]), textcoords="offset points",
                                       ha="center", va="center", fontsize=fontsize,
                                       color=b.edge, zorder=6, annotation_clip=False)
                self.d.artists[b.name].append(ann)

    def local_axes(self, bodies, fontsize):
        for b in bodies:
            L = (0.12 if b.ground else 0.07) * self.span
            i = self.bi[b.name]
            R = _rot(self.ang0[i])
            for f in (0.35, 0.7, 1.0, 1.15):
                self.obstacles += [self.org0[i] + R @ (f * L, 0.0), self.org0[i] + R @ (0.0, f * L)]
            for (dx, dy), name in (((L, 0.0), "x"), ((0.0, L), "y")):
                arrow = FancyArrow(0.0, 0.0, dx, dy, width=0.04 * self.w, head_width=0.55 * self.w,
                                   head_length=0.9 * self.w, length_includes_head=True,
                                   color=INK, zorder=6)
                self.add(b.name, arrow, b)
                txt = self.ax.annotate(f"${name}_{{{b.number}}}$", xy=(dx * 1.12, dy * 1.12),
                                       xycoords=self.trans(b), ha="center", va="center",
                                       fontsize=fontsize, color=INK, zorder=6,
                                       annotation_clip=False)
                self.d.artists[b.name].append(txt)

    def frame(self):
        """Limits covering every artist over the motion."""
        org, ang = self.st.poses(self.P, self.Q)
        step = max(1, self.P.shape[0] // 24)
        boxes = [self.P.reshape(-1, 2)]
        for b in self.st.bodies:
            verts = [v for v in map(_vertices, self.d.artists[b.name]) if v is not None
                     and len(v)]
            if not verts:
                continue
            V = np.concatenate(verts)
            if b.ground or b.name not in self.d._tf:
                boxes.append(V)
                continue
            i = self.bi[b.name]
            for f in range(0, self.P.shape[0], step):
                boxes.append(org[f, i] + V @ _rot(ang[f, i]).T)
        allv = np.concatenate(boxes)
        lo, hi = allv.min(axis=0), allv.max(axis=0)
        pad = MARGIN * float(max(hi - lo) or 1.0)
        return (lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad)


def _as_solution(mech, solution):
    if isinstance(solution, Solution):
        return solution
    if isinstance(solution, (int, float, np.floating, np.integer)) \
            and not isinstance(solution, bool):
        return mech.solve(float(solution))
    raise TypeError(f"draw() takes a Solution (mech.solve(t)) or a time, got {solution!r}")


def motion(mech, solution, span=1.0, n=MOTION_POINTS):
    """The points and coordinates of the motion from a solution over ``span`` time units
    (warm-started from it, so in its assembly mode; cut short at a lock): (P, Q)."""
    import warnings
    m = solution.mechanism
    last = m.last
    sw = None
    try:
        with warnings.catch_warnings():   # only framing: a branch warning would mislead
            warnings.simplefilter("ignore")
            sw = m.sweep(solution.t, solution.t + span, n, guess=solution.q)
    except MechgenError as exc:
        sw = getattr(exc, "sweep", None)
    finally:
        m.last = last
    P0, q0 = solution.points()[None], solution.q[None]
    if sw is None or not len(sw):
        return P0, q0
    return np.concatenate([P0, sw.points()]), np.concatenate([q0, sw.Q])


def _new_axes(frame, width=8.0):
    import matplotlib.pyplot as plt
    dx, dy = frame[1] - frame[0], frame[3] - frame[2]
    height = min(max(width * dy / max(dx, 1e-12), 2.5), 1.6 * width) + 0.7
    fig, ax = plt.subplots(figsize=(width, height))
    return ax


def _set_frame(ax, frame, width=None, aside=0.0):
    """Limits, equal aspect; on a figure of our own, a height that fits the frame (and
    ``aside`` inches on the right for a legend)."""
    ax.set_xlim(frame[0], frame[1])
    ax.set_ylim(frame[2], frame[3])
    ax.set_aspect("equal", adjustable="box")
    if width is not None:
        left, right, bottom, top = 0.7, 0.25 + aside, 0.45, 0.45
        aw = width - left - right
        ah = min(max(aw * (frame[3] - frame[2]) / max(frame[1] - frame[0], 1e-12), 1.5),
                 1.6 * width)
        height = ah + bottom + top
        fig = ax.figure
        fig.set_size_inches(width, height)
        fig.subplots_adjust(left=left / width, right=1 - right / width, bottom=bottom / height,
                            top=1 - top / height)


def draw(mech, solution, ax=None, *, sweep=None, frame=None, labels=False, axes=False,
         artists=None, colors=None, title=None, legend=False, grid=True, fontsize=9,
         width=8.0):
    """Draw the mechanism at one instant; returns a :class:`Drawing`.

    ``solution``: a Solution (``mech.solve(t)``) or a time. The frame covers the motion:
    of ``sweep`` when given, else of one time unit solved from the solution (in its
    assembly mode); ``frame=(xmin, xmax, ymin, ymax)`` fixes it, ``frame="pose"`` fits
    this configuration only. ``labels``: True (or a list of body names) writes P1, P2, ...;
    ``axes``: True (or body names) draws local axes. ``artists``: {body name: Shape,
    function(ax, xy) or a list of them} replaces a body's automatic bar (add ``"auto"`` to
    the list to keep it); for the ground it replaces the automatic guides. ``colors``:
    {body name: colour}. ``title``: text, False for none, None for the model and time.
    """
    solution = _as_solution(mech, solution)
    st = _Structure(mech, colors)
    P0, q0 = solution.points(), solution.q
    if sweep is not None:
        P, Q = np.concatenate([P0[None], sweep.points()]), np.concatenate([q0[None], sweep.Q])
    elif isinstance(frame, str) and frame == "pose":
        P, Q = P0[None], q0[None]
    elif frame is None:
        P, Q = motion(mech, solution)
    else:
        P, Q = P0[None], q0[None]
    if isinstance(frame, str) and frame != "pose":
        raise ValueError(f"frame must be None, 'pose' or (xmin, xmax, ymin, ymax), got {frame!r}")
    own = ax is None
    if own:
        lo, hi = P.reshape(-1, 2).min(axis=0), P.reshape(-1, 2).max(axis=0)
        pad = 0.12 * float(max(hi - lo) or 1.0)
        guess = frame if isinstance(frame, (tuple, list)) else \
            (lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad)
        ax = _new_axes(guess, width)
    bld = _Builder(ax, mech, st, P0, q0, solution.t, P, Q)
    custom = dict(artists or {})
    unknown = [k for k in custom if k not in st.by_name]
    if unknown:
        raise MechgenError(f"artists: no body named {', '.join(map(repr, unknown))} in "
                           f"'{mech.name}' (bodies: {', '.join(st.by_name)})")

    # joints first: they decide which bodies are slotted or boxed
    ground_custom = any(b.ground and b.name in custom for b in st.bodies)
    for _, kind, used in st.joints:
        if kind == "revolute" and len(used) == 2:
            bld.revolute(*used)
        elif kind == "point_on_line" and len(used) == 3:
            if ground_custom and bld.body_of(used[1]).ground and bld.body_of(used[2]).ground:
                bld.block(used[0], used[1], used[2], bld.body_of(used[0]))
            else:
                bld.point_on_line(*used)
        elif kind == "translate" and len(used) == 4:
            n_before = {k: len(v) for k, v in bld.d.artists.items()}
            bld.translate(*used)
            if ground_custom:   # the user's ground drawing replaces the automatic guide
                for b in st.bodies:
                    if b.ground:
                        for art in bld.d.artists[b.name][n_before[b.name]:]:
                            art.remove()
                        del bld.d.artists[b.name][n_before[b.name]:]
        elif kind == "relative_distance" and len(used) == 2:
            bld.rod(*used)
    for b in st.bodies:
        shapes = custom.get(b.name)
        keep_auto = True
        if shapes is not None:
            shapes = shapes if isinstance(shapes, (list, tuple)) else [shapes]
            keep_auto = bld.custom(b, shapes)
        if b.ground:
            xy = np.array([P0[k] for k in b.pts]) if b.pts else np.zeros((0, 2))
            if len(xy):
                bld.add(b.name, Line2D(xy[:, 0], xy[:, 1], linestyle="none", marker="o",
                                       markersize=3, color=INK, zorder=1.3))
            continue
        if keep_auto and not bld.boxed.get(b.name, False):
            bld.body_shape(b)

    def chosen(option):
        if option is True:
            return st.bodies
        if not option:
            return []
        names = [option] if isinstance(option, str) else list(option)
        missing = [n for n in names if n not in st.by_name]
        if missing:
            raise MechgenError(f"no body named {', '.join(map(repr, missing))} in "
                               f"'{mech.name}' (bodies: {', '.join(st.by_name)})")
        return [st.by_name[n] for n in names]

    bld.local_axes(chosen(axes), fontsize - 1)
    d = bld.d
    d.frame = tuple(frame) if isinstance(frame, (tuple, list)) else bld.frame()
    outside = legend is True and own
    if outside:
        width += 1.4
    _set_frame(ax, d.frame, width if own else None, 1.5 if outside else 0.0)
    bld.labels(chosen(labels), fontsize)
    if grid:
        ax.grid(True, color="#dddddd", linewidth=0.6, zorder=0)
        ax.set_axisbelow(True)
    ax.tick_params(labelsize=fontsize - 1)
    if title is None:
        d.title = ax.set_title(f"{mech.name}   T = {solution.t:.4g}", fontsize=fontsize + 2)

        def retitle(P, q, t, text=d.title, name=mech.name):
            text.set_text(f"{name}   T = {t:.4g}")
        d._dynamic.append(retitle)
    elif title:
        d.title = ax.set_title(title, fontsize=fontsize + 2)
    if legend:
        handles = [Patch(facecolor=b.fill, edgecolor=b.edge, label=b.name)
                   for b in st.bodies if not b.ground]
        if outside:   # beside the drawing, where it hides nothing
            ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0),
                      borderaxespad=0.0, fontsize=fontsize)
        else:
            ax.legend(handles=handles, loc=legend if isinstance(legend, str) else "best",
                      fontsize=fontsize, framealpha=0.85)
    return d


def draw_modes(mech, solutions, axs=None, titles=None, **kwargs):
    """Several configurations (assembly modes at one time, say) side by side, on one common
    frame; returns the list of Drawings. Titles default to the coordinates that differ."""
    solutions = [_as_solution(mech, s) for s in solutions]
    if not solutions:
        raise ValueError("draw_modes() needs at least one solution")
    n = len(solutions)
    own = axs is None
    if own:
        import matplotlib.pyplot as plt
        _, axs = plt.subplots(1, n, figsize=(5.0 * n, 4.6), squeeze=False)
        axs = list(axs[0])
    axs = list(np.ravel(axs))
    if len(axs) != n:
        raise ValueError(f"draw_modes(): {n} solutions but {len(axs)} axes")
    if titles is None:
        Q = np.array([s.q for s in solutions])
        differ = [k for k in range(Q.shape[1]) if np.ptp(Q[:, k]) > 1e-6]
        names = [mech.coordinates[k] for k in differ][:3]
        titles = [f"mode {i + 1}: " + ", ".join(f"{c} = {s[c]:.4g}" for c in names)
                  if names else f"mode {i + 1}" for i, s in enumerate(solutions)]
    drawings = [draw(mech, s, ax=ax, title=t, **kwargs)
                for s, ax, t in zip(solutions, axs, titles)]
    if "frame" not in kwargs:
        F = np.array([d.frame for d in drawings])
        common = (F[:, 0].min(), F[:, 1].max(), F[:, 2].min(), F[:, 3].max())
        for d in drawings:
            d.frame = common
            d.ax.set_xlim(common[0], common[1])
            d.ax.set_ylim(common[2], common[3])
    fig = drawings[0].ax.figure
    fig.suptitle(f"{mech.name}   T = {solutions[0].t:.4g}"
                 if len({s.t for s in solutions}) == 1 else mech.name)
    if own:   # panels shaped like the common frame
        f = drawings[0].frame
        panel = 5.0 if (f[1] - f[0]) < 1.3 * (f[3] - f[2]) else 6.0
        ah = min(max((panel - 0.8) * (f[3] - f[2]) / max(f[1] - f[0], 1e-12), 1.5), 1.6 * panel)
        fig.set_size_inches(panel * n, ah + 1.3)
        fig.tight_layout()
    return drawings


# -- animation ----------------------------------------------------------------------------
class Animation:
    """What animate() made: the Drawing, its traces, ``frames()`` (RGB arrays),
    ``save(path)`` and, for notebooks and windows, a matplotlib FuncAnimation
    (``.animation``) stepping the same artists."""

    def __init__(self, drawing, step, n, fps, traces):
        self.drawing = drawing
        self.traces = traces
        self.fps = fps
        self.path = None
        self._step = step
        self._n = n
        self._anim = None

    def __len__(self):
        return self._n

    @property
    def figure(self):
        return self.drawing.figure

    @property
    def animation(self):
        """A blit-free matplotlib FuncAnimation moving the drawing's artists in place."""
        if self._anim is None:
            from matplotlib.animation import FuncAnimation
            self._anim = FuncAnimation(self.figure, self._step, frames=self._n,
                                       interval=1000.0 / self.fps, blit=False, repeat=True,
                                       cache_frame_data=False)
        return self._anim

    def _moving(self):
        """The artists that change between frames (the ground's and the legend stay)."""
        d = self.drawing
        still = {b.name for b in d.structure.bodies if b.ground and b.name not in d._redrawn}
        arts = [a for name, group in d.artists.items() if name not in still for a in group]
        if d.title is not None:
            arts.append(d.title)
        return arts

    def frames(self, dpi=None):
        """Render every frame as an (h, w, 3) uint8 array. The still parts (axes, ticks,
        grid) are rendered once; each frame moves the artists in place and draws only them."""
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        fig = self.figure
        canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)
        old_dpi = fig.dpi
        if dpi is not None:
            fig.set_dpi(dpi)
        moving = self._moving()
        try:
            for a in moving:
                a.set_animated(True)
            canvas.draw()
            background = canvas.copy_from_bbox(fig.bbox)
            for f in range(self._n):
                self._step(f)
                canvas.restore_region(background)
                for a in sorted(self._moving(), key=lambda a: a.get_zorder()):
                    a.axes.draw_artist(a) if a.axes is not None else fig.draw_artist(a)
                yield np.asarray(canvas.buffer_rgba())[..., :3].copy()
        finally:
            for a in self._moving():
                a.set_animated(False)
            if dpi is not None:
                fig.set_dpi(old_dpi)

    def save(self, path, fps=None, dpi=80):
        """Write a GIF (pillow) or, with ffmpeg on the PATH, an MP4 (.mp4, .mov, .mkv)."""
        fps = self.fps if fps is None else fps
        ext = check_movie_path(path)
        if ext == ".gif":
            from PIL import Image
            images = [Image.fromarray(f) for f in self.frames(dpi)]
            # one palette for the whole film: from a few frames side by side
            picks = images[:: max(1, len(images) // 4)][:4]
            sheet = Image.new("RGB", (sum(i.width for i in picks), picks[0].height))
            x = 0
            for im in picks:
                sheet.paste(im, (x, 0))
                x += im.width
            palette = sheet.quantize(colors=127, method=Image.Quantize.MEDIANCUT)
            colors = np.array(palette.getpalette()[:3 * 127]).reshape(-1, 3)
            colors[colors.min(axis=1) >= 244] = 255      # paper stays white, not 252-grey
            palette.putpalette(colors.ravel().tolist() + [255, 255, 255] * (256 - len(colors)))
            film = [im.quantize(palette=palette, dither=Image.Dither.NONE) for im in images]
            film[0].save(str(path), save_all=True, append_images=film[1:],
                         duration=int(round(1000.0 / fps)), loop=0, optimize=False)
        else:
            from matplotlib import animation as manim
            writer = manim.FFMpegWriter(fps=fps)
            with writer.saving(self.figure, str(path), dpi):
                for f in range(self._n):
                    self._step(f)
                    writer.grab_frame()
        self._step(0)
        self.path = path
        return path


MOVIES = (".mp4", ".m4v", ".mov", ".mkv")


def check_movie_path(path) -> str:
    """The extension of an animation file name, or a MechgenError saying what works."""
    ext = os.path.splitext(str(path))[1].lower()
    if ext == ".gif":
        return ext
    if ext in MOVIES:
        from matplotlib import animation as manim
        if not manim.writers.is_available("ffmpeg"):
            raise MechgenError(f"writing {path} needs ffmpeg on the PATH; install it or write "
                               "a .gif instead")
        return ext
    raise MechgenError(f"cannot write an animation as {str(path)!r}: give a .gif (or "
                       f"{', '.join(MOVIES)} with ffmpeg installed)")


def animate(mech, sweep, path=None, *, trace=(), fps=25, ax=None, dpi=80, **kwargs):
    """Animate a sweep (``mech.sweep(0, 1, 200)``): one drawing whose artists move in place
    frame by frame; ``trace`` names points whose paths are drawn (coupler curves: POINTS
    labels or ``body[k]``). Writes ``path`` (.gif with pillow, .mp4 with ffmpeg) when given.
    Other keywords go to draw(). Returns an :class:`Animation`."""
    if not isinstance(sweep, Sweep):
        raise TypeError(f"animate() takes a Sweep (mech.sweep(t0, t1, n)), got {sweep!r}")
    if not len(sweep):
        raise MechgenError("animate(): the sweep holds no points")
    if path is not None:
        check_movie_path(path)
    if isinstance(trace, str):
        trace = (trace,)
    st = _Structure(mech)
    idx = [st.point(label) for label in trace]
    P, Q, T = sweep.points(), sweep.Q, sweep.t
    kwargs.setdefault("width", 7.0)
    d = draw(mech, sweep[0], ax=ax, sweep=sweep, **kwargs)
    d.artists["traces"] = []
    lines = []
    for k in idx:
        color = d.structure.by_name[st.owner[k]].edge
        full = Line2D(P[:, k, 0], P[:, k, 1], color=color, linewidth=0.8, alpha=0.4,
                      linestyle="--", zorder=4.4)
        part = Line2D(P[:1, k, 0], P[:1, k, 1], color=color, linewidth=1.8, zorder=4.5)
        d.ax.add_line(full)
        d.ax.add_line(part)
        d.artists["traces"] += [full, part]
        lines.append((k, part))

    def step(f):
        d.set_state(P[f], Q[f], T[f])
        for k, line in lines:
            line.set_data(P[:f + 1, k, 0], P[:f + 1, k, 1])
        return ()

    out = Animation(d, step, len(T), fps, [line for _, line in lines])
    if path is not None:
        out.save(path, dpi=dpi)
    return out


# -- quantities against time ---------------------------------------------------------------
def unit(mech, name, length="length", time="s"):
    """The unit of a quantity name: rad for angles, the length unit for X/Y, per time for
    derivatives; "" when unknown (a declared output)."""
    import re
    kind, k, order = _lookup(mech, name)
    per = ("", f"/{time}", f"/{time}²")[order]
    if kind == "q":
        c = mech.coordinates[k]
        if re.match(r"^(th|theta|phi|psi|alpha|beta|ang)", c, re.I):
            return "rad" + per
        if re.match(r"^[XY]\d+$", c):
            return length + per
        return ("1" + per) if per else ""
    return per[1:] if per else ""


def _label(mech, name, **units):
    u = unit(mech, name, **units)
    return f"{name} [{u}]" if u else name


def _auto_labels(sweeps):
    params = [sw.mechanism.parameters for sw in sweeps]
    keys = [k for k in params[0] if len({p.get(k) for p in params}) > 1]
    if keys:
        return [", ".join(f"{k} = {p[k]:.4g}" for k in keys) for p in params]
    names = [sw.mechanism.name for sw in sweeps]
    if len(set(names)) == len(names):
        return names
    return [f"sweep {i + 1}" for i in range(len(sweeps))]


def plot(sweep, *names, x=None, ax=None, labels=None, length="length", time="s",
         title=None, **line_kwargs):
    """Quantities of a sweep against time, or against quantity ``x``: ``plot(sw, "X4")``,
    ``plot(sw, "X4", "X4d")``, ``plot(sw, "Th3", x="Th2")``. ``sweep`` may be a list of
    sweeps (a family over a parameter), overlaid and labelled by the parameters that
    differ (or ``labels``). Returns the list of Line2D."""
    sweeps = list(sweep) if isinstance(sweep, (list, tuple)) else [sweep]
    if not sweeps or not all(isinstance(s, Sweep) for s in sweeps):
        raise TypeError("plot() takes a Sweep or a list of Sweeps")
    flat = []
    for n in names:
        flat += [n] if isinstance(n, str) else list(n)
    if not flat:
        raise ValueError("plot(): name at least one quantity, e.g. plot(sw, 'X4')")
    if labels is None:
        labels = _auto_labels(sweeps) if len(sweeps) > 1 else [None]
    elif isinstance(labels, str):
        labels = [labels]
    if len(labels) != len(sweeps):
        raise ValueError(f"plot(): {len(sweeps)} sweeps but {len(labels)} labels")
    own = ax is None
    if own:
        import matplotlib.pyplot as plt
        _, ax = plt.subplots(figsize=(7.0, 4.2))
    mech = sweeps[0].mechanism
    lines = []
    for sw, lab in zip(sweeps, labels):
        xs = sw.t if x is None else sw[x]
        for n in flat:
            ys = sw[n]
            text = n if lab is None else (lab if len(flat) == 1 else f"{n}, {lab}")
            lines += ax.plot(xs, ys, label=text, **line_kwargs)
    ax.set_xlabel(f"T [{time}]" if x is None else _label(mech, x, length=length, time=time))
    if len(flat) == 1:
        ax.set_ylabel(_label(mech, flat[0], length=length, time=time))
    else:
        us = {unit(mech, n, length=length, time=time) for n in flat}
        ax.set_ylabel(f"[{us.pop()}]" if len(us) == 1 and "" not in us else "value")
    ax.grid(True, color="#dddddd", linewidth=0.7)
    if len(lines) > 1:
        ax.legend(fontsize="small")
    if title is None:
        title = f"{mech.name}: {', '.join(flat)}" + ("" if x is None else f" against {x}")
    if title:
        ax.set_title(title)
    if own:
        ax.figure.tight_layout()
    return lines


__all__ = ["draw", "draw_modes", "animate", "plot", "motion", "unit", "Drawing", "Animation",
           "Shape", "Disk", "Bar", "Edge", "Plate", "AUTO"]
