"""Pictures of synthesis from positions (docs/reference/synthesis.md): the poses as frames, the
centre-point and circle-point curves of four poses, the Burmester points of five, and a chosen
four-bar drawn at every pose.

This module knows nothing of mechgen.synthesis (the plot layer sits beside it): it takes
plain numbers, a curve as the coefficients C (4×4) of Σ C[i, k] x^i y^k = 0
(synthesis.centre_point_cubic, synthesis.circle_point_cubic), and a four-bar as any object
with ``input.fixed``, ``input.moving``, ``output.fixed``, ``output.moving`` (the ground
pivots and the body's pivots in the poses' frame) and ``poses`` (a synthesis.FourBar).
Every function takes ``ax=None`` (a new figure when None) and returns the axes."""
from __future__ import annotations

import math

import numpy as np

from .style import INK, PALETTE

POSE_COLOUR = "crimson"
CENTRE_COLOUR = "#2e3fa8"
CIRCLE_COLOUR = "#1e8449"
PLOT_AREA = (0.07, 0.08, 0.6, 0.84)     # the axes in a figure of its own; the legend beside


def _axes(ax):
    if ax is None:
        import matplotlib.pyplot as plt
        fig = plt.figure(figsize=(11, 7.5))
        ax = fig.add_axes(PLOT_AREA)
        ax.mechgen_own_figure = True
    ax.set_aspect("equal", adjustable="box")
    return ax


def size(poses) -> float:
    """A length for the picture: the poses' spread (their origins' largest distance from
    their mean), 1 where they share one origin."""
    xy = np.asarray(poses, dtype=float)[:, :2]
    s = float(np.max(np.linalg.norm(xy - xy.mean(axis=0), axis=1))) if len(xy) else 0.0
    return s if s > 0 else 1.0


def poses(ax, poses, length=None, numbers=True, label="poses"):
    """Each pose as a frame: an arrow along its x axis (``length``: a quarter of the poses'
    spread by default), a short tick along its y axis, its number beside it."""
    ax = _axes(ax)
    P = np.asarray(poses, dtype=float)
    L = 0.35 * size(P) if length is None else float(length)
    for k, (x, y, th) in enumerate(P):
        c, s = math.cos(th), math.sin(th)
        ax.annotate("", xy=(x + L * c, y + L * s), xytext=(x, y), zorder=6,
                    arrowprops=dict(arrowstyle="-|>", color=POSE_COLOUR, lw=1.8,
                                    mutation_scale=14))
        ax.plot([x, x - 0.4 * L * s], [y, y + 0.4 * L * c], color=POSE_COLOUR, lw=1.2,
                zorder=6)
        if numbers:
            ax.annotate(str(k + 1), (x, y), xytext=(-10 * c + 8 * s, -10 * s - 8 * c),
                        textcoords="offset points", ha="center", va="center",
                        color=POSE_COLOUR, fontsize=11, fontweight="bold", zorder=7)
    ax.plot(P[:, 0], P[:, 1], "o", color=POSE_COLOUR, ms=5, zorder=7, label=label)
    return ax


def curve(ax, C, box, color=CENTRE_COLOUR, label=None, lw=1.6, points=400):
    """The curve Σ C[i, k] x^i y^k = 0 inside ``box`` (xmin, xmax, ymin, ymax)."""
    ax = _axes(ax)
    C = np.asarray(C, dtype=float)
    x = np.linspace(box[0], box[1], points)
    y = np.linspace(box[2], box[3], points)
    X, Y = np.meshgrid(x, y)
    Z = np.zeros_like(X)
    for i in range(C.shape[0]):
        for k in range(C.shape[1]):
            if C[i, k]:
                Z += C[i, k] * X ** i * Y ** k
    ax.contour(X, Y, Z, levels=[0.0], colors=[color], linewidths=lw, zorder=2)
    if label:
        ax.plot([], [], color=color, lw=lw, label=label)
    return ax


def curves(ax, poses_, centre=None, circle=None, box=None):
    """Four poses' centre-point curve (fixed pivots) and circle-point curve (moving pivots
    where the body is in pose 1), inside ``box`` (default: the poses' spread thrice about
    their mean)."""
    ax = _axes(ax)
    if box is None:
        box = around(poses_, 3.0)
    if centre is not None:
        curve(ax, centre, box, CENTRE_COLOUR, "centre-point curve (fixed pivots)")
    if circle is not None:
        curve(ax, circle, box, CIRCLE_COLOUR, "circle-point curve (moving pivots, pose 1)",
              lw=1.3)
    ax.set_xlim(box[0], box[1])
    ax.set_ylim(box[2], box[3])
    return ax


def around(poses_, spreads, points=()):
    """(xmin, xmax, ymin, ymax): a square box ``spreads`` spreads about the poses' mean,
    grown to hold ``points``."""
    P = np.asarray(poses_, dtype=float)[:, :2]
    centre, r = P.mean(axis=0), spreads * size(poses_)
    lo, hi = centre - r, centre + r
    extra = np.asarray(list(points), dtype=float).reshape(-1, 2)
    if extra.size:
        lo = np.minimum(lo, extra.min(axis=0) - 0.15 * r)
        hi = np.maximum(hi, extra.max(axis=0) + 0.15 * r)
    half = 0.5 * float(np.max(hi - lo))
    mid = 0.5 * (lo + hi)
    return (mid[0] - half, mid[0] + half, mid[1] - half, mid[1] + half)


def pivots(ax, fixed, moving=None, label="Burmester points"):
    """Fixed pivots as squares, their moving pivots (global, pose 1) as circles, each pair
    joined by a thin dashed line."""
    ax = _axes(ax)
    F = np.asarray(fixed, dtype=float).reshape(-1, 2)
    ax.plot(F[:, 0], F[:, 1], "s", color=CENTRE_COLOUR, ms=7, zorder=5,
            label=f"{label}: fixed")
    if moving is not None:
        M = np.asarray(moving, dtype=float).reshape(-1, 2)
        ax.plot(M[:, 0], M[:, 1], "o", mfc="white", mec=CIRCLE_COLOUR, mew=1.8, ms=7,
                zorder=5, label=f"{label}: moving (pose 1)")
        for f, m in zip(F, M):
            ax.plot([f[0], m[0]], [f[1], m[1]], ls=":", color=INK, lw=0.8, zorder=1)
    return ax


def _place(pose, u):
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return np.array([c * u[0] - s * u[1] + pose[0], s * u[0] + c * u[1] + pose[1]])


def fourbar(ax, link, highlight=0, label="four-bar"):
    """The four-bar ``link`` at every one of its poses: ground pivots O2, O4 (triangles),
    crank O2–A, output link O4–B, the coupler A–B with the poses' frame origin joined to it;
    pose ``highlight`` (0-based) in full colour, the others faint."""
    ax = _axes(ax)
    O2 = np.asarray(link.input.fixed, dtype=float)
    O4 = np.asarray(link.output.fixed, dtype=float)
    uA, uB = link.input.moving, link.output.moving
    crank, coupler = PALETTE[0][1], PALETTE[2][1]
    output, fill = PALETTE[1][1], PALETTE[2][0]
    P = np.asarray(link.poses, dtype=float)
    for j, pose in enumerate(P):
        A, B = _place(pose, uA), _place(pose, uB)
        Z = pose[:2]
        strong = j == highlight
        alpha, lw = (1.0, 3.0) if strong else (0.35, 1.6)
        ax.fill([A[0], B[0], Z[0]], [A[1], B[1], Z[1]], color=fill,
                alpha=0.45 if strong else 0.08, zorder=3)
        ax.plot([A[0], B[0], Z[0], A[0]], [A[1], B[1], Z[1], A[1]], color=coupler,
                alpha=alpha, lw=0.6 * lw, zorder=3)
        ax.plot([O2[0], A[0]], [O2[1], A[1]], color=crank, alpha=alpha, lw=lw, zorder=4,
                solid_capstyle="round", label="crank (input)" if strong else None)
        ax.plot([O4[0], B[0]], [O4[1], B[1]], color=output, alpha=alpha, lw=lw, zorder=4,
                solid_capstyle="round", label="output link" if strong else None)
        ax.plot([A[0], B[0]], [A[1], B[1]], color=coupler, alpha=alpha, lw=lw, zorder=4,
                solid_capstyle="round", label="coupler" if strong else None)
        ax.plot([A[0], B[0]], [A[1], B[1]], "o", color="white", mec=INK, ms=5,
                alpha=max(alpha, 0.6), zorder=5)
    ax.plot([O2[0], O4[0]], [O2[1], O4[1]], color="#888888", lw=1.2, ls="--", zorder=1)
    ax.plot([O2[0], O4[0]], [O2[1], O4[1]], "^", color=INK, ms=11, zorder=6,
            label=f"{label}: ground pivots")
    for name, p in (("O2", O2), ("O4", O4)):
        ax.annotate(name, p, xytext=(8, -14), textcoords="offset points", fontsize=10)
    return ax


def figure(poses_, link=None, centre=None, circle=None, fixed=None, moving=None,
           title=None, ax=None, reach=6.0):
    """The whole picture: the poses; with four poses the centre- and circle-point curves
    (``centre``, ``circle``: their cubics); Burmester points (``fixed`` and, in pose 1,
    ``moving``; those farther than ``reach`` spreads from the poses are left out and
    counted in a note); the four-bar ``link`` at every pose; equal axes, a legend outside
    the plot, a title."""
    ax = _axes(ax)
    spots = [] if link is None else pins(link)
    note = None
    if fixed is not None:
        F = np.asarray(fixed, dtype=float).reshape(-1, 2)
        M = None if moving is None else np.asarray(moving, dtype=float).reshape(-1, 2)
        mean = np.asarray(poses_, dtype=float)[:, :2].mean(axis=0)
        near = np.linalg.norm(F - mean, axis=1) <= reach * size(poses_)
        if M is not None:
            near &= np.linalg.norm(M - mean, axis=1) <= reach * size(poses_)
        for p in spots[:2]:                         # the four-bar's own pivots are drawn
            near |= np.linalg.norm(F - np.asarray(p, dtype=float), axis=1) <= 1e-9
        if not np.all(near):
            far = F[~near]
            note = (f"{len(far)} Burmester pair(s) beyond the picture, fixed pivot at "
                    + ", ".join(f"({x:.3g}, {y:.3g})" for x, y in far))
        fixed, moving = F[near], None if M is None else M[near]
        spots += list(fixed) + ([] if moving is None else list(moving))
    box = around(poses_, 1.6 if centre is None and circle is None else 2.5, spots)
    if centre is not None or circle is not None:
        curves(ax, poses_, centre, circle, box=box)
    if fixed is not None and len(fixed):
        pivots(ax, fixed, moving)
    if link is not None:
        fourbar(ax, link)
    poses(ax, poses_)
    ax.set_xlim(box[0], box[1])
    ax.set_ylim(box[2], box[3])
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.grid(True, color="#e6e6e6", lw=0.6, zorder=0)
    if title:
        ax.set_title(title, fontsize=11)
    if note:
        ax.annotate(note, (0.01, 0.01), xycoords="axes fraction", fontsize=8,
                    color="#555555")
    if getattr(ax, "mechgen_own_figure", False):
        ax.figure.legend(*ax.get_legend_handles_labels(), loc="upper left",
                         bbox_to_anchor=(PLOT_AREA[0] + PLOT_AREA[2] + 0.02, 0.92),
                         fontsize=9)
    else:
        ax.legend(loc="best", fontsize=8, framealpha=0.9)
    return ax


def pins(link) -> list:
    """The four-bar's ground pivots and its moving pivots at every pose."""
    out = [np.asarray(link.input.fixed, dtype=float), np.asarray(link.output.fixed, float)]
    for pose in np.asarray(link.poses, dtype=float):
        out += [_place(pose, link.input.moving), _place(pose, link.output.moving)]
    return out
