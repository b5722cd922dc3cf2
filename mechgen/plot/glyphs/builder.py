"""The glyphs of a drawing, read off the constraints: pins and ground pivots (revolute),
slots and sliding blocks (point_on_line), boxes on guides (translate), connecting rods
(relative_distance), the bodies as bars or rounded plates, custom shapes, point labels,
local axes, and the frame that covers it all over the motion."""
from __future__ import annotations

import math

import numpy as np
from matplotlib.collections import Collection, LineCollection
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, FancyArrow, Patch, Polygon, Rectangle
from matplotlib.transforms import Affine2D

from ...errors import MechgenError
from ..labels import put_labels
from ..style import BAR, GROUND, INK, MARGIN
from .gears import pitch_markers
from .ground import crosses, hangs, obstacles
from .shapes import AUTO, Shape, hatch, hull, rot, rounded


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


class Builder:
    """Puts the glyphs into a Drawing at configuration (P0, q0), sized and framed by the
    motion (P, Q); each glyph is fixed in its body's frame or moved by the drawing."""

    def __init__(self, drawing, P0, q0, t0, P, Q):
        self.d = drawing
        self.ax, self.st = drawing.ax, drawing.structure
        st = self.st
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
                self.d.transforms[b.name] = Affine2D()
        self.d.set_state(P0, q0, t0)
        self.slotted = set()
        self.boxed = {}
        self.pivots = {}            # ground point -> its pivot's artists (plot.glyphs.ground)

    # frames and local coordinates
    def trans(self, body):
        tf = self.d.transforms.get(body.name)
        return self.ax.transData if tf is None else tf + self.ax.transData

    def local(self, body, k, P=None):
        """Point k (POINTS index) in body's frame, at the drawn configuration."""
        i = self.bi[body.name]
        R = rot(self.ang0[i])
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
        """A ground pivot: a triangle on a hatched base, standing below the point, or
        hanging above it where its links swing below (plot.glyphs.ground.hangs)."""
        if k in self.pivots:
            return
        x, y = self.P0[k]
        w = self.w
        up = -1.0 if hangs(self, k) else 1.0
        h, half, foot = 3.0 * w * up, 1.9 * w, 3.0 * w
        ground = self.st.by_name[self.st.owner[k]]
        base = np.array([(x - foot, y - h), (x + foot, y - h)])
        self.pivots[k] = [
            self.add(ground.name, Polygon([(x, y), (x - half, y - h), (x + half, y - h)],
                                          closed=True, facecolor="#e6e6e6", edgecolor=INK,
                                          linewidth=1.0, zorder=1.2)),
            self.add(ground.name, Line2D(base[:, 0], base[:, 1], color=INK, linewidth=1.4,
                                         zorder=1.2)),
            self.add(ground.name, LineCollection(hatch(base, 1.1 * w, 1.3 * w, up),
                                                 colors=INK, linewidths=0.8, zorder=1.2))]

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
        self.add(ground.name, LineCollection(hatch(path, 1.1 * self.w, 1.4 * self.w,
                                                    hatch_side), colors=INK, linewidths=0.8,
                                             zorder=1.2))

    def free_side(self, ground, a1, a2):
        """The unit normal of the ground's axis a1->a2 pointing away from the ground's other
        points (its left when all lie on the axis): where a slider's box sits. Read off
        the ground alone, so that every drawing and animation puts it on the same side."""
        A, B = self.P0[a1], self.P0[a2]
        u = (B - A) / (math.hypot(*(B - A)) or 1.0)
        left = np.array([-u[1], u[0]])
        off = [(self.P0[k] - A) @ left for k in ground.pts]
        off = [x for x in off if abs(x) > 1e-9 * self.span]
        return -left if off and np.mean(off) > 0 else left

    def ground_link(self, ground):
        """The fixed link between the ground's pivots (a four-bar's fourth bar): grey bars
        along the shortest tree joining the ground points that hold a moving body."""
        pivots = []
        for _, kind, used in self.st.joints:
            if kind not in ("revolute", "relative_distance") or len(used) != 2:
                continue
            b1, b2 = self.body_of(used[0]), self.body_of(used[1])
            for k, other in ((used[0], b2), (used[1], b1)):
                if self.body_of(k) is ground and not other.ground and \
                        all(math.hypot(*(self.P0[k] - self.P0[j])) > 1e-9 * self.span
                            for j in pivots):
                    pivots.append(k)
        if len(pivots) < 2:
            return
        outlines, discs = obstacles(self)
        joined, rest = [pivots[0]], pivots[1:]
        while rest:       # Prim: the nearest pivot not yet joined by a bar that is clear
            edges = sorted((math.hypot(*(self.P0[i] - self.P0[j])), i, j)
                           for i in joined for j in rest)
            edge = next(((i, j) for _, i, j in edges
                         if not crosses(self, i, j, outlines, discs)), None)
            if edge is None:    # the rest stand on their own symbols
                joined.append(rest.pop(0))
                continue
            i, j = edge
            self.add(ground.name, Polygon(rounded([self.P0[i], self.P0[j]], 0.6 * self.w),
                                          closed=True, facecolor=GROUND[0], edgecolor=INK,
                                          linewidth=1.0, zorder=1.1))
            joined.append(j)
            rest.remove(j)

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
        self.add(body.name, Polygon(rounded(ends, hs), closed=True, facecolor="white",
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
        self.d.on_move(move)

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
        if g.ground:                       # the box sits on the guide, on its free side
            R = rot(self.ang0[self.bi[s.name]])
            sign = 1.0 if (R @ n) @ self.free_side(g, a1, a2) >= 0 else -1.0
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
                    ext.append(org[f, i] + rot(ang[f, i]) @ c)
            R = rot(self.ang0[i])
            self.rail(g, a1, a2, np.array(ext), R @ (n * (hi + lo)))
        else:
            self.slot(g, a1, a2, [self.local(g, b1), self.local(g, b2)])

    def rod(self, k1, k2):
        """A connecting rod between two points (relative_distance)."""
        r = 0.55 * self.w
        poly = self.add("joints", Polygon(rounded([self.P0[k1], self.P0[k2]], r, 12),
                                          closed=True, facecolor="#555555", edgecolor=INK,
                                          linewidth=1.0, zorder=4))
        ring = [(r * math.cos(a), r * math.sin(a)) for a in np.linspace(0, 2 * math.pi, 12,
                                                                          endpoint=False)]
        ring = np.array(ring)

        def move(P, q, t, poly=poly):
            poly.set_xy(hull(np.concatenate([P[k1] + ring, P[k2] + ring])))
        self.d.on_move(move)
        for k in (k1, k2):
            b = self.body_of(k)
            if b.ground:
                self.pivot(k)
            self.pin(b, k, 0.6 * self.w)

    # bodies
    def outline_points(self, b):
        """The POINTS indices a body's outline is drawn through: its own points and those
        its joints name, less a gear's pitch markers (plot.gears draws the pitch circle:
        a crank on a gear is as long as its points) and a cam's profile (plot.glyphs.cams)."""
        markers = pitch_markers(self.st.joints)
        return [k for k in b.every if (k in b.pts or k not in markers and (
                k != b.origin or any(k in used for _, _, used in self.st.joints)))
                and k not in getattr(self, "profiled", ())]

    def body_shape(self, b):
        keep = self.outline_points(b)
        if not keep and getattr(self, "profiled", ()) and b.every:
            return                                    # a cam body: its profile is its shape
        if not keep:
            keep = [b.origin]
        pts = np.array([self.local(b, k) for k in keep])
        r = (1.45 if b.name in self.slotted else 1.0) * self.w
        self.add(b.name, Polygon(rounded(pts, r), closed=True, facecolor=b.fill,
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
        self.d.redrawn.add(b.name)

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
        self.d.on_move(move)

    def labels(self, bodies, fontsize, named=False):
        """P1, P2, ... next to the points of the bodies, where they collide with nothing
        (mechgen.plot.labels); one label for a point several of them share; ``named``:
        body.P1, body.P2, ..."""
        self.d._place_labels = put_labels(self, bodies, fontsize, named=named)

    def local_axes(self, bodies, fontsize):
        for b in bodies:
            L = (0.12 if b.ground else 0.07) * self.span
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
            if b.ground or b.name not in self.d.transforms:
                boxes.append(V)
                continue
            i = self.bi[b.name]
            for f in range(0, self.P.shape[0], step):
                boxes.append(org[f, i] + V @ rot(ang[f, i]).T)
        allv = np.concatenate(boxes)
        lo, hi = allv.min(axis=0), allv.max(axis=0)
        pad = MARGIN * float(max(hi - lo) or 1.0)
        return (lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad)
