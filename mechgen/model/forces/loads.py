"""Mass properties and loads (Mech's Body[..., Mass, Inertia, Centroid], Gravity, SetLoads):
the ``Model`` methods that declare them (``LoadsMixin``, inherited by ``Model``).

They leave the kinematics alone: Φ and its derivatives do not read them, and a model
without mass or loads builds exactly the module it built before. mechgen.model.forces.dynamics
turns them into the generalized forces of Φ_qᵀ λ = Q_a + Q_c − I.

Every value may be a number, a parameter or an expression; a load may also read the
coordinates, their velocities (``dt(...)``, ``velocity(p)``) and T. A negative mass or
inertia (at the parameters' defaults) is a ModelError naming the body.
"""
from __future__ import annotations

import sympy as sp

from ...errors import ModelError
from ..geometry import Body, Line, Point, T, as_pair, label_name


def _s(expr) -> str:
    """An expression as a label shows it (1.5, not 1.50000000000000)."""
    return sp.sstr(expr, full_prec=False)


def _real(expr, what):
    """``expr``, or a ModelError where it holds the imaginary unit."""
    if expr.has(sp.I):
        raise ModelError(f"{what}: {expr} is complex (it holds I); the module computes in "
                         "real numbers")
    return expr


class Load:
    """One load: ``kind`` ("force", "moment", "spring", "damper"), its ``name`` (or None)
    and the parts dynamics reads: points, bodies, a vector or a value."""

    def __init__(self, kind, name, **parts):
        self.kind = kind
        self.name = name
        self.__dict__.update(parts)

    @property
    def label(self) -> str:
        """``kind(arguments)``, prefixed by ``name: `` when the load has a name."""
        text = getattr(self, "text", self.kind)
        return f"{self.name}: {text}" if self.name else text

    def __repr__(self):
        return f"<load {self.label}>"


class LoadsMixin:
    """Mass properties on bodies, gravity, forces, moments, springs and dampers."""

    @property
    def loads(self) -> list:
        """The loads in declaration order ([] for a model without them)."""
        return self.__dict__.setdefault("_loads", [])

    @property
    def gravity_vector(self):
        """(g_x, g_y): the acceleration of gravity, or None without m.gravity."""
        return self.__dict__.get("_gravity")

    @property
    def gravity_parts(self):
        """(g, the length of the direction given) of m.gravity, or None without it."""
        return self.__dict__.get("_gravity_parts")

    # -- mass properties (read by Model.body) ------------------------------------------
    def _mass_properties(self, name, mass, inertia, centroid):
        """(mass, inertia, centroid) of body ``name`` as sympy values, checked."""
        m = self._property(mass, f"body '{name}': mass")
        j = self._property(inertia, f"body '{name}': inertia")
        for value, what in ((m, "mass"), (j, "inertia")):
            number = value.subs({s: v for s, v in self.params.values()})
            if number.is_number and float(number) < 0:
                raise ModelError(f"body '{name}': {what} {value} is negative "
                                 f"({float(number):g} at the parameters' defaults)")
        c = as_pair((0, 0) if centroid is None else centroid, f"body '{name}': centroid")
        c = tuple(self._property(v, f"body '{name}': centroid") for v in c)
        return m, j, c

    def _property(self, value, what):
        expr = _real(self._expr(value, what), what)
        if T in expr.free_symbols:
            raise ModelError(f"{what} may not depend on T")
        return expr

    @property
    def has_dynamics(self) -> bool:
        """True when the model has a mass, an inertia or a load (its module then holds the
        force functions)."""
        massive = any(getattr(b, "mass", 0) != 0 or getattr(b, "inertia", 0) != 0
                      for b in self.bodies.values() if not b.is_ground)
        return massive or bool(self.loads) or self.gravity_vector is not None

    def load_doubts(self) -> list:
        """What the loads do not do that their author likely meant: gravity on a model
        whose moving bodies have no mass acts on nothing (its forces are all zero)."""
        if self.gravity_vector is None:
            return []
        if any(getattr(b, "mass", 0) != 0 for b in self.bodies.values() if not b.is_ground):
            return []
        return [f"model '{self.name}' sets gravity, but none of its moving bodies has a "
                "mass: gravity exerts no force on it (give the bodies mass=...)"]

    # -- loads ------------------------------------------------------------------------
    def gravity(self, g=None, direction=(0, -1)):
        """Mech's Gravity: m·g on every body at its centroid along ``direction`` (a
        vector, made unit; downwards unless given). Without ``g``, standard gravity in the
        model's units (9.80665 m/s² in "SI", 9806.65 mm/s² in "mm-N-s")."""
        if self.gravity_vector is not None:
            raise ModelError(f"model '{self.name}' already has gravity; declare it once")
        if g is None:
            if not self.units.declared:
                raise ModelError(f"model '{self.name}': m.gravity() without g takes standard "
                                 "gravity in the model's units, and the model declares none: "
                                 "give Model(..., units=\"SI\") (or \"mm-N-s\"), or the "
                                 "value, m.gravity(9.81)")
            g = self.units.gravity
        g = self._property(g, "gravity: g")
        number = g.subs({s: v for s, v in self.params.values()})
        if number.is_number and float(number) < 0:
            raise ModelError(f"gravity: g = {_s(g)} is negative: g is the magnitude, and "
                             "direction= gives the way it acts (downwards, (0, -1), unless "
                             "given); write m.gravity(9.81) for gravity pointing down")
        d = [self._property(v, "gravity: direction") for v in as_pair(direction,
                                                                       "gravity: direction")]
        size = sp.sqrt(d[0] ** 2 + d[1] ** 2)
        if size.is_number and float(size) == 0:
            raise ModelError("gravity: direction must not be the zero vector")
        if size.is_number and abs(float(size) - 1.0) == 0:
            size = sp.Integer(1)
        self.__dict__["_gravity"] = (g * d[0] / size, g * d[1] / size)
        self.__dict__["_gravity_parts"] = (g, size)    # (read by the module's load_constants)
        self._equations = None

    def force(self, point, f, along=None, name=None):
        """A force at ``point``: ``force(p, (fx, fy))`` in global components, or
        ``force(p, f, along=axis)``: magnitude f along the axis' direction (turning with
        the axis' body)."""
        p = self._load_point(point, "force", 1)
        if p.body.is_ground:
            raise ModelError(f"force: point {p.label} is fixed in the ground '{p.body.name}', "
                             "which does not move: a force on it does no work and enters no "
                             "equation (what the joints apply to the ground is "
                             f"s.reaction(name, on='{p.body.name}')); put it on a moving body")
        if along is not None:
            if not isinstance(along, Line):
                raise ModelError(f"force: along= must be an axis such as body.line(1, 2), "
                                 f"got {along!r}")
            if along.model is not self:
                raise ModelError(f"force: along= {along!r} belongs to model "
                                 f"'{along.model.name}', not to model '{self.name}' (its "
                                 "direction would read this model's coordinates of the same "
                                 "names); use an axis of this model")
            mag = self._load_value(f, "force: magnitude")
            u = along.u
            vec = sp.Matrix([mag * u[0], mag * u[1]]) / sp.sqrt(u[0] ** 2 + u[1] ** 2)
            text = f"force({p.label}, {_s(mag)}, along={along!r})"
        else:
            fx, fy = as_pair(f, "force: (fx, fy)")
            vec = sp.Matrix([self._load_value(fx, "force: fx"),
                             self._load_value(fy, "force: fy")])
            text = f"force({p.label}, ({_s(vec[0])}, {_s(vec[1])}))"
        return self._add_load(Load("force", self._load_name(name, "force"), point=p,
                                   vector=vec, text=text))

    def moment(self, b1, b2_or_value, value=None, name=None):
        """A pure moment: ``moment(body, M)`` on one body (counter-clockwise positive),
        or ``moment(b1, b2, M)``: +M on b1 and −M on b2 (a motor between them)."""
        if value is None:
            bodies, value = (self._load_body(b1, "moment", 1),), b2_or_value
        else:
            bodies = (self._load_body(b1, "moment", 1), self._load_body(b2_or_value, "moment", 2))
        if all(b.is_ground for b in bodies) or len(bodies) == 2 and bodies[0] is bodies[1]:
            what = ("the ground, which does not move" if bodies[0].is_ground else
                    f"body '{bodies[0].name}' twice (+M and -M cancel)")
            raise ModelError(f"moment({', '.join(b.name for b in bodies)}, ...): it acts on "
                             f"{what}: it enters no equation; a moment acts on a moving body "
                             "(or between two bodies)")
        m = self._load_value(value, "moment: M")
        text = f"moment({', '.join(b.name for b in bodies)}, {_s(m)})"
        return self._add_load(Load("moment", self._load_name(name, "moment"), bodies=bodies,
                                   value=m, text=text))

    def spring(self, p1, p2, k, length, name=None):
        """A spring between two points: tension k·(distance − length) along p1–p2
        (conservative: its energy ½k(distance − length)² is the model's potential)."""
        a = self._load_point(p1, "spring", 1)
        b = self._load_point(p2, "spring", 2)
        self._two_bodies("spring", a, b)
        k = self._load_value(k, "spring: k", velocities=False)
        length = self._load_value(length, "spring: length", velocities=False)
        self._not_negative(k, f"spring({a.label}, {b.label}): the stiffness k", zero=False)
        self._not_negative(length, f"spring({a.label}, {b.label}): the free length")
        return self._add_load(Load("spring", self._load_name(name, "spring"), points=(a, b),
                                   k=k, length=length,
                                   text=f"spring({a.label}, {b.label}, k={_s(k)}, length={_s(length)})"))

    def damper(self, p1, p2, c, name=None):
        """A damper between two points: tension c·(rate of change of their distance)."""
        a = self._load_point(p1, "damper", 1)
        b = self._load_point(p2, "damper", 2)
        self._two_bodies("damper", a, b)
        c = self._load_value(c, "damper: c")
        self._not_negative(c, f"damper({a.label}, {b.label}): the coefficient c", zero=False)
        return self._add_load(Load("damper", self._load_name(name, "damper"), points=(a, b),
                                   c=c, text=f"damper({a.label}, {b.label}, c={_s(c)})"))

    # -- checks -----------------------------------------------------------------------
    def _add_load(self, load):
        self.loads.append(load)
        self._equations = None
        return load

    def _load_name(self, name, kind):
        if name is None:
            return None
        label_name(name, kind)
        if any(x.name == name for x in self.loads):
            raise ModelError(f"{kind}: a load named {name!r} exists already")
        return name

    def _load_point(self, value, kind, pos):
        if not isinstance(value, Point):
            raise ModelError(f"{kind}: argument {pos} must be a point such as body[1], "
                             f"got {value!r}")
        if value.body.model is not self:
            raise ModelError(f"{kind}: argument {pos} ({value}) belongs to another model")
        return value

    def _two_bodies(self, kind, a, b):
        """A spring or damper joins two bodies: with both ends in one its length never
        changes and it acts on nothing."""
        if a.body is b.body:
            raise ModelError(f"{kind}({a.label}, {b.label}): both ends are fixed in body "
                             f"'{a.body.name}', so their distance never changes and the "
                             f"{kind} acts on nothing; join points of two bodies")

    def _not_negative(self, value, what, zero=True):
        """A ModelError where ``value`` is negative at the parameters' defaults, or (``zero``
        False) a plain number that is 0; values that read the coordinates are not checked."""
        number = value.subs({s: v for s, v in self.params.values()})
        if not number.is_number:
            return
        x = complex(number)
        if x.imag == 0 and (x.real < 0 or (not zero and x.real == 0 and value.is_number)):
            at = "" if value.is_number else f" ({x.real:g} at the parameters' defaults)"
            raise ModelError(f"{what} {_s(value)} is {'negative' if x.real < 0 else 'zero'}"
                             f"{at}: it must be {'not negative' if zero else 'positive'}")

    def _load_body(self, value, kind, pos):
        if isinstance(value, str):
            value = self[value]
        if not isinstance(value, Body) or value.model is not self:
            raise ModelError(f"{kind}: argument {pos} must be a body of this model, "
                             f"got {value!r}")
        return value

    def _load_value(self, value, what, velocities=True):
        """A load's value: coordinates, velocities (not accelerations), T and parameters."""
        expr = _real(self._expr(value, what, allow_coordinates=True,
                                allow_derivatives=velocities), what)
        from ..symbolic import derivative_symbols
        _, qdd = derivative_symbols(self.coords)
        if expr.free_symbols & set(qdd):
            raise ModelError(f"{what}: a load may not read accelerations "
                             f"({', '.join(sorted(str(s) for s in expr.free_symbols & set(qdd)))})")
        return expr
