"""Gears without a phase ambiguity (issue 20): the rolling row vanishes only where the
gears mesh at phase c, never half a turn out of phase; assembly modes are counted as
poses (every body's rotation modulo 2π), so that a geared five-bar has 2, as its closed
form; and the drawing flaws a new user saw (a crank on a gear drawn to the pitch radius,
ground bars across gears and cams, a cam's pivot without its symbol).

Every expected value is computed here from the geometry (math.atan2, circle
intersections), never taken from mechgen."""
import math
import os

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
import sympy as sp  # noqa: E402
from matplotlib.patches import Polygon  # noqa: E402

import mechgen  # noqa: E402
from mechgen import Model, T, cos, pi, sin  # noqa: E402
from mechgen.compiler.check import check_report  # noqa: E402
from mechgen.model.loader import load_model  # noqa: E402
from conftest import ROOT  # noqa: E402

R1, R2, COUPLER, CRANK = 2.0, 1.0, 3.0, 1.0     # gear ratio -R1/R2 = -2


def geared_five_bar(c=0):
    """Two cranks (length 1) on gears of radii 2 and 1 on ground shafts 3 apart, couplers
    3 and 3 joined at P; gear 1 driven at one turn per unit of T."""
    m = Model("geared5")
    base = m.ground("base", points=[(0, 0), (R1 + R2, 0)])
    g1 = m.body("g1", points=[(0, 0), (CRANK, 0)], guess=(0, 0, 0))
    g2 = m.body("g2", points=[(0, 0), (CRANK, 0)], guess=(R1 + R2, 0, 0))
    c1 = m.body("c1", points=[(0, 0), (COUPLER, 0)], guess=(1, 0, 1.2))
    c2 = m.body("c2", points=[(0, 0), (COUPLER, 0)], guess=(4, 0, 1.9))
    m.revolute(base[1], g1[1])
    m.revolute(base[2], g2[1])
    m.gear_ratio(g1[1], R1, g2[1], R2, c, name="mesh")
    m.revolute(g1[2], c1[1])
    m.revolute(g2[2], c2[1])
    m.revolute(c1[2], c2[2], name="P")
    m.rotation_lock(g1, 2 * pi * T, name="input")
    return m


def five_bar_closed_form(t, c=0.0):
    """The two assemblies at t: crank angles from the rolling relation
    R1 th1 + R2 th2 = c (centre line along x), P where the couplers' circles meet."""
    th1 = 2 * math.pi * t
    th2 = (c - R1 * th1) / R2
    A = np.array([CRANK * math.cos(th1), CRANK * math.sin(th1)])
    B = np.array([R1 + R2 + CRANK * math.cos(th2), CRANK * math.sin(th2)])
    d = B - A
    L = math.hypot(*d)
    a = L / 2                                   # equal couplers: P on the bisector
    h = math.sqrt(COUPLER ** 2 - a ** 2)
    mid, n = A + d / 2, np.array([-d[1], d[0]]) / L
    return th1, th2, [mid + h * n, mid - h * n]


def same_angle(a, b, tol=1e-9):
    return abs(math.remainder(a - b, 2 * math.pi)) < tol


@pytest.fixture(scope="module")
def five_bar(tmp_path_factory):
    out = str(tmp_path_factory.mktemp("gears"))
    return mechgen.compile(geared_five_bar(), outdir=out, tier="python")


# -- the row ---------------------------------------------------------------------------
def _gear_row(r1, r2, c=0):
    m = Model("pair")
    a = m.body("a", points=[(0, 0)], guess=(0, 0, 0))
    b = m.body("b", points=[(0, 0)], guess=(1, 0, 0))
    m.gear_ratio(a[1], r1, b[1], r2, c)
    row = m.constraints[0].exprs[0]
    syms = {s.name: s for s in row.free_symbols}
    names = ("X2", "Y2", "Th2", "X3", "Y3", "Th3")
    return sp.lambdify([syms.get(n, sp.Symbol(n)) for n in names], row)


@pytest.mark.parametrize("r1, r2, c", [(1.0, 3.0, 0.0), (1.5, 2.5, 0.7), (1.0, -2.5, 0.3),
                                       (2.0, -1.2, -0.4)])
def test_the_rolling_row_is_the_wrapped_rolling_relation(r1, r2, c):
    """(r1 + r2) times the angle from the pitch direction u/(r1 + r2) to ψ in (−π, π]:
    zero where r1 (Th1 − β) + r2 (Th2 − β) = c, β the angle of u/(r1 + r2), and
    ±π (r1 + r2), not 0, half a turn out of phase (where |u| sin(ψ − β) vanished too)."""
    f = _gear_row(r1, r2, c)
    R = r1 + r2
    rng = np.random.default_rng(5)
    for _ in range(40):
        x2, y2, x3, y3 = rng.uniform(-3, 3, 4)
        th2, th3 = rng.uniform(-9, 9, 2)
        beta = math.atan2((y3 - y2) / R, (x3 - x2) / R)     # the pitch direction's angle
        psi = (r1 * th2 + r2 * th3 - c) / R
        want = R * math.remainder(psi - beta, 2 * math.pi)
        assert f(x2, y2, th2, x3, y3, th3) == pytest.approx(want, abs=1e-12)
        # meshed at phase c (Th3 solving the relation): 0; half a turn of phase away: not
        th3 = (c + R * beta - r1 * th2) / r2
        assert abs(f(x2, y2, th2, x3, y3, th3)) < 1e-11
        flipped = th3 + math.pi * R / r2
        assert abs(f(x2, y2, th2, x3, y3, flipped)) == pytest.approx(math.pi * abs(R), rel=1e-9)


def test_mesh_angle_derivatives_are_those_of_its_atan2():
    """The derivatives mesh_angle states (those of ψ − β) against sympy's derivatives of
    the atan2 it prints as, at random points, for k = 1, −1 and a symbol."""
    from mechgen.model.library2d.gears import mesh_angle
    ux, uy, psi, k = sp.symbols("ux uy psi k", real=True)
    rng = np.random.default_rng(3)
    for kk in (1, -1, k):
        f = mesh_angle(ux, uy, psi, kk)
        g = f.as_atan2()
        for x in (ux, uy, psi):
            mine = sp.lambdify((ux, uy, psi, k), f.diff(x))
            ref = sp.lambdify((ux, uy, psi, k), g.diff(x))
            for v in rng.uniform(-3, 3, (5, 4)):
                v[3] = v[3] if kk is k else kk
                assert mine(*v) == pytest.approx(ref(*v), rel=1e-12, abs=1e-12)


# -- the geared five-bar against its closed form ----------------------------------------------
def test_check_counts_two_modes_of_the_geared_five_bar():
    text, ok = check_report(geared_five_bar(), 0.0)
    assert ok
    assert "assembly modes at t = 0: 2 found" in text, text


@pytest.mark.parametrize("t", [0.0, 0.137, 0.5, 0.81])
def test_assemblies_of_the_geared_five_bar(five_bar, t):
    th1, th2, Ps = five_bar_closed_form(t)
    modes = five_bar.assemblies(t, starts=64)
    assert len(modes) == 2
    P = sorted(tuple(np.round(five_bar.points_at(s.q, t)[five_bar.point_names.index("c1[2]")], 9))
               for s in modes)
    want = sorted(tuple(np.round(p, 9)) for p in Ps)
    assert np.allclose(P, want, atol=1e-8)
    for s in modes:
        assert same_angle(s["Th2"], th1) and same_angle(s["Th3"], th2)
        assert s.residual < 1e-10
    a, b = modes
    assert not all(same_angle(a.q[j], b.q[j], 1e-7) for j in range(five_bar.n))


def test_single_solves_mesh_the_gears_in_phase(five_bar):
    """At 100 times the driven gear's partner turns at −2 times its angle (mod 2π): never
    half a turn out of phase, whichever P the solve reaches."""
    bad = 0
    for t in np.linspace(0.0, 1.0, 100, endpoint=False):
        th1, th2, Ps = five_bar_closed_form(float(t))
        try:
            s = five_bar.solve(float(t))
        except mechgen.MechgenError:
            continue                        # a refusal is not a wrong answer
        P = five_bar.points_at(s.q, float(t))[five_bar.point_names.index("c1[2]")]
        if not (same_angle(s["Th3"], th2, 1e-8) and min(np.hypot(*(P - p)) for p in Ps) < 1e-8):
            bad += 1
    assert bad == 0


def test_assemblies_never_return_one_pose_twice(five_bar):
    """Gear 2 is read by Φ through (2 Th2 + Th3)/3: Th3 and Th3 + 6π both solve it, one
    pose; the modes differ modulo 2π in some coordinate."""
    modes = five_bar.assemblies(0.3, starts=200)
    for i, a in enumerate(modes):
        for b in modes[i + 1:]:
            d = [abs(math.remainder(x - y, 2 * math.pi)) for x, y in zip(a.q, b.q)]
            assert max(d) > 1e-6


def test_fourbar_assemblies_against_circle_intersection(tmp_path):
    """A four-bar at random dimensions: its two modes are the two intersections of the
    coupler's and the rocker's circles."""
    rng = np.random.default_rng(11)
    a, b, c, d = 1.0, 3.1, 2.4, 3.3
    th = 0.7
    m = Model("fb")
    g = m.ground("g", points=[(0, 0), (d, 0)])
    crank = m.body("crank", points=[(0, 0), (a, 0)], guess=(0, 0, th))
    coupler = m.body("coupler", points=[(0, 0), (b, 0)], guess=(a * math.cos(th), a * math.sin(th), 0.5))
    rocker = m.body("rocker", points=[(0, 0), (c, 0)], guess=(d, 0, 1.5))
    m.revolute(g[1], crank[1])
    m.revolute(crank[2], coupler[1])
    m.revolute(coupler[2], rocker[2])
    m.revolute(g[2], rocker[1])
    m.rotation_lock(crank, th + 2 * pi * T)
    mech = mechgen.compile(m, outdir=str(tmp_path), tier="python")
    for t in rng.uniform(0, 1, 3):
        phi = th + 2 * math.pi * t
        A = np.array([a * math.cos(phi), a * math.sin(phi)])
        D = np.array([d, 0.0])
        v = D - A
        L = math.hypot(*v)
        x = (L ** 2 + b ** 2 - c ** 2) / (2 * L)
        h = math.sqrt(b ** 2 - x ** 2)
        n = np.array([-v[1], v[0]]) / L
        want = sorted(tuple(np.round(A + x * v / L + s * h * n, 8)) for s in (1, -1))
        modes = mech.assemblies(float(t), starts=64)
        got = sorted(tuple(np.round(mech.points_at(s.q, float(t))[mech.point_names.index("coupler[2]")], 8))
                     for s in modes)
        assert len(modes) == 2 and np.allclose(got, want, atol=1e-7)


# -- pictures --------------------------------------------------------------------------------
@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _extent_along(poly, origin, direction):
    xy = poly.get_transform().transform(poly.get_xy())
    xy = plt.gca().transData.inverted().transform(xy)
    s = (xy - origin) @ direction
    return s.min(), s.max()


def test_a_crank_on_a_gear_is_drawn_as_long_as_its_points(five_bar):
    """Gear 1 (pitch radius 2) carries a crank of length 1: its bar reaches 1 (plus its
    rounded end), not the pitch radius; no ground bar runs through the meshing gears."""
    from mechgen import plot
    s = five_bar.solve(0.0)
    d = plot.draw(five_bar, s)
    plt.sca(d.ax)
    bar = [a for a in d.artists["g1"] if isinstance(a, Polygon)]
    assert len(bar) == 1
    lo, hi = _extent_along(bar[0], np.zeros(2), np.array([1.0, 0.0]))
    assert hi == pytest.approx(CRANK + d.size, abs=1e-6)       # the crank, w beyond its pin
    assert hi < R1 - 0.5
    assert not [a for a in d.artists["base"] if isinstance(a, Polygon) and a.get_zorder() < 1.2]


def cam_arm_model():
    """A disc cam (radius 2, eccentric 0.5) on a ground pivot driving a roller (0.5) on an
    arm of length 3 pivoted at (3, 3)."""
    m = Model("camarm")
    ground = m.ground("ground", points=[(0, 0), (3.0, 3.0)])
    cam = m.body("cam", guess=(0, 0, 0))
    arm = m.body("arm", points=[(0, 0), (-3.0, 0)], guess=(3.0, 3.0, 0.0))
    m.revolute(ground[1], cam[0])
    m.rotation_lock(cam, 2 * pi * T, name="cam angle")
    m.revolute(ground[2], arm[1])
    disc = m.profile("disc", xy=lambda s: (0.5 + 2 * cos(s), 2 * sin(s)))
    m.cam_to_point(cam, disc, arm[2], contact="s", guess=1.0, radius=0.5)
    return m


def test_a_cam_pivot_shows_its_symbol_and_no_bar_crosses_the_cam(tmp_path):
    from mechgen import plot
    mech = mechgen.compile(cam_arm_model(), outdir=str(tmp_path), tier="python")
    d = plot.draw(mech, mech.solve(0.1))
    cam_plate = max(a.get_zorder() for a in d.artists["cam"] if isinstance(a, Polygon))
    pivots = [a for a in d.artists["ground"] if isinstance(a, Polygon) and a.get_zorder() >= 1.2]
    # two triangles: the cam's drawn over its plate, the arm's standing below its pivot
    assert len(pivots) == 2
    tri = {tuple(np.round(p.get_xy()[0], 9)): p for p in pivots}
    assert tri[(0.0, 0.0)].get_zorder() > cam_plate
    arm_tri = tri[(3.0, 3.0)].get_xy()
    assert np.all(arm_tri[:3, 1] <= 3.0 + 1e-12)
    assert not [a for a in d.artists["ground"] if isinstance(a, Polygon) and a.get_zorder() < 1.2]


@pytest.mark.parametrize("t", [0.1, 0.55, 0.85])
def test_quick_return_assemblies_against_closed_form(qr, t):
    """Seed 001's quick-return: the lever through the crank pin C = (0, 5) + 3 (cos φ,
    sin φ) ends at 9 C/|C|; the slider on y = 10 lies 5 from it, on either side: two
    modes, X4 = x ± √(25 − (10 − y)²)."""
    phi = 2 * math.pi * t
    C = np.array([3 * math.cos(phi), 5 + 3 * math.sin(phi)])
    tip = 9 * C / math.hypot(*C)
    half = math.sqrt(25 - (10 - tip[1]) ** 2)
    modes = qr.assemblies(t, starts=64)
    assert sorted(s["X4"] for s in modes) == pytest.approx([tip[0] - half, tip[0] + half],
                                                           abs=1e-9)
    for s in modes:
        assert same_angle(s["Th3"], math.atan2(C[1], C[0]) - math.pi / 2)


def test_a_gear_train_has_one_meshing_at_a_time():
    """examples/gear_train.py (A drives BC, BC drives D whose centre slides along x): the
    wrapped rolling rows vanish on every meshing whole turns of the centre line apart
    (14 "modes" before); at one time, with A where its driver puts it, only the meshing
    that Mech's relation r1 (Th1 − β) + r2 (Th2 − β) = c gives is this mechanism: D right
    of C (X4 = 8) exactly once, with Th3 = −rA Th2/rB and Th4 = −rC Th3/rD (β = 0)."""
    mech = mechgen.load(os.path.join(ROOT, "generated", "gear_train.py"))
    t = 0.1
    right = [s for s in mech.assemblies(t) if abs(s["X4"] - 8.0) < 1e-9]
    assert len(right) == 1
    th2 = 2 * math.pi * t
    th3 = -1.0 * th2 / 3.0
    th4 = -1.5 * th3 / 2.5
    assert math.remainder(right[0]["Th3"] - th3, 2 * math.pi) == pytest.approx(0, abs=1e-9)
    assert math.remainder(right[0]["Th4"] - th4, 2 * math.pi) == pytest.approx(0, abs=1e-9)
    text, ok = check_report(load_model(os.path.join(ROOT, "examples", "gear_train.py")), t)
    assert ok
    table = text.split("    mode  X4", 1)[1].splitlines()[1:]
    rows = []
    for line in table:
        if not line.strip()[:1].isdigit():
            break
        rows.append(line.split())
    assert sum(1 for r in rows if abs(float(r[1]) - 8.0) < 1e-6) == 1, text


# -- an internal pair and a planetary arm meshing at phase c, whichever gear comes first --
def _compile(m, tmp_path):
    return mechgen.compile(m, outdir=str(tmp_path), tier="python")


def _same_angle(a, b, tol=1e-9):
    return abs(math.remainder(a - b, 2 * math.pi)) < tol


# -- internal gears declared ring first ---------------------------------------------------
def _internal_pair(ring_first):
    """A pinion (radius 1) at (1.5, 0) inside a ring (radius 2.5) at the origin, both on
    fixed shafts, the pinion driven: with c = 0 every x axis along +x (from the ring's
    centre through the pinion's to the pitch point (2.5, 0)) is a meshing position
    (docs/constraints.md: e1 = e2 = 0), so the ring turns at rp/rr from 0."""
    m = Model("ring_first" if ring_first else "pinion_first")
    b = m.ground("b", points=[(0, 0), (1.5, 0)])
    ring = m.body("ring", points=[(0, 0)], guess=(0, 0, 0))
    pin = m.body("pin", points=[(0, 0)], guess=(1.5, 0, 0))
    m.revolute(b[1], ring[1])
    m.revolute(b[2], pin[1])
    if ring_first:
        m.gear_ratio(ring[1], -2.5, pin[1], 1.0)
    else:
        m.gear_ratio(pin[1], 1.0, ring[1], -2.5)
    m.rotation_lock(pin, 2 * T)
    return m


@pytest.mark.parametrize("ring_first", [False, True])
def test_an_internal_pair_meshes_at_phase_c_whichever_gear_comes_first(ring_first, tmp_path):
    mech = _compile(_internal_pair(ring_first), tmp_path)
    for t in (0.0, 0.1, 1.0):
        s = mech.solve(t, level="velocity")
        assert _same_angle(s["Th2"], 2 * t / 2.5), (t, s["Th2"])
        assert s["Th2d"] == pytest.approx(0.8, abs=1e-12)


def _planetary(ring_first):
    """Sun (1) driven, planet (0.6) on an arm, fixed ring (2.2) = the ground; the all-zero
    pose meshes both pairs at c = 0, so the arm turns at ω rs/(rs + rr) from 0 (Willis)."""
    p = Model("planet_ring_first" if ring_first else "planet_first")
    frame = p.ground("frame", points=[(0, 0)])
    sun = p.body("sun", points=[(0, 0)], guess=(0, 0, 0))
    planet = p.body("planet", points=[(0, 0)], guess=(1.6, 0, 0))
    arm = p.body("arm", points=[(0, 0), (1.6, 0)], guess=(0, 0, 0))
    p.revolute(frame[1], sun[1])
    p.revolute(frame[1], arm[1])
    p.revolute(arm[2], planet[1])
    p.gear_ratio(sun[1], 1.0, planet[1], 0.6)
    if ring_first:
        p.gear_ratio(frame[1], -2.2, planet[1], 0.6)
    else:
        p.gear_ratio(planet[1], 0.6, frame[1], -2.2)
    p.rotation_lock(sun, 2 * T)
    return p


@pytest.mark.parametrize("ring_first", [False, True])
def test_a_planetary_arm_starts_where_its_gears_mesh_at_phase_c(ring_first, tmp_path):
    mech = _compile(_planetary(ring_first), tmp_path)
    w_arm = 2 * 1.0 / 3.2
    for t in (0.0, 0.3, 2.0):
        s = mech.solve(t, level="velocity")
        assert _same_angle(s["Th4"], w_arm * t), (t, s["Th4"])
        assert s["Th4d"] == pytest.approx(w_arm, abs=1e-12)
