"""Interpolation, exact extremes and roots, assembly modes, design tables and exports
(mechgen.runtime: interpolate, events, assembly, design), on the committed generated modules."""
import math
import os
import subprocess
import sys

import numpy as np
import pytest

import mechgen
from mechgen.runtime.analysis.assembly import angle_coordinates
from closed_forms import quick_return
from conftest import ROOT, example_model

T_MIN, X4_MIN = 0.6024163823, -1.257536965      # the stroke (test_output_functions
T_MAX, X4_MAX = 0.8975836177, 9.542463035       # checks these against mpmath)


def same_angle(a, b, tol=1e-9):
    return abs(math.remainder(a - b, 2 * math.pi)) < tol


# -- interpolation -------------------------------------------------------------------------
@pytest.mark.parametrize("level, method, err", [
    ("acceleration", "quintic hermite", 3e-3),     # measured 1.4e-3: the fast return
    ("velocity", "cubic hermite", 4e-2),           # measured 2.0e-2  (near T = 0.75) is
    ("position", "cubic spline", 1e-1),            # measured 6.3e-2  the hard part
])
def test_interpolate_uses_the_derivatives_held(qr, level, method, err):
    sw = qr.sweep(0.0, 1.0, 21, level=level)
    f = sw.interpolate("X4")
    assert f.method == method
    assert np.allclose(f(sw.t), sw["X4"], atol=1e-12, rtol=0)       # through the data
    ts = np.linspace(0.013, 0.987, 37)
    exact = np.array([float(quick_return(t)[6]) for t in ts])       # tests/closed_forms.py
    worst = np.max(np.abs(f(ts) - exact))
    assert worst < err
    if level != "position":                                          # slopes at the nodes
        assert np.allclose(f(sw.t, 1), sw["X4d"], rtol=1e-9, atol=1e-9)


def test_hermite_beats_the_spline(qr):
    ts = np.linspace(0.013, 0.987, 37)
    exact = np.array([float(quick_return(t)[6]) for t in ts])       # tests/closed_forms.py
    errs = [np.max(np.abs(qr.sweep(0, 1, 21, level=lev).interpolate("X4")(ts) - exact))
            for lev in ("position", "velocity", "acceleration")]
    assert errs[2] < errs[1] < errs[0]


def test_interpolate_methods_and_domain(qr):
    sw = qr.sweep(0.0, 1.0, 21, level="velocity")
    lin = sw.interpolate("X4", method="linear")
    assert lin(0.025) == pytest.approx((sw["X4"][0] + sw["X4"][1]) / 2, abs=1e-14)
    lag = sw.interpolate("X4", method="lagrange")
    assert np.allclose(lag(sw.t), sw["X4"], atol=1e-12)
    # a third-order local interpolant is exact on cubics
    cubic = sw.interpolate("Th2", method="lagrange")
    assert cubic(0.3337) == pytest.approx(2 * math.pi * 0.3337, abs=1e-12)
    with pytest.raises(ValueError, match="outside"):
        lag(1.2)
    assert np.isfinite(sw.interpolate("X4", extrapolate=True)(1.01))
    with pytest.raises(ValueError, match="hermite"):
        qr.sweep(0, 1, 5).interpolate("X4", method="hermite")
    with pytest.raises(ValueError, match="method"):
        sw.interpolate("X4", method="akima")
    with pytest.raises(KeyError, match="level"):
        sw.interpolate("X4dd")
    with pytest.raises(KeyError):
        sw.interpolate("Z9")


def test_interpolate_outputs_and_derivatives(qr):
    sw = qr.sweep(0.0, 1.0, 21, level="acceleration")
    f = sw.interpolate("stroke_x")               # declared in examples/quick_return.py
    g = sw.interpolate("X4")
    assert f.method == "quintic hermite"
    assert f(0.4321) == pytest.approx(g(0.4321), abs=1e-12)
    fd = sw.interpolate("X4d")                    # cubic Hermite with X4dd
    assert fd.method == "cubic hermite"
    # independently: scipy's Hermite pieces through the closed form's X4, X4d, X4dd at the
    # 21 times (tests/closed_forms.py; the sweep's own values are those to 1e-12)
    import mpmath as mp
    from scipy.interpolate import BPoly, CubicHermiteSpline, PPoly
    with mp.workdps(30):
        D = np.array([[float(mp.diff(lambda u: quick_return(u)[6], mp.mpf(t), k))
                       for k in range(3)] for t in sw.t])
    assert np.allclose(D, np.c_[sw["X4"], sw["X4d"], sw["X4dd"]], rtol=0, atol=1e-11)
    ts = np.linspace(0.0, 1.0, 101)
    assert np.abs(fd(ts) - CubicHermiteSpline(sw.t, D[:, 1], D[:, 2])(ts)).max() < 1e-10
    quintic = PPoly.from_bernstein_basis(BPoly.from_derivatives(sw.t, D))
    assert np.abs(f(ts) - quintic(ts)).max() < 1e-10
    assert np.allclose(f.derivative().roots(), quintic.derivative().roots(extrapolate=False),
                       rtol=0, atol=1e-9)
    assert np.allclose(f.derivative().roots(), (T_MIN, T_MAX), atol=1e-5)   # the spline's error


def test_interpolate_a_decreasing_sweep(qr):
    sw = qr.sweep(1.0, 0.0, 21, level="velocity")
    f = sw.interpolate("X4")
    assert f(0.5) == pytest.approx(sw["X4"][10], abs=1e-12)


# -- extrema and roots -----------------------------------------------------------------------
@pytest.mark.parametrize("level", ["position", "velocity", "acceleration"])
def test_extrema_exact_from_any_level(qr, level):
    sw = qr.sweep(0.0, 1.0, 21, level=level)
    ev = sw.extrema("X4")
    assert [e.kind for e in ev] == ["min", "max"]
    assert np.allclose(ev.t, (T_MIN, T_MAX), atol=1e-10, rtol=0)
    assert np.allclose(ev.value, (X4_MIN, X4_MAX), atol=1e-9, rtol=0)
    for e in ev:                      # what the interpolant says, and how far off it is
        assert 0 < abs(e.error_t) < 1e-2 and abs(e.error_value) < 1e-2
        assert e.solves > 0
    assert ev.minima.t[0] == ev[0].t and ev.maxima.value[0] == ev[1].value


def test_extrema_leave_last_alone_and_print(qr):
    s = qr.solve(0.123)
    ev = qr.sweep(0.0, 1.0, 11, level="velocity").extrema("X4")
    qr.solve(0.123)
    assert qr.last.t == s.t
    text = repr(ev)
    assert "min" in text and "0.6024163823" in text
    assert "<table>" in ev._repr_html_()
    assert "min of X4" in repr(ev[0])


def test_extrema_of_a_decreasing_sweep(qr):
    ev = qr.sweep(1.0, 0.0, 21).extrema("X4")
    assert [e.kind for e in ev] == ["min", "max"]
    assert np.allclose(ev.t, (T_MIN, T_MAX), atol=1e-10)


def test_extrema_of_velocity_and_constant(qr):
    sw = qr.sweep(0.0, 1.0, 41, level="acceleration")
    ev = sw.extrema("X4d")                          # needs exact accelerations
    assert [e.kind for e in ev] == ["min", "max"]
    import mpmath as mp
    for e in ev:                                    # against the closed form's X4d, X4dd
        with mp.workdps(30):
            d1, d2 = (float(mp.diff(lambda u: quick_return(u)[6], mp.mpf(e.t), k)) for k in (1, 2))
        assert abs(d2) < 1e-8 and d1 == pytest.approx(e.value, abs=1e-10)
    assert len(sw.extrema("Y4")) == 0               # constant: round-off is not an extreme
    with pytest.raises(ValueError, match="third derivative"):
        sw.extrema("X4dd")


def test_roots(qr):
    sw = qr.sweep(0.0, 1.0, 21)
    r = sw.roots("X4")                               # the slider crosses x = 0 twice
    assert [e.kind for e in r] == ["falling", "rising"]
    for e in r:
        assert abs(float(quick_return(e.t)[6])) < 1e-12          # the closed form's X4
        assert abs(e.t_interp - e.t) < 1e-3
    d = qr.sweep(0.0, 1.0, 21, level="velocity").roots("X4d")
    assert np.allclose(d.t, (T_MIN, T_MAX), atol=1e-10)
    th = sw.roots("Th3")                             # zeros that fall on sweep points
    assert np.allclose(th.t, (0.25, 0.75), atol=1e-12)


# -- assembly modes --------------------------------------------------------------------------
FOURBAR = [(0.5274103891, 1.792465604), (-1.048246730, -2.313301945)]


def test_angle_coordinates(qr, fourbar_loop, qr_slider):
    assert [qr.coordinates[j] for j in angle_coordinates(qr)] == ["Th3", "Th4"]   # Th2 is driven
    assert [fourbar_loop.coordinates[j] for j in angle_coordinates(fourbar_loop)] == ["theta3", "theta4"]
    assert "Th2" in [qr_slider.coordinates[j] for j in angle_coordinates(qr_slider)]


@pytest.mark.parametrize("fixture, names", [("fourbar", ("Th3", "Th4")),
                                            ("fourbar_loop", ("theta3", "theta4"))])
def test_assemblies_fourbar(request, fixture, names):
    mech = request.getfixturevalue(fixture)
    modes = mech.assemblies(0.0)
    assert len(modes) == 2
    got = sorted((s[names[0]], s[names[1]]) for s in modes)
    want = sorted(FOURBAR)
    for (a, b), (c, d) in zip(got, want):
        assert abs(a - c) < 1e-9 and abs(b - d) < 1e-9        # (−π, π], as Maple prints
    for s in modes:
        assert s.residual < 1e-12


def test_assemblies_quick_return_at_085(qr):
    modes = qr.assemblies(0.85)
    assert len(modes) == 2
    # the guess's mode first, then the other (tests/closed_forms.py)
    assert modes[0]["X4"] == pytest.approx(float(quick_return(0.85)[6]), abs=1e-12)
    assert modes[1]["X4"] == pytest.approx(float(quick_return(0.85, side=-1)[6]), abs=1e-12)
    assert sorted(round(s["X4"], 5) for s in modes) == [0.80263, 9.37314]        # as printed
    for s in modes:
        assert same_angle(s["Th3"], -0.600822, 1e-6) and s["Th2"] == pytest.approx(5.34071, abs=1e-5)
        assert s["Th4"] == pytest.approx(0.0, abs=1e-12)
    # the slider reversed on its guide also solves u1 × u2 = 0: listed only on request
    assert len(qr.assemblies(0.85, flips=True)) == 4


def test_follow_a_mode(qr):
    low = min(qr.assemblies(0.85), key=lambda s: s["X4"])
    sw = qr.sweep(0.85, 1.0, 16, guess=low)
    assert np.all(sw["X4"] < 4) and np.max(np.abs(np.diff(sw["X4"]))) < 1.0
    hi = qr.sweep(0.85, 1.0, 16)
    assert np.all(hi["X4"] > 4)


def test_assemblies_slider_driven(qr_slider):
    modes = qr_slider.assemblies(0.0, level="velocity")
    assert len(modes) == 2
    assert sorted(round(s["Th2"], 4) for s in modes) == [-1.6269, 1.7945]
    assert all(s.qd is not None for s in modes)
    assert all(s["X4"] == pytest.approx(4.13931, abs=1e-9) for s in modes)


def test_assemblies_arguments(qr):
    with pytest.raises(ValueError):
        qr.assemblies(0.85, starts=-1)
    only_guess = qr.assemblies(0.85, starts=0)
    assert len(only_guess) == 1


# -- design tables -----------------------------------------------------------------------------
def test_design_table_over_longitud(qr):
    """Table[SetGuess[]; SolveMech[{0, 1}, 20], {longitud, 1.5, 3., 0.75}]"""
    tab = qr.sweep(0.0, 1.0, 20, params={"longitud": np.arange(1.5, 3.01, 0.75)})
    assert tab.shape == (3,) and tab["X4"].shape == (3, 20) and tab.ok.all()
    for i, L in enumerate((1.5, 2.25, 3.0)):
        ref = qr.with_params(longitud=L).sweep(0.0, 1.0, 20)
        assert np.array_equal(tab["X4"][i], ref["X4"])
        assert np.array_equal(tab.sweep(longitud=L)["Th3"], ref["Th3"])
    assert tab["X4"][2, 0] == pytest.approx(9.07905, abs=1e-5)        # the seed's SolveMech[0]
    strokes = np.nanmax(tab["X4"], axis=1) - np.nanmin(tab["X4"], axis=1)
    assert np.all(np.diff(strokes) > 0)                                 # longer crank, longer stroke
    assert len(tab.sweeps) == 3 and "3 designs" in repr(tab)


def test_design_table_grid_levels_outputs(qr):
    tab = qr.design_sweep(0.0, 1.0, 11, {"longitud": [2.0, 3.0], "velocidad": [math.pi, 2 * math.pi],
                                          "anguloI": 0.1}, level="acceleration")
    assert tab.shape == (2, 2) and tab["X4dd"].shape == (2, 2, 11)
    ref = qr.with_params(longitud=2.0, velocidad=math.pi, anguloI=0.1).sweep(0, 1, 11, level="acceleration")
    assert np.array_equal(tab["X4dd"][0, 0], ref["X4dd"])
    assert np.allclose(tab["stroke_x"][1, 1], tab["X4"][1, 1], atol=0)
    assert np.allclose(tab.sweep(1, 0)["Th2"], 0.1 + math.pi * tab.t)
    header, data = tab.table()
    assert header[:3] == ["longitud", "velocidad", "T"] and data.shape[0] == 44


def test_design_table_failures_are_nan(qr):
    with pytest.warns(RuntimeWarning, match="longitud=6"):
        tab = qr.sweep(0.0, 1.0, 30, params={"longitud": [3.0, 6.0]})
    assert list(tab.ok) == [True, False]
    (values, t_fail, status), = tab.failures
    assert values == {"longitud": 6.0} and 0 < t_fail < 1 and status != 0
    x4 = tab["X4"][1]
    k = int(tab.done[1])
    assert np.all(np.isfinite(x4[:k])) and np.all(np.isnan(x4[k:]))
    assert len(tab.sweep(longitud=6.0)) == k
    with pytest.raises(mechgen.MechgenError):
        qr.design_sweep(0.0, 1.0, 30, {"longitud": [3.0, 6.0]}, on_fail="raise")


def test_design_table_progress(qr, capsys):
    seen = []
    qr.design_sweep(0.0, 1.0, 5, {"longitud": np.linspace(1.0, 3.0, 120)},
                    progress=lambda done, total: seen.append((done, total)))
    assert len(seen) > 1 and seen[-1] == (120, 120)
    assert all(a[0] < b[0] for a, b in zip(seen, seen[1:]))
    qr.design_sweep(0.0, 1.0, 5, {"longitud": [1.0, 2.0]}, progress=True)
    assert "designs solved: 2/2" in capsys.readouterr().err


def test_design_table_arguments(qr):
    with pytest.raises(ValueError, match="no parameter"):
        qr.sweep(0, 1, 5, params={"lenght": [1, 2]})
    with pytest.raises(ValueError, match="finite"):
        qr.sweep(0, 1, 5, params={"longitud": [1, float("nan")]})
    sw = qr.sweep(0, 1, 5, params={"longitud": 2.0})          # nothing varies: a Sweep
    assert isinstance(sw, mechgen.Sweep) and sw.mechanism.parameters["longitud"] == 2.0


# -- export and display ------------------------------------------------------------------------
def test_csv_dataframe_repr_html(qr, tmp_path):
    sw = qr.sweep(0.0, 1.0, 25, level="velocity")
    path = sw.to_csv(tmp_path / "qr.csv")
    back = np.genfromtxt(path, delimiter=",", names=True)
    assert np.array_equal(back["X4d"], sw["X4d"]) and np.array_equal(back["T"], sw.t)
    assert "25 points" in repr(sw) and "20 columns" in repr(sw)
    html = sw._repr_html_()
    assert html.count("<tr>") == 1 + 16 + 1 and "X4d" in html      # head, tail, ellipsis
    assert "<table>" in sw[3]._repr_html_()
    tab = qr.sweep(0.0, 1.0, 4, params={"longitud": [2.0, 3.0]})
    tab.to_csv(tmp_path / "tab.csv")
    rows = np.genfromtxt(tmp_path / "tab.csv", delimiter=",", names=True)
    assert rows.shape == (8,) and list(rows["longitud"][:4]) == [2.0] * 4
    try:
        import pandas  # noqa: F401
    except ImportError:
        with pytest.raises(ImportError, match="pandas"):
            sw.to_dataframe()
    else:
        df = sw.to_dataframe()
        assert list(df["X4"]) == list(sw["X4"])
        assert tab.to_dataframe().shape[0] == 8


def test_model_latex_for_notebooks():
    m = example_model("quick_return")
    text = m._repr_latex_()
    assert "\\begin{align" in text and "quick\\_return" in text
    assert "\n% " not in "\n" + text                           # no comments left for MathJax


def test_analysis_leaves_sympy_unloaded(tmp_path):
    code = (
        "import sys, numpy as np, mechgen\n"
        f"mech = mechgen.load({os.path.join(ROOT, 'generated', 'quick_return.py')!r})\n"
        "sw = mech.sweep(0, 1, 21, level='velocity')\n"
        "sw.interpolate('X4')(0.3); sw.extrema('X4'); sw.roots('X4'); mech.assemblies(0.85, starts=16)\n"
        "mech.sweep(0, 1, 5, params={'longitud': [2.0, 3.0]})\n"
        "print('sympy' in sys.modules)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "False"


def test_param_option_of_the_command_line():
    from mechgen.cli.options import parse_param_option
    got = parse_param_option(["longitud=1.5:3:step=0.75", "velocidad=1,2", "anguloI=0.5"])
    assert np.allclose(got["longitud"], [1.5, 2.25, 3.0])       # {longitud, 1.5, 3., 0.75}
    assert np.allclose(got["velocidad"], [1.0, 2.0]) and got["anguloI"] == 0.5
    # START:STOP:COUNT: COUNT values, both ends included (numpy's linspace)
    got = parse_param_option(["longitud=1:3:5", "velocidad=2:1:n=3", "anguloI=0.5:0.5:1"])
    assert np.array_equal(got["longitud"], np.linspace(1.0, 3.0, 5))
    assert np.array_equal(got["velocidad"], [2.0, 1.5, 1.0])
    assert np.array_equal(got["anguloI"], [0.5])
    for bad in ("longitud", "longitud=1:2", "longitud=2:1:step=1", "longitud=a,b",
                "longitud=1:3:0", "longitud=1:3:0.5", "longitud=1:3:step=0",
                "longitud=1:1:3", "longitud=1:3:k=2", "longitud=1:2:3:4"):
        with pytest.raises(mechgen.MechgenError, match="--param"):
            parse_param_option([bad])
