"""A position sweep with sensitivities solves them in its quick path
(docs/reference/sensitivities.md; mechgen/compiler/sensitivity_sweep.py,
mechgen/runtime/sensitivity/fused.py): the sensitivity module's sweep_fast_sensitivities
runs in place of the module's sweep_fast, and its derivatives are those of the separate
pass over the sweep's points (of_sweep) to rounding, and those of the closed form
(tests/sensitivity_closed_forms.py, mpmath) to 1e-8. Where the quick path stops (a
sweep into a change point) the careful continuation's points take the separate pass's
derivatives, bit for bit.

Bugs planted by hand and caught here: the loop's sin and cos swapped in the fused
statements (sensitivity_sweep.fused_statements); the wanted columns taken as the first
len(cols) (fused.py: want[:len(cols)]); the continuation's pass started at the last
vouched point instead of the multiple of 8 before it (fused.py: start = vouched)."""
import math

import numpy as np
import pytest

import mechgen
import models
import sensitivity_closed_forms as cf
from mechgen.runtime.sensitivity.companion import companion
from mechgen.runtime.sensitivity.solve import of_sweep

TIER = "python"     # the plain tier: the same text as numba's, no compile
RTOL = 1e-8
FOURBAR = dict(a=0.8, b=2.5, c=2.0, d=3.0, omega=2 * math.pi, theta0=math.pi / 3)
CHANGE_POINT = dict(a=1.0, b=3.0, c=2.0, d=2.0)   # a + b = c + d: all four links on one
T_CHANGE = 5 / 6                                   # line at θ = π/3 + 2πT = 2π


@pytest.fixture(scope="module")
def mech(tmp_path_factory):
    fb = models.four_bar("sens_fused", **FOURBAR, params={k: k for k in FOURBAR})
    return mechgen.compile(fb.m, outdir=str(tmp_path_factory.mktemp("fused")), tier=TIER)


def _spy(monkeypatch, mech):
    """The counts the companion's sweep_fast_sensitivities returned, one per call."""
    comp, _ = companion(mech)
    assert comp.SWEEP_FUSED, "a four-bar's sensitivity module has the fused quick path"
    calls, real = [], comp.sweep_fast_sensitivities

    def spy(ts, *args):
        calls.append((len(ts), real(ts, *args)))
        return calls[-1][1]
    monkeypatch.setattr(comp, "sweep_fast_sensitivities", spy)
    return calls


def test_the_quick_path_solves_the_sensitivities(mech, monkeypatch):
    calls = _spy(monkeypatch, mech)
    names = ["a", "d", "omega"]
    n = 120
    sw = mech.sweep(0.0, 1.0, n, sensitivities=names)
    assert calls == [(n, n)], "the fused quick path ran once and vouched for every point"
    plain = mech.sweep(0.0, 1.0, n)
    assert np.array_equal(sw.Q, plain.Q), "the sweep itself is the one without sensitivities"
    ref = of_sweep(mech, plain, names)
    cols = ref.columns
    got = sw.sensitivities.full[0]
    assert got.shape == ref.full[0].shape
    others = [j for j in range(len(mech.parameter_names)) if j not in cols]
    assert np.isnan(got[:, :, others]).all(), "the columns not asked for are NaN"
    # the separate pass turns sin and cos from Q; the loop holds the position code's own
    scale = np.abs(ref.full[0][:, :, cols]).max()
    np.testing.assert_allclose(got[:, :, cols], ref.full[0][:, :, cols], rtol=1e-12,
                               atol=1e-13 * scale)
    assert not sw.sensitivities.singular.any() and len(sw.sensitivity_singular) == 0
    for k in (0, 17, 59, 101, n - 1):
        t = float(sw.t[k])
        q, _, _ = cf.motion(cf.fourbar, t, FOURBAR)
        np.testing.assert_allclose(sw.Q[k], q, rtol=1e-9, atol=1e-9, err_msg=f"q at t={t}")
        dq, _, _ = cf.sensitivities(cf.fourbar, t, FOURBAR, names)
        for j, p in enumerate(names):
            np.testing.assert_allclose(got[k, :, cols[j]], dq[:, j],
                                       rtol=RTOL, atol=RTOL * max(1.0, np.abs(dq).max()),
                                       err_msg=f"dq/d{p} at t={t}")
        assert sw.sensitivity("Th4", "d")[k] == got[k, 8, cols[1]]


@pytest.mark.filterwarnings("ignore::mechgen.BranchJumpWarning")
def test_the_careful_continuation_takes_the_separate_pass(mech, monkeypatch):
    changed = mech.with_params(**CHANGE_POINT)
    calls = _spy(monkeypatch, changed)
    n = 101
    sw = changed.sweep(0.5, T_CHANGE, n, sensitivities=["a", "d"])
    assert len(calls) == 1 and 0 < calls[0][1] < n, \
        "the quick path stops before the change point; sweep() goes on"
    plain = changed.sweep(0.5, T_CHANGE, n)
    assert np.array_equal(sw.Q, plain.Q)
    ref = of_sweep(changed, plain, ["a", "d"])
    got, want = sw.sensitivities.full[0], ref.full[0]
    vouched = calls[0][1] - 1
    # the careful points: the separate pass's numbers, bit for bit
    assert np.array_equal(got[vouched:], want[vouched:], equal_nan=True)
    finite = np.isfinite(want)
    np.testing.assert_allclose(got[finite], want[finite], rtol=1e-11, atol=1e-12)
    assert np.array_equal(sw.sensitivities.singular, ref.singular)
    assert ref.singular[-1] and not ref.singular[:-1].any()
    assert np.allclose(sw.sensitivity_singular, [T_CHANGE])
    params = dict(FOURBAR, **CHANGE_POINT)
    for k in (0, vouched // 2, n - 2):
        t = float(sw.t[k])
        dq, _, _ = cf.sensitivities(cf.fourbar, t, params, ["a", "d"])
        cols = ref.columns
        np.testing.assert_allclose(got[k][:, cols], dq, rtol=1e-6,
                                   atol=1e-6 * max(1.0, np.abs(dq).max()),
                                   err_msg=f"dq/dp at t={t}, {k} of {n}")


@pytest.mark.parametrize("options", [dict(level="velocity"), dict(cse=False)])
def test_only_a_default_build_gets_the_fused_quick_path(tmp_path, options):
    """The fused quick path copies a default build's fast sweep: a module built otherwise
    (another level, no common subexpressions) has none, and its sweep's sensitivities
    come from the separate pass, still those of the closed form's module."""
    fb = models.four_bar("sens_other", **FOURBAR, params={k: k for k in FOURBAR})
    other = mechgen.compile(fb.m, outdir=str(tmp_path / "other"), tier=TIER, **options)
    plain = mechgen.compile(fb.m, outdir=str(tmp_path / "plain"), tier=TIER)
    assert companion(plain)[0].SWEEP_FUSED
    assert not companion(other)[0].SWEEP_FUSED
    a = other.sweep(0.0, 0.5, 40, level="position", sensitivities=True)
    b = plain.sweep(0.0, 0.5, 40, level="position", sensitivities=True)
    assert np.allclose(a.dq_dp, b.dq_dp, rtol=1e-10, atol=1e-12)
