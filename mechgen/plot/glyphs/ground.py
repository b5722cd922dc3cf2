"""The ground's symbols, placed where they hide nothing: the fixed link's bars only where
they cross no other body at the drawn configuration (a four-bar's fourth bar, not a bar
through meshing gears or across a cam), each pivot's triangle standing below its point or
hanging above it, whichever side its links leave free over the motion, and a pivot under a
cam drawn over the cam's plate (which would hide it).

Read off the Builder (mechgen.plot.glyphs.builder): the drawn configuration P0, the motion P, the
gears' pitch circles (plot.glyphs.gears) and the cams' outlines (plot.glyphs.cams)."""
from __future__ import annotations

import math

import numpy as np
from matplotlib.path import Path

from .shapes import hull

PIVOT_ON_CAM = 2.15      # above a cam's plate (2 + 0.01 body number) and its hub


def _segment_distance(x, a, b):
    """Distance from each point x (k, 2) to the segment a-b."""
    d = b - a
    L2 = float(d @ d)
    s = np.zeros(len(x)) if L2 == 0 else np.clip((x - a) @ d / L2, 0.0, 1.0)
    return np.hypot(*(x - (a + s[:, None] * d)).T)


def _outline_distance(x, poly):
    """Distance from points x (k, 2) to a convex outline (a point, a segment or a
    polygon; 0 inside it)."""
    if len(poly) == 1:
        return np.hypot(*(x - poly[0]).T)
    if len(poly) == 2:
        return _segment_distance(x, poly[0], poly[1])
    dist = np.min([_segment_distance(x, poly[i], poly[(i + 1) % len(poly)])
                   for i in range(len(poly))], axis=0)
    inside = Path(poly).contains_points(x)
    return np.where(inside, 0.0, dist)


def obstacles(bld):
    """What a ground bar must not cross at the drawn configuration: the moving bodies'
    outlines (convex hulls of the points they are drawn through, global) and the gears'
    pitch discs and the cams' plates (global polygons and (centre, radius) discs)."""
    outlines = []
    for b in bld.st.bodies:
        if b.ground:
            continue
        keep = bld.outline_points(b)
        if keep:
            outlines.append(hull(np.array([bld.P0[k] for k in keep])))
    for _, ks in getattr(bld, "cam_outlines", ()):
        outlines.append(np.array([bld.P0[k] for k in ks]))
    return outlines, list(getattr(bld, "gear_discs", ()))


def crosses(bld, i, j, outlines, discs) -> bool:
    """Whether a bar from ground point i to j would cross a body, a pitch circle or a cam
    beyond the pins at its ends."""
    a, b = bld.P0[i], bld.P0[j]
    L = math.hypot(*(b - a))
    end = 2.5 * bld.w                 # a pin and a link leaving it sit at each end
    if L <= 2 * end:
        return False
    s = np.linspace(end, L - end, max(8, int(L / bld.w)))
    x = a + s[:, None] * (b - a) / L
    clear = 1.6 * bld.w               # a body's half-width and the bar's
    for c, r in discs:
        if np.any(np.hypot(*(x - c).T) < abs(r) + 0.6 * bld.w):
            return True
    return any(np.any(_outline_distance(x, poly) < clear) for poly in outlines)


def hangs(bld, k) -> bool:
    """Whether the pivot at ground point k should hang above it (its triangle pointing
    down onto the point from a base above) rather than stand below it: when the links
    pinned there spend clearly more of the motion below the pivot than above it."""
    below = above = 0
    for _, kind, used in bld.st.joints:
        if kind != "revolute" or k not in used or len(used) != 2:
            continue
        other = used[1] if used[0] == k else used[0]
        body = bld.body_of(other)
        if body.ground:
            continue
        pts = [p for p in bld.outline_points(body) if p != other] or [other]
        d = bld.P[:, pts] - bld.P[:, [k]]           # (F, n, 2) from the pivot
        far = np.hypot(d[..., 0], d[..., 1]) > 2 * bld.w
        steep = np.abs(d[..., 1]) > 0.5 * np.abs(d[..., 0])   # within ~63° of the vertical
        below += int(np.sum(far & steep & (d[..., 1] < 0)))
        above += int(np.sum(far & steep & (d[..., 1] > 0)))
    return below > 2 * above


def lift_cam_pivots(bld):
    """Pivots inside a cam's outline drawn over the cam's plate."""
    outlines = [np.array([bld.P0[k] for k in ks]) for _, ks in getattr(bld, "cam_outlines", ())]
    for k, artists in getattr(bld, "pivots", {}).items():
        if any(Path(poly).contains_point(bld.P0[k]) for poly in outlines):
            for art in artists:
                art.set_zorder(PIVOT_ON_CAM)
