"""How force results name things: the constraints (by name, label or number) with their
rows and whether they drive, the bodies with their coordinates, and the force levels."""
from __future__ import annotations

import functools

from ...protocol import FORCE_LEVELS


def loads_guarded(span: bool):
    """Decorate a force solve (``span`` False: its first argument after the mechanism is t)
    or a force sweep or simulation (True: t0, t1) so that a division by zero in the module's
    force functions (a spring or damper whose two ends meet has no direction; a load that
    divides by zero there) is a SingularError that says when and names the springs and
    dampers, not a bare ZeroDivisionError from the generated code."""
    def wrap(func):
        @functools.wraps(func)
        def guarded(mech, *args, **kwargs):
            try:
                return func(mech, *args, **kwargs)
            except ZeroDivisionError:
                pass
            t = float(args[0])
            when = f"between t={t:.10g} and t={float(args[1]):.10g}" if span else \
                f"at t={t:.10g}"
            raise division_error(mech, when, float("nan") if span else t) from None
        return guarded
    return wrap


def division_error(mech, when, t=float("nan")):
    """The SingularError of loads_guarded: the force terms divide by zero ``when``. Where
    the mechanism's parameters break a load constant (gravity's direction of zero length:
    limits.refused_constant), that is the cause it names; else the springs and dampers
    whose ends may meet."""
    from ...errors import SingularError
    from .limits import refused_constant
    cause = refused_constant(mech.module, mech.p)
    if cause:
        return SingularError(f"model '{mech.name}': the force terms divide by zero (or are "
                             f"not finite) {when}: {cause}", t=t)
    ends = [f"{name or kind} ({kind})" for name, kind, _ in
            getattr(mech.module, "LOADS", ()) if kind in ("spring", "damper")]
    said = (f"a spring or damper whose two ends meet has no direction (this model's: "
            f"{', '.join(ends)}), or " if ends else "")
    return SingularError(f"model '{mech.name}': the force terms divide by zero (or are "
                         f"not finite) {when}: "
                         f"{said}a load, mass or spring expression divides by zero there", t=t)


def is_force_level(level) -> bool:
    return level.__class__ is str and level in FORCE_LEVELS


# -- the model's tables -------------------------------------------------------------------
class _Tables:
    """What the force results look up, read once per module: constraint rows and names,
    the bodies' coordinates, the driver rows."""

    def __init__(self, mech):
        mod = mech.module
        self.forces = bool(getattr(mod, "FORCES", False))
        self.driver_rows = tuple(getattr(mod, "DRIVER_ROWS", ()))
        self.constraints = {}        # name, label or number -> (label, rows, is driver)
        self.ambiguous = {}          # a text that names several constraints -> their labels
        row = 0
        for number, kind, label, count, driver in mod.CONSTRAINTS:
            entry = (label, tuple(range(row, row + count)), bool(driver))
            row += count
            self.constraints[number] = entry
            for key in (label, name_of(label, kind), *_stage_names(label, kind),
                        str(number)):
                if key is None:
                    continue
                known = self.constraints.get(key, entry)
                if known[0] != entry[0]:          # two constraints answer to this text
                    self.ambiguous.setdefault(key, [known[0]]).append(entry[0])
                self.constraints.setdefault(key, entry)
        for key in self.ambiguous:
            del self.constraints[key]
        index = {c: k for k, c in enumerate(mech.coordinates)}
        self.bodies = {}             # name -> (X, Y, Th) indices, or None for the ground
        self.ground = None
        for name, number, is_ground in mod.BODIES:
            if is_ground:
                self.ground = name
                self.bodies[name] = None
            else:
                self.bodies[name] = (index[f"X{number}"], index[f"Y{number}"],
                                     index[f"Th{number}"])

    def find(self, name, mech):
        """The entry of constraint ``name`` (its name, label or number), None where no
        constraint has it; a ValueError where it names several (two constraints with one
        name=, or a name that is another constraint's number): never the first of them
        silently."""
        if name.__class__ is str and name in self.ambiguous:
            labels = self.ambiguous[name]
            raise ValueError(f"model '{mech.name}': {name!r} names {len(labels)} "
                             f"constraints ({'; '.join(labels)}); give the number (an "
                             "int) or the whole label")
        return self.constraints.get(name)

    def constraint(self, name, mech):
        entry = self.find(name, mech)
        if entry is None:
            names = sorted({str(v[0]) for v in self.constraints.values()})
            raise ValueError(f"model '{mech.name}' has no constraint {name!r} (constraints: "
                             f"{'; '.join(names)})")
        return entry

    def body(self, name, mech):
        name = getattr(name, "name", name)
        if name not in self.bodies:
            raise ValueError(f"model '{mech.name}' has no body {name!r} (bodies: "
                             f"{', '.join(self.bodies)})")
        return self.bodies[name]


def name_of(label, kind):
    """The ``name=`` of a constraint from its label ``name: kind(args)``, or None."""
    marker = f": {kind}("
    return label.split(marker, 1)[0] if marker in label else None


def column_name(tab, label, kind, number) -> str:
    """How a table's columns name a constraint: its name=, or its number where it has
    none or shares its name with another constraint (two columns "pin on crank fx"
    would be told apart by position only)."""
    name = name_of(label, kind)
    return name if name is not None and name not in tab.ambiguous else str(number)


def effort_column(name, taken) -> str:
    """The table column of a driver's effort: its name, or ``<name> effort`` where that
    name is a column already (a coordinate, an output or a parameter of the same name:
    a driver named like the coordinate it drives), so that no two columns share a name.
    ``taken`` (a set) gains the column."""
    column, k = name, 1
    while column in taken:
        k += 1
        column = f"{name} effort" if k == 2 else f"{name} effort {k - 1}"
    taken.add(column)
    return column


def _stage_names(label, kind):
    """The names of a stage group's constraints, ``[stage] name: kind(args) | ...``."""
    if kind != "stages":
        return ()
    out = []
    for part in label.split(" | "):
        part = part.split("] ", 1)[-1]
        if ": " in part:
            out.append(part.split(": ", 1)[0])
    return tuple(out)


def tables(mech) -> _Tables:
    mod = mech.module
    state = mech.state
    cached = state.force_tables
    if cached is None or cached[0] is not mod:
        cached = state.force_tables = (mod, _Tables(mech))
    return cached[1]


def _constraints_of(mech, row_labels):
    """The constraints (their labels) of some row labels, in order, each once."""
    tab = tables(mech)
    out = []
    for label, rows, _ in {v[0]: v for v in tab.constraints.values()}.values():
        if any(mech.constraint_labels[r] in row_labels for r in rows):
            out.append(label)
    return tuple(out)
