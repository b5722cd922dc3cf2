"""Forces found wrong by an acceptance audit of API.md §5, each against a computation written
here: a distance driver whose d(T)² holds a constant (its effort from the power balance), a
reaction's moment about a body's first point when that point is its origin or about
``body.at(x, y)`` (Newton–Euler), springs whose stiffness or free length read a coordinate
or T (the documented tension k·(distance − length), and the power balance)."""
import numpy as np
import pytest
import sympy as sp

import mechgen
from mechgen import Model, T, sin, sqrt

G = 9.81
MASS, INERTIA, CENTROID = 2.0, 0.1, (0.5, 0.1)       # the arm, pivoted at its origin
S = 0.6                                              # the ground point (S, 0)


def _compile(model, tmp_path):
    return mechgen.compile(model, outdir=str(tmp_path), tier="python")


def _arm(m, guess=0.8):
    base = m.ground("base", points=[(0, 0), (S, 0), (0.5, 0.4)])
    arm = m.body("arm", points=[(0, 0), (1, 0)], guess=(0, 0, guess), mass=MASS,
                 inertia=INERTIA, centroid=CENTROID)
    m.revolute(base[1], arm[1], name="O")
    return base, arm


def _rot(th, c):
    return np.array([np.cos(th) * c[0] - np.sin(th) * c[1], np.sin(th) * c[0] + np.cos(th) * c[1]])


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def test_a_distance_driver_whose_square_holds_a_constant_gives_its_true_force(tmp_path):
    # d(T) = sqrt(0.5 + 0.2 sin T): the row |r1 − r2|² − d² is |r1 − r2|² − 0.5 − 0.2 sin T;
    # the effort took the constant for part of |r1 − r2|² (39 % off, no error)
    m = Model("audit_distance")
    base, arm = _arm(m)
    m.relative_distance(base[2], arm[2], sqrt(0.5 + 0.2 * sin(T)), name="cylinder")
    m.gravity(G)
    mech = _compile(m, tmp_path)
    t = sp.Symbol("t")
    d2 = 0.5 + 0.2 * sp.sin(t)                       # |P − S|² = 1 + S² − 2 S cos θ
    th = sp.acos((1 + S ** 2 - d2) / (2 * S))
    f = sp.lambdify(t, [th, th.diff(t), th.diff(t, 2), sp.sqrt(d2).diff(t)])
    j_o = INERTIA + MASS * (CENTROID[0] ** 2 + CENTROID[1] ** 2)
    for tt in (0.2, 0.9, 2.0):
        a, ad, add, dd = f(tt)
        yg_rate = ad * (np.cos(a) * CENTROID[0] - np.sin(a) * CENTROID[1])   # d/dt of y_G
        need = j_o * ad * add + MASS * G * yg_rate                 # power the driver gives
        s = mech.solve(tt, level="dynamic")
        assert abs(s["Th2"] - a) < 1e-9
        assert abs(s.driver("cylinder") * dd - need) < 1e-9 * max(1.0, abs(need))


def test_a_reaction_moment_about_the_first_point_at_the_origin_and_about_at(tmp_path):
    # arm[1] is the arm's origin: the module keeps it as arm[0], and about=arm[1] said
    # "not a point of model"; about=arm.at(x, y) too
    m = Model("audit_about")
    base, arm = _arm(m)
    m.rotation_lock(arm, base, 0.3 + 1.5 * T, name="drv")
    m.gravity(G)
    mech = _compile(m, tmp_path)
    tt = 0.4
    th, w = 0.3 + 1.5 * tt, 1.5
    a_g = -w ** 2 * _rot(th, CENTROID)
    f = MASS * a_g + np.array([0.0, MASS * G])       # what the pin applies to the arm, at O
    s = mech.solve(tt, level="dynamic")
    for about, xy in ((arm[1], (0.0, 0.0)), (arm[0], (0.0, 0.0)), (arm[2], _rot(th, (1, 0))),
                      (arm.at(0.25, -0.5), _rot(th, (0.25, -0.5))), (base[2], (S, 0.0))):
        got = s.reaction("O", on="arm", about=about)
        want = [f[0], f[1], _cross(-np.asarray(xy), f)]
        assert np.abs(got - want).max() < 1e-9, about


def _spring_model(name, k, length):
    m = Model(name)
    base, arm = _arm(m, 0.3)
    m.rotation_lock(arm, base, 0.3 + 1.5 * T, name="drv")
    m.spring(base[3], arm[2], k(arm, T), length(arm, T), name="spring")
    return m


def _spring_torque(tt, k, length):
    """The torque that holds the arm against the tension k·(distance − length) (the arm
    turns at constant speed about its origin: no inertial moment)."""
    th = 0.3 + 1.5 * tt
    p = _rot(th, (1, 0))
    d = p - np.array([0.5, 0.4])
    size = np.linalg.norm(d)
    f = -k(th, tt) * (size - length(th, tt)) * d / size      # on the arm's point
    return -_cross(p, f)


def test_springs_whose_stiffness_or_length_read_a_coordinate_pull_as_documented(tmp_path):
    # ½k(q)(L − L0(q))² is no potential of the tension k(L − L0): its gradient added terms
    cases = {"k": (lambda b, t: 100 * (1 + b.th), lambda b, t: 0.4,
                   lambda th, t: 100 * (1 + th), lambda th, t: 0.4),
             "length": (lambda b, t: 100, lambda b, t: 0.4 + 0.1 * b.th,
                        lambda th, t: 100, lambda th, t: 0.4 + 0.1 * th)}
    for name, (k, length, k_num, length_num) in cases.items():
        mech = _compile(_spring_model("audit_spring_" + name, k, length), tmp_path)
        for tt in (0.0, 0.5, 1.0):
            want = _spring_torque(tt, k_num, length_num)
            assert abs(mech.solve(tt, level="dynamic").driver("drv") - want) < 1e-9, name
        sw = mech.sweep(0, 1, 11, level="dynamic")
        assert np.abs(sw.power()["residual"]).max() < 1e-9


def test_the_power_balance_closes_with_a_spring_whose_length_changes_with_time(tmp_path):
    # ∂V/∂t was in "potential" (dV/dt) but in nothing else: the residual was ∂V/∂t
    mech = _compile(_spring_model("audit_spring_t", lambda b, t: 100 * (1 + t),
                                  lambda b, t: 0.4 + 0.1 * sin(3 * t)), tmp_path)
    sw = mech.sweep(0, 1, 201, level="dynamic")
    for k in (0, 100, 200):
        want = _spring_torque(sw.t[k], lambda th, t: 100 * (1 + t),
                              lambda th, t: 0.4 + 0.1 * np.sin(3 * t))
        assert abs(sw.driver("drv")[k] - want) < 1e-9
    power = sw.power()
    assert np.abs(power["residual"]).max() < 1e-9 * np.abs(power["drivers"]).max()
    # "potential" is the potential energy's rate (central differences on sw.energy())
    v = sw.energy()["potential"]
    rate = (v[2:] - v[:-2]) / (sw.t[2:] - sw.t[:-2])
    assert np.abs(rate - power["potential"][1:-1]).max() < 1e-3 * np.abs(rate).max()


def test_a_negative_mass_or_inertia_given_at_run_time_is_refused_naming_the_body(tmp_path):
    """The build refuses a negative mass in the model's defaults; with_params (and load's
    params=) refuse one given later, naming the body, where it used to solve silently."""
    m = Model("audit_params_mass")
    mass, inertia = m.param("mass", MASS), m.param("inertia", INERTIA)
    base = m.ground("base", points=[(0, 0)])
    arm = m.body("arm", points=[(0, 0), (1, 0)], guess=(0, 0, 0.8), mass=mass,
                 inertia=inertia, centroid=CENTROID)
    m.revolute(base[1], arm[1], name="O")
    m.rotation_lock(arm, 0.8 + T, name="drive")
    m.gravity(G)
    mech = _compile(m, tmp_path)
    with pytest.raises(ValueError, match=r"mass=-3.0: body 'arm' has a negative mass \(-3\)"):
        mech.with_params(mass=-3.0)
    # J is the inertia about the centroid: J + m|c|² > 0 still, and it is refused
    with pytest.raises(ValueError, match=r"body 'arm' has a negative inertia \(-0.05\)"):
        mech.with_params(inertia=-0.05)
    with pytest.raises(ValueError, match=r"negative mass"):
        mechgen.load(mech.module, params={"mass": -1.0})
    s = mech.with_params(mass=0.0, inertia=0.0).solve(0.1, level="dynamic")
    assert abs(s.driver("drive")) < 1e-12            # massless: nothing to drive
    s = mech.with_params(mass=3.0).solve(0.1, level="static")
    th = 0.9
    c = _rot(th, CENTROID)
    assert abs(s.driver("drive") - 3.0 * G * c[0]) < 1e-12
