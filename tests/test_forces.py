"""Statics and inverse dynamics (issue 21, docs/reference/forces.md): every figure against a
computation written here, never mechgen's own equations: a closed-form slider-crank (its driver
torque by the power form, its pin forces by Newton–Euler body by body), a four-bar held still
against gravity and a spring (virtual work on the closed-form potential), a parallelogram with a
redundant crank."""
import math

import numpy as np
import pytest
import sympy as sp

import mechgen
import models
from mechgen import Model, ModelError, SingularError, T

G = 9.807
R, L = 0.2, 0.6                       # crank, rod
W, TH0 = 3.0, 0.3                     # crank speed, angle at t = 0
M2, J2, C2 = 1.5, 0.02, (0.08, 0.02)  # crank: mass, inertia, centroid (local)
M3, J3, C3 = 2.0, 0.07, (0.25, -0.03)
M4, J4, C4 = 3.0, 0.01, (0.05, 0.04)
PRESS = (-500.0, 120.0)               # on the slider's pin, global components


def _compile(model, tmp_path):
    return mechgen.compile(model, outdir=str(tmp_path), tier="python")


def slider_crank():
    """tests/models.py's slider-crank (crank R, rod L, θ = TH0 + wT) with masses, the
    slider's a parameter, under gravity and a press on the slider's pin."""
    m, base, crank, rod, slider = models.slider_crank(
        "sc_forces", R, L, 0.0, TH0, W, params={"omega": "w"}, ground=[(0, 0), (1, 0)],
        ground_name="base", guide=(1, 2), joints=("A", "B", "C", "guide"),
        masses={"crank": dict(mass=M2, inertia=J2, centroid=C2),
                "rod": dict(mass=M3, inertia=J3, centroid=C3),
                "slider": dict(mass=("mass4", M4), inertia=J4, centroid=C4)},
        drive="crank driver")
    m.gravity(G)
    m.force(slider[1], PRESS, name="press")
    return m


def _rot(th, c):
    cs, sn = np.cos(th), np.sin(th)
    return np.array([cs * c[0] - sn * c[1], sn * c[0] + cs * c[1]])


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _perp(v):
    return np.array([-v[1], v[0]])


def closed_form(t):
    """Slider-crank kinematics (θ̈ = 0) and, per body, (r_G, v_G, a_G, ω, α)."""
    th, thd = W * t + TH0, W
    phi = -np.arcsin(R * np.sin(th) / L)
    phid = -R * np.cos(th) * thd / (L * np.cos(phi))
    phidd = (R * np.sin(th) * thd ** 2 + L * np.sin(phi) * phid ** 2) / (L * np.cos(phi))
    x = R * np.cos(th) + L * np.cos(phi)
    xd = -R * np.sin(th) * thd - L * np.sin(phi) * phid
    xdd = -R * np.cos(th) * thd ** 2 - L * np.cos(phi) * phid ** 2 - L * np.sin(phi) * phidd
    B = R * np.array([np.cos(th), np.sin(th)])
    vB = R * thd * np.array([-np.sin(th), np.cos(th)])
    aB = -R * thd ** 2 * np.array([np.cos(th), np.sin(th)])
    C = np.array([x, 0.0])
    c2, c3 = _rot(th, C2), _rot(phi, C3)
    bodies = {
        "crank": (c2, thd * _perp(c2), -thd ** 2 * c2, thd, 0.0),
        "rod": (B + c3, vB + phid * _perp(c3), aB + phidd * _perp(c3) - phid ** 2 * c3,
                phid, phidd),
        "slider": (C + np.array(C4), np.array([xd, 0.0]), np.array([xdd, 0.0]), 0.0, 0.0),
    }
    return dict(th=th, thd=thd, B=B, C=C, vC=np.array([xd, 0.0]), bodies=bodies)


MASS = {"crank": (M2, J2), "rod": (M3, J3), "slider": (M4, J4)}


def power_torque(k):
    """T·θ̇ = Σ(m a_G·v_G + J α ω) − Σ F·v (gravity at the centroids, the press at C)."""
    total = 0.0
    for name, (rg, vg, ag, om, al) in k["bodies"].items():
        m, J = MASS[name]
        total += m * ag @ vg + J * al * om - m * np.array([0.0, -G]) @ vg
    total -= np.array(PRESS) @ k["vC"]
    return total / k["thd"]


def newton_euler(k):
    """Pin forces body by body: slider (x), rod (3×3), crank; each force is what the
    named pin applies to the first body of its name (F_C on the slider, F_B on the rod,
    F_A on the crank), N and the guide's moment about the slider's origin, and τ."""
    g = np.array([0.0, -G])
    P = np.array(PRESS)
    rg4, _, a4, _, _ = k["bodies"]["slider"]
    rg3, _, a3, _, al3 = k["bodies"]["rod"]
    rg2, _, a2, _, _ = k["bodies"]["crank"]
    B, C = k["B"], k["C"]
    fcx = M4 * a4[0] - P[0]
    dB, dC = B - rg3, C - rg3
    A = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, -1.0], [-dB[1], dB[0], -dC[0]]])
    rhs = np.array([M3 * a3[0] + fcx, M3 * a3[1] - M3 * g[1], J3 * al3 - dC[1] * fcx])
    fbx, fby, fcy = np.linalg.solve(A, rhs)
    FB, FC = np.array([fbx, fby]), np.array([fcx, fcy])
    FA = M2 * a2 + FB - M2 * g
    tau = -_cross(-rg2, FA) + _cross(B - rg2, FB)
    N = M4 * a4[1] - FC[1] - P[1] - M4 * g[1]
    c4 = rg4 - C
    guide_moment = M4 * _cross(c4, a4) - _cross(c4, M4 * g)
    return dict(FA=FA, FB=FB, FC=FC, N=N, guide=guide_moment, tau=tau)


@pytest.fixture(scope="module")
def sc(tmp_path_factory):
    return _compile(slider_crank(), tmp_path_factory.mktemp("sc"))


def _close(actual, expected, scale):
    np.testing.assert_allclose(actual, expected, rtol=1e-9, atol=1e-9 * scale)


def test_slider_crank_driver_torque_power_form(sc):
    n = 1000
    period = 2 * math.pi / W
    sw = sc.sweep(0.0, period, n, level="dynamic")
    tau = sw.driver("crank driver")
    expected = np.array([power_torque(closed_form(t)) for t in sw.t])
    scale = np.abs(expected).max()
    assert scale > 50                  # the loads matter
    _close(tau, expected, scale)
    # the driver's power input is its torque times the crank's rate
    _close(sw.power()["drivers"], expected * W, scale * W)
    # the kinetic energy against the closed form
    ke = [sum(0.5 * MASS[b][0] * v @ v + 0.5 * MASS[b][1] * om ** 2
              for b, (_, v, _, om, _) in closed_form(t)["bodies"].items()) for t in sw.t]
    _close(sw.energy()["kinetic"], ke, max(ke))


def test_slider_crank_pin_forces_newton_euler(sc):
    for t in np.linspace(0.0, 2 * math.pi / W, 13):
        s = sc.solve(t, level="dynamic", guess=sc.last if sc.last is not None else None)
        ne = newton_euler(closed_form(t))
        scale = 600.0
        _close(s.driver("crank driver"), ne["tau"], scale)
        _close(s.reaction("C", on="slider"), [*ne["FC"], 0.0], scale)
        _close(s.reaction("C", on="rod", about=closed_form(t)["C"]),
               [*-ne["FC"], 0.0], scale)
        _close(s.reaction("B", on="rod"), [*ne["FB"], 0.0], scale)
        _close(s.reaction("B", on="crank", about="crank[2]"), [*-ne["FB"], 0.0], scale)
        crank = sc.model["crank"]
        _close(s.reaction("B", on=crank, about=crank[2]), [*-ne["FB"], 0.0], scale)
        B = closed_form(t)["B"]
        _close(s.reaction("B", on="crank"), [*-ne["FB"], _cross(B, -ne["FB"])], scale)
        _close(s.reaction("A", on="crank"), [*ne["FA"], 0.0], scale)
        _close(s.reaction("A", on="base"), [*-ne["FA"], 0.0], scale)
        _close(s.reaction("guide", on="slider"), [0.0, ne["N"], ne["guide"]], scale)
        assert s.indeterminate == ()
        assert set(s.multipliers) == set(sc.constraint_labels)


def test_slider_crank_shaking_and_power_balance(sc):
    sw = sc.sweep(0.0, 2 * math.pi / W, 181, level="dynamic")
    power = sw.power()
    assert np.abs(power["residual"]).max() <= 1e-9 * np.abs(power["drivers"]).max()
    _close(power["loads"], [np.array(PRESS) @ closed_form(t)["vC"] for t in sw.t], 500.0)
    # what the moving parts apply to the frame: external loads minus Σ m a_G (force), and
    # their moments about the origin minus Σ (r_G × m a_G + J α)
    expected = []
    for t in sw.t:
        k = closed_form(t)
        f = np.array(PRESS).copy()
        mo = _cross(k["C"], np.array(PRESS))
        for b, (rg, _, ag, _, al) in k["bodies"].items():
            m, J = MASS[b]
            f += m * np.array([0.0, -G]) - m * ag
            mo += _cross(rg, m * np.array([0.0, -G])) - _cross(rg, m * ag) - J * al
        expected.append([f[0], f[1], mo])
    _close(sw.shaking(), np.array(expected), 600.0)
    # the potential energy's rate against finite differences of the sweep's potential
    V = sw.energy()["potential"]
    dt = sw.t[1] - sw.t[0]
    fd = (V[2:] - V[:-2]) / (2 * dt)
    np.testing.assert_allclose(power["potential"][1:-1], fd, atol=2e-3 * np.abs(fd).max())


def test_static_slider_crank_holds_the_press(sc):
    """At rest the torque balances gravity and the press alone: τ = −Σ F·∂r/∂θ."""
    for t in (0.1, 0.7, 1.3):
        s = sc.solve(t, level="static")
        k = closed_form(t)
        tau = 0.0
        for name, (rg, vg, _, _, _) in k["bodies"].items():
            tau -= MASS[name][0] * np.array([0.0, -G]) @ vg / k["thd"]
        tau -= np.array(PRESS) @ k["vC"] / k["thd"]
        _close(s.driver("crank driver"), tau, 100.0)


# -- a four-bar held still against gravity and a spring ---------------------------------
A4, B4, C4R, D4 = 0.3, 0.7, 0.5, 0.8
S_GROUND, S_LOCAL, K, L0 = (0.2, 0.6), (0.35, 0.1), 800.0, 0.3
FB_MASS = {"crank": (0.7, 0.004, (0.12, 0.01)), "coupler": (1.1, 0.05, (0.3, 0.05)),
           "rocker": (0.9, 0.02, (0.2, -0.02))}


def four_bar():
    m = Model("fourbar_static")
    base = m.ground("base", points=[(0, 0), (D4, 0), S_GROUND])
    th0 = m.param("th0", 1.0)
    w = m.param("w", 1.0)
    bodies = {}
    for name, length, guess in (("crank", A4, (0, 0, 1.0)), ("coupler", B4, (0.16, 0.25, 0.3)),
                                ("rocker", C4R, (D4, 0, 1.6))):
        mass, J, c = FB_MASS[name]
        bodies[name] = m.body(name, points=[(0, 0), (length, 0)], guess=guess, mass=mass,
                              inertia=J, centroid=c)
    crank, coupler, rocker = bodies["crank"], bodies["coupler"], bodies["rocker"]
    m.revolute(base[1], crank[1], name="O2")
    m.revolute(crank[2], coupler[1], name="A")
    m.revolute(coupler[2], rocker[2], name="B")
    m.revolute(base[2], rocker[1], name="O4")
    m.rotation_lock(crank, th0 + w * T, name="hold")
    m.gravity(G)
    m.spring(base[3], coupler.at(*S_LOCAL), K, L0, name="return spring")
    return m


def four_bar_potential(th, upper=True):
    """V(θ): gravity on the centroids and the spring's energy, from the closed-form
    position (the coupler–rocker pin by intersecting two circles)."""
    A = A4 * np.array([math.cos(th), math.sin(th)])
    O4 = np.array([D4, 0.0])
    d = O4 - A
    dist = math.hypot(*d)
    along = (B4 ** 2 - C4R ** 2 + dist ** 2) / (2 * dist)
    h = math.sqrt(B4 ** 2 - along ** 2)
    u = d / dist
    Bp = A + along * u + (h if upper else -h) * np.array([-u[1], u[0]])
    beta = math.atan2(*(Bp - A)[::-1])
    gamma = math.atan2(*(Bp - O4)[::-1])
    frames = {"crank": (np.zeros(2), th), "coupler": (A, beta), "rocker": (O4, gamma)}
    V = 0.0
    for name, (origin, ang) in frames.items():
        mass, _, c = FB_MASS[name]
        V += mass * G * (origin + _rot(ang, c))[1]
    S = A + _rot(beta, S_LOCAL)
    ext = math.hypot(*(S - np.array(S_GROUND))) - L0
    return V + 0.5 * K * ext ** 2


@pytest.fixture(scope="module")
def fb(tmp_path_factory):
    return _compile(four_bar(), tmp_path_factory.mktemp("fb"))


def test_four_bar_static_virtual_work(fb):
    h = 1e-3
    for th in (0.6, 1.0, 1.4, 2.0):
        mech = fb.with_params(th0=th)
        s = mech.solve(0.0, level="static")
        assert abs(s["Th2"] - th) < 1e-12
        upper = s["Y4"] + C4R * math.sin(s["Th4"]) > 0      # the branch it holds
        V = [four_bar_potential(th + j * h, upper) for j in (-2, -1, 1, 2)]
        dV = (V[0] - 8 * V[1] + 8 * V[2] - V[3]) / (12 * h)
        assert abs(dV) > 1.0
        np.testing.assert_allclose(s.driver("hold"), dV, rtol=1e-9)


# -- no mass, no loads; bad input -------------------------------------------------------
def test_no_mass_no_loads_gives_zeros(tmp_path):
    m = Model("fourbar_bare")
    base = m.ground("base", points=[(0, 0), (D4, 0)])
    crank = m.body("crank", points=[(0, 0), (A4, 0)], guess=(0, 0, 1.0))
    coupler = m.body("coupler", points=[(0, 0), (B4, 0)], guess=(0.16, 0.25, 0.3))
    rocker = m.body("rocker", points=[(0, 0), (C4R, 0)], guess=(D4, 0, 1.6))
    m.revolute(base[1], crank[1])
    m.revolute(crank[2], coupler[1])
    m.revolute(coupler[2], rocker[2])
    m.revolute(base[2], rocker[1])
    m.rotation_lock(crank, 1.0 + T, name="drive")
    mech = _compile(m, tmp_path)
    assert not hasattr(mech.module, "force_terms")    # the module is the kinematic one
    s = mech.solve(0.2, level="dynamic")
    assert all(v == 0.0 for v in s.multipliers.values())
    assert s.driver("drive") == 0.0
    assert np.all(s.reaction(2, on="coupler") == 0.0)
    sw = mech.sweep(0, 1, 5, level="static")
    assert np.all(sw.driver("drive") == 0.0) and np.all(sw.shaking() == 0.0)
    assert all(np.all(v == 0.0) for v in sw.power().values())


def test_negative_mass_names_the_body():
    m = Model("bad_mass")
    m.ground("base")
    with pytest.raises(ModelError, match="body 'lever': mass"):
        m.body("lever", points=[(1, 0)], mass=-1.0)
    k = m.param("k", -2.0)
    with pytest.raises(ModelError, match="body 'arm': inertia"):
        m.body("arm", points=[(1, 0)], mass=1.0, inertia=k)
    assert "lever" not in m.bodies and "arm" not in m.bodies
    b = m.body("ok", points=[(1, 0)])
    with pytest.raises(ModelError, match="accelerations"):
        m.force(b[1], (sp.Symbol("X2dd", real=True), 0))


def test_unknown_names_are_clear(sc):
    s = sc.solve(0.1, level="dynamic")
    with pytest.raises(ValueError, match="no constraint 'D'"):
        s.reaction("D", on="rod")
    with pytest.raises(ValueError, match="no body 'wheel'"):
        s.reaction("B", on="wheel")
    with pytest.raises(ValueError, match="not a driver"):
        s.driver("B")


# -- redundant constraints: the parallelogram with a third crank -------------------------
def parallelogram(third):
    m = Model("parallelogram3" if third else "parallelogram2")
    base = m.ground("base", points=[(0, 0), (1, 0), (0.5, 0)])
    c2 = m.body("c2", points=[(0, 0), (0.3, 0)], guess=(0, 0, 0.7))
    cp = m.body("coupler", points=[(0, 0), (1, 0), (0.5, 0)], guess=(0.23, 0.19, 0.0),
                mass=2.0, inertia=0.2, centroid=(0.4, 0.05))
    c4 = m.body("c4", points=[(0, 0), (0.3, 0)], guess=(1, 0, 0.7), mass=0.5, inertia=0.01,
                centroid=(0.15, 0))
    m.revolute(base[1], c2[1], name="O2")
    m.revolute(c2[2], cp[1], name="A")
    m.revolute(cp[2], c4[2], name="B")
    m.revolute(base[2], c4[1], name="O4")
    if third:
        c6 = m.body("c6", points=[(0, 0), (0.3, 0)], guess=(0.5, 0, 0.7))
        m.revolute(base[3], c6[1], name="O6")
        m.revolute(cp[3], c6[2], name="M")
    m.rotation_lock(c2, 0.7 + 2.0 * T, name="drive")
    m.gravity(G)
    return m


def test_redundant_crank_indeterminate_but_driver_exact(tmp_path):
    two = _compile(parallelogram(False), tmp_path / "two")
    with pytest.warns(mechgen.RedundancyWarning):
        three = _compile(parallelogram(True), tmp_path / "three")
        s3 = three.solve(0.3, level="dynamic")
    s2 = two.solve(0.3, level="dynamic")
    assert s2.indeterminate == ()
    assert s3.indeterminate and all(x.split(":")[0] in {"O2", "A", "B", "O4", "O6", "M"}
                                    for x in s3.indeterminate)
    assert not any(x.startswith("drive") for x in s3.indeterminate)
    np.testing.assert_allclose(s3.driver("drive"), s2.driver("drive"), rtol=1e-9)
    # the minimum-norm multipliers still balance every body
    J = three.jacobian(s3.q, s3.t)
    lam = np.array(list(s3.multipliers.values()))
    np.testing.assert_allclose(J.T @ lam, s3.terms[0] + s3.terms[1] - s3.terms[2],
                               atol=1e-9 * np.abs(lam).max())


def test_lock_with_a_load_is_singular(tmp_path):
    """A slider-crank driven by its slider at the dead centre: no crank torque balances a
    moment on the crank there."""
    m = Model("dead_centre")
    base = m.ground("base", points=[(0, 0), (1, 0)])
    crank = m.body("crank", points=[(0, 0), (R, 0)], guess=(0, 0, 0.01))
    rod = m.body("rod", points=[(0, 0), (L, 0)], guess=(R, 0, 0.0))
    slider = m.body("slider", points=[(0, 0), (1, 0)], guess=(R + L, 0, 0))
    m.revolute(base[1], crank[1])
    m.revolute(crank[2], rod[1])
    m.revolute(rod[2], slider[1])
    m.translate(base.line(1, 2), slider.line(1, 2))
    m.relative_x(slider[1], R + L - T, name="push")
    m.moment(crank, 3.0)
    mech = _compile(m, tmp_path)
    with pytest.raises(SingularError):
        mech.solve(0.0, level="static")
    th = 0.63                                  # off the dead centre: a finite force
    s = mech.solve(0.05, level="static", guess={"Th2": th, "X3": R * math.cos(th),
                                                "Y3": R * math.sin(th), "Th3": -0.2})
    assert math.isfinite(s.driver("push"))


def test_changed_mass_rebuilds(tmp_path, monkeypatch):
    """The build fingerprint covers masses and loads: a changed mass is a new module."""
    first = mechgen.compile(slider_crank(), outdir=str(tmp_path), tier="python")
    tau1 = first.solve(0.4, level="dynamic").driver("crank driver")
    m = slider_crank()
    m.bodies["rod"].mass = sp.Float(2.5)
    second = mechgen.compile(m, outdir=str(tmp_path), tier="python")
    tau2 = second.solve(0.4, level="dynamic").driver("crank driver")
    monkeypatch.setitem(MASS, "rod", (2.5, J3))
    expected = power_torque(closed_form(0.4))
    assert abs(tau2 - tau1) > 1e-3
    np.testing.assert_allclose(tau2, expected, rtol=1e-9)


def test_flywheel_of_the_slider_crank(sc):
    """ΔE = the largest swing of ∫(T − T̄) dθ over a turn (trapezoids on the closed-form
    torque), inertia ΔE / (cs ω²)."""
    n = 721
    sw = sc.sweep(0.0, 2 * math.pi / W, n, level="dynamic")
    th = np.linspace(0.0, 2 * math.pi, n)
    torque = np.array([power_torque(closed_form(x / W)) for x in th])
    work = np.concatenate([[0.0], np.cumsum(np.diff(th) * (torque[1:] + torque[:-1]) / 2)])
    swing = work - work[-1] * th / th[-1]
    energy = swing.max() - swing.min()
    fw = sw.flywheel(0.05)
    assert energy > 1.0
    np.testing.assert_allclose(fw["energy"], energy, rtol=1e-9)
    np.testing.assert_allclose(fw["inertia"], energy / (0.05 * W ** 2), rtol=1e-9)
    with pytest.raises(ValueError, match="positive"):
        sw.flywheel(0.0)


def test_flywheel_over_a_period_that_does_not_start_at_zero(tmp_path):
    """A turn from t0 = 0.37 of the slider-crank working against a moment of 4 on its
    crank (a mean power of 4 W, where the press and gravity give none): ΔE, the inertia
    and the mean power against trapezoids on the closed-form torque over that turn, the
    mean taken over the turn's own length (a mean power of work / t1, or a mean rate of
    ∫ω dt / t1, passes every sweep from 0)."""
    m = slider_crank()
    m.moment(m.bodies["crank"], -4.0, name="resist")
    mech = _compile(m, tmp_path)
    n, t0 = 721, 0.37
    period = 2 * math.pi / W
    sw = mech.sweep(t0, t0 + period, n, level="dynamic")
    ts = np.linspace(t0, t0 + period, n)
    torque = np.array([power_torque(closed_form(x)) + 4.0 for x in ts])
    power = torque * W
    work = np.concatenate([[0.0], np.cumsum(np.diff(ts) * (power[1:] + power[:-1]) / 2)])
    mean = work[-1] / period
    swing = work - mean * (ts - t0)
    energy = swing.max() - swing.min()
    fw = sw.flywheel(0.05)
    assert energy > 1.0 and abs(mean) > 1.0
    np.testing.assert_allclose(fw["mean_power"], mean, rtol=1e-9)
    np.testing.assert_allclose(fw["energy"], energy, rtol=1e-9)
    np.testing.assert_allclose(fw["inertia"], energy / (0.05 * W ** 2), rtol=1e-9)


def test_redundant_sweep_takes_the_svd_path(tmp_path):
    two = _compile(parallelogram(False), tmp_path / "two")
    with pytest.warns(mechgen.RedundancyWarning):
        three = _compile(parallelogram(True), tmp_path / "three")
        sw3 = three.sweep(0.0, 1.0, 21, level="dynamic")
    sw2 = two.sweep(0.0, 1.0, 21, level="dynamic")
    np.testing.assert_allclose(sw3.driver("drive"), sw2.driver("drive"), rtol=1e-9)
    assert sw3.indeterminate and sw2.indeterminate == ()
    # the shaking force is the same: the third crank is massless
    np.testing.assert_allclose(sw3.shaking()[:, :2], sw2.shaking()[:, :2], rtol=1e-9,
                               atol=1e-9 * np.abs(sw2.shaking()).max())


def test_static_sweep_flags_the_dead_centre(tmp_path):
    """Through a dead centre under load: NaN and a flag at that point, the power balance
    of the others (τ ẋ + M θ̇ = 0) exact."""
    m = Model("dead_centre_sweep")
    base = m.ground("base", points=[(0, 0), (1, 0)])
    crank = m.body("crank", points=[(0, 0), (R, 0)], guess=(0, 0, 0.01))
    rod = m.body("rod", points=[(0, 0), (L, 0)], guess=(R, 0, 0.0))
    slider = m.body("slider", points=[(0, 0), (1, 0)], guess=(R + L, 0, 0))
    m.revolute(base[1], crank[1])
    m.revolute(crank[2], rod[1])
    m.revolute(rod[2], slider[1])
    m.translate(base.line(1, 2), slider.line(1, 2))
    m.relative_x(slider[1], R + L - T, name="push")
    m.moment(crank, 3.0)
    mech = _compile(m, tmp_path)
    with pytest.warns(UserWarning) as rec:
        sw = mech.sweep(0.0, 0.1, 11, level="static")
    said = " ".join(str(w.message) for w in rec)
    assert "no force balance" in said and "could not keep" not in said
    # leaving the dead centre is marked as such (tests/test_robustness.py), not as a jump
    assert len(sw.jumps) == 0 and list(sw.crossings) == [sw.t[1]]
    assert sw.force_singular[0] and not sw.force_singular[1:].any()
    force = sw.driver("push")
    assert np.isnan(force[0]) and np.all(np.isfinite(force[1:]))
    # closed form: x = R cos θ + sqrt(L² − R² sin² θ) = R + L − t; the push's rate is
    # d(R + L − x)/dt... its driven quantity is x, so F ẋ + 3 θ̇ = 0, F = −3 dθ/dx
    for t, f in zip(sw.t[1:], force[1:]):
        x = R + L - t
        th = math.acos((x ** 2 + R ** 2 - L ** 2) / (2 * x * R))
        dx_dth = -R * math.sin(th) - R ** 2 * math.sin(th) * math.cos(th) / math.sqrt(
            L ** 2 - R ** 2 * math.sin(th) ** 2)
        np.testing.assert_allclose(f, -3.0 / dx_dth, rtol=1e-9)


def inertia_and_weight_power(sw, bodies):
    """Σ(m a_G·v_G + J α ω) + Σ m g v_Gy at every point of a sweep, v_G and a_G written
    here from its coordinates and their derivatives; bodies: {number: (m, J, centroid)}."""
    out = np.zeros(len(sw))
    for b, (mass, J, c) in bodies.items():
        th, om, al = sw[f"Th{b}"], sw[f"Th{b}d"], sw[f"Th{b}dd"]
        rc = np.array([np.cos(th) * c[0] - np.sin(th) * c[1],
                       np.sin(th) * c[0] + np.cos(th) * c[1]])
        v = np.array([sw[f"X{b}d"], sw[f"Y{b}d"]]) + om * np.array([-rc[1], rc[0]])
        a = np.array([sw[f"X{b}dd"], sw[f"Y{b}dd"]]) + al * np.array([-rc[1], rc[0]]) \
            - om ** 2 * rc
        out += mass * np.sum(a * v, axis=0) + J * al * om + mass * G * v[1]
    return out


def test_quick_return_power_balance_and_torque(tmp_path):
    """examples/quick_return_forces.py over a full turn at 1,000 points: its power balance
    closes to 1e-9 of the input power, and the crank torque is the power form
    Σ(m a_G·v_G + J α ω) − Σ F·v over θ̇, with v_G, a_G written here from the sweep's
    coordinates and their derivatives."""
    import os
    mech = mechgen.compile(os.path.join(os.path.dirname(os.path.dirname(__file__)),
                                        "examples", "quick_return_forces.py"),
                           outdir=str(tmp_path), tier="python")
    sw = mech.sweep(0.0, 1.0, 1000, level="dynamic")
    power = sw.power()
    assert np.abs(power["residual"]).max() <= 1e-9 * np.abs(power["drivers"]).max()
    bodies = {2: (2.0, 1.5, (1.5, 0.0)), 3: (5.0, 33.75, (0.0, 4.5)), 4: (3.0, 1.0, (1.0, 0.2))}
    expected = inertia_and_weight_power(sw, bodies)
    cut = np.where(sw["X4d"] < 0, 500.0, 0.0)           # the slow (cutting) stroke
    expected -= cut * sw["X4d"]
    expected /= 2 * math.pi
    np.testing.assert_allclose(sw.driver("crank driver"), expected, rtol=1e-9,
                               atol=1e-9 * np.abs(expected).max())


def test_every_load_kind_by_the_power_form(tmp_path):
    """A massless crank at constant speed under a spring, a damper, a moment, a moment
    pair with the ground, a force along a fixed axis and a drag on its tip (a load read
    from velocity(p)): τ ω = −Σ P_loads, each P written here from the closed form."""
    from mechgen import velocity
    r, w, th0, c, k, l0, mo, f, b = 0.3, 2.0, 0.4, 3.0, 400.0, 0.4, 1.7, 25.0, 0.8
    S, U = np.array([0.5, 0.4]), np.array([1.0, 2.0]) / math.sqrt(5.0)
    m = Model("loads_kinds")
    base = m.ground("base", points=[(0, 0), tuple(S), (1.0, 2.0)])
    crank = m.body("crank", points=[(0, 0), (r, 0)], guess=(0, 0, th0))
    m.revolute(base[1], crank[1], name="O")
    m.rotation_lock(crank, w * T + th0, name="motor")
    m.spring(base[2], crank[2], k, l0, name="spring")
    m.damper(base[2], crank[2], c)
    m.moment(crank, mo)
    m.moment(crank, base, 0.5 * mo, name="pair")
    m.force(crank[2], f, along=base.line(1, 3), name="push")
    v = velocity(crank[2])
    m.force(crank[2], (-b * v[0], -b * v[1]), name="drag")
    mech = _compile(m, tmp_path)
    sw = mech.sweep(0.0, 3.0, 50, level="dynamic")
    expected = []
    for t in sw.t:
        th = w * t + th0
        P = r * np.array([math.cos(th), math.sin(th)])
        vP = r * w * np.array([-math.sin(th), math.cos(th)])
        L = np.linalg.norm(P - S)
        Ld = (P - S) @ vP / L
        loads = (-k * (L - l0) * Ld - c * Ld ** 2 + mo * w + 0.5 * mo * w + f * U @ vP
                 - b * vP @ vP)
        expected.append(-loads / w)
    np.testing.assert_allclose(sw.driver("motor"), expected, rtol=1e-9)
    power = sw.power()
    assert np.abs(power["residual"]).max() <= 1e-9 * np.abs(power["drivers"]).max()


def test_moment_pair_between_moving_bodies(tmp_path):
    """+M on the rod, −M on the crank: its power M (φ̇ − θ̇) joins the power form."""
    m = slider_crank()
    m.moment(m["rod"], m["crank"], 4.0, name="elbow motor")
    mech = _compile(m, tmp_path)
    for t in (0.1, 0.9, 1.7):
        s = mech.solve(t, level="dynamic", guess=mech.last)
        k = closed_form(t)
        phid = k["bodies"]["rod"][3]
        expected = power_torque(k) - 4.0 * (phid - k["thd"]) / k["thd"]
        np.testing.assert_allclose(s.driver("crank driver"), expected, rtol=1e-9)


def test_distance_driver_effort_is_the_actuator_force(tmp_path):
    """A lever raised by a linear actuator of length d(T) (relative_distance) against a
    moment M: the effort F satisfies F ḋ + M ω = 0 (the power form), F = −M d / ((B − A)
    · ∂B/∂θ)."""
    r, M = 0.5, 12.0
    A = np.array([0.6, -0.2])
    m = Model("actuator")
    base = m.ground("base", points=[(0, 0), tuple(A)])
    lever = m.body("lever", points=[(0, 0), (r, 0)], guess=(0, 0, 0.5))
    m.revolute(base[1], lever[1], name="O")
    m.relative_distance(base[2], lever[2], 0.45 + 0.1 * T, name="actuator")
    m.moment(lever, M)
    mech = _compile(m, tmp_path)
    for t in (0.0, 0.5, 1.0):
        s = mech.solve(t, level="static")
        th = s["Th2"]
        B = r * np.array([math.cos(th), math.sin(th)])
        d = np.linalg.norm(B - A)
        assert abs(d - (0.45 + 0.1 * t)) < 1e-9
        dB = r * np.array([-math.sin(th), math.cos(th)])
        np.testing.assert_allclose(s.driver("actuator"), -M * d / ((B - A) @ dB), rtol=1e-9)


def test_compiled_tier_gives_the_python_tier_s_forces():
    """The committed module of examples/quick_return_forces.py under numba: the same
    multipliers as the plain-Python tier (force_terms, energies, force_rows compiled; in
    place, so that numba's cache of it is the one the suite's other users of the module
    share rather than a copy's compiled again)."""
    import os
    path = os.path.join(os.path.dirname(os.path.dirname(__file__)), "generated",
                        "quick_return_forces.py")
    fast = mechgen.load(path, tier="compiled")
    slow = mechgen.load(path, tier="python")
    a = fast.sweep(0.0, 1.0, 101, level="dynamic")
    b = slow.sweep(0.0, 1.0, 101, level="dynamic")
    scale = np.abs(b.LAM).max()
    np.testing.assert_allclose(a.LAM, b.LAM, rtol=1e-12, atol=1e-12 * scale)
    np.testing.assert_allclose(a.energy()["total"], b.energy()["total"], rtol=1e-12)
    s, t = fast.solve(0.37, level="static"), slow.solve(0.37, level="static")
    np.testing.assert_allclose(s.driver("crank driver"), t.driver("crank driver"), rtol=1e-12)


def test_stages_driver_effort_on_both_sides_of_the_switch(tmp_path):
    """The staged quick-return (the crank turns back at t = 0.5) with a heavy lever: the
    stage driver's torque by the power form on each side of the switch, where the sweep
    holds both sides' velocities."""
    import os
    source = open(os.path.join(os.path.dirname(os.path.dirname(__file__)), "examples",
                               "quick_return_stages.py")).read()
    source = source.replace('guess=(0, 0, -0.5))', 'guess=(0, 0, -0.5), mass=5.0, '
                            'inertia=33.75, centroid=(0, 4.5))') + "\nm.gravity(9.807)\n"
    path = tmp_path / "qrs_forces.py"
    path.write_text(source.replace('Model("quick_return_stages")', 'Model("qrs_forces")'))
    mech = mechgen.compile(str(path), outdir=str(tmp_path / "gen"), tier="python")
    sw = mech.sweep(0.0, 1.0, 21, level="dynamic")
    assert np.sum(sw.t == 0.5) == 2
    expected = inertia_and_weight_power(sw, {3: (5.0, 33.75, (0.0, 4.5))}) / sw["Th2d"]
    for name in ("crank forward", "crank back"):
        np.testing.assert_allclose(sw.driver(name), expected, rtol=1e-9,
                                   atol=1e-9 * np.abs(expected).max())
    power = sw.power()
    assert np.abs(power["residual"]).max() <= 1e-9 * np.abs(power["drivers"]).max()


def test_static_sweep_power_is_zero(sc):
    """At rest nothing moves: every power of a static sweep is zero, and a flywheel
    needs a dynamic sweep."""
    sw = sc.sweep(0.0, 1.0, 5, level="static")
    assert all(np.all(v == 0.0) for v in sw.power().values())
    assert np.all(np.isfinite(sw.driver("crank driver")))
    with pytest.raises(ValueError, match="dynamic"):
        sw.flywheel(0.05)


def test_written_out_multipliers_equal_a_dense_solve():
    """multipliers_point (the blocks written out: one division, or Cramer's rule on two
    rows) against numpy's dense solve of Φ_qᵀ λ = Q_a + Q_c − I over a turn of the
    quick-return with masses and a cutting force, and against multipliers_sorted (the
    elimination it replaces in the sweep)."""
    import os
    from conftest import ROOT
    mech = mechgen.load(os.path.join(ROOT, "generated", "quick_return_forces.py"))
    mod = mech.module
    assert mod.FORCE_POINT
    sw = mech.sweep(0.0, 1.0, 97, level="acceleration")
    n, m = mech.n, mech.m
    worst = 0.0
    for k in range(len(sw)):
        q, qd, qdd, t = sw.Q[k], sw.QD[k], sw.QDD[k], float(sw.t[k])
        J, terms, lam = np.empty((m, n)), np.empty((3, n)), np.empty(m)
        mod.phi_q(q, t, mech.p, J)
        mod.force_terms(q, qd, qdd, t, mech.p, terms)
        rhs = terms[0] + terms[1] - terms[2]
        assert mod.multipliers_point(q, qd, qdd, t, mech.p, lam) >= 1e-3
        want = np.linalg.solve(J.T, rhs)
        worst = max(worst, np.abs(lam - want).max() / np.abs(want).max())
        other = np.empty(m)
        mod.multipliers_sorted(J, rhs, other, np.empty((n, n)), np.empty(n), np.empty(n))
        np.testing.assert_allclose(lam, other, rtol=1e-11, atol=1e-11 * np.abs(other).max())
    assert worst < 1e-12


def test_the_quick_return_s_torque_is_the_power_balance_of_its_closed_form():
    """The committed quick-return with masses, gravity and a cutting force on the return
    stroke: the crank torque of a dynamic sweep (the module's fused path) and of single
    solves against τ θ̇ = d/dt E − P_cut on the closed form (tests/closed_forms.
    quick_return_torque, mpmath), no function of the module in the reference (the dense
    solve above checks the written-out λ against the module's own Φ_q and force terms)."""
    import os
    from closed_forms import quick_return_torque
    from conftest import ROOT
    mech = mechgen.load(os.path.join(ROOT, "generated", "quick_return_forces.py"),
                        tier="python")
    bodies = {"manivela": (2.0, 1.5, (1.5, 0)), "colisa": (5.0, 33.75, (0, 4.5)),
              "deslizadera": (3.0, 1.0, (1, 0.2))}
    sw = mech.sweep(0.0, 1.0, 41, level="dynamic")
    for k in range(0, 41, 5):
        t = float(sw.t[k])
        want = quick_return_torque(t, bodies, cut=500.0)
        assert abs(sw.driver("crank driver")[k] - want) < 1e-8 * (1 + abs(want)), t
        got = mech.solve(t, level="dynamic").driver("crank driver")
        assert abs(got - want) < 1e-8 * (1 + abs(want)), t


def test_forces_across_a_stage_switch(tmp_path):
    """A quick-return whose crank turns forward (2πT) up to T = 0.5 and back (2π(1 − T))
    after it: at T and 1 − T the configuration is the same and the crank's speed reversed
    at zero angular acceleration, so the torque (quadratic in the speed, plus gravity) is
    the same, while the power (torque × rate) changes sign; the switch is held twice, and
    the power balance closes on both sides of it."""
    m = Model("qr_stage_forces")
    base = m.ground("base", points=[(0, 0), (0, 5), (-5, 10), (12, 10)])
    man = m.body("crank", points=[(0, 0), (3, 0)], guess=(0, 5, 0), mass=2.0, inertia=0.5,
                 centroid=(1.5, 0))
    col = m.body("rocker", points=[(0, 0), (0, 9)], guess=(0, 0, -0.5), mass=4.0,
                 inertia=3.0, centroid=(0, 4.5))
    des = m.body("slider", points=[(0, 0), (2, 0)], guess=(6, 10, 0), mass=3.0, inertia=0.2)
    m.revolute(base[2], man[1])
    with m.stage("forward", until=0.5):
        m.rotation_lock(man, base, 2 * math.pi * T, name="crank forward")
    with m.stage("back"):
        m.rotation_lock(man, base, 2 * math.pi * (1 - T), name="crank back")
    m.revolute(base[1], col[1])
    m.point_on_line(man[2], col.line(1, 2))
    m.relative_distance(col[2], des[1], 5)
    m.translate(base.line(3, 4), des.line(1, 2))
    m.gravity(G)
    mech = _compile(m, tmp_path)
    sw = mech.sweep(0.0, 1.0, 21, level="dynamic")
    assert np.count_nonzero(sw.t == 0.5) == 2
    tau = sw.driver("crank forward")
    _close(tau, tau[::-1], np.abs(tau).max())           # T and 1 - T, the switch included
    p = sw.power()
    assert np.abs(p["residual"]).max() <= 1e-9 * np.abs(p["drivers"]).max()
    _close(p["drivers"], -p["drivers"][::-1], np.abs(p["drivers"]).max())
    for t in (0.3, 0.7):
        s = mech.solve(t, level="dynamic")
        assert s.driver("crank back") == pytest.approx(tau[np.argmin(np.abs(sw.t - t))],
                                                       rel=1e-9)
