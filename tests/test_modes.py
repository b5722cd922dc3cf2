"""Assembly modes (docs/reference/runtime.md): mechgen never reports a configuration of the wrong
assembly mode, nor a mode twice, against closed forms written here.

A mode picked by mech.assemblies(t) and passed to a sweep
(``sweep(..., guess=mode)``, as Mechanism.assemblies says to follow one), a design table
or singularities starting at another time keeps that mode: a Solution is a configuration
at its own time (as set_guess takes it), carried to the sweep's first time along the
motion, not a Newton start at that time that falls into whichever mode is nearest.

Closed form for the quick-return of generated/quick_return.py (crank 3 about (0, 5), lever
about the origin through the crank pin, its tip 9 along it, a link of 5 to the slider on
y = 10): X4 = tip_x ± √(25 − (10 − tip_y)²); the two modes are the slider right (+) and
left (−) of the lever's tip.
"""
import math
import os
import textwrap
import warnings

import numpy as np
import pytest

import mechgen
from models import four_bar, four_bar_q

GENERATED = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                         "generated")


def x4(t, sign):
    th = 2 * math.pi * t
    ax, ay = 3 * math.cos(th), 5 + 3 * math.sin(th)
    r = math.hypot(ax, ay)
    tx, ty = 9 * ax / r, 9 * ay / r
    return tx + sign * math.sqrt(25 - (10 - ty) ** 2)


def sign_of(value, t):
    return min((1, -1), key=lambda s: abs(value - x4(t, s)))


@pytest.fixture(scope="module")
def qr():
    return mechgen.load(os.path.join(GENERATED, "quick_return.py"), tier="python")


@pytest.mark.parametrize("ta", [0.35, 0.45, 0.55, 0.65])
def test_sweep_from_another_time_follows_the_mode_given(qr, ta):
    for mode in qr.assemblies(ta):
        sign = sign_of(mode["X4"], ta)
        assert mode["X4"] == pytest.approx(x4(ta, sign), abs=1e-9)
        sw = qr.sweep(0.0, 1.0, 21, guess=mode)
        assert np.allclose(sw["X4"], [x4(t, sign) for t in sw.t], atol=1e-9)


def test_design_table_from_another_time_follows_the_mode_given(qr):
    for mode in qr.assemblies(0.35):
        sign = sign_of(mode["X4"], 0.35)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            tab = qr.sweep(0.0, 1.0, 11, params={"longitud": [3.0]}, guess=mode)
        assert np.allclose(tab["X4"][0], [x4(t, sign) for t in tab.t], atol=1e-9)
        assert np.allclose(tab.sweep(0).mechanism.solve(0.35).q, mode.q, atol=1e-9)


@pytest.fixture(scope="module")
def crank_four_bar(tmp_path_factory):
    """models.four_bar with its crank's length a parameter, guessed at T = 0 on mode 1."""
    out = tmp_path_factory.mktemp("modes")
    return mechgen.compile(four_bar("modes_four_bar", params={"a": "a"}).m, outdir=str(out),
                           tier="python")


@pytest.mark.parametrize("t0", [0.6, 0.8])
def test_design_table_far_from_the_guess_time_keeps_its_mode(crank_four_bar, t0):
    """A table starting most of a turn after its guess's time, by the full Newton: each
    design, carried to its crank length at T = 0, is walked along the motion to t0 before
    its sweep starts. (Without that walk, or from the walk's first point, the Newton from
    the T = 0 configuration lands the a = 0.8 design on the other mode at t0, every
    status OK. The sorted solver picks its dyads' sides by sign, so method "auto" keeps
    the mode either way.)"""
    lengths = [0.8, 0.9, 1.0]
    tab = crank_four_bar.design_sweep(t0, t0 + 0.05, 3, {"a": lengths}, method="full",
                                      level="position")
    assert (tab.status == 0).all()
    for d, a in enumerate(lengths):
        want = [four_bar_q(float(t), a=a, mode=1) for t in tab.t]
        assert np.allclose(tab.Q[d], want, atol=1e-9), (a, tab.Q[d][0], want[0])


def test_singularities_from_another_time_start_on_the_mode_given():
    """The slider-driven quick-return (generated/quick_return_slider.py) locks at the
    stroke's ends; singularities(guess=mode) from another time runs on that mode."""
    mech = mechgen.load(os.path.join(GENERATED, "quick_return_slider.py"), tier="python")
    for mode in mech.assemblies(0.1):
        from_mode = mech.singularities(0.1, 1.0, guess=mode)
        carried = mech.singularities(0.0, 1.0, guess=mode)
        assert [s.t for s in carried if s.t >= 0.1] == pytest.approx([s.t for s in from_mode],
                                                                      abs=1e-9)


# -- rack and pinion (examples/rack_pinion.py, Mech's RackAndPinion1): the pinion of radius r
# turns at θ = ωT about (0, r); the rack slides on the x axis, its travel X = r θ. Its
# rolling row reads the rack's rotation unwrapped, r (θ − Th_rack): a rack turned a whole
# turn solves Φ with its travel one circumference 2πr further on, the same meshing teeth
# further on, as mechgen.turns says of gears. At one time there are two poses: the rack as
# built (Th = 0, X = r θ) and the rack turned half a turn on its guide (Th = π) ----------
RACK = '''
from mechgen import Model, T, pi
m = Model("rack_long")
r = m.param("r", 0.8)
omega = m.param("omega", pi)
base = m.ground("base", points=[(0, 0), (1, 0), (0, r)])
pinion = m.body("pinion", points=[(0, 0), (r, 0)], guess=(0, r, 0))
rack = m.body("rack", points=[(-12, 0), (12, 0)], guess=(0, 0, 0))
m.revolute(base[3], pinion[1], name="shaft")
m.translate(base.line(1, 2), rack.line(1, 2), name="guide")
m.rack_ratio(pinion[1], r, rack.line(1, 2), 12, name="mesh")
m.rotation_lock(pinion, omega * T, name="input")
'''


@pytest.fixture(scope="module")
def long_rack(tmp_path_factory):
    path = tmp_path_factory.mktemp("modes") / "rack_long.py"
    path.write_text(textwrap.dedent(RACK))
    return mechgen.compile(str(path), outdir=str(path.parent), tier="python")


@pytest.mark.parametrize("t", [0.0, 0.3])
def test_a_rack_has_two_poses_with_its_angle_in_range(long_rack, t):
    """A rack 24 long (the quasi-random starts reach ±12 along it) had 9 "assembly modes"
    at t = 0: the rack turned 2π k (Th = ±2π, ±3π, ±4π reported as such, outside
    (−π, π]) with X = r θ + 2π r k; now the two poses, their angles in (−π, π]."""
    r, theta = 0.8, math.pi * t
    modes = long_rack.assemblies(t)
    assert len(modes) == 2
    for s in modes:
        assert -math.pi < s["Th3"] <= math.pi
    assert modes[0]["Th3"] == pytest.approx(0.0, abs=1e-12)
    assert modes[0]["X3"] == pytest.approx(r * theta, abs=1e-9)     # the guess's mode first
    assert abs(modes[1]["Th3"]) == pytest.approx(math.pi, abs=1e-12)
    assert np.all(np.abs(long_rack.residual(modes[1].q, t)) < 1e-9)


# -- an offset slider-crank (crank a = 1, rod b = 3.2, slider on y = e = 0.4) driven by
# its crank, θ = 0.3 + 2πT; the model's guess has the slider right of the crank ----------
SLIDER_CRANK = '''
from mechgen import Model, T, pi
m = Model("offset_slider_crank")
a = m.param("a", 1.0)
b = m.param("b", 3.2)
e = m.param("e", 0.4)
g = m.ground("g", points=[(0, 0)])
crank = m.body("crank", points=[(0, 0), (a, 0)], guess=(0, 0, 0.3))
rod = m.body("rod", points=[(0, 0), (b, 0)], guess=(0.95, 0.3, 0.0))
slider = m.body("slider", points=[(0, 0)], guess=(4.1, 0.4, 0))
m.revolute(g[1], crank[1])
m.revolute(crank[2], rod[1])
m.revolute(rod[2], slider[1])
m.relative_y(slider[1], e)
m.rotation_lock(slider, 0)
m.rotation_lock(crank, 0.3 + 2 * pi * T, name="crank angle")
'''


def slider_crank(t, side):
    """(Th3, X4) of the offset slider-crank at t with the slider right (side +1) or left
    (-1) of the crank pin: X4 = a cos θ + side √(b² − (e − a sin θ)²)."""
    th = 0.3 + 2 * math.pi * t
    ax, ay = math.cos(th), math.sin(th)
    x4 = ax + side * math.sqrt(3.2 ** 2 - (0.4 - ay) ** 2)
    return math.atan2(0.4 - ay, x4 - ax), x4


@pytest.fixture(scope="module")
def offset_slider_crank(tmp_path_factory):
    path = tmp_path_factory.mktemp("modes") / "offset_slider_crank.py"
    path.write_text(textwrap.dedent(SLIDER_CRANK))
    return mechgen.compile(str(path), outdir=str(path.parent), tier="python")


@pytest.mark.parametrize("t", [-0.8, 0.1, 0.5, 1.29])
@pytest.mark.parametrize("near", [0.0, 0.2, 0.35])
def test_a_guess_of_the_slider_alone_picks_its_mode(offset_slider_crank, t, near):
    """solve(t, guess={"X4": x}) with x at the left assembly's slider position (or moved
    20 %, 35 % of the way to the right one) came back on the right assembly (X4 = 3.7 at
    t = -0.886 for x = -2.6): the model's guess filled the rod's angle in, pointing right,
    and that decided the mode. The coordinates given now hold while the others are fitted
    to them, so the slider's side is the one asked for; likewise a sweep's start."""
    left, right = slider_crank(t, -1), slider_crank(t, +1)
    x = left[1] + near * (right[1] - left[1])
    s = offset_slider_crank.solve(t, guess={"X4": x})
    assert s["X4"] == pytest.approx(left[1], abs=1e-9)
    assert math.remainder(s["Th3"] - left[0], 2 * math.pi) == pytest.approx(0, abs=1e-9)
    if near == 0.2:
        sw = offset_slider_crank.sweep(t, t + 0.5, 5, guess={"X4": x})
        want = [slider_crank(u, -1)[1] for u in sw.t]
        assert np.abs(sw["X4"] - want).max() < 1e-9
    # the right one still comes from a guess there, and from the rod's angle alone
    s = offset_slider_crank.solve(t, guess={"X4": right[1] - near * (right[1] - left[1])})
    assert s["X4"] == pytest.approx(right[1], abs=1e-9)
    s = offset_slider_crank.solve(t, guess={"Th3": math.pi - 0.1})
    assert s["X4"] == pytest.approx(left[1], abs=1e-9)


# -- a six-bar whose loops close together (a four-bar r4-cp-r6 on the ground, its coupler
# point driven by a rod from a crank), its model guess poor -------------------------------
SIX_BAR = '''
from mechgen import Model, T, pi
m = Model("six_bar_poor_guess")
L5 = m.param("L5", 2.6)
om = m.param("om", 2 * pi)
ground = m.ground("ground", points=[(0, 0), (3, 0), (1.0, -2.5)])
crank = m.body("crank", points=[(0, 0), (0.6, 0)], guess=(1.0, -2.5, 0.0))
r4 = m.body("r4", points=[(0, 0), (1.5, 0)], guess=(0, 0, 1.2))
cp = m.body("cp", points=[(0, 0), (2.5, 0), (1.2, 1.0)], guess=(0.54, 1.4, -0.3))
r6 = m.body("r6", points=[(0, 0), (1.8, 0)], guess=(3, 0, 1.8))
l5 = m.body("l5", points=[(0, 0), (L5, 0)], guess=(1.6, -2.5, 1.4))
m.revolute(ground[3], crank[1])
m.revolute(ground[1], r4[1])
m.revolute(r4[2], cp[1])
m.revolute(cp[2], r6[2])
m.revolute(ground[2], r6[1])
m.revolute(crank[2], l5[1])
m.revolute(l5[2], cp[3])
m.rotation_lock(crank, om * T, name="crank angle")
'''


def test_solve_and_sweep_from_the_model_guess_keep_angles_near_it(tmp_path):
    """solve(0) without a guess returned the rocker at Th3 = -100.97 rad, the coupler at
    5.85 and the rod at -30.36 (the model's guess 1.2, -0.3, 1.4: Newton threw them whole
    turns away), and a sweep from t = 0 kept them there, while solve(0, guess=the same
    guess) gave -0.434, -0.436, 1.060: the same pose. Both now give the angles near the
    guess (each within π of it), as an explicit guess does."""
    path = tmp_path / "six_bar_poor_guess.py"
    path.write_text(textwrap.dedent(SIX_BAR))
    mech = mechgen.compile(str(path), outdir=str(tmp_path), tier="python")
    explicit = mech.solve(0.0, guess=dict(zip(mech.coordinates, mech.guess))).q
    angles = [j for j, name in enumerate(mech.coordinates) if name.startswith("Th")]
    assert np.all(np.abs(explicit[angles] - mech.guess[angles]) < math.pi)
    assert np.abs(mech.solve(0.0).q - explicit).max() < 1e-12
    assert np.abs(mech.sweep(0.0, 0.01, 2).Q[0] - explicit).max() < 1e-12
    later = mech.solve(0.01).q
    assert np.all(np.abs(later[angles] - explicit[angles]) < 0.2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tab = mech.sweep(0.0, 0.01, 2, params={"L5": [2.6, 2.62]})
    assert np.abs(tab.Q[0, 0] - explicit).max() < 1e-12       # a design table's starts too
    assert np.abs(tab.Q[1, 0] - mech.with_params(L5=2.62).solve(0.0).q).max() < 1e-9


def test_assemblies_put_the_mode_of_a_partial_guess_first(offset_slider_crank):
    """assemblies(t, guess={"X4": x}) with x the left slider position listed the right
    assembly first (the mode the guess reaches comes first), as solve(t, guess=) went
    there; now the left one, the one solve(t, guess=) returns."""
    t = -0.886
    left, right = slider_crank(t, -1), slider_crank(t, +1)
    modes = offset_slider_crank.assemblies(t, guess={"X4": left[1]})
    assert [s["X4"] for s in modes] == pytest.approx([left[1], right[1]], abs=1e-9)


def test_singularities_without_a_guess_search_the_branch_solve_is_on(tmp_path):
    """singularities(t0, t1) with no guess started from a Newton at t0 from the model's
    guess (a configuration at t = 0), while solve(t0) and sweep() follow the motion from
    there: on seed 001's slider-driven quick-return, whose motion from its guess locks at
    t = 0.2465, singularities(0.5, 1) reported the locks 0.7415 and 0.7585 of whatever
    mode the Newton at 0.5 fell into, where solve(0.5) says the motion cannot get there.
    It now starts where solve(t0) is, and says so where that cannot be reached."""
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    mech = mechgen.compile(mechgen.load_model(f"{root}/examples/quick_return_slider.py"),
                           outdir=str(tmp_path), tier="python")
    locks = [float(x) for x in mech.singularities(0.0, 0.3)]
    # the lock: the crank pin's quadratic on the lever (s² − 10 s cos φ + 25 − L² = 0) has
    # a double root, cos φ = 4/5, sin φ = −3/5 on this mode; the lever's end 9(−sin φ,
    # cos φ) 5 from the slider on y = 10: X4² − 10.8 X4 + 12 = 0; X4 = centro + amplitud
    # sin 2πT (tests/closed_forms.slider_driven_configurations)
    import mpmath as mp
    x_lock = (mp.mpf("10.8") + mp.sqrt(mp.mpf("10.8") ** 2 - 48)) / 2
    t_lock = float(mp.asin((x_lock - mp.mpf("4.13931")) / mp.mpf("5.40447")) / (2 * mp.pi))
    assert abs(locks[0] - t_lock) < 1e-6
    with pytest.raises(mechgen.ConvergenceError, match="singularities.*follows the motion"):
        mech.singularities(0.5, 1.0)
    with pytest.raises(mechgen.ConvergenceError):
        mech.solve(0.5)
    # a guess near t0 still searches from there
    s = mech.solve(0.5, guess={"Th2": 1.9, "Th3": 0.1, "X4": 4.0})
    got = [float(x) for x in mech.singularities(0.5, 1.0, guess=s)]
    assert len(got) >= 1 and 0.5 < got[0] < 1.0
