"""Cams in a drawing: each profile as a closed outline fixed in its cam's frame (so that it
turns with the body), a roller follower as a circle on its follower, and the contact
point marked. Read from the module's JOINTS: a cam constraint lists its follower's points
(cam_to_point: the point, then a rim point of the roller when it has one; cam_to_line:
the axis' points) and then PROFILE_POINTS points of each profile
(mechgen.model.library2d.cams lists them)."""
from __future__ import annotations

import numpy as np
from matplotlib.patches import Circle, Polygon

from ..style import INK

KINDS = ("cam_to_point", "cam_to_line", "cam_to_cam")
PROFILE_POINTS = 96       # as model.library2d.cams.PROFILE_POINTS (tests/test_cams.py checks)


def profile_indices(kind, used):
    """(follower point indices, [profile point indices, ...]) of a cam joint."""
    used = list(used)
    n = 2 if kind == "cam_to_cam" else 1
    head = len(used) - n * PROFILE_POINTS
    profiles = [used[head + i * PROFILE_POINTS: head + (i + 1) * PROFILE_POINTS]
                for i in range(n)]
    return used[:head], profiles


def draw(bld, kind, used):
    """Add the glyphs of one cam joint to the Builder ``bld`` (mechgen.plot.glyphs.builder)."""
    follower, profiles = profile_indices(kind, used)
    if any(len(p) != PROFILE_POINTS for p in profiles):
        return
    if not hasattr(bld, "profiled"):
        bld.profiled = set()          # points the body outlines leave out (glyphs.body_shape)
        bld.cam_outlines = set()
    for ks in profiles:
        body = bld.body_of(ks[0])
        bld.profiled.update(ks)
        key = (body.name, tuple(ks))
        if key in bld.cam_outlines:
            continue
        bld.cam_outlines.add(key)
        xy = np.array([bld.local(body, k) for k in ks])
        bld.add(body.name, Polygon(xy, closed=True, facecolor=body.fill, edgecolor=body.edge,
                                   linewidth=1.3, zorder=2 + 0.01 * body.number), body)
        hub = bld.local(body, body.origin) if body.origin >= 0 else np.zeros(2)
        bld.add(body.name, Circle(hub, 0.5 * bld.w, facecolor="white", edgecolor=INK,
                                  linewidth=1.0, zorder=2.1 + 0.01 * body.number), body)
    if kind == "cam_to_point" and len(follower) == 2:     # a roller, centred at the point
        k, rim = follower
        bld.profiled.add(rim)
        fb = bld.body_of(k)
        r = float(np.hypot(*(bld.P0[rim] - bld.P0[k])))
        bld.add(fb.name, Circle(bld.local(fb, k), r, facecolor="#f4f4f4", edgecolor=INK,
                                linewidth=1.2, zorder=4.5), fb)
        bld.pin(fb, k, 0.45 * bld.w)
