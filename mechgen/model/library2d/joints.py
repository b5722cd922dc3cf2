"""More of Mech's 2D constraints: PointOnLines2, OriginLock2, DirectedDistance1, and the
joints that bring their own coordinate (GenRevolute2, GenTranslate2).

Each is a small Constraint class with labelled rows, as in ``constraints``; the Model
methods that declare them are in ``library2d``. The forms are documented, with their
printed rows, in docs/constraints.md.
"""
from __future__ import annotations

import sympy as sp

from ...errors import ModelError
from ..constraints import Constraint, checked_body, checked_line, checked_point, shown, cross2, dot2
from ..geometry import Body, Line, Point, as_pair


def _direction(model, value, kind, pos):
    """An axis (a Line) or a constant global direction (a pair of numbers, parameters or
    expressions of T): (u, |u|, text)."""
    if isinstance(value, Line):
        a = checked_line(model, value, kind, pos)
        return a.u, a.length, f"{a}"
    if isinstance(value, (Body, Point)):
        raise ModelError(f"{kind}: argument {pos} must be an axis such as body.line(1, 2) or "
                         f"a direction (dx, dy), got {shown(value)}")
    dx, dy = as_pair(value, f"{kind}: the direction")
    dx = model._expr(dx, f"{kind}: the direction's x")
    dy = model._expr(dy, f"{kind}: the direction's y")
    if dx.is_zero and dy.is_zero:
        raise ModelError(f"{kind}: the direction (0, 0) has no direction")
    return sp.Matrix([dx, dy]), sp.sqrt(dx ** 2 + dy ** 2), f"({dx}, {dy})"


def body_fixed(a, kind, pos):
    """(body, local angle) of an axis fixed in one body, or a ModelError naming it."""
    found = a.body_fixed_angle()
    if found is None:
        raise ModelError(f"{kind}: argument {pos} ({a!r}) must be an axis fixed in one body "
                         "(body.line(i, j) or Line(p, direction=...)): its angle is needed")
    return found


class PointOnLines(Constraint):
    """``point_on_lines(p, a1, a2)``: p at the intersection of two axes (Mech's
    PointOnLines2): (a1.first − r(p)) × u1 = 0 and (a2.first − r(p)) × u2 = 0."""

    kind = "point_on_lines"
    components = ("line 1", "line 2")

    def build(self, p, a1, a2):
        p = checked_point(self.model, p, self.kind, 1)
        a1 = checked_line(self.model, a1, self.kind, 2)
        a2 = checked_line(self.model, a2, self.kind, 3)
        self.exprs = [cross2(a1.first.r - p.r, a1.u), cross2(a2.first.r - p.r, a2.u)]
        return f"{p}, {a1}, {a2}"


class OriginLock(Constraint):
    """``origin_lock(b1[, b2][, offset])``: the origin of body b1 held at the origin of
    b2 (the global origin without b2) plus a global offset (Mech's OriginLock2):
    X_b1 − X_b2 − ox = 0, Y_b1 − Y_b2 − oy = 0. The angles stay free."""

    kind = "origin_lock"
    components = ("x", "y")

    def build(self, b1, b2=None, offset=None):
        b1 = checked_body(self.model, b1, self.kind, 1)
        if b2 is not None and not isinstance(b2, Body):      # origin_lock(b, offset)
            if offset is not None:
                raise ModelError(f"{self.kind}: argument 2 must be a body, got {shown(b2)}")
            b2, offset = None, b2
        if b2 is not None:
            b2 = checked_body(self.model, b2, self.kind, 2)
            if b2 is b1:
                raise ModelError(f"{self.kind}: body {b1} locked to itself")
        ox, oy = (0, 0) if offset is None else as_pair(offset, f"{self.kind}: the offset")
        ox = self.model._expr(ox, f"{self.kind}: the offset's x")
        oy = self.model._expr(oy, f"{self.kind}: the offset's y")
        x2, y2 = (0, 0) if b2 is None else (b2.x, b2.y)
        self.exprs = [b1.x - x2 - ox, b1.y - y2 - oy]
        other = b2 if b2 is not None else self.model.ground_body
        # drawn as a pin where the origins meet (nothing with an offset)
        self.drawn = [other[0], b1[0]] if offset is None and other is not None else []
        text = f"{b1}" + ("" if b2 is None else f", {b2}")
        return text + ("" if offset is None else f", ({ox}, {oy})")


class DirectedDistance(Constraint):
    """``directed_distance(p1, p2, direction, d)``: p1 lies d from p2 measured along the
    direction (Mech's DirectedDistance1): (r(p1) − r(p2)) · u / |u| − d = 0. Without p2
    the global origin; without d, d = |u|."""

    kind = "directed_distance"

    def build(self, p1, p2, direction=None, d=None):
        p1 = checked_point(self.model, p1, self.kind, 1)
        if not isinstance(p2, Point):          # directed_distance(p1, direction[, d])
            if d is not None:
                raise ModelError(f"{self.kind}: argument 2 must be a point, got {shown(p2)}")
            p2, direction, d = None, p2, direction
        else:
            p2 = checked_point(self.model, p2, self.kind, 2)
        if direction is None:
            raise ModelError(f"{self.kind}: a direction (an axis or (dx, dy)) is needed")
        u, length, utext = _direction(self.model, direction, self.kind, 3 if p2 else 2)
        dist = length if d is None else self.model._expr(d, f"{self.kind}: the distance")
        r = p1.r if p2 is None else p1.r - p2.r
        self.exprs = [dot2(r, u) / length - dist]
        text = f"{p1}" + ("" if p2 is None else f", {p2}") + f", {utext}"
        return text + ("" if d is None else f", {dist}")


class _WithCoordinate(Constraint):
    """A joint whose relative motion is a coordinate of its own (``coordinate``)."""

    coordinate = None

    def _coord(self, coord):
        if not isinstance(coord, sp.Symbol) or coord not in self.model.coords:
            raise ModelError(f"{self.kind}: the coordinate must be a name or a symbol from "
                             f"m.coordinate(...), got {shown(coord)}")
        if any(coord in b.coordinates for b in self.model.bodies.values()):
            raise ModelError(f"{self.kind}: {coord} is a body's coordinate; give the joint a "
                             "coordinate of its own (a new name)")
        self.coordinate = coord
        return coord

    def _axes(self, a1, a2):
        """The two axes, each fixed in its body, on two bodies: (a1, a2, (b1, α1), (b2, α2))."""
        a1 = checked_line(self.model, a1, self.kind, 1)
        a2 = checked_line(self.model, a2, self.kind, 2)
        f1, f2 = body_fixed(a1, self.kind, 1), body_fixed(a2, self.kind, 2)
        if f1[0] is f2[0]:
            raise ModelError(f"{self.kind}: both axes are fixed in body {f1[0]}; a joint joins "
                             "two bodies")
        return a1, a2, f1, f2


class GenRevolute(_WithCoordinate):
    """``gen_revolute(a1, a2, phi)``: a revolute whose angle is the coordinate phi (Mech's
    GenRevolute2, arguments in the order of relative_angle): the axes' first points
    coincide (rows x, y) and the angle from a1 to a2 is phi:
    (Th_b2 + α2) − (Th_b1 + α1) − phi = 0."""

    kind = "gen_revolute"
    components = ("x", "y", "angle")

    def build(self, a1, a2, coord):
        a1, a2, (b1, al1), (b2, al2) = self._axes(a1, a2)
        phi = self._coord(coord)
        d = a1.first.r - a2.first.r
        self.exprs = [d[0], d[1], (b2.th + al2) - (b1.th + al1) - phi]
        self.drawn = [a1.first, a2.first]          # drawn as a pin
        return f"{a1}, {a2}, {phi}"


class GenTranslate(_WithCoordinate):
    """``gen_translate(a1, a2, s)``: a slider whose travel is the coordinate s (Mech's
    GenTranslate2, in the order of translate): axis a2 slides along a1 without turning
    (rows parallel, offset as translate) and a2's first point lies s from a1's first point
    along a1: (a2.first − a1.first) · u1 / |u1| − s = 0."""

    kind = "gen_translate"
    components = ("parallel", "offset", "travel")

    def build(self, a1, a2, coord):
        a1, a2, _, _ = self._axes(a1, a2)
        s = self._coord(coord)
        u1, u2 = a1.u, a2.u
        d = a2.first.r - a1.first.r
        self.exprs = [cross2(u1, u2), cross2(d, u2), dot2(d, u1) / a1.length - s]
        ends = [a1.first, a1.second, a2.first, a2.second]
        self.drawn = ends if all(e is not None for e in ends) else []   # drawn as translate
        return f"{a1}, {a2}, {s}"


class Loop(Constraint):
    """``loop(z)``: a complex vector loop z = 0 (seed 000's a e^{iθ2} + b e^{iθ3} − ...),
    split into its real and imaginary parts (Maple's evalc(Re(z)), evalc(Im(z))), rows
    "loop k re" and "loop k im", k counting the model's loops."""

    kind = "loop"
    components = ("re", "im")
    index = 1

    def build(self, z):
        if isinstance(z, sp.Equality):
            z = z.lhs - z.rhs
        z = self.model._expr(z, "loop(z)", allow_coordinates=True)
        if not z.free_symbols & set(self.model.coords):
            raise ModelError(f"loop({z}): the expression holds no coordinate of model "
                             f"'{self.model.name}'")
        re, im = sp.expand_complex(z).as_real_imag()
        for part, what in ((re, "real"), (im, "imaginary")):
            if not sp.sympify(part).free_symbols & set(self.model.coords):
                raise ModelError(f"loop({z}): its {what} part {part} holds no coordinate; "
                                 "a loop is a complex equation (write the vectors as "
                                 "r*exp(I*angle)); for one real equation use constraint()")
        self.index = 1 + sum(isinstance(c, Loop) for c in self.model.constraints)
        self.exprs = [re, im]
        return f"{z}"

    @property
    def label(self) -> str:
        """``loop k`` (``name: loop k`` with a name): rows read "loop 1 re", "loop 1 im"."""
        base = f"loop {self.index}"
        return f"{self.name}: {base}" if self.name else base


KINDS_JOINTS = (PointOnLines, OriginLock, DirectedDistance, GenRevolute, GenTranslate, Loop)
