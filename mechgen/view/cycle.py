"""One cycle of the live view: the sweep over [t0, t1] for one set of parameter values,
computed by the compiled module, turned into the columns the page reads (the frames'
poses, the traced paths, every quantity a plot may show), or, where the mechanism cannot
assemble, the message that replaces the drawing and the range over which it can.

Columns: ``t``; ``f<j>x``, ``f<j>y``, ``f<j>a`` (frame j's pose, see view.geometry; a
point's frame, which never turns, has no angle column); ``tr<j>x``, ``tr<j>y`` (traced
point j); and one column per quantity, named as the user names it: coordinates, their velocities (``X4d``) and accelerations (``X4dd``), the
declared outputs (``stroke_x``, ``stroke_xd``, ``stroke_xdd``) and, for a model with
masses or loads, each driver's effort (``driver: crank driver``).
"""
from __future__ import annotations

import warnings

import numpy as np

from ..errors import BranchJumpWarning, MechgenError
from ..runtime.tables.starts import quiet_params
from ..units import MODEL_UNITS, Units, coordinate_kind, effort_kind
from ..units import of as units_of
from .geometry import poses

DRIVER = "driver: "      # the prefix of a driver effort's column


def drivers(mech) -> list:
    """(column name, name or number for sw.driver) of each driver, for a model with
    masses or loads (its module has FORCES); [] otherwise."""
    mod = mech.module
    if not getattr(mod, "FORCES", False):
        return []
    out = []
    for entry in getattr(mod, "CONSTRAINTS", ()):
        number, _, label, _, driving = entry[:5]
        if driving:
            name = label.split(":", 1)[0].strip() if ":" in label else str(number)
            out.append((DRIVER + name, int(name) if name.isdigit() else name))
    return out


def quantity_names(mech) -> list:
    """Every quantity the plots may show, in the order the selectors list them."""
    names = []
    for suffix in ("", "d", "dd"):
        names += [c + suffix for c in mech.coordinates]
    for suffix in ("", "d", "dd"):
        names += [o + suffix for o in mech.outputs]
    return names + [column for column, _ in drivers(mech)]


def unit_of(name, mech=None) -> str:
    """A quantity's unit: in the model's declared units (mechgen.units: "mm/s", "N·mm",
    "deg" where angles are shown in degrees), else in its length (L) and time (T) units
    ("model units" for a driver's effort). With ``mech``, the quantity is read as the
    mechanism names it (a coordinate or output, then its rates X4d, X4dd): an output whose
    own name ends in d ("speed", "feed") is not a rate."""
    units = units_of(mech) if mech is not None else Units.undeclared()
    if name == "t":
        return units.time if units.declared else "T: the model's time unit"
    if name.startswith(DRIVER):
        if not units.declared:
            return MODEL_UNITS
        kind = driver_kinds(mech).get(name[len(DRIVER):], "")
        return units.of(kind) if kind else f"{units.force} or {units.of('torque')}"
    base, order = name.rstrip("d"), None
    if mech is not None:
        known = set(mech.coordinates) | set(mech.outputs)
        for k in (0, 1, 2):
            stem = name[:len(name) - k] if k else name
            if stem in known and name.endswith("d" * k):
                base, order = stem, k
                break
    if order is None:
        order = len(name) - len(base)
    if base.startswith("Th") and base[2:].isdigit():
        return units.of("angle", order) if units.declared else \
            ("rad", "rad/T", "rad/T²")[min(order, 2)]
    if base[:1] in "XY" and base[1:].isdigit():
        return units.of("length", order) if units.declared else \
            ("L", "L/T", "L/T²")[min(order, 2)]
    if units.declared:
        return units.of("1", order)
    return ("", "per T", "per T²")[min(order, 2)] if order else ""


def driver_kinds(mech) -> dict:
    """Each driver's name (as drivers() names it) -> "torque" or "force" (mechgen.units)."""
    out = {}
    for entry in getattr(mech.module, "CONSTRAINTS", ()):
        number, kind, label, _, driving = entry[:5]
        if driving:
            name = label.split(":", 1)[0].strip() if ":" in label else str(number)
            out[name] = effort_kind(kind)
    return out


class Failure(Exception):
    """The cycle cannot be solved for these parameter values: ``message`` says where."""


def solve_cycle(mech, t0, t1, n, guess=None, notes=None):
    """The sweep of one cycle at the level the plots need (dynamic where the model has
    masses or loads), or Failure naming the time it stopped at and why. ``notes`` (a
    list) receives what the solve warned of the assembly mode, each once: a mode that
    could not be carried to these parameters, a singular configuration passed (the page
    shows them under the drawing; other warnings are not the page's)."""
    level = "dynamic" if drivers(mech) else "acceleration"
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            sw = mech.sweep(float(t0), float(t1), int(n), level=level, guess=guess)
    except MechgenError as exc:
        first = str(exc).split("\n")[0]
        raise Failure(first) from None
    if notes is not None:
        for w in caught:
            text = str(w.message)
            if issubclass(w.category, BranchJumpWarning) and text not in notes:
                notes.append(text)
    return sw


def columns(mech, sw, frames, traces) -> dict:
    """The page's columns of a solved cycle (see the module's docstring)."""
    P = sw.points()
    data = {"t": np.asarray(sw.t, dtype=float)}
    pose = poses(frames, P, sw.Q)
    for j in range(len(frames)):
        if frames[j][0] == "fixed":
            continue
        data[f"f{j}x"], data[f"f{j}y"] = pose[:, j, 0], pose[:, j, 1]
        if frames[j][0] != "point":        # a point's frame never turns: no angle column
            data[f"f{j}a"] = pose[:, j, 2]
    for j, (_, where) in enumerate(traces):
        xy = where(P, sw.Q)
        data[f"tr{j}x"], data[f"tr{j}y"] = xy[:, 0], xy[:, 1]
    degrees = units_of(mech).degrees        # shown in degrees: the poses stay in radians
    for k, c in enumerate(mech.coordinates):
        turn = np.degrees if degrees and coordinate_kind(c) == "angle" else np.asarray
        data[c] = turn(sw.Q[:, k])
        data[c + "d"] = turn(sw.QD[:, k])
        data[c + "dd"] = turn(sw.QDD[:, k])
    if mech.outputs:
        for order, suffix in enumerate(("", "d", "dd")):
            values = sw.outputs(order)
            for k, o in enumerate(mech.outputs):
                data[o + suffix] = values[:, k]
    for column, name in drivers(mech):
        try:
            data[column] = np.asarray(sw.driver(name), dtype=float)
        except ValueError:          # an effort not defined (a driver along a path): none
            data[column] = np.full(len(sw.t), np.nan)
    return data


def empty_columns(names) -> dict:
    """The columns of a cycle that could not be solved: every one empty."""
    return {name: np.zeros(0) for name in names}


def assembling_range(mech, name, lo, hi, t0, t1, n=40, designs=25):
    """The interval of parameter ``name`` within [lo, hi] over which the mechanism
    assembles over the whole cycle (the others as in ``mech``), from a quick design
    table; the run of good designs nearest the current value. None if none assembles."""
    values = np.linspace(float(lo), float(hi), designs)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            tab = mech.sweep(float(t0), float(t1), n, params={name: values}, on_fail="ignore",
                             workers=1)     # a small table: threads would cost more
        ok = np.asarray(tab.ok).ravel()
    except (MechgenError, TypeError, ValueError):
        ok = np.array([_assembles(mech, name, v, t0, t1, n) for v in values])
    if not ok.any():
        return None
    current = mech.parameters[name]
    good = np.nonzero(ok)[0]
    # the run of good designs nearest the current value
    runs = np.split(good, np.nonzero(np.diff(good) > 1)[0] + 1)
    best = min(runs, key=lambda r: min(abs(values[r[0]] - current), abs(values[r[-1]] - current)))
    return float(values[best[0]]), float(values[best[-1]])


def _assembles(mech, name, value, t0, t1, n) -> bool:
    try:
        solve_cycle(quiet_params(mech, {name: value}), t0, t1, n)
    except Failure:
        return False
    return True
