"""What the live view draws, read off the drawing ``mechgen draw`` makes: every glyph
(bodies, pins, blocks, rods, the ground's symbols, point labels) as vertices fixed in the
frame it moves with, so that the page moves it over a whole cycle from poses alone.

``mechgen.plot.draw`` builds the glyphs into a matplotlib Axes (never shown); a Builder
that records which frame each joint glyph moves with (a block moves with its point and
the axis it slides on, a rod with its two ends) tells us where each artist goes. A frame
is one of

- ``("fixed",)``: the ground, the global frame;
- ``("body", origin, th)``: a moving body: origin at POINTS[origin], angle q[th];
- ``("axis", k, a1, a2)``: at POINTS[k], along POINTS[a2] - POINTS[a1] (a block);
- ``("pair", k1, k2)``: at POINTS[k1], along POINTS[k2] - POINTS[k1] (a rod);
- ``("point", k)``: at POINTS[k], not turning (a point label).

poses() gives every frame's (x, y, angle) at every time of a cycle; a glyph's vertices at
time i are its local vertices turned by the angle and moved to (x, y). Nothing here
imports sympy; matplotlib draws off-screen (Agg) and is never shown.
"""
from __future__ import annotations

import math

import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.colors import to_hex, to_rgba
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.artist import Artist
from matplotlib.patches import Circle, Patch

from ..plot.drawing import draw
from ..plot.glyphs.builder import Builder
from ..runtime.results import Solution

PT_PX = 96.0 / 72.0      # a matplotlib point in CSS pixels


class Recorder(Builder):
    """The drawing's Builder, noting in ``store`` (a class attribute: see recorder())
    the frame of each glyph a mover, not a body's transform, carries: blocks, rods."""

    store = None                          # id(artist) -> frame spec

    def _glyphs(self):
        return [a for group in self.d.artists.values() for a in group]

    def block(self, k, a1, a2, body):
        before = {id(a) for a in self._glyphs()}
        super().block(k, a1, a2, body)
        for art in self._glyphs():
            if id(art) not in before:
                self.store[id(art)] = ("axis", k, a1, a2)

    def rod(self, k1, k2):
        first = len(self.d.artists["joints"])
        super().rod(k1, k2)
        # the rod itself comes first (its pins and pivots move with their bodies)
        self.store[id(self.d.artists["joints"][first])] = ("pair", k1, k2)


def recorder(store):
    """A Recorder class writing into the dict ``store``."""
    return type("Recording", (Recorder,), {"store": store})


def poses(frames, P, Q):
    """(F, K, 3): x, y and angle of each of the K frames at each of F configurations,
    points P (F, N, 2), coordinates Q (F, n)."""
    F = P.shape[0]
    out = np.zeros((F, len(frames), 3))
    for j, spec in enumerate(frames):
        kind = spec[0]
        if kind == "body":
            _, origin, th = spec
            if origin >= 0:
                out[:, j, :2] = P[:, origin]
            if th is not None:
                out[:, j, 2] = Q[:, th]
        elif kind == "axis":
            _, k, a1, a2 = spec
            d = P[:, a2] - P[:, a1]
            out[:, j, :2] = P[:, k]
            out[:, j, 2] = np.arctan2(d[:, 1], d[:, 0])
        elif kind == "pair":
            _, k1, k2 = spec
            d = P[:, k2] - P[:, k1]
            out[:, j, :2] = P[:, k1]
            out[:, j, 2] = np.arctan2(d[:, 1], d[:, 0])
        elif kind == "point":
            out[:, j, :2] = P[:, spec[1]]
    return out


def _to_local(xy, pose):
    c, s = math.cos(pose[2]), math.sin(pose[2])
    d = np.asarray(xy, dtype=float) - pose[:2]
    return np.column_stack([c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1]])


def _color(c):
    """(hex colour, alpha) of a matplotlib colour, or (None, 0) for none."""
    if c is None or (isinstance(c, str) and c == "none"):
        return None, 0.0
    rgba = to_rgba(c)
    return to_hex(rgba, keep_alpha=False), float(rgba[3])


def circle_vertices(r, size=None) -> int:
    """How many vertices draw a circle of radius r: 20 for a pin, more for a large one (a
    gear's pitch circle, a cam's roller), so that no chord strays from the circle by
    more than 3 % of ``size`` (a bar's half-width, the drawing's unit of detail)."""
    if not size or r <= 0:
        return 20
    return int(max(20, min(240, math.ceil(math.pi * math.sqrt(r / (0.06 * size))))))


def _data_xy(artist, ax, size=None):
    """An artist's vertices in data coordinates at the configuration drawn."""
    extra = Artist.get_transform(artist) - ax.transData
    if isinstance(artist, Circle):
        c, r = np.asarray(artist.center, dtype=float), artist.radius
        a = np.linspace(0.0, 2 * math.pi, circle_vertices(r, size), endpoint=False)
        return extra.transform(c + r * np.column_stack([np.cos(a), np.sin(a)]))
    if isinstance(artist, Patch):
        path = artist.get_path().transformed(artist.get_patch_transform())
        return extra.transform(path.vertices)
    return extra.transform(np.asarray(artist.get_xydata(), dtype=float))


def blank_axes():
    """An off-screen Axes to draw on (never shown). draw() sets its limits itself, so the
    data limits matplotlib updates at every patch added (half of draw()'s time on a
    redraw) are not kept up: the view redraws its glyphs at a slider's move."""
    ax = Figure(figsize=(8.0, 6.0), dpi=72).add_subplot()
    ax._update_patch_limits = lambda patch: None
    return ax


class Picture:
    """The glyphs of one mechanism (one set of parameter values) at a configuration:
    ``frames`` (specs, see the module's docstring), ``pieces`` (dicts: kind "patch",
    "line", "segs" or "dots"; frame; local x, y; colours; z), ``labels`` (text, frame,
    offset in pixels, colour) and ``extent`` (xmin, xmax, ymin, ymax over the motion)."""

    def __init__(self, mech, q0, t0, sweep, labels=True, ax=None, keep_labels=None):
        if ax is None:
            ax = blank_axes()
        else:       # an Axes drawn on before: emptied (cheaper than a new one)
            for art in list(ax.patches) + list(ax.lines) + list(ax.collections) + \
                    list(ax.texts) + list(ax.artists):
                art.remove()
        self.ax = ax
        sol = Solution(mech, float(t0), np.asarray(q0, dtype=float))
        recorded = {}
        d = draw(mech, sol, ax=ax, sweep=sweep, labels=labels, title=False, grid=False,
                 builder=recorder(recorded))
        self.drawing = d
        st = d.structure
        frames = [("fixed",)]
        index = {frames[0]: 0}

        def frame_of(spec):
            if spec not in index:
                index[spec] = len(frames)
                frames.append(spec)
            return index[spec]

        body_tf = {id(tf): (b.origin, b.th) for b in st.bodies
                   for name, tf in d.transforms.items() if name == b.name}
        P0 = sol.points()
        self.pieces, self.labels = [], []
        label_ids = {id(art) for _, art in d.labels}
        for group, arts in d.artists.items():
            if group == "traces":
                continue
            for art in arts:
                if id(art) in label_ids or not art.get_visible():
                    continue
                spec = recorded.get(id(art))
                if spec is None:
                    tf = getattr(Artist.get_transform(art), "_a", None)
                    spec = ("body",) + body_tf[id(tf)] if id(tf) in body_tf else ("fixed",)
                piece = _piece(art, ax, d.size)
                if piece is None:
                    continue
                j = frame_of(spec)
                pose = poses([spec], P0[None], sol.q[None])[0, 0]
                if piece["kind"] == "segs":
                    segs = piece["segs"]           # all at once, then split again
                    cut = np.cumsum([len(seg) for seg in segs])[:-1]
                    flat = np.concatenate(segs) if segs else np.zeros((0, 2))
                    piece["segs"] = np.split(_to_local(flat, pose), cut)
                else:
                    piece["xy"] = _to_local(piece["xy"], pose)
                piece["frame"] = j
                piece["owner"] = group        # a body's name, or "joints"
                self.pieces.append(piece)
        for text, art in d.labels:
            k = _label_point(art, P0)
            if k is None:
                continue
            off = getattr(art, "xybox", None) or getattr(art, "xyann", (0.0, 0.0))
            color = _label_color(art)
            self.labels.append(dict(text=text, point=k, frame=frame_of(("point", k)),
                                    dx=float(off[0]) * PT_PX, dy=float(off[1]) * PT_PX,
                                    color=color))
        for lab in keep_labels or ():     # labels placed before, on this drawing again
            self.labels.append(dict(lab, frame=frame_of(("point", lab["point"]))))
        self.frames = frames
        self.extent = tuple(float(v) for v in d.frame)


def _label_point(art, P0):
    """The POINTS index a label names (the point nearest its anchor)."""
    xy = getattr(art, "xy", None)
    if xy is None:
        return None
    tf = art.xycoords if not isinstance(art.xycoords, str) else None
    where = np.asarray(tf.transform(xy) if tf is not None else xy, dtype=float)
    if tf is not None:     # display back to data
        where = art.axes.transData.inverted().transform(where)
    return int(np.argmin(np.hypot(*(P0 - where).T)))


def _label_color(art):
    try:
        return _color(art.get_color())[0]
    except AttributeError:
        return "#222222"


def _piece(art, ax, size=None):
    """A glyph as a dict (kind, vertices in data coordinates, style), or None."""
    z = float(art.get_zorder())
    if isinstance(art, LineCollection):
        segs = [np.asarray(s, dtype=float) for s in art.get_segments()]
        extra = Artist.get_transform(art) - ax.transData
        segs = [extra.transform(s) for s in segs if len(s)]
        color = _color(art.get_edgecolor()[0] if len(art.get_edgecolor()) else "#222222")
        width = float(np.ravel(art.get_linewidths())[0]) if len(art.get_linewidths()) else 1.0
        return dict(kind="segs", segs=segs, line=color[0], alpha=color[1],
                    width=width * PT_PX, z=z)
    if isinstance(art, Patch):
        fill, falpha = _color(art.get_facecolor())
        if falpha == 0.0:       # facecolor "none" (an internal gear's pitch circle): no
            fill = None         # fill, whatever the patch's alpha (matplotlib's rule)
        edge, _ = _color(art.get_edgecolor())
        alpha = art.get_alpha()
        return dict(kind="patch", xy=_data_xy(art, ax, size), fill=fill,
                    fill_alpha=falpha if alpha is None else float(alpha), line=edge,
                    width=float(art.get_linewidth()) * PT_PX, z=z)
    if isinstance(art, Line2D):
        color, alpha = _color(art.get_color())
        if art.get_linestyle() in ("None", "none", "", " ") and art.get_marker() not in (None, "None", "none"):
            return dict(kind="dots", xy=_data_xy(art, ax), line=color, alpha=alpha,
                        size=float(art.get_markersize()) * PT_PX, z=z)
        return dict(kind="line", xy=_data_xy(art, ax), line=color, alpha=alpha,
                    width=float(art.get_linewidth()) * PT_PX, z=z)
    return None
