"""A model's units (docs/reference/model.md, "Units"): what its numbers are measured in, declared
with ``Model(..., units="SI" | "mm-N-s" | mapping)``, carried into the generated module's header as
the constant ``UNITS`` (a dict of plain strings) and read back by the runtime, the pictures, the CSV
files, ``mechgen forces`` and the live view, none of which import the model. mechgen computes in one
consistent set of units whatever is declared: the declaration names them (and gives ``m.gravity()``
its standard value); ``"angle": "deg"`` only changes what is shown, never what is computed
(radians). Without a declaration every output says "model units" (``Units.undeclared()``).

Base layer: no mechgen imports, nothing heavy.
"""
from __future__ import annotations

import math

MODEL_UNITS = "model units"
STANDARD_GRAVITY = 9.80665          # m/s², by definition (CGPM 1901)
# each unit: its size in the SI unit of its kind
LENGTHS = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "km": 1e3, "in": 0.0254, "ft": 0.3048}
MASSES = {"kg": 1.0, "g": 1e-3, "t": 1e3}
TIMES = {"s": 1.0, "ms": 1e-3, "min": 60.0}
ANGLES = ("rad", "deg")
FORCES = {1.0: "N", 1e3: "kN", 1e-3: "mN", 1e-5: "dyn"}   # mass·length/time² in N
SYSTEMS = {"SI": {"length": "m", "mass": "kg", "time": "s", "angle": "rad"},
           "mm-N-s": {"length": "mm", "mass": "t", "time": "s", "angle": "rad"}}
KEYS = ("length", "mass", "time", "angle")


class Units:
    """The units of a model: ``length``, ``mass``, ``time``, ``force`` (mass·length/time²,
    named N where it is one) and ``angle`` ("rad", or "deg": angles shown in degrees);
    all None for a model that declares none (``declared`` False), whose labels then say
    "model units"."""

    def __init__(self, length=None, mass=None, time=None, angle="rad"):
        self.length, self.mass, self.time, self.angle = length, mass, time, angle
        self.declared = length is not None
        self.force = None
        if self.declared:
            size = MASSES[mass] * LENGTHS[length] / TIMES[time] ** 2
            self.force = next((name for s, name in FORCES.items()
                               if math.isclose(size, s, rel_tol=1e-12)),
                              f"{mass}·{length}/{time}²")

    @classmethod
    def undeclared(cls) -> "Units":
        return cls()

    def __repr__(self):
        return f"Units({self.header()!r})" if self.declared else "Units(undeclared)"

    def __eq__(self, other):
        return isinstance(other, Units) and self.header() == other.header()

    def header(self) -> dict | None:
        """What the generated module states as UNITS (None: nothing is stated)."""
        if not self.declared:
            return None
        return {k: getattr(self, k) for k in KEYS}

    @property
    def degrees(self) -> bool:
        """Whether angles are shown in degrees."""
        return self.angle == "deg"

    @property
    def gravity(self) -> float:
        """Standard gravity in these units (length/time²)."""
        if not self.declared:
            raise ValueError("standard gravity needs the model's units")
        return STANDARD_GRAVITY * TIMES[self.time] ** 2 / LENGTHS[self.length]

    def of(self, kind, order=0) -> str:
        """The unit of a quantity of ``kind`` with ``order`` time derivatives: kind
        "length", "angle" (rad or deg as shown), "1" (a number), "force", "torque"
        (force × length, also a moment), "energy", "power", "time", "mass", "inertia"; ""
        for an unknown kind (a declared output). Undeclared: "model units" for a force,
        torque, energy or power, the kind's name for a length ("length")."""
        per = ("", "/{t}", "/{t}²")[min(order, 2)]
        if kind == "angle":
            return ("deg" if self.degrees else "rad") + per.format(t=self.time or "s")
        if kind == "time":
            return self.time or "s"
        if kind == "1":
            return ("1" + per.format(t=self.time or "s")) if order else ""
        if not self.declared:
            if kind == "length":
                return "length" + per.format(t="s")
            return MODEL_UNITS if kind in ("force", "torque", "energy", "power",
                                           "mass", "inertia") else ""
        si = self.force == "N" and self.length == "m" and self.time == "s"
        name = {"length": self.length, "force": self.force, "mass": self.mass,
                "torque": f"{self.force}·{self.length}",
                "energy": "J" if si else f"{self.force}·{self.length}",
                "power": "W" if si else f"{self.force}·{self.length}/{self.time}",
                "inertia": f"{self.mass}·{self.length}²"}.get(kind)
        return (name + per.format(t=self.time)) if name else ""

    def shown(self, kind, values):
        """Values of a quantity as labels show them: angles (and their rates) in degrees
        where the model asks for them; everything else as computed."""
        return [math.degrees(v) for v in values] if kind == "angle" and self.degrees \
            else values


def parse(spec, where="units") -> Units:
    """A declaration made Units: "SI", "mm-N-s" or a mapping of length, mass, time (and
    optionally angle); ValueError naming what is not understood."""
    if spec is None:
        return Units.undeclared()
    if isinstance(spec, Units):
        return spec
    if isinstance(spec, str):
        if spec not in SYSTEMS:
            raise ValueError(f"{where}={spec!r} is not a system mechgen knows: "
                             f"{', '.join(map(repr, SYSTEMS))}, or a mapping such as "
                             "{'length': 'mm', 'mass': 'kg', 'time': 's', 'angle': 'deg'}")
        return Units(**SYSTEMS[spec])
    if not hasattr(spec, "items"):
        raise ValueError(f"{where} must be 'SI', 'mm-N-s' or a mapping of length, mass, "
                         f"time and angle, got {type(spec).__name__}")
    spec = dict(spec)
    unknown = sorted(set(map(str, spec)) - set(KEYS))
    if unknown:
        raise ValueError(f"{where}: unknown key(s) {', '.join(map(repr, unknown))} (known: "
                         f"{', '.join(KEYS)}; a force unit follows from mass, length and time)")
    missing = [k for k in ("length", "mass", "time") if k not in spec]
    if missing:
        raise ValueError(f"{where}: give {', '.join(missing)} too (a consistent set needs "
                         "length, mass and time)")
    for key, known in (("length", LENGTHS), ("mass", MASSES), ("time", TIMES),
                       ("angle", ANGLES)):
        if key in spec and spec[key] not in known:
            raise ValueError(f"{where}: {key} {spec[key]!r} is not one mechgen knows "
                             f"({', '.join(known)})")
    return Units(spec["length"], spec["mass"], spec["time"], spec.get("angle", "rad"))


def of(module) -> Units:
    """The units a generated module states (its UNITS constant), or undeclared ones; a
    Mechanism's module (``mech.module``) or the Mechanism itself."""
    module = getattr(module, "module", module)
    stated = getattr(module, "UNITS", None)
    return parse(stated, "the module's UNITS") if stated else Units.undeclared()


def coordinate_kind(name) -> str:
    """The kind of a coordinate by its name: "angle" (Th3, and an extra coordinate named
    th.., theta.., phi.., psi.., alpha.., beta.., ang..), "length" (X2, Y2), else "1"."""
    low = name.lower()
    if (name.startswith("Th") and name[2:].isdigit()) or \
            low.startswith(("th", "phi", "psi", "alpha", "beta", "ang")):
        return "angle"
    if name[:1] in "XY" and name[1:].isdigit():
        return "length"
    return "1"


# the constraint kinds whose driver's effort is a torque (they drive an angle) or a force
# (they drive a length); another driver's effort has no unit mechgen can name
TORQUE_KINDS = ("rotation_lock", "relative_angle", "gen_revolute")
FORCE_KINDS = ("relative_x", "relative_y", "relative_distance", "gen_translate",
               "directed_distance")


def effort_kind(constraint_kind) -> str:
    """"torque", "force" or "" (unknown): what a driver of this constraint kind exerts."""
    return "torque" if constraint_kind in TORQUE_KINDS else \
        "force" if constraint_kind in FORCE_KINDS else ""
