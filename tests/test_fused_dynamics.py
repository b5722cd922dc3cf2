"""The multipliers solved in the kinematics' own pass (compiler/functions/dynamics_code.py): a
dynamic sweep's quick path (sweep_fast_forces), a static sweep's (sweep_fast_statics) and
a dynamic solve (dynamics_sorted) against the separate pass over the solved points
(force_rows), numpy's dense solve of Φ_qᵀ λ = Q_a + Q_c − I written here and, at rest,
virtual work; the points the quick path leaves (the careful sweep's, a pivot below
SING_RTOL) solved again; the plain tier's ZeroDivisionError."""
from __future__ import annotations

import os
import re

import numpy as np
import pytest

import mechgen
from mechgen.runtime.forces.points import solve_points
from mechgen.runtime.forces.sweep import attach
from mechgen.runtime.kinematics.solving import sweep as sweep_once

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


@pytest.fixture(scope="module")
def qr():
    """The committed quick-return with masses and a cutting force, compiled (its fast
    sweep writes the multipliers into the loop); in place, sharing numba's cache of it
    with the suite's other users of the module instead of compiling a copy."""
    return mechgen.load(os.path.join(ROOT, "generated", "quick_return_forces.py"),
                        tier="compiled")


def _dense(mech, sw, ks) -> np.ndarray:
    """λ at points ks by numpy's least squares on Φ_qᵀ λ = Q_a + Q_c − I (at rest where
    the sweep has no velocities: a static one)."""
    out = []
    for k in ks:
        q, t = sw.Q[k], float(sw.t[k])
        terms = np.zeros((3, mech.n))
        qd, qdd = (np.zeros(mech.n),) * 2 if sw.QD is None else (sw.QD[k], sw.QDD[k])
        mech.module.force_terms(q, qd, qdd, t, mech.p, terms)
        rhs = terms[0] + terms[1] - terms[2]
        out.append(np.linalg.lstsq(mech.jacobian(q, t).T, rhs, rcond=None)[0])
    return np.array(out)


def _separate(mech, sw, level="dynamic"):
    return solve_points(mech.module, sw.t, sw.Q, sw.QD, sw.QDD, mech.p, level,
                        extras=False)


def _fused_sweep(mech, t0, t1, n, level="acceleration", times=None):
    fused = {}
    sw = sweep_once(mech.state, t0, t1, n, level, None, None, None, None, times, None, fused)
    return sw, fused


def _close(a, b, rtol):
    np.testing.assert_allclose(a, b, rtol=0, atol=rtol * np.abs(b).max())


def test_quick_path_solves_every_point_as_the_separate_pass(qr):
    sw, fused = _fused_sweep(qr, 0.0, 1.0, 2001)
    assert fused["count"] == len(sw)
    assert np.all(fused["FPIV"] >= qr.sing_rtol)
    ref = _separate(qr, sw)
    _close(fused["LAM"], ref.LAM, 1e-13)
    np.testing.assert_array_equal(fused["FACTORS"], ref.FACTORS)
    ks = np.arange(0, 2001, 50)
    _close(fused["LAM"][ks], _dense(qr, sw, ks), 1e-11)
    dyn = qr.sweep(0.0, 1.0, 2001, level="dynamic")
    np.testing.assert_array_equal(dyn.LAM, fused["LAM"])
    assert not dyn.force_singular.any()


def test_the_careful_sweep_s_points_are_solved_after(qr):
    """A step of 1.9 rad of the crank in the middle: the quick path stops there, the
    careful sweep solves the rest; their multipliers come from the separate pass."""
    times = np.concatenate([np.linspace(0.0, 0.3, 61), np.linspace(0.6, 1.0, 41)])
    fused = {}
    sw = sweep_once(qr.state, 0.0, 1.0, len(times), "acceleration", None, None, None, None, times,
                        None, fused)
    assert 0 < fused["count"] < len(sw)
    dyn = attach(sw, "dynamic", fused)
    _close(dyn.LAM, _separate(qr, sw).LAM, 1e-13)
    _close(dyn.LAM[::5], _dense(qr, sw, range(0, len(sw), 5)), 1e-11)


def test_static_quick_path_solves_every_point_as_the_separate_pass(qr):
    """A static sweep's quick path (a position sweep) solves λ at q̇ = q̈ = 0 on its way:
    the separate pass's numbers, numpy's, and what mech.sweep(level="static") returns."""
    assert "def sweep_fast_statics(" in open(qr.module.__file__).read()
    sw, fused = _fused_sweep(qr, 0.0, 1.0, 2001, level="position")
    assert sw.QD is None and fused["count"] == len(sw)
    assert np.all(fused["FPIV"] >= qr.sing_rtol)
    ref = _separate(qr, sw, "static")
    _close(fused["LAM"], ref.LAM, 1e-13)
    np.testing.assert_array_equal(fused["FACTORS"], ref.FACTORS)
    ks = np.arange(0, 2001, 50)
    _close(fused["LAM"][ks], _dense(qr, sw, ks), 1e-11)
    static = qr.sweep(0.0, 1.0, 2001, level="static")
    np.testing.assert_array_equal(static.LAM, fused["LAM"])


def test_static_torque_is_the_rate_of_potential_energy(qr):
    """At rest the crank's torque holds gravity alone (the cutting force acts only while
    the slider moves): by virtual work τ θ̇2 = dV/dt, V = g Σ m y_G, with the centroids of
    examples/quick_return_forces.py and the velocities of a kinematic sweep."""
    L, g, w = 3.0, 9.807, 2 * np.pi
    static = qr.sweep(0.0, 1.0, 401, level="static")
    kin = qr.sweep(0.0, 1.0, 401, level="velocity")
    Q, QD = kin.Q, kin.QD
    c = {name: j for j, name in enumerate(qr.coordinates)}

    def y_rate(y, th, x_local, y_local):      # d/dt of Y + x sin θ + y cos θ
        return QD[:, c[y]] + (x_local * np.cos(Q[:, c[th]]) -
                              y_local * np.sin(Q[:, c[th]])) * QD[:, c[th]]
    dV = g * (2.0 * y_rate("Y2", "Th2", L / 2, 0.0) + 5.0 * y_rate("Y3", "Th3", 0.0, 4.5) +
              3.0 * y_rate("Y4", "Th4", 1.0, 0.2))
    torque = static.driver("crank driver")
    np.testing.assert_allclose(torque, dV / w, rtol=0, atol=1e-10 * np.abs(dV / w).max())


def test_the_static_sweep_s_careful_points_are_solved_after(qr):
    times = np.concatenate([np.linspace(0.0, 0.3, 61), np.linspace(0.6, 1.0, 41)])
    sw, fused = _fused_sweep(qr, 0.0, 1.0, len(times), level="position", times=times)
    assert 0 < fused["count"] < len(sw)
    static = attach(sw, "static", fused)
    _close(static.LAM, _separate(qr, sw, "static").LAM, 1e-13)
    _close(static.LAM[::5], _dense(qr, sw, range(0, len(sw), 5)), 1e-11)


def test_a_point_below_the_pivot_is_solved_again(qr):
    sw, fused = _fused_sweep(qr, 0.0, 1.0, 101)
    ref = _separate(qr, sw).LAM
    fused["FPIV"][[3, 40]] = 0.0, np.nan
    fused["LAM"][3], fused["LAM"][40] = 1e300, np.nan
    dyn = attach(sw, "dynamic", fused)
    _close(dyn.LAM, ref, 1e-13)


def test_a_cam_model_s_step_calls_dynamics_sorted(tmp_path):
    """A model whose solvers are not written into the loop (a cam profile's helper
    functions): the fast sweep calls dynamics_sorted (plain tier: the same text as
    compiled)."""
    import test_contact_forces as tc
    mech = mechgen.compile(tc.cam_model("flat"), outdir=str(tmp_path), tier="python")
    assert "dynamics_sorted(q, t, p, qd, qdd, piv, LAM[k], FACTORS[k])" in \
        open(mech.module.__file__).read()
    sw, fused = _fused_sweep(mech, 0.0, 1.0, 101)
    assert fused["count"] == len(sw)
    _close(fused["LAM"], _separate(mech, sw).LAM, 1e-13)
    _close(fused["LAM"][::10], _dense(mech, sw, range(0, 101, 10)), 1e-11)


def test_dynamic_solve_takes_the_multipliers_from_the_derivatives_pass(qr, monkeypatch):
    ref = qr.sweep(0.0, 0.37, 2, level="dynamic")
    calls = []
    real = qr.module.dynamics_sorted

    def counted(*args):
        calls.append(1)
        return real(*args)

    monkeypatch.setattr(qr.module, "dynamics_sorted", counted)
    s = qr.solve(0.37, level="dynamic", guess=ref.Q[-1])
    assert calls
    _close(s.lam, ref.LAM[-1], 1e-13)
    # the plain tier raises where numba's numpy error model gives inf: solved otherwise

    def raising(*args):
        raise ZeroDivisionError

    monkeypatch.setattr(qr.module, "dynamics_sorted", raising)
    t = qr.solve(0.37, level="dynamic", guess=ref.Q[-1])
    _close(t.lam, ref.LAM[-1], 1e-13)
    np.testing.assert_allclose(t.driver("crank driver"), s.driver("crank driver"), rtol=1e-13)


def test_design_table_of_peak_torque_solves_the_multipliers_in_its_sweeps(qr, monkeypatch):
    """reduce= on the driver of a dynamic table: each design's quick path solves λ on its
    way (sweep_designs_forces), the careful rest after it; the same extremes and times as
    the separate pass (force_rows_designs), designs that cannot turn among them."""
    import mechgen.runtime.tables.chunks as chunks
    kw = dict(params={"longitud": np.linspace(2.0, 6.5, 12)}, on_fail="ignore", workers=1,
              level="dynamic", reduce=["crank driver", "X4"])
    assert chunks.fused_level(qr.module, np.array([[2, 0, 1]]), 2, 0) == 1
    fused = qr.sweep(0.0, 1.0, 201, **kw)
    monkeypatch.setattr(chunks, "fused_level", lambda *args: None)
    separate = qr.sweep(0.0, 1.0, 201, **kw)
    _same_tables(fused, separate)


def _same_tables(fused, separate):
    """The fused table and the separate pass: the same designs done (some not to the end)
    and the same extremes of the crank's effort and of X4, with their times."""
    np.testing.assert_array_equal(fused.done, separate.done)
    assert fused.done.min() < 201 and fused.done.max() == 201
    for name in ("crank driver", "X4"):
        a, b = fused.reduced(name), separate.reduced(name)
        for part in ("min", "max", "tmin", "tmax"):
            x, y = getattr(a, part), getattr(b, part)
            np.testing.assert_allclose(x, y, rtol=1e-12, atol=1e-12 * np.nanmax(np.abs(y)))

def test_static_design_table_solves_the_multipliers_in_its_sweeps(qr, monkeypatch):
    """reduce= on the driver of a static table: each design's position quick path solves
    λ at rest on its way (sweep_designs_statics); the same extremes as the separate pass,
    designs that cannot turn among them."""
    import mechgen.runtime.tables.chunks as chunks
    assert qr.module.STATIC_FUSED
    kw = dict(params={"longitud": np.linspace(2.0, 6.5, 12)}, on_fail="ignore", workers=1,
              level="static", reduce=["crank driver", "X4"])
    assert chunks.fused_level(qr.module, np.array([[2, 0, 0]]), 0, 0) == 0
    assert chunks.fused_level(qr.module, np.array([[2, 0, 0]]), 2, 0) is None
    calls = []
    for step in ("fast", "rest"):       # its quick paths, then the rests of the designs
        real = getattr(qr.module, "sweep_designs_statics_" + step)  # that cannot turn
        monkeypatch.setattr(qr.module, "sweep_designs_statics_" + step,
                            lambda *a, _real=real, _step=step: calls.append(_step) or _real(*a))
    fused = qr.sweep(0.0, 1.0, 201, **kw)
    assert calls == ["fast", "rest"]
    monkeypatch.setattr(chunks, "fused_level", lambda *args: None)
    separate = qr.sweep(0.0, 1.0, 201, **kw)
    _same_tables(fused, separate)


def test_bounds_of_a_row_scale():
    """_bound: |sin|, |cos| <= 1 and nothing else; a coordinate's size is not bounded."""
    import sympy as sp
    from mechgen.compiler.functions.forces_code import _bound, _never_small
    x, X = sp.symbols("x X", real=True)
    scale = sp.Max(1, sp.Abs(2.6 * sp.cos(x) - 40.0 * sp.sin(x)))
    assert _bound(scale) == pytest.approx(42.6)
    assert _bound(sp.Abs(3 * sp.sin(x) ** 2 * sp.cos(2 * x))) == pytest.approx(3.0)
    assert _bound(sp.Max(1, sp.Abs(X * sp.sin(x)))) is None
    assert _never_small(sp.Integer(1), scale) and not _never_small(sp.Float(1e-9), scale)
    assert not _never_small(sp.Abs(sp.cos(x)), scale)        # not a constant


def test_constant_pivots_no_row_scale_can_dwarf_go_untested(tmp_path):
    """The Strandbeest leg with masses: the rows whose pivot is a constant 1 against a
    scale bounded by |a cos + b sin| <= |a| + |b| carry no pivot test in the fused step
    (dynamics_sorted), whose λ still equal numpy's solve of Φ_qᵀ λ = Q_a + Q_c − I, on the
    plain tier (the same text)."""
    import sys
    from mechgen.compiler.build import build
    from mechgen.model.loader import load_models
    sys.path.insert(0, os.path.join(ROOT, "benchmarks"))
    model = load_models(os.path.join(ROOT, "benchmarks", "strandbeest_forces.py"))[0]
    mech = mechgen.load(build(model, str(tmp_path)), tier="python")
    text = open(mech.module.__file__).read()
    fused = text.split("def dynamics_sorted(")[1].split("\ndef ")[0]
    point = text.split("def multipliers_point(")[1].split("\ndef ")[0]
    # the tests left are the 2 x 2 blocks' (_fa<row>a, _fa<row>b): every 1 x 1 block of
    # this leg has a constant pivot, 1, and a scale its trig bounds; multipliers_point
    # (which reports the smallest pivot) tests them all
    left = re.findall(r"not (_fa\w+) >= SING_RTOL", fused)
    assert left and all(name[-1] in "ab" for name in left), left
    assert re.search(r"not _p\d+ >= SING_RTOL", point)
    n = mech.n
    for t in (0.05, 0.4, 0.8):
        s = mech.solve(t, level="acceleration")
        lam, piv = np.zeros(len(mech.module.CONSTRAINT_LABELS)), np.zeros(3)
        factors = np.zeros(len(mech.module.DRIVER_ROWS))
        qd, qdd = np.zeros(n), np.zeros(n)
        assert mech.module.dynamics_sorted(s.q.copy(), t, mech.p, qd, qdd, piv, lam,
                                           factors) == 0
        assert piv[2] == 1.0
        terms = np.zeros((3, n))
        mech.module.force_terms(s.q, qd, qdd, t, mech.p, terms)
        dense = np.linalg.solve(mech.jacobian(s.q, t).T, terms[0] + terms[1] - terms[2])
        _close(lam, dense, 1e-12)
