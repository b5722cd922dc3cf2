"""Point labels (P1, P2, ...) placed where they collide with nothing.

A point several bodies share (a joint) gets one label: the bodies' point numbers in their
own colours, in body order, joined by a middle dot ("P2·P1·P1": P2 of the first body, P1
of the next two), so that a joint of four bodies does not carry four labels on top of
each other. Points merge when they coincide over the whole motion the drawing covers.

Each label is placed greedily, the hardest first (the most crowded spots), among
candidate spots around its point: 16 directions at a few distances. A spot is scored on
screen, at the drawn configuration, against everything already on the axes: other labels
and text (never overlapped), lines and hatching (never struck through), pins and blocks
(never hidden), the outlines and fills of bodies (avoided where possible), the edge of the
axes; then nearness and the direction away from the point's bodies. A second round moves
each label again with all the others in place.
"""
from __future__ import annotations

import math

import numpy as np
from matplotlib import patheffects
from matplotlib.collections import LineCollection
from matplotlib.colors import to_rgba
from matplotlib.lines import Line2D
from matplotlib.offsetbox import AnnotationBbox, HPacker, TextArea
from matplotlib.patches import FancyArrow, Patch
from matplotlib.text import Text

from .style import INK

JOIN = "·"                            # between the numbers of a point several bodies share
GAPS = (2.0, 6.0, 11.0, 18.0, 28.0)   # candidate distances from the pin, in points
TURNS = 16                            # candidate directions
MARGIN = 1.5                          # pixels kept free around a label
MARK = 36.0                           # a filled shape smaller than this (points) is a pin
                                      # or a block, to keep visible
# the cost of a spot (a label that cannot avoid everything takes the cheapest)
W_TEXT = 1e5      # overlapping another label or text
W_LINE = 1e3      # per line or hatching segment struck through
W_MARK = 400.0    # hiding a pin or block (fraction of the label covering it)
W_DARK = 300.0    # sitting on a dark fill (a connecting rod)
W_EDGE = 30.0     # per outline segment of a body crossed
W_FILL = 3.0      # sitting on a body's light fill (fraction covered)
W_OUT = 1e4       # leaving the axes
W_FAR = 0.35      # per pixel of distance from the pin
W_TURN = 4.0      # turning from the preferred direction (1 - cos)
HALO = [patheffects.withStroke(linewidth=2.2, foreground="white")]   # legible on a fill


class Obstacles:
    """Everything on the axes a label must keep off, in display pixels."""

    def __init__(self, ax, renderer, skip=()):
        self.mark = MARK * ax.figure.dpi / 72.0
        self.boxes = []                        # text: (x0, y0, x1, y1)
        self.lines = []                        # segments not to strike through
        self.edges = []                        # outline segments of filled shapes
        self.fills = []                        # (Path, weight per covered fraction)
        skip = {id(a) for a in skip}
        children = list(ax.patches) + list(ax.lines) + list(ax.collections) + \
            list(ax.texts) + list(ax.artists)
        for art in children:
            if id(art) in skip or not art.get_visible():
                continue
            if isinstance(art, Patch):
                self._patch(art)
            elif isinstance(art, Line2D):
                self._line(art, ax)
            elif isinstance(art, LineCollection):
                tf = art.get_transform()
                for seg in art.get_segments():
                    self._polyline(tf.transform(np.asarray(seg, dtype=float)), self.lines)
            elif isinstance(art, (Text, AnnotationBbox)):
                if isinstance(art, Text) and not art.get_text().strip():
                    continue
                bb = art.get_window_extent(renderer)
                self.boxes.append((bb.x0, bb.y0, bb.x1, bb.y1))
        self.lines = np.array(self.lines).reshape(-1, 2, 2)
        self.edges = np.array(self.edges).reshape(-1, 2, 2)

    @staticmethod
    def _polyline(xy, out, closed=False):
        xy = xy[np.all(np.isfinite(xy), axis=1)]
        if closed and len(xy) > 2:
            xy = np.vstack([xy, xy[:1]])
        out.extend(np.stack([xy[:-1], xy[1:]], axis=1))

    def _line(self, line, ax):
        xy = line.get_transform().transform(np.asarray(line.get_xydata(), dtype=float))
        if line.get_linestyle() not in ("None", "none", " ", ""):
            self._polyline(xy, self.lines)
        if line.get_marker() not in (None, "None", "none", " ", ""):
            r = line.get_markersize() * ax.figure.dpi / 72.0 / 2 + 1.0
            self.boxes.extend((x - r, y - r, x + r, y + r) for x, y in xy
                              if np.isfinite(x) and np.isfinite(y))

    def _patch(self, patch):
        path = patch.get_path().transformed(patch.get_transform())
        polys = path.to_polygons(closed_only=False)
        if not polys:
            return
        xy = np.concatenate(polys)
        ext = xy.max(axis=0) - xy.min(axis=0)
        area = sum(abs(_area(p)) for p in polys)
        perimeter = sum(np.hypot(*np.diff(p, axis=0).T).sum() for p in polys) or 1.0
        if isinstance(patch, FancyArrow) or area / perimeter < 1.2:   # an arrow, a thin bar
            for p in polys:
                self._polyline(p, self.lines, closed=True)
            return
        for p in polys:
            self._polyline(p, self.edges, closed=True)
        face = to_rgba(patch.get_facecolor())
        if not patch.get_fill() or face[3] == 0:
            return
        luminance = 0.3 * face[0] + 0.59 * face[1] + 0.11 * face[2]
        if max(ext) < self.mark:
            weight = W_MARK                       # a pin, a block: keep it visible
        elif luminance < 0.45:
            weight = W_DARK
        else:
            weight = W_FILL
        self.fills.append((path, weight))


def renderer_of(fig):
    """The renderer that measures text on the figure's canvas."""
    get = getattr(fig.canvas, "get_renderer", None)
    return get() if get is not None else fig._get_renderer()


def _area(p):
    return 0.5 * float(np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1]))


def crossings(rects, segs):
    """How many of the segments (S, 2, 2) meet each rectangle (C, 4) (x0, y0, x1, y1):
    Liang-Barsky clipping, all pairs at once."""
    if not len(segs) or not len(rects):
        return np.zeros(len(rects))
    p, d = segs[:, 0], segs[:, 1] - segs[:, 0]
    t0 = np.zeros((len(rects), len(segs)))
    t1 = np.ones_like(t0)
    for axis, (lo, hi) in enumerate(((rects[:, 0], rects[:, 2]), (rects[:, 1], rects[:, 3]))):
        pa, da = p[:, axis][None], d[:, axis][None]
        lo, hi = lo[:, None], hi[:, None]
        flat = da == 0
        with np.errstate(divide="ignore", invalid="ignore"):
            ta, tb = (lo - pa) / da, (hi - pa) / da
        inside = (pa >= lo) & (pa <= hi)
        tmin = np.where(flat, np.where(inside, -np.inf, np.inf), np.minimum(ta, tb))
        tmax = np.where(flat, np.where(inside, np.inf, -np.inf), np.maximum(ta, tb))
        t0, t1 = np.maximum(t0, tmin), np.minimum(t1, tmax)
    return (t0 <= t1).sum(axis=1).astype(float)


def overlaps(rects, boxes):
    """How many boxes (B, 4) each rectangle (C, 4) overlaps."""
    if not len(boxes) or not len(rects):
        return np.zeros(len(rects))
    b = np.asarray(boxes, dtype=float)
    hit = ((rects[:, None, 0] < b[None, :, 2]) & (b[None, :, 0] < rects[:, None, 2]) &
           (rects[:, None, 1] < b[None, :, 3]) & (b[None, :, 1] < rects[:, None, 3]))
    return hit.sum(axis=1).astype(float)


class Label:
    """One label: the point it names (display pixels), its size, the spot chosen."""

    def __init__(self, artist, at, size, prefer, clear):
        self.artist = artist
        self.at = np.asarray(at, dtype=float)      # the point, pixels
        self.size = np.asarray(size, dtype=float)  # width, height, pixels
        self.prefer = prefer                       # unit direction to favour
        self.clear = clear                         # pixels from the point to keep clear
        self.box = None                            # the spot chosen (x0, y0, x1, y1)
        self.offset = None                         # its centre from the point, pixels

    def candidates(self, px_per_pt):
        """(centres (C, 2), rectangles (C, 4), cost of distance and direction (C,))."""
        a = np.arange(TURNS) * (2 * math.pi / TURNS)
        d = np.column_stack([np.cos(a), np.sin(a)])
        half = self.size / 2 + MARGIN
        with np.errstate(divide="ignore"):
            reach = np.minimum(half[0] / np.abs(d[:, 0]), half[1] / np.abs(d[:, 1]))
        centres, cost = [], []
        for gap in GAPS:
            r = self.clear + gap * px_per_pt
            centres.append(self.at + d * (r + reach)[:, None])
            cost.append(W_FAR * (r - self.clear) + W_TURN * (1.0 - d @ self.prefer))
        c = np.concatenate(centres)
        rects = np.column_stack([c - half, c + half])
        return c, rects, np.concatenate(cost)


def _score(rects, obstacles, placed, inside):
    cost = W_TEXT * (overlaps(rects, obstacles.boxes) + overlaps(rects, placed))
    cost += W_LINE * crossings(rects, obstacles.lines)
    cost += W_EDGE * crossings(rects, obstacles.edges)
    # fills: the share of a 3 x 3 grid over the label that a shape covers
    fx, fy = np.meshgrid((0.1, 0.5, 0.9), (0.1, 0.5, 0.9))
    grid = np.column_stack([fx.ravel(), fy.ravel()])
    pts = (rects[:, None, :2] + grid[None] * (rects[:, None, 2:] - rects[:, None, :2]))
    flat = pts.reshape(-1, 2)
    for path, weight in obstacles.fills:
        cost += weight * path.contains_points(flat).reshape(len(rects), -1).mean(axis=1)
    x0, y0, x1, y1 = inside
    out = (rects[:, 0] < x0) | (rects[:, 1] < y0) | (rects[:, 2] > x1) | (rects[:, 3] > y1)
    return cost + W_OUT * out


def place(labels, obstacles, inside, px_per_pt, rounds=2):
    """Choose every label's spot (sets ``label.box`` and the centre's offset in pixels,
    ``label.offset``): the most crowded first, then ``rounds - 1`` rounds of moving each
    label again with all the others in place."""
    if not labels:
        return
    at = np.array([lb.at for lb in labels])
    crowd = [int(np.sum(np.hypot(*(at - lb.at).T) < 4 * lb.size[1])) + lb.size[0] / 100
             for lb in labels]
    order = sorted(range(len(labels)), key=lambda i: -crowd[i])
    for rnd in range(rounds):
        for i in order:
            lb = labels[i]
            others = [o.box for o in labels if o is not lb and o.box is not None]
            centres, rects, cost = lb.candidates(px_per_pt)
            total = cost + _score(rects, obstacles, others, inside)
            best = int(np.argmin(total))
            lb.box = tuple(rects[best] + (MARGIN, MARGIN, -MARGIN, -MARGIN))
            lb.offset = centres[best] - lb.at


def label_artist(ax, pieces, xy, transform, fontsize):
    """The label's artist at offset (0, 0) from xy (in ``transform`` coordinates): a text
    for one body's point, a row of coloured numbers for a point bodies share.
    ``pieces``: [(text, colour)]."""
    common = dict(xy=xy, xycoords=transform, annotation_clip=False)
    if len(pieces) == 1:
        text, color = pieces[0]
        art = ax.annotate(text, xytext=(0.0, 0.0), textcoords="offset points", ha="center",
                          va="center", fontsize=fontsize, color=color, zorder=6,
                          path_effects=HALO, **common)
        return art
    parts = []
    for n, (text, color) in enumerate(pieces):
        if n:
            parts.append(TextArea(JOIN, textprops=dict(color=INK, fontsize=fontsize,
                                                       path_effects=HALO)))
        parts.append(TextArea(text, textprops=dict(color=color, fontsize=fontsize,
                                                   path_effects=HALO)))
    row = HPacker(children=parts, align="baseline", pad=0, sep=0)
    art = AnnotationBbox(row, xybox=(0.0, 0.0), boxcoords="offset points", frameon=False,
                         pad=0.0, box_alignment=(0.5, 0.5), zorder=6, **common)
    ax.add_artist(art)
    return art


def set_offset(artist, offset_pt):
    """Move a label made by label_artist to an offset (points) from its point."""
    if isinstance(artist, AnnotationBbox):
        artist.xybox = tuple(offset_pt)
    else:
        artist.xyann = tuple(offset_pt)


def put_labels(bld, bodies, fontsize, named=False):
    """Label the points of ``bodies`` in the drawing a glyphs.Builder ``bld`` is making
    (its configuration P0, motion P, bar size w) and place them; returns a function
    that places them again where the figure's layout or the configuration has changed
    (``Drawing.place_labels``). ``named``: each point as ``body.P2`` (a forces drawing,
    where the labels are read beside the arrows' names), not P2 alone."""
    if not bodies:
        return lambda: None
    ax, d = bld.ax, bld.d
    renderer = renderer_of(ax.figure)
    tol = 1e-6 * bld.span
    groups = []          # [(body, number, POINTS index)] of points that stay together
    for b in sorted(bodies, key=lambda b: bld.bi[b.name]):
        for n, k in enumerate(b.pts, start=1):
            for g in groups:
                if np.abs(bld.P[:, k] - bld.P[:, g[0][2]]).max() <= tol:
                    g.append((b, n, k))
                    break
            else:
                groups.append([(b, n, k)])
    made = []            # (artist, POINTS index, the bodies' points around it)
    for g in groups:
        host, _, k = next((m for m in g if not m[0].ground), g[0])   # moves with it
        pieces = [(f"{b.name}.P{n}" if named else f"P{n}", b.edge) for b, n, _ in g]
        art = label_artist(ax, pieces, bld.local(host, k), bld.trans(host), fontsize)
        d.artists[host.name].append(art)
        d.labels.append((JOIN.join(text for text, _ in pieces), art))
        made.append((art, k, [b.pts for b, _, _ in g]))
    pin = 0.85 * bld.w

    def again():
        P = d.points if d.points is not None else bld.P0
        ax.apply_aspect()
        fig = ax.figure
        to_px = ax.transData.transform
        px_per_pt = fig.dpi / 72.0
        scale = abs(to_px((1.0, 0.0))[0] - to_px((0.0, 0.0))[0])   # pixels per length
        obstacles = Obstacles(ax, renderer, skip=[art for art, _, _ in made])
        placed = []
        for art, k, around in made:
            prefer = np.zeros(2)
            for pts in around:      # away from the middle of each body the point is on
                away = P[k] - np.mean([P[j] for j in pts], axis=0)
                norm = math.hypot(*away)
                prefer += away / norm if norm > 1e-9 * bld.span else 0.0
            norm = math.hypot(*prefer)
            prefer = prefer / norm if norm > 1e-9 else np.array([0.6, 0.8])
            set_offset(art, (0.0, 0.0))
            bb = art.get_window_extent(renderer)
            placed.append(Label(art, to_px(P[k]), (bb.width, bb.height), prefer,
                                pin * scale + 1.0))
        frame = ax.get_window_extent(renderer)
        place(placed, obstacles, (frame.x0, frame.y0, frame.x1, frame.y1), px_per_pt)
        for lb in placed:
            set_offset(lb.artist, lb.offset / px_per_pt)
    again()
    return again
