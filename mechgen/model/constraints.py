"""Constraints: each a small class that checks its arguments and returns labelled equations.

The forms reproduce the equations Mech prints (seed 001): see docs/reference/model.md and
docs/constraints.md.
"""
from __future__ import annotations

import sympy as sp

from ..errors import ModelError
from .geometry import Body, Line, Point, T, as_pair


def cross2(a, b):
    """The planar cross product a × b = a_x b_y − a_y b_x."""
    return a[0] * b[1] - a[1] * b[0]


def dot2(a, b):
    """The dot product a · b of two 2-vectors."""
    return a[0] * b[0] + a[1] * b[1]


class Constraint:
    """Base class: ``kind`` names the call; ``rows()`` gives (expression, label suffix)."""

    kind = "constraint"
    components: tuple = ("",)

    def __init__(self, model, number: int, name: str | None, args_text: str, where: str | None):
        self.model = model
        self.number = number
        self.name = name
        self.args_text = args_text
        self.where = where
        self.exprs: list = []

    def build(self, *args) -> str:
        """Check the arguments, set ``exprs`` (one expression per row, = 0) and return
        the arguments as the label writes them. Each kind defines it."""
        raise NotImplementedError

    @property
    def label(self) -> str:
        """``kind(arguments)``, prefixed by ``name: `` when the constraint has a name."""
        base = f"{self.kind}({self.args_text})"
        return f"{self.name}: {base}" if self.name else base

    def rows(self):
        """[(expr, row label)] with row labels such as ``"1 revolute(base[2], manivela[1]) x"``."""
        out = []
        for expr, comp in zip(self.exprs, self.components):
            text = f"{self.number} {self.label}"
            out.append((expr, f"{text} {comp}".rstrip()))
        return out

    @property
    def is_driver(self) -> bool:
        """True when an equation holds the time T."""
        return any(T in sp.sympify(e).free_symbols for e in self.exprs)

    def __repr__(self):
        return f"<constraint {self.number} {self.label}>"


def checked_point(model, value, kind, pos):
    if not isinstance(value, Point):
        raise ModelError(f"{kind}: argument {pos} must be a point such as body[1], got {shown(value)}")
    _same_model(model, value.body, kind, pos, value)
    return value


def checked_line(model, value, kind, pos):
    if not isinstance(value, Line):
        raise ModelError(f"{kind}: argument {pos} must be an axis such as body.line(1, 2) "
                         f"or Line(p1, p2), got {shown(value)}")
    _same_model(model, value.first.body, kind, pos, value)
    if value.second is not None:
        _same_model(model, value.second.body, kind, pos, value)
    return value


def checked_body(model, value, kind, pos):
    if not isinstance(value, Body):
        raise ModelError(f"{kind}: argument {pos} must be a body, got {shown(value)}")
    _same_model(model, value, kind, pos, value)
    return value


def _same_model(model, body, kind, pos, value):
    if body.model is not model:
        other = body.model
        place = getattr(other, "_where", None)
        if other.name == model.name and place:
            owner = f"another model also named '{other.name}' (declared at {place})"
        else:
            owner = f"model '{other.name}'"
        raise ModelError(f"{kind}: argument {pos} ({shown(value)}) belongs to {owner}, "
                         f"not to model '{model.name}'; use the bodies of this model")


def shown(value):
    if isinstance(value, (Body, Point, Line)):
        return f"{type(value).__name__.lower()} {value}"
    text = repr(value)
    return text if len(text) < 60 else text[:57] + "..."


class Revolute(Constraint):
    """``revolute(p1, p2)``: r(p1) − r(p2) = 0, rows x and y."""

    kind = "revolute"
    components = ("x", "y")

    def build(self, p1, p2):
        p1 = checked_point(self.model, p1, self.kind, 1)
        p2 = checked_point(self.model, p2, self.kind, 2)
        self.points = (p1, p2)          # mechgen check names a loop's lengths from them
        d = p1.r - p2.r
        self.exprs = [d[0], d[1]]
        return f"{p1}, {p2}"


class Translate(Constraint):
    """``translate(a1, a2)``: u1 × u2 = 0 (parallel), (a2.first − a1.first) × u2 = 0 (offset)."""

    kind = "translate"
    components = ("parallel", "offset")

    def build(self, a1, a2):
        a1 = checked_line(self.model, a1, self.kind, 1)
        a2 = checked_line(self.model, a2, self.kind, 2)
        u1, u2 = a1.u, a2.u
        self.exprs = [cross2(u1, u2), cross2(a2.first.r - a1.first.r, u2)]
        return f"{a1}, {a2}"


class PointOnLine(Constraint):
    """``point_on_line(p, a)``: (a.first − r(p)) × u = 0."""

    kind = "point_on_line"

    def build(self, p, a):
        p = checked_point(self.model, p, self.kind, 1)
        a = checked_line(self.model, a, self.kind, 2)
        self.exprs = [cross2(a.first.r - p.r, a.u)]
        return f"{p}, {a}"


class RelativeDistance(Constraint):
    """``relative_distance(p1, p2, d)``: ‖r(p1) − r(p2)‖² − d² = 0."""

    kind = "relative_distance"

    def build(self, p1, p2, d):
        p1 = checked_point(self.model, p1, self.kind, 1)
        p2 = checked_point(self.model, p2, self.kind, 2)
        d = self.model._expr(d, f"{self.kind}: the distance")
        r = p1.r - p2.r
        self.squared = r[0] ** 2 + r[1] ** 2     # ‖r(p1) − r(p2)‖²: a driver's factor reads it
        self.exprs = [self.squared - d ** 2]
        return f"{p1}, {p2}, {d}"


class RotationLock(Constraint):
    """``rotation_lock(b1, b2, angle)``: Th_b1 − Th_b2 − angle = 0; ``(b, angle)``: Th_b − angle."""

    kind = "rotation_lock"

    def build(self, b1, b2, angle=None):
        if angle is None:  # rotation_lock(b, angle)
            b1 = checked_body(self.model, b1, self.kind, 1)
            angle = self.model._expr(b2, f"{self.kind}: the angle")
            self.exprs = [b1.th - angle]
            return f"{b1}, {angle}"
        b1 = checked_body(self.model, b1, self.kind, 1)
        b2 = checked_body(self.model, b2, self.kind, 2)
        angle = self.model._expr(angle, f"{self.kind}: the angle")
        self.exprs = [b1.th - b2.th - angle]
        return f"{b1}, {b2}, {angle}"


class _RelativeAxis(Constraint):
    """relative_x / relative_y: ``axis`` 0 or 1."""

    axis = 0

    def build(self, p1, p2, value=None):
        if value is None:  # relative_x(p, x)
            p1 = checked_point(self.model, p1, self.kind, 1)
            value = self.model._expr(p2, f"{self.kind}: the value")
            self.exprs = [p1.r[self.axis] - value]
            return f"{p1}, {value}"
        p1 = checked_point(self.model, p1, self.kind, 1)
        p2 = checked_point(self.model, p2, self.kind, 2)
        value = self.model._expr(value, f"{self.kind}: the offset")
        self.exprs = [p2.r[self.axis] - p1.r[self.axis] - value]
        return f"{p1}, {p2}, {value}"


class RelativeX(_RelativeAxis):
    """``relative_x(p, x)``: x(p) − x = 0; ``(p1, p2, dx)``: x(p2) − x(p1) − dx = 0."""

    kind = "relative_x"
    axis = 0


class RelativeY(_RelativeAxis):
    """``relative_y(p, y)``: y(p) − y = 0; ``(p1, p2, dy)``: y(p2) − y(p1) − dy = 0."""

    kind = "relative_y"
    axis = 1


class Parallel(Constraint):
    """``parallel(a1, a2)``: u1 × u2 = 0."""

    kind = "parallel"

    def build(self, a1, a2):
        a1 = checked_line(self.model, a1, self.kind, 1)
        a2 = checked_line(self.model, a2, self.kind, 2)
        self.exprs = [cross2(a1.u, a2.u)]
        return f"{a1}, {a2}"


class Orthogonal(Constraint):
    """``orthogonal(a1, a2)``: u1 · u2 = 0."""

    kind = "orthogonal"

    def build(self, a1, a2):
        a1 = checked_line(self.model, a1, self.kind, 1)
        a2 = checked_line(self.model, a2, self.kind, 2)
        self.exprs = [dot2(a1.u, a2.u)]
        return f"{a1}, {a2}"


class RelativeAngle(Constraint):
    """Angle from a1 to a2 held at ``angle``. Between body-fixed axes this is the linear
    form Th2 + α2 − Th1 − α1 − angle (one solution); otherwise θ − angle wrapped to
    (−π, π], θ the angle from u1 to u2: atan2(|u1||u2| sin(θ − angle), |u1||u2| cos(θ −
    angle)), whose sine and cosine are (u1 × u2) cos(angle) − (u1 · u2) sin(angle) and
    (u1 · u2) cos(angle) + (u1 × u2) sin(angle). Its one root is θ = angle: a row
    |u1||u2| sin(θ − angle) alone also vanishes at angle + π, where a guess nearer that
    would have been held."""

    kind = "relative_angle"

    def build(self, a1, a2, angle):
        a1 = checked_line(self.model, a1, self.kind, 1)
        a2 = checked_line(self.model, a2, self.kind, 2)
        angle = self.model._expr(angle, f"{self.kind}: the angle")
        f1, f2 = a1.body_fixed_angle(), a2.body_fixed_angle()
        if f1 is not None and f2 is not None:
            (b1, al1), (b2, al2) = f1, f2
            self.exprs = [(b2.th + al2) - (b1.th + al1) - angle]
        else:
            u1, u2 = a1.u, a2.u
            cross, dot = cross2(u1, u2), dot2(u1, u2)
            c, s = sp.cos(angle), sp.sin(angle)
            self.exprs = [sp.atan2(cross * c - dot * s, dot * c + cross * s)]
        return f"{a1}, {a2}, {angle}"


class Expression(Constraint):
    """``constraint(expr)``: expr = 0 (an ``Eq(lhs, rhs)`` reads lhs − rhs = 0)."""

    kind = "constraint"

    def build(self, expr):
        if isinstance(expr, (sp.Equality,)):
            expr = expr.lhs - expr.rhs
        expr = self.model._expr(expr, "constraint(expr)", allow_coordinates=True)
        if not expr.free_symbols & set(self.model.coords):
            raise ModelError(f"constraint({expr}): the expression holds no coordinate of "
                             f"model '{self.model.name}'")
        self.exprs = [expr]
        return f"{expr}"


KINDS = {c.kind: c for c in (Revolute, Translate, PointOnLine, RelativeDistance, RotationLock,
                             RelativeX, RelativeY, Parallel, Orthogonal, RelativeAngle, Expression)}

__all__ = ["Constraint", "KINDS", "cross2", "dot2", "as_pair"]
