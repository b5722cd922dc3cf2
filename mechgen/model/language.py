"""The model: bodies, coordinates, parameters, constraints and outputs, in declaration order."""
from __future__ import annotations

import keyword
import math
import numbers
import sys
import unicodedata

import sympy as sp

from .. import units as _units
from ..errors import ModelError, user_frame
from .constraints import (Constraint, Expression, Orthogonal, Parallel, PointOnLine,
                          RelativeAngle, RelativeDistance, RelativeX, RelativeY, Revolute,
                          RotationLock, Translate)
from .forces.loads import LoadsMixin
from .geometry import Body, T, label_name
from .library2d.cams import CamsMixin
from .library2d.methods import Mech2D
from .quantities import register_coordinates, register_model
from .stages import StageMixin

# The names a model may not give a parameter, coordinate, body or output: Python's keywords,
# the time symbol T, and what ``from mechgen import *`` brings into a model file (sympy's
# constant E excepted, as sympy's other one-letter names I, S and N are not exported).
# Names the generated module uses for itself (i, k, t, q, p, tol, ...) are free: the
# compiler writes a model's symbols under other identifiers where they collide.
API_NAMES = frozenset({
    "ModelError", "ConvergenceError", "SingularError", "MechgenError", "SolveError",
    "BranchJumpWarning", "RedundancyWarning", "ModelWarning", "load", "compile", "__version__",
    "sin", "cos", "tan", "sqrt", "atan2", "atan", "asin", "acos", "exp", "log", "pi",
    "Abs", "sign", "sinh", "cosh", "tanh", "Rational", "Piecewise", "Symbol", "Matrix",
    "location", "distance", "point_to_line_distance", "angle", "rotation", "intersection",
    "project_on_line", "direction", "magnitude", "unit", "cross", "rotation_matrix",
    "point_to_local", "polar_to_xy", "xy_to_polar", "velocity", "acceleration", "dt",
    "Model", "T", "Line", "load_model", "Mechanism", "Solution", "Sweep", "Equations",
    "DesignTable", "Reduction", "OptimizeResult"})
REFUSED = API_NAMES | {"T"} | set(keyword.kwlist)


# modules the generated code, numba or mechgen import: a model may not take their names
_IMPORTED = frozenset({"numpy", "numba", "llvmlite", "scipy", "sympy", "jinja2", "mechgen",
                       "matplotlib", "mpmath", "dask", "distributed", "pandas"})
# the longest model name, in UTF-8 bytes: <name>.py and numba's cache files
# <name>.<function>-<line>.py311.nbi must fit a file name (255 bytes on most systems)
MAX_MODEL_NAME = 150
_CREATED = None     # while model.loader runs a file: the list of every Model it creates


def collect_models(into) -> None:
    """From now on append every Model created to the list ``into`` (None: stop)."""
    global _CREATED
    _CREATED = into


def _is_identifier(name) -> bool:
    """A Python identifier that Python reads back unchanged (NFKC-normalised)."""
    return isinstance(name, str) and name.isidentifier() and \
        unicodedata.normalize("NFKC", name) == name


# the names of the derived quantities <name>d, <name>dd, in words
_DERIVED = {"coordinate": ("velocity", "acceleration"),
            "output": ("first derivative", "second derivative")}


class Model(CamsMixin, LoadsMixin, Mech2D, StageMixin):
    """A planar mechanism: bodies, constraints, parameters, loads.

    Every ``Model`` defined at module level of a model file is built. Bodies, joints,
    drivers and parameters are declared with its methods (below, and on the constraint
    reference); ``m.equations()`` expands them into Φ, Φ_q, ν and γ.

    Parameters
    ----------
    name : str
        The name of the generated module (a Python identifier, not a keyword nor the name
        of a module mechgen imports).
    units : str or mapping, optional
        What its numbers are measured in: "SI", "mm-N-s" or a mapping of length, mass,
        time and angle (docs/reference/model.md "Units", mechgen.units); None: "model
        units".
    """

    def __init__(self, name: str, units=None):
        if not _is_identifier(name) or keyword.iskeyword(name):
            raise ModelError(f"Model name {name!r} must be a Python identifier that is not a "
                             "keyword (it names the generated module)")
        if name in getattr(sys, "stdlib_module_names", ()) or name in _IMPORTED:
            raise ModelError(f"Model name {name!r} is the name of a Python module (the "
                             "standard library's, or one mechgen and numba import): the "
                             "generated module would shadow it; choose another name")
        if len(name.encode("utf-8")) > MAX_MODEL_NAME:
            raise ModelError(f"Model name {name[:40]}... is {len(name.encode('utf-8'))} bytes "
                             f"long: it names the module file <name>.py and numba's cache "
                             f"files beside it, which the file system limits; keep it within "
                             f"{MAX_MODEL_NAME} bytes")
        self.name = name
        self.doc = ""
        try:
            self.units = _units.parse(units)
        except ValueError as exc:
            raise ModelError(f"model '{name}': {exc}") from None
        self.params: dict[str, tuple[sp.Symbol, float]] = {}
        self.ground_body: Body | None = None
        self.bodies: dict[str, Body] = {}
        self.coords: list[sp.Symbol] = []        # q, in declaration order
        self.guess: dict[sp.Symbol, object] = {}
        self.constraints: list[Constraint] = []
        self.outputs: dict[str, object] = {}
        self._names: dict[str, str] = {}          # every user-visible name -> what it is
        self._equations = None
        self._where = _where()
        register_model(self)                        # dt without a model: see quantities
        if _CREATED is not None:                    # a model file being loaded: see loader
            _CREATED.append(self)

    def __repr__(self):
        return (f"<Model {self.name!r}: {len(self.bodies)} bodies, {len(self.coords)} coordinates, "
                f"{sum(len(c.exprs) for c in self.constraints)} equations>")

    # -- declarations -------------------------------------------------------------
    def _claim(self, name: str, what: str):
        self._check_name(name, what)
        self._names[name] = what
        self._equations = None

    def _check_name(self, name: str, what: str, derived=False):
        """``derived``: the name is a coordinate's or an output's, whose own derived names
        (<name>d, <name>dd) must be free too."""
        if not _is_identifier(name):
            raise ModelError(f"{what} name {name!r} must be an identifier (letters, digits, _; "
                             "not starting with a digit)")
        if name in REFUSED:
            raise ModelError(f"{what} name {name!r} is reserved (Python or mechgen's own "
                             "API uses it); choose another")
        if name in self._names:
            raise ModelError(f"{what} name {name!r} clashes with the {self._names[name]} "
                             f"of the same name")
        # a coordinate's velocity and acceleration are named <name>d and <name>dd, and so
        # are an output's first and second derivatives (s["vd"], a sweep's CSV column)
        others = [("coordinate", c.name) for c in self.coords] + \
            [("output", o) for o in self.outputs]
        for kind, other in others:
            for suffix, which in zip(("d", "dd"), _DERIVED[kind]):
                if name == other + suffix:
                    raise ModelError(f"{what} name {name!r} clashes with the {which} of "
                                     f"{kind} '{other}'")
        if derived:
            kind = "output" if what == "output" else "coordinate"
            for suffix, which in zip(("d", "dd"), _DERIVED[kind]):
                if name + suffix in self._names:
                    raise ModelError(f"{what} name {name!r}: its {which} {name + suffix} "
                                     f"clashes with the {self._names[name + suffix]} of the "
                                     "same name")

    def param(self, name: str, default) -> sp.Symbol:
        """A parameter: a sympy Symbol with a numeric default, changeable at run time."""
        self._check_name(name, "parameter")
        value = _number(default, f"parameter '{name}': the default")
        self._claim(name, "parameter")
        sym = sp.Symbol(name, real=True)
        self.params[name] = (sym, value)
        return sym

    def ground(self, name: str, points=()) -> Body:
        """The fixed body (number 1); its points are global."""
        if self.ground_body is not None:
            raise ModelError(f"model '{self.name}' already has a ground "
                             f"('{self.ground_body.name}'); one ground per model")
        self._check_name(name, "body")
        body = Body(self, name, 1, _points(points, name), ground=True)
        self._check_local(body)
        self._claim(name, "body")
        self.ground_body = body
        self.bodies[name] = body
        return body

    def body(self, name: str, points=(), guess=(0.0, 0.0, 0.0), mass=0, inertia=0,
             centroid=None) -> Body:
        """A moving body, numbered 2, 3, ... in declaration order, coordinates X<n>, Y<n>, Th<n>.
        ``mass``, ``inertia`` (polar, about the centroid) and ``centroid`` (local; default
        the origin) are its mass properties (mechgen.model.forces.loads)."""
        # validate everything first: a rejected body leaves the model as it was
        self._check_name(name, "body")
        number = 2 + sum(1 for b in self.bodies.values() if not b.is_ground)
        body = Body(self, name, number, _points(points, name), ground=False)
        for sym in body.coordinates:
            self._check_name(sym.name, f"coordinate of body '{name}'", derived=True)
            if name in (sym.name, sym.name + "d", sym.name + "dd"):
                raise ModelError(f"body name {name!r} clashes with the coordinate {sym.name} "
                                 f"of this body (body {number}: X{number}, Y{number}, "
                                 f"Th{number}), or its derivative; choose another")
        self._check_local(body)
        if isinstance(guess, (str, bytes)) or isinstance(guess, sp.MatrixBase):
            guess = list(guess) if isinstance(guess, sp.MatrixBase) else guess
        try:
            gx, gy, gth = guess
        except (TypeError, ValueError):
            raise ModelError(f"body '{name}': guess must be (x, y, th), got {guess!r}") from None
        values = [self._guess_value(value, f"body '{name}': guess of {sym}")
                  for sym, value in zip(body.coordinates, (gx, gy, gth))]
        body.mass, body.inertia, body.centroid = self._mass_properties(name, mass, inertia,
                                                                       centroid)
        self._claim(name, "body")
        for sym, value in zip(body.coordinates, values):
            self._claim(sym.name, f"coordinate of body '{name}'")
            self.guess[sym] = value
        self.coords.extend(body.coordinates)
        register_coordinates(body.coordinates)
        self.bodies[name] = body
        return body

    def coordinate(self, name: str, guess=0.0) -> sp.Symbol:
        """An extra scalar coordinate (a joint angle of a loop-closure model, say)."""
        self._check_name(name, "coordinate", derived=True)
        value = self._guess_value(guess, f"coordinate '{name}': guess")
        self._claim(name, "coordinate")
        sym = sp.Symbol(name, real=True)
        self.guess[sym] = value
        self.coords.append(sym)
        register_coordinates([sym])
        return sym

    def output(self, name: str, expr):
        """Declare a quantity to compile into the generated module (``s[name]``)."""
        self._check_name(name, "output", derived=True)
        if isinstance(expr, (list, tuple)):
            expr = sp.Matrix(expr)
        if isinstance(expr, sp.MatrixBase):
            raise ModelError(f"output '{name}': give one scalar per output "
                             f"(e.g. location(p)[0]), not a {expr.shape[0]}-vector")
        value = self._expr(expr, f"output '{name}'", allow_coordinates=True,
                           allow_derivatives=True)
        _real(value, f"output '{name}'")
        self._claim(name, "output")
        self.outputs[name] = value
        return value

    def __getitem__(self, name: str) -> Body:
        """The body named ``name`` (``m["colisa"]``)."""
        if name not in self.bodies:
            known = ", ".join(self.bodies) or "none yet"
            raise ModelError(f"model '{self.name}' has no body named {name!r} (declared: {known})")
        return self.bodies[name]

    # -- constraints --------------------------------------------------------------
    # Each call returns its Constraint, numbered in declaration order; ``name=`` labels it
    # (the label names its rows in printed equations, generated code and errors).
    # docs/constraints.md shows each kind's equations as `mechgen equations` prints them.
    def _add(self, cls, args, name):
        from .geometry import Line, Point
        if isinstance(name, (Body, Point, Line)):
            raise ModelError(f"{cls.kind}: too many arguments ({name!r} is one too many)")
        if name is not None:
            label_name(name, cls.kind)
        con = cls(self, len(self.constraints) + 1, name, "", _where())
        try:
            con.args_text = con.build(*args)
        except TypeError as exc:
            raise ModelError(f"{cls.kind}: wrong arguments ({exc})") from None
        coords = set(self.coords)
        for expr, comp in zip(con.exprs, con.components):
            row = f"its {comp} equation" if comp else "its equation"
            _real(expr, f"constraint {con.number} {con.label}: {row}",
                  ": write a vector loop as m.loop(z), which takes its real and imaginary "
                  "parts, or each part as a constraint")
            if not sp.sympify(expr).free_symbols & coords:
                raise ModelError(f"constraint {con.number} {con.label}: {row} reads "
                                 f"{expr} = 0 and involves no coordinate: it constrains "
                                 "nothing or cannot hold")
        _joins_two_bodies(con, args)
        con.points = _points_of(args)
        con.placed = [a for a in con.points if any(a is b for b in args)]
        self.constraints.append(con)
        self._equations = None
        return con

    def revolute(self, p1, p2, name=None):
        """A pin joint: points ``p1`` and ``p2`` (of two bodies) coincide. Two equations,
        r(p1) − r(p2) = 0 (x and y rows). ``name=`` labels the constraint."""
        return self._add(Revolute, (p1, p2), name)

    def translate(self, a1, a2, name=None):
        """A sliding joint: axis ``a2`` slides along axis ``a1`` without turning. Two
        equations: u1 × u2 = 0 (parallel) and (a2.first − a1.first) × u2 = 0 (on one line),
        u the axes' directions."""
        return self._add(Translate, (a1, a2), name)

    def point_on_line(self, p, a, name=None):
        """Point ``p`` stays on axis ``a`` (a pin in a slot): (a.first − r(p)) × u = 0,
        one equation; u is the axis' direction, not normalised."""
        return self._add(PointOnLine, (p, a), name)

    def relative_distance(self, p1, p2, d, name=None):
        """Points ``p1`` and ``p2`` stay ``d`` apart (a rod with pins at both ends):
        ‖r(p1) − r(p2)‖² − d² = 0, one equation. ``d``: a number, parameter or expression
        of parameters and T."""
        return self._add(RelativeDistance, (p1, p2, d), name)

    def rotation_lock(self, b1, b2, angle=None, name=None):
        """Body ``b1`` turned by ``angle`` relative to body ``b2``: Th_b1 − Th_b2 − angle = 0
        (the ground's angle is 0). ``rotation_lock(b, angle)`` fixes b's own angle. With
        T in ``angle`` it is a driver (a crank turning at a given speed)."""
        return self._add(RotationLock, (b1, b2, angle), name)

    def relative_x(self, p1, p2, dx=None, name=None):
        """``relative_x(p, x)``: point p's global x is ``x`` (x(p) − x = 0).
        ``relative_x(p1, p2, dx)``: p2 lies ``dx`` to the right of p1 (x(p2) − x(p1) − dx = 0).
        With T in the value it is a driver (a slider pushed along x)."""
        return self._add(RelativeX, (p1, p2, dx), name)

    def relative_y(self, p1, p2, dy=None, name=None):
        """``relative_y(p, y)``: point p's global y is ``y``; ``relative_y(p1, p2, dy)``:
        p2 lies ``dy`` above p1. As relative_x, in y."""
        return self._add(RelativeY, (p1, p2, dy), name)

    def parallel(self, a1, a2, name=None):
        """Axes ``a1`` and ``a2`` stay parallel (or antiparallel): u1 × u2 = 0."""
        return self._add(Parallel, (a1, a2), name)

    def orthogonal(self, a1, a2, name=None):
        """Axes ``a1`` and ``a2`` stay at a right angle: u1 · u2 = 0."""
        return self._add(Orthogonal, (a1, a2), name)

    def relative_angle(self, a1, a2, angle, name=None):
        """The angle from axis ``a1`` to axis ``a2`` (counter-clockwise, radians) is
        ``angle``. Between axes fixed in bodies this is the linear equation
        (Th_b2 + α2) − (Th_b1 + α1) − angle = 0, α an axis' angle in its body; otherwise
        (u1 × u2) cos(angle) − (u1 · u2) sin(angle) = 0."""
        return self._add(RelativeAngle, (a1, a2, angle), name)

    def constraint(self, expr, name=None):
        """Any equation: ``expr`` = 0 (or a sympy ``Eq(lhs, rhs)``), an expression in the
        coordinates (``body.x``, ``body.th``, ``m.coordinate`` symbols), parameters and T."""
        return self._add(Expression, (expr,), name)

    # -- queries ------------------------------------------------------------------
    @property
    def moving_bodies(self):
        """The moving bodies, in declaration order (numbers 2, 3, ...)."""
        return [b for b in self.bodies.values() if not b.is_ground]

    @property
    def param_symbols(self):
        """The parameters' sympy Symbols, in declaration order."""
        return [sym for sym, _ in self.params.values()]

    @property
    def param_defaults(self):
        """{parameter name: default value}, in declaration order."""
        return {name: value for name, (_, value) in self.params.items()}

    @property
    def drivers(self):
        """The constraints whose equations hold T (they drive the motion)."""
        return [c for c in self.constraints if c.is_driver]

    def guess_vector(self):
        """The initial guess as floats, in coordinate order (parameters at their defaults)."""
        subs = {sym: value for sym, value in self.params.values()}
        return [float(sp.sympify(self.guess[c]).subs(subs)) for c in self.coords]

    def equations(self):
        """The expanded system: q, qd, qdd, phi, phi_q, phi_t, nu, gamma (sympy Matrices)."""
        from .symbolic import expand
        if self._equations is None:
            self._equations = expand(self)
        return self._equations

    def _repr_latex_(self):
        """The labelled equations for Jupyter: report.equations_text(latex=True), whose
        comment lines become headings, each a display of its own beside the align* blocks."""
        from .printing import equations_text
        out = []
        for line in equations_text(self, latex=True).splitlines():
            if line.startswith("% "):
                text = "".join("\\" + c if c in "_&#%{}$" else "\\^{}" if c == "^" else c
                               for c in line[2:])
                line = f"$$\\textbf{{{text}}}$$"
            out.append(line)
        return "\n".join(out) + "\n"

    # -- validation helpers ---------------------------------------------------------
    def _expr(self, value, what, allow_coordinates=False, allow_derivatives=False):
        try:
            expr = sp.sympify(value)
        except (sp.SympifyError, TypeError):
            raise ModelError(f"{what}: cannot read {value!r} as a number or expression") from None
        if isinstance(expr, sp.MatrixBase) or not isinstance(expr, sp.Expr):
            raise ModelError(f"{what}: expected a scalar expression, got {value!r}")
        allowed = set(self.param_symbols) | {T}
        if allow_coordinates:
            allowed |= set(self.coords)
        if allow_derivatives:
            from .symbolic import derivative_symbols
            d1, d2 = derivative_symbols(self.coords)
            allowed |= set(d1) | set(d2)
        unknown = sorted((s for s in expr.free_symbols if s not in allowed), key=str)
        if unknown:
            names = ", ".join(map(str, unknown))
            raise ModelError(f"{what}: {names} {'is' if len(unknown) == 1 else 'are'} not a "
                             f"declared parameter{', coordinate' if allow_coordinates else ''} "
                             f"or T of model '{self.name}'{self._namesake(unknown)}")
        if expr.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
            raise ModelError(f"{what}: {expr} is not finite")
        from sympy.core.function import AppliedUndef
        undefined = sorted(map(str, expr.atoms(AppliedUndef)))
        if undefined:       # sympy.Function("f")(T): nothing to evaluate it with
            raise ModelError(f"{what}: {', '.join(undefined)} is an undefined function (a "
                             "sympy.Function without a formula): write it as an expression "
                             "of T, the parameters and the coordinates")
        return expr

    def _check_local(self, body):
        allowed = set(self.param_symbols)
        for k, (x, y) in enumerate(body.points, start=1):
            for v in (x, y):
                bad = [s for s in v.free_symbols if s not in allowed]
                if bad:
                    raise ModelError(f"point {k} of body '{body.name}': "
                                     f"{', '.join(sorted(map(str, bad)))} is not a declared "
                                     "parameter (points may hold parameters only)"
                                     f"{self._namesake(bad)}")
                if v.has(sp.zoo, sp.oo, sp.nan):
                    raise ModelError(f"point {k} of body '{body.name}' is not finite")
                _real(v, f"point {k} of body '{body.name}'")

    def _namesake(self, unknown) -> str:
        """Why a symbol named like a declared one is not it: text, or a Symbol of its own
        (sympy tells symbols by name and assumptions; the model's are real)."""
        same = [s for s in unknown if getattr(s, "name", None) in self._names or
                getattr(s, "name", None) == "T"]
        if not same:
            return ""
        said = ", ".join(f"{s.name} ({self._names.get(s.name, 'time')})" for s in same)
        return (f"; {said}: a symbol named like the model's but not it (a string, or a "
                "sympy.Symbol made apart): use the symbol that m.param or m.coordinate "
                "returned, body.x/.y/.th, or mechgen.T")

    def _guess_value(self, value, what):
        expr = self._expr(value, what)
        _real(expr, what)
        if T in expr.free_symbols:
            raise ModelError(f"{what} may not depend on T")
        return expr


def _real(expr, what, hint=""):
    """A ModelError where ``expr`` holds the imaginary unit: the module computes in real
    numbers (a complex vector loop goes through m.loop, which takes its two parts)."""
    if isinstance(expr, sp.Basic) and expr.has(sp.I):
        raise ModelError(f"{what}: {expr} is complex (it holds I); the module computes in "
                         f"real numbers{hint}")


# the joints that relate two bodies: with every point and axis fixed in one body their
# equations are constants of the coordinates (0 = 0, or an equation that cannot hold);
# relative_x/relative_y between two points of one body are not among them (they set the
# body's angle), nor are rotation_lock and constraint (checked by their equations)
_TWO_BODY_KINDS = frozenset({"revolute", "translate", "point_on_line", "relative_distance",
                             "parallel", "orthogonal", "relative_angle"})


def _joins_two_bodies(con, args):
    """A ModelError where a joint names points and axes of one body only."""
    if con.kind not in _TWO_BODY_KINDS:
        return
    bodies = {p.body for p in _points_of(args)}
    if len(bodies) == 1:
        body = bodies.pop()
        raise ModelError(f"constraint {con.number} {con.label}: every point and axis it names "
                         f"is fixed in body '{body.name}', so its equations do not depend on "
                         "the coordinates (they hold always or never): a joint "
                         f"({con.kind}) relates two bodies; name a point or axis of the other")


def _points_of(args):
    """The points a constraint's arguments name (for drawing and the points routine)."""
    from .geometry import Line, Point
    out = []
    for a in args:
        if isinstance(a, Point):
            out.append(a)
        elif isinstance(a, Line):
            out.append(a.first)
            if a.second is not None:
                out.append(a.second)
    return out


def _points(points, name):
    if isinstance(points, (str, bytes)) or not hasattr(points, "__iter__"):
        raise ModelError(f"body '{name}': points must be a list of (x, y) pairs, got {points!r}")
    return list(points)


def _number(value, what) -> float:
    if isinstance(value, bool):
        raise ModelError(f"{what} must be a number, got {value!r}")
    try:
        if isinstance(value, numbers.Real):
            x = float(value)
        else:
            x = float(sp.sympify(value))
    except (TypeError, ValueError, sp.SympifyError):
        raise ModelError(f"{what} must be a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ModelError(f"{what} must be finite, got {value!r}")
    return x


def _where():
    frame = user_frame()
    if frame is None or not frame.filename or frame.filename.startswith("<"):
        return None
    return f"{frame.filename}:{frame.lineno}"


