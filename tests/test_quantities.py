"""Mech's output functions as symbolic quantities: each against a hand computation, the
symbolic form seed 001 prints, and the number it prints at a solved configuration.

Configurations come from the seed's own printouts where it prints them (SolveMech[.5],
SolveMech[0.15, Solution->Acceleration], section 2B's SolveMech[.245]) and from the
compiled quick-return (session fixture ``qr``) at the other times the seed uses.
"""
import math

import numpy as np
import pytest
import sympy as sp
from sympy.parsing.mathematica import parse_mathematica

import mechgen
from conftest import example_model
from mechgen import (ModelError, T, acceleration, angle, cross, direction, distance, dt,
                     intersection, location, magnitude, point_to_line_distance, point_to_local,
                     polar_to_xy, project_on_line, rotation, rotation_matrix, unit, velocity,
                     xy_to_polar)
from mechgen.model.geometry import Line


def close(a, b, digits=6):
    """Mech prints six significant digits."""
    a, b = float(a), float(b)
    if b == 0:
        return abs(a) < 1e-9
    return abs(a - b) <= 0.6 * 10 ** (math.floor(math.log10(abs(b))) - digits + 1)


@pytest.fixture(scope="module")
def m():
    return example_model("quick_return")


@pytest.fixture(scope="module")
def bodies(m):
    return m["base"], m["manivela"], m["colisa"], m["deslizadera"]


def syms(m, *names):
    eq = m.equations()
    table = {str(s): s for s in (*eq.q, *eq.qd, *eq.qdd, *eq.params)}
    return [table[n] for n in names]


def mma(text, m):
    eq = m.equations()
    table = {str(s): s for s in (*eq.q, *eq.qd, *eq.qdd, *eq.params)}
    expr = parse_mathematica(text)
    return expr.xreplace({s: table[str(s)] for s in expr.free_symbols})


def printed_values(m, **values):
    """A substitution from the seed's printed numbers (and the seed's parameters)."""
    eq = m.equations()
    table = {str(s): s for s in (*eq.q, *eq.qd, *eq.qdd)}
    sub = {table[k]: v for k, v in values.items() if k in table}   # outputs are no symbols
    sub.update({sym: val for sym, val in m.params.values()})
    sub[T] = values.get("T", 0.0)
    return sub


def solved(m, mech, t, level="position"):
    s = mech.solve(t, level=level)
    values = {k: s[k] for k in s.keys()}
    values["T"] = t
    return printed_values(m, **values)


def ev(expr, sub):
    if isinstance(expr, sp.MatrixBase):
        return [float(sp.sympify(e).xreplace(sub)) for e in expr]
    return float(sp.sympify(expr).xreplace(sub))


def zero(expr):
    if isinstance(expr, sp.MatrixBase):
        return all(sp.simplify(e) == 0 for e in expr)
    return sp.simplify(expr) == 0


# SolveMech[.5] and SolveMech[0.15, Solution->Acceleration] as printed
SOLVE_05 = dict(T=0.5, X2=0., Y2=5., Th2=3.14159, X3=0., Y3=0., Th3=0.54042, X4=-0.181877,
                Y4=10., Th4=0.)
SOLVE_015 = dict(T=0.15, X2=0., Y2=5., Th2=0.942478, X3=0., Y3=0., Th3=-0.233107, X4=6.92194,
                 Y4=10., Th4=0., X2d=0., Y2d=0., Th2d=6.28319, X3d=0., Y3d=0., Th3d=2.27897,
                 X4d=-18.7395, Y4d=0., Th4d=0., X2dd=0., Y2dd=0., Th2dd=0., X3dd=0., Y3dd=0.,
                 Th3dd=1.64018, X4dd=-40.9024, Y4dd=0., Th4dd=0.)


# -- location -------------------------------------------------------------------------
def test_location_by_hand(m, bodies):
    base, manivela, colisa, deslizadera = bodies
    X3, Y3, Th3, X4, Y4, Th4 = syms(m, "X3", "Y3", "Th3", "X4", "Y4", "Th4")
    # r = R + A s: s = (0, 9) in colisa's frame
    hand = sp.Matrix([X3 + sp.cos(Th3) * 0 - sp.sin(Th3) * 9, Y3 + sp.sin(Th3) * 0 + sp.cos(Th3) * 9])
    for form in (location(colisa[2]), location(colisa, 2), location(colisa, (0, 9))):
        assert form.shape == (2, 1)
        assert zero(form - hand)
    assert zero(location(colisa, 0) - sp.Matrix([X3, Y3]))
    assert zero(location(colisa) - sp.Matrix([X3, Y3]))
    assert zero(location(colisa.at(1, 2)) - sp.Matrix([X3 + sp.cos(Th3) - 2 * sp.sin(Th3),
                                                       Y3 + sp.sin(Th3) + 2 * sp.cos(Th3)]))
    assert location(base[4]) == sp.Matrix([12, 10])          # ground points are global
    # a point holding a parameter
    longitud, X2, Y2, Th2 = syms(m, "longitud", "X2", "Y2", "Th2")
    assert zero(location(manivela[2]) - sp.Matrix([X2 + longitud * sp.cos(Th2),
                                                   Y2 + longitud * sp.sin(Th2)]))


def test_location_seed_form_and_numbers(m, bodies, qr):
    colisa = bodies[2]
    printed = sp.Matrix(mma("{X3 - 9 Sin[Th3], Y3 + 9 Cos[Th3]}", m))
    assert location(colisa[2]) == printed                  # Location[Point[colisa, 2]]
    assert location(colisa, 2) == printed                  # Location[colisa, 2]
    for t, expect in ((0.3, (-1.05511, 8.93794)), (0.4, (-3.03987, 8.47108))):
        got = ev(printed, solved(m, qr, t))
        assert all(close(a, b) for a, b in zip(got, expect)), (t, got)


def test_location_errors(bodies):
    colisa = bodies[2]
    with pytest.raises(ModelError, match="has 2 points"):
        location(colisa, 3)
    with pytest.raises(ModelError, match="takes a point"):
        location(colisa[1], 2)


# -- distance -------------------------------------------------------------------------
def test_distance_by_hand_and_seed(m, bodies, qr):
    base, manivela, colisa, deslizadera = bodies
    X2, Y2, X4, Y4, Th4 = syms(m, "X2", "Y2", "X4", "Y4", "Th4")
    d = distance(manivela[1], deslizadera[2])
    hand = sp.sqrt((X4 + 2 * sp.cos(Th4) - X2) ** 2 + (Y4 + 2 * sp.sin(Th4) - Y2) ** 2)
    assert zero(d - hand)
    # printed (extraction turned both squares into "/2"): Sqrt[(…)^2 + (…)^2]
    printed = mma("Sqrt[(-X2 + X4 + 2 Cos[Th4])^2 + (-Y2 + Y4 + 2 Sin[Th4])^2]", m)
    assert zero(d - printed)
    for t, expect in ((0.1, 11.0022), (0.2, 9.38401)):
        assert close(ev(d, solved(m, qr, t)), expect), t
    # two points of one body: the constant, as Mech prints 3 (longitud = 3)
    same_body = distance(manivela[1], manivela[2])
    assert same_body.free_symbols == set(syms(m, "longitud"))
    assert same_body.subs(syms(m, "longitud")[0], 3) == 3
    assert distance((0, 0), (3, 4)) == 5
    assert distance(base[1], (3, 4)) == 5


# -- point_to_line_distance -------------------------------------------------------------
def test_point_to_line_distance_seed_form_sign_and_numbers(m, bodies, qr):
    base, manivela, colisa, deslizadera = bodies
    d = point_to_line_distance(manivela[1], colisa.line(1, 2))
    printed = mma("(9 (-X2 + X3) Cos[Th3] - 9 (Y2 - Y3) Sin[Th3]) / 9", m)
    assert zero(d - printed)
    assert not d.has(sp.sqrt(81 * sp.sin(syms(m, "Th3")[0]) ** 2 + 81 * sp.cos(syms(m, "Th3")[0]) ** 2))
    # signed as Mech: +0.58617 at T = .2, and ~0 (1.1e-16) at T = .25, where the crank
    # pivot lies on the lever's axis
    assert close(ev(d, solved(m, qr, 0.2)), 0.58617)
    assert abs(ev(d, solved(m, qr, 0.25))) < 1e-9
    # between the two crossings (T = .25 and .75, where it is 0 up to roundoff) the pivot
    # lies on the other side of the axis
    assert ev(d, solved(m, qr, 0.5)) < -0.1
    assert abs(ev(d, solved(m, qr, 0.75))) < 1e-9


def test_point_to_line_distance_by_hand():
    m = mechgen.Model("ptl")
    g = m.ground("g", points=[(0, 0), (4, 0), (0, 3)])
    # (first − p) × u / |u|: the point (0, 3) against the x axis -> (0·0 − (−3)·4) / 4;
    # positive to the left of the axis, looking along it
    assert point_to_line_distance(g[3], g.line(1, 2)) == 3
    assert point_to_line_distance(g[3], Line(g[2], g[1])) == -3
    assert point_to_line_distance((1, -2), g.line(1, 2)) == -2
    # a point on the axis
    assert point_to_line_distance((7, 0), g.line(1, 2)) == 0


# -- angle, rotation, direction, magnitude, unit, cross --------------------------------
def test_angle_seed_form_and_number(m, bodies, qr):
    colisa, deslizadera = bodies[2], bodies[3]
    a = angle(Line(colisa[2], deslizadera[1]))     # Angle[Line[colisa, 2, deslizadera, 1]]
    assert a == mma("ArcTan[-X3 + X4 + 9 Sin[Th3], -Y3 + Y4 - 9 Cos[Th3]]", m)
    assert close(math.degrees(ev(a, solved(m, qr, 0.3))), 12.2638)
    assert angle((0, 1)) == sp.pi / 2 and angle((-1, 0)) == sp.pi
    assert angle((1, -1)) == -sp.pi / 4


def test_angles_of_body_vectors_in_the_slider_model():
    """Section 3B at T = .245 (printed solution): Angle[Vector[manivela, 2]] = -35.0245°,
    Angle[Vector[colisa, 2]] = 53.1519°, their difference 88.1764°."""
    s = example_model("quick_return_slider")
    sub = printed_values(s, T=0.245, X2=0., Y2=5., Th2=-0.611293, X3=0., Y3=0.,
                         Th3=-0.643121, X4=9.54111, Y4=10., Th4=0.)
    a2 = math.degrees(ev(angle(s["manivela"].vector(2)), sub))
    a3 = math.degrees(ev(angle(s["colisa"].vector(2)), sub))
    assert close(a2, -35.0245) and close(a3, 53.1519) and close(a3 - a2, 88.1764)


def test_rotation(m, bodies):
    base, colisa = bodies[0], bodies[2]
    assert rotation(colisa) == syms(m, "Th3")[0]           # Rotation[colisa] = Th3
    assert rotation(base) == 0
    with pytest.raises(ModelError, match="expected a body"):
        rotation(colisa[1])


def test_direction_seed_form_and_number(m, bodies, qr):
    colisa, deslizadera = bodies[2], bodies[3]
    u = direction(Line(colisa[2], deslizadera[1]))
    assert u == sp.Matrix(mma("{-X3 + X4 + 9 Sin[Th3], -Y3 + Y4 - 9 Cos[Th3]}", m))
    got = ev(u, solved(m, qr, 0.45))
    assert close(got[0], 4.62876) and close(got[1], 1.89067)
    # a body-fixed axis rotates with its body; a pair is its own direction
    Th3 = syms(m, "Th3")[0]
    assert zero(direction(colisa.line(1, 2)) - sp.Matrix([-9 * sp.sin(Th3), 9 * sp.cos(Th3)]))
    assert direction((3, 5)) == sp.Matrix([3, 5])


def test_magnitude(m, bodies, qr):
    colisa, deslizadera = bodies[2], bodies[3]
    assert magnitude((9, 12)) == 15                       # Magnitude[{9, 12}]
    line = Line(colisa[2], deslizadera[1])                 # the 5-long connecting rod
    assert close(ev(magnitude(line), solved(m, qr, 0.3)), 5.0)
    assert magnitude(colisa.line(1, 2)) == 9               # body-fixed: a constant
    assert magnitude(sp.Matrix([1, 1])) == sp.sqrt(2)


def test_unit(m, bodies):
    u = unit((3, 5))
    assert u == sp.Matrix([3 / sp.sqrt(34), 5 / sp.sqrt(34)])     # Unit[{3, 5}]
    Th3 = syms(m, "Th3")[0]
    assert zero(unit(bodies[2].line(1, 2)) - sp.Matrix([-sp.sin(Th3), sp.cos(Th3)]))
    v = unit(Line(bodies[2][2], bodies[3][1]))
    assert zero(v[0] ** 2 + v[1] ** 2 - 1)


def test_cross_seed_form_and_number(m, bodies):
    colisa, deslizadera = bodies[2], bodies[3]
    c = cross(Line(colisa[2], deslizadera[1]), (0, 3))   # Cross[Line[…], {0, 3}]
    assert zero(c - mma("3 (-X3 + X4 + 9 Sin[Th3])", m))
    assert close(ev(c, printed_values(m, **SOLVE_05)), 13.3458)
    assert cross((1, 0), (0, 1)) == 1 and cross((0, 1), (1, 0)) == -1
    assert cross((2, 3), (4, 6)) == 0


# -- intersection, project_on_line ---------------------------------------------------------
def test_intersection_by_hand_and_seed(m, bodies, qr):
    base, manivela, colisa, deslizadera = bodies
    g = mechgen.Model("inter").ground("g", points=[(0, 0), (2, 2), (0, 2), (2, 0)])
    assert intersection(g.line(1, 2), g.line(3, 4)) == sp.Matrix([1, 1])
    # IntersectionPoint[Line[colisa, 2, deslizadera, 1], Line[base, 0, {0, 1}]] at T = .3
    p = intersection(Line(colisa[2], deslizadera[1]), Line(base[0], direction=(0, 1)))
    got = ev(p, solved(m, qr, 0.3))
    assert abs(got[0]) < 1e-9 and close(got[1], 9.16729)


def test_project_on_line_by_hand_and_seed(m, bodies, qr):
    base, manivela, colisa, deslizadera = bodies
    g = mechgen.Model("proj").ground("g", points=[(0, 0), (4, 0), (1, 1)])
    assert project_on_line((2, 3), g.line(1, 2)) == sp.Matrix([2, 0])
    assert project_on_line((2, 0), Line(g[1], g[3])) == sp.Matrix([1, 1])
    # ProjectOnLine[Point[manivela, 2], Line[colisa, 2, deslizadera, 1]] at T = .3
    p = project_on_line(manivela[2], Line(colisa[2], deslizadera[1]))
    got = ev(p, solved(m, qr, 0.3))
    assert close(got[0], -1.15799) and close(got[1], 8.91557)


# -- rotation_matrix, point_to_local ----------------------------------------------------
def test_rotation_matrix_and_local_points(m, bodies):
    deslizadera = bodies[3]
    R = rotation_matrix(deslizadera)
    assert R == sp.Matrix(mma("{{Cos[Th4], -Sin[Th4]}, {Sin[Th4], Cos[Th4]}}", m))
    assert zero(R.T * R - sp.eye(2))
    printed = sp.Matrix(mma("{X4 + 3 Cos[Th4] - 8 Sin[Th4], Y4 + 8 Cos[Th4] + 3 Sin[Th4]}", m))
    assert zero(location(deslizadera, 0) + R * sp.Matrix([3, 8]) - printed)
    assert zero(location(deslizadera, (3, 8)) - printed)
    sub = printed_values(m, **SOLVE_05)
    got = ev(printed, sub)
    assert close(got[0], 2.81812) and close(got[1], 18.0)
    # PointToLocal[deslizadera, %] -> {3., 8.}
    back = point_to_local(deslizadera, location(deslizadera, (3, 8)))
    assert zero(back - sp.Matrix([3, 8]))
    assert np.allclose(ev(back, sub), [3.0, 8.0])
    # of the ground: the identity; a body is required
    assert rotation_matrix(bodies[0]) == sp.eye(2)
    assert point_to_local(bodies[0], (5, 6)) == sp.Matrix([5, 6])
    with pytest.raises(ModelError, match="expected a body"):
        point_to_local((1, 2), (3, 4))


# -- polar_to_xy, xy_to_polar -------------------------------------------------------------
def test_polar_conversions(m, bodies):
    assert polar_to_xy((4, sp.pi / 3)) == sp.Matrix([2, 2 * sp.sqrt(3)])     # PolarToXY[{4, Pi/3}]
    assert polar_to_xy(4, sp.pi / 3) == sp.Matrix([2, 2 * sp.sqrt(3)])
    back = xy_to_polar(polar_to_xy((4, sp.pi / 3)))                     # XYToPolar[%]
    assert back == sp.Matrix([4, sp.atan2(2 * sp.sqrt(3), 2)]) == sp.Matrix([4, sp.pi / 3])
    assert xy_to_polar(0, -2) == sp.Matrix([2, -sp.pi / 2])
    # XYToPolar[Location[deslizadera, 2]] /. LastSolve[] (T = .5) -> {10.1639, 1.39095}
    got = ev(xy_to_polar(location(bodies[3], 2)), printed_values(m, **SOLVE_05))
    assert close(got[0], 10.1639) and close(got[1], 1.39095)


# -- velocity, acceleration, dt ------------------------------------------------------------
def test_velocity_and_acceleration_by_hand(m, bodies):
    deslizadera = bodies[3]
    X4d, Y4d, Th4, Th4d, X4dd, Y4dd, Th4dd = syms(m, "X4d", "Y4d", "Th4", "Th4d", "X4dd",
                                                  "Y4dd", "Th4dd")
    # r = (X4 + 2 cos Th4, Y4 + 2 sin Th4)
    v = sp.Matrix([X4d - 2 * sp.sin(Th4) * Th4d, Y4d + 2 * sp.cos(Th4) * Th4d])
    a = sp.Matrix([X4dd - 2 * sp.cos(Th4) * Th4d ** 2 - 2 * sp.sin(Th4) * Th4dd,
                   Y4dd - 2 * sp.sin(Th4) * Th4d ** 2 + 2 * sp.cos(Th4) * Th4dd])
    assert zero(velocity(deslizadera[2]) - v)
    assert zero(velocity(deslizadera, 2) - v)          # Velocity[deslizadera, 2]
    assert zero(acceleration(deslizadera[2]) - a)
    assert zero(acceleration(deslizadera, 2) - a)
    assert velocity(bodies[0][3]) == sp.zeros(2, 1)     # a ground point stands still


def test_velocity_of_the_slider_matches_the_seed(m, bodies):
    """Velocity[deslizadera, 2][[1]] at SolveMech[0.15, Solution->Velocity] is X4d."""
    got = ev(velocity(bodies[3], 2), printed_values(m, **SOLVE_015))
    assert close(got[0], -18.7395) and abs(got[1]) < 1e-12
    acc = ev(acceleration(bodies[3], 2), printed_values(m, **SOLVE_015))
    assert close(acc[0], -40.9024)


def test_dt_of_distance_seed_form_and_numbers(m, bodies):
    manivela, deslizadera = bodies[1], bodies[3]
    d = distance(manivela[1], deslizadera[1])
    assert zero(d - mma("Sqrt[(-X2 + X4)^2 + (-Y2 + Y4)^2]", m))
    printed = mma("(2 (-X2 + X4) (-X2d + X4d) + 2 (-Y2 + Y4) (-Y2d + Y4d)) /"
                  " (2 Sqrt[(-X2 + X4)^2 + (-Y2 + Y4)^2])", m)
    assert zero(dt(d) - printed)                       # Dt[%, T]
    assert zero(dt(d, order=1) - printed)
    sub = printed_values(m, **SOLVE_015)
    assert close(ev(dt(d), sub), -15.1909)             # DDistanceDT /. LastSolve[]
    assert close(ev(dt(d, 2), sub), -19.056)           # D2DistanceDT2, Dt[…, {T, 2}]
    assert zero(dt(d, 2) - dt(dt(d)))
    assert dt(d, 0) == d


def test_dt_through_coordinates_and_time(m):
    X2, X2d, X2dd, Th3, Th3d, Th3dd = syms(m, "X2", "X2d", "X2dd", "Th3", "Th3d", "Th3dd")
    e = sp.sin(T) * X2 + sp.cos(Th3)
    assert zero(dt(e) - (sp.cos(T) * X2 + sp.sin(T) * X2d - sp.sin(Th3) * Th3d))
    assert zero(dt(e, 2) - (-sp.sin(T) * X2 + 2 * sp.cos(T) * X2d + sp.sin(T) * X2dd
                            - sp.cos(Th3) * Th3d ** 2 - sp.sin(Th3) * Th3dd))
    assert zero(dt(sp.Matrix([X2, Th3])) - sp.Matrix([X2d, Th3d]))
    assert zero(dt([X2, Th3], 2) - sp.Matrix([X2dd, Th3dd]))
    assert dt(sp.Integer(7)) == 0
    with pytest.raises(ModelError, match="order"):
        dt(X2, -1)
    with pytest.raises(ModelError, match="third derivative"):
        dt(X2dd, model=m)       # (without model=, a coordinate named X2d of another test's
                                # model in this process makes X2dd a velocity)


def test_quantities_compile_as_outputs_and_evaluate(m, bodies):
    """The symbolic quantities are what m.output compiles; spot-check they are accepted."""
    model = mechgen.Model("outputs_check")
    g = model.ground("g", points=[(0, 0)])
    b = model.body("b", points=[(0, 0), (1, 0)], guess=(0, 0, 0))
    model.revolute(g[1], b[1])
    model.rotation_lock(b, T)
    model.output("tip_x", location(b[2])[0])
    model.output("tip_vy", velocity(b[2])[1])
    model.output("tip_speed2", velocity(b, 2).dot(velocity(b, 2)))
    X2d, Y2d, Th2, Th2d = syms(model, "X2d", "Y2d", "Th2", "Th2d")
    assert zero(model.outputs["tip_vy"] - (Y2d + sp.cos(Th2) * Th2d))
    assert zero(model.outputs["tip_speed2"] - ((X2d - sp.sin(Th2) * Th2d) ** 2
                                               + (Y2d + sp.cos(Th2) * Th2d) ** 2))
    with pytest.raises(ModelError, match="one scalar"):
        model.output("tip", location(b[2]))
