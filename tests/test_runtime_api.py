"""The runtime API of docs/reference/runtime.md: Mechanism, Solution, Sweep, guards, errors,
evaluate()."""
from __future__ import annotations

import csv
import math

import numpy as np
import pytest

import mechgen
from conftest import GENERATED, example_model

TWO_PI = 2 * math.pi


def close(a, b, digits=6):
    """Mech prints 6 significant digits."""
    return abs(a - b) <= 0.6 * 10 ** (math.floor(math.log10(max(abs(b), 1e-300))) - digits + 1) + 1e-12


# -- fixtures ---------------------------------------------------------------------------
@pytest.fixture(scope="session")
def qr_model():
    return example_model("quick_return")


@pytest.fixture(scope="session")
def qr_compiled(qr_model, tmp_path_factory):
    """mechgen.compile(model): built into a tmp dir, loaded, the model kept. On the
    plain-Python tier: its tests are about the model and the symbolic side kept (the same
    numbers as numba's), and a fresh build compiled by numba cost ~20 s of CPU."""
    return mechgen.compile(qr_model, outdir=str(tmp_path_factory.mktemp("compiled")),
                           tier="python")


class Spy:
    """A stand-in for a generated module that records every call into it."""

    def __init__(self, module):
        self._module = module
        self.calls = []

    def __getattr__(self, name):
        value = getattr(self._module, name)
        if callable(value) and not isinstance(value, type):
            def call(*args, **kwargs):
                self.calls.append(name)
                return value(*args, **kwargs)
            return call
        return value


@pytest.fixture
def spied(qr):
    """A copy of the quick-return mechanism whose module calls are recorded."""
    mech = qr.with_params()
    mech.module = Spy(qr.module)
    return mech


# -- attributes ------------------------------------------------------------------------
def test_coordinates_and_parameters(qr):
    assert qr.coordinates == ("X2", "Y2", "Th2", "X3", "Y3", "Th3", "X4", "Y4", "Th4")
    assert qr.parameters == {"longitud": 3.0, "velocidad": TWO_PI, "anguloI": 0.0}
    assert isinstance(qr.coordinates, tuple)


def test_with_params_changes_the_answer_and_leaves_the_original(qr):
    short = qr.with_params(longitud=1.5)
    assert short.parameters["longitud"] == 1.5
    assert qr.parameters["longitud"] == 3.0
    a, b = qr.solve(0.15), short.solve(0.15)
    assert abs(a["X4"] - b["X4"]) > 0.1
    # the crank pin is now 1.5 from the crank pivot (0, 5), on the slotted lever's axis
    th2, th3 = b["Th2"], b["Th3"]
    pin = np.array([1.5 * math.cos(th2), 5 + 1.5 * math.sin(th2)])
    lever = np.array([-math.sin(th3), math.cos(th3)])
    assert abs(pin[0] * lever[1] - pin[1] * lever[0]) < 1e-12
    assert qr.solve(0.15)["X4"] == a["X4"]


def test_with_params_rejects_unknown_and_bad_values(qr):
    with pytest.raises(ValueError, match="no parameter 'lenght'.*longitud"):
        qr.with_params(lenght=1.5)
    with pytest.raises(ValueError, match="finite"):
        qr.with_params(longitud=float("nan"))
    with pytest.raises(ValueError, match="number"):
        qr.with_params(longitud="long")


# -- solve ---------------------------------------------------------------------------------
def test_solve_levels_and_solution_fields(qr):
    s = qr.solve(0.15)
    assert s.t == 0.15 and s.level == "position"
    assert s.q.shape == (9,) and s.q.dtype == np.float64
    assert s.qd is None and s.qdd is None
    with pytest.raises(KeyError, match="velocity"):
        s["X4d"]
    s = qr.solve(0.15, level="velocity")
    assert s.qd.shape == (9,) and s.qdd is None
    assert close(s["X4d"], -18.7395)
    with pytest.raises(KeyError, match="acceleration"):
        s["X4dd"]
    s = qr.solve(0.15, level="acceleration")
    assert close(s["Th3"], -0.233107) and close(s["X4d"], -18.7395) and close(s["X4dd"], -40.9024)
    assert s["X4"] == s.q[6] and s["X4d"] == s.qd[6] and s["X4dd"] == s.qdd[6]
    assert isinstance(s["X4"], float)


def test_guess_forms(qr):
    mode2 = qr.solve(0.85, guess={"X4": 1.0})
    assert close(mode2["X4"], 0.802632)
    # an array and a Solution work as guesses too, and stay on that branch
    again = qr.solve(0.85, guess=mode2.q + 0.01)
    assert abs(again["X4"] - mode2["X4"]) < 1e-10
    near = qr.solve(0.86, guess=mode2)
    from closed_forms import quick_return                 # the other mode, in closed form
    assert abs(near["X4"] - float(quick_return(0.86, side=-1)[6])) < 1e-10
    assert abs(mode2["X4"] - float(quick_return(0.85, side=-1)[6])) < 1e-10
    # the guess array is not modified by the solve
    g = mode2.q + 0.01
    kept = g.copy()
    qr.solve(0.85, guess=g)
    assert np.array_equal(g, kept)


def test_last(qr):
    s = qr.solve(0.5)
    assert qr.last is s
    sw = qr.sweep(0.0, 0.2, 5)
    assert qr.last.t == 0.2 and qr.last["X4"] == sw["X4"][-1]


def test_solution_mapping(qr):
    s = qr.solve(0.15, level="velocity")
    d = s.as_dict()
    assert d["T"] == 0.15 and d["X4"] == s["X4"] and d["X4d"] == s["X4d"]
    assert "X4dd" not in d
    assert list(s.keys())[:9] == list(qr.coordinates)
    assert "X4" in repr(s)


# -- sweep -----------------------------------------------------------------------------------
def test_sweep_includes_both_ends(qr):
    sw = qr.sweep(0.0, 1.0, 101, level="velocity")
    assert len(sw) == 101 and sw.t[0] == 0.0 and sw.t[-1] == 1.0
    assert np.allclose(np.diff(sw.t), 0.01)
    assert isinstance(sw["X4"], np.ndarray) and sw["X4"].shape == (101,)
    assert sw["X4d"].shape == (101,)
    with pytest.raises(KeyError, match="acceleration"):
        sw["X4dd"]
    one = qr.sweep(0.3, 0.3, 1)
    assert len(one) == 1 and one.t[0] == 0.3


def test_sweep_rows_are_solutions(qr):
    sw = qr.sweep(0.0, 1.0, 21, level="acceleration")
    for k in (0, 7, 20):
        s = qr.solve(sw.t[k], level="acceleration")
        assert np.allclose(sw[k].q, s.q, atol=1e-10)
        assert np.allclose(sw[k].qd, s.qd, atol=1e-8)
        assert np.allclose(sw[k].qdd, s.qdd, atol=1e-7)
        assert sw["X4dd"][k] == sw.QDD[k, 6]
    assert sw[-1].t == 1.0
    with pytest.raises(IndexError):
        sw[21]


def test_sweep_outputs_by_name(qr):
    sw = qr.sweep(0.0, 1.0, 11, level="acceleration")
    assert np.array_equal(sw["stroke_x"], sw["X4"])
    assert np.array_equal(sw["stroke_xd"], sw["X4d"])
    assert np.array_equal(sw["stroke_xdd"], sw["X4dd"])
    assert sw[4]["stroke_x"] == sw["X4"][4]


def test_to_csv_round_trip(qr, tmp_path):
    sw = qr.sweep(0.0, 1.0, 21, level="acceleration")
    path = tmp_path / "qr.csv"
    assert sw.to_csv(str(path)) == str(path)
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    header, body = rows[0], rows[1:]
    assert header[0] == "T" and {"X4", "X4d", "X4dd", "stroke_x"} <= set(header)
    assert len(body) == 21
    data = np.array(body, dtype=np.float64)
    assert np.array_equal(data[:, 0], sw.t)
    for name in ("X4", "Th3d", "X4dd", "stroke_x"):
        assert np.array_equal(data[:, header.index(name)], sw[name])    # exact: repr floats


# -- guards (in Python, before any jitted call) ------------------------------------------------
@pytest.mark.parametrize("call,match", [
    (lambda m: m.solve(float("nan")), "finite"),
    (lambda m: m.solve(float("inf")), "finite"),
    (lambda m: m.solve("soon"), "number"),
    (lambda m: m.solve(0.1, level="jerk"), "position, velocity, acceleration"),
    (lambda m: m.solve(0.1, guess={"X5": 1.0}), "'X5' is not a coordinate"),
    (lambda m: m.solve(0.1, guess={"X4": float("nan")}), "finite"),
    (lambda m: m.solve(0.1, guess=np.zeros(8)), r"shape \(9,\)"),
    (lambda m: m.solve(0.1, guess=np.zeros((9, 1))), r"shape \(9,\)"),
    (lambda m: m.solve(0.1, guess=np.full(9, np.inf)), "NaN or infinite"),
    (lambda m: m.solve(0.1, method="magic"), "method"),
    (lambda m: m.sweep(0.0, 1.0, 0), "positive integer"),
    (lambda m: m.sweep(0.0, 1.0, -3), "positive integer"),
    (lambda m: m.sweep(0.0, 1.0, 2.5), "positive integer"),
    (lambda m: m.sweep(0.0, float("nan"), 5), "finite"),
    (lambda m: m.sweep(float("-inf"), 1.0, 5), "finite"),
    (lambda m: m.sweep(0.0, 1.0, 5, level="fast"), "level"),
    (lambda m: m.sweep(0.0, 1.0, 5, guess={"Th9": 0}), "'Th9' is not a coordinate"),
    (lambda m: m.sweep(None, None, None, times=[0.0, float("nan")]), "finite"),
])
def test_guards_raise_before_any_jitted_call(spied, call, match):
    with pytest.raises(ValueError, match=match):
        call(spied)
    assert spied.module.calls == [], spied.module.calls


def test_spy_sees_calls(spied):
    """The spy works: a good solve goes through the generated module."""
    spied.solve(0.1, guess=spied.guess)
    # the sorted solver with the checks: the full Newton is not called (nor compiled)
    assert spied.module.calls == ["solve_point_sorted"], spied.module.calls
    # without a guess: the guess solved at t = 0, the continuation to t (its quick path:
    # nothing is hard on the way, so the careful sweep is not called), the solve at t
    spied.module.calls.clear()
    spied.solve(0.1)
    calls = spied.module.calls
    assert calls[0] == calls[-1] == "solve_point_sorted" and set(calls) == \
        {"solve_point_sorted", "sweep_fast"}, calls


def test_unknown_names_when_indexing(qr):
    s = qr.solve(0.1)
    with pytest.raises(KeyError, match="'X9' is neither a coordinate nor an output"):
        s["X9"]
    sw = qr.sweep(0.0, 0.1, 3)
    with pytest.raises(KeyError, match="X4"):
        sw["x4"]


# -- errors -------------------------------------------------------------------------------------
def test_convergence_error_carries_time_iterations_residual(qr):
    before = qr.solve(0.1)
    with pytest.raises(mechgen.ConvergenceError) as info:
        qr.solve(0.3, guess={"Th3": 2.5, "X4": -30.0}, maxit=1)
    exc = info.value
    assert exc.t == 0.3 and "0.3" in str(exc)
    assert isinstance(exc.iterations, int) and exc.iterations >= 1
    assert math.isfinite(exc.residual) and exc.residual > qr.tol
    assert f"{exc.iterations} iteration" in str(exc)
    assert qr.last is before                  # the failed solve left no configuration behind


def test_no_assembly_raises_and_returns_no_numbers(qr_slider):
    """Past the slider-driven version's lock (X4 beyond the stroke) nothing assembles."""
    qr_slider.solve(0.0)
    before = qr_slider.last
    with pytest.raises((mechgen.ConvergenceError, mechgen.SingularError)) as info:
        qr_slider.solve(0.25, guess=qr_slider.solve(0.2))
    exc = info.value
    assert exc.t == 0.25
    assert qr_slider.last.t == 0.2 and qr_slider.last is not before


def test_failed_sweep_keeps_the_points_before_the_failure(qr_slider):
    with pytest.raises((mechgen.ConvergenceError, mechgen.SingularError)) as info:
        qr_slider.sweep(0.0, 0.3, 31, level="velocity")
    exc = info.value
    sw = exc.sweep
    assert isinstance(sw, mechgen.Sweep)
    assert 20 <= len(sw) < 31
    assert np.allclose(sw.t, np.linspace(0.0, 0.3, 31)[:len(sw)])
    assert sw.t[-1] < exc.t <= 0.3 and exc.t < 0.26
    # the points it kept are good solutions
    for k in (0, len(sw) - 1):
        s = qr_slider.solve(sw.t[k], guess=sw[k], level="velocity")
        assert np.allclose(s.q, sw.Q[k], atol=1e-9) and np.allclose(s.qd, sw.QD[k], atol=1e-7)
        assert qr_slider.residual(sw.Q[k], sw.t[k]) < 1e-10


def test_error_classes_are_exported():
    assert issubclass(mechgen.ConvergenceError, mechgen.MechgenError)
    assert issubclass(mechgen.SingularError, mechgen.MechgenError)
    assert issubclass(mechgen.ModelError, mechgen.MechgenError)


# -- compile and evaluate ---------------------------------------------------------------------
def test_compile_keeps_the_model(qr_compiled, qr_model):
    assert qr_compiled.model is qr_model
    assert qr_compiled.coordinates == ("X2", "Y2", "Th2", "X3", "Y3", "Th3", "X4", "Y4", "Th4")
    assert close(qr_compiled.solve(0.5)["X4"], -0.181877)
    assert qr_compiled.with_params(longitud=2.0).model is qr_model
    assert not qr_compiled.module.__file__.startswith(GENERATED)


def test_evaluate_needs_the_model(qr, qr_model):
    from mechgen import distance
    s = qr.solve(0.1)
    with pytest.raises(mechgen.ModelError, match="mechgen.compile"):
        qr.evaluate(distance(qr_model["manivela"][1], qr_model["deslizadera"][2]), s)


def test_evaluate_seed_output_functions(qr_compiled, qr_model):
    """Section 5 of seed 001: output functions at SolveMech[t] / LastSolve[]."""
    from mechgen import (Line, angle, cross, direction, distance, intersection, location,
                         magnitude, point_to_line_distance, project_on_line, xy_to_polar)
    mech, m = qr_compiled, qr_model
    base, manivela, colisa, deslizadera = m["base"], m["manivela"], m["colisa"], m["deslizadera"]
    ev = mech.evaluate
    d = distance(manivela[1], deslizadera[2])
    assert close(ev(d, mech.solve(0.1)), 11.0022)
    assert close(ev(d, mech.solve(0.2)), 9.38401)
    assert ev(distance(manivela[1], manivela[2]), mech.last) == pytest.approx(3.0, abs=1e-14)
    pl = point_to_line_distance(manivela[1], colisa.line(1, 2))
    assert close(ev(pl, mech.solve(0.2)), 0.58617, 5)
    assert abs(ev(pl, mech.solve(0.25))) < 1e-12
    arm = Line(colisa[2], deslizadera[1])
    s = mech.solve(0.3)
    assert close(ev(angle(arm), s) / (math.pi / 180), 12.2638)
    x, y = ev(intersection(arm, Line(base[0], direction=(0, 1))), s)
    assert abs(x) < 1e-12 and close(y, 9.16729)
    x, y = ev(project_on_line(manivela[2], arm), s)
    assert close(x, -1.15799) and close(y, 8.91557)
    dx, dy = ev(direction(arm), mech.solve(0.45))
    assert close(dx, 4.62876) and close(dy, 1.89067)
    assert ev(magnitude(arm), mech.last) == pytest.approx(5.0, abs=1e-12)
    s = mech.solve(0.5)
    assert close(ev(cross(arm, (0, 3)), s), 13.3458)
    x, y = ev(location(deslizadera, (3, 8)), s)
    assert close(x, 2.81812) and close(y, 18.0)
    r, a = ev(xy_to_polar(location(deslizadera[2])), s)
    assert close(r, 10.1639) and close(a, 1.39095)


def test_evaluate_derivatives(qr_compiled, qr_model):
    """DDistanceDT and D2DistanceDT2 of seed 001 at SolveMech[0.15, ...]."""
    from mechgen import distance, dt
    mech, m = qr_compiled, qr_model
    d = distance(m["manivela"][1], m["deslizadera"][1])
    s = mech.solve(0.15, level="acceleration")
    assert close(mech.evaluate(dt(d), s), -15.1909)
    assert close(mech.evaluate(dt(d, 2), s), -19.056, 5)
    with pytest.raises(ValueError, match="level='velocity'"):
        mech.evaluate(dt(d), mech.solve(0.15))
    with pytest.raises(ValueError, match="acceleration"):
        mech.evaluate(dt(d, 2), mech.solve(0.15, level="velocity"))


def test_evaluate_on_a_sweep_is_vectorised(qr_compiled, qr_model, monkeypatch):
    """One call of the lambdified function for the whole sweep; the values equal those at
    each point; matrices get a leading axis."""
    import mechgen.bridge as ev_mod
    from mechgen import distance, location, velocity
    mech, m = qr_compiled, qr_model
    sw = mech.sweep(0.0, 1.0, 101, level="velocity")
    calls = []
    real = ev_mod._compiled

    def counting(mech_, expr):
        fn, slots, shape = real(mech_, expr)

        def wrapped(*args):
            calls.append(len(args))
            return fn(*args)
        return wrapped, slots, shape
    monkeypatch.setattr(ev_mod, "_compiled", counting)
    d = distance(m["manivela"][1], m["deslizadera"][2])
    values = mech.evaluate(d, sw)
    assert values.shape == (101,) and len(calls) == 1
    for k in (0, 33, 100):
        assert values[k] == pytest.approx(mech.evaluate(d, sw[k]), rel=1e-14)
    loc = mech.evaluate(location(m["deslizadera"][2]), sw)
    assert loc.shape == (101, 2)
    assert np.allclose(loc[:, 1], 10.0) and np.allclose(loc[:, 0], sw["X4"] + 2.0)
    vel = mech.evaluate(velocity(m["deslizadera"][2]), sw)
    assert np.allclose(vel[:, 0], sw["X4d"], atol=1e-12) and np.allclose(vel[:, 1], 0, atol=1e-12)
    const = mech.evaluate(distance(m["manivela"][1], m["manivela"][2]), sw)
    assert const.shape == (101,) and np.allclose(const, 3.0)


def test_evaluate_uses_the_mechanism_parameters(qr_compiled, qr_model):
    from mechgen import distance
    m = qr_model
    crank = distance(m["manivela"][1], m["manivela"][2])
    short = qr_compiled.with_params(longitud=1.5)
    assert short.evaluate(crank, short.solve(0.2)) == pytest.approx(1.5, abs=1e-14)
    assert short.evaluate(m.params["longitud"][0] * 2, short.solve(0.2)) == 3.0


def test_evaluate_rejects_foreign_symbols(qr_compiled):
    import sympy as sp
    s = qr_compiled.solve(0.1)
    with pytest.raises(mechgen.ModelError, match="Z9"):
        qr_compiled.evaluate(sp.Symbol("Z9") + 1, s)
    with pytest.raises(TypeError):
        qr_compiled.evaluate("not an expression [", s)



def test_symbolic_side_is_attached_by_compile_and_kept(qr_compiled, qr_model):
    """mechgen.compile attaches the symbolic side (mechgen.bridge.Symbolic); with_params
    keeps it; a symbolic quantity in the analysis goes through it (the runtime never
    imports sympy itself)."""
    from mechgen import distance, dt
    from mechgen.bridge import Symbolic
    assert isinstance(qr_compiled.symbolic, Symbolic) and qr_compiled.symbolic.model is qr_model
    assert qr_compiled.with_params(longitud=2.0).symbolic is qr_compiled.symbolic
    d = distance(qr_model["manivela"][1], qr_model["deslizadera"][1])
    side = qr_compiled.symbolic
    assert side.level(qr_compiled, d) == 0 and side.level(qr_compiled, dt(d)) == 1
    assert side.level(qr_compiled, dt(d, 2)) == 2
    s = qr_compiled.solve(0.15, level="acceleration")
    assert qr_compiled.evaluate(side.derivative(d), s) == qr_compiled.evaluate(dt(d), s)


def test_symbolic_quantities_need_the_symbolic_side(qr, qr_model):
    """A loaded mechanism (mechgen.load) has no symbolic side: a symbolic quantity says to
    use mechgen.compile, and with only mech.model set by hand, how to attach it."""
    from mechgen import distance
    from mechgen.bridge import attach
    d = distance(qr_model["manivela"][1], qr_model["deslizadera"][1])
    mech = qr.with_params()
    sw = mech.sweep(0.0, 1.0, 11, level="velocity")
    for call in (lambda: sw.extrema(d), lambda: sw.interpolate(d), lambda: mech.evaluate(d, sw)):
        with pytest.raises(mechgen.ModelError, match="mechgen.compile"):
            call()
    mech.model = qr_model
    with pytest.raises(mechgen.ModelError, match=r"mechgen.bridge.attach"):
        sw.roots(d)
    attach(mech, qr_model)
    assert np.allclose(sw.interpolate(d)(sw.t), mech.evaluate(d, sw), atol=1e-12)


def test_sweep_at_level_solves_the_derivatives_at_its_own_positions(qr):
    """Sweep.at_level (Mechanism.solve_derivatives): velocities and accelerations solved at
    a position sweep's own points equal those of solves there; levels held are kept."""
    sw = qr.sweep(0.0, 1.0, 21)
    assert sw.level == "position" and sw.QD is None
    up = sw.at_level("acceleration")
    assert up.level == "acceleration" and up.Q is sw.Q and np.array_equal(up.t, sw.t)
    for k in (0, 7, 15, 20):
        s = qr.solve(sw.t[k], guess=sw.Q[k], level="acceleration")
        assert np.allclose(up.QD[k], s.qd, rtol=1e-12, atol=1e-12)
        assert np.allclose(up.QDD[k], s.qdd, rtol=1e-11, atol=1e-11)
    assert np.allclose(up["X4d"], qr.sweep(0.0, 1.0, 21, level="velocity")["X4d"],
                       rtol=1e-10, atol=1e-10)
    vel = sw.at_level("velocity")
    assert vel.level == "velocity" and vel.QDD is None
    assert up.at_level("velocity").QDD is up.QDD          # a level held is kept
    QD, QDD = qr.solve_derivatives(sw.t, sw.Q, level="velocity")
    assert QDD is None and np.array_equal(QD, vel.QD)


def test_sweep_warm_start_follows_the_branch(qr):
    """A sweep started in the second assembly mode stays there (warm starts, predictor)."""
    sw = qr.sweep(0.85, 1.35, 51, guess={"X4": 1.0}, level="acceleration")
    cold = qr.sweep(0.85, 1.35, 51, level="acceleration")
    assert close(sw["X4"][0], 0.802632)
    assert np.all(sw["X4"] < cold["X4"] - 1.0)
    assert np.max(np.abs(np.diff(sw["X4"]))) < 1.0


# -- a failed solve never returns numbers: NaN in the equations -----------------------------------
@pytest.fixture(scope="module")
def nan_probe(tmp_path_factory):
    """Two equations without a real solution for T < 1: a = √(T − 1) is an explicit block of
    the sorted solver, √b = 1 + T a Newton block started at b = −1 (√ of a negative)."""
    from mechgen import Model, T, sqrt
    m = Model("nan_probe")
    a = m.coordinate("a", guess=1.0)
    b = m.coordinate("b", guess=-1.0)
    m.constraint(a - sqrt(T - 1), name="explicit root")
    m.constraint(sqrt(b) - 1 - T, name="newton root")
    return mechgen.compile(m, outdir=str(tmp_path_factory.mktemp("nan_probe")))


@pytest.mark.parametrize("method", ["auto", "sorted", "full"])
def test_nan_equations_raise(nan_probe, method):
    with pytest.raises(mechgen.ConvergenceError) as info:
        nan_probe.solve(0.0, method=method)
    assert info.value.t == 0.0
    with pytest.raises(mechgen.ConvergenceError):       # the explicit block alone
        nan_probe.solve(0.0, guess={"b": 1.0}, method=method)


def test_nan_equations_solve_where_real(nan_probe):
    s = nan_probe.solve(2.0, guess={"b": 5.0})
    assert s["a"] == pytest.approx(1.0, abs=1e-12) and s["b"] == pytest.approx(9.0, abs=1e-9)
    with pytest.raises(mechgen.ConvergenceError) as info:
        nan_probe.sweep(0.0, 2.0, 5, guess={"b": 5.0})
    assert len(info.value.sweep) == 0


@pytest.mark.parametrize("n", [2, 3, 5, 9])
@pytest.mark.parametrize("level", ["position", "acceleration"])
def test_coarse_sweeps_keep_the_assembly_mode(qr, n, level):
    """A quarter turn of the crank (or more) between points: the sweep still follows the
    branch it started on, the seed's (the closed form of tests/closed_forms.py)."""
    from closed_forms import motion, quick_return
    sw = qr.sweep(0.0, 1.0, n, level=level)
    assert len(sw) == n
    for k in range(n):
        q, qd, qdd = motion(quick_return, sw.t[k])
        assert np.abs(sw.Q[k] - q).max() < 1e-10, (k, sw.t[k])
        if level == "acceleration":
            assert np.abs(sw.QD[k] - qd).max() < 1e-9 * (1 + np.abs(qd).max()), (k, sw.t[k])
            assert np.abs(sw.QDD[k] - qdd).max() < 1e-9 * (1 + np.abs(qdd).max()), (k, sw.t[k])
