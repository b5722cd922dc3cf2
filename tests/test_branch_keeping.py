"""Every accepted point of a sweep lies on the branch of the point before: the signs of
Φ_q's blocks (det Φ_q and the pattern of its blocks' signs, jacobian_det) are watched at
every point, whatever the size of the blocks. Checked against closed forms written here."""
import math
import textwrap
import warnings

import numpy as np
import pytest

import mechgen

# issue 20's reproducer: an offset slider-crank driven by its slider (crank a = 1, rod
# b = 3.2, slider on y = e = 0.4) pushed to and fro so hard (θ̈ = -913 at the start) that
# a coarse sweep's predictor lands near the other assembly mode
A, B, E = 1.0, 3.2, 0.4
TH0 = 0.5 + math.pi / 2 - 0.5625 * math.pi
X0 = math.cos(TH0) + math.sqrt(B ** 2 - (math.sin(TH0) - E) ** 2)
SLIDER_CRANK = f'''
from mechgen import Model, T, pi, sin
m = Model("offset_slider_crank_driven")
g = m.ground("g", points=[(0, 0)])
crank = m.body("crank", points=[(0, 0), ({A}, 0)], guess=(0, 0, 0.3))
rod = m.body("rod", points=[(0, 0), ({B}, 0)], guess=(0.95, 0.3, 0.0))
slider = m.body("slider", points=[(0, 0)], guess=(4.1, {E}, 0))
m.revolute(g[1], crank[1])
m.revolute(crank[2], rod[1])
m.revolute(rod[2], slider[1])
m.relative_y(slider[1], {E})
m.rotation_lock(slider, 0)
m.relative_x(slider[1], {X0!r} - 0.6 * sin(2 * pi * T), name="slider driver")
'''


def crank_angle(t, sign=1.0):
    """The crank angle on the branch of θ(0) = TH0 (the crank above the rod's line):
    (x - cos θ)² + (e - sin θ)² = b² is R cos(θ - φ) = C, and θ = φ + acos(C / R)
    along the whole motion (the slider never reaches a dead centre); sign -1: the other
    assembly mode, θ = φ - acos(C / R)."""
    x = X0 - 0.6 * np.sin(2 * np.pi * np.asarray(t))
    R, phi = np.hypot(x, E), np.arctan2(E, x)
    C = (x ** 2 + A ** 2 + E ** 2 - B ** 2) / 2
    return phi + sign * np.arccos(C / R)


@pytest.fixture(scope="module")
def slider_crank(tmp_path_factory):
    path = tmp_path_factory.mktemp("branch") / "offset_slider_crank.py"
    path.write_text(textwrap.dedent(SLIDER_CRANK))
    # plain Python: the branch is kept by the module's text (the same numbers as numba's),
    # and 36 sweeps of it cost less than compiling it (~15 s of CPU)
    return mechgen.compile(str(path), outdir=str(path.parent), tier="python")


def test_the_closed_form_is_the_branch_of_the_start():
    assert crank_angle(0.0) == pytest.approx(TH0, abs=1e-12)


@pytest.mark.parametrize("method", [None, "sorted", "full"])
@pytest.mark.parametrize("level", ["position", "velocity", "acceleration"])
@pytest.mark.parametrize("n", [5, 9, 17, 40])
def test_a_coarse_sweep_never_takes_the_other_mode(slider_crank, method, level, n):
    mech = slider_crank
    start = mech.solve(0.0, level="acceleration")
    assert start["Th2"] == pytest.approx(TH0, abs=1e-9)
    assert start["Th2dd"] == pytest.approx(-913.0, abs=0.5)     # as the issue says
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sw = mech.sweep(0.0, 0.45, n, level=level, guess=start, method=method)
    ok = np.asarray(sw.status).reshape(-1) == 0
    want = crank_angle(sw.t)
    err = np.abs((sw["Th2"] - want + np.pi) % (2 * np.pi) - np.pi)
    assert ok.all()                     # every point on the branch is reachable ...
    assert err.max() < 1e-9             # ... and reached


def test_the_fast_pass_reports_the_det_of_a_block_of_four(slider_crank):
    """derivatives_sorted's piv: det Φ_q (here one Newton block of four unknowns, whose
    det used to be NaN) equal to jacobian_det's, and the blocks' sign pattern."""
    mod, p = slider_crank.module, slider_crank.p
    n = len(slider_crank.coordinates)
    for t in np.linspace(0.0, 0.45, 7):
        for sign in (1.0, -1.0):
            s = slider_crank.solve(t, guess={"Th2": crank_angle(t, sign)})
            assert s["Th2"] == pytest.approx(crank_angle(t, sign), abs=1e-9)
            q = np.array([s[c] for c in slider_crank.coordinates])
            piv, pj = np.zeros(2), np.zeros(2)
            assert mod.derivatives_sorted(q.copy(), t, p, np.zeros(n), np.zeros(n), piv) == 0
            det = mod.jacobian_det(q, t, p, pj)
            assert np.isfinite(piv[0]) and piv[0] == pytest.approx(det, rel=1e-10)
            assert piv[1] == pj[1] == (1.0 if det < 0 else 0.0)


SIX_BAR = '''
from mechgen import Model, T, pi
m = Model("six_bar_two_dyads")
g = m.ground("g", points=[(0, 0), (3, 0), (1, 3)])
crank = m.body("crank", points=[(0, 0), (1, 0)], guess=(0, 0, 0.5))
coupler = m.body("coupler", points=[(0, 0), (3, 0), (1.5, 0.8)], guess=(0.9, 0.5, 0.3))
rocker = m.body("rocker", points=[(0, 0), (2.5, 0)], guess=(3, 0, 1.6))
link5 = m.body("link5", points=[(0, 0), (2.2, 0)], guess=(2.3, 1.9, 1.0))
link6 = m.body("link6", points=[(0, 0), (2.0, 0)], guess=(1, 3, -0.3))
m.revolute(g[1], crank[1])
m.revolute(crank[2], coupler[1])
m.revolute(g[2], rocker[1])
m.revolute(coupler[2], rocker[2])
m.revolute(coupler[3], link5[1])
m.revolute(g[3], link6[1])
m.revolute(link5[2], link6[2])
m.rotation_lock(crank, 0.6 + 2 * pi * T, name="crank angle")
'''


def _circles(p1, r1, p2, r2, sign):
    """The intersection of circle (p1, r1) and circle (p2, r2) on side ``sign`` of p1→p2."""
    d = np.subtract(p2, p1)
    L = math.hypot(*d)
    a = (r1 ** 2 - r2 ** 2 + L ** 2) / (2 * L)
    h = math.sqrt(r1 ** 2 - a ** 2)
    u = d / L
    return np.array(p1) + a * u + sign * h * np.array([-u[1], u[0]])


def _six_bar_pose(th, s1, s2):
    """Body angles of the six-bar at crank angle th, dyad signs s1 and s2 (closed form)."""
    A = np.array([math.cos(th), math.sin(th)])
    C = _circles(A, 3.0, (3.0, 0.0), 2.5, s1)
    th3 = math.atan2(*(C - A)[::-1])
    th4 = math.atan2(*(C - (3.0, 0.0))[::-1])
    P = A + np.array([[math.cos(th3), -math.sin(th3)], [math.sin(th3), math.cos(th3)]]) @ (1.5, 0.8)
    D = _circles(P, 2.2, (1.0, 3.0), 2.0, s2)
    th5 = math.atan2(*(D - P)[::-1])
    th6 = math.atan2(*(D - (1.0, 3.0))[::-1])
    return {"Th2": th, "X3": A[0], "Y3": A[1], "Th3": th3, "X4": 3.0, "Y4": 0.0, "Th4": th4,
            "X5": P[0], "Y5": P[1], "Th5": th5, "X6": 1.0, "Y6": 3.0, "Th6": th6}


def test_each_assembly_mode_of_a_six_bar_has_its_own_sign_pattern(tmp_path):
    """Two dyads, four modes: det Φ_q's sign alone cannot tell (+, +) from (-, -), the
    pattern of the blocks' signs tells all four apart (a jump of both dyads in one step
    changes it)."""
    path = tmp_path / "six_bar.py"
    path.write_text(textwrap.dedent(SIX_BAR))
    mech = mechgen.compile(str(path), outdir=str(tmp_path), tier="python")
    t = 0.1
    seen = {}
    for s1 in (1, -1):
        for s2 in (1, -1):
            pose = _six_bar_pose(0.6 + 2 * math.pi * t, s1, s2)
            s = mech.solve(t, guess={k: v for k, v in pose.items() if k in mech.coordinates})
            for k in ("Th3", "Th4", "Th5", "Th6"):
                assert abs((s[k] - pose[k] + math.pi) % (2 * math.pi) - math.pi) < 1e-9
            q = np.array([s[c] for c in mech.coordinates])
            piv = np.zeros(2)
            seen[s1, s2] = (np.sign(mech.module.jacobian_det(q, t, mech.p, piv)), piv[1])
    assert seen[1, 1][0] == seen[-1, -1][0]             # the product alone: the same sign
    assert len({pattern for _, pattern in seen.values()}) == 4


def test_newton_from_a_poor_guess_keeps_its_angles_near_the_guess(fourbar):
    """From a guess with every link in a line, Newton's first step throws the coupler's
    angle some 2e8 rad away (where a float keeps 3e-8 of it): the solve brings the angles
    back by whole turns and solves again, to the closed form's full precision."""
    m = fourbar.with_params(a=1.0, b=2.0, c=1.3, d=2.0, theta2=0.0, omega=-1.0)
    guess = np.zeros(len(m.coordinates))
    guess[m.coordinates.index("Th4")] = 7.547137326712447e-10
    s = m.solve(0.0, guess=guess)
    # the closed form: crank pin (1, 0), rocker pivot (2, 0); C at distance 2 and 1.3
    x = (2.0 ** 2 - 1.3 ** 2 + 1.0) / 2.0
    y = math.sqrt(2.0 ** 2 - x ** 2)
    modes = [(math.atan2(sg * y, x), math.atan2(sg * y, 1.0 + x - 2.0)) for sg in (1, -1)]
    assert abs(s["Th3"]) < math.pi and abs(s["Th4"]) < math.pi
    assert min(abs(s["Th3"] - th3) + abs(s["Th4"] - th4) for th3, th4 in modes) < 1e-12
