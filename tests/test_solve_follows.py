"""A single solve never lands on another assembly mode (issue 20).

``mech.solve(t)`` without a guess follows the motion from the guess (a configuration at
t = 0, or set_guess()'s at its time) and returns the configuration on the guess's mode,
or raises where the way is blocked; an explicit guess is Newton from it, whatever
multiple of 2π its angles carry, in every method. Each check is against a closed form
written here: circle intersections for four-bars, a geared five-bar and a cam driving a
roller-follower arm, at random times and dimensions (seeded)."""
from __future__ import annotations

import math
import os
import textwrap

import numpy as np
import pytest

import mechgen
from mechgen.errors import SolveError

from conftest import GENERATED

TWO_PI = 2.0 * math.pi


def wrap(x):
    """x into (−π, π]."""
    return x - TWO_PI * np.ceil((np.asarray(x) - math.pi) / TWO_PI)


def circles(c1, r1, c2, r2, mode):
    """The intersection of the circle (c1, r1) with (c2, r2) to the left (mode +1) or the
    right (−1) of the line c1 → c2; None where they do not meet."""
    c1, c2 = np.asarray(c1, float), np.asarray(c2, float)
    v = c2 - c1
    L = math.hypot(*v)
    x = (r1 * r1 - r2 * r2 + L * L) / (2 * L)
    h2 = r1 * r1 - x * x
    if h2 <= 0:
        return None
    u = v / L
    return c1 + x * u + mode * math.sqrt(h2) * np.array([-u[1], u[0]])


def angle(v):
    return math.atan2(v[1], v[0])


def close(q, exact, angles, tol):
    """max |q − exact|, angles compared modulo 2π."""
    d = np.asarray(q, float) - exact
    d[angles] = wrap(d[angles])
    return float(np.abs(d).max())


# -- four-bars (generated/fourbar.py: crank a, coupler b, rocker c, ground d) ----------------
FB_ANGLES = [2, 5, 8]


@pytest.fixture(scope="module")
def fourbar_mech():
    return mechgen.load(os.path.join(GENERATED, "fourbar.py"))


def fourbar_closed(dims, th2, mode):
    """q of the four-bar (X2 Y2 Th2 X3 Y3 Th3 X4 Y4 Th4) at crank angle th2 with the
    coupler-rocker joint to the left (+1) or right (−1) of the line crank pin → rocker pivot."""
    a, b, c, d = dims
    A = np.array([a * math.cos(th2), a * math.sin(th2)])
    D = np.array([d, 0.0])
    B = circles(A, b, D, c, mode)
    if B is None:
        return None
    return np.array([0, 0, th2, A[0], A[1], angle(B - A), d, 0, angle(B - D)])


def grashof_crank_rocker(rng):
    """Dimensions whose crank a turns fully (a the shortest, Grashof) and never nears a
    toggle by less than a margin."""
    while True:
        a = rng.uniform(0.3, 1.0)
        b, c, d = rng.uniform(1.5, 4.0, size=3)
        s, l = a, max(b, c, d)
        if s + l < (a + b + c + d - s - l) - 0.15 and min(b, c, d) > a + 0.2:
            return a, b, c, d


def test_solve_follows_the_guess_on_random_crank_rockers(fourbar_mech):
    rng = np.random.default_rng(20)
    wrong = 0
    for _ in range(6):
        dims = grashof_crank_rocker(rng)
        th0, omega = rng.uniform(-math.pi, math.pi), rng.choice([-1, 1]) * rng.uniform(3, 9)
        mech = fourbar_mech.with_params(a=dims[0], b=dims[1], c=dims[2], d=dims[3],
                                        theta2=th0, omega=omega)
        mode = int(rng.choice([-1, 1]))
        t_g = rng.uniform(-1, 1)
        start = fourbar_closed(dims, th0 + omega * t_g, mode)
        start[FB_ANGLES] = wrap(start[FB_ANGLES])         # a guess holds angles mod 2π
        mech.set_guess(start + rng.normal(scale=0.02, size=9), t=t_g)
        for t in rng.uniform(-3, 3, size=17):
            s = mech.solve(float(t))
            wrong += close(s.q, fourbar_closed(dims, th0 + omega * t, mode), FB_ANGLES,
                           1e-9) > 1e-9
    assert wrong == 0


def test_the_model_guess_is_a_configuration_at_t0_and_solve_follows_it(fourbar_mech):
    mech = fourbar_mech.with_params()
    dims = (0.8, 2.5, 2.0, 3.0)
    # the model's guess (Th3 0.5, Th4 1.8) lies near the joint left of crank pin → pivot
    mode = 1
    assert mech.guess_t == 0.0
    rng = np.random.default_rng(3)
    for t in np.concatenate([[0.0, 1.25, -0.75], rng.uniform(-4, 4, size=40)]):
        s = mech.solve(float(t), level="velocity")
        exact = fourbar_closed(dims, math.pi / 3 + TWO_PI * t, mode)
        assert close(s.q, exact, FB_ANGLES, 1e-10) <= 1e-10, t
        assert s.q[2] == pytest.approx(math.pi / 3 + TWO_PI * t, abs=1e-12)


def test_set_guess_of_a_solution_takes_its_time_and_mode(fourbar_mech):
    mech = fourbar_mech.with_params()
    dims = (0.8, 2.5, 2.0, 3.0)
    other = fourbar_closed(dims, math.pi / 3 + TWO_PI * 0.3, -1)
    s = mech.solve(0.3, guess=other)                  # an explicit guess: Newton from it
    assert close(s.q, other, FB_ANGLES, 0) <= 1e-10
    mech.set_guess(s)
    assert mech.guess_t == 0.3
    for t in (0.3, 0.31, 1.7, -2.2):
        exact = fourbar_closed(dims, math.pi / 3 + TWO_PI * t, -1)
        assert close(mech.solve(t).q, exact, FB_ANGLES, 0) <= 1e-10
    mech.set_guess()                                  # back to the model's, at t = 0
    assert mech.guess_t == 0.0
    exact = fourbar_closed(dims, math.pi / 3 + TWO_PI * 1.7, 1)
    assert close(mech.solve(1.7).q, exact, FB_ANGLES, 0) <= 1e-10


def test_a_lock_on_the_way_raises_naming_it(fourbar_mech):
    """A non-Grashof four-bar whose crank rocks within ±θmax: after a full turn of the
    driver the configuration exists again (the same as at t = 0), but the mechanism cannot
    get there: the solve raises instead of returning it."""
    dims = (2.0, 2.5, 2.0, 3.0)          # s + l = 5 > p + q = 4.5: no link turns fully
    mech = fourbar_mech.with_params(a=2.0, b=2.5, c=2.0, d=3.0, theta2=0.0, omega=TWO_PI)
    mech.set_guess(fourbar_closed(dims, 0.0, 1), t=0.0)
    assert close(mech.solve(0.05).q, fourbar_closed(dims, TWO_PI * 0.05, 1), FB_ANGLES,
                 0) <= 1e-10
    # the crank locks where b + c reach... the joint angle limit: |crank pin − D| = b + c
    th_lock = math.acos((2.0 ** 2 + 3.0 ** 2 - 4.5 ** 2) / (2 * 2.0 * 3.0))
    for t in (1.0, 0.9, 1.0 - th_lock / TWO_PI + 0.01):
        with pytest.raises(SolveError) as info:
            mech.solve(t)
        msg = str(info.value)
        assert "could not reach t" in msg and "lock" in msg
        assert f"{th_lock / TWO_PI:.4f}"[:5] in msg        # the lock's time, t ≈ θ/2π


def test_explicit_guess_with_angles_off_by_turns_in_every_method(fourbar_mech):
    """Newton from an exact configuration whose angles are wrapped into (−π, π] and
    shifted by ±2π stays on its mode, whatever the method (issue 20: the full Newton went
    to the other mode at t = 1.25)."""
    rng = np.random.default_rng(201)
    wrong = []
    for k in range(40):
        dims = rng.uniform(0.5, 3.5, size=4)
        th0, omega = rng.uniform(-math.pi, math.pi), rng.uniform(-9, 9)
        mech = fourbar_mech.with_params(a=dims[0], b=dims[1], c=dims[2], d=dims[3],
                                        theta2=th0, omega=omega)
        t = 1.25 if k == 0 else float(rng.uniform(-3, 3))
        if k == 0:
            mech, dims, th0, omega = fourbar_mech.with_params(), (0.8, 2.5, 2.0, 3.0), \
                math.pi / 3, TWO_PI
        for mode in (1, -1):
            exact = fourbar_closed(dims, th0 + omega * t, mode)
            if exact is None or abs(mech.pivot_ratio(exact, t)) < 1e-3:
                continue
            for shift in (0, 1, -1, 2):
                guess = exact.copy()
                guess[FB_ANGLES] = wrap(guess[FB_ANGLES]) + TWO_PI * shift * \
                    rng.integers(-1, 2, size=3)
                for method in ("auto", "sorted", "full"):
                    s = mech.solve(t, guess=guess, method=method)
                    err = close(s.q, exact, FB_ANGLES, 0)
                    if err > 1e-10 or abs(s.q[2] - (th0 + omega * t)) > 1e-10:
                        wrong.append((k, t, mode, shift, method, err))
    assert wrong == []


def test_unwrap_turns_on_the_library_toy():
    """The library's unwrap_turns on the toy crank-slider (th driven, ph an angle that no
    linear row holds, x a length): th comes back to the driver's value, ph and x stay."""
    from mechgen.compiler.library import solve, toy
    p = np.array([1.0, 2.0, 1.0])
    t = 7.3
    th = p[2] * t
    ph = math.asin(-p[0] * math.sin(th) / p[1])
    x = p[0] * math.cos(th) + p[1] * math.cos(ph)
    for k in (-2, -1, 1, 3):
        q = np.array([th + TWO_PI * k, ph + TWO_PI, x + TWO_PI])
        assert solve.unwrap_turns(q, t, p) == 1
        assert q[0] == pytest.approx(th, abs=1e-12)
        assert q[1] == ph + TWO_PI and q[2] == x + TWO_PI
    q = np.array([th, ph, x])
    assert solve.unwrap_turns(q, t, p) == 0 and q[0] == th
    assert toy.N_COORDS == 3


# -- a geared five-bar: two cranks on gears of ratio −2, couplers 3 and 3 joined at P --------
GEARED = '''
from mechgen import Model, T, pi
m = Model("geared_fivebar")
l1 = m.param("l1", 1.0)
l2 = m.param("l2", 0.5)
ground = m.ground("ground", points=[(0, 0), (3, 0)])
gA = m.body("gA", points=[(0, 0), (l1, 0)], guess=(0, 0, 0))
gB = m.body("gB", points=[(0, 0), (l2, 0)], guess=(3, 0, 0))
c1 = m.body("c1", points=[(0, 0), (3, 0)], guess=(1, 0, 1.1))
c2 = m.body("c2", points=[(0, 0), (3, 0)], guess=(3.5, 0, 2.0))
m.revolute(ground[1], gA[1])
m.revolute(ground[2], gB[1])
m.gear_ratio(gA[1], 2, gB[1], 1, name="mesh")
m.rotation_lock(gA, 2 * pi * T, name="drive")
m.revolute(gA[2], c1[1])
m.revolute(gB[2], c2[1])
m.revolute(c1[2], c2[2])
'''
GEARED_ANGLES = [2, 5, 8, 11]


def geared_closed(t, mode=1):
    """Gear A (pitch radius 2 at the origin) turns 2πt; gear B (radius 1 at (3, 0))
    meshes with it, θB = −2 θA; P to the left of crank pin A → crank pin B (mode +1)."""
    tha = TWO_PI * t
    thb = -2.0 * tha
    A = np.array([math.cos(tha), math.sin(tha)])
    B = np.array([3 + 0.5 * math.cos(thb), 0.5 * math.sin(thb)])
    P = circles(A, 3.0, B, 3.0, mode)
    return np.array([0, 0, tha, 3, 0, thb, A[0], A[1], angle(P - A), B[0], B[1],
                     angle(P - B)])


# -- a disc cam (an eccentric circle) driving a roller-follower arm ----------------------
CAM = '''
from mechgen import Model, T, cos, pi, sin
m = Model("cam_arm")
ground = m.ground("ground", points=[(0, 0), (4, 3)])
cam = m.body("cam", guess=(0, 0, 0))
arm = m.body("arm", points=[(0, 0), (3.5, 0)], guess=(4, 3, -2.2))
m.revolute(ground[1], cam[0])
m.rotation_lock(cam, 2 * pi * T, name="cam angle")
m.revolute(ground[2], arm[1])
disc = m.profile("disc", xy=lambda s: (0.5 + 2 * cos(s), 2 * sin(s)))
m.cam_to_point(cam, disc, arm[2], contact="s", guess=0.6, radius=0.5)
'''


def cam_closed(t, mode):
    """The cam turns θ = 2πt about the origin; its disc's centre is C = 0.5 (cos θ,
    sin θ), the roller's centre R + ρ = 2.5 from C and 3.5 from the arm's pivot G = (4, 3):
    the intersection to the right (mode −1) or left of C → G. s: the contact angle on the
    disc, in the cam's frame."""
    th = TWO_PI * t
    C = 0.5 * np.array([math.cos(th), math.sin(th)])
    G = np.array([4.0, 3.0])
    R = circles(C, 2.5, G, 3.5, mode)
    return {"Th2": th, "X3": 4.0, "Y3": 3.0, "Th3": angle(R - G), "s": angle(R - C) - th}


def build(tmp_path_factory, name, text):
    path = tmp_path_factory.mktemp(name) / f"{name}.py"
    path.write_text(textwrap.dedent(text))
    return str(path)


@pytest.fixture(scope="module")
def geared_file(tmp_path_factory):
    return build(tmp_path_factory, "geared_fivebar", GEARED)


@pytest.fixture(scope="module")
def cam_file(tmp_path_factory):
    return build(tmp_path_factory, "cam_arm", CAM)


def test_geared_fivebar_single_solves_stay_in_mesh(geared_file, tmp_path):
    mech = mechgen.compile(geared_file, outdir=str(tmp_path), tier="python")
    assert close(mech.solve(0.0).q, geared_closed(0.0), GEARED_ANGLES, 0) <= 1e-10
    rng = np.random.default_rng(62)
    wrong = 0
    for t in rng.uniform(-2, 2, size=100):
        wrong += close(mech.solve(float(t)).q, geared_closed(t), GEARED_ANGLES, 0) > 1e-9
    assert wrong == 0


def test_cam_arm_single_solves_keep_the_roller_on_its_side(cam_file, tmp_path):
    mech = mechgen.compile(cam_file, outdir=str(tmp_path), tier="python")
    names = ("Th2", "X3", "Y3", "Th3", "s")
    at = [mech.coordinates.index(n) for n in names]
    s0 = mech.solve(0.0)
    mode = 1 if abs(wrap(s0["Th3"] - cam_closed(0.0, 1)["Th3"])) < 1e-9 else -1
    assert abs(wrap(s0["Th3"] - cam_closed(0.0, mode)["Th3"])) < 1e-9
    rng = np.random.default_rng(37)
    wrong = 0
    for t in rng.uniform(-2, 2, size=100):
        exact = cam_closed(t, mode)
        q = mech.solve(float(t)).q
        wrong += close(q[at], np.array([exact[n] for n in names]), [0, 3, 4], 0) > 1e-9
    assert wrong == 0


def test_cli_solve_and_draw_follow_the_motion(geared_file, tmp_path, monkeypatch, capsys):
    """`mechgen solve` prints the configuration on the guess's mode at a time where a
    Newton from the guess lands half a turn out of mesh; `draw` takes the same solve."""
    from mechgen.cli import main
    monkeypatch.setenv("MECHGEN_TIER", "python")
    t = 0.3711
    exact = geared_closed(t)
    assert main(["solve", geared_file, "-t", str(t), "--outdir", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    for k, name in ((5, "Th3"), (8, "Th4"), (11, "Th5")):
        value = float(out.split(name, 1)[1].split("->", 1)[1].split()[0])
        assert abs(wrap(value - exact[k])) < 1e-6, (name, value, exact[k])
    calls = []
    real = mechgen.runtime.mechanism.Mechanism.solve

    def spy(self, t, guess=None, **kw):
        calls.append(guess)
        return real(self, t, guess=guess, **kw)
    monkeypatch.setattr(mechgen.runtime.mechanism.Mechanism, "solve", spy)
    png = tmp_path / "g.png"
    assert main(["draw", geared_file, "-t", str(t), "-o", str(png),
                 "--outdir", str(tmp_path)]) == 0
    assert png.exists() and calls == [None]


def test_a_time_too_far_from_the_guess_is_refused_before_any_work(fourbar_mech):
    mech = fourbar_mech.with_params()
    with pytest.raises(ValueError, match=r"solve\(t=1000000\).*farther.*guess near t"):
        mech.solve(1e6)
    assert mech.state.path is None or mech.state.path.count == {1: 0, -1: 0}


def test_an_unsorted_build_keeps_the_mode_too(tmp_path):
    """A --no-sort build solves by the full Newton alone: an explicit guess off by whole
    turns, and solve(t) following the motion, stay on the mode."""
    from conftest import example_model
    from mechgen.compiler.build import build
    mech = mechgen.load(build(example_model("fourbar"), str(tmp_path), sort=False),
                        tier="python")
    assert not mech.module.SORTED
    dims = (0.8, 2.5, 2.0, 3.0)
    rng = np.random.default_rng(7)
    for t in np.concatenate([[1.25], rng.uniform(-2, 2, size=12)]):
        for mode in (1, -1):
            exact = fourbar_closed(dims, math.pi / 3 + TWO_PI * t, mode)
            guess = exact.copy()
            guess[FB_ANGLES] = wrap(guess[FB_ANGLES]) + TWO_PI * rng.integers(-1, 2, size=3)
            assert close(mech.solve(t, guess=guess).q, exact, FB_ANGLES, 0) <= 1e-10
        assert close(mech.solve(t).q, fourbar_closed(dims, math.pi / 3 + TWO_PI * t, 1),
                     FB_ANGLES, 0) <= 1e-10


@pytest.mark.parametrize("code", ["JUMP", "THROUGH_SINGULAR"])
def test_a_flagged_step_on_the_way_is_said(fourbar_mech, monkeypatch, code):
    """Where the careful sweep (after the quick path, which hands a hard point to it) marks
    a point reached by a jump it could not avoid, the solve raises; a singular
    configuration passed on the way is a BranchJumpWarning."""
    from mechgen import protocol
    from mechgen.errors import BranchJumpWarning
    mech = fourbar_mech.with_params()
    real = mech.module.sweep

    def flagged(ts, q0, p, level, tol, xtol, maxit, method, Q, QD, QDD, S, report):
        done = real(ts, q0, p, level, tol, xtol, maxit, method, Q, QD, QDD, S, report)
        S[done - 1, protocol.STATUS_CODE] = getattr(protocol, code)
        report[protocol.REPORT_JUMP] = 0.5
        return done
    monkeypatch.setattr(mech.module, "sweep", flagged)
    # the quick path finds the way hard from its first point: the careful sweep goes
    monkeypatch.setattr(mech.module, "sweep_fast", lambda *args: 0)
    if code == "JUMP":
        with pytest.raises(SolveError, match=r"solve\(t=0.3\).*could not keep the assembly"):
            mech.solve(0.3)
    else:
        with pytest.warns(BranchJumpWarning, match=r"solve\(t=0.3\).*singular configuration"):
            s = mech.solve(0.3)
        exact = fourbar_closed((0.8, 2.5, 2.0, 3.0), math.pi / 3 + TWO_PI * 0.3, 1)
        assert close(s.q, exact, FB_ANGLES, 0) <= 1e-10
