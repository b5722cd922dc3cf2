"""Seed 001's output functions (sections 5, 6, 7), the slider stroke ("OBTENCION VALORES
MAXIMO Y MINIMO X4") and the lock-point angles of section 3B, evaluated with
mech.evaluate on a mechanism built by mechgen.compile, and as compiled outputs."""
import math
import os

import numpy as np
import pytest
import sympy as sp

import mechgen
from mechgen import (Line, angle, cross, direction, distance, dt, intersection, location,
                     magnitude, point_to_line_distance, point_to_local, polar_to_xy,
                     project_on_line, rotation, rotation_matrix, unit, xy_to_polar)
from mechgen.bridge import attach
from conftest import GENERATED, example_model


def close(a, b, digits=6):
    """Mech prints 6 significant digits: a matches when it rounds to b."""
    return abs(a - b) <= 0.6 * 10 ** (math.floor(math.log10(max(abs(b), 1e-300))) - digits + 1)


def close_vec(a, b, digits=6):
    a = np.asarray(a, dtype=float).ravel()
    return a.shape == (len(b),) and all(close(x, y, digits) if y != 0 else abs(x) < 1e-9
                                        for x, y in zip(a, b))


@pytest.fixture(scope="module")
def qr_model():
    """The crank-driven quick-return with the seed's distance declared as compiled outputs."""
    m = example_model("quick_return")
    m.name = "qr_output_functions"       # its own module, apart from generated/quick_return
    b = m.bodies
    m.output("d_crank_slider", distance(b["manivela"][1], b["deslizadera"][1]))
    m.output("link_angle", angle(Line(b["colisa"][2], b["deslizadera"][1])))
    return m


@pytest.fixture(scope="module")
def mech(qr_model, tmp_path_factory):
    """On the plain-Python tier: the values of the seed's functions, the same text and
    numbers as numba's (which runs a module's outputs in generated/quick_return.py's
    tests), without compiling this build (~25 s of CPU)."""
    return mechgen.compile(qr_model, outdir=str(tmp_path_factory.mktemp("outfn")),
                           tier="python")


@pytest.fixture(scope="module")
def parts(qr_model):
    return qr_model.bodies


# -- section 5: position output functions ------------------------------------------------
def test_location_symbolic_and_values(mech, parts):
    colisa = parts["colisa"]
    X3, Y3, Th3 = colisa.x, colisa.y, colisa.th
    expr = location(colisa, 2)
    assert sp.simplify(expr - sp.Matrix([X3 - 9 * sp.sin(Th3), Y3 + 9 * sp.cos(Th3)])) == sp.zeros(2, 1)
    assert close_vec(mech.evaluate(expr, mech.solve(0.3)), (-1.05511, 8.93794))
    assert close_vec(mech.evaluate(location(colisa[2]), mech.solve(0.4)), (-3.03987, 8.47108))


def test_distance(mech, parts):
    d = distance(parts["manivela"][1], parts["deslizadera"][2])
    assert close(mech.evaluate(d, mech.solve(0.1)), 11.0022)
    assert close(mech.evaluate(d, mech.solve(0.2)), 9.38401)
    # two points of one body: the crank's length, 3, whatever the configuration
    crank = distance(parts["manivela"][1], parts["manivela"][2])
    assert not crank.free_symbols & {parts["manivela"].th, parts["manivela"].x}
    assert mech.evaluate(crank, mech.last) == pytest.approx(3.0, abs=1e-14)


def test_point_to_line_distance(mech, parts):
    d = point_to_line_distance(parts["manivela"][1], parts["colisa"].line(1, 2))
    assert close(mech.evaluate(d, mech.solve(0.2)), 0.58617)
    assert abs(mech.evaluate(d, mech.solve(0.25))) < 1e-12      # Mech: 1.14807 10^-16


def test_angle_intersection_projection_at_03(mech, parts):
    link = Line(parts["colisa"][2], parts["deslizadera"][1])
    s = mech.solve(0.3)
    assert close(math.degrees(mech.evaluate(angle(link), s)), 12.2638)
    vertical = Line(parts["base"][0], direction=(0, 1))
    assert close_vec(mech.evaluate(intersection(link, vertical), mech.last), (0.0, 9.16729))
    proj = project_on_line(parts["manivela"][2], link)
    assert close_vec(mech.evaluate(proj, mech.last), (-1.15799, 8.91557))
    assert rotation(parts["colisa"]) == parts["colisa"].th


def test_vector_algebra(mech, parts):
    link = Line(parts["colisa"][2], parts["deslizadera"][1])
    s = mech.solve(0.45)
    assert close_vec(mech.evaluate(direction(link), s), (4.62876, 1.89067))
    assert abs(mech.evaluate(magnitude(link), mech.last) - 5.0) < 1e-12
    assert sp.simplify(magnitude((9, 12)) - 15) == 0
    assert sp.simplify(unit((3, 5)) - sp.Matrix([3, 5]) / sp.sqrt(34)) == sp.zeros(2, 1)
    colisa, desl = parts["colisa"], parts["deslizadera"]
    c = cross(link, (0, 3))
    assert sp.expand(c - 3 * (-colisa.x + desl.x + 9 * sp.sin(colisa.th))) == 0
    assert close(mech.evaluate(c, mech.solve(0.5)), 13.3458)


def test_rotation_matrix_location_and_back(mech, parts):
    desl = parts["deslizadera"]
    Th4 = desl.th
    assert rotation_matrix(desl) == sp.Matrix([[sp.cos(Th4), -sp.sin(Th4)], [sp.sin(Th4), sp.cos(Th4)]])
    by_matrix = location(desl, 0) + rotation_matrix(desl) * sp.Matrix([3, 8])
    p = location(desl, (3, 8))
    assert sp.simplify(by_matrix - p) == sp.zeros(2, 1)
    s = mech.solve(0.5)
    assert close_vec(mech.evaluate(p, s), (2.81812, 18.0))
    back = mech.evaluate(point_to_local(desl, p), mech.last)
    assert np.allclose(np.ravel(back), (3.0, 8.0), atol=1e-12)


def test_polar_conversions(mech, parts):
    xy = polar_to_xy((4, sp.pi / 3))
    assert sp.simplify(xy - sp.Matrix([2, 2 * sp.sqrt(3)])) == sp.zeros(2, 1)
    back = xy_to_polar(xy)
    assert sp.simplify(back[0] - 4) == 0 and sp.simplify(back[1] - sp.pi / 3) == 0
    s = mech.solve(0.5)                         # LastSolve[] of the seed at this point
    assert close_vec(mech.evaluate(xy_to_polar(location(parts["deslizadera"][2])), s),
                     (10.1639, 1.39095))


# -- sections 6 and 7: time derivatives -----------------------------------------------------
def test_distance_derivatives_symbolic(mech, parts):
    d = distance(parts["manivela"][1], parts["deslizadera"][1])
    s = mech.solve(0.15, level="acceleration")
    assert close(mech.evaluate(dt(d), s), -15.1909)
    assert close(mech.evaluate(dt(d, 2), s), -19.056, 5)


def test_distance_derivatives_compiled(mech):
    """m.output(...) is compiled with its first and second time derivatives."""
    s = mech.solve(0.15, level="acceleration")
    assert close(s["d_crank_slider"], math.hypot(6.92194, 10 - 5), 5)   # from the seed's X4
    assert close(s["d_crank_sliderd"], -15.1909)
    assert close(s["d_crank_sliderdd"], -19.056, 5)
    with pytest.raises(KeyError):
        mech.solve(0.15)["d_crank_sliderd"]          # needs velocities


def test_compiled_outputs_match_evaluate_on_a_sweep(mech, parts):
    sw = mech.sweep(0.0, 1.0, 41, level="acceleration")
    d = distance(parts["manivela"][1], parts["deslizadera"][1])
    assert np.allclose(sw["d_crank_slider"], mech.evaluate(d, sw), rtol=1e-13, atol=1e-13)
    assert np.allclose(sw["d_crank_sliderd"], mech.evaluate(dt(d), sw), rtol=1e-11, atol=1e-11)
    assert np.allclose(sw["d_crank_sliderdd"], mech.evaluate(dt(d, 2), sw), rtol=1e-10, atol=1e-10)
    k = 12
    assert close(math.degrees(sw[k]["link_angle"]),
                 math.degrees(mech.evaluate(angle(Line(parts["colisa"][2], parts["deslizadera"][1])),
                                            sw[k])), 12)


def test_velocity_of_slider_point_interpolates(mech, parts):
    """Section 6: TimeInterpolate[Velocity[deslizadera, 2][[1]], veltab] on 11 points."""
    from mechgen import velocity
    veltab = mech.sweep(0.0, 1.0, 11, level="velocity")
    vx = mech.evaluate(velocity(parts["deslizadera"][2])[0], veltab)
    assert np.allclose(vx, veltab["X4d"], atol=1e-12)          # the slider only translates
    p1 = veltab.interpolate("X4d")
    # independently: the not-a-knot cubic spline (X4dd is not held at level velocity)
    # through the closed form's dX4/dT at the 11 times; the points are exact to 1e-12, and
    # the spline is linear in them
    from scipy.interpolate import CubicSpline
    import mpmath as mp
    with mp.workdps(30):
        exact = [float(mp.diff(_x4_exact, mp.mpf(t))) for t in veltab.t]
        truth = float(mp.diff(_x4_exact, mp.mpf("0.37")))
    assert np.max(np.abs(veltab["X4d"] - exact)) < 1e-11
    for t in (0.37, 0.05, 0.61, 0.93):
        assert abs(p1(t) - CubicSpline(veltab.t, exact)(t)) < 1e-10, t
    s = mech.solve(0.37, level="velocity")
    assert abs(s["X4d"] - truth) < 1e-11


# -- the stroke: Mech's coarse route and the exact extremes --------------------------------
def _x4_exact(T):
    """Closed form of X4(T) for the seed's geometry (the slider right of the lever's end)."""
    import mpmath as mp
    th = 2 * mp.pi * T
    px, py = 3 * mp.cos(th), 5 + 3 * mp.sin(th)
    r = mp.sqrt(px ** 2 + py ** 2)
    ex, ey = 9 * px / r, 9 * py / r
    return ex + mp.sqrt(25 - (10 - ey) ** 2)


@pytest.fixture(scope="module")
def stroke_reference():
    import mpmath as mp
    mp.mp.dps = 30
    out = []
    for bracket in ((0.55, 0.65), (0.85, 0.95)):
        t = mp.findroot(lambda T: mp.diff(_x4_exact, T), bracket, solver="anderson")
        out.append((float(t), float(_x4_exact(t))))
    return out


def test_stroke_mech_route(mech):
    """posicionT = SolveMech[{0,1}, 20]: Mech's 20 points. FindRoot on the interpolated X4d
    (Mathematica's default third-order InterpolatingFunction) gives the seed's digits."""
    posicion = mech.sweep(0.0, 1.0, 20)
    x4t = posicion.interpolate("X4", method="lagrange")
    velocidad = mech.sweep(0.0, 1.0, 20, level="velocity")
    x4dt = velocidad.interpolate("X4d", method="lagrange")
    from scipy.optimize import brentq
    tmin = brentq(x4dt, 0.55, 0.65, xtol=1e-14)
    tmax = brentq(x4dt, 0.85, 0.95, xtol=1e-14)
    assert close(tmin, 0.602307) and close(tmax, 0.897082)
    lo, hi = x4t(tmin), x4t(tmax)
    assert close(lo, -1.26516) and close(hi, 9.54378)
    assert close((hi - lo) / 2, 5.40447) and close(lo + (hi - lo) / 2, 4.13931)
    # the same numbers as the coarse side of extrema()
    ev = velocidad.extrema("X4", method="lagrange")
    assert [e.kind for e in ev] == ["min", "max"]
    assert close(ev[0].t_interp, 0.602307) and close(ev[0].value_interp, -1.26516)
    assert close(ev[1].t_interp, 0.897082) and close(ev[1].value_interp, 9.54378)


def test_stroke_exact(mech, stroke_reference):
    (t_lo, x_lo), (t_hi, x_hi) = stroke_reference
    assert abs(t_lo - 0.6024164) < 1e-7 and abs(x_lo + 1.2575370) < 1e-7
    assert abs(t_hi - 0.8975836) < 1e-7 and abs(x_hi - 9.5424630) < 1e-7
    for sweep in (mech.sweep(0.0, 1.0, 20), mech.sweep(0.0, 1.0, 21, level="acceleration")):
        ev = sweep.extrema("X4")
        assert [e.kind for e in ev] == ["min", "max"]
        assert abs(ev[0].t - t_lo) < 1e-10 and abs(ev[0].value - x_lo) < 1e-11
        assert abs(ev[1].t - t_hi) < 1e-10 and abs(ev[1].value - x_hi) < 1e-11
    # and the seed's coarse answer is off by more than 1e-4 in t and 7e-3 in X4
    coarse = mech.sweep(0.0, 1.0, 20, level="velocity").extrema("X4", method="lagrange")
    assert abs(coarse[0].error_t) > 1e-4 and abs(coarse[0].error_value) > 7e-3


def test_stroke_of_a_compiled_output_and_an_expression(mech, parts, stroke_reference):
    (t_lo, _), (t_hi, _) = stroke_reference
    sw = mech.sweep(0.0, 1.0, 21, level="velocity")
    ev = sw.extrema("stroke_x")
    assert np.allclose(ev.t, (t_lo, t_hi), atol=1e-10)
    ev = sw.extrema(location(parts["deslizadera"][1])[0])
    assert np.allclose(ev.t, (t_lo, t_hi), atol=1e-10)
    assert np.allclose(sw.roots("X4d").t, (t_lo, t_hi), atol=1e-10)


# -- section 3B: transmission angle at the lock point of the slider-driven model --------------
@pytest.fixture(scope="module")
def slider():
    model = example_model("quick_return_slider")
    mech = mechgen.load(os.path.join(GENERATED, "quick_return_slider.py"))
    attach(mech, model)     # the symbolic side mechgen.compile would attach
    return mech, model.bodies


def test_transmission_angle_at_lock_point(slider):
    mech, b = slider
    sw = mech.sweep(0.0, 0.245, 50)                  # follow the seed's branch from T = 0
    s = sw[-1]
    assert close(s["Th2"], -0.611293) and close(s["X4"], 9.54111)
    crank = math.degrees(mech.evaluate(angle(b["manivela"].vector(2)), s))
    lever = math.degrees(mech.evaluate(angle(b["colisa"].vector(2)), s))
    assert close(crank, -35.0245) and close(lever, 53.1519)
    assert close(lever - crank, 88.1764)
