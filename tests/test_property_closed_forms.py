"""Property-based tests (hypothesis): random Grashof four-bars and offset slider-cranks
against their closed forms over whole crank cycles (positions, velocities,
accelerations), and random inputs that cannot assemble, which must raise.

Each topology is a mechgen Model compiled once into a temporary folder; every example
only changes parameters (mech.with_params). Run with ``-s`` to see how many random
mechanisms and configurations were checked."""
import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import mechgen

COUNTS = {"four-bars": 0, "slider-cranks": 0, "configurations": 0,
          "single solves": 0, "single solves refused": 0,
          "non-assemblable inputs": 0, "non-assemblable refused": 0}
SETTINGS = settings(max_examples=25, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow])


@pytest.fixture(scope="module", autouse=True)
def report_counts():
    yield
    print("\nproperty tests: " + ", ".join(f"{k} {v}" for k, v in COUNTS.items()))


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
    from mechgen import Model, T
    m = Model("prop_slider_crank")
    a, b, e = m.param("a", 1.0), m.param("b", 3.0), m.param("e", 0.2)
    th0, w = m.param("theta0", 0.0), m.param("omega", 6.0)
    ground = m.ground("ground", points=[(0, 0), (0, e), (1, e)])
    crank = m.body("crank", points=[(0, 0), (a, 0)], guess=(0, 0, 0))
    rod = m.body("rod", points=[(0, 0), (b, 0)], guess=(1, 0, 0))
    slider = m.body("slider", points=[(0, 0), (1, 0)], guess=(4, 0.2, 0))
    m.revolute(ground[1], crank[1])
    m.revolute(crank[2], rod[1])
    m.revolute(rod[2], slider[1])
    m.translate(ground.line(2, 3), slider.line(1, 2))
    m.rotation_lock(crank, th0 + w * T, name="crank")
    return m


@pytest.fixture(scope="module")
def mechs(tmp_path_factory):
    from mechgen.compiler.build import build
    out = str(tmp_path_factory.mktemp("property_models"))
    return {"fourbar": mechgen.load(build(fourbar_model(), out)),
            "slider": mechgen.load(build(slider_crank_model(), out))}


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


def check_sweep(mech, name, params, sigma, n=97):
    """A whole crank cycle from the closed form's start; every point must match."""
    period = 2 * math.pi / abs(params["omega"])
    q0 = exact(name, params, sigma, np.array([0.0]))[0][0]
    guess = q0 + 1e-4 * np.where(ANGLES, 1.0, 0.0)
    m = mech.with_params(**params)
    sw = m.sweep(0.0, period, n, level="acceleration", guess=guess)
    Q, QD, QDD = exact(name, params, sigma, sw.t)
    dq = sw.Q - Q
    dq[:, ANGLES] = np.remainder(dq[:, ANGLES] + np.pi, 2 * np.pi) - np.pi
    vscale = 1.0 + np.abs(QD).max()
    ascale = 1.0 + np.abs(QDD).max()
    assert np.abs(dq).max() < 1e-8, np.abs(dq).max()
    assert np.abs(sw.QD - QD).max() < 1e-8 * vscale
    assert np.abs(sw.QDD - QDD).max() < 1e-7 * ascale
    # angles continuous along the sweep: the crank exactly θ0 + ωt, no wrapping
    assert np.abs(sw["Th2"] - (params["theta0"] + params["omega"] * sw.t)).max() < 1e-9
    assert np.abs(np.diff(sw.Q[:, ANGLES], axis=0)).max() < math.pi / 2
    COUNTS["configurations"] += len(sw)


# -- strategies -------------------------------------------------------------------------------
@st.composite
def grashof_fourbars(draw):
    """Crank-rockers: the crank a is the shortest link and s + l < p + q by a margin."""
    a = draw(st.floats(0.2, 1.0))
    b = draw(st.floats(a + 0.3, 4.0))
    d = draw(st.floats(a + 0.3, 4.0))
    margin = 0.03 * (b + d)
    lo, hi = max(a + 0.3, a + abs(b - d) + margin), b + d - a - margin
    assume(hi > lo)
    c = lo + draw(st.floats(0.0, 1.0)) * (hi - lo)
    return dict(a=a, b=b, c=c, d=d, theta0=draw(st.floats(-math.pi, math.pi)),
                omega=draw(st.sampled_from([-1.0, 1.0])) * draw(st.floats(0.5, 12.0)))


@st.composite
def slider_cranks(draw):
    """Full-turning offset slider-cranks: b > a + |e| by a margin."""
    a = draw(st.floats(0.2, 2.0))
    e = draw(st.floats(-1.0, 1.0)) * a
    b = a + abs(e) + draw(st.floats(0.05, 3.0)) * a
    return dict(a=a, b=b, e=e, theta0=draw(st.floats(-math.pi, math.pi)),
                omega=draw(st.sampled_from([-1.0, 1.0])) * draw(st.floats(0.5, 12.0)))


# -- whole cycles against the closed forms ---------------------------------------------------------
@SETTINGS
@given(params=grashof_fourbars(), sigma=st.sampled_from([1.0, -1.0]))
def test_random_grashof_fourbars_match_closed_form(mechs, params, sigma):
    check_sweep(mechs["fourbar"], "fourbar", params, sigma)
    COUNTS["four-bars"] += 1


@SETTINGS
@given(params=slider_cranks(), sigma=st.sampled_from([1.0, -1.0]))
def test_random_slider_cranks_match_closed_form(mechs, params, sigma):
    check_sweep(mechs["slider"], "slider", params, sigma)
    COUNTS["slider-cranks"] += 1


@SETTINGS
@given(params=grashof_fourbars(), t=st.floats(0.0, 1.0),
       guess=st.lists(st.floats(-4.0, 4.0), min_size=9, max_size=9))
def test_single_solves_are_right_or_refused(mechs, params, t, guess):
    """From an arbitrary guess a solve may fail, but what it returns is one of the two
    assembly modes of the closed form."""
    m = mechs["fourbar"].with_params(**params)
    COUNTS["single solves"] += 1
    try:
        s = m.solve(t, guess=np.array(guess), level="acceleration")
    except (mechgen.ConvergenceError, mechgen.SingularError):
        COUNTS["single solves refused"] += 1
        return
    tt = np.array([t])
    ok = []
    for sigma in (1.0, -1.0):
        Q, QD, QDD = (x[0] for x in exact("fourbar", params, sigma, tt))
        dq = s.q - Q
        dq[ANGLES] = np.remainder(dq[ANGLES] + np.pi, 2 * np.pi) - np.pi
        ok.append(np.abs(dq).max() < 1e-8 and np.abs(s.qd - QD).max() < 1e-8 * (1 + np.abs(QD).max())
                  and np.abs(s.qdd - QDD).max() < 1e-7 * (1 + np.abs(QDD).max()))
    assert any(ok), (params, t, s.q)


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
