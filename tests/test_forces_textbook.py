"""docs/reference/forces.md against textbook-style force analyses: a Norton-style
four-bar (Design of Machinery Ex. 11-3 proportions 5, 15, 10, 19) with all three links
massive, a force on the coupler, a torque on the rocker, gravity, the coupler's and
rocker's local frames rotated and offset from their pins; its driver torque, every pin
reaction and the shaking of the frame against a Newton–Euler solve written here (the
textbook's matrix method on closed-form kinematics, no mechgen equation used). And the
errors of a kinematic solution or sweep asked for forces, and of a mistyped level."""
import math

import numpy as np
import pytest

import mechgen
from mechgen import Model, T

A, B, C, D = 5.0, 15.0, 10.0, 19.0
TH0, W0, AL0 = math.radians(60), 25.0, 15.0
BETA, GAM = 0.7, -0.4                   # the coupler's / rocker's link line in local axes
OFF3, OFF4 = (1.0, -2.0), (-2.0, 1.0)   # pin A of the coupler, pin O4 of the rocker (local)
MASS = {"crank": (0.0388, 0.1, (3 * math.cos(math.pi / 6), 1.5)),
        "coupler": (0.0199, 1.5, (4.0, 5.0)),
        "rocker": (0.0150, 0.8, (0.5, 3.0))}
FP, PL, T4, G = (-40.0, 30.0), (6.0, 1.0), 120.0, 386.0


def _along(off, length, ang):
    return (off[0] + length * math.cos(ang), off[1] + length * math.sin(ang))


def four_bar():
    m = Model("norton_fourbar")
    base = m.ground("base", points=[(0, 0), (D, 0)])
    kw = {n: dict(mass=v[0], inertia=v[1], centroid=v[2]) for n, v in MASS.items()}
    crank = m.body("crank", points=[(0, 0), (A, 0)], guess=(0, 0, TH0), **kw["crank"])
    coup = m.body("coupler", points=[OFF3, _along(OFF3, B, BETA), PL],
                  guess=(0.5, 6, 0.35 - BETA), **kw["coupler"])
    rock = m.body("rocker", points=[OFF4, _along(OFF4, C, GAM)], guess=(D + 2, -1, 1.3 - GAM),
                  **kw["rocker"])
    m.revolute(base[1], crank[1], name="O2")
    m.revolute(crank[2], coup[1], name="A")
    m.revolute(coup[2], rock[2], name="B")
    m.revolute(base[2], rock[1], name="O4")
    m.rotation_lock(crank, TH0 + W0 * T + AL0 * T ** 2 / 2, name="drive")
    m.gravity(G)
    m.force(coup[3], FP, name="FP")
    m.moment(rock, T4)
    return m


def _rot(th):
    return np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _perp(v):
    return np.array([-v[1], v[0]])


def kinematics(t):
    """Link-line angles θ2, θ3, θ4 and their first two derivatives (closed-form positions,
    the velocity and acceleration loop equations solved as 2×2 systems)."""
    th2, w2, a2 = TH0 + W0 * t + AL0 * t * t / 2, W0 + AL0 * t, AL0
    pa = A * np.array([math.cos(th2), math.sin(th2)])
    dv = np.array([D, 0.0]) - pa
    L = np.linalg.norm(dv)
    x = (B * B - C * C + L * L) / (2 * L)
    e = dv / L
    pb = pa + x * e + math.sqrt(B * B - x * x) * _perp(e)
    th3 = math.atan2(*(pb - pa)[::-1])
    th4 = math.atan2(pb[1], pb[0] - D)
    # A e2 + B e3 = d + C e4, differentiated: [-B u3, C u4] [w3, w4] = A w2 u2 (u = perp e)
    u = [_perp(np.array([math.cos(a), math.sin(a)])) for a in (th2, th3, th4)]
    e_ = [np.array([math.cos(a), math.sin(a)]) for a in (th2, th3, th4)]
    M = np.column_stack([-B * u[1], C * u[2]])
    w3, w4 = np.linalg.solve(M, A * w2 * u[0])
    rhs = A * a2 * u[0] - A * w2 ** 2 * e_[0] - B * w3 ** 2 * e_[1] + C * w4 ** 2 * e_[2]
    a3, a4 = np.linalg.solve(M, rhs)
    return (th2, w2, a2), (th3, w3, a3), (th4, w4, a4), pa, pb


def newton_euler(t):
    """(τ, {pin: force on the later-named body}, shaking force and moment about O2)."""
    (th2, w2, a2), (th3, w3, a3), (th4, w4, a4), pa, pb = kinematics(t)
    bodies = {"crank": (th2, w2, a2, np.zeros(2), (0, 0)),
              "coupler": (th3 - BETA, w3, a3, pa, OFF3),
              "rocker": (th4 - GAM, w4, a4, np.array([D, 0.0]), OFF4)}
    inert, rg = {}, {}
    for name, (th, w, al, pin, off) in bodies.items():
        m, J, c = MASS[name]
        r = _rot(th) @ (np.array(c) - off)          # pin to centroid, global
        ap = {"crank": np.zeros(2),
              "coupler": -A * w2 ** 2 * np.array([math.cos(th2), math.sin(th2)])
              + A * a2 * np.array([-math.sin(th2), math.cos(th2)]), "rocker": np.zeros(2)}[name]
        ag = ap + al * _perp(r) - w * w * r
        rg[name] = pin + r
        inert[name] = (m * ag, J * al)
    # unknowns: F12 (2), F23 (2), F34 (2), F14 (2), τ: force on the later body from the earlier
    P = pa + _rot(th3 - BETA) @ (np.array(PL) - OFF3)      # the load FP's point
    rows, rhs = [], []

    def eq(body, fcols, mrow, const_f, const_m):
        rows.extend([fcols[0], fcols[1], mrow])
        rhs.extend([const_f[0], const_f[1], const_m])

    z = np.zeros(9)
    g = np.array([0.0, -G])
    # crank: F12 at O2, -F23 at A, τ
    m2 = MASS["crank"][0]
    f = [z.copy(), z.copy()]
    f[0][[0, 2]] = 1, -1
    f[1][[1, 3]] = 1, -1
    mo = z.copy()
    r1, r2 = -rg["crank"], pa - rg["crank"]
    mo[[0, 1, 2, 3, 8]] = -r1[1], r1[0], r2[1], -r2[0], 1
    eq("crank", f, mo, inert["crank"][0] - m2 * g, inert["crank"][1])
    # coupler: F23 at A, -F34 at B, FP at P
    m3 = MASS["coupler"][0]
    f = [z.copy(), z.copy()]
    f[0][[2, 4]] = 1, -1
    f[1][[3, 5]] = 1, -1
    mo = z.copy()
    r1, r2 = pa - rg["coupler"], pb - rg["coupler"]
    mo[[2, 3, 4, 5]] = -r1[1], r1[0], r2[1], -r2[0]
    eq("coupler", f, mo, inert["coupler"][0] - m3 * g - np.array(FP),
       inert["coupler"][1] - _cross(P - rg["coupler"], np.array(FP)))
    # rocker: F34 at B, F14 at O4, T4
    m4 = MASS["rocker"][0]
    f = [z.copy(), z.copy()]
    f[0][[4, 6]] = 1, 1
    f[1][[5, 7]] = 1, 1
    mo = z.copy()
    r1, r2 = pb - rg["rocker"], np.array([D, 0.0]) - rg["rocker"]
    mo[[4, 5, 6, 7]] = -r1[1], r1[0], -r2[1], r2[0]
    eq("rocker", f, mo, inert["rocker"][0] - m4 * g, inert["rocker"][1] - T4)
    x = np.linalg.solve(np.array(rows), np.array(rhs))
    F12, F23, F34, F14, tau = x[0:2], x[2:4], x[4:6], x[6:8], x[8]
    shake_f = -F12 - F14
    shake_m = -tau + _cross(np.array([D, 0.0]), -F14)
    origins = {"crank": np.zeros(2), "coupler": pa - _rot(th3 - BETA) @ np.array(OFF3),
               "rocker": np.array([D, 0.0]) - _rot(th4 - GAM) @ np.array(OFF4)}
    at = {"O2": np.zeros(2), "A": pa, "B": pb, "O4": np.array([D, 0.0])}
    pins = {("O2", "crank"): F12, ("A", "crank"): -F23, ("A", "coupler"): F23,
            ("B", "coupler"): -F34, ("B", "rocker"): F34, ("O4", "rocker"): F14}
    reactions = {k: np.array([*f, _cross(at[k[0]] - origins[k[1]], f)]) for k, f in pins.items()}
    return tau, reactions, np.array([*shake_f, shake_m])


@pytest.fixture(scope="module")
def fb(tmp_path_factory):
    return mechgen.compile(four_bar(), outdir=str(tmp_path_factory.mktemp("fb")), tier="python")


def test_the_norton_four_bar_s_torque_pin_forces_and_shaking(fb):
    ts = np.array([0.0, 0.05, 0.13])
    sw = fb.sweep(0.0, 0.13, 27, level="dynamic")
    for t in ts:
        tau, reactions, shake = newton_euler(float(t))
        s = fb.solve(float(t), level="dynamic")
        assert abs(s.driver("drive") - tau) < 1e-9 * abs(tau)
        for (pin, body), ref in reactions.items():
            np.testing.assert_allclose(s.reaction(pin, on=body), ref, rtol=1e-9, atol=1e-9)
    k = [0, 10, 26]
    for j, t in zip(k, sw.t[k]):
        tau, reactions, shake = newton_euler(float(t))
        assert abs(sw.driver("drive")[j] - tau) < 1e-9 * abs(tau)
        np.testing.assert_allclose(sw.shaking()[j], shake, rtol=1e-9, atol=1e-9)
    assert np.abs(sw.power()["residual"]).max() < 1e-8


def test_a_kinematic_solution_or_sweep_asked_for_forces_says_which_level(fb):
    # was AttributeError: 'Solution' object has no attribute 'driver'
    s = fb.solve(0.05, level="acceleration")
    sw = fb.sweep(0.0, 0.1, 3, level="velocity")
    for call in (lambda: s.driver("drive"), lambda: s.reaction("A", on="crank"),
                 lambda: s.multipliers):
        with pytest.raises(AttributeError, match='solve at level "dynamic" or "static".*'
                                                 "acceleration"):
            call()
    for call in (lambda: sw.driver("drive"), lambda: sw.shaking(), lambda: sw.power(),
                 lambda: sw.flywheel(0.05)):
        with pytest.raises(AttributeError, match='sweep at level "dynamic" or "static".*'
                                                 "velocity"):
            call()
    assert getattr(s, "lam", None) is None and not hasattr(sw, "nothing_such")


def test_a_mistyped_level_names_the_force_levels_too(fb):
    # was "level must be one of position, velocity, acceleration, got 'Dynamic'"
    for bad in ("Dynamic", "statics"):
        with pytest.raises(ValueError, match="static, dynamic, got"):
            fb.solve(0.05, level=bad)
        with pytest.raises(ValueError, match="static, dynamic, got"):
            fb.sweep(0.0, 0.1, 3, level=bad)


def test_a_force_solution_asked_for_a_sweep_s_quantity_says_so(fb):
    s = fb.solve(0.05, level="dynamic")
    sw = fb.sweep(0.0, 0.1, 3, level="static")
    with pytest.raises(AttributeError, match="it is a sweep's"):
        s.shaking()
    with pytest.raises(AttributeError, match="it is a solve's.*'static'"):
        sw.multipliers


def test_the_frame_s_reaction_at_its_offset_pivot_has_its_moment_arm(fb):
    """What pin O4 at (D, 0) applies to the frame, −F14 of the Newton–Euler solve, its
    moment about the frame's origin (D, 0) × (−F14), and zero about the pivot itself: the
    frame's moment sums each body's share with its arm from the origin, which a pin at the
    origin (O2) cannot tell from none."""
    sw = fb.sweep(0.0, 0.13, 27, level="dynamic")
    for k in (0, 10, 26):
        t = float(sw.t[k])
        _, reactions, _ = newton_euler(t)
        f = -reactions[("O4", "rocker")][:2]
        want = [f[0], f[1], _cross(np.array([D, 0.0]), f)]
        assert abs(want[2]) > 1.0
        s = fb.solve(t, level="dynamic")
        np.testing.assert_allclose(s.reaction("O4", on="base"), want, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(sw.reaction("O4", on="base")[k], want, rtol=1e-9,
                                   atol=1e-9)
        np.testing.assert_allclose(s.reaction("O4", on="base", about=(D, 0.0)),
                                   [f[0], f[1], 0.0], rtol=1e-9, atol=1e-9)
