"""Tables on the terminal and in CSV files: the times asked for, chosen columns, no -0."""
from __future__ import annotations

import csv
import math

import numpy as np

from ..errors import MechgenError
from ..protocol import LEVELS
from ..runtime.guards import fits, point_bytes
from ..runtime.quantity import column_names
from .options import written

FORCE_LEVELS = ("static", "dynamic")    # mechgen.runtime.forces (not imported by the parser)


def times(t0, t1, n) -> np.ndarray:
    """The n times of a sweep from t0 to t1 (both ends), as the user means them:
    t0 + k (t1 - t0)/(n - 1), and where 15 significant digits say the same number up to
    round-off (0.15000000000000002), that shorter decimal (0.15)."""
    if n < 1:
        raise MechgenError(f"n must be a positive integer, got {n}")
    fits(n, point_bytes(1, 0), "sweep points", "-n")    # before any allocation
    if n == 1:
        return np.array([float(t0)])
    out = np.empty(n)
    step = (t1 - t0) / (n - 1)
    for k in range(n):
        t = t0 + k * step
        short = float(f"{t:.15g}")
        out[k] = short if abs(short - t) <= 4 * math.ulp(t) else t
    out[0], out[-1] = t0, t1
    return out


def needed_level(mech, names, asked=None) -> str:
    """The level to solve at: the one asked for (--level), or the lowest that yields
    every named column. Unknown names, or names the level asked for cannot give, raise
    MechgenError listing what there is."""
    if asked in FORCE_LEVELS:       # the forces' levels hold every kinematic column
        kinematic = [n for n in names or () if not force_column(mech, n)]
        needed_level(mech, kinematic, "position" if asked == "static" else "acceleration")
        return asked
    low = LEVELS.index(asked) if asked else 0
    need = low
    for name in names or ():
        for k in range(len(LEVELS)):
            if name in column_names(mech, k):
                need = max(need, k)
                break
        else:
            if force_column(mech, name):
                raise MechgenError(f"{name!r} is a force column of '{mech.name}' (a driver's "
                                   "effort or a reaction): it needs --level static or dynamic")
            known = ", ".join(column_names(mech, len(LEVELS) - 1))
            raise MechgenError(f"no column {name!r} in '{mech.name}' (columns: T, {known})")
    if asked and need > low:
        raise MechgenError(f"column(s) {', '.join(names)} need --level {LEVELS[need]} "
                           f"(asked for {asked})")
    return LEVELS[need]


def force_column(mech, name) -> bool:
    """Whether ``name`` is a column of the force levels' tables: a driver's name (its
    effort; --reduce takes it too) or "<constraint> on <body> fx" (fy, m: a reaction)."""
    from ..runtime.forces.lookup import tables
    tab = tables(mech)
    entry = tab.find(name, mech)
    if entry is not None:
        return entry[2]
    if name.endswith(" effort"):       # a driver named like a column: its effort's column
        entry = tab.find(name[:-len(" effort")], mech)
        if entry is not None:
            return entry[2]
    head, _, part = name.rpartition(" ")
    constraint, on, body = head.rpartition(" on ")
    return bool(on) and part in ("fx", "fy", "m") and constraint in tab.constraints and \
        body in tab.bodies


def select(header, data, names, keep=1):
    """The table with only the named columns, after the first ``keep`` (T, or a design
    table's parameters and T); all of it when names is None."""
    if names is None:
        return header, data
    missing = [n for n in names if n not in header]
    if missing:
        raise MechgenError(f"column(s) {', '.join(repr(n) for n in missing)} not in this "
                           f"table (its columns: {', '.join(header)})")
    index = [header.index(n) for n in names if n not in header[:keep]]
    cols = list(range(keep)) + index
    return [header[c] for c in cols], data[:, cols]


def cell(v) -> str:
    """A value for the terminal: 6 significant digits, never -0."""
    if isinstance(v, float):
        return f"{v + 0.0:.6g}"          # + 0.0 turns -0.0 into 0.0
    return str(v)


def format_table(header, rows) -> str:
    """Right-aligned columns under their names."""
    cells = [[cell(float(v)) for v in row] for row in rows]
    widths = [max(len(h), *(len(r[k]) for r in cells)) if cells else len(h)
              for k, h in enumerate(header)]
    out = ["  ".join(h.rjust(w) for h, w in zip(header, widths))]
    out += ["  ".join(c.rjust(w) for c, w in zip(r, widths)) for r in cells]
    return "\n".join(out)


def write_csv(path, header, data):
    """A table as CSV: full precision (the shortest text that reads back as the same
    float), NaN (not solved) as an empty cell, never -0."""
    with written(path) as tmp, open(tmp, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for row in data:
            w.writerow(["" if x != x else repr(float(x) + 0.0) for x in row])
    return path
