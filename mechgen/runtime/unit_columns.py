"""A table's header with each column's unit, for a model that declares its units
(mechgen.units, the module's UNITS): "T [s]", "X4 [mm]", "Th3d [rad/s]", a driver's effort
"crank driver [N·mm]", a reaction "O2 on manivela fx [N]" and its moment "... m [N·mm]"; a
declared output keeps its bare name (its unit is the user's). Angles shown in degrees
(``"angle": "deg"``) have their values converted. A model without a declaration keeps its
header as it was."""
from __future__ import annotations

import numpy as np

from ..units import coordinate_kind, effort_kind
from ..units import of as units_of


def column_units(mech, header) -> list:
    """The unit of each column of ``header`` (a Sweep's or ForceSweep's table), "" where
    none is known, as (kind, order) pairs made strings by the model's Units."""
    kinds = column_kinds(mech, header)
    units = units_of(mech)
    return [units.of(kind, order) if kind else "" for kind, order in kinds]


def column_kinds(mech, header) -> list:
    """(kind, order) of each column (mechgen.units' kinds; "" for unknown)."""
    coords = {c: k for k, c in enumerate(mech.coordinates)}
    efforts = _effort_kinds(mech, [h for h in header if " on " not in h])
    out = []
    for name in header:
        if name == "T":
            out.append(("time", 0))
            continue
        stem, _, what = name.rpartition("_")
        if stem and what in ("min", "max", "tmin", "tmax") and name not in coords:
            # a table of reductions: a quantity's extreme (its own unit), or when it is
            # reached (a time)
            out.append(("time", 0) if what in ("tmin", "tmax")
                       else column_kinds(mech, [stem])[0])
            continue
        found = None
        for order, suffix in ((0, ""), (1, "d"), (2, "dd")):
            stem = name[:len(name) - len(suffix)] if suffix else name
            if name.endswith(suffix) and stem in coords:
                found = (coordinate_kind(stem), order)
                break
        if found is None:
            if name in efforts:
                found = (efforts[name], 0)
            elif name.endswith((" fx", " fy")) and " on " in name:
                found = ("force", 0)
            elif name.endswith(" m") and " on " in name:
                found = ("torque", 0)
            else:
                found = ("", 0)
        out.append(found)
    return out


def _effort_kinds(mech, header) -> dict:
    """The driver effort columns of ``header`` (a force table's: named by the driver's
    name=, or its number, with " effort" where that name is taken; forces.lookup's
    effort_column), each its kind (torque, force), read off the module's CONSTRAINTS
    (nothing imported from forces: it sits above this module)."""
    drivers = []
    for number, kind, label, _, driver in getattr(mech.module, "CONSTRAINTS", ()):
        if driver:
            name = label.split(":", 1)[0].strip() if ":" in label else str(number)
            drivers.append((name, effort_kind(kind)))
    out = {}
    for column in header:
        for name, kind in drivers:
            if column == name or column.startswith(name + " effort"):
                out.setdefault(column, kind)
    return out


def labelled(mech, header, data):
    """(header, data) as the CSV file writes them: each name with its unit in brackets,
    angles in degrees where the model shows them so; unchanged without declared units."""
    units = units_of(mech)
    if not units.declared:
        return header, data
    kinds = column_kinds(mech, header)
    if units.degrees:
        data = np.array(data, dtype=float, copy=True)
        for k, (kind, _) in enumerate(kinds):
            if kind == "angle":
                data[:, k] = np.degrees(data[:, k])
    names = [f"{name} [{units.of(kind, order)}]" if kind and units.of(kind, order) else name
             for name, (kind, order) in zip(header, kinds)]
    return names, data
