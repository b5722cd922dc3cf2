"""The fast sweep's step (issue 6): the position solve and the derivative pass written out
as one piece of code, sin and cos shared between them, turned by Newton steps and taken
from closed forms — each checked against the separate solvers and the careful sweep."""
import inspect
import math

import numpy as np
import pytest
import sympy as sp

import mechgen
from mechgen.compiler.codegen.ir import Assign, Guard, render
from mechgen.compiler.codegen.schedule import emit
from mechgen.runtime.kinematics.guesses import start_vector

from conftest import example_model


def test_turn_is_sin_and_cos_of_the_new_angle(qr):
    """_turn(sin y, cos y, d, y − d) against math.sin and math.cos of y − d, for steps in
    the series branch and beyond it."""
    turn = qr.module._turn
    rng = np.random.default_rng(6)
    for y in rng.uniform(-7.0, 7.0, 40):
        for d in (0.0, 1e-14, -3e-11, 2e-8, -9.9e-6, 1e-5, 0.3, -2.0):
            s, c = turn(math.sin(y), math.cos(y), d, y - d)
            assert abs(s - math.sin(y - d)) < 5e-16 and abs(c - math.cos(y - d)) < 5e-16


def _fast_and_careful(mech, ts, guess=None):
    mod, n, N = mech.module, mech.n, len(ts)
    q0 = start_vector(mech, guess)
    out = []
    for fn in ("sweep_fast", "sweep"):
        Q, QD, QDD = np.zeros((N, n)), np.zeros((N, n)), np.zeros((N, n))
        STATUS = np.zeros((N, 2), dtype=np.int16)
        if fn == "sweep_fast":
            done = mod.sweep_fast(ts, q0, mech.p, 1e-10, 1e-10, 50, Q, QD, QDD, STATUS)
        else:
            done = mod.sweep(ts, q0, mech.p, 2, 1e-10, 1e-10, 50, 1, Q, QD, QDD, STATUS,
                             np.zeros(8))
        assert done == N, f"{fn} stopped at point {done}"
        out.append((Q, QD, QDD))
    return out


@pytest.mark.parametrize("name, t1", [("qr", 1.0), ("qr_slider", 0.2), ("fourbar", 1.0),
                                       ("fourbar_loop", 1.0)])
def test_fast_sweep_agrees_with_the_careful_sweep(request, name, t1):
    mech = request.getfixturevalue(name)
    ts = np.linspace(0.0, t1, 400)
    (Q, QD, QDD), (Qc, QDc, QDDc) = _fast_and_careful(mech, ts)
    scale = 1.0 + np.abs(Qc).max()
    assert np.abs(Q - Qc).max() < 1e-11 * scale
    assert np.abs(QD - QDc).max() < 1e-9 * (1.0 + np.abs(QDc).max())
    assert np.abs(QDD - QDDc).max() < 1e-8 * (1.0 + np.abs(QDDc).max())


def test_fast_sweep_calls_trigonometry_only_where_it_must(qr):
    """In the quick-return's step only the crank angle (driven) needs sin and cos: the
    lever's (Th3) and Th4's come from their closed forms, and the derivative pass reuses
    them all; the lever's guess is read for its assembly sign at the first point only."""
    src = inspect.getsource(qr.module.sweep_fast)
    calls = sorted(set(x for x in src.split() if x.startswith("math.sin(")
                       or x.startswith("math.cos(")))
    assert calls == ["math.cos(Th2)", "math.sin(Th2)"]
    assert src.count("math.sin(") == 2 and src.count("math.cos(") == 2
    first = src[src.index("if k == 0:"):]
    assert first.index("math.cos(Th3)") < first.index("_sg_Th3 = ")
    assert "Th4dd = 0" in src                  # a constant γ row folded: no 0 / pivot


def test_solver_argument_names_are_free_for_the_model():
    """They were reserved; the compiler now writes such a parameter under another name
    (tests/test_names.py builds and solves models that use them)."""
    m = mechgen.Model("reserved")
    for name in ("tol", "xtol", "maxit", "info", "piv"):
        m.param(name, 1.0)
    assert list(m.params) == ["tol", "xtol", "maxit", "info", "piv"]


def test_invariant_assignments_and_guards_are_hoisted_out_of_a_loop():
    x, c, den, y = sp.symbols("x c _den_y y")
    st = [Assign(den, 2 * sp.cos(c)), Guard(den, sp.Float(1e-12), "4"), Assign(y, x / den)]
    before, inside = (render(part) for part in emit(st, variant={x}))
    assert before[0].startswith("_den_y = ") and before[1].startswith("if not abs(_den_y)")
    assert len(inside) == 1 and inside[0].startswith("y = ")


def test_closed_form_sin_and_cos_of_the_root(build_dir):
    """--closed-forms all: Th3 comes from a sin + b cos + c = 0 and its sin and cos from
    a, b and the root choice; the sweep agrees with Newton everywhere on the cycle."""
    import os
    from mechgen.compiler.build import build
    m = example_model("quick_return")
    m.name = "quick_return_turn_all"
    # plain Python (the same text and numbers; numba compiles the closed forms' turned sin
    # and cos in generated/quick_return.py's step, the tests above)
    mech = mechgen.load(build(m, os.path.join(build_dir, "turn"), closed_forms="all"),
                        tier="python")
    src = inspect.getsource(mech.module.sweep_fast)
    step = src[:src.index("if k == 0:")] + src[src.index("_sg_Th3 = 1.0 if"):]
    assert "math.sin(Th3)" not in step and "math.cos(Th3)" not in step   # but at the first point
    ts = np.linspace(0.0, 1.0, 300)
    (Q, QD, QDD), (Qc, _, _) = _fast_and_careful(mech, ts)
    assert np.abs(Q - Qc).max() < 1e-11


def test_turned_sin_and_cos_do_not_drift_on_a_long_sweep(qr):
    """20,000 points: the pairs turned from point to point are called afresh every few
    points, so the quick path stays as accurate as the careful sweep that calls them at
    every point."""
    src = inspect.getsource(qr.module.sweep_fast)
    assert "_turn(_sw_sin_Th2, _sw_cos_Th2" in src
    assert "Th3 = _sw_Th3 + _sd * (" in src       # the lever's angle from the last point's
    ts = np.linspace(0.0, 1.0, 20_000)
    (Q, QD, QDD), (Qc, QDc, QDDc) = _fast_and_careful(qr, ts)
    assert np.abs(Q - Qc).max() < 2e-14
    assert np.abs(QD - QDc).max() < 1e-12


def test_solve_point_equals_the_call_by_call_solve(qr, qr_slider):
    """Mechanism.solve() (one compiled call: the module's solve_point /
    solve_point_derivatives) gives what the module's separate solvers give step by step:
    the same position, velocities and accelerations bit for bit, the same flags, and an
    error of the right kind where a step fails."""
    from test_robustness import NEAR_T1, T1
    from mechgen.protocol import METHOD_AUTO as AUTO
    from mechgen.protocol import INFO_ITERATIONS, INFO_RANK, LEVEL, LEVELS, OK, \
        POINT_INFO_SIZE, SING_RTOL
    for mech, cases in ((qr, [(0.15, None), (0.85, {"X4": 1.0}), (0.6, None)]),
                        (qr_slider, [(0.0, None), (T1, NEAR_T1), (0.25, NEAR_T1)])):
        mod, p = mech.module, mech.p
        for t, guess in cases:
            if guess is None:       # Newton from the model's guess (no guess follows the motion)
                guess = dict(zip(mech.coordinates, mech.guess.copy()))
            for level in LEVELS:
                lev = LEVEL[level]
                q, info = start_vector(mech, guess), np.zeros(POINT_INFO_SIZE)
                status = mod.solve_position(q, t, p, mech.tol, mech.xtol, mech.maxit, AUTO, info)
                expected = None if status == OK else mechgen.ConvergenceError
                singular = int(info[INFO_RANK]) < mech.n or not mod.pivot_ratio(q, t, p) >= SING_RTOL
                qd = qdd = None
                if expected is None and lev >= LEVEL["velocity"]:
                    qd = np.empty(mech.n)
                    if singular or mod.solve_velocity(q, t, p, AUTO, qd) != OK:
                        expected = mechgen.SingularError
                if expected is None and lev >= LEVEL["acceleration"]:
                    qdd = np.empty(mech.n)
                    if mod.solve_acceleration(q, qd, t, p, AUTO, qdd) != OK:
                        expected = mechgen.SingularError
                if expected is not None:
                    with pytest.raises(expected):
                        mech.solve(t, guess=guess, level=level)
                    continue
                s = mech.solve(t, guess=guess, level=level)
                assert np.array_equal(s.q, q)
                for got, want in ((s.qd, qd), (s.qdd, qdd)):
                    assert (got is None) == (want is None)
                    assert want is None or np.array_equal(got, want)
                assert s.singular == singular and s.iterations == int(info[INFO_ITERATIONS])
                assert s.residual == mech.residual(q, t)
