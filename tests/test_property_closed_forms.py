"""Property-based tests (hypothesis): random Grashof four-bars and offset slider-cranks
against their closed forms over whole crank cycles (positions, velocities,
accelerations), and random inputs that cannot assemble, which must raise.

The dimensions reach close to a toggle (a margin from the Grashof or the rod's limit drawn
down to 1e-5 of the link lengths), where the two assembly modes nearly meet. A point with
status OK must be the closed form's; a solve may refuse (raise, or flag a point JUMP or
THROUGH_SINGULAR) only where the closed form says the configuration is near-singular
(NEAR_SINGULAR), and at most MAX_REFUSED of a test's examples may refuse.

Each topology is a mechgen Model built once into a temporary folder and run on the
plain-Python tier (the generated text, the same numbers as numba's: tests/test_tiers.py;
~35 s of CPU less than compiling both); every example only changes parameters
(mech.with_params). Run with ``-s`` to see how many random
mechanisms and configurations were checked."""
import math
import warnings

import numpy as np
import pytest
import sympy as sp
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import mechgen
import models
from mechgen.protocol import OK

COUNTS = {"four-bars": 0, "slider-cranks": 0, "configurations": 0,
          "single solves": 0, "single solves refused": 0,
          "non-assemblable inputs": 0, "non-assemblable refused": 0}
SETTINGS = settings(max_examples=25, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow])
NEAR_SINGULAR = 0.02    # |sin| of the transmission angle (four-bar), |cos| of the rod's (slider)
MAX_REFUSED = 5         # of a test's 25 examples
REFUSED = {}            # test name -> examples refused


@pytest.fixture(scope="module", autouse=True)
def report_counts():
    yield
    print("\nproperty tests: " + ", ".join(f"{k} {v}" for k, v in COUNTS.items()))
    print("refusals: " + (", ".join(f"{k} {v}" for k, v in REFUSED.items()) or "none"))


# -- the models ---------------------------------------------------------------------------
def fourbar_model():
    from mechgen import Model, T
    m = Model("prop_fourbar")
    a, b, c, d = (m.param(n, v) for n, v in (("a", 0.8), ("b", 2.5), ("c", 2.0), ("d", 3.0)))
    th0, w = m.param("theta0", 1.0), m.param("omega", 6.0)
    ground = m.ground("ground", points=[(0, 0), (d, 0)])
    crank = m.body("crank", points=[(0, 0), (a, 0)], guess=(0, 0, 1.0))
    coupler = m.body("coupler", points=[(0, 0), (b, 0)], guess=(0.4, 0.7, 0.5))
    rocker = m.body("rocker", points=[(0, 0), (c, 0)], guess=(3, 0, 1.8))
    m.revolute(ground[1], crank[1])
    m.revolute(crank[2], coupler[1])
    m.revolute(ground[2], rocker[1])
    m.revolute(coupler[2], rocker[2])
    m.rotation_lock(crank, th0 + w * T, name="crank")
    return m


def slider_crank_model():
    """tests/models.py's offset slider-crank, every length, the offset, θ0 and ω parameters
    a, b, e, theta0, omega."""
    return models.slider_crank("prop_slider_crank", 1.0, 3.0, 0.2, 0.0, 6.0,
                               params={"r": "a", "l": "b", "e": "e", "theta0": "theta0",
                                       "omega": "omega"}).m


@pytest.fixture(scope="module")
def mechs(tmp_path_factory):
    from mechgen.compiler.build import build
    out = str(tmp_path_factory.mktemp("property_models"))
    return {"fourbar": mechgen.load(build(fourbar_model(), out), tier="python"),
            "slider": mechgen.load(build(slider_crank_model(), out), tier="python")}


# -- closed forms (sympy, differentiated in time, lambdified once) ------------------------------
def _closed_forms():
    a, b, c, d, e, th0, w, t, sg = sp.symbols("a b c d e theta0 omega t sigma", real=True)
    th = th0 + w * t
    # four-bar: C is where the circles about B (radius b) and D (radius c) meet
    Bx, By = a * sp.cos(th), a * sp.sin(th)
    ex, ey = d - Bx, -By
    L = sp.sqrt(ex ** 2 + ey ** 2)
    x = (b ** 2 - c ** 2 + L ** 2) / (2 * L)
    y = sg * sp.sqrt(b ** 2 - x ** 2)
    Cx, Cy = Bx + (x * ex - y * ey) / L, By + (x * ey + y * ex) / L
    fb = [sp.S(0), sp.S(0), th, Bx, By, sp.atan2(Cy - By, Cx - Bx), d + 0 * t, sp.S(0),
          sp.atan2(Cy, Cx - d)]
    # offset slider-crank: the rod from the crank pin to the slider on the line y = e
    s = e - a * sp.sin(th)
    r = sp.sqrt(b ** 2 - s ** 2)
    sc = [sp.S(0), sp.S(0), th, a * sp.cos(th), a * sp.sin(th), sp.atan2(s, sg * r),
          a * sp.cos(th) + sg * r, e + 0 * t, sp.S(0)]
    out = {}
    for name, q, args in (("fourbar", fb, (a, b, c, d, th0, w, sg, t)),
                          ("slider", sc, (a, b, e, th0, w, sg, t))):
        levels = [q, [sp.diff(x, t) for x in q], [sp.diff(x, t, 2) for x in q]]
        out[name] = [sp.lambdify(args, lev, "numpy") for lev in levels]
    return out


CLOSED = _closed_forms()
ANGLES = np.array([False, False, True, False, False, True, False, False, True])


def exact(name, params, sigma, t):
    """(Q, QD, QDD) of the closed form at times t, arrays (len(t), 9)."""
    args = [params[k] for k in (("a", "b", "c", "d") if name == "fourbar" else ("a", "b", "e"))]
    args += [params["theta0"], params["omega"], sigma]
    res = []
    for f in CLOSED[name]:
        cols = [np.broadcast_to(np.asarray(v, dtype=float), t.shape) for v in f(*args, t)]
        res.append(np.stack(cols, axis=1))
    return res


def conditioning(name, params, t):
    """How far from singular the closed form's configuration is at times t (1: far, 0: the
    two assembly modes meet and Φ_q loses rank): |sin μ| of the four-bar's transmission
    angle μ between coupler and rocker; |cos| of the slider-crank rod's angle to the guide."""
    th = params["theta0"] + params["omega"] * np.asarray(t, dtype=float)
    a, b = params["a"], params["b"]
    if name == "fourbar":
        c, d = params["c"], params["d"]
        L2 = (d - a * np.cos(th)) ** 2 + (a * np.sin(th)) ** 2
        cos_mu = np.clip((b * b + c * c - L2) / (2 * b * c), -1.0, 1.0)
        return np.sqrt(1.0 - cos_mu ** 2)
    s = np.clip((params["e"] - a * np.sin(th)) / b, -1.0, 1.0)
    return np.sqrt(1.0 - s ** 2)


def refuse(test, why):
    """A refusal, counted per test; more than MAX_REFUSED fail the test."""
    REFUSED[test] = REFUSED.get(test, 0) + 1
    assert REFUSED[test] <= MAX_REFUSED, f"{test}: {REFUSED[test]} refusals ({why})"


def check_sweep(mech, name, params, sigma, n=97, test=""):
    """A whole crank cycle from the closed form's start. Every point up to a refusal must
    match; a refusal (raised, or a point flagged) only near a singular configuration."""
    period = 2 * math.pi / abs(params["omega"])
    q0 = exact(name, params, sigma, np.array([0.0]))[0][0]
    guess = q0 + 1e-4 * np.where(ANGLES, 1.0, 0.0)
    m = mech.with_params(**params)
    step = period / (n - 1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", mechgen.BranchJumpWarning)   # the flags say it too
        try:
            sw = m.sweep(0.0, period, n, level="acceleration", guess=guess)
        except mechgen.SolveError as exc:
            sw = exc.sweep                  # the points it accepted before it stopped
            t_stop = sw.t[-1] + step if len(sw) else 0.0
            near = conditioning(name, params, np.linspace(t_stop - step, t_stop, 33)).min()
            assert near < NEAR_SINGULAR, (f"refused at t={t_stop} where the closed form is "
                                          f"regular (conditioning {near:.3g})", params, sigma)
            refuse(test, f"raised near t={t_stop}")
    t, Q_, QD_, QDD_ = sw.t, sw.Q, sw.QD, sw.QDD
    flagged = np.nonzero(sw.status != OK)[0]
    if len(flagged):                        # flagged: must be near a singular configuration
        k = flagged[0]
        near = conditioning(name, params, np.linspace(t[max(k - 1, 0)], t[k], 33)).min()
        assert near < NEAR_SINGULAR, (f"point {k} flagged {sw.status[k]} where the closed "
                                      f"form is regular (conditioning {near:.3g})", params, sigma)
        refuse(test, f"flagged at t={t[k]}")
        t, Q_, QD_, QDD_ = t[:k], Q_[:k], QD_[:k], QDD_[:k]   # the points before must be right
    if not len(t):
        return
    Q, QD, QDD = exact(name, params, sigma, t)
    dq = Q_ - Q
    dq[:, ANGLES] = np.remainder(dq[:, ANGLES] + np.pi, 2 * np.pi) - np.pi
    vscale = 1.0 + np.abs(QD).max()
    ascale = 1.0 + np.abs(QDD).max()
    assert np.abs(dq).max() < 1e-8, (np.abs(dq).max(), params, sigma)
    assert np.abs(QD_ - QD).max() < 1e-8 * vscale, (params, sigma)
    assert np.abs(QDD_ - QDD).max() < 1e-7 * ascale, (params, sigma)
    # angles continuous along the sweep: the crank exactly θ0 + ωt, no wrapping
    assert np.abs(Q_[:, 2] - (params["theta0"] + params["omega"] * t)).max() < 1e-9
    assert np.abs(np.diff(Q_[:, ANGLES], axis=0)).max(initial=0.0) < math.pi / 2
    COUNTS["configurations"] += len(t)


# -- strategies -------------------------------------------------------------------------------
def margin(draw):
    """How far from a toggle (a fraction of the lengths): 1e-5 to 3e-2, log-uniform."""
    return 10.0 ** draw(st.floats(-5.0, -1.5))


@st.composite
def grashof_fourbars(draw):
    """Crank-rockers: the crank a is the shortest link and s + l < p + q. The rocker c at
    either edge of its range (a margin from a toggle: b + c or |b - c| reaches the crank
    pin's extreme distance from the rocker's pivot, d ± a) or anywhere inside it."""
    a = draw(st.floats(0.2, 1.0))
    b = draw(st.floats(a + 0.3, 4.0))
    d = draw(st.floats(a + 0.3, 4.0))
    gap = margin(draw) * (b + d)
    lo, hi = max(a + 0.3, a + abs(b - d) + gap), b + d - a - gap
    assume(hi > lo)
    where = draw(st.sampled_from(["low edge", "high edge", "inside"]))
    c = lo if where == "low edge" else hi if where == "high edge" else \
        lo + draw(st.floats(0.0, 1.0)) * (hi - lo)
    return dict(a=a, b=b, c=c, d=d, theta0=draw(st.floats(-math.pi, math.pi)),
                omega=draw(st.sampled_from([-1.0, 1.0])) * draw(st.floats(0.5, 12.0)))


@st.composite
def slider_cranks(draw, near=False):
    """Full-turning offset slider-cranks: b > a + |e| by 0.05 a to 3 a, or (near) by a
    margin down to 1e-5 a (at the crank pin's farthest point from the guide the rod is
    then nearly square to it)."""
    a = draw(st.floats(0.2, 2.0))
    e = draw(st.floats(-1.0, 1.0)) * a
    b = a + abs(e) + (margin(draw) if near else draw(st.floats(0.05, 3.0))) * a
    return dict(a=a, b=b, e=e, theta0=draw(st.floats(-math.pi, math.pi)),
                omega=draw(st.sampled_from([-1.0, 1.0])) * draw(st.floats(0.5, 12.0)))


# -- whole cycles against the closed forms ---------------------------------------------------------
@SETTINGS
@given(params=grashof_fourbars(), sigma=st.sampled_from([1.0, -1.0]))
def test_random_grashof_fourbars_match_closed_form(mechs, params, sigma):
    check_sweep(mechs["fourbar"], "fourbar", params, sigma, test="four-bar sweeps")
    COUNTS["four-bars"] += 1


@SETTINGS
@given(params=slider_cranks(), sigma=st.sampled_from([1.0, -1.0]))
def test_random_slider_cranks_match_closed_form(mechs, params, sigma):
    check_sweep(mechs["slider"], "slider", params, sigma, test="slider-crank sweeps")
    COUNTS["slider-cranks"] += 1


@SETTINGS
@given(params=slider_cranks(near=True), sigma=st.sampled_from([1.0, -1.0]))
def test_random_slider_cranks_near_a_toggle_match_closed_form(mechs, params, sigma):
    check_sweep(mechs["slider"], "slider", params, sigma, test="slider-crank sweeps near a toggle")
    COUNTS["slider-cranks"] += 1


@st.composite
def solve_times(draw, params):
    """Any time, or one within a small angle of the crank angles 0 and π (mod 2π), where the
    crank pin is nearest to and farthest from the rocker's pivot: the toggles' angles."""
    if draw(st.booleans()):
        return draw(st.floats(0.0, 1.0))
    angle = draw(st.sampled_from([0.0, math.pi])) + draw(st.floats(-0.05, 0.05))
    return (angle - params["theta0"]) / params["omega"]


def closed_form_mode(params, t, s):
    """Which of the closed form's two assembly modes (σ = ±1) the solution s is, or None."""
    for sigma in (1.0, -1.0):
        Q, QD, QDD = (x[0] for x in exact("fourbar", params, sigma, np.array([t])))
        dq = s.q - Q
        dq[ANGLES] = np.remainder(dq[ANGLES] + np.pi, 2 * np.pi) - np.pi
        if np.abs(dq).max() < 1e-8 and np.abs(s.qd - QD).max() < 1e-8 * (1 + np.abs(QD).max()) \
                and np.abs(s.qdd - QDD).max() < 1e-7 * (1 + np.abs(QDD).max()):
            return sigma
    return None


@SETTINGS
@given(data=st.data(), params=grashof_fourbars(), sigma=st.sampled_from([1.0, -1.0]),
       guess=st.lists(st.floats(-4.0, 4.0), min_size=9, max_size=9))
def test_single_solves_are_right_or_refused(mechs, data, params, sigma, guess):
    """From an arbitrary guess a solve returns one of the two assembly modes of the closed
    form, or refuses. From a guess within 0.05 rad of mode σ it returns mode σ (either
    mode where the closed form is near-singular: the modes meet there), and refuses only
    there."""
    t = data.draw(solve_times(params), label="t")
    m = mechs["fourbar"].with_params(**params)
    COUNTS["single solves"] += 1
    try:
        s = m.solve(t, guess=np.array(guess), level="acceleration")
        assert closed_form_mode(params, t, s) is not None, (params, t, s.q)
    except mechgen.SolveError:
        # Newton may fail from a poor guess (all links in a line, say): counted, not
        # bounded (hypothesis replays examples while it shrinks a failure elsewhere)
        COUNTS["single solves refused"] += 1
    near = exact("fourbar", params, sigma, np.array([t]))[0][0] + np.where(ANGLES, 0.05, 0.0)
    try:
        s = m.solve(t, guess=near, level="acceleration")
    except mechgen.SolveError as exc:
        cond = float(conditioning("fourbar", params, t))
        assert cond < NEAR_SINGULAR, (f"refused where the closed form is regular "
                                      f"(conditioning {cond:.3g}): {exc}", params, t)
        refuse("single solves from a near guess", f"t={t}")
        COUNTS["single solves refused"] += 1
        return
    got = closed_form_mode(params, t, s)
    if float(conditioning("fourbar", params, t)) < NEAR_SINGULAR:
        assert got is not None, (params, t, s.q)    # the modes are closer than the guess's
    else:                                           # 0.05 rad there: either one is right
        assert got == sigma, (params, t, sigma, s.q)


# -- inputs that cannot assemble ------------------------------------------------------------------
@SETTINGS
@given(a=st.floats(0.2, 3.0), b=st.floats(0.2, 3.0), c=st.floats(0.2, 3.0), d=st.floats(0.2, 3.0),
       th=st.floats(-math.pi, math.pi), guess=st.lists(st.floats(-3.0, 3.0), min_size=9, max_size=9))
def test_fourbars_that_cannot_assemble_raise(mechs, a, b, c, d, th, guess):
    L = math.hypot(d - a * math.cos(th), a * math.sin(th))
    assume(L > (b + c) * 1.001 or L < abs(b - c) * 0.999)
    m = mechs["fourbar"].with_params(a=a, b=b, c=c, d=d, theta0=th, omega=0.0)
    for g in (None, np.array(guess)):
        COUNTS["non-assemblable inputs"] += 1
        with pytest.raises((mechgen.ConvergenceError, mechgen.SingularError)):
            m.solve(0.0, guess=g)
        COUNTS["non-assemblable refused"] += 1
    with pytest.raises((mechgen.ConvergenceError, mechgen.SingularError)) as info:
        m.sweep(0.0, 1.0, 5)
    assert len(info.value.sweep) == 0


@SETTINGS
@given(params=slider_cranks(), shrink=st.floats(0.05, 0.95), t=st.floats(0.0, 1.0))
def test_slider_cranks_with_too_short_a_rod_raise(mechs, params, shrink, t):
    """A rod shorter than the crank pin's distance from the guide: no assembly at t."""
    th = params["theta0"] + params["omega"] * t
    gap = abs(params["e"] - params["a"] * math.sin(th))
    assume(gap > 0.05)
    params = dict(params, b=shrink * gap)
    m = mechs["slider"].with_params(**params)
    COUNTS["non-assemblable inputs"] += 1
    with pytest.raises((mechgen.ConvergenceError, mechgen.SingularError)):
        m.solve(t)
    COUNTS["non-assemblable refused"] += 1
