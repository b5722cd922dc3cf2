"""Contact forces (issue 21): ``s.contact(name)``, ``sw.contact(name)``,
``sw.contact_lost(name)`` for cams, gears and racks, each against a closed form written
here, never mechgen's own equations.

The cams: an eccentric disc (radius RC, its centre E from the pivot) turns at w about the
origin; the follower slides on the vertical through the pivot, a return spring k pressing
it towards the cam. The follower's height y(θ) is closed form for a knife edge, a roller
outside the disc, a roller inside a ring (a hollow cam) and a flat face; Newton for the
follower alone, m ÿ = N n_y − m g + F_spring, gives the contact force N; contact is lost
first at the speed where min over θ of m w² y''(θ) + m g − F_spring reaches zero."""
import math
import os
import warnings

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import brentq, minimize_scalar

import mechgen
from mechgen import Model, T, cos, sin

RC, E, RHO = 2.0, 0.5, 0.4          # disc radius, its eccentricity, roller radius
MF, MC = 1.5, 2.0                   # follower, cam masses
K, G, W, TH0 = 100.0, 9.807, 2 * math.pi, 0.3
H = 6.0                             # spring anchors at (0, ±H)


def _compile(model, tmp_path):
    return mechgen.compile(model, outdir=str(tmp_path), tier="python")


# -- cams ------------------------------------------------------------------------------------
CAMS = {  # kind: (distance of the follower's reference point from the disc's centre,
    #              side of the contact normal: +1 away from the disc's centre, free length
    #              of the spring giving its free position y_f)
    "knife": (RC, 1, 1.5),
    "roller": (RC + RHO, 1, 1.5),
    "ring": (RC - RHO, -1, 4.0),       # a roller inside a hollow cam, the spring below
    "flat": (None, 1, 1.5),
    "discs": (RC + RHO, 1, 1.5),        # cam_to_cam: the roller as a profile of its own
}


def height(kind):
    """y(θ) of the follower's reference point (sympy): the roller's centre, the knife's
    point or the flat face."""
    th = sp.Symbol("th")
    d = CAMS[kind][0]
    if d is None:
        return th, E * sp.sin(th) + RC
    return th, E * sp.sin(th) + sp.sqrt(d ** 2 - (E * sp.cos(th)) ** 2)


def cam_model(kind):
    """The eccentric disc cam with follower ``kind`` (CAMS)."""
    d, side, y_free = CAMS[kind]
    th, y = height(kind)
    y0 = float(y.subs(th, TH0))
    m = Model(f"contact_{kind}")
    w = m.param("w", W)
    ground = m.ground("ground", points=[(0, 0), (0, 1), (0, H), (0, -H)])
    cam = m.body("cam", guess=(0, 0, TH0), mass=MC, inertia=0.3)
    fol = m.body("follower", points=[(0, 0), (0, 1), (-1, 0), (1, 0)], guess=(0, y0, 0),
                 mass=MF, inertia=0.01)
    m.revolute(ground[1], cam[0], name="pivot")
    m.rotation_lock(cam, w * T + TH0, name="drive")
    m.translate(ground.line(1, 2), fol.line(1, 2), name="guide")
    disc = m.profile("disc", xy=lambda s: (E + RC * cos(s), RC * sin(s)))
    alpha = math.atan2(y0 - E * math.sin(TH0), -E * math.cos(TH0)) - TH0  # centre to contact
    if kind in ("knife", "roller", "ring"):
        extra = {} if kind == "knife" else dict(radius=RHO, side="inside" if kind == "ring"
                                                 else "outside")
        m.cam_to_point(cam, disc, fol[1], contact="s", guess=alpha, name="cam", **extra)
    elif kind == "flat":
        m.cam_to_line(cam, disc, fol.line(3, 4), contact="s", guess=math.pi / 2 - TH0,
                      name="cam")
    else:
        roller = m.profile("roller", xy=lambda s: (RHO * cos(s), RHO * sin(s)))
        m.cam_to_cam(cam, disc, fol, roller, contact=("s1", "s2"),
                     guess=(alpha, alpha + TH0 + math.pi), name="cam")
    m.gravity(G)
    if side > 0:   # pressed down by a spring to the anchor above: force −k (y − y_free)
        m.spring(fol[1], ground[3], K, H - y_free, name="return")
    else:          # pressed up by a spring to the anchor below
        m.spring(fol[1], ground[4], K, H + y_free, name="return")
    return m


def cam_closed_form(kind, t, w=W):
    """Per time: the contact force N (positive: the cam pushes), its normal's x and y
    components (the direction the cam pushes the follower), y and the follower's
    acceleration."""
    d, side, y_free = CAMS[kind]
    th, y = height(kind)
    f, f2 = (sp.lambdify(th, e, "numpy") for e in (y, sp.diff(y, th, 2)))
    ang = w * np.asarray(t) + TH0
    yv, ydd = f(ang), w ** 2 * f2(ang)
    if d is None:
        nx, ny = np.zeros_like(ang), np.ones_like(ang)
    else:  # from the disc's centre to the follower's point, then the side
        nx, ny = side * (0 - E * np.cos(ang)) / d, side * (yv - E * np.sin(ang)) / d
    spring = -K * (yv - y_free)                  # on the follower, along y
    N = (MF * (ydd + G) - spring) / ny          # m ÿ = N n_y − m g + spring
    return N, nx, ny, yv, ydd


@pytest.fixture(scope="module")
def cams(tmp_path_factory):
    out = {}
    for kind in CAMS:
        out[kind] = _compile(cam_model(kind), tmp_path_factory.mktemp(kind))
    return out


@pytest.mark.parametrize("kind", list(CAMS))
def test_cam_contact_force_against_newton(cams, kind):
    mech = cams[kind]
    sw = mech.sweep(0, 1, 101, level="dynamic")
    N, nx, ny, y, _ = cam_closed_form(kind, sw.t)
    np.testing.assert_allclose(sw["Y3"], y, rtol=1e-12)       # the follower's height
    assert np.all(N > 0)                          # the spring keeps contact at speed W
    np.testing.assert_allclose(sw.contact("cam"), N, rtol=1e-9)
    s = mech.solve(0.37, level="dynamic")
    N1 = cam_closed_form(kind, 0.37)[0]
    np.testing.assert_allclose(s.contact("cam"), N1, rtol=1e-9)
    label = next(lab for _, _, lab, _, _ in mech.module.CONSTRAINTS if lab.startswith("cam:"))
    assert s.contacts() == {label: s.contact("cam")}
    # the guide carries the contact force's sideways part; the pivot that and the cam's
    # weight (its centroid on the pivot)
    np.testing.assert_allclose(sw.contact("guide"), np.abs(N * nx), rtol=1e-9,
                               atol=1e-9 * N.max())
    pin = np.hypot(N * nx, N * ny + MC * G)
    np.testing.assert_allclose(sw.contact("pivot"), pin, rtol=1e-9)
    # at rest (level static): N n_y = m g − spring
    st = mech.solve(0.37, level="static")
    _, _, ny, y, _ = cam_closed_form(kind, 0.37)
    np.testing.assert_allclose(st.contact("cam"), (MF * G + K * (y - CAMS[kind][2])) / ny,
                               rtol=1e-9)


def critical_speed(kind):
    """The cam speed at which the contact force's minimum over a turn reaches zero:
    N n_y = m w² y'' + m g − F_spring(y) = 0 where y'' < 0:
    w² = min over θ of (m g − F) / (−m y'')."""
    _, _, y_free = CAMS[kind]
    th, y = height(kind)
    f, f2 = (sp.lambdify(th, e, "math") for e in (y, sp.diff(y, th, 2)))

    def ratio(a):
        return (MF * G + K * (f(a) - y_free)) / (-MF * f2(a)) if f2(a) < 0 else np.inf

    grid = np.linspace(0, 2 * np.pi, 721)
    k = int(np.argmin([ratio(a) for a in grid]))
    best = minimize_scalar(ratio, bracket=(grid[k - 1], grid[k], grid[k + 1]), tol=1e-12)
    return math.sqrt(best.fun), (f, f2)


@pytest.mark.parametrize("kind", ["roller", "flat"])
def test_cam_loses_contact_above_the_critical_speed(cams, kind):
    wc, (f, f2) = critical_speed(kind)
    _, _, y_free = CAMS[kind]
    for factor in (0.99, 1.01):
        w = factor * wc
        mech = cams[kind].with_params(w=w)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            sw = mech.sweep(0, 2 * np.pi / w, 361, level="dynamic")
        pulls = [str(x.message) for x in caught if "would have to pull" in str(x.message)]
        loss = sw.contact_lost("cam")
        np.testing.assert_allclose(sw.contact("cam"), cam_closed_form(kind, sw.t, w)[0],
                                   rtol=1e-9, atol=1e-9 * abs(sw.contact("cam")).max())
        if factor < 1:
            assert not loss and not pulls and loss.first is None and loss.intervals == ()
            continue
        assert loss and loss.lost and len(pulls) == 1 and "contact_lost" in pulls[0]

        def h(a):            # N n_y at cam angle a
            return MF * w ** 2 * f2(a) + MF * G + K * (f(a) - y_free)

        ang = TH0 + w * sw.t
        hv = np.array([h(a) for a in ang])
        np.testing.assert_array_equal(loss.mask, hv < 0)
        np.testing.assert_array_equal(loss.times, sw.t[hv < 0])
        i = int(np.argmax(hv < 0))
        first = (brentq(h, ang[i - 1], ang[i], xtol=1e-15) - TH0) / w
        np.testing.assert_allclose(loss.first, first, rtol=1e-9)
        assert len(loss.intervals) == 1 and loss.intervals[0][0] == loss.first
        j = i + int(np.sum(hv < 0))         # one interval: the first point in contact again
        regained = (brentq(h, ang[j - 1], ang[j], xtol=1e-15) - TH0) / w
        np.testing.assert_allclose(loss.intervals[0][1], regained, rtol=1e-9)


def test_contact_lost_names_only_cams(cams):
    sw = cams["roller"].sweep(0, 0.2, 5, level="dynamic")
    with pytest.raises(ValueError, match="not a cam contact"):
        sw.contact_lost("guide")
    with pytest.raises(ValueError, match="no constraint 'nope'"):
        sw.contact("nope")
    with pytest.raises(ValueError, match="rotation_lock; contact forces are defined for"):
        sw.contact("drive")


def test_a_model_without_loads_transmits_nothing(tmp_path):
    """examples/cam_eccentric.py has no mass and no loads: its flat face (constraint 4)
    carries nothing, and never pulls."""
    path = os.path.join(os.path.dirname(__file__), "..", "examples", "cam_eccentric.py")
    mech = mechgen.compile(path, outdir=str(tmp_path), tier="python")
    sw = mech.sweep(0, 1, 11, level="dynamic")
    np.testing.assert_array_equal(sw.contact(4), np.zeros(11))
    assert not sw.contact_lost(4) and mech.solve(0.3, level="static").contact(4) == 0


# -- gears and racks -------------------------------------------------------------------------
R1, R2, J1, J2, ML, A = 1.0, 2.5, 0.4, 1.7, 3.0, 0.35
MR, PR, MW = 4.0, -25.0, 3.0        # the rack's mass and load, the rolling wheel's mass


def angle(t, w=1.3):
    """The driven angle θ(t) = w t + A sin 3t and its derivatives."""
    return (w * t + A * np.sin(3 * t), w + 3 * A * np.cos(3 * t), -9 * A * np.sin(3 * t))


def gear_model(kind, r2):
    m = Model(f"gears_{kind}_{'int' if r2 < 0 else 'ext'}")
    c = R1 + r2
    ground = m.ground("ground", points=[(0, 0), (c, 0), (c + 1, 0)])
    g1 = m.body("g1", points=[(0, 0)], guess=(0, 0, 0), inertia=J1, mass=1.0)
    g2 = m.body("g2", points=[(0, 0)], guess=(c, 0, 0), inertia=J2, mass=2.0)
    m.revolute(ground[1], g1[1], name="shaft 1")
    if kind == "gear_ratio":
        m.revolute(ground[2], g2[1], name="shaft 2")
        m.gear_ratio(g1[1], R1, g2[1], r2, name="mesh")
    else:                  # gear 2's centre in a slot: the gears' distance row holds it
        m.point_on_line(g2[1], ground.line(2, 3), name="slot")
        m.gears(g1[1], R1, g2[1], r2, name="mesh")
    m.rotation_lock(g1, 1.3 * T + A * sin(3 * T), name="motor")
    m.moment(g2, ML, name="load")
    m.gravity(G)
    return m


@pytest.mark.parametrize("kind,r2", [("gear_ratio", R2), ("gears", R2), ("gear_ratio", -R2)])
def test_gear_tooth_force_is_torque_over_pitch_radius(tmp_path, kind, r2):
    mech = _compile(gear_model(kind, r2), tmp_path)
    sw = mech.sweep(0, 2, 41, level="dynamic")
    th, thd, thdd = angle(sw.t)
    th2dd, th2d = -R1 / r2 * thdd, -R1 / r2 * thd
    mesh2 = J2 * th2dd - ML                     # gear 2: J2 θ̈2 = mesh torque + load
    torque = (J1 * thdd * thd + J2 * th2dd * th2d - ML * th2d) / thd   # the power form
    mesh1 = J1 * thdd - torque                  # gear 1: J1 θ̈1 = torque + mesh torque
    np.testing.assert_allclose(sw.driver("motor"), torque, rtol=1e-9)
    np.testing.assert_allclose(sw.contact("mesh"), mesh2 / r2, rtol=1e-9)
    np.testing.assert_allclose(sw.contact("mesh"), mesh1 / R1, rtol=1e-9)
    s = mech.solve(0.8, level="dynamic")
    np.testing.assert_allclose(s.contact("mesh"), sw.contact("mesh")[16], rtol=1e-9)
    # the tooth force acts on gear 2 at the pitch point across the centre line (along y):
    # its support carries it and its weight, (0, M2 g + W)
    support = "shaft 2" if kind == "gear_ratio" else "slot"
    np.testing.assert_allclose(sw.contact(support), np.abs(2.0 * G + mesh2 / r2), rtol=1e-9)


def rack_model():
    """A pinion (radius R1) on a ground shaft R1 above the rack's pitch line drives the
    rack (mass MR) against a load PR; the rack's travel is R1 θ."""
    m = Model("rack_contact")
    ground = m.ground("ground", points=[(0, 0), (1, 0), (0, R1)])
    pinion = m.body("pinion", points=[(0, 0), (R1, 0)], guess=(0, R1, 0), inertia=J1,
                    mass=1.0)
    rack = m.body("rack", points=[(-3, 0), (3, 0)], guess=(0, 0, 0), mass=MR)
    m.revolute(ground[3], pinion[1], name="shaft")
    m.translate(ground.line(1, 2), rack.line(1, 2), name="guide")
    m.rack_ratio(pinion[1], R1, rack.line(1, 2), 3, name="mesh")
    m.rotation_lock(pinion, 1.3 * T + A * sin(3 * T), name="motor")
    m.force(rack[1], (PR, 0), name="load")
    m.gravity(G)
    return m



def test_rack_force_is_pinion_torque_over_pitch_radius(tmp_path):
    mech = _compile(rack_model(), tmp_path)
    sw = mech.sweep(0, 2, 41, level="dynamic")
    th, thd, thdd = angle(sw.t)
    np.testing.assert_allclose(sw["X3"], R1 * th, rtol=1e-12, atol=1e-12)
    xd, xdd = R1 * thd, R1 * thdd
    torque = (J1 * thdd * thd + MR * xdd * xd - PR * xd) / thd      # the power form
    np.testing.assert_allclose(sw.driver("motor"), torque, rtol=1e-9)
    rack_force = MR * xdd - PR                  # on the rack along x: MR ẍ = F + PR
    np.testing.assert_allclose(sw.contact("mesh"), rack_force, rtol=1e-9)
    np.testing.assert_allclose(sw.contact("mesh"), (torque - J1 * thdd) / R1, rtol=1e-9)


def test_rolling_pinion_pushes_the_ground_rack(tmp_path):
    """A wheel (mass MW) rolls on the ground's x axis (rack_and_pinion), its angle driven:
    its centre's x is 1 − R1 θ, so the rack (the ground) feels −MW ẍ = MW R1 θ̈ along x."""
    m = Model("rolling_contact")
    ground = m.ground("ground", points=[(-4, 0), (4, 0)])
    wheel = m.body("wheel", points=[(0, 0), (R1, 0)], guess=(1, R1, 0), mass=MW,
                   inertia=0.6)
    m.rack_and_pinion(wheel[1], R1, ground.line(1, 2), 5.0, name="mesh")
    m.rotation_lock(wheel, 1.3 * T + A * sin(3 * T), name="motor")
    m.gravity(G)
    mech = _compile(m, tmp_path)
    sw = mech.sweep(0, 2, 21, level="dynamic")
    th, thd, thdd = angle(sw.t)
    np.testing.assert_allclose(sw["X2"], 1.0 - R1 * th, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(sw.contact("mesh"), MW * R1 * thdd, rtol=1e-9,
                               atol=1e-12)



# -- the command line -------------------------------------------------------------------------
CLI_MODEL = '''
import math
from mechgen import Model, T, cos, sin
m = Model("cli_cam")
ground = m.ground("ground", points=[(0, 0), (0, 1), (0, 6)])
cam = m.body("cam", guess=(0, 0, 0.3), mass=2.0, inertia=0.3)
fol = m.body("follower", points=[(0, 0), (0, 1)], guess=(0, 2.55, 0), mass=1.5,
             inertia=0.01)
m.revolute(ground[1], cam[0], name="pivot")
m.rotation_lock(cam, W * T + 0.3, name="drive")
m.translate(ground.line(1, 2), fol.line(1, 2), name="guide")
disc = m.profile("disc", xy=lambda s: (0.5 + 2.0 * cos(s), 2.0 * sin(s)))
m.cam_to_point(cam, disc, fol[1], contact="s", guess=1.4, radius=0.4, name="cam")
m.gravity(9.807)
m.spring(fol[1], ground[3], 100.0, 6 - 1.5, name="return")
'''


@pytest.mark.parametrize("w", [W, 14.0])
def test_cli_forces_prints_contact_forces(tmp_path, capsys, monkeypatch, w):
    from mechgen.cli import main
    monkeypatch.setenv("MECHGEN_TIER", "python")
    path = tmp_path / "cli_cam.py"
    path.write_text(CLI_MODEL.replace("W * T", f"{w!r} * T"))
    t = (math.pi / 2 - 0.3) / w                # the follower at the top of its stroke
    assert main(["forces", str(path), "-t", repr(t), "--outdir", str(tmp_path / "g")]) == 0
    out = capsys.readouterr().out
    section = out[out.index("contact forces"):]
    line = next(x for x in section.splitlines() if x.strip().startswith("cam: cam_to_point"))
    value = float(line.split(")", 1)[1].split()[0])
    N = cam_closed_form("roller", t, w)[0]
    np.testing.assert_allclose(value, N, rtol=1e-9)
    assert ("pulling" in line) == (N < 0) and (N < 0) == (w > 13.0)
