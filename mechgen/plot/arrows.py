"""Force arrows on a drawn configuration (``draw(mech, s, forces=...)``, force_arrows): the
joint reactions, the drivers' efforts and the applied loads of a solution at level
"dynamic" or "static", scaled to the largest and labelled with their sizes.

Each force is drawn on its line of action, at the point of it nearest to where the
constraint acts on the body (the pin, the sliding point, the middle of a slider's line):
for a slider (translate) that is its centre of pressure. What a force carries besides
(a translate's moment where the centre of pressure lies far off, a driver's torque, a
pure moment) is a curved arrow round that point, counter-clockwise for a positive moment.

- ``on=None``: the pin force at every revolute (on the joint's second body, or its moving
  one), every driver's effort on the body it drives, and the loads on every moving body;
- ``on="colisa"`` (or a list): the free body diagram of each body named: every
  constraint's reaction on it, its loads and, at level "dynamic", its inertia force
  −m·a_G (d'Alembert's, dashed), so that the arrows balance.

numpy and matplotlib only: the numbers are the solution's (``s.reaction``, ``s.terms``).
"""
from __future__ import annotations

import math

import numpy as np
from matplotlib.lines import Line2D
from matplotlib.patches import FancyArrow, FancyArrowPatch
from matplotlib.path import Path

from ..errors import MechgenError
from ..runtime.forces import ForceSolution, is_force_level
from ..runtime.forces.lookup import name_of, tables
from ..units import of as units_of
from .forceplots import number, require_forces, short_name
from .labels import HALO, Label, Obstacles, place, renderer_of, set_offset
from .style import INK

LENGTH = 0.22        # the largest arrow, as a fraction of the drawing's larger side
FAR = 0.6            # a line of action farther than this (fraction of the side) is not used
LOAD_COLOR = INK
INERTIA_COLOR = "#6e6e6e"
INERTIA_FILL = "#d0d0d0"
PIN_KINDS = ("revolute", "gen_revolute")


class ForceArrow:
    """One force drawn: ``kind`` ("reaction", "driver", "load" or "inertia"), ``name``
    (the constraint's label, or "loads" / "inertia"), ``short`` (its name on the picture:
    the constraint's name= or number, "loads", "−m·a"), ``body``, ``at`` (the global point
    it is drawn from), ``force`` (fx, fy), ``moment`` (about ``at``), ``text`` (its label)
    and ``artists`` (``arrow``, a FancyArrow from ``at`` of length |force| × scale; ``dot``
    at ``at``; ``arc``, the curved arrow of the moment; ``label``)."""

    def __init__(self, kind, name, body, at, force, moment, short, color):
        self.kind, self.name, self.body = kind, name, body
        self.at = np.asarray(at, dtype=float)
        self.force = np.asarray(force, dtype=float)
        self.moment = float(moment)
        self.short, self.color = short, color
        self.text = short
        self.where = None                # a pin's point, "colisa.P2" (acting_point)
        self.arrow = self.arc = self.label = self.dot = None
        self.head = self.at.copy()       # where the label goes: the arrow's tip

    @property
    def artists(self):
        return [a for a in (self.arrow, self.dot, self.arc, self.label) if a is not None]

    def __repr__(self):
        return (f"ForceArrow({self.kind}, {self.name!r} on {self.body}, at={self.at.round(6)}, "
                f"force={self.force.round(6)}, moment={self.moment:.6g})")


class ForceArrows:
    """What force_arrows() drew: ``arrows`` (ForceArrow), ``scale`` (drawn length per unit
    of force), ``note`` (a text where there was nothing to draw), ``bodies`` (the free
    bodies drawn; empty for the pins), ``place_labels()``."""

    def __init__(self, arrows, scale, note=None, bodies=()):
        self.arrows, self.scale, self.note = arrows, scale, note
        self.bodies = list(bodies)       # the free bodies drawn (none: the pins)
        self._place = lambda: None

    def artists(self):
        out = [a for arrow in self.arrows for a in arrow.artists]
        return out + ([self.note] if self.note is not None else [])

    def extent(self):
        """Every point the arrows reach, (k, 2), to frame them."""
        pts = [a.at for a in self.arrows] + [a.at + a.force * self.scale for a in self.arrows]
        return np.array(pts).reshape(-1, 2)

    def place_labels(self):
        self._place()


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _on_line(ref, f, m_ref, span):
    """(point, moment left about it): the point of the line of action of (f, m_ref about
    ref) nearest to ref, where it lies within FAR·span; else ref and m_ref."""
    size = math.hypot(f[0], f[1])
    if size == 0.0:
        return ref, m_ref
    s = -m_ref / size
    if abs(s) > FAR * span:
        return ref, m_ref
    n = np.array([-f[1], f[0]]) / size
    return ref + s * n, 0.0


def _reference(mech, scene, P, q, number, body, kind):
    """Where constraint ``number`` acts on ``body`` (global): the mean of its points on the
    body (a point_on_line: its sliding point, on both bodies); of all its points when
    none is the body's; without points (a driver), the origin of the first moving body
    it drives."""
    used = dict((n, u) for n, _, u in getattr(mech.module, "JOINTS", ())).get(number, ())
    if kind == "point_on_line" and used:
        pts = [used[0]]
    else:
        pts = [k for k in used if scene.owner[k] == body] or list(used)
    if pts:
        return np.mean([P[k] for k in pts], axis=0)
    return _origin(mech, scene, P, q, body)


def acting_point(mech, scene, number, body, kind):
    """The point a constraint's force on ``body`` acts at, named by its body and number
    as the drawing's point labels name it ("colisa.P2"; "manivela.P2 on colisa" where
    the point is another body's: a slot's sliding pin), or None (a driver, a guide: no
    one point)."""
    used = dict((n, u) for n, _, u in getattr(mech.module, "JOINTS", ())).get(number, ())
    if kind == "point_on_line" and used:
        pts = [used[0]]
    else:
        pts = [k for k in used if scene.owner[k] == body]
    if len(pts) != 1:
        return None
    k = pts[0]
    owner = scene.by_name[scene.owner[k]]
    if k not in owner.pts:
        return None
    text = f"{owner.name}.P{owner.pts.index(k) + 1}"
    return text if owner.name == body else f"{text} on {body}"


def _origin(mech, scene, P, q, body):
    b = scene.by_name[body]
    if b.ground:
        return np.zeros(2)
    if b.origin >= 0:
        return np.array(P[b.origin], dtype=float)
    idx = tables(mech).bodies[body]
    return np.array([q[idx[0]], q[idx[1]]])


def _centre(scene, P, body):
    b = scene.by_name[body]
    ks = list(b.pts) + ([b.origin] if b.origin >= 0 else [])
    return np.mean([P[k] for k in ks], axis=0) if ks else np.zeros(2)


def _resultant(terms, idx, origin, ref):
    """(f, moment about ref) of generalized forces ``terms`` (n,) on a body's (X, Y, Th)."""
    f = np.array([terms[idx[0]], terms[idx[1]]])
    m = terms[idx[2]] + _cross(origin - ref, f)
    return f, m


def collect(solution, scene, P, on=None, span=1.0):
    """The forces to draw (ForceArrow, not yet drawn) of a ForceSolution at points P."""
    mech = solution.mechanism
    tab = tables(mech)
    q = solution.q
    cons = {label: (number_, kind, is_driver)
            for number_, kind, label, _, is_driver in mech.module.CONSTRAINTS}
    joints = {n: u for n, _, u in getattr(mech.module, "JOINTS", ())}
    reactions = solution.reactions()
    wanted = []                                  # (label, body, kind of arrow)
    if on is None:
        for label, (number_, kind, is_driver) in cons.items():
            bodies = [b for (lab, b) in reactions if lab == label and not scene.by_name[b].ground]
            if is_driver and bodies:
                wanted.append((label, bodies[0], "driver"))
            elif kind in PIN_KINDS and bodies:
                used = joints.get(number_, ())
                owners = [scene.owner[k] for k in used if not scene.by_name[scene.owner[k]].ground]
                body = owners[-1] if owners else bodies[0]
                wanted.append((label, body, "reaction"))
        loaded = [b.name for b in scene.bodies if not b.ground]
        inertia = []
    else:
        chosen = on
        wanted = [(label, body, "driver" if cons[label][2] else "reaction")
                  for (label, body) in reactions if body in chosen]
        loaded = [b for b in chosen if not scene.by_name[b].ground]
        inertia = loaded if solution.force_level == "dynamic" else []
    out = []
    for label, body, what in wanted:
        number_, kind, _ = cons[label]
        ref = _reference(mech, scene, P, q, number_, body, kind)
        r = solution.reaction(label, on=body, about=ref)
        at, m = _on_line(ref, r[:2], r[2], span)
        name = short_name(mech, label)
        if label in getattr(solution, "indeterminate", ()):
            name += "*"                # redundant: its share is not unique
        color = scene.by_name[body].edge
        out.append(ForceArrow(what, label, body, at, r[:2], m, name, color))
        where = acting_point(mech, scene, number_, body, kind)
        if where is not None and what != "driver":     # a pin's force: body and point
            named = name_of(label, kind) is not None
            out[-1].where = where
            out[-1].text = f"{where} ({name})" if named else \
                where + ("*" if name.endswith("*") else "")
    terms = solution.terms if solution.terms is not None else np.zeros((3, mech.n))
    for body, kind, vec, color in ([(b, "load", terms[0] + terms[1], LOAD_COLOR) for b in loaded]
                                   + [(b, "inertia", -terms[2], INERTIA_COLOR) for b in inertia]):
        idx = tab.bodies[body]
        ref = _centre(scene, P, body)
        f, m = _resultant(vec, idx, _origin(mech, scene, P, q, body), ref)
        at, m = _on_line(ref, f, m, span)
        text = "loads" if kind == "load" else "−m·a"
        out.append(ForceArrow(kind, "loads" if kind == "load" else "inertia", body, at, f, m,
                              text, color))
        if kind == "load" and len(loaded) > 1:
            out[-1].text = f"loads on {body}"   # (their colour is the ink's, not the body's)
    return out


def check_bodies(mech, on) -> list:
    """The body names of ``on`` (a name, a body or a list of them); MechgenError naming
    any the model does not have."""
    names = [on] if isinstance(on, str) else [getattr(b, "name", b) for b in on]
    known = [name for name, _, _ in mech.module.BODIES]
    missing = [n for n in names if n not in known]
    if missing:
        raise MechgenError(f"forces: no body named {', '.join(map(repr, missing))} in "
                           f"'{mech.name}' (bodies: {', '.join(known)})")
    return names


def _arc(at, radius, positive, color, width):
    """A curved arrow round ``at``, counter-clockwise when ``positive``: 270° of a circle."""
    a = np.radians(np.linspace(-45.0, 225.0, 40))
    if not positive:
        a = a[::-1]
    xy = at + radius * np.column_stack([np.cos(a), np.sin(a)])
    return FancyArrowPatch(path=Path(xy), arrowstyle="-|>", mutation_scale=9.0,
                           color=color, linewidth=width, zorder=8.2)


def force_arrows(drawing, solution, on=None, *, scale=None, length=LENGTH, fontsize=9,
                 reframe=True):
    """Draw the forces of ``solution`` (``mech.solve(t, level="dynamic"|"static")``) on
    ``drawing`` (plot.draw of the same configuration); returns :class:`ForceArrows`.

    ``on``: None (the pins, drivers and loads), a body name or a list of them (their free
    body diagrams). Arrows are straight, their lengths proportional to the forces'
    sizes: the largest is ``length`` × the drawing's larger side, or ``scale`` (drawn
    length per unit of force: the same scale in several drawings). Each is labelled
    with the constraint's name and its size; a moment with its size beside a curved
    arrow; a starred name is a redundant constraint's (``s.indeterminate``), its share
    the minimum-norm one, not unique. A model without mass and loads raises MechgenError (every force is zero);
    forces that are all zero at this instant leave a note on the drawing.
    ``reframe``: grow the axes' limits to show every arrow, and place the labels now."""
    if not isinstance(solution, ForceSolution) or not is_force_level(solution.force_level):
        raise TypeError("forces: draw a solution at level 'dynamic' or 'static' "
                        "(mech.solve(t, level=\"dynamic\")), got "
                        f"{type(solution).__name__}")
    mech = solution.mechanism
    require_forces(mech, "forces")
    scene, ax = drawing.structure, drawing.ax
    if on is not None:
        on = check_bodies(mech, on)
    P = solution.points()
    lo, hi = P.min(axis=0), P.max(axis=0)
    frame = drawing.frame
    span = float(max(frame[1] - frame[0], frame[3] - frame[2])) if frame is not None \
        else float(max(hi - lo)) or 1.0
    arrows = collect(solution, scene, P, on, span)
    sizes = [math.hypot(*a.force) for a in arrows]
    top = max(sizes, default=0.0)
    tiny_f = 1e-9 * top
    tiny_m = max(1e-6 * top * span, 1e-12) if top > 0 else 1e-12
    shown = [a for a, s in zip(arrows, sizes) if s > tiny_f and s > 0 or abs(a.moment) > tiny_m]
    if scale is None:
        scale = length * span / top if top > 0 else 0.0
    w = drawing.size or 0.014 * span
    units = units_of(mech)          # sizes in N and N·mm where the model declares them
    f_unit = f" {units.force}" if units.declared else ""
    m_unit = f" {units.of('torque')}" if units.declared else ""
    result = ForceArrows(shown, float(scale), bodies=on or ())
    if not shown:
        where = f"T = {solution.t:.4g}"
        result.note = ax.text(0.5, 0.04, f"every force is zero at {where} ({solution.force_level})",
                              transform=ax.transAxes, ha="center", va="bottom",
                              fontsize=fontsize, color=INK, zorder=9)
        return result
    for a in shown:
        size = math.hypot(*a.force)
        dashed = a.kind == "inertia"
        parts = []
        if size > tiny_f and size > 0:
            d = a.force * scale
            # a short arrow keeps an arrow's shape, only smaller (not a flat tick)
            head = min(2.4 * w, 0.45 * math.hypot(*d))
            a.arrow = FancyArrow(a.at[0], a.at[1], d[0], d[1],
                                 width=min(0.42 * w, 0.25 * head), head_width=min(1.6 * w, head),
                                 head_length=head, length_includes_head=True,
                                 facecolor=INERTIA_FILL if dashed else a.color,
                                 edgecolor=a.color, linewidth=0.9,
                                 linestyle="--" if dashed else "-", zorder=8)
            ax.add_patch(a.arrow)
            # where it acts, seen even where the arrow is short
            a.dot = ax.add_line(Line2D([a.at[0]], [a.at[1]], linestyle="none", marker="o",
                                       markersize=3.2, color=a.color, zorder=8.1))
            a.head = a.at + d
            parts.append(number(size) + f_unit)
        if abs(a.moment) > tiny_m:
            a.arc = _arc(a.at, 2.6 * w, a.moment > 0, a.color, 1.3)
            ax.add_patch(a.arc)
            if not parts:
                a.head = a.at + np.array([0.0, 2.6 * w])
            parts.append(("M " if parts else "") + number(abs(a.moment)) + m_unit)
        a.text = f"{a.text} {', '.join(parts)}"
        a.label = ax.annotate(a.text, xy=a.head, xytext=(0.0, 0.0), textcoords="offset points",
                              ha="center", va="center", fontsize=fontsize, color=a.color,
                              zorder=9, path_effects=HALO, annotation_clip=False)
    if any(a.short.endswith("*") for a in shown):
        result.note = ax.text(0.01, 0.01, "* not unique (redundant constraints): the "
                              "minimum-norm shares", transform=ax.transAxes, ha="left",
                              va="bottom", fontsize=fontsize - 1, color=INK, zorder=9)
    result._place = lambda: _place_labels(ax, shown)
    if reframe:                 # alone on a drawing: framed and labelled now (draw()
        _grow(ax, result.extent())   # frames them with the rest and labels them last)
        result.place_labels()
    return result


def _grow(ax, pts):
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    if lo[0] >= x0 and hi[0] <= x1 and lo[1] >= y0 and hi[1] <= y1:
        return
    pad = 0.05 * max(hi[0] - lo[0], hi[1] - lo[1], x1 - x0, y1 - y0)
    ax.set_xlim(min(x0, lo[0] - pad), max(x1, hi[0] + pad))
    ax.set_ylim(min(y0, lo[1] - pad), max(y1, hi[1] + pad))


def _place_labels(ax, arrows):
    """Each label beside its arrow's tip (its arc's top), where it collides with nothing:
    the placement of the point labels (plot.labels), preferring the arrow's direction."""
    fig = ax.figure
    ax.apply_aspect()
    renderer = renderer_of(fig)
    to_px = ax.transData.transform
    px_per_pt = fig.dpi / 72.0
    labels = []
    for a in arrows:
        set_offset(a.label, (0.0, 0.0))
        bb = a.label.get_window_extent(renderer)
        d = a.head - a.at
        norm = math.hypot(*d)
        prefer = d / norm if norm > 0 else np.array([0.0, 1.0])
        labels.append(Label(a.label, to_px(a.head), (bb.width, bb.height), prefer, 2.0))
    obstacles = Obstacles(ax, renderer, skip=[a.label for a in arrows])
    frame = ax.get_window_extent(renderer)
    place(labels, obstacles, (frame.x0, frame.y0, frame.x1, frame.y1), px_per_pt)
    for lb in labels:
        set_offset(lb.artist, lb.offset / px_per_pt)
