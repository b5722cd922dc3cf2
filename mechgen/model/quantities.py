"""Mech's output functions as symbolic quantities (sympy expressions in q, q̇, q̈).

Vectors come back as 2×1 sympy Matrices; scalars as sympy expressions. An "axis" is a
``Line``; where Mech accepts a vector, a pair (x, y) or a 2-vector Matrix works too.
"""
from __future__ import annotations

import numbers
import weakref

import sympy as sp

from .constraints import cross2, dot2
from ..errors import ModelError
from .geometry import Body, Line, Point, as_pair
from .symbolic import total_derivative

# Coordinate symbols of every model built in this process, and the models themselves
# (for dt without a model).
_COORDINATES: dict[str, sp.Symbol] = {}
_MODELS = weakref.WeakSet()


def register_coordinates(coords):
    for c in coords:
        _COORDINATES[c.name] = c


def register_model(model):
    _MODELS.add(model)


def _coordinates_of(names):
    """The coordinates of dt(expr) without a model, for an expression holding ``names``.
    A symbol is one name whichever model declared it, so one model's parameter L is the
    very symbol of another model's coordinate L: the coordinates are those of the models
    that declare every name of the expression (as coordinates or parameters before as
    rates), and must agree there; where no model declares them all, every coordinate of
    the process named in the expression."""
    names = set(names) - {"T"}
    rated = {n[:-1] for n in names if n.endswith("d")} | \
        {n[:-2] for n in names if n.endswith("dd")}
    direct, through_rates = [], []
    for mdl in list(_MODELS):
        coords = {c.name for c in mdl.coords}
        own = coords | set(mdl.params)
        if names <= own:
            direct.append(mdl)
        elif names <= own | {c + "d" for c in coords} | {c + "dd" for c in coords}:
            through_rates.append(mdl)
    for group in (direct, through_rates):
        if not group:
            continue
        picks = {}
        for mdl in group:
            key = tuple(c.name for c in mdl.coords if c.name in names | rated)
            picks.setdefault(key, []).append(mdl.name)
        if len(picks) > 1:
            said = "; ".join(f"{', '.join(k) or 'none'} in model {', '.join(map(repr, v))}"
                             for k, v in picks.items())
            raise ModelError(f"dt: which of {', '.join(sorted(names))} are coordinates "
                             f"depends on the model (coordinates: {said}); say which "
                             "model: dt(expr, model=m)")
        (key,) = picks
        mdl = next(m for m in group if m.name in picks[key])
        return [c for c in mdl.coords if c.name in key]
    return [c for name, c in _COORDINATES.items()
            if name in names or name + "d" in names or name + "dd" in names]


def _vec(value, what) -> sp.Matrix:
    if isinstance(value, Line):
        return value.u
    if isinstance(value, Point):
        return value.r
    return sp.Matrix(as_pair(value, what))


def _pt(value, what) -> sp.Matrix:
    if isinstance(value, Point):
        return value.r
    if isinstance(value, Line):
        raise ModelError(f"{what}: expected a point, got the axis {value}")
    return sp.Matrix(as_pair(value, what))


def _axis(value, what) -> Line:
    if not isinstance(value, Line):
        raise ModelError(f"{what}: expected an axis (body.line(i, j) or Line(...)), got {value!r}")
    return value


def location(p, local=None) -> sp.Matrix:
    """Global position of a point (Mech's Location).

    Parameters
    ----------
    p : Point or Body
        The point (``body[2]``, ``body.at(3, 8)``), or a body whose point ``local`` names.
    local : int or (x, y), optional
        With a body: its k-th point, or a point at local coordinates (``location(body,
        (3, 8))``); without, the body's origin ``body[0]``.

    Returns
    -------
    sympy.Matrix
        (x, y), expressions in the coordinates.
    """
    return _point_of(p, local, "location").r


def _point_of(p, local, what) -> Point:
    """A Point from ``p`` or ``(body, k)`` or ``(body, (x, y))``; a bare (x, y) stays a pair."""
    if isinstance(p, Body):
        if local is None:
            return p[0]
        if isinstance(local, (numbers.Integral, sp.Integer)) and not isinstance(local, bool):
            return p[int(local)]
        return p.at(*as_pair(local, f"{what}: local point"))
    if local is not None:
        raise ModelError(f"{what}(p) takes a point, or a body and a point index or (x, y)")
    if isinstance(p, Point):
        return p
    return _GlobalPoint(_pt(p, what))


class _GlobalPoint:
    """A fixed global point given as a pair (no body)."""

    def __init__(self, r):
        self.r = r


def distance(p1, p2):
    """Distance between two points (Mech's Distance).

    Between two points of one body it is the constant local distance (Mech prints 3 for
    the crank's two points, not a square root of sines).

    Parameters
    ----------
    p1, p2 : Point or (x, y)
        Points of any bodies, or global points given as pairs.

    Returns
    -------
    sympy.Expr
        The distance, an expression in the coordinates.
    """
    if isinstance(p1, Point) and isinstance(p2, Point) and p1.body is p2.body:
        dx, dy = p2.local[0] - p1.local[0], p2.local[1] - p1.local[1]
        return sp.sqrt(dx ** 2 + dy ** 2)
    d = _pt(p1, "distance") - _pt(p2, "distance")
    return sp.sqrt(d[0] ** 2 + d[1] ** 2)


def point_to_line_distance(p, a):
    """Signed distance of a point from an axis (Mech's PointToLineDistance).

    (a.first − r(p)) × u / ‖u‖ as Mech prints it: positive when p lies to the left of the
    axis (seen looking along u).

    Parameters
    ----------
    p : Point or (x, y)
        The point.
    a : Line
        The axis (``body.line(1, 2)``, ``Line(p1, p2)``).

    Returns
    -------
    sympy.Expr
        The signed distance.
    """
    a = _axis(a, "point_to_line_distance")
    return cross2(a.first.r - _pt(p, "point_to_line_distance"), a.u) / a.length


def angle(a):
    """Direction angle of an axis or vector against the global X axis (Mech's Angle).

    Parameters
    ----------
    a : Line or (dx, dy)
        An axis, or a vector.

    Returns
    -------
    sympy.Expr
        ``atan2(u_y, u_x)`` in radians.
    """
    u = _vec(a, "angle")
    return sp.atan2(u[1], u[0])


def rotation(body):
    """A body's rotation angle (Mech's Rotation): its coordinate ``Th<n>``.

    Parameters
    ----------
    body : Body
        A body of the model (the ground's is 0).

    Returns
    -------
    sympy.Symbol or 0
        The body's angle coordinate.
    """
    if not isinstance(body, Body):
        raise ModelError(f"rotation: expected a body, got {body!r}")
    return body.th


# Two axes whose sine of the angle between them is below this are parallel for
# intersection(): the point would lie over 1e10 axis lengths away, every digit of it
# made of the round-off in u × v (two axes parallel by symmetry at some instant give
# u × v ~ 1e-17 and a "point" at -4.6e17), so it is NaN, and so are its rates.
PARALLEL_SINE = 1e-10


class unless_parallel(sp.Function):
    """``unless_parallel(c, size)``: c = u × v where c² > PARALLEL_SINE² size (size =
    ‖u‖² ‖v‖²), NaN where the axes are parallel. Its rate is c's (its derivative in c
    is 1): a point divided by it, and that point's velocity and acceleration (dt), are
    NaN where the axes are parallel, and no division by an exact 0.0 raises in the
    generated code (the comparison is computed, never a quotient)."""

    is_real = True

    def fdiff(self, argindex=1):
        if argindex == 1:
            return sp.S.One
        if argindex == 2:
            return sp.S.Zero
        raise sp.ArgumentIndexError(self, argindex)

    @classmethod
    def eval(cls, c, size):
        if c.is_Number and size.is_Number:
            return c if c ** 2 > PARALLEL_SINE ** 2 * size else sp.nan

    def _code(self, printer, nan, where=None):
        c, size = (printer._print(a) for a in self.args)
        test = f"({c})*({c}) > {PARALLEL_SINE ** 2!r}*({size})"
        return f"{where}({test}, {c}, {nan})" if where else f"(({c}) if {test} else {nan})"

    def _pythoncode(self, printer):         # the generated module (np.nan, as its library)
        return self._code(printer, "np.nan")

    def _numpycode(self, printer):          # lambdify(modules="numpy"): mech.evaluate
        return self._code(printer, "numpy.nan", where="numpy.where")

    def _latex(self, printer):
        return printer._print(self.args[0])


def intersection(a1, a2) -> sp.Matrix:
    """The intersection point of two axes (Mech's IntersectionPoint).

    NaN (as are its time derivatives) while they are parallel (the sine of their angle
    below PARALLEL_SINE); two axes that are always parallel are a ModelError.

    Parameters
    ----------
    a1, a2 : Line
        The two axes.

    Returns
    -------
    sympy.Matrix
        (x, y) of the point.
    """
    a1, a2 = _axis(a1, "intersection"), _axis(a2, "intersection")
    p, u = a1.first.r, a1.u
    r, v = a2.first.r, a2.u
    c = cross2(u, v)
    d1, d2 = a1.local_difference(), a2.local_difference()
    if d1 is not None and d2 is not None and a1.first.body is a2.first.body and \
            sp.expand(d1[0] * d2[1] - d1[1] * d2[0]) == 0 or c == 0:
        raise ModelError(f"intersection: the axes {a1} and {a2} are parallel at every "
                         "configuration: they have no intersection point")
    if c.free_symbols:
        c = unless_parallel(c, dot2(u, u) * dot2(v, v))
    s = cross2(r - p, v) / c
    return p + s * u


def project_on_line(p, a) -> sp.Matrix:
    """Orthogonal projection of a point onto an axis (Mech's ProjectOnLine).

    Parameters
    ----------
    p : Point or (x, y)
        The point.
    a : Line
        The axis.

    Returns
    -------
    sympy.Matrix
        (x, y) of the projection.
    """
    a = _axis(a, "project_on_line")
    base, u = a.first.r, a.u
    s = dot2(_pt(p, "project_on_line") - base, u) / a.length ** 2
    return base + s * u


def direction(a) -> sp.Matrix:
    """An axis's direction vector u, its second point minus its first (Mech's Direction).

    Parameters
    ----------
    a : Line or (dx, dy)
        An axis, or a vector (returned as it is).

    Returns
    -------
    sympy.Matrix
        (u_x, u_y), not normalised.
    """
    return _vec(a, "direction")


def magnitude(a):
    """Length of an axis's direction vector or of a vector (Mech's Magnitude).

    Parameters
    ----------
    a : Line or (dx, dy)
        An axis, or a vector.

    Returns
    -------
    sympy.Expr
        ‖u‖.
    """
    if isinstance(a, Line):
        return a.length
    u = _vec(a, "magnitude")
    return sp.sqrt(u[0] ** 2 + u[1] ** 2)


def unit(a) -> sp.Matrix:
    """The unit vector along an axis or a vector (Mech's Unit).

    Parameters
    ----------
    a : Line or (dx, dy)
        An axis, or a vector.

    Returns
    -------
    sympy.Matrix
        u / ‖u‖.
    """
    return _vec(a, "unit") / magnitude(a)


def cross(a, b):
    """Planar cross product of two axes or vectors, a_x b_y − a_y b_x (Mech's Cross).

    Parameters
    ----------
    a, b : Line or (dx, dy)
        Axes (their direction vectors) or vectors.

    Returns
    -------
    sympy.Expr
        The scalar cross product.
    """
    return cross2(_vec(a, "cross"), _vec(b, "cross"))


def rotation_matrix(body) -> sp.Matrix:
    """A body's rotation matrix (Mech's RotationMatrix): local to global directions.

    Parameters
    ----------
    body : Body
        A body of the model.

    Returns
    -------
    sympy.Matrix
        [[cos Th, −sin Th], [sin Th, cos Th]] of the body's angle.
    """
    if not isinstance(body, Body):
        raise ModelError(f"rotation_matrix: expected a body, got {body!r}")
    return body.rotation()


def point_to_local(body, xy) -> sp.Matrix:
    """Local coordinates, in ``body``'s frame, of a global point (Mech's PointToLocal).

    Parameters
    ----------
    body : Body
        The body whose frame.
    xy : Point or (x, y)
        The point, global.

    Returns
    -------
    sympy.Matrix
        (x, y) in the body's frame.
    """
    if not isinstance(body, Body):
        raise ModelError(f"point_to_local: expected a body first, got {body!r}")
    g = _pt(xy, "point_to_local")
    d = g - sp.Matrix([body.x, body.y])
    return body.rotation().T * d


def polar_to_xy(r, ang=None) -> sp.Matrix:
    """Cartesian components of a polar pair (Mech's PolarToXY).

    Parameters
    ----------
    r : expression or (r, angle)
        The radius, or the pair.
    ang : expression, optional
        The angle in radians, when ``r`` is the radius alone.

    Returns
    -------
    sympy.Matrix
        (r cos angle, r sin angle).
    """
    if ang is None:
        r, ang = as_pair(r, "polar_to_xy")
    r, ang = sp.sympify(r), sp.sympify(ang)
    return sp.Matrix([r * sp.cos(ang), r * sp.sin(ang)])


def xy_to_polar(x, y=None) -> sp.Matrix:
    """Polar pair of Cartesian components (Mech's XYToPolar).

    Parameters
    ----------
    x : expression, (x, y) or Line
        The x component, or a vector or axis.
    y : expression, optional
        The y component, when ``x`` is the x component alone.

    Returns
    -------
    sympy.Matrix
        (sqrt(x² + y²), atan2(y, x)).
    """
    if y is None:
        x, y = as_pair(_vec(x, "xy_to_polar"), "xy_to_polar")
    x, y = sp.sympify(x), sp.sympify(y)
    return sp.Matrix([sp.sqrt(x ** 2 + y ** 2), sp.atan2(y, x)])


def dt(expr, order: int = 1, model=None):
    """Total time derivative (Mech's Dt[expr, T]) through q, q̇ and T.

    Parameters
    ----------
    expr : sympy expression, Matrix or list
        Any quantity in the coordinates, their rates, parameters and ``T``.
    order : int, default 1
        How many times to differentiate (0 returns ``expr``).
    model : Model, optional
        Whose coordinates; by default those the expression's symbols name.

    Returns
    -------
    sympy.Expr or sympy.Matrix
        The derivative, in the coordinates and their rates (``X4d``, ``Th3dd``).
    """
    if not isinstance(order, int) or order < 0:
        raise ModelError(f"dt: order must be a non-negative integer, got {order!r}")
    if isinstance(expr, (list, tuple)):
        expr = sp.Matrix(expr)
    expr = sp.sympify(expr)
    if model is not None:
        coords = list(model.coords)
    else:
        coords = _coordinates_of({s.name for s in expr.free_symbols})
    return total_derivative(expr, coords, order)


def velocity(p, local=None) -> sp.Matrix:
    """Global velocity of a point (Mech's Velocity).

    Parameters
    ----------
    p : Point or Body
        The point, or a body whose point ``local`` names (as for :func:`location`).
    local : int or (x, y), optional
        With a body: its k-th point or a point at local coordinates.

    Returns
    -------
    sympy.Matrix
        (vx, vy), in the coordinates and their rates.
    """
    point = _point_of(p, local, "velocity")
    return dt(point.r, 1, model=getattr(getattr(point, "body", None), "model", None))


def acceleration(p, local=None) -> sp.Matrix:
    """Global acceleration of a point (Mech's Acceleration).

    Parameters
    ----------
    p : Point or Body
        The point, or a body whose point ``local`` names (as for :func:`location`).
    local : int or (x, y), optional
        With a body: its k-th point or a point at local coordinates.

    Returns
    -------
    sympy.Matrix
        (ax, ay), in the coordinates, their rates and accelerations.
    """
    point = _point_of(p, local, "acceleration")
    return dt(point.r, 2, model=getattr(getattr(point, "body", None), "model", None))


__all__ = ["location", "distance", "point_to_line_distance", "angle", "rotation", "intersection",
           "project_on_line", "direction", "magnitude", "unit", "cross", "rotation_matrix",
           "point_to_local", "polar_to_xy", "xy_to_polar", "velocity", "acceleration", "dt"]
