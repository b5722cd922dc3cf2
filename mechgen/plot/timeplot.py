"""Quantities of a sweep against time or against each other (plot), with their units
(unit): coordinates, their derivatives and declared outputs, one sweep or a family."""
from __future__ import annotations

import re

from ..protocol import LEVELS
from ..runtime.results import Sweep, _lookup


def unit(mech, name, length="length", time="s"):
    """The unit of a quantity name: rad for angles, the length unit for X/Y, per time for
    derivatives; "" when unknown (a declared output)."""
    kind, k, order = _lookup(mech, name)
    per = ("", f"/{time}", f"/{time}²")[order]
    if kind == "q":
        c = mech.coordinates[k]
        if re.match(r"^(th|theta|phi|psi|alpha|beta|ang)", c, re.I):
            return "rad" + per
        if re.match(r"^[XY]\d+$", c):
            return length + per
        return ("1" + per) if per else ""
    return per[1:] if per else ""


def _label(mech, name, **units):
    u = unit(mech, name, **units)
    return f"{name} [{u}]" if u else name


def _auto_labels(sweeps):
    params = [sw.mechanism.parameters for sw in sweeps]
    keys = [k for k in params[0] if len({p.get(k) for p in params}) > 1]
    if keys:
        return [", ".join(f"{k} = {p[k]:.4g}" for k in keys) for p in params]
    names = [sw.mechanism.name for sw in sweeps]
    if len(set(names)) == len(names):
        return names
    return [f"sweep {i + 1}" for i in range(len(sweeps))]


def plot(sweep, *names, x=None, ax=None, labels=None, length="length", time="s",
         title=None, **line_kwargs):
    """Quantities of a sweep against time, or against quantity ``x``: ``plot(sw, "X4")``,
    ``plot(sw, "X4", "X4d")``, ``plot(sw, "Th3", x="Th2")``. ``sweep`` may be a list of
    sweeps (a family over a parameter), overlaid and labelled by the parameters that
    differ (or ``labels``). Returns the list of Line2D."""
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
    lines = []
    for sw, lab in zip(sweeps, labels):
        xs = sw.t if x is None else sw[x]
        for n in flat:
            ys = sw[n]
            text = n if lab is None else (lab if len(flat) == 1 else f"{n}, {lab}")
            lines += ax.plot(xs, ys, label=text, **line_kwargs)
    ax.set_xlabel(f"T [{time}]" if x is None else _label(mech, x, length=length, time=time))
    if len(flat) == 1:
        ax.set_ylabel(_label(mech, flat[0], length=length, time=time))
    else:
        us = {unit(mech, n, length=length, time=time) for n in flat}
        ax.set_ylabel(f"[{us.pop()}]" if len(us) == 1 and "" not in us else "value")
    ax.grid(True, color="#dddddd", linewidth=0.7)
    if len(lines) > 1:
        ax.legend(fontsize="small")
    if title is None:
        title = f"{mech.name}: {', '.join(flat)}" + ("" if x is None else f" against {x}")
    if title:
        ax.set_title(title)
    if own:
        ax.figure.tight_layout()
    return lines


def needed_level(mech, names) -> str:
    """The lowest sweep level (one of protocol.LEVELS) that yields every named quantity: a
    derivative's order, plus an output's own order. An unknown name raises KeyError."""
    need = 0
    for name in names:
        kind, k, order = _lookup(mech, name)
        if kind == "out":
            order += mech.output_orders[k]
        need = max(need, order)
    return LEVELS[min(need, len(LEVELS) - 1)]
