"""Pictures of a force sweep (``mech.sweep(t0, t1, n, level="dynamic"|"static")``, see
mechgen.runtime.forces): a driver's effort against the quantity it drives over a cycle,
with its mean and peak (effort), and the polar diagram of a joint's force on a body, the
locus of the force vector's tip over the sweep (polar), as Norton and Marghitu draw them.

A model that declares its units (``Model(..., units=...)``, mechgen.units) has its forces,
torques, lengths and time labelled in them (N, N·mm, mm, s); without a declaration forces
and moments are printed as they are and their axes say "model units" (the model's units of
force and length), and time is taken to be in seconds, as plot.unit takes it.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import MechgenError
from ..runtime.forces import ForceSweep, is_force_level
from ..runtime.forces.lookup import name_of, tables
from ..units import FORCE_KINDS, TORQUE_KINDS, Units
from ..units import of as units_of
from .labels import Label, Obstacles, place, renderer_of, set_offset
from .style import INK

ANGLE_KINDS, LENGTH_KINDS = TORQUE_KINDS, FORCE_KINDS     # (mechgen.units)
MEAN_COLOR = "#555555"
MODEL_UNITS = "model units"     # what a force or moment is measured in: mechgen cannot know
JUMP = 6.0           # a step of a polar locus this many times its neighbours' is a jump (a load
JUMP_SHARE = 0.02    # switching on or off) where it is also this share of the largest force
ABOVE, BELOW = "#f4b6b0", "#b5cdef"     # effort above its mean (work stored), below it


def number(x) -> str:
    """A force or moment for a label: four significant figures, no exponent between 1e-3
    and 1e6 (47055, 106.1, 63.58, 0.1234); 0 for zero."""
    x = float(x)
    if x == 0 or not math.isfinite(x):
        return f"{x:g}"
    if not 1e-3 <= abs(x) < 1e6:
        return f"{x:.3e}"
    digits = max(0, 3 - int(math.floor(math.log10(abs(x)))))
    return f"{x:.{digits}f}"


def degree(x) -> str:
    """An angle in degrees for a label, to a tenth: 240°, 257.5°."""
    return f"{float(x):.1f}".rstrip("0").rstrip(".") + "°"


def effort_unit(nature, units=None) -> str:
    """The unit of a driver's effort for an axis: a torque is a force times a length (N·mm
    in "mm-N-s"; "force × length, model units" without declared units)."""
    units = units or Units.undeclared()
    if units.declared:
        return units.of("torque" if nature == "angle" else "force") \
            if nature in ("angle", "length") else f"{units.force} or {units.of('torque')}"
    what = "force × length" if nature == "angle" else "force" if nature == "length" else ""
    return f"{what}, {MODEL_UNITS}" if what else MODEL_UNITS


def short_unit(nature, units) -> str:
    """The effort's unit after a number: "N·mm", or "model units"."""
    return effort_unit(nature, units) if units.declared else MODEL_UNITS


def time_span(t0, t1, units=None) -> str:
    """A sweep's time for a title: "time 0 .. 1 s" (T in seconds unless the model's units
    say otherwise, as plot.unit takes it)."""
    return f"time {float(t0):.4g} .. {float(t1):.4g} {(units or Units()).of('time')}"


def _degree_ticks(v, _pos):
    return f"{v:g}°"


def broken(f, share=JUMP_SHARE, ratio=JUMP):
    """The locus ``f`` (n, 2) with a NaN row between two consecutive points where it jumps
    (a load switching on or off), so that no chord is drawn across the diagram: a step
    ``ratio`` times larger than the largest of the three steps on either side of it and
    larger than ``share`` of the largest force."""
    f = np.asarray(f, dtype=float)
    if len(f) < 3:
        return f
    step = np.hypot(*np.diff(f, axis=0).T)
    size = np.hypot(f[:, 0], f[:, 1])
    top = float(np.max(size[np.isfinite(size)], initial=0.0))
    if top == 0:
        return f
    padded = np.concatenate([np.full(3, np.nan), step, np.full(3, np.nan)])
    near = np.stack([padded[k:k + len(step)] for k in (0, 1, 2, 4, 5, 6)])
    with np.errstate(invalid="ignore"):
        around = np.nanmax(np.where(np.isfinite(near), near, -np.inf), axis=0)
        jump = (step > share * top) & (step > ratio * np.maximum(around, 0.0))
    cuts = np.flatnonzero(jump) + 1
    return np.insert(f, cuts, np.nan, axis=0) if len(cuts) else f


def _check(sweep, who):
    if not isinstance(sweep, ForceSweep) or not is_force_level(sweep.force_level):
        raise TypeError(f"{who}() takes a sweep at level 'dynamic' or 'static' "
                        f"(mech.sweep(t0, t1, n, level=\"dynamic\")), got {sweep!r}")
    if len(sweep) < 2:
        raise ValueError(f"{who}(): the sweep has {len(sweep)} point(s); it needs two or more")


def short_name(mech, label) -> str:
    """A constraint's name for a label: its ``name=``, else its number (as the CSV
    columns of mechgen sweep name it)."""
    for number_, kind, full, _, _ in mech.module.CONSTRAINTS:
        if full == label:
            return name_of(full, kind) or str(number_)
    return str(label)


def pick_driver(mech, driver):
    """(label, rows, kind) of the driver named, or of the model's only driver."""
    tab = tables(mech)
    kinds = {label: kind for _, kind, label, _, _ in mech.module.CONSTRAINTS}
    if driver is None:
        names = [label for _, _, label, _, is_driver in mech.module.CONSTRAINTS if is_driver]
        if len(names) != 1:
            raise ValueError(f"model '{mech.name}' has {len(names)} drivers; name one "
                             f"(driver=...): {'; '.join(names) or 'none'}")
        driver = names[0]
    label, rows, is_driver = tab.constraint(driver, mech)
    if not is_driver:
        raise ValueError(f"constraint {label!r} of model '{mech.name}' is not a driver "
                         "(its equations do not hold T)")
    return label, rows, kinds[label]


def driven(sweep, driver=None):
    """(values, kind, absolute) of the quantity a driver drives, at every point of a
    force sweep. kind is "angle" (radians), "length" or "" (unknown); absolute is False
    where the values are its change since the sweep's first point.

    A row g(q) − f(T) (factor −1) gives f's change exactly: Φ(q(t), t₀) = f(t) − f(t₀);
    a rotation_lock's g has no constant term, so f itself is −Φ(0, t). A
    relative_distance row |r₁ − r₂|² − d(T)² has the factor −2d: d = −factor / 2. A
    stage row (a Piecewise in T) is integrated from its rate, −ν/factor (trapezoids)."""
    mech = sweep.mechanism
    tab = tables(mech)
    label, rows, kind = pick_driver(mech, driver)
    if len(rows) != 1:
        raise ValueError(f"driver {label!r} has {len(rows)} rows; its driven quantity is "
                         "one number only for a one-row driver")
    r = rows[0]
    nature = "angle" if kind in ANGLE_KINDS else "length" if kind in LENGTH_KINDS else ""
    factor = sweep.FACTORS[:, tab.driver_rows.index(r)] if tab.forces and r in \
        tab.driver_rows else -np.ones(len(sweep))
    mod, p = mech.module, mech.p
    row = np.empty(mech.m)
    if kind == "relative_distance" and np.all(np.isfinite(factor)):
        return -factor / 2.0, nature, True
    if kind == "rotation_lock":
        zero = np.zeros(mech.n)
        out = np.empty(len(sweep))
        for k, t in enumerate(sweep.t):
            mod.phi(zero, float(t), p, row)
            out[k] = -row[r]
        return out, nature, True
    if kind != "stages" and np.all(factor == -1.0):
        t0 = float(sweep.t[0])
        out = np.empty(len(sweep))
        for k, q in enumerate(sweep.Q):
            mod.phi(q, t0, p, row)
            out[k] = row[r]
        return out, nature, False
    rate = -sweep.NU[:, r] / factor
    steps = np.diff(sweep.t) * (rate[1:] + rate[:-1]) / 2
    return np.concatenate([[0.0], np.cumsum(steps)]), nature, False


def cycle_mean(x, y):
    """The mean of y over x (∫ y dx / (x₁ − x₀), trapezoids on the finite points): for
    an effort against its driven quantity, the work per unit of it. Where x does not
    move one way only (an oscillating driver) the plain mean over the points."""
    ok = np.isfinite(x) & np.isfinite(y)
    x, y = x[ok], y[ok]
    if len(x) < 2:
        return float("nan")
    dx = np.diff(x)
    if np.all(dx > 0) or np.all(dx < 0):
        return float(np.sum(dx * (y[1:] + y[:-1]) / 2) / (x[-1] - x[0]))
    return float(np.mean(y))


class EffortPlot:
    """What effort() drew: ``ax``, ``line`` (the effort), ``mean_line``, ``peak_marker``
    and ``peak_text``; the numbers ``x`` (as plotted: degrees for an angle), ``effort``,
    ``mean``, ``peak`` (the effort of largest size, signed) and ``peak_at`` (its x)."""

    def __init__(self, ax):
        self.ax = ax
        self.line = self.mean_line = self.peak_marker = self.peak_text = None
        self.fills = []

    @property
    def figure(self):
        return self.ax.figure


def effort(sweep, driver=None, ax=None, *, degrees=True, mean=True, peak=True, fill=True,
           title=None, **line_kwargs):
    """A driver's effort (torque for an angle driver, force for a distance driver) against
    the quantity it drives, over a force sweep (one cycle: ``mech.sweep(0, period, n,
    level="dynamic")``); returns an :class:`EffortPlot`.

    ``driver``: its name, label or number (None: the model's only driver). The x axis is
    the driven angle in degrees (``degrees=False``: radians), or the driven length, or, for
    another driver, the change of its driven quantity since the sweep's first point.
    ``mean`` draws the mean over the cycle as a dashed line (the work per unit of the
    driven quantity: ∫ effort df / Δf, which a constant-speed motor gives as its mean
    torque); ``fill`` shades the effort above (red) and below (blue) it, the areas whose
    largest swing is the flywheel's energy (``sw.flywheel``); ``peak`` marks the effort
    of largest size with its value. Points where the force balance has no solution
    (``sw.force_singular``) are gaps."""
    _check(sweep, "effort")
    mech = sweep.mechanism
    units = units_of(mech)
    label, _, kind = pick_driver(mech, driver)
    y = np.asarray(sweep.driver(label), dtype=float)
    x, nature, absolute = driven(sweep, label)
    name = short_name(mech, label)
    if nature == "angle" and degrees:
        x = np.degrees(x)
    own = ax is None
    if own:
        import matplotlib.pyplot as plt
        _, ax = plt.subplots(figsize=(7.0, 4.0))
    out = EffortPlot(ax)
    out.x, out.effort = x, y
    style = dict(color="C0", linewidth=1.6, label=f"{name}")
    style.update(line_kwargs)
    out.line = ax.plot(x, y, zorder=3, **style)[0]
    out.mean = cycle_mean(x, y)
    if mean and math.isfinite(out.mean):
        out.mean_line = ax.axhline(out.mean, color=MEAN_COLOR, linestyle="--", linewidth=1.1,
                                   zorder=2, label=f"mean {number(out.mean)} "
                                         f"({short_unit(nature, units)})")
        if fill:
            out.fills = [ax.fill_between(x, y, out.mean, where=y >= out.mean, color=ABOVE,
                                         linewidth=0, zorder=1, interpolate=True),
                         ax.fill_between(x, y, out.mean, where=y < out.mean, color=BELOW,
                                         linewidth=0, zorder=1, interpolate=True)]
    finite = np.isfinite(y)
    if peak and finite.any():
        k = int(np.nanargmax(np.where(finite, np.abs(y), -np.inf)))
        out.peak, out.peak_at = float(y[k]), float(x[k])
        where = degree(x[k]) if nature == "angle" and degrees else number(x[k])
        out.peak_marker = ax.plot([x[k]], [y[k]], "o", color=INK, markersize=4.5, zorder=4)[0]
        # the text on the side of the plot with more room, inside the axes
        lo, hi = float(np.nanmin(x)), float(np.nanmax(x))
        right = x[k] < (lo + hi) / 2
        peak_unit = f" {effort_unit(nature, units)}" if units.declared else ""
        out.peak_text = ax.annotate(f"peak {number(y[k])}{peak_unit} at {where}",
                                    xy=(x[k], y[k]),
                                    xytext=(10 if right else -10, -4 if y[k] > 0 else 4),
                                    textcoords="offset points",
                                    ha="left" if right else "right",
                                    va="top" if y[k] > 0 else "bottom",
                                    fontsize=9, color=INK, zorder=5)
    what = "torque" if nature == "angle" else "force" if nature == "length" else "effort"
    unit = (" [°]" if degrees else " [rad]") if nature == "angle" else \
        f" [{units.of('length')}]" if nature == "length" and units.declared else \
        f" [length, {MODEL_UNITS}]" if nature == "length" else f" [{MODEL_UNITS}]"
    quantity = {"angle": "angle", "length": "length"}.get(nature, "driven quantity")
    if absolute:
        ax.set_xlabel(f"{name}: driven {quantity}{unit}")
    else:
        ax.set_xlabel(f"{name}: change of the driven {quantity} since time "
                      f"{sweep.t[0]:.4g} {units.of('time')}{unit}")
    ax.set_ylabel(f"{name} {what} [{effort_unit(nature, units)}]")
    if nature == "angle" and degrees and np.all(np.isfinite(x)):
        span = abs(x[-1] - x[0])
        if 90 <= span <= 1440:
            step = 45 if span <= 360 else 90
            first = math.ceil(min(x[0], x[-1]) / step) * step
            ax.set_xticks(np.arange(first, max(x[0], x[-1]) + 1e-9, step))
        from matplotlib.ticker import FuncFormatter
        ax.xaxis.set_major_formatter(FuncFormatter(_degree_ticks))
    ax.set_xlim(min(x[0], x[-1]), max(x[0], x[-1]))
    ax.axhline(0.0, color="#999999", linewidth=0.7, zorder=1.5)
    ax.grid(True, color="#dddddd", linewidth=0.7)
    ax.legend(loc="best", fontsize="small", framealpha=0.9)
    if title is None:
        title = f"{mech.name}: {name} {what} over {time_span(sweep.t[0], sweep.t[-1], units)} " \
                f"({sweep.force_level})"
    if title:
        ax.set_title(title, fontsize=10)
    if own:
        ax.figure.tight_layout()
    return out


class PolarPlot:
    """What polar() drew: ``ax``, ``line`` (the locus of the force's tip), ``rays`` (the
    force vectors drawn from the origin at ``marks`` points) with their ``texts``,
    ``peak_marker``; the numbers ``force`` ((n, 2) as plotted) and ``at`` (the driven
    angles in degrees, or the times T, of the rays)."""

    def __init__(self, ax):
        self.ax = ax
        self.line = self.peak_marker = None
        self.rays, self.texts = [], []
        self.tips = np.zeros((0, 2))

    @property
    def figure(self):
        return self.ax.figure

    def place_labels(self):
        """Place the rays' labels, each beside its tip where it crosses neither the locus,
        nor a ray, nor another label (plot.labels' placement); again after a change of
        the figure's layout (``fig.tight_layout()``)."""
        if not self.texts:
            return
        ax, fig = self.ax, self.ax.figure
        ax.apply_aspect()
        renderer = renderer_of(fig)
        to_px = ax.transData.transform
        origin = to_px((0.0, 0.0))
        labels = []
        for art, tip in zip(self.texts, self.tips):
            set_offset(art, (0.0, 0.0))
            bb = art.get_window_extent(renderer)
            at = to_px(tip)
            d = at - origin
            norm = math.hypot(*d)
            prefer = d / norm if norm > 1e-9 else np.array([0.0, 1.0])
            labels.append(Label(art, at, (bb.width, bb.height), prefer, 2.0))
        obstacles = Obstacles(ax, renderer, skip=self.texts)
        frame = ax.get_window_extent(renderer)
        px_per_pt = fig.dpi / 72.0
        place(labels, obstacles, (frame.x0, frame.y0, frame.x1, frame.y1), px_per_pt)
        for lb in labels:
            set_offset(lb.artist, lb.offset / px_per_pt)


def polar(sweep, constraint, on, ax=None, *, local=False, marks=8, title=None,
          **line_kwargs):
    """The polar diagram of the force that ``constraint`` applies to body ``on`` over a
    force sweep: the locus of the force vector's tip (fx, fy) drawn from a common origin,
    at equal scale; returns a :class:`PolarPlot`. A pin's bearing load is this diagram
    for the pin on the ground (``on="base"``), its journal load for the pin on the body.

    ``local=True`` resolves the force in the body's own frame (the load a journal fixed
    in the body sees turning round it). ``marks`` rays from the origin at evenly spaced
    driven angles (or times) of the sweep, each labelled with the driven angle (an angle
    driver) or the time, placed clear of the locus (``place_labels()`` again after a change
    of layout); the force of largest size is marked with its value. Where the force jumps
    (a load switching on or off) the locus is broken, not joined by a chord (``broken``)."""
    _check(sweep, "polar")
    mech = sweep.mechanism
    units = units_of(mech)
    tab = tables(mech)
    label = tab.constraint(constraint, mech)[0]
    body = tab.body(on, mech)
    on = getattr(on, "name", on)
    f = np.asarray(sweep.reaction(label, on=on)[:, :2], dtype=float)
    if local and body is not None:
        th = sweep.Q[:, body[2]]
        c, s = np.cos(th), np.sin(th)
        f = np.column_stack([c * f[:, 0] + s * f[:, 1], -s * f[:, 0] + c * f[:, 1]])
    own = ax is None
    if own:      # a figure shaped like the diagram (drawn at equal scale)
        import matplotlib.pyplot as plt
        ok = np.isfinite(f).all(axis=1)
        box = np.ptp(np.vstack([f[ok], [[0.0, 0.0]]]), axis=0) if ok.any() else np.ones(2)
        ratio = float(box[1] / box[0]) if box[0] > 0 else 1.0
        _, ax = plt.subplots(figsize=(6.4, min(max(5.2 * ratio + 1.2, 3.2), 8.0)))
    out = PolarPlot(ax)
    out.force = f
    name = short_name(mech, label)
    style = dict(color="C3", linewidth=1.5)
    style.update(line_kwargs)
    out.line = ax.plot(*broken(f).T, zorder=3, **style)[0]
    ax.plot([0], [0], "+", color=INK, markersize=9, zorder=4)
    ax.axhline(0.0, color="#999999", linewidth=0.7, zorder=1)
    ax.axvline(0.0, color="#999999", linewidth=0.7, zorder=1)
    size = np.hypot(f[:, 0], f[:, 1])
    finite = np.isfinite(size)
    top = float(np.max(size[finite])) if finite.any() else 0.0
    angle = None
    try:
        x, nature, _ = driven(sweep)
        if nature == "angle":
            angle = np.degrees(x)
    except ValueError:       # several drivers, or one that is not one number: label by T
        pass
    along = angle if angle is not None else np.asarray(sweep.t, dtype=float)
    out.at, tips = rays_at(along, f, int(marks), top)
    shown = []
    for a, tip in zip(out.at, tips):
        if not np.all(np.isfinite(tip)):
            continue
        out.rays += ax.plot([0, tip[0]], [0, tip[1]], color="#8c8c8c", linewidth=0.8,
                            zorder=2)
        ax.plot([tip[0]], [tip[1]], ".", color=style["color"], markersize=5, zorder=4)
        text = degree(a) if angle is not None else f"t = {a:.3g} {units.of('time')}"
        out.texts.append(ax.annotate(text, xy=(tip[0], tip[1]), xytext=(0.0, 0.0),
                                     textcoords="offset points", ha="center", va="center",
                                     fontsize=8, color="#444444", zorder=5,
                                     annotation_clip=False))
        shown.append(tip)
    out.tips = np.array(shown).reshape(-1, 2)
    if top > 0:
        k = int(np.nanargmax(np.where(finite, size, -np.inf)))
        where = degree(angle[k]) if angle is not None else f"t = {sweep.t[k]:.4g} {units.of('time')}"
        out.peak_marker = ax.plot([f[k, 0]], [f[k, 1]], "o", color=INK, markersize=5,
                                  zorder=5, label=f"largest {number(top)}"
                                  f"{' ' + units.force if units.declared else ''} at {where}")[0]
        ax.legend(loc="best", fontsize="small", framealpha=0.9)
    frame = f"{on}'s frame" if local and body is not None else "global axes"
    force = units.force if units.declared else f"force, {MODEL_UNITS}"
    ax.set_xlabel(f"fx [{force}] ({frame})")
    ax.set_ylabel(f"fy [{force}] ({frame})")
    ax.set_aspect("equal", adjustable="box")
    ax.grid(True, color="#dddddd", linewidth=0.7)
    if top > 0:   # room for the ray labels around the locus
        lo, hi = np.nanmin(f, axis=0), np.nanmax(f, axis=0)
        pad = 0.12 * top
        ax.set_xlim(min(lo[0], 0) - pad, max(hi[0], 0) + pad)
        ax.set_ylim(min(lo[1], 0) - pad, max(hi[1], 0) + pad)
    if title is None:
        title = f"{mech.name}: force of {name} on {on} over " \
                f"{time_span(sweep.t[0], sweep.t[-1], units)}"
    if title:
        ax.set_title(title, fontsize=10)
    if own:
        ax.figure.tight_layout()
    out.place_labels()
    return out


def rays_at(along, f, count, top):
    """(values, tips): ``count`` evenly spaced values of the quantity ``along`` (n,) over
    the sweep (the last left out where the force closes its cycle: it is the first) and
    the force (fx, fy) there, linear between the sweep's points (on the drawn locus)."""
    n = len(along)
    if count <= 0 or n < 2 or not np.all(np.isfinite(along)):
        return np.zeros(0), np.zeros((0, 2))
    closed = n > 2 and np.allclose(f[0], f[-1], atol=1e-9 * max(top, 1e-300))
    values = np.linspace(along[0], along[-1], count + 1)[:-1] if closed else \
        np.linspace(along[0], along[-1], count)
    step = np.diff(along)
    if np.all(step > 0) or np.all(step < 0):
        sign = 1.0 if step[0] > 0 else -1.0
        tips = np.column_stack([np.interp(sign * values, sign * along, f[:, j]) for j in (0, 1)])
        return values, tips
    k = np.unique(np.linspace(0, n - 1, count).round().astype(int))   # not monotonic
    return along[k], f[k]


def require_forces(mech, what):
    """MechgenError where a model has no mass and no loads: every force is zero, and a
    picture of them says nothing."""
    if not tables(mech).forces:
        raise MechgenError(f"{what}: model '{mech.name}' has no masses and no loads, so every "
                           "force is zero (declare mass=, inertia=, m.gravity(...), "
                           "m.force(...) in the model)")
