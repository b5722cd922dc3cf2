"""Forces and forward dynamics found wrong by an acceptance audit of API.md §5–6 on models
beyond revolutes and sliders (stages, gears, cams, extra coordinates, velocity loads), each
against a computation written here (the power balance of a closed form, Lagrange's
equations, Newton–Euler)."""
import numpy as np
import pytest

import mechgen
from mechgen import Model, T, cos, sin, sqrt

G = 9.81
MASS, INERTIA, CENTROID = 2.0, 0.1, (0.5, 0.1)       # an arm pivoted at its origin
S = 0.6                                              # the ground point (S, 0)


def _compile(model, tmp_path):
    return mechgen.compile(model, outdir=str(tmp_path), tier="python")


def _arm(m, guess=0.8):
    base = m.ground("base", points=[(0, 0), (S, 0)])
    arm = m.body("arm", points=[(0, 0), (1, 0)], guess=(0, 0, guess), mass=MASS,
                 inertia=INERTIA, centroid=CENTROID)
    m.revolute(base[1], arm[1], name="O")
    return base, arm


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
    assert abs(s.driver("crank driver") - 68.8434987) < 1e-5
    for con, body in ((5, "deslizadera"), (3, "colisa"), (1, "manivela")):
        np.testing.assert_allclose(sw.reaction(con, on=body)[left], s.reaction(con, on=body),
                                   atol=1e-6)
    power = sw.power()
    assert np.abs(power["residual"]).max() < 1e-9 * np.abs(power["drivers"]).max()
    st = mech.sweep(0.0, 0.5, 11, level="static")
    s = mech.solve(float(np.nextafter(0.25, 0.0)), level="static")
    assert abs(st.driver("crank driver")[left] - s.driver("crank driver")) < 1e-6


def test_simulate_a_planetary_set_with_two_planets_redundant_meshes(tmp_path):
    # two planets on the arm, each meshing with the sun and the fixed ring: one mesh is
    # redundant (13 rows, 12 coordinates). The force solves give the driver's torque
    # (minimum-norm multipliers); simulate refused the motion, which is determined:
    # "SingularError: the equations of motion lose rank (23 of 24)"
    import warnings
    rs, rq = 1.0, 0.75
    rr = rs + 2 * rq
    j_sun, j_arm, m_planet, j_planet = 0.3, 0.25, 0.5, 0.05
    p = Model("audit_two_planets")
    frame = p.ground("frame", points=[(0, 0)])
    sun = p.body("sun", points=[(0, 0), (rs, 0)], guess=(0, 0, 0), mass=1, inertia=j_sun)
    arm = p.body("arm", points=[(0, 0), (rs + rq, 0), (-(rs + rq), 0)], guess=(0, 0, 0),
                 mass=0.8, inertia=j_arm)
    p1 = p.body("p1", points=[(0, 0), (rq, 0)], guess=(rs + rq, 0, 0), mass=m_planet,
                inertia=j_planet)
    p2 = p.body("p2", points=[(0, 0), (rq, 0)], guess=(-(rs + rq), 0, 0), mass=m_planet,
                inertia=j_planet)
    p.revolute(frame[1], sun[1], name="sun shaft")
    p.revolute(frame[1], arm[1], name="arm shaft")
    p.revolute(arm[2], p1[1], name="pin1")
    p.revolute(arm[3], p2[1], name="pin2")
    p.gear_ratio(sun[1], rs, p1[1], rq, name="sun-p1")
    p.gear_ratio(p1[1], rq, frame[1], -rr, name="p1-ring")
    p.gear_ratio(sun[1], rs, p2[1], rq, name="sun-p2")
    p.gear_ratio(p2[1], rq, frame[1], -rr, name="p2-ring")
    p.rotation_lock(sun, 3.5 * T, name="input")
    p.moment(arm, -1.0, name="load")
    mech = _compile(p, tmp_path)
    ka = rs / (rs + rr)                          # arm / sun, Willis
    kp = ka - (rs / rq) * (1 - ka)               # planet / sun
    inertia = j_sun + (j_arm + 2 * m_planet * (rs + rq) ** 2) * ka ** 2 + 2 * j_planet * kp ** 2
    alpha = -1.0 * ka / inertia                  # the sun's angular acceleration, released
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        s = mech.solve(0.3, level="dynamic")
        assert s.indeterminate and abs(s.driver("input") - 1.0 * ka) < 1e-12
        sw = mech.simulate(0.0, 1.0, 11, free=["input"])
    assert "sun-p2: gear_ratio(sun[1], 1.0, p2[1], 0.75)" in sw.indeterminate
    np.testing.assert_allclose(sw["Th2"], 3.5 * sw.t + 0.5 * alpha * sw.t ** 2, atol=1e-7)
    np.testing.assert_allclose(sw["Th2dd"], alpha, rtol=1e-9)
    np.testing.assert_allclose(sw["Th3"], ka * sw["Th2"], atol=1e-9)
    energy = sw.energy()["total"]
    np.testing.assert_allclose(energy - energy[0], -1.0 * (sw["Th3"] - sw["Th3"][0]), atol=1e-7)
    assert np.abs(sw.power()["residual"]).max() < 1e-9
    r = np.empty(mech.m)
    keep = [i for i, label in enumerate(mech.constraint_labels) if "input" not in label]
    for k in range(len(sw)):
        mech.module.phi(sw.Q[k], float(sw.t[k]), mech.p, r)
        assert np.abs(r[keep]).max() < 1e-10


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


@pytest.mark.parametrize("method", ["dopri5", "RK45"])
def test_simulate_across_a_switch_of_a_driver_still_prescribed(tmp_path, method):
    # a cart pushed x = 0.3 sin 2T up to t = 0.5, then x = 0.3 sin 1 + 0.1 (T - 0.5) (its
    # speed jumps from 0.324 to 0.1), a pendulum hinged on it released. Its momentum about
    # the hinge, (J + m lc²) θ' + m lc cos θ x', is kept through the jump; simulate
    # integrated across the switch as if nothing happened and put the cart's speed right
    # by a least-norm projection that left θ' = -1.375 (it is -0.972 after the switch):
    # θ off by 0.09 rad at t = 0.8, no error
    from scipy.integrate import solve_ivp
    cart_m, mass, inertia, lc = 2.0, 0.8, 0.05, 0.4
    m = Model("audit_cart_stage")
    base = m.ground("base", points=[(0, 0), (1, 0)])
    cart = m.body("cart", points=[(0, 0), (1, 0)], guess=(0, 0, 0), mass=cart_m, inertia=0.1)
    pend = m.body("pend", points=[(0, 0), (0, -0.7)], guess=(0, 0, 0.4), mass=mass,
                  inertia=inertia, centroid=(0, -lc))
    m.translate(base.line(1, 2), cart.line(1, 2), name="rail")
    with m.stage("swing", until=0.5):
        m.relative_x(cart[1], 0.3 * sin(2 * T), name="push a")
    with m.stage("glide"):
        m.relative_x(cart[1], 0.3 * sin(1) + 0.1 * (T - 0.5), name="push b")
    m.revolute(cart[1], pend[1], name="hinge")
    m.rotation_lock(pend, cart, 0.4 + 0.5 * T, name="hold")
    m.gravity(G)
    mech = _compile(m, tmp_path)
    sw = mech.simulate(0.0, 1.0, 11, free=["hold"], method=method, rtol=1e-10, atol=1e-12)
    i0 = inertia + mass * lc ** 2

    def rhs(t, y):
        xdd = -1.2 * np.sin(2 * t) if t < 0.5 else 0.0
        return [y[1], (-mass * G * lc * np.sin(y[0]) - mass * lc * np.cos(y[0]) * xdd) / i0]
    a = solve_ivp(rhs, (0, 0.5), [0.4, 0.5], method="DOP853", rtol=1e-12, atol=1e-12,
                  t_eval=np.linspace(0, 0.5, 6))
    th, w = a.y[:, -1]
    w = w - mass * lc * np.cos(th) * (0.1 - 0.6 * np.cos(1.0)) / i0       # the impulse
    b = solve_ivp(rhs, (0.5, 1.0), [th, w], method="DOP853", rtol=1e-12, atol=1e-12,
                  t_eval=np.linspace(0.5, 1.0, 6))
    np.testing.assert_allclose(sw["Th3"], np.r_[a.y[0], b.y[0][1:]], atol=1e-7)
    np.testing.assert_allclose(sw["Th3d"], np.r_[a.y[1][:-1], b.y[1]], atol=1e-7)
    np.testing.assert_allclose(sw["X2d"][5:], 0.1, atol=1e-12)


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
