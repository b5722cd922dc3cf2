"""Bodies, points and axes: the nouns of a model. Pure sympy, no numbers solved here."""
from __future__ import annotations

import numbers
import unicodedata

import sympy as sp

from ..errors import ModelError

T = sp.Symbol("T", real=True)


def as_pair(value, what: str):
    """A 2-vector as a tuple of sympy expressions, or a ModelError naming `what`."""
    if isinstance(value, sp.MatrixBase):
        if value.shape not in ((2, 1), (1, 2)):
            raise ModelError(f"{what} must be a 2-vector, got a matrix of shape {value.shape}")
        value = list(value)
    try:
        x, y = value
    except (TypeError, ValueError):
        raise ModelError(f"{what} must be a pair (x, y), got {value!r}") from None
    try:
        return sp.sympify(x), sp.sympify(y)
    except (sp.SympifyError, TypeError):
        raise ModelError(f"{what} must hold numbers or expressions, got {value!r}") from None


def label_name(name, what: str) -> str:
    """A ``name=`` label (a constraint's, a load's, a stage's), checked: a non-empty string
    of one line. The label is written into the generated module's comments and tables,
    into error messages and CSV headers, where a line break, a NUL or another control
    character would break them."""
    if not isinstance(name, str) or not name.strip():
        raise ModelError(f"{what}: name= must be a non-empty string, got {name!r}")
    bad = [c for c in name if unicodedata.category(c) in ("Cc", "Zl", "Zp")]
    if bad:
        raise ModelError(f"{what}: name= {name!r} holds the control character {bad[0]!r}; "
                         "a name is one line of printable text")
    return name


def _describe(value) -> str:
    if isinstance(value, Body):
        return f"body {value.name}"
    if isinstance(value, Line):
        return f"the axis {value!r}"
    text = repr(value)
    return text if len(text) < 60 else text[:57] + "..."


class Body:
    """A rigid body: ground (number 1, fixed) or moving (numbered 2, 3, ...).

    A moving body carries the coordinates ``X<n>, Y<n>, Th<n>`` (``body.x``, ``body.y``,
    ``body.th``: the global position of its local origin and its rotation angle); the
    ground's are 0. Its points are given in its local frame: ``body[k]`` is the k-th
    (counted from 1), ``body[0]`` the origin, ``body.at(x, y)`` any local point.
    """

    def __init__(self, model, name: str, number: int, points, ground: bool):
        self.model = model
        self.name = name
        self.number = number
        self.is_ground = ground
        self.points = tuple(as_pair(p, f"point {k} of body '{name}'")
                            for k, p in enumerate(points, start=1))
        if ground:
            self.x = self.y = self.th = sp.Integer(0)
        else:
            self.x = sp.Symbol(f"X{number}", real=True)
            self.y = sp.Symbol(f"Y{number}", real=True)
            self.th = sp.Symbol(f"Th{number}", real=True)

    def __repr__(self):
        return f"<body {self.name!r} #{self.number}>"

    def __str__(self):
        return self.name

    def __getitem__(self, k) -> "Point":
        """``body[k]``: the k-th point of the body's list, counted from 1 (Mech's P1, P2,
        ...); ``body[0]`` is the origin of the body's local frame (local (0, 0), the point
        whose global position is (X<n>, Y<n>); for the ground, the global origin)."""
        if isinstance(k, bool) or not isinstance(k, (numbers.Integral, sp.Integer)):
            raise ModelError(f"body '{self.name}': a point index must be an integer, got {k!r}")
        k = int(k)
        if k == 0:
            return Point(self, (sp.Integer(0), sp.Integer(0)), f"{self.name}[0]")
        if not 1 <= k <= len(self.points):
            raise ModelError(f"body '{self.name}' has {len(self.points)} points; "
                             f"point {k} does not exist (points count from 1, 0 is the origin)")
        return Point(self, self.points[k - 1], f"{self.name}[{k}]")

    def at(self, x, y) -> "Point":
        """A point at local coordinates (x, y)."""
        local = as_pair((x, y), f"body '{self.name}'.at(...)")
        return Point(self, local, f"{self.name}.at({local[0]}, {local[1]})")

    def line(self, i, j) -> "Line":
        """The axis from point i to point j of this body."""
        return Line(self[i], self[j])

    def vector(self, k) -> "Line":
        """Mech's Vector[body, k]: the axis from the body origin to its point k."""
        return Line(self[0], self[k])

    @property
    def coordinates(self):
        """(X<n>, Y<n>, Th<n>), or () for the ground."""
        return () if self.is_ground else (self.x, self.y, self.th)

    def rotation(self):
        """The 2×2 rotation matrix of the body's angle (Mech's RotationMatrix)."""
        return sp.Matrix([[sp.cos(self.th), -sp.sin(self.th)],
                          [sp.sin(self.th), sp.cos(self.th)]])

    def to_global(self, local) -> sp.Matrix:
        """The global position (2×1) of the point at local coordinates ``local``."""
        sx, sy = local
        if self.is_ground:
            return sp.Matrix([sx, sy])
        c, s = sp.cos(self.th), sp.sin(self.th)
        return sp.Matrix([self.x + c * sx - s * sy, self.y + s * sx + c * sy])

    def rotate(self, local) -> sp.Matrix:
        """A local direction expressed globally."""
        sx, sy = local
        if self.is_ground:
            return sp.Matrix([sx, sy])
        c, s = sp.cos(self.th), sp.sin(self.th)
        return sp.Matrix([c * sx - s * sy, s * sx + c * sy])


class Point:
    """A point fixed in a body, at local coordinates ``local``; ``label`` is how it is
    written (``colisa[2]``, ``coupler.at(1.2, 0.8)``) in labels and errors."""

    def __init__(self, body: Body, local, label: str):
        self.body = body
        self.local = local
        self.label = label

    def __repr__(self):
        return self.label

    @property
    def r(self) -> sp.Matrix:
        """Global position (2×1 sympy Matrix)."""
        return self.body.to_global(self.local)


class Line:
    """An axis: from one point to another, or through a point with a fixed direction.

    ``Line(p1, p2)`` runs from p1 to p2 (points of any bodies: it turns and stretches as
    they move); ``Line(p, direction=(dx, dy))`` passes through p with a direction fixed in
    p's body. Its direction u is not normalised. ``body.line(i, j)`` is
    ``Line(body[i], body[j])``.

    Parameters
    ----------
    p1 : Point
        The axis' first point (``body[1]``, ``body.at(x, y)``).
    p2 : Point, optional
        Its second point; give this or ``direction``, not both.
    direction : (dx, dy), optional
        A direction in p1's body's local frame.
    """

    def __init__(self, p1, p2=None, *, direction=None):
        if not isinstance(p1, Point):
            raise ModelError("Line: the first argument must be a point such as body[1], "
                             f"got {_describe(p1)}")
        if (p2 is None) == (direction is None):
            raise ModelError("Line takes a second point or direction=(dx, dy), exactly one of them")
        if p2 is not None and not isinstance(p2, Point):
            raise ModelError(f"Line: the second argument must be a point, got {_describe(p2)}")
        self.first = p1
        self.second = p2
        self.local_direction = None if direction is None else as_pair(direction, "Line direction")
        if p2 is not None and p2.body.model is not p1.body.model:
            raise ModelError(f"Line({p1}, {p2}): the points belong to different models")
        d = self.local_difference()
        if d is not None and all(sp.sympify(v).is_zero for v in d):
            raise ModelError(f"axis {self!r} has no direction: its two points coincide "
                             "(or its direction is (0, 0))")

    @property
    def model(self):
        """The model the axis' points belong to."""
        return self.first.body.model

    def __repr__(self):
        if self.second is not None:
            b1, b2 = self.first.body, self.second.body
            if b1 is b2:
                i, j = self.first.label[len(b1.name):], self.second.label[len(b2.name):]
                if i.startswith("[") and j.startswith("["):
                    return f"{b1.name}.line({i[1:-1]}, {j[1:-1]})"
            return f"Line({self.first}, {self.second})"
        d = self.local_direction
        return f"Line({self.first}, direction=({d[0]}, {d[1]}))"

    @property
    def u(self) -> sp.Matrix:
        """The direction vector in global coordinates."""
        if self.second is None:
            return self.first.body.rotate(self.local_direction)
        b1, b2 = self.first.body, self.second.body
        if b1 is b2:  # rotate the local difference: shorter expressions, same value
            d = (self.second.local[0] - self.first.local[0],
                 self.second.local[1] - self.first.local[1])
            return b1.rotate(d)
        return self.second.r - self.first.r

    def local_difference(self):
        """The direction in the frame of the one body it is fixed in, or None when the
        axis joins points of two bodies."""
        if self.second is None:
            return self.local_direction
        if self.first.body is self.second.body:
            return (self.second.local[0] - self.first.local[0],
                    self.second.local[1] - self.first.local[1])
        return None

    @property
    def length(self):
        """‖u‖. For an axis fixed in one body this is the constant local length (9, not
        sqrt(81 sin² + 81 cos²)), as Mech prints it."""
        d = self.local_difference()
        if d is None:
            u = self.u
            return sp.sqrt(u[0] ** 2 + u[1] ** 2)
        return sp.sqrt(d[0] ** 2 + d[1] ** 2)

    def body_fixed_angle(self):
        """(body, local angle) when the direction is fixed in one body, else None."""
        if self.second is None:
            d = self.local_direction
            return self.first.body, sp.atan2(d[1], d[0])
        if self.first.body is self.second.body:
            d = (self.second.local[0] - self.first.local[0],
                 self.second.local[1] - self.first.local[1])
            return self.first.body, sp.atan2(d[1], d[0])
        return None
