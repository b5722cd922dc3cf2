"""Springs and dampers drawn between their points (the module's LOADS table): a spring as
a zigzag, a damper as a dashpot (a piston rod in an open cylinder), both stretching with
the motion. Forces and moments are drawn by plot.arrows (draw(forces=...))."""
from __future__ import annotations

import math

import numpy as np
from matplotlib.lines import Line2D

from ..style import INK

TEETH = 7          # a spring's zigzag: this many teeth
ENDS = 0.18        # the straight ends, as shares of the length


def zigzag(a, b, width):
    """The polyline of a spring from a to b, its teeth ``width`` to each side."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    d = b - a
    length = math.hypot(*d)
    if not length > 0.0:
        return np.array([a, b])
    u = d / length
    n = np.array([-u[1], u[0]])
    k = np.arange(1, 2 * TEETH)
    along = ENDS + (1.0 - 2.0 * ENDS) * k / (2 * TEETH)
    side = np.where(k % 2 == 1, 1.0, -1.0)
    mid = a + np.outer(along * length, u) + np.outer(side * width, n)
    return np.vstack([a, a + ENDS * length * u, mid, b - ENDS * length * u, b])


def dashpot(a, b, width):
    """(rod, cylinder) polylines of a damper from a to b: the piston rod from a with its
    plate, the cylinder open towards a, its own rod to b."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    d = b - a
    length = math.hypot(*d)
    if not length > 0.0:
        return np.array([a, b]), np.array([b, b])
    u = d / length
    n = np.array([-u[1], u[0]])
    plate = a + 0.5 * length * u
    rod = np.array([a, plate, plate + 0.8 * width * n, plate - 0.8 * width * n])
    c0, c1 = a + 0.35 * length * u, a + 0.65 * length * u
    cyl = np.array([c0 + width * n, c1 + width * n, c1 - width * n, c0 - width * n,
                    c1 - width * n, c1, b])
    return rod, cyl


def draw_loads(bld):
    """Add the springs and dampers of the scene to a drawing (moved with it)."""
    w = 0.9 * bld.w
    for _name, kind, used in bld.st.loads:
        if len(used) != 2:
            continue
        k1, k2 = used
        if kind == "spring":
            xy = zigzag(bld.P0[k1], bld.P0[k2], w)
            line = bld.add("joints", Line2D(xy[:, 0], xy[:, 1], color=INK, linewidth=1.1,
                                            zorder=3.5, marker="o", markersize=3.5,
                                            markevery=[0, len(xy) - 1]))

            def move(P, q, t, line=line, k1=k1, k2=k2):
                xy = zigzag(P[k1], P[k2], w)
                line.set_data(xy[:, 0], xy[:, 1])
            bld.d.on_move(move)
        elif kind == "damper":
            parts = dashpot(bld.P0[k1], bld.P0[k2], w)
            lines = [bld.add("joints", Line2D(xy[:, 0], xy[:, 1], color=INK, linewidth=1.1,
                                              zorder=3.5, marker="o", markersize=3.5,
                                              markevery=[end]))
                     for xy, end in zip(parts, (0, len(parts[1]) - 1))]

            def move(P, q, t, lines=lines, k1=k1, k2=k2):
                for line, xy in zip(lines, dashpot(P[k1], P[k2], w)):
                    line.set_data(xy[:, 0], xy[:, 1])
            bld.d.on_move(move)
