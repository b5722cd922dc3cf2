"""Driver efforts and reactions (docs/reference/forces.md), each against a computation written here:
a distance driver whose d(T)² holds a constant (its effort from the power balance), a reaction's
moment about a body's first point when that point is its origin or about ``body.at(x, y)``
(Newton–Euler), springs whose stiffness or free length read a coordinate or T (the documented
tension k·(distance − length), and the power balance); drivers in stages and at a switch's left
limit, a driver of two rows, a rack driven by its phase, two drivers prescribing one motion (the
power balance, Newton–Euler)."""
import numpy as np
import pytest
import sympy as sp

import mechgen
from mechgen import Model, T, cos, sin, sqrt

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


def test_a_distance_driver_in_a_stage_gives_its_force_not_its_multiplier(tmp_path):
    # a motor turns the arm up to t = 0.5, a cylinder (relative_distance, d(T)) drives it
    # after: the cylinder's effort came out as -λ instead of -2dλ (4.088 where the force
    # is 6.702 at t = 0.7, no error), the stage row taking the factor of a rotation_lock
    law = 0.9 + 0.3 * (T - 0.5)
    d = sqrt(1 + S ** 2 - 2 * S * cos(law))
    m = Model("audit_stage_cylinder")
    base, arm = _arm(m)
    with m.stage("motor", until=0.5):
        m.rotation_lock(arm, 0.8 + 0.2 * T, name="motor")
    with m.stage("cylinder"):
        m.relative_distance(base[2], arm[2], d, name="cylinder")
    m.gravity(G)
    mech = _compile(m, tmp_path)
    j_o = INERTIA + MASS * (CENTROID[0] ** 2 + CENTROID[1] ** 2)
    sw = mech.sweep(0.0, 1.0, 11, level="dynamic")
    for k, tt in enumerate(sw.t):
        th, w, a = sw["Th2"][k], sw["Th2d"][k], sw["Th2dd"][k]
        power = j_o * w * a + MASS * G * w * (np.cos(th) * CENTROID[0] - np.sin(th) * CENTROID[1])
        if k <= 5:           # the motor: torque x its rate (the switch's left side included)
            assert abs(sw.driver("motor")[k] * w - power) < 1e-9 * max(1, abs(power))
        else:                # the cylinder: force x the rate of its length
            dist = np.sqrt(1 + S ** 2 - 2 * S * np.cos(th))
            rate = S * np.sin(th) * w / dist
            assert abs(sw.driver("cylinder")[k] * rate - power) < 1e-9 * max(1, abs(power))
    s = mech.solve(0.7, level="static")
    th = s["Th2"]
    torque = MASS * G * (np.cos(th) * CENTROID[0] - np.sin(th) * CENTROID[1])
    arm_of = S * np.sin(th) / np.sqrt(1 + S ** 2 - 2 * S * np.cos(th))   # d(dist)/dθ
    assert abs(s.driver("cylinder") * arm_of - torque) < 1e-9 * abs(torque)


def _quick_return_torque(t):
    """The crank torque of the crank-driven quick-return with the lever's mass 5, inertia
    33.75 about its centroid (0, 4.5) local and the slider's mass 2, under gravity 9.807
    (tests/closed_forms.quick_return_torque: the power balance by mpmath)."""
    from closed_forms import quick_return_torque
    return quick_return_torque(t, {"colisa": (5.0, 33.75, (0, 4.5)),
                                   "deslizadera": (2.0, 0.5, (0, 0))})


def test_the_left_limit_of_a_switch_keeps_the_earlier_stages_forces(tmp_path):
    # examples/quick_return_crank_slider.py with masses: the crank drives up to t = 0.25,
    # the slider after it. The sweep's row of the switch's left limit (the crank's motion)
    # had its multipliers solved on the slider stage's equations (T = 0.25 picks them):
    # crank torque -20.40 where a solve just below the switch gives 68.84, the slider
    # guide's reaction 19.61 instead of 23.78, with no error
    import os
    from conftest import EXAMPLES
    src = open(os.path.join(EXAMPLES, "quick_return_crank_slider.py")).read()
    src = src.replace('guess=(0, 0, -0.5))', 'guess=(0, 0, -0.5), mass=5.0, inertia=33.75, '
                      'centroid=(0, 4.5))')
    src = src.replace('guess=(6, 10, 0))', 'guess=(6, 10, 0), mass=2.0, inertia=0.5)')
    path = tmp_path / "qrcs_forces.py"
    path.write_text(src.replace('Model("quick_return_crank_slider")', 'Model("qrcs_forces")')
                    + "\nm.gravity(9.807)\n")
    mech = mechgen.compile(str(path), outdir=str(tmp_path / "gen"), tier="python")
    sw = mech.sweep(0.0, 0.5, 11, level="dynamic")
    left = sw.switches[0].row_before
    assert sw.t[left] == 0.25
    s = mech.solve(float(np.nextafter(0.25, 0.0)), level="dynamic")
    np.testing.assert_allclose(sw.Q[left], s.q, atol=1e-9)
    assert abs(sw.driver("crank driver")[left] - s.driver("crank driver")) < 1e-6
    assert abs(s.driver("crank driver") - _quick_return_torque(0.25)) < 1e-5
    for con, body in ((5, "deslizadera"), (3, "colisa"), (1, "manivela")):
        np.testing.assert_allclose(sw.reaction(con, on=body)[left], s.reaction(con, on=body),
                                   atol=1e-6)
    power = sw.power()
    assert np.abs(power["residual"]).max() < 1e-9 * np.abs(power["drivers"]).max()
    st = mech.sweep(0.0, 0.5, 11, level="static")
    s = mech.solve(float(np.nextafter(0.25, 0.0)), level="static")
    assert abs(st.driver("crank driver")[left] - s.driver("crank driver")) < 1e-6


def test_a_driver_of_two_rows_in_t_has_no_summed_effort(tmp_path):
    # origin_lock moving a block along a path (x = cos T, y = 0.5 sin T): driver() gave
    # λx·(−1) + λy·(−1) = fx + fy = 17.39 (the x force added to the y force), a number
    # whose product with no rate is the driver's power (9.57); now a clear ValueError,
    # the force itself being the reaction
    m = Model("audit_path")
    m.ground("base", points=[(0, 0)])
    blk = m.body("blk", points=[(0, 0), (1, 0)], guess=(1, 0, 0), mass=2.0, inertia=0.1)
    m.origin_lock(blk, offset=(cos(T), 0.5 * sin(T)), name="path")
    m.rotation_lock(blk, 0.3, name="keep")
    m.gravity(G)
    mech = _compile(m, tmp_path)
    s = mech.solve(0.4, level="dynamic")
    with pytest.raises(ValueError, match="several"):
        s.driver("path")
    np.testing.assert_allclose(s.reaction("path", on="blk")[:2],
                               [-2.0 * np.cos(0.4), -np.sin(0.4) + 2.0 * G], atol=1e-12)
    sw = mech.sweep(0.0, 1.0, 3, level="dynamic")
    with pytest.raises(ValueError, match="several"):
        sw.driver("path")
    assert "path" not in sw.force_columns()[0]


def test_a_rack_and_pinion_driven_by_its_phase_gives_the_force_along_the_rack(tmp_path):
    # rack_and_pinion(..., c = 1 + 0.5 sin 2T) on a rack inclined by 0.3 rad, the wheel
    # held from turning: the phase pushes it along the rack. Its effort was refused ("not
    # defined for this form of equation": the offset row, free of T, got NaN); the force
    # along the rack is m (s'' + g sin α), s = c(T) - r θ
    al, rad, mass = 0.3, 0.4, 2.0
    p = Model("audit_rack_phase")
    ground = p.ground("ground", points=[(0, 0), (cos(al), sin(al))])
    wheel = p.body("wheel", points=[(0, 0), (rad, 0)], guess=(0.5, 0.5, 0), mass=mass,
                   inertia=0.1)
    p.rack_and_pinion(wheel[1], rad, ground.line(1, 2), 1.0 + 0.5 * sin(2 * T), name="mesh")
    p.rotation_lock(wheel, 0.0, name="stop")
    p.gravity(G)
    mech = _compile(p, tmp_path)
    sw = mech.sweep(0.0, 2.0, 5, level="dynamic")
    np.testing.assert_allclose(sw.driver("mesh"),
                               mass * (-2.0 * np.sin(2 * sw.t) + G * np.sin(al)), rtol=1e-12)
    power = sw.power()
    np.testing.assert_allclose(power["drivers"], sw.driver("mesh") * np.cos(2 * sw.t),
                               rtol=1e-12, atol=1e-12)
    st = mech.solve(0.7, level="static")
    assert abs(st.driver("mesh") - mass * G * np.sin(al)) < 1e-12


def test_two_drivers_that_prescribe_one_motion_say_their_efforts_are_shared(tmp_path):
    # two gears on fixed shafts, each driven by its own rotation_lock at the meshing
    # ratio: the two drivers and the mesh are redundant, and how the torque splits between
    # the drivers is not determined. driver() gave the minimum-norm shares (-0.2867 and
    # 0.1564) as if they were the efforts, silently; now a RedundancyWarning says so (their
    # power together stays exact)
    m = Model("audit_two_drivers")
    base = m.ground("base", points=[(0, 0), (4, 0)])
    a = m.body("A", points=[(0, 0), (1, 0)], guess=(0, 0, 0), mass=1, inertia=0.2)
    b = m.body("B", points=[(0, 0), (3, 0)], guess=(4, 0, 0), mass=1, inertia=0.9)
    m.revolute(base[1], a[1], name="a shaft")
    m.revolute(base[2], b[1], name="b shaft")
    m.gear_ratio(a[1], 1.0, b[1], 3.0, name="mesh")
    m.rotation_lock(a, T + 0.5 * sin(2 * T), name="drive A")
    m.rotation_lock(b, -(T + 0.5 * sin(2 * T)) / 3, name="drive B")
    mech = _compile(m, tmp_path)
    with pytest.warns(mechgen.RedundancyWarning):
        s = mech.solve(0.3, level="dynamic")
    with pytest.warns(mechgen.RedundancyWarning, match="not unique"):
        ta = s.driver("drive A")
    with pytest.warns(mechgen.RedundancyWarning, match="not unique"):
        tb = s.driver("drive B")
    w = 1 + np.cos(0.6)                              # the input's rate, and its acceleration
    alpha = -2 * np.sin(0.6)
    need = (0.2 + 0.9 / 9) * alpha * w               # d/dt of the kinetic energy
    assert abs(ta * w + tb * (-w / 3) - need) < 1e-12
    with pytest.warns(mechgen.RedundancyWarning, match="not unique"):
        mech.sweep(0.0, 1.0, 3, level="dynamic").driver("drive B")


MB_, KB_, OMB_ = 0.7, 9.0, 1.3               # tests/test_simulate_drivers.bead_on_rod's


def _bead_forces(t):
    """The bead's push along e_r and the rod's force along e_t in closed form: in the rod's
    frame, F = m (s̈ − s ω²) + k s + m g sin ωt, N = 2 m ṡ ω + m g cos ωt (Coriolis and
    gravity), s = 0.5 + 0.2 sin 3T; as global (x, y) pairs."""
    s, sd, sdd = 0.5 + 0.2 * np.sin(3 * t), 0.6 * np.cos(3 * t), -1.8 * np.sin(3 * t)
    c, sn = np.cos(OMB_ * t), np.sin(OMB_ * t)
    push = MB_ * (sdd - s * OMB_ ** 2) + KB_ * s + MB_ * G * sn
    rod = 2 * MB_ * sd * OMB_ + MB_ * G * c
    return np.array([push * c, push * sn]), np.array([-rod * sn, rod * c])


def test_a_bead_pushed_along_a_turning_rod_gets_its_push_and_the_rods_force(tmp_path):
    # rows that mix T and the coordinates (Φ_qt ≠ 0, so γ holds −2 Φ_qt q̇): the bead of
    # tests/test_simulate_drivers.bead_on_rod pushed to s = 0.5 + 0.2 sin 3T along a rod
    # turning at ω; its push and the rod's force against _bead_forces (the closed form
    # s(T), not the module's q̈), and its accelerations against the polar form's
    from test_simulate_drivers import KB, MB, OMB, bead_on_rod
    assert (MB, KB, OMB) == (MB_, KB_, OMB_)
    mech = _compile(bead_on_rod(), tmp_path)
    for t in (0.0, 0.45, 1.1, 2.0):
        sol = mech.solve(t, level="dynamic")
        push, rod = _bead_forces(t)
        np.testing.assert_allclose(sol.reaction("push", on="bead")[:2], push, atol=1e-9)
        np.testing.assert_allclose(sol.reaction("rod", on="bead")[:2], rod, atol=1e-9)
        s, sd, sdd = 0.5 + 0.2 * np.sin(3 * t), 0.6 * np.cos(3 * t), -1.8 * np.sin(3 * t)
        c, sn = np.cos(OMB * t), np.sin(OMB * t)
        np.testing.assert_allclose(
            [sol["X2dd"], sol["Y2dd"]],
            [(sdd - s * OMB ** 2) * c - 2 * sd * OMB * sn,
             (sdd - s * OMB ** 2) * sn + 2 * sd * OMB * c], atol=1e-9)
    st = mech.solve(0.7, level="static")    # static: no inertia, the spring and gravity
    s7 = 0.5 + 0.2 * np.sin(2.1)
    f = KB * s7 + MB * G * np.sin(OMB * 0.7)
    np.testing.assert_allclose(st.reaction("push", on="bead")[:2],
                               [f * np.cos(OMB * 0.7), f * np.sin(OMB * 0.7)], atol=1e-9)


def test_a_dynamic_sweep_of_the_bead_gives_its_push_and_the_rods_force(tmp_path):
    from test_simulate_drivers import bead_on_rod
    mech = _compile(bead_on_rod(), tmp_path)
    sw = mech.sweep(0.0, 2.0, 9, level="dynamic")
    for k, t in enumerate(sw.t):
        push, rod = _bead_forces(t)
        np.testing.assert_allclose(sw.reaction("push", on="bead")[k, :2], push, atol=1e-9)
        np.testing.assert_allclose(sw.reaction("rod", on="bead")[k, :2], rod, atol=1e-9)

