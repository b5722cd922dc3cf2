"""docs/reference/sensitivities.md (parameter sensitivities) against independent references.

Six mechanisms are built here as mechgen Models — a four-bar, an offset slider-crank, an
inverted slider-crank (quick return), a Watt six-bar, an eccentric cam with a flat-faced
and a roller follower, a four-bar whose crank is driven through a gear pair — and each has
a closed form written in tests/sensitivity_closed_forms.py with mpmath alone (circle
intersections, the cam's and the gears' geometry; no mechgen equation). mpmath
differentiates it: in the parameter for ∂q/∂p, mixed in T and the parameter for ∂q̇/∂p
and ∂q̈/∂p, the drivers' laws held. mechgen's own finite differences are never used.

``test_*_motion_matches_closed_form`` checks each closed form's q, q̇, q̈ against today's
``mech.solve(t, level="acceleration")``: that the references describe the same mechanism in
the same assembly mode. The other tests check the sensitivities themselves
(``sensitivities=True``, ``s.sensitivity``, ``s.dq_dp``/``dqd_dp``/``dqdd_dp``, a sweep's,
a declared output's, the refusal at a singular configuration).
"""
import math

import numpy as np
import pytest

import mechgen
import models
from mechgen import Line, Model, T, cos, location, sin

import sensitivity_closed_forms as cf

TIER = "python"     # the plain tier: no numba compile of each model's module (the rest of
                    # the suite runs the compiled tier; the numbers are the same)
RTOL = 1e-8


# -- the models -------------------------------------------------------------------------------
def _guess(fn, params, k):
    """The guess of body k (counted from 0 among the moving bodies): its closed-form
    configuration at T = 0, rounded (only the assembly mode is taken from it)."""
    q = fn(0.0, **params)
    return tuple(round(float(v), 1) for v in q[3 * k:3 * k + 3])


FOURBAR = dict(a=0.8, b=2.5, c=2.0, d=3.0, omega=2 * math.pi, theta0=math.pi / 3)


def fourbar_model():
    m = Model("sens_fourbar")
    P = {k: m.param(k, v) for k, v in FOURBAR.items()}
    ground = m.ground("ground", points=[(0, 0), (P["d"], 0)])
    crank = m.body("crank", points=[(0, 0), (P["a"], 0)], guess=(0, 0, 1.0))
    coupler = m.body("coupler", points=[(0, 0), (P["b"], 0), (0.5, 0.8)], guess=(0.4, 0.7, 0.5))
    rocker = m.body("rocker", points=[(0, 0), (P["c"], 0)], guess=(3, 0, 1.8))
    m.revolute(ground[1], crank[1])
    m.revolute(crank[2], coupler[1])
    m.revolute(ground[2], rocker[1])
    m.revolute(coupler[2], rocker[2])
    m.rotation_lock(crank, P["theta0"] + P["omega"] * T, name="crank angle")
    m.output("px", location(coupler[3])[0])        # the coupler point (0.5, 0.8)'s x
    m.output("tip_y", location(rocker[2])[1])      # the rocker's tip: explicit in c
    return m


SLIDER = dict(r=1.0, l=3.5, e=0.6)


def slider_crank_model():
    """tests/models.py's offset slider-crank, its lengths and offset parameters r, l, e,
    driven θ = 0.4 + 2πT by an unnamed rotation_lock."""
    return models.slider_crank("sens_slider_crank", **SLIDER, theta0=0.4, omega=2 * math.pi,
                               params={k: k for k in SLIDER}, drive=None).m


QUICK = dict(L=3.0, h=5.0, rod=5.0)


def inverted_slider_crank_model():
    m = Model("sens_quick_return")
    L, h, rod = (m.param(k, v) for k, v in QUICK.items())
    base = m.ground("base", points=[(0, 0), (0, h), (-5, 10), (12, 10)])
    crank = m.body("crank", points=[(0, 0), (L, 0)], guess=(0, 5, 0))
    lever = m.body("lever", points=[(0, 0), (0, 9)], guess=(0, 0, -0.5))
    slider = m.body("slider", points=[(0, 0), (2, 0)], guess=(6, 10, 0))
    m.revolute(base[2], crank[1])
    m.rotation_lock(crank, base, 2 * math.pi * T, name="crank driver")
    m.revolute(base[1], lever[1])
    m.point_on_line(crank[2], lever.line(1, 2))
    m.relative_distance(lever[2], slider[1], rod)
    m.translate(base.line(3, 4), slider.line(1, 2))
    return m


WATT = dict(a=0.8, c=2.0, g=2.0, e=2.5, f=2.0)


def watt_model():
    m = Model("sens_watt")
    a, c, g, e, f = (m.param(k, v) for k, v in WATT.items())
    ground = m.ground("ground", points=[(0, 0), (3.0, 0), cf.WATT_O6])
    crank = m.body("crank", points=[(0, 0), (a, 0)], guess=(0, 0, 1.0))
    coupler = m.body("coupler", points=[(0, 0), (2.5, 0)], guess=(0.4, 0.7, 0.5))
    rocker = m.body("rocker", points=[(0, 0), (c, 0), (g * math.cos(cf.WATT_ARM),
                                                        g * math.sin(cf.WATT_ARM))],
                    guess=(3, 0, 1.8))
    link = m.body("link", points=[(0, 0), (e, 0)], guess=_guess(cf.watt_sixbar, WATT, 3))
    rocker2 = m.body("rocker2", points=[(0, 0), (f, 0)], guess=_guess(cf.watt_sixbar, WATT, 4))
    m.revolute(ground[1], crank[1])
    m.revolute(crank[2], coupler[1])
    m.revolute(ground[2], rocker[1])
    m.revolute(coupler[2], rocker[2])
    m.revolute(rocker[3], link[1])
    m.revolute(ground[3], rocker2[1])
    m.revolute(link[2], rocker2[2])
    m.rotation_lock(crank, math.pi / 3 + 2 * math.pi * T)
    return m


CAM = dict(R=2.0, e=0.5, rho=0.4, f=0.7)


def cam_model():
    m = Model("sens_cam")
    R, e, rho, f = (m.param(k, v) for k, v in CAM.items())
    q0 = [float(v) for v in cf.eccentric_cam(0.0, **CAM)]
    ground = m.ground("ground", points=[(0, 0), (0, 1), (0, f), (1, f)])
    cam = m.body("cam", guess=(0, 0, 0))
    flat = m.body("flat", points=[(-1, 0), (1, 0), (0, 1)], guess=(0, 2.5, 0))
    roller = m.body("roller", points=[(0, 0), (1, 0)], guess=(round(q0[6], 1), 0.7, 0))
    m.revolute(ground[1], cam[0])
    m.rotation_lock(cam, 2 * math.pi * T, name="cam angle")
    m.translate(ground.line(1, 2), Line(flat[0], flat[3]))
    m.translate(ground.line(3, 4), roller.line(1, 2))
    disc = m.profile("disc", xy=lambda s: (e + R * cos(s), R * sin(s)))
    m.cam_to_line(cam, disc, flat.line(1, 2), contact="s1", guess=1.6)
    m.cam_to_point(cam, disc, roller[1], contact="s2", guess=round(q0[10], 1), radius=rho)
    return m


GEARED = dict(rA=1.0, rB=1.5, a=0.8, b=2.5)


def geared_model():
    m = Model("sens_geared")
    rA, rB, a, b = (m.param(k, v) for k, v in GEARED.items())
    ground = m.ground("ground", points=[(-(rA + rB), 0), (0, 0), (3.0, 0)])
    gA = m.body("gearA", points=[(0, 0)], guess=_guess(cf.geared_fourbar, GEARED, 0))
    gB = m.body("gearB", points=[(0, 0), (a, 0)], guess=_guess(cf.geared_fourbar, GEARED, 1))
    coupler = m.body("coupler", points=[(0, 0), (b, 0)],
                     guess=_guess(cf.geared_fourbar, GEARED, 2))
    rocker = m.body("rocker", points=[(0, 0), (2.0, 0)], guess=_guess(cf.geared_fourbar, GEARED, 3))
    m.revolute(ground[1], gA[1], name="input shaft")
    m.revolute(ground[2], gB[1], name="crank shaft")
    m.gear_ratio(gA[1], rA, gB[1], rB, c=cf.GEAR_PHASE, name="mesh")
    m.rotation_lock(gA, 2 * math.pi * T, name="input")
    m.revolute(gB[2], coupler[1])
    m.revolute(ground[3], rocker[1])
    m.revolute(coupler[2], rocker[2])
    return m


# name: (model, closed form, parameters (all of the model's, in declared order), times)
CASES = {
    "fourbar": (fourbar_model, cf.fourbar, FOURBAR, (0.0, 0.3, 0.71, 1.37)),
    "slider_crank": (slider_crank_model, cf.slider_crank, SLIDER, (0.0, 0.37, 0.82)),
    "inverted_slider_crank": (inverted_slider_crank_model, cf.inverted_slider_crank, QUICK,
                              (0.1, 0.45, 0.8)),
    "watt_sixbar": (watt_model, cf.watt_sixbar, WATT, (0.0, 0.29, 0.66)),
    "cam": (cam_model, cf.eccentric_cam, CAM, (0.0, 0.19, 0.58)),
    "geared_fourbar": (geared_model, cf.geared_fourbar, GEARED, (0.0, 0.26, 0.9)),
}


@pytest.fixture(scope="module")
def outdir(tmp_path_factory):
    return str(tmp_path_factory.mktemp("sensitivity_references"))


@pytest.fixture(scope="module")
def mechs(outdir):
    """Each case's mechanism, compiled when first asked for (so that -k builds only what
    it runs)."""
    built = {}

    def get(name):
        if name not in built:
            built[name] = mechgen.compile(CASES[name][0](), outdir=outdir, tier=TIER)
        return built[name]
    return get


def _close(got, ref, what, rtol=RTOL):
    """|got − ref| <= rtol (|ref| + max(1, max |ref|)): relative to each entry and to the
    matrix's scale."""
    ref = np.asarray(ref, dtype=float)
    got = np.asarray(got, dtype=float)
    assert got.shape == ref.shape, f"{what}: shape {got.shape}, expected {ref.shape}"
    scale = max(1.0, float(np.abs(ref).max()) if ref.size else 1.0)
    np.testing.assert_allclose(got, ref, rtol=rtol, atol=rtol * scale, err_msg=what)


# -- the references describe mechgen's mechanisms (passes without §8) ---------------------------
@pytest.mark.parametrize("case", list(CASES))
def test_motion_matches_closed_form(mechs, case):
    _, fn, params, times = CASES[case]
    mech = mechs(case)
    assert list(mech.parameters) == list(params)
    for t in times:
        q, qd, qdd = cf.motion(fn, t, params)
        s = mech.solve(t, level="acceleration")
        _close(s.q, q, f"{case} q at t={t}", rtol=1e-9)
        _close(s.qd, qd, f"{case} qd at t={t}", rtol=1e-9)
        _close(s.qdd, qdd, f"{case} qdd at t={t}", rtol=1e-9)


def test_fourbar_outputs_match_closed_form(mechs):
    mech = mechs("fourbar")
    for t in (0.0, 0.3, 0.71):
        ref = [float(v) for v in cf.fourbar_outputs(t, **FOURBAR)]
        s = mech.solve(t)
        assert s["px"] == pytest.approx(ref[0], rel=1e-10, abs=1e-10)
        assert s["tip_y"] == pytest.approx(ref[1], rel=1e-10, abs=1e-10)


def test_references_obey_the_obvious_identities():
    """Checks of the references alone: ∂Th2/∂ω = T and ∂Th2/∂θ0 = 1 for the four-bar; the
    flat-faced follower's Y3 = e sin ωT + R; the gear relation ThB = (c − rA ThA)/rB."""
    t = 0.3
    dq, dqd, _ = cf.sensitivities(cf.fourbar, t, FOURBAR, ["omega", "theta0"])
    assert dq[2, 0] == pytest.approx(t, abs=1e-15) and dq[2, 1] == pytest.approx(1.0, abs=1e-15)
    assert dqd[2, 0] == pytest.approx(1.0, abs=1e-15) and dqd[2, 1] == pytest.approx(0, abs=1e-15)
    dq, _, _ = cf.sensitivities(cf.eccentric_cam, t, CAM, ["R", "e"])
    assert dq[4, 0] == pytest.approx(1.0, abs=1e-15)
    assert dq[4, 1] == pytest.approx(math.sin(2 * math.pi * t), abs=1e-15)
    dq, _, _ = cf.sensitivities(cf.geared_fourbar, t, GEARED, ["rA", "rB"])
    thA = 2 * math.pi * t
    assert dq[5, 0] == pytest.approx(-thA / GEARED["rB"], abs=1e-14)
    assert dq[5, 1] == pytest.approx(-(cf.GEAR_PHASE - GEARED["rA"] * thA) / GEARED["rB"] ** 2,
                                     abs=1e-14)
    assert dq[0, 0] == pytest.approx(-1.0, abs=1e-15)


# -- the sensitivities ---------------------------------------------------------------------------
def _check_solution(s, case, fn, params, t, names):
    """s (solved at level acceleration with every parameter) against the references."""
    mech = s.mechanism
    n, k = len(mech.coordinates), len(params)
    assert list(s.sensitivity_params) == list(params)
    cols = [list(s.sensitivity_params).index(p) for p in names]
    ref = cf.sensitivities(fn, t, params, names)
    for got, r, level in zip((s.dq_dp, s.dqd_dp, s.dqdd_dp), ref, ("q", "qd", "qdd")):
        got = np.asarray(got)
        assert got.shape == (n, k), f"{case} d{level}/dp shape {got.shape}"
        _close(got[:, cols], r, f"{case} d{level}/dp at t={t} (columns {names})")
    # s.sensitivity(name, p) reads the same numbers, for every coordinate and level
    for i, c in enumerate(mech.coordinates):
        for j, p in enumerate(names):
            for suffix, r in zip(("", "d", "dd"), ref):
                got = s.sensitivity(c + suffix, p)
                assert got == pytest.approx(r[i, j], rel=RTOL,
                                            abs=RTOL * max(1.0, float(np.abs(r).max()))), \
                    f"{case}: d{c}{suffix}/d{p} at t={t}: {got} against {r[i, j]}"


@pytest.mark.parametrize("case", list(CASES))
def test_sensitivities_match_closed_form(mechs, case):
    _, fn, params, times = CASES[case]
    mech = mechs(case)
    for t in times:
        s = mech.solve(t, level="acceleration", sensitivities=True)
        _check_solution(s, case, fn, params, t, list(params))


def test_fourbar_sensitivities_of_named_parameters_at_lower_levels(mechs):
    """sensitivities=[names]: those columns only, in that order; at levels position and
    velocity the same numbers as at acceleration."""
    mech = mechs("fourbar")
    t, names = 0.71, ["c", "omega", "a"]
    dq, dqd, _ = cf.sensitivities(cf.fourbar, t, FOURBAR, names)
    s = mech.solve(t, level="velocity", sensitivities=names)
    assert list(s.sensitivity_params) == names
    _close(s.dq_dp, dq, "velocity-level dq/dp")
    _close(s.dqd_dp, dqd, "velocity-level dqd/dp")
    assert s.sensitivity("Th4d", "omega") == pytest.approx(dqd[8, 1], rel=RTOL)
    s = mech.solve(t, sensitivities=["d"])
    assert list(s.sensitivity_params) == ["d"]
    dq_d, _, _ = cf.sensitivities(cf.fourbar, t, FOURBAR, ["d"])
    _close(s.dq_dp, dq_d, "position-level dq/dd")
    assert s.sensitivity("X4", "d") == pytest.approx(1.0, rel=1e-12)
    assert s.sensitivity("Th2", "d") == pytest.approx(0.0, abs=1e-12)


def test_sensitivities_with_other_parameter_values(mechs):
    """A mechanism with_params answers at its own parameters (a slider-crank with a longer
    rod and a larger offset)."""
    mech = mechs("slider_crank").with_params(l=4.2, e=-0.9)
    params = dict(SLIDER, l=4.2, e=-0.9)
    t = 0.52
    s = mech.solve(t, level="acceleration", sensitivities=True)
    _check_solution(s, "slider_crank (l=4.2, e=-0.9)", cf.slider_crank, params, t, list(params))


def test_sweep_sensitivities_match_solves_and_closed_form(mechs):
    mech = mechs("fourbar")
    n = 20
    sw = mech.sweep(0.0, 0.95, n, level="acceleration", sensitivities=True)
    assert np.allclose(sw.t, np.linspace(0.0, 0.95, n))
    names = ["a", "omega", "d"]
    quantities = ["X3", "Th3", "Th4", "Th4d", "Y3dd", "Th4dd"]
    got = {(c, p): np.asarray(sw.sensitivity(c, p)) for c in quantities for p in names}
    for arr in got.values():
        assert arr.shape == (n,)
    index = {c: k for k, c in enumerate(mech.coordinates)}
    for k, t in enumerate(sw.t):
        t = float(t)
        s = mech.solve(t, level="acceleration", sensitivities=True)
        ref = cf.sensitivities(cf.fourbar, t, FOURBAR, names)
        for (c, p), arr in got.items():
            base, level = c.rstrip("d"), len(c) - len(c.rstrip("d"))    # Th4dd: Th4, 2
            r = ref[level][index[base], names.index(p)]
            scale = max(1.0, float(np.abs(ref[level]).max()))
            assert arr[k] == pytest.approx(s.sensitivity(c, p), rel=1e-9, abs=1e-9 * scale), \
                f"sweep d{c}/d{p}[{k}] (t={t}) against the single solve"
            assert arr[k] == pytest.approx(r, rel=RTOL, abs=RTOL * scale), \
                f"sweep d{c}/d{p}[{k}] (t={t}) against the closed form"


def test_sensitivity_of_declared_outputs_over_a_sweep(mechs):
    """sw.sensitivity of a declared output: px (the coupler point's x, implicit in every
    parameter) and tip_y (the rocker tip's y, explicit in c as well)."""
    mech = mechs("fourbar")
    sw = mech.sweep(0.1, 0.9, 9, level="position", sensitivities=True)
    names = list(FOURBAR)
    for k, t in enumerate(sw.t):
        t = float(t)
        vals = [float(v) for v in cf.fourbar_outputs(t, **FOURBAR)]
        assert sw["px"][k] == pytest.approx(vals[0], rel=1e-10, abs=1e-10)
        ref, _, _ = cf.sensitivities(cf.fourbar_outputs, t, FOURBAR, names)
        for j, p in enumerate(names):
            for i, out in enumerate(("px", "tip_y")):
                got = float(np.asarray(sw.sensitivity(out, p))[k])
                assert got == pytest.approx(ref[i, j], rel=RTOL, abs=RTOL), \
                    f"d{out}/d{p} at t={t}: {got} against {ref[i, j]}"


def test_sensitivity_of_a_declared_output_at_a_solve(mechs):
    mech = mechs("fourbar")
    t = 0.44
    s = mech.solve(t, level="acceleration", sensitivities=True)
    ref, _, _ = cf.sensitivities(cf.fourbar_outputs, t, FOURBAR, ["c", "a"])
    assert s.sensitivity("tip_y", "c") == pytest.approx(ref[1, 0], rel=RTOL, abs=RTOL)
    assert s.sensitivity("px", "a") == pytest.approx(ref[0, 1], rel=RTOL, abs=RTOL)


# -- singular configurations ---------------------------------------------------------------------
CHANGE_POINT = dict(a=1.0, b=3.0, c=2.0, d=2.0)   # a + b = c + d; θ = π/3 + 2πT: all four
T_CHANGE = 5 / 6                                   # links on one line at θ = 2π, T = 5/6


@pytest.mark.filterwarnings("ignore::mechgen.BranchJumpWarning")
def test_singular_configuration_refuses_sensitivities(mechs):
    mech = mechs("fourbar").with_params(**CHANGE_POINT)
    s = mech.solve(T_CHANGE)
    assert s.singular                     # the position exists; Φ_q has lost rank there
    with pytest.raises(mechgen.SingularError) as info:
        mech.solve(T_CHANGE, sensitivities=True)
    assert info.value.t == pytest.approx(T_CHANGE)
    with pytest.raises(mechgen.SingularError):
        mech.solve(T_CHANGE, sensitivities=["a"])
    # just off the change point Φ_q is regular again and the sensitivities exist
    s = mech.solve(T_CHANGE - 0.02, sensitivities=["a"])
    assert np.all(np.isfinite(s.dq_dp))


@pytest.mark.filterwarnings("ignore::mechgen.BranchJumpWarning")
def test_sweep_through_a_singular_configuration_gives_nan_there(mechs):
    mech = mechs("fourbar").with_params(**CHANGE_POINT)
    sw = mech.sweep(0.5, T_CHANGE, 11, sensitivities=["a", "d"])
    params = dict(FOURBAR, **CHANGE_POINT)
    for k in (0, 5, 10):            # the sweep keeps the closed form's assembly mode
        q, _, _ = cf.motion(cf.fourbar, float(sw.t[k]), params)
        _close(sw.Q[k], q, f"change-point four-bar q at t={sw.t[k]}", rtol=1e-9)
    x4 = np.asarray(sw.sensitivity("Th4", "a"))
    assert np.isnan(x4[-1])
    assert np.all(np.isfinite(x4[:-1]))
    where = np.asarray(sw.sensitivity_singular)
    if where.dtype == bool and where.shape == (11,):
        assert where[-1] and not where[:-1].any()
    else:                                 # the times it names
        assert np.any(np.isclose(where.astype(float), T_CHANGE))
    # the regular points agree with the closed form (the change-point dimensions)
    for k in (0, 5):
        t = float(sw.t[k])
        ref, _, _ = cf.sensitivities(cf.fourbar, t, params, ["a"])
        assert x4[k] == pytest.approx(ref[8, 0], rel=RTOL, abs=RTOL)



def test_sensitivity_of_mech_output_functions(mechs):
    """A symbolic quantity (Mech's location, here the coupler point (0.5, 0.8) and the
    rocker's tip) through the symbolic side: the same as the closed form's, a vector
    quantity with a last axis, on a sweep and at a solve."""
    mech = mechs("fourbar")
    coupler, rocker = mech.model.bodies["coupler"], mech.model.bodies["rocker"]
    sw = mech.sweep(0.1, 0.9, 5, level="position", sensitivities=["a", "c"])
    both = sw.sensitivity(location(coupler[3]), "a")
    assert both.shape == (5, 2)
    for k, t in enumerate(sw.t):
        ref, _, _ = cf.sensitivities(cf.fourbar_outputs, float(t), FOURBAR, ["a", "c"])
        assert both[k, 0] == pytest.approx(ref[0, 0], rel=RTOL, abs=RTOL)
        tip = sw.sensitivity(location(rocker[2])[1], "c")[k]
        assert tip == pytest.approx(ref[1, 1], rel=RTOL, abs=RTOL)
    s = mech.solve(0.3, sensitivities=["c"])
    ref, _, _ = cf.sensitivities(cf.fourbar_outputs, 0.3, FOURBAR, ["c"])
    assert s.sensitivity(location(rocker[2])[1], "c") == pytest.approx(ref[1, 0], rel=RTOL)
