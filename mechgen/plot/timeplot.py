"""Quantities of a sweep against time or against each other (plot), with their units
(unit): coordinates, their derivatives and declared outputs, one sweep or a family.

A model that declares its units (``Model(..., units=...)``, mechgen.units; the module's
UNITS) is labelled in them: lengths in its length unit, ``T`` in its time unit, angles in
degrees where it asks for them (the values shown converted; computed in radians). Without a
declaration ``T`` (the model's time symbol, the one its drivers are written in) is taken to
be in seconds unless ``time=`` says otherwise; lengths carry no unit unless ``length=``
names one; angles are in radians. A quantity whose unit is unknown (a declared output) is
labelled by its name alone.
"""
from __future__ import annotations

import math
import re

import numpy as np
from matplotlib import rcParams

from ..protocol import LEVELS
from ..units import of as units_of
from ..runtime.results import Sweep, lookup
from .scene import Scene, point_coordinate

SCALE_RATIO = 5.0    # quantities whose sizes differ more than this go on a second y axis
_ANGLE = re.compile(r"^(th|theta|phi|psi|alpha|beta|ang)", re.I)


def quantity(sweep, name):
    """The values of a quantity along a sweep: ``sweep[name]`` for a coordinate, its
    derivatives and outputs; for a point's global coordinate (``foot[3].x``,
    ``coupler.at(1.2, 0.8).y``, see scene.point_coordinate) the module's compiled point
    positions, so that nothing need be declared to plot it."""
    found = point_coordinate(name)
    if found is None:
        return sweep[name]
    label, axis = found
    _, path = Scene(sweep.mechanism).locate(label)
    return path(sweep.points(), sweep.Q)[:, axis]


def _dimension(mech, name):
    """(kind, order) of a quantity: kind "rad", "length", "1" (another coordinate) or ""
    (a declared output: unknown); order the number of time derivatives."""
    if point_coordinate(name) is not None:
        return "length", 0
    kind, k, order = lookup(mech, name)
    if kind != "q":
        return "", order
    c = mech.coordinates[k]
    if _ANGLE.match(c):
        return "rad", order
    if re.match(r"^[XY]\d+$", c):
        return "length", order
    return "1", order


def unit(mech, name, length="length", time="s", angle="rad"):
    """The unit of a quantity name: ``angle`` (rad, or deg where shown in degrees) for
    angles, ``length`` for X/Y (``length=None``: no unit stated for anything measured in
    lengths), per ``time`` for derivatives; "" when unknown (a declared output and its
    derivatives)."""
    kind, order = _dimension(mech, name)
    per = ("", f"/{time}", f"/{time}²")[order]
    if kind == "rad":
        return angle + per
    if kind == "length":
        return (length + per) if length else ""
    if kind == "1":
        return ("1" + per) if per else ""
    return ""


def model_units(mech, length=None, time=None):
    """(length, time, angle) to label ``mech``'s quantities with: the caller's length and
    time where given, else the model's declared ones (mechgen.units), else no length and
    seconds; angle "deg" where the model shows angles in degrees, else "rad"."""
    u = units_of(mech)
    if u.declared:
        return (u.length if length is None else length), \
            (u.time if time is None else time), u.angle
    return length, ("s" if time is None else time), "rad"


def shown(mech, name, values):
    """A quantity's values as its label states them: an angle (and its rates) in degrees
    where the model declares ``"angle": "deg"``; else as computed."""
    if units_of(mech).degrees and _dimension(mech, name)[0] == "rad":
        return np.degrees(values)
    return values


def _label(mech, name, length, time, angle="rad"):
    u = unit(mech, name, length=length, time=time, angle=angle)
    return f"{name} [{u}]" if u else name


def _axis_label(mech, names, length, time, angle="rad"):
    """One axis' label: the name with its unit, or the names with their common unit."""
    if len(names) == 1:
        return _label(mech, names[0], length, time, angle)
    units = {unit(mech, n, length=length, time=time, angle=angle) for n in names}
    if len(units) > 1:   # each its own unit; those with none stated last ("Th3 [rad], X4",
        # not "X4, Th3 [rad]", which reads as both in rad)
        ordered = sorted(names, key=lambda n: not unit(mech, n, length=length, time=time))
        return ", ".join(_label(mech, n, length, time, angle) for n in ordered)
    common = units.pop()
    return ", ".join(names) + (f" [{common}]" if common else "")


def _auto_labels(sweeps):
    params = [sw.mechanism.parameters for sw in sweeps]
    keys = [k for k in params[0] if len({p.get(k) for p in params}) > 1]
    if keys:
        return [", ".join(f"{k} = {p[k]:.4g}" for k in keys) for p in params]
    names = [sw.mechanism.name for sw in sweeps]
    if len(set(names)) == len(names):
        return names
    return [f"sweep {i + 1}" for i in range(len(sweeps))]


def _xy_pair(a, b) -> bool:
    """Names that differ only by an x where the other has a y ("foot_x", "foot_y")."""
    if len(a) != len(b):
        return False
    diff = [(p, q) for p, q in zip(a.lower(), b.lower()) if p != q]
    return len(diff) == 1 and set(diff[0]) == {"x", "y"}


def is_path(mech, names, x) -> bool:
    """True when plotting ``names`` against ``x`` draws a path in the plane: every one a
    length (X4 against X2) or one name paired with x by x/y ("foot_y" against "foot_x")."""
    if x is None:
        return False
    if all(_dimension(mech, n) == ("length", 0) for n in [x, *names]):
        return True
    return len(names) == 1 and _xy_pair(x, names[0])


def split_axes(mech, names, values):
    """The names grouped for a left and, when needed, a right y axis: two kinds of
    quantity (a length and a velocity, X4 and X4d) each get their own axis, and so do
    sizes more than SCALE_RATIO apart (judged on the largest magnitude of each)."""
    if len(names) < 2:
        return [list(names)]
    dims = [_dimension(mech, n) for n in names]
    known = {d for d in dims if d[0]}
    if len(known) == 2 and all(d[0] for d in dims):
        first = dims[0]
        return [[n for n, d in zip(names, dims) if d == first],
                [n for n, d in zip(names, dims) if d != first]]
    size = [float(np.nanmax(np.abs(v))) if np.size(v) and np.any(np.isfinite(v)) else 0.0
            for v in values]
    top = max(size)
    if top == 0.0:
        return [list(names)]
    # a quantity that stays at zero says nothing about sizes: it joins the first axis
    sized = sorted((math.log10(s), n) for s, n in zip(size, names) if s > 1e-9 * top)
    if len(sized) < 2 or sized[-1][0] - sized[0][0] <= math.log10(SCALE_RATIO):
        return [list(names)]
    gaps = [b[0] - a[0] for a, b in zip(sized, sized[1:])]
    cut = int(np.argmax(gaps)) + 1
    big = {n for _, n in sized[cut:]}
    small, large = [n for n in names if n not in big], [n for n in names if n in big]
    return [small, large] if names[0] in small else [large, small]   # the first on the left


def plot(sweep, *names, x=None, ax=None, labels=None, length=None, time=None, title=None,
         equal=None, **line_kwargs):
    """Quantities of a sweep against time, or against quantity ``x``: ``plot(sw, "X4")``,
    ``plot(sw, "X4", "X4d")``, ``plot(sw, "Th3", x="Th2")``. A quantity is a coordinate,
    its derivative (X4d, X4dd), a declared output, or a point's global coordinate
    (``"colisa[2].x"``, ``"coupler.at(1.2, 0.8).y"``: no output need be declared; ``plot(sw,
    "colisa[2].y", x="colisa[2].x")`` draws its path). ``sweep`` may be a list of
    sweeps (a family over a parameter), overlaid and labelled by the parameters that
    differ (or ``labels``). Returns the list of Line2D (``line.axes`` is the y axis it is
    drawn on).

    The time axis reads "time T [s]": T is the model's time symbol, the one its drivers
    are written in (``velocidad * T``); ``time`` names its unit (the model's declared
    one, else seconds unless you say otherwise). ``length`` names the unit of lengths ("mm"
    gives "X4 [mm]", "X4d [mm/s]"); by default the model's declared one, else none is
    stated. Angles are in rad, or deg (their values converted) where the model says so.

    Quantities of two kinds (X4 and X4d) or of sizes more than ``SCALE_RATIO`` apart go on
    two y axes, the second on the right (``ax.twinx()``), each labelled in its line's
    colour when it holds one line, else with one legend for both. A path (y and x
    both lengths, or names paired by x/y such as ``plot(sw, "foot_y", x="foot_x")``) is
    drawn at equal scale; ``equal=True`` or ``False`` decides it yourself.
    """
    sweeps = list(sweep) if isinstance(sweep, (list, tuple)) else [sweep]
    if not sweeps or not all(isinstance(s, Sweep) for s in sweeps):
        raise TypeError("plot() takes a Sweep or a list of Sweeps")
    flat = []
    for n in names:
        flat += [n] if isinstance(n, str) else list(n)
    if not flat:
        raise ValueError("plot(): name at least one quantity, e.g. plot(sw, 'X4')")
    if labels is None:
        labels = _auto_labels(sweeps) if len(sweeps) > 1 else [None]
    elif isinstance(labels, str):
        labels = [labels]
    if len(labels) != len(sweeps):
        raise ValueError(f"plot(): {len(sweeps)} sweeps but {len(labels)} labels")
    own = ax is None
    if own:
        import matplotlib.pyplot as plt
        _, ax = plt.subplots(figsize=(7.0, 4.2))
    mech = sweeps[0].mechanism
    needed_level(mech, flat + ([x] if x is not None else []))   # unknown names fail here
    length, time, angle = model_units(mech, length, time)
    values = {n: np.concatenate([np.ravel(shown(mech, n, quantity(sw, n))) for sw in sweeps])
              for n in flat}
    path = is_path(mech, flat, x) if equal is None else bool(equal)
    groups = [flat] if path else split_axes(mech, flat, [values[n] for n in flat])
    axes = [ax] if len(groups) == 1 else [ax, ax.twinx()]
    where = {n: axes[g] for g, group in enumerate(groups) for n in group}
    # one colour cycle over both axes: a twin axis would start its own again
    cycle = rcParams["axes.prop_cycle"].by_key().get("color", ["C0"])
    recolor = not ({"color", "c"} & set(line_kwargs))
    lines = []
    for sw, lab in zip(sweeps, labels):
        xs = sw.t if x is None else shown(mech, x, quantity(sw, x))
        for n in flat:
            text = n if lab is None else (lab if len(flat) == 1 else f"{n}, {lab}")
            kw = dict(line_kwargs)
            if recolor:
                kw["color"] = cycle[len(lines) % len(cycle)]
            lines += where[n].plot(xs, shown(mech, n, quantity(sw, n)), label=text, **kw)
    ax.set_xlabel(f"time T [{time}]" if x is None else _label(mech, x, length, time, angle))
    coloured = 0
    for a, group in zip(axes, groups):
        a.set_ylabel(_axis_label(mech, group, length, time, angle))
        mine = [ln for ln in lines if ln.axes is a]
        if len(axes) > 1 and len({ln.get_color() for ln in mine}) == 1:
            a.yaxis.label.set_color(mine[0].get_color())   # which axis is whose
            coloured += 1
    ax.grid(True, color="#dddddd", linewidth=0.7)
    if len(lines) > 1 and coloured < len(axes):   # (axis labels in line colours say it all)
        axes[-1].legend(handles=lines, fontsize="small")
    if path:
        ax.set_aspect("equal", adjustable="datalim")
    if title is None:
        title = f"{mech.name}: {', '.join(flat)}" + ("" if x is None else f" against {x}")
    if title:
        ax.set_title(title)
    if own:
        ax.figure.tight_layout()
    return lines


def needed_level(mech, names) -> str:
    """The lowest sweep level (one of protocol.LEVELS) that yields every named quantity: a
    derivative's order, plus an output's own order; a point's coordinate (``foot[3].x``)
    needs positions only. An unknown name raises KeyError (a point: MechgenError)."""
    need = 0
    for name in names:
        found = point_coordinate(name)
        if found is not None:
            Scene(mech).locate(found[0])      # an unknown point fails here, naming them all
            continue
        kind, k, order = lookup(mech, name)
        if kind == "out":
            order += mech.output_orders[k]
        need = max(need, order)
    return LEVELS[min(need, len(LEVELS) - 1)]
