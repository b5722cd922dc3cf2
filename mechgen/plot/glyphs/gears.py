"""Glyphs for the kinds of Mech's 2D library that drawing.py's own loop does not know:
gears and racks (pitch circles and a toothed pitch line with tick marks fixed in their
bodies, so that rolling shows), and the joints that reuse other glyphs (gen_revolute and
origin_lock as pins, gen_translate as a slider, point_on_lines as two sliding blocks).

Read off ``JOINTS``: a gear joint names its centre and a pitch marker (the point r along
the body's x axis from the centre: its distance is the radius, its side the sign, a
negative radius being an internal gear); a rack joint the pinion's centre and marker and
the rack's pitch line (two points of the rack's body).
"""
from __future__ import annotations

import math

import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.patches import Circle, Polygon

from ..style import INK
from .shapes import rot

GEAR_KINDS = ("gears", "gear_ratio")
RACK_KINDS = ("rack_and_pinion", "rack_ratio")
TEETH = 18            # ticks on the smallest pitch circle of a drawing


def pitch_markers(joints) -> set:
    """The POINTS indices that gear and rack joints name only as pitch markers (where a
    pitch circle passes, not a point of the body's own): a body's outline leaves them
    out, so that a crank on a gear is drawn as long as its own points, not its radius."""
    markers, named = set(), set()
    for _, kind, used in joints:
        if kind in GEAR_KINDS and len(used) == 4:
            markers.update((used[1], used[3]))
            named.update((used[0], used[2]))
        elif kind in RACK_KINDS and len(used) == 4:
            markers.add(used[1])
            named.update((used[0], used[2], used[3]))
        else:
            named.update(used)
    return markers - named


def _radius(bld, body, centre, marker):
    v = bld.local(body, marker) - bld.local(body, centre)
    r = math.hypot(*v)
    return r if v[0] >= 0 else -r


def _contact(bld, c1, r1, c2, r2):
    """Where two pitch circles touch at the drawn configuration (global), or None."""
    C1, C2 = bld.P0[c1], bld.P0[c2]
    d = C2 - C1
    L = math.hypot(*d)
    if L < 1e-12 * bld.span:
        return None
    sign = 1.0 if r1 + r2 > 0 else -1.0
    return C1 + sign * r1 * d / L


def _local_angle(bld, body, centre, point):
    i = bld.bi[body.name]
    v = rot(bld.ang0[i]).T @ (point - bld.P0[centre])
    return math.atan2(v[1], v[0])


def gear(bld, body, centre, r, pitch, phase):
    """A pitch circle of |r| about point ``centre`` of ``body`` with ticks every ``pitch``
    (one at local angle ``phase``), teeth outward, or inward for an internal gear (r < 0)."""
    c = bld.local(body, centre)
    R = abs(r)
    n = max(6, int(round(2 * math.pi * R / pitch)))
    h = 1.1 * bld.w
    face = Circle(c, R, facecolor=body.fill if r > 0 else "none", edgecolor=body.edge,
                  linewidth=1.0, alpha=0.55 if r > 0 else 1.0, zorder=1.8)
    bld.add(body.name, face, body)
    if r < 0:        # a ring: its rim outside the pitch circle
        bld.add(body.name, Circle(c, R + 2.2 * h, facecolor="none", edgecolor=body.edge,
                                  linewidth=1.0, zorder=1.8), body)
    a = phase + 2 * math.pi * np.arange(n) / n
    e = np.column_stack([np.cos(a), np.sin(a)])
    inner, outer = (R - h, R + h * 0.2) if r < 0 else (R - 0.2 * h, R + h)
    segs = np.stack([c + inner * e, c + outer * e], axis=1)
    bld.add(body.name, LineCollection(segs, colors=body.edge, linewidths=1.3, zorder=1.9),
            body)
    bld.add(body.name, Circle(c, 0.45 * bld.w, facecolor="white", edgecolor=INK,
                              linewidth=1.0, zorder=5), body)


def rack(bld, body, a1, a2, pinion_centre, contact, pitch, side):
    """The rack's pitch line along a1->a2 of ``body`` over the pinion's travel, with teeth
    every ``pitch`` (one at ``contact``) on the side away from the pinion (``side``)."""
    A, B = bld.local(body, a1), bld.local(body, a2)
    u = B - A
    L = math.hypot(*u)
    if L == 0:
        return
    u = u / L
    n = np.array([-u[1], u[0]]) * side          # towards the teeth' backs
    s = (bld.local_motion(body, pinion_centre) - A) @ u
    s0 = (bld.local(body, 0, P=np.array([contact])) - A) @ u if contact is not None else s[0]
    own = np.array([(bld.local(body, k) - A) @ u for k in body.pts]) if body.pts else s
    lo = min(s.min() - 4 * pitch, own.min())
    hi = max(s.max() + 4 * pitch, own.max())
    h = 1.1 * bld.w
    back = np.array([A + lo * u + 2.2 * h * n, A + hi * u + 2.2 * h * n,
                     A + hi * u - 0.2 * h * n, A + lo * u - 0.2 * h * n])
    bld.add(body.name, Polygon(back, closed=True, facecolor=body.fill, edgecolor=body.edge,
                               linewidth=1.0, alpha=0.55, zorder=1.8), body)
    k = np.arange(math.ceil((lo - s0) / pitch), math.floor((hi - s0) / pitch) + 1)
    x = s0 + k * pitch
    segs = np.stack([A + x[:, None] * u + 0.2 * h * n, A + x[:, None] * u - h * n], axis=1)
    # above a slider's box (translate draws the rack's body as one)
    bld.add(body.name, LineCollection(segs, colors=body.edge, linewidths=1.3, zorder=2.7),
            body)


def draw_library(bld):
    """Every joint of these kinds in the drawing's structure, drawn by ``bld`` (the
    glyphs.Builder), before the bodies' own shapes."""
    joints = bld.st.joints
    circles = {}            # (body, centre, rounded r) -> (r, phase or None)
    meshes = []
    for _, kind, used in joints:
        if kind in GEAR_KINDS and len(used) == 4:
            c1, m1, c2, m2 = used
            b1, b2 = bld.body_of(c1), bld.body_of(c2)
            r1, r2 = _radius(bld, b1, c1, m1), _radius(bld, b2, c2, m2)
            meshes.append(("gears", (b1, c1, r1), (b2, c2, r2)))
        elif kind in RACK_KINDS and len(used) == 4:
            c, m, a1, a2 = used
            b = bld.body_of(c)
            meshes.append(("rack", (b, c, _radius(bld, b, c, m)), (bld.body_of(a1), a1, a2)))
        elif kind == "gen_revolute" and len(used) == 2:
            bld.revolute(*used)
        elif kind == "origin_lock" and len(used) == 2:
            if math.hypot(*(bld.P0[used[0]] - bld.P0[used[1]])) < 1e-9 * bld.span:
                bld.revolute(*used)
        elif kind == "gen_translate" and len(used) == 4:
            bld.translate(*used)
        elif kind == "point_on_lines" and len(used) == 5:
            bld.point_on_line(used[0], used[1], used[2])
            bld.point_on_line(used[0], used[3], used[4])
    if not meshes:
        return
    radii = [abs(m[1][2]) for m in meshes] + [abs(m[2][2]) for m in meshes if m[0] == "gears"]
    pitch = 2 * math.pi * min(radii) / TEETH
    for what, (b1, c1, r1), second in meshes:
        if what == "gears":
            b2, c2, r2 = second
            touch = _contact(bld, c1, r1, c2, r2)
            for b, c, r in ((b1, c1, r1), (b2, c2, r2)):
                key = (b.name, c, round(r, 9))
                if key not in circles or circles[key][1] is None:
                    phase = None if touch is None else _local_angle(bld, b, c, touch)
                    circles[key] = (b, c, r, phase)
        else:
            rb, a1, a2 = second
            A, B = bld.P0[a1], bld.P0[a2]
            u = (B - A) / (math.hypot(*(B - A)) or 1.0)
            left = np.array([-u[1], u[0]])
            side = 1.0 if (bld.P0[c1] - A) @ left > 0 else -1.0
            touch = bld.P0[c1] - side * abs(r1) * left
            key = (b1.name, c1, round(r1, 9))
            circles[key] = (b1, c1, r1, _local_angle(bld, b1, c1, touch))
            rack(bld, rb, a1, a2, c1, touch, pitch, -side)
    bld.gear_discs = []         # the pitch discs, global (plot.ground keeps bars off them)
    for b, c, r, phase in circles.values():
        gear(bld, b, c, r, pitch, 0.0 if phase is None else phase)
        bld.gear_discs.append((bld.P0[c].copy(), r))
