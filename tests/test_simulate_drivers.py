"""mech.simulate (API.md §6) with drivers freed and drivers still prescribed: tolerances a
user can get wrong, a start velocity given by name, a prescribed motion that reaches a
toggle while another driver is free, a prescribed driver that switches stage, redundant
meshes. Each reference is written here: a flywheel under a motor M = a − bω (closed form),
a slider-crank's kinematics (the crank angle from the law of cosines), a planetary set
(Willis), a cart-pendulum integrated by scipy with the switch's impulse."""
import math
import warnings

import numpy as np
import pytest

import mechgen
from mechgen import Model, T, cos, dt, rotation, sin

J, A_M, B_M, W0, TH0 = 0.4, 6.0, 0.5, 3.0, 0.2
G = 9.81


def flywheel():
    m = Model("audit_flywheel")
    base = m.ground("base", points=[(0, 0)])
    wh = m.body("wh", points=[(0, 0), (1, 0)], guess=(0, 0, 0.0), inertia=J)
    m.revolute(base[1], wh[0])
    w = m.param("w", W0)
    m.rotation_lock(wh, TH0 + w * T, name="drv")
    m.moment(wh, A_M - B_M * dt(rotation(wh)), name="motor")
    return m


def motor_speed(t, w0):
    """ω(t) of J ω̇ = a − b ω from ω(0) = w0."""
    wss = A_M / B_M
    return wss + (w0 - wss) * np.exp(-B_M * t / J)


def _compile(model, tmp_path):
    return mechgen.compile(model, outdir=str(tmp_path), tier="python")


@pytest.mark.parametrize("method", ["dopri5", "RK45"])
@pytest.mark.parametrize("bad", [dict(rtol=-1.0), dict(atol=-1e-3), dict(atol=0.0),
                                 dict(rtol=0.0), dict(rtol=float("nan")),
                                 dict(atol=float("inf")), dict(max_step=0.0),
                                 dict(max_step=-1.0)])
def test_a_tolerance_that_is_not_positive_is_refused_by_name(tmp_path, bad, method):
    """Before: the compiled integrator took rtol=-1 or atol=-1 and returned a motion wrong
    by 1e-2 without a word; atol=0 (a flywheel's X2, Y2 stay exactly 0, so the error
    scale is 0/0) stopped with "the integration stalled ... a load that switches on and
    off", rtol=nan with "a motion ... carries no mass" at t=nan, scipy's RK45 with
    "SVD did not converge"."""
    mech = _compile(flywheel(), tmp_path)
    name = next(iter(bad))
    with pytest.raises(ValueError, match=rf"simulate: {name} must be"):
        mech.simulate(0.0, 1.0, 3, free=["drv"], method=method, **bad)


def test_a_start_velocity_given_by_name_is_kept(tmp_path):
    """qd0={"Th2d": 5.0}, as q0 takes a dict: the wheel starts at 5 rad/s (the motor's
    closed form from there); the coordinates not named keep their kinematic rates at t0.
    Before: TypeError "float() argument must be a string or a real number, not 'dict'"."""
    mech = _compile(flywheel(), tmp_path)
    sw = mech.simulate(0.0, 2.0, 21, free=["drv"], qd0={"Th2d": 5.0}, rtol=1e-11,
                       atol=1e-13)
    assert sw["Th2d"][0] == 5.0
    assert np.abs(sw["Th2d"] - motor_speed(sw.t, 5.0)).max() < 1e-9
    sw = mech.simulate(0.0, 2.0, 21, free=["drv"], qd0={"Th2": 5.0}, rtol=1e-11,
                       atol=1e-13)                       # the coordinate's name says the same
    assert np.abs(sw["Th2d"] - motor_speed(sw.t, 5.0)).max() < 1e-9
    with pytest.raises(ValueError, match="qd0: 'Th9d' is not"):
        mech.simulate(0.0, 1.0, 3, free=["drv"], qd0={"Th9d": 1.0})


def test_a_named_crank_rate_is_kept_and_the_chain_follows(tmp_path):
    """The slider-crank of crank_and_pendulum with its crank's rate named (the slider's
    driver freed, the pendulum still held): the crank starts at exactly 3 rad/s, the rod
    and the slider at the rates the constraints give them (x = r cos θ + √(l² − r² sin² θ)
    differentiated), not a minimum-norm compromise that slows the crank."""
    mech = _compile(crank_and_pendulum(), tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")              # nothing the user named was moved
        sw = mech.simulate(0.0, 0.01, 2, free=["sdrv"], qd0={"Th2d": 3.0})
    th = sw["Th2"][0]
    assert sw["Th2d"][0] == 3.0
    xd = (-R_C * math.sin(th) - R_C ** 2 * math.sin(th) * math.cos(th)
          / math.sqrt(L_C ** 2 - (R_C * math.sin(th)) ** 2)) * 3.0
    assert abs(sw["X4d"][0] - xd) < 1e-9


R_C, L_C = 1.0, 2.0


def crank_and_pendulum():
    """A slider-crank whose slider is driven, x = 2.5 + 0.5 sin T, so that the crank
    reaches its dead centre (x = r + l) at T = π/2, with a pendulum hanging from the
    slider held by a second driver, "pdrv"."""
    m = Model("audit_toggle")
    base = m.ground("base", points=[(0, 0), (1, 0)])
    cr = m.body("cr", points=[(0, 0), (R_C, 0)], guess=(0, 0, 0.8), mass=1.0, inertia=0.1,
                centroid=(0.5, 0))
    rod = m.body("rod", points=[(0, 0), (L_C, 0)], guess=(0.7, 0.7, -0.35), mass=1.0,
                 inertia=0.3, centroid=(1, 0))
    sl = m.body("sl", points=[(0, 0), (1, 0)], guess=(2.5, 0, 0), mass=2.0, inertia=0.1)
    pe = m.body("pe", points=[(0, 0), (0.5, 0)], guess=(2.5, 0, -1.2), mass=0.5,
                inertia=0.0, centroid=(0.5, 0))
    m.revolute(base[1], cr[1])
    m.revolute(cr[2], rod[1])
    m.revolute(rod[2], sl[1])
    m.translate(base.line(1, 2), sl.line(1, 2))
    m.relative_x(sl[1], 2.5 + 0.5 * sin(T), name="sdrv")
    m.revolute(sl[1], pe[1])
    s = m.param("s", 0.0)
    m.rotation_lock(pe, -1.2 + s * T, name="pdrv")
    m.gravity(9.81)
    return m


@pytest.mark.parametrize("method", ["dopri5", "RK45"])
def test_a_prescribed_motion_through_a_toggle_is_not_bounced_silently(tmp_path, method):
    """With pdrv freed, the crank chain still moves as sdrv prescribes: its angle is
    the kinematics' (cos θ from x), passing the dead centre at π/2 with θ̇ = −1/√3, so θ
    keeps decreasing over [0, 3]; simulate must either follow that or stop with the
    SingularError API.md promises at a lock of the constraints still acting. Before: no
    error, θ bounced back at π/2 (θ̇ from −0.577 to +0.577, a 7e4 rad/s² spike 4.5e-6 rad
    from the dead centre, above the block solve's SING_RTOL), the sweep's numbers wrong
    by up to 2|θ| afterwards (free=[] on the same model, by the Schur complement, did
    raise)."""
    mech = _compile(crank_and_pendulum(), tmp_path)
    try:
        sw = mech.simulate(0.0, 3.0, 31, free=["pdrv"], method=method)
    except mechgen.SingularError as err:
        assert 1.56 < err.t < 1.58
        return
    assert sw["Th2d"].max() < 0.0
    x = 2.5 + 0.5 * np.sin(sw.t)
    theta = np.arccos((x ** 2 + R_C ** 2 - L_C ** 2) / (2 * R_C * x))
    theta = np.where(sw.t < math.pi / 2, theta, -theta)
    assert np.abs(sw["Th2"] - theta).max() < 1e-6


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


# -- a bead on a rod that turns at ω: its rows mix T and the coordinates (Φ_qt ≠ 0) --------
MB, KB, OMB = 0.7, 9.0, 1.3                  # the bead's mass, the spring, the rod's rate


def bead_on_rod():
    """A bead on a rod through the origin turning at θ = ωT (the rod is a row, not a body:
    −X sin ωT + Y cos ωT = 0), pushed along it to s = 0.5 + 0.2 sin 3T
    (X cos ωT + Y sin ωT − s(T) = 0), a spring of free length 0 to the origin, gravity.
    Freed, the push leaves s̈ = −(k/m − ω²) s − g sin ωt: with Ω² = k/m − ω²,
    s = s0 cos Ωt + (v0 − Aω)/Ω sin Ωt + A sin ωt, A = −g / (Ω² − ω²)."""
    m = Model("bead_on_rod")
    g = m.ground("g", points=[(0, 0)])
    b = m.body("bead", points=[(0, 0)], guess=(0.5, 0, 0), mass=MB, inertia=0.01)
    m.rotation_lock(b, OMB * T, name="spin")
    m.constraint(-b.x * sin(OMB * T) + b.y * cos(OMB * T), name="rod")
    m.constraint(b.x * cos(OMB * T) + b.y * sin(OMB * T) - (0.5 + 0.2 * sin(3 * T)),
                 name="push")
    m.spring(g[1], b[1], KB, 0, name="spring")
    m.gravity(G)
    return m


def bead_free(t, s0=0.5, v0=0.6):
    """(s, ṡ) of the freed bead from s0, v0 at t = 0."""
    big = math.sqrt(KB / MB - OMB ** 2)
    a = -G / (big ** 2 - OMB ** 2)
    c2 = (v0 - a * OMB) / big
    s = s0 * np.cos(big * t) + c2 * np.sin(big * t) + a * np.sin(OMB * t)
    sd = -s0 * big * np.sin(big * t) + c2 * big * np.cos(big * t) + a * OMB * np.cos(OMB * t)
    return s, sd


@pytest.mark.parametrize("method", ["dopri5", "RK45"])
def test_simulate_a_bead_on_a_turning_rod_against_its_closed_form(tmp_path, method):
    """The push freed: the bead's distance along the rod and its rate against bead_free
    (the rows' ∂Φ_q/∂T enter γ and the projection; a γ without them moves the bead)."""
    mech = _compile(bead_on_rod(), tmp_path)
    sw = mech.simulate(0.0, 3.0, 31, free=["push"], method=method, rtol=1e-11, atol=1e-12)
    s, sd = bead_free(sw.t)
    c, sn = np.cos(OMB * sw.t), np.sin(OMB * sw.t)
    np.testing.assert_allclose(sw["X2"] * c + sw["Y2"] * sn, s, atol=1e-7)
    np.testing.assert_allclose(-sw["X2"] * sn + sw["Y2"] * c, 0.0, atol=1e-10)
    np.testing.assert_allclose(sw["X2d"], sd * c - s * OMB * sn, atol=1e-7)
    np.testing.assert_allclose(sw["Y2d"], sd * sn + s * OMB * c, atol=1e-7)


@pytest.mark.parametrize("model", ["bead", "pendulum"])
def test_a_long_simulation_keeps_its_velocities_on_the_constraints(tmp_path, model):
    """At every output of a long run at loose tolerances, the velocities satisfy the rows
    still acting: Φ_q q̇ − ν, measured by central differences of Φ along (q̇, 1) (the
    module's Φ alone, not its Φ_q or ν), stays at round-off, as Φ does. The integrator
    drifts off by its tolerance between outputs; the projection puts it back."""
    if model == "bead":
        mech, free = _compile(bead_on_rod(), tmp_path), ["push"]
    else:
        mech, free = _compile(crank_and_pendulum(), tmp_path), ["pdrv"]
    sw = mech.simulate(0.0, 20.0 if model == "bead" else 1.4, 201, free=free, rtol=1e-5,
                       atol=1e-7)
    keep = [i for i, label in enumerate(mech.constraint_labels)
            if f" {free[0]}:" not in f" {label}"]

    def phi(q, t):
        out = np.empty(mech.m)
        mech.module.phi(q, t, mech.p, out)
        return out[keep]
    h = 1e-6
    for k in range(len(sw)):
        q, qd, t = sw.Q[k], sw.QD[k], float(sw.t[k])
        assert np.abs(phi(q, t)).max() < 1e-10
        rate = (phi(q + h * qd, t + h) - phi(q - h * qd, t - h)) / (2 * h)
        assert np.abs(rate).max() < 1e-7 * (1 + np.abs(qd).max()), (k, t)

