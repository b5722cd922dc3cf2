"""docs/reference/sensitivities.md's tolerance and clearance bands (mech.tolerance) against the
test's own reference: the four-bar's closed form (circle intersection, mpmath; the helpers of
tests/sensitivity_closed_forms.py), written here once more with its crank's pivot moved by the
clearance's offset e, differentiated by mpmath in the parameters and in e.

- "worst" and "rss" are the linear formulas on the closed form's derivatives (1e-8);
- a revolute's clearance c adds c·‖∂out/∂e‖ (worst) and σ = c/3 per direction (rss);
- "montecarlo" lies within the closed form's own extremes over the tolerance box (or the
  clearance's disc) and comes close to them;
- bad input is refused naming the culprit.
"""
import math
import warnings

import mpmath as mp
import numpy as np
import pytest

import mechgen
from mechgen import Model, T, location

import sensitivity_closed_forms as cf

FOURBAR = dict(a=0.8, b=2.5, c=2.0, d=3.0, omega=2 * math.pi, theta0=math.pi / 3)
U, V = 0.5, 0.8                 # the coupler point whose x is the output px
TIMES = (0.0, 0.9, 7)           # the sweep: t0, t1, n
RTOL = 1e-8
TOLS = {"a": 0.01, "b": (-0.02, 0.01), "d": 0.03}


def fourbar_model():
    m = Model("tol_fourbar")
    P = {k: m.param(k, v) for k, v in FOURBAR.items()}
    ground = m.ground("ground", points=[(0, 0), (P["d"], 0)])
    crank = m.body("crank", points=[(0, 0), (P["a"], 0)], guess=(0, 0, 1.0))
    coupler = m.body("coupler", points=[(0, 0), (P["b"], 0), (U, V)], guess=(0.4, 0.7, 0.5))
    rocker = m.body("rocker", points=[(0, 0), (P["c"], 0)], guess=(3, 0, 1.8))
    m.revolute(ground[1], crank[1], name="O2")
    m.revolute(crank[2], coupler[1], name="A")
    m.revolute(ground[2], rocker[1], name="O4")
    m.revolute(coupler[2], rocker[2], name="B")
    m.rotation_lock(crank, P["theta0"] + P["omega"] * T, name="crank angle")
    m.output("px", location(coupler[3])[0])
    m.output("pin_x", location(crank[2])[0])      # X2 + a cos θ: explicit in a as well
    return m


def fourbar_offset(t, a, b, c, d, omega, theta0, ex=0, ey=0):
    """cf.fourbar with the crank's pivot pin apart from the ground's by e: O2's rows read
    r(ground[1]) − r(crank[1]) = e, so the crank turns about −e; then px appended."""
    th = theta0 + omega * t
    A = (-ex + a * mp.cos(th), -ey + a * mp.sin(th))
    _, th3, th4 = cf.dyad(A, b, (d, 0), c, +1, 0.5, 1.8)
    px = A[0] + U * mp.cos(th3) - V * mp.sin(th3)
    return [-ex, -ey, th, A[0], A[1], th3, d, 0, th4, px]


NAMES = {"X3": 3, "Th3": 5, "Th4": 8, "px": 9, "pin_x": 3}   # in fourbar_offset's list
PARAMS = dict(FOURBAR, ex=0.0, ey=0.0)


@pytest.fixture(scope="module")
def mech(tmp_path_factory):
    return mechgen.compile(fourbar_model(), outdir=str(tmp_path_factory.mktemp("tol")))


@pytest.fixture(scope="module")
def sweep(mech):
    return mech.sweep(*TIMES, level="velocity")


@pytest.fixture(scope="module")
def reference(sweep):
    """{t: (∂/∂(a, b, d, ex, ey) of every entry, its rate's)} of the closed form."""
    names = ["a", "b", "d", "ex", "ey"]
    out = []
    for t in sweep.t:
        dq, dqd, _ = cf.sensitivities(fourbar_offset, float(t), PARAMS, names)
        out.append((dq, dqd))
    return names, out


def _grad(reference, name, param, order=0):
    names, ref = reference
    return np.array([r[order][NAMES[name], names.index(param)] for r in ref])


def _close(got, want, what, scale=None):
    got, want = np.asarray(got, dtype=float), np.asarray(want, dtype=float)
    scale = np.abs(want) if scale is None else scale
    assert np.all(np.abs(got - want) <= RTOL * scale + 1e-13), \
        f"{what}: {got} against {want}"


def _value(t, **change):
    return [float(v) for v in fourbar_offset(t, **dict(PARAMS, **change))]


# -- the linear bands ------------------------------------------------------------------------
def test_the_sweep_is_the_closed_forms(sweep):
    for k, t in enumerate(sweep.t):
        ref = _value(float(t))
        for name, i in NAMES.items():
            assert sweep[name][k] == pytest.approx(ref[i], rel=1e-10, abs=1e-10)


@pytest.mark.parametrize("name", ["Th4", "X3", "px"])
def test_worst_case_is_the_linear_sum(mech, sweep, reference, name):
    band = mech.tolerance(sweep, TOLS, method="worst")
    got = band[name]
    nominal = np.asarray(sweep[name])
    assert np.array_equal(got["nominal"], nominal)
    up = down = 0.0
    for p, tol in TOLS.items():
        lo, hi = (-tol, tol) if not isinstance(tol, tuple) else tol
        g = _grad(reference, name, p)
        up = up + np.maximum(g * lo, g * hi)
        down = down + np.minimum(g * lo, g * hi)
        _close(band.contributions(name)[p], np.abs(g) * (hi - lo) / 2, f"{name} share of {p}")
    _close(got["high"] - nominal, up, f"{name} worst high")
    _close(nominal - got["low"], -down, f"{name} worst low")
    assert set(band.contributions(name)) == set(TOLS)


@pytest.mark.parametrize("name", ["Th4", "px"])
def test_rss_takes_a_third_of_each_tolerance(mech, sweep, reference, name):
    band = mech.tolerance(sweep, TOLS, method="rss")
    nominal = np.asarray(sweep[name])
    shift, var = 0.0, 0.0
    for p, tol in TOLS.items():
        lo, hi = (-tol, tol) if not isinstance(tol, tuple) else tol
        g = _grad(reference, name, p)
        shift = shift + g * (lo + hi) / 2          # an asymmetric one: about its centre
        var = var + (g * (hi - lo) / 6) ** 2       # σ = t/3 (half its width over 3)
    half = 3 * np.sqrt(var)
    _close(band[name]["high"] - nominal, shift + half, f"{name} rss high", half)
    _close(band[name]["low"] - nominal, shift - half, f"{name} rss low", half)


def test_rates_have_bands_too(mech, sweep, reference):
    band = mech.tolerance(sweep, {"a": 0.01}, clearance={"O2": 0.02})
    g = _grad(reference, "Th4", "a", 1)
    ge = np.hypot(_grad(reference, "Th4", "ex", 1), _grad(reference, "Th4", "ey", 1))
    _close(band["Th4d"]["high"] - sweep["Th4d"], 0.01 * np.abs(g) + 0.02 * ge, "Th4d worst")


@pytest.mark.parametrize("name", ["Th4", "X3", "px", "pin_x"])
def test_a_clearance_adds_c_times_the_offset_gradient(mech, sweep, reference, name):
    c = 0.05
    band = mech.tolerance(sweep, clearance={"O2": c}, method="worst")
    norm = np.hypot(_grad(reference, name, "ex"), _grad(reference, name, "ey"))
    _close(band.contributions(name)["O2"], c * norm, f"{name} O2 share")
    _close(band[name]["high"] - sweep[name], c * norm, f"{name} O2 worst high")
    _close(sweep[name] - band[name]["low"], c * norm, f"{name} O2 worst low")
    gx, gy = band.gradients(name)[1]["O2"].T          # e = r(ground[1]) − r(crank[1])
    _close(gx, _grad(reference, name, "ex"), f"{name} d/dex", norm)
    _close(gy, _grad(reference, name, "ey"), f"{name} d/dey", norm)
    rss = mech.tolerance(sweep, clearance={"O2": c}, method="rss")
    _close(rss[name]["high"] - sweep[name], c * norm, f"{name} O2 rss (3σ = c)", c * norm)


def test_tolerances_and_clearances_add_up(mech, sweep, reference):
    band = mech.tolerance(sweep, {"a": 0.01}, clearance={"O2": 0.02, "B": 0.01})
    shares = band.contributions("Th4")
    assert list(shares) == ["a", "O2", "B"]
    total = sum(shares.values())
    _close(band["Th4"]["high"] - sweep["Th4"], total, "the shares sum to the half-width")
    _close(shares["O2"], 0.02 * np.hypot(_grad(reference, "Th4", "ex"),
                                         _grad(reference, "Th4", "ey")), "O2 beside B")


def test_a_symbolic_quantity_and_a_point(mech, sweep):
    """Mech's location(coupler[3])[0] and the point's "coupler[3].x" have px's band."""
    coupler = mech.model.bodies["coupler"]
    band = mech.tolerance(sweep, {"a": 0.01, "c": 0.02}, clearance={"O2": 0.03})
    want = band["px"]
    for name in (location(coupler[3])[0], "coupler[3].x"):
        got = band[name]
        for key in ("nominal", "low", "high"):
            np.testing.assert_allclose(got[key], want[key], rtol=1e-12, atol=1e-12)


def test_a_solution_gives_floats(mech, sweep):
    s = mech.solve(float(sweep.t[3]), level="velocity")
    band = mech.tolerance(s, TOLS, clearance={"O2": 0.05})
    whole = mech.tolerance(sweep, TOLS, clearance={"O2": 0.05})
    got = band["Th4"]
    assert all(isinstance(v, float) for v in got.values())
    assert got["high"] == pytest.approx(whole["Th4"]["high"][3], rel=1e-12)
    assert band.contributions("Th4")["O2"] == pytest.approx(
        whole.contributions("Th4")["O2"][3], rel=1e-12)
    assert "T = " in repr(band) and "O2 clearance 0.05" in repr(band)


def test_the_sweeps_own_sensitivities_are_used(mech):
    """A sweep that carries them is read, not solved again; one that carries others is
    left as it was."""
    sw = mech.sweep(*TIMES, sensitivities=["a"])
    before = sw.sensitivities
    band = mech.tolerance(sw, {"a": 0.01, "b": 0.01})
    assert band["Th4"]["high"].shape == (TIMES[2],)
    assert sw.sensitivities is before and sw.sensitivity_params == ["a"]


# -- Monte Carlo against the closed form's own extremes ---------------------------------------
def _truth(sweep, corners, name):
    """The closed form's min and max of ``name`` at each time over ``corners`` (a list of
    {parameter: value} changes)."""
    vals = np.array([[_value(float(t), **ch)[NAMES[name]] for ch in corners]
                     for t in sweep.t])
    return vals.min(axis=1), vals.max(axis=1)


def test_montecarlo_brackets_the_nonlinear_truth(mech, sweep):
    tols = {"a": 0.02, "d": (-0.05, 0.02)}
    band = mech.tolerance(sweep, tols, method="montecarlo", seed=7)
    assert band.samples == 10_000 and band.used == 10_000 and band.failed == 0
    grid = [dict(a=FOURBAR["a"] + da, d=FOURBAR["d"] + dd)
            for da in np.linspace(-0.02, 0.02, 5) for dd in np.linspace(-0.05, 0.02, 5)]
    for name in ("Th4", "px"):
        lo, hi = _truth(sweep, grid, name)
        width = hi - lo
        got = band[name]
        assert np.all(got["low"] >= lo - 1e-9 * width) and np.all(got["high"] <= hi + 1e-9 * width)
        assert np.all(got["low"] - lo <= 0.05 * width), name        # and reaches them
        assert np.all(hi - got["high"] <= 0.05 * width), name
    again = mech.tolerance(sweep, tols, method="montecarlo", seed=7, samples=500)
    assert again.samples == 500


def test_montecarlo_with_a_clearance_is_the_nonlinear_truth(mech, sweep):
    c = 0.05
    band = mech.tolerance(sweep, clearance={"O2": c}, method="montecarlo", seed=3)
    linear = mech.tolerance(sweep, clearance={"O2": c}, method="worst")
    circle = [dict(ex=c * math.cos(a), ey=c * math.sin(a))
              for a in np.linspace(0, 2 * math.pi, 73)]
    for name in ("Th4", "X3", "px"):
        lo, hi = _truth(sweep, circle, name)
        width = hi - lo
        got, lin = band[name], linear[name]
        assert np.all(got["low"] >= lo - 1e-3 * width) and np.all(got["high"] <= hi + 1e-3 * width)
        assert np.all(got["low"] - lo <= 0.05 * width) and np.all(hi - got["high"] <= 0.05 * width)
        slack = 0.05 * (lin["high"] - lin["low"])       # the linear band, widened slightly
        assert np.all(got["high"] <= lin["high"] + slack)
        assert np.all(got["low"] >= lin["low"] - slack)
        assert np.all(got["high"] - got["nominal"] >= 0.9 * (lin["high"] - lin["nominal"]))
        if name == "X3":            # X3 = −ex + a cos θ: exactly ±c about the nominal
            np.testing.assert_allclose(got["high"] - got["nominal"], c, rtol=0.01)
    rates = band["Th4d"]
    assert np.all(rates["low"] <= rates["nominal"]) and np.all(rates["nominal"] <= rates["high"])


def test_montecarlo_reports_samples_that_fail(mech, sweep):
    """A coupler as short as 1.2 cannot close the loop over the whole turn: those designs
    are counted and left out, never drawn as numbers."""
    with pytest.warns(RuntimeWarning, match="Monte Carlo samples"):
        band = mech.tolerance(sweep, {"b": (-1.3, 0.0)}, method="montecarlo", samples=400,
                              seed=1)
    assert 0 < band.failed < 400 and band.used + band.failed == 400
    assert "failed" in repr(band)
    got = band["Th4"]
    assert np.all(np.isfinite(got["low"])) and np.all(np.isfinite(got["high"]))


# -- refusals ------------------------------------------------------------------------------
@pytest.mark.parametrize("tols, clearance, match", [
    ({"zz": 0.1}, None, "no such parameter.*a, b, c, d"),
    ({"a": -0.1}, None, "negative"),
    ({"a": (0.01, 0.02)}, None, "low = 0.01 > 0"),
    ({"a": (-0.02, -0.01)}, None, "high = -0.01 < 0"),
    ({"a": (0.1,)}, None, "t or \\(low, high\\)"),
    ({"a": "wide"}, None, "give a number"),
    ({"a": float("nan")}, None, "finite"),
    (None, {"crank angle": 0.1}, "not a revolute.*'O2', 'A', 'O4', 'B'"),
    (None, {"Q9": 0.1}, "no constraint.*'O2'"),
    (None, {"O2": -0.1}, "negative"),
    (None, None, "at least one"),
])
def test_bad_input_is_refused(mech, sweep, tols, clearance, match):
    with pytest.raises(ValueError, match=match) as info:
        mech.tolerance(sweep, tols, clearance=clearance)
    assert isinstance(info.value, mechgen.MechgenError)


def test_bad_options_are_refused(mech, sweep):
    with pytest.raises(ValueError, match="method must be one of"):
        mech.tolerance(sweep, {"a": 0.01}, method="taguchi")
    with pytest.raises(ValueError, match="montecarlo"):
        mech.tolerance(sweep, {"a": 0.01}, method="rss", samples=100)
    with pytest.raises(mechgen.MechgenError, match="samples must be a positive integer"):
        mech.tolerance(sweep, {"a": 0.01}, method="montecarlo", samples=0)
    with pytest.raises(TypeError, match="unexpected"):
        mech.tolerance(sweep, {"a": 0.01}, method="montecarlo", sample=10)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tab = mech.sweep(0, 0.5, 3, params={"a": [0.8, 0.85]})
    with pytest.raises(ValueError, match="design table"):
        mech.tolerance(tab, {"a": 0.01})
