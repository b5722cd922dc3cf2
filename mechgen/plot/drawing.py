"""One instant of a mechanism drawn (draw), several side by side (draw_modes), and the
Drawing they return, whose artists move in place to any other configuration.

Everything is computed from the generated module and from solved coordinates: numpy and
matplotlib only, never sympy.
"""
from __future__ import annotations

import math
import warnings

import numpy as np
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, Polygon

from ..errors import MechgenError
from ..runtime.results import Solution
from ..units import of as units_of
from .arrows import force_arrows
from .glyphs.builder import Builder
from .glyphs.cams import KINDS as CAM_KINDS
from .glyphs.cams import draw as draw_cam
from .glyphs.gears import draw_library
from .glyphs.ground import lift_cam_pivots
from .glyphs.shapes import AUTO
from .glyphs.springs import draw_loads
from .scene import Scene
from .style import INK, MARGIN

MOTION_POINTS = 41   # solves of the sweep that frames a single drawing


class Drawing:
    """What draw() drew: ``ax``, ``artists`` (by body name; ``"joints"`` for pins, blocks
    and rods), ``labels`` ((text, artist) of the point labels), ``frame`` (xmin, xmax,
    ymin, ymax), ``size`` (a bar's half-width, the unit of every detail),
    ``update(solution)`` to move it and ``place_labels()`` to place its labels anew."""

    def __init__(self, ax, mech, structure):
        self.ax = ax
        self.mechanism = mech
        self.structure = structure
        self.artists = {b.name: [] for b in structure.bodies}
        self.artists["joints"] = []
        self.frame = None
        self.size = None
        self.title = None
        self.labels = []          # (text, artist) of every point label, "P2·P1" when shared
        self.transforms = {}      # body name -> the Affine2D that carries its artists
        self.redrawn = set()      # bodies drawn by user functions, redrawn at each update
        self.points = None        # the points (npoints, 2) of the configuration shown
        self.forces = None        # the force arrows (plot.arrows.ForceArrows), if drawn
        self._movers = []         # functions (P, q, t) moving what a transform cannot
        self._place_labels = lambda: None

    @property
    def figure(self):
        return self.ax.figure

    def all_artists(self):
        return [a for group in self.artists.values() for a in group]

    def on_move(self, fn):
        """Call ``fn(P, q, t)`` at every move (after the bodies' transforms are set)."""
        self._movers.append(fn)

    def moving(self):
        """The artists that change between frames (the ground's and the legend stay)."""
        still = {b.name for b in self.structure.bodies if b.ground and b.name not in self.redrawn}
        arts = [a for name, group in self.artists.items() if name not in still for a in group]
        if self.title is not None:
            arts.append(self.title)
        return arts

    def update(self, solution):
        """Move the drawing to another configuration (a Solution of the same mechanism)."""
        self.set_state(solution.points(), solution.q, solution.t)

    def place_labels(self):
        """Place the point labels again for the configuration shown and the figure as it
        is now (after a change of its size or layout, or an update())."""
        self._place_labels()

    def set_state(self, P, q, t):
        """Move every artist to points P (npoints, 2), coordinates q, time t, in place."""
        self.points = P
        for b in self.structure.bodies:
            tf = self.transforms.get(b.name)
            if tf is None:
                continue
            o = P[b.origin] if b.origin >= 0 else (0.0, 0.0)
            th = q[b.th] if b.th is not None else 0.0
            c, s = math.cos(th), math.sin(th)
            tf.set_matrix(np.array([[c, -s, o[0]], [s, c, o[1]], [0.0, 0.0, 1.0]]))
        for fn in self._movers:
            fn(P, q, t)


def time_unit(mech) -> str:
    """" s" after a time where the model declares its units (mechgen.units), else ""."""
    u = units_of(mech)
    return f" {u.time}" if u.declared else ""


def _listed(shapes):
    return list(shapes) if isinstance(shapes, (list, tuple)) else [shapes]


def _as_solution(mech, solution, level="position"):
    if isinstance(solution, Solution):
        return solution
    if isinstance(solution, (int, float, np.floating, np.integer)) \
            and not isinstance(solution, bool):
        return mech.solve(float(solution), level=level)
    raise TypeError(f"draw() takes a Solution (mech.solve(t)) or a time, got {solution!r}")


def motion(mech, solution, span=1.0, n=MOTION_POINTS):
    """The points and coordinates of the motion from a solution over ``span`` time units
    (warm-started from it, so in its assembly mode; cut short at a lock): (P, Q)."""
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


def trace_paths(scene, trace, P, Q):
    """[(scene body, path (F, 2))] of the points named in ``trace`` (a name or a list of
    them; see Scene.locate) over frames P (F, N, 2), Q (F, n)."""
    if isinstance(trace, str):
        trace = (trace,)
    out = []
    for label in trace or ():
        body, where = scene.locate(label)
        out.append((body, where(P, Q)))
    return out


def add_path(ax, scene, body, xy, **kwargs):
    """A traced point's path, a line in its body's colour under the bodies' pins."""
    style = dict(color=scene.by_name[body.name].edge, linewidth=1.3, alpha=0.75, zorder=4.4)
    style.update(kwargs)
    line = Line2D(xy[:, 0], xy[:, 1], **style)
    ax.add_line(line)
    return line


def _trace_marks(d, scene, trace, P0, q0):
    """A dot on each traced point where the drawing shows it, moved with the drawing."""
    marks = []
    for label in ((trace,) if isinstance(trace, str) else trace):
        body, where = scene.locate(label)
        xy = where(P0[None], q0[None])[0]
        mark = Line2D([xy[0]], [xy[1]], linestyle="none", marker="o", markersize=4.5,
                      color=scene.by_name[body.name].edge, zorder=7.5)
        d.ax.add_line(mark)

        def move(P, q, t, mark=mark, where=where):
            xy = where(P[None], np.asarray(q)[None])[0]
            mark.set_data([xy[0]], [xy[1]])
        d.on_move(move)
        marks.append(mark)
    return marks


def _take_in(frame, xy):
    """The frame (xmin, xmax, ymin, ymax) grown to hold the points xy (k, 2), with the
    margin a frame keeps."""
    lo = np.minimum([frame[0], frame[2]], xy.min(axis=0))
    hi = np.maximum([frame[1], frame[3]], xy.max(axis=0))
    if np.all(lo >= [frame[0], frame[2]]) and np.all(hi <= [frame[1], frame[3]]):
        return frame
    pad = MARGIN * float(max(hi - lo) or 1.0)
    return (min(frame[0], lo[0] - pad), max(frame[1], hi[0] + pad),
            min(frame[2], lo[1] - pad), max(frame[3], hi[1] + pad))


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
         width=8.0, trace=(), forces=None, builder=None):
    """Draw the mechanism at one instant; returns a :class:`Drawing`.

    ``solution``: a Solution (``mech.solve(t)``) or a time. The frame covers the motion:
    of ``sweep`` when given, else of one time unit solved from the solution (in its
    assembly mode); ``frame=(xmin, xmax, ymin, ymax)`` fixes it, ``frame="pose"`` fits
    this configuration only. ``labels``: True (or a list of body names) writes P1, P2, ...
    where they overlap nothing (one label, "P2·P1", for a point two bodies share);
    ``axes``: True (or body names) draws local axes. ``artists``: {body name: Shape,
    function(ax, xy) or a list of them} replaces a body's automatic bar (add ``"auto"`` to
    the list to keep it); for the ground it replaces the automatic guides. ``colors``:
    {body name: colour}. ``title``: text, False for none, None for the model and time.
    ``trace``: points whose paths over the motion (``sweep``, else the one time unit that
    frames the drawing) are drawn in their body's colour: ``"colisa[2]"``, ``body[k]``,
    ``body.at(x, y)`` (a point the model need not name); the frame takes them in.
    ``forces``: True draws the pin force at every revolute, the drivers' efforts and the
    loads; a body name (or a list) its free body diagram; ``solution`` is then a solve at
    level "dynamic" or "static" (a time is solved at "dynamic"). The arrows are
    ``d.forces`` (plot.arrows.ForceArrows), drawn for this configuration only: update()
    hides them. ``builder``: a subclass of plot.glyphs.Builder to put the glyphs (the live
    view, mechgen.view, records with one which frame each glyph moves with).
    """
    solution = _as_solution(mech, solution, "dynamic" if forces is not None and
                            forces is not False else "position")
    st = Scene(mech, colors)
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
    bld = (builder or Builder)(Drawing(ax, mech, st), P0, q0, solution.t, P, Q)
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
        elif kind in CAM_KINDS:
            draw_cam(bld, kind, used)
    draw_library(bld)        # gears, racks, gen_revolute, ... (plot/glyphs/gears.py)
    draw_loads(bld)          # springs and dampers (plot/glyphs/springs.py)
    lift_cam_pivots(bld)     # a pivot under a cam's plate drawn over it (plot/glyphs/ground.py)
    for b in st.bodies:
        if b.ground and (b.name not in custom or AUTO in _listed(custom[b.name])):
            bld.ground_link(b)
    for b in st.bodies:
        shapes = custom.get(b.name)
        keep_auto = True
        if shapes is not None:
            keep_auto = bld.custom(b, _listed(shapes))
        if b.ground:
            xy = np.array([P0[k] for k in b.pts]) if b.pts else np.zeros((0, 2))
            if len(xy):
                bld.add(b.name, Line2D(xy[:, 0], xy[:, 1], linestyle="none", marker="o",
                                       markersize=3, color=INK, zorder=1.3))
            continue
        if keep_auto and not bld.boxed.get(b.name, False):
            bld.body_shape(b)

    stack_bodies(bld.d, P0)

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
    if trace:
        # the sweep's own points (P begins with this configuration, which need not be on
        # the sweep's time grid), else the motion that frames the drawing
        PT, QT = (sweep.points(), sweep.Q) if sweep is not None else (P, Q)
        paths = trace_paths(st, trace, PT, QT)
        d.artists["traces"] = [add_path(ax, st, body, xy) for body, xy in paths]
        d.artists["traces"] += _trace_marks(d, st, trace, P0, q0)
        if not isinstance(frame, (tuple, list)):
            d.frame = _take_in(d.frame, np.concatenate([xy for _, xy in paths]))
    arrows = None
    if forces is not None and forces is not False:
        arrows = add_forces(d, solution, None if forces is True else forces, fontsize)
        if not isinstance(frame, (tuple, list)) and arrows.arrows:
            d.frame = _take_in(d.frame, arrows.extent())
    outside = legend is True and own
    if outside:
        width += 1.4
    _set_frame(ax, d.frame, width if own else None, 1.5 if outside else 0.0)
    bld.labels(chosen(labels), fontsize, named=arrows is not None)
    if arrows is not None:      # their labels placed last, clear of the points' labels
        arrows.place_labels()
        points_again = d._place_labels

        def again():
            points_again()
            arrows.place_labels()
        d._place_labels = again
    if grid:
        ax.grid(True, color="#dddddd", linewidth=0.6, zorder=0)
        ax.set_axisbelow(True)
    ax.tick_params(labelsize=fontsize - 1)
    units = units_of(mech)
    if units.declared:      # the frame's axes in the model's length unit
        ax.set_xlabel(f"x [{units.length}]", fontsize=fontsize - 1)
        ax.set_ylabel(f"y [{units.length}]", fontsize=fontsize - 1)
    if title is None:
        said = "" if arrows is None else "   forces" + \
            ("" if forces is True else " on " + ", ".join(arrows.bodies)) + \
            f" ({solution.force_level})"
        unit = time_unit(mech)
        d.title = ax.set_title(f"{mech.name}   T = {solution.t:.4g}{unit}{said}",
                               fontsize=fontsize + 2)

        def retitle(P, q, t, text=d.title, name=mech.name):
            # the forces belong to the configuration drawn (add_forces hides them elsewhere)
            shown = arrows is not None and arrows.artists() and arrows.artists()[0].get_visible()
            text.set_text(f"{name}   T = {t:.4g}{unit}{said if shown else ''}")
        d.on_move(retitle)
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


def stack_bodies(d, P0):
    """Stack the moving bodies so that none hides another: the smaller (shorter) a body,
    the higher its layer, so that a crank is drawn over the lever it drives and over the
    lever's slot. A layer holds a body's outline (zorder 2 + 0.01 × its number, as drawn),
    its slider box (2.5) and its slot (3), in that order, all within [2, 2.09]: under
    the pins, blocks and rods as before, and under a cam's hub and the pivots over it."""
    st = d.structure
    moving = [b for b in st.bodies if not b.ground and b.every]
    n = len(moving)
    if n < 2:
        return

    def size(b):
        xy = np.asarray(P0)[list(b.every)]
        return float(np.max(np.hypot(*(xy[:, None] - xy[None]).reshape(-1, 2).T)))

    order = sorted(moving, key=lambda b: (-size(b), b.number))
    step = 0.09 / n
    for r, b in enumerate(order):
        layer = {2 + 0.01 * b.number: 0.0, 2.5: 0.3 * step, 3.0: 0.6 * step}
        for art in d.artists.get(b.name, ()):
            if not isinstance(art, Polygon):
                continue
            z = art.get_zorder()
            for old, offset in layer.items():
                if abs(z - old) < 1e-12:
                    art.set_zorder(2 + r * step + offset)
                    break


def add_forces(d, solution, on, fontsize):
    """The force arrows of a drawing (plot.arrows), hidden when it moves elsewhere."""
    arrows = force_arrows(d, solution, on, fontsize=fontsize, reframe=False)
    d.forces = arrows
    d.artists["forces"] = arrows.artists()
    q0, t0 = np.array(solution.q), solution.t

    def hide(P, q, t):
        shown = t == t0 and np.array_equal(q, q0)
        for art in d.artists["forces"]:
            art.set_visible(shown)
    d.on_move(hide)
    return arrows


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
    fig.suptitle(f"{mech.name}   T = {solutions[0].t:.4g}{time_unit(mech)}"
                 if len({s.t for s in solutions}) == 1 else mech.name)
    if own:   # panels shaped like the common frame
        f = drawings[0].frame
        panel = 5.0 if (f[1] - f[0]) < 1.3 * (f[3] - f[2]) else 6.0
        ah = min(max((panel - 0.8) * (f[3] - f[2]) / max(f[1] - f[0], 1e-12), 1.5), 1.6 * panel)
        fig.set_size_inches(panel * n, ah + 1.3)
        fig.tight_layout()
    for d in drawings:       # on the panels as laid out
        d.place_labels()
    return drawings
