"""Stages (Mech's TimeSwitch / StageSwitch): constraint sets that switch at given times.

References independent of the stage machinery: the single-stage crank-driven quick-return
(generated/quick_return.py) solved at the mirrored times for the forward-then-back crank,
and at the crank angle the slider stage reaches (with the chain rule for its derivatives)
for the crank-then-slider handover; sympy's lambdify of each stage's own system and finite
differences of the generated Φ for the module's functions on each side of a switch.
"""
from __future__ import annotations

import math
import os
import re

import numpy as np
import pytest
import sympy as sp

import mechgen
from conftest import GENERATED, ROOT, example_model
from mechgen import Model, T, pi
from mechgen.model.printing import equations_text


@pytest.fixture(scope="module")
def staged():
    return mechgen.load(os.path.join(GENERATED, "quick_return_stages.py"))


@pytest.fixture(scope="module")
def handover():
    """On the plain-Python tier: the same text and numbers; numba compiles a staged
    module's switches in ``staged``'s tests."""
    return mechgen.load(os.path.join(GENERATED, "quick_return_crank_slider.py"), tier="python")


def _crank_model(back_law=None, until=0.5):
    """A small crank (one body on a pin) with a two-stage driver."""
    m = Model("crank_stages")
    w = m.param("w", 2 * pi)
    base = m.ground("base", points=[(0, 0)])
    a = m.body("a", points=[(0, 0), (2, 0)], guess=(0, 0, 0))
    m.revolute(base[1], a[1])
    with m.stage("out", until=until):
        m.rotation_lock(a, w * T, name="turn out")
    with m.stage("back"):
        m.rotation_lock(a, w * (1 - T) if back_law is None else back_law(w), name="turn back")
    return m


# -- the seed's quick-return, forward by its crank to T = 0.5 and back after it ----------------
def test_forward_then_back_mirrors_the_single_stage_model(staged, qr):
    sw = staged.sweep(0, 1, 21, level="acceleration")
    assert len(sw) == 22 and list(sw.t).count(0.5) == 2       # the switch time held twice
    (s,) = sw.switches
    assert (s.t, s.before, s.after) == (0.5, "forward", "back")
    assert (s.row_before, s.row_after) == (10, 11)
    assert list(sw.stage) == [0] * 11 + [1] * 11
    worst = [0.0, 0.0, 0.0]
    for k, t in enumerate(sw.t):
        back = sw.stage[k] == 1
        ref = qr.solve(1 - t if back else t, guess=sw.Q[k], level="acceleration")
        sign = -1.0 if back else 1.0
        for j, (got, want) in enumerate(((sw.Q[k], ref.q), (sw.QD[k], sign * ref.qd),
                                         (sw.QDD[k], ref.qdd))):
            worst[j] = max(worst[j], float(np.max(np.abs(got - want))))
    scale = [1.0, float(np.abs(sw.QD).max()), float(np.abs(sw.QDD).max())]
    assert all(w <= 1e-10 * s for w, s in zip(worst, scale)), (worst, scale)
    # positions continuous, velocities reversed, accelerations equal at the switch
    a, b = s.row_before, s.row_after
    assert np.max(np.abs(sw.Q[a] - sw.Q[b])) < 1e-12
    np.testing.assert_allclose(sw.QD[b], -sw.QD[a], atol=1e-10)
    assert abs(sw["Th2d"][a] - 2 * math.pi) < 1e-12 and abs(sw["Th2d"][b] + 2 * math.pi) < 1e-12
    jump = sw.jump("X4d")[0]
    assert abs(jump + 2 * sw["X4d"][a]) < 1e-10 and abs(jump) > 1.0
    assert sw.jump("X4")[0] == pytest.approx(0.0, abs=1e-12)


def test_sweep_analysis_does_not_smooth_across_the_switch(staged, qr):
    sw = staged.sweep(0, 1, 21, level="acceleration")
    at = qr.solve(0.5, level="velocity")
    f = sw.interpolate("X4d")
    left, right = float(f(0.5 - 1e-9)), float(f(0.5))
    assert abs(left - at["X4d"]) < 1e-6 and abs(right + at["X4d"]) < 1e-6
    x4 = sw.interpolate("X4")
    assert abs(x4(0.5) - at["X4"]) < 1e-12
    np.testing.assert_allclose(x4(np.array([0.3, 0.7])), [x4(0.3), x4(0.7)])
    # X4 turns round at the switch: an extreme there, at the exact switch position
    ex = sw.extrema("X4")
    at_switch = [e for e in ex if e.t == 0.5]
    assert len(at_switch) == 1 and at_switch[0].method == "switch"
    assert abs(at_switch[0].value - at["X4"]) < 1e-12
    # the single-stage sweep's extremes inside (0, 0.5) appear mirrored in (0.5, 1)
    ref = qr.sweep(0, 1, 21, level="acceleration").extrema("X4")
    inside = [e.t for e in ref if 0 < e.t < 0.5]
    got = [e.t for e in ex if e.method != "switch"]
    for t in inside:
        assert min(abs(g - t) for g in got) < 1e-9 and min(abs(g - (1 - t)) for g in got) < 1e-9
    # the velocity jumps through zero at the switch: no root there
    assert all(abs(e.t - 0.5) > 1e-6 for e in sw.roots("X4d"))


def test_a_sweep_that_crosses_no_switch_is_an_ordinary_sweep(staged, qr):
    sw = staged.sweep(0.6, 0.9, 4, level="velocity")
    assert type(sw) is mechgen.Sweep and len(sw) == 4
    ref = qr.sweep(0.4, 0.1, 4, level="velocity")
    np.testing.assert_allclose(sw.Q, ref.Q, atol=1e-10)
    assert type(qr.sweep(0, 1, 5)) is mechgen.Sweep        # a model without stages


# -- crank-driven, then slider-driven (the seed's sections 2A and 2B) --------------------------
def test_crank_then_slider_against_the_crank_model(handover, qr):
    sw = handover.sweep(0, 0.5, 11, level="acceleration")
    (s,) = sw.switches
    assert (s.t, s.before, s.after) == (0.25, "crank", "slider")
    w = 2 * math.pi
    t = sw.t
    law = np.sqrt(24) + np.sin(w * (t - 0.25))
    slider = sw.stage == 1
    assert np.max(np.abs(sw["X4"][slider] - law[slider])) < 1e-10
    assert np.max(np.abs(sw["X4d"][slider] - w * np.cos(w * (t[slider] - 0.25)))) < 1e-9
    assert np.max(np.abs(sw.Q[s.row_before] - sw.Q[s.row_after])) < 1e-10
    for k in range(len(sw)):
        # the crank model at the crank angle reached: the same configuration; its
        # derivatives by the chain rule, tau(t) = Th2 / w
        tau, tau_d, tau_dd = sw["Th2"][k] / w, sw["Th2d"][k] / w, sw["Th2dd"][k] / w
        ref = qr.solve(tau, guess=sw.Q[k], level="acceleration")
        np.testing.assert_allclose(sw.Q[k], ref.q, atol=1e-10)
        np.testing.assert_allclose(sw.QD[k], ref.qd * tau_d, atol=1e-9)
        np.testing.assert_allclose(sw.QDD[k], ref.qdd * tau_d ** 2 + ref.qd * tau_dd, atol=1e-8)
        if not slider[k]:
            assert abs(tau - t[k]) < 1e-12


def test_a_backward_sweep_crosses_the_switch_too(handover):
    fw = handover.sweep(0, 0.5, 11, level="velocity")
    bw = handover.sweep(0.5, 0, 11, level="velocity", guess=fw[-1])
    (s,) = bw.switches
    assert (s.before, s.after) == ("slider", "crank")
    np.testing.assert_allclose(bw.Q[::-1], fw.Q, atol=1e-10)
    np.testing.assert_allclose(bw.QD[::-1], fw.QD, atol=1e-9)
    assert bw.jump("X4d")[0] == pytest.approx(-fw.jump("X4d")[0], abs=1e-9)


def test_stages_that_disagree_in_position_are_refused_when_swept(handover):
    # at velocidad = pi the crank stands at 45 degrees at T = 0.25: the slider law's
    # sqrt(24) is not where the crank left the slider
    with pytest.raises(mechgen.ModelError) as err:
        handover.with_params(velocidad=math.pi).sweep(0, 0.5, 11)
    text = str(err.value)
    for part in ("'crank'", "'slider'", "t=0.25", "disagree in position", "slider driver"):
        assert part in text, text
    solved = err.value.sweep            # what was solved before the switch, and no more
    assert solved.t[-1] == 0.25 and len(solved) == 6 and not solved.switches


def test_a_driver_law_that_jumps_is_refused_at_the_model():
    m = _crank_model(back_law=lambda w: w * (2 - T))
    with pytest.raises(mechgen.ModelError) as err:
        m.equations()
    text = str(err.value)
    for part in ("'out'", "'back'", "t=0.5", "disagree in position", "turn back"):
        assert part in text, text
    _crank_model().equations()          # the continuous law is accepted


def test_stage_declarations_are_checked():
    m = Model("bad_stages")
    base = m.ground("base", points=[(0, 0)])
    a = m.body("a", points=[(0, 0), (2, 0)])
    m.revolute(base[1], a[1])
    with pytest.raises(mechgen.ModelError, match="until= must be a number"):
        m.stage("s", until="soon")
    with m.stage("one", until=1.0):
        with pytest.raises(mechgen.ModelError, match="do not nest"):
            with m.stage("inner", until=2.0):
                pass
        m.rotation_lock(a, T)
    with pytest.raises(mechgen.ModelError, match="must come after"):
        m.stage("early", until=0.5)
    with pytest.raises(mechgen.ModelError, match="declared twice"):
        m.stage("one")
    with pytest.raises(mechgen.ModelError, match="no stage follows"):
        m.equations()
    with m.stage("two"):
        m.relative_x(a[2], 1.0 + T)
        m.relative_y(a[2], 0.0)
    with pytest.raises(mechgen.ModelError, match=r"different numbers of equations \('one' 1, 'two' 2\)"):
        m.equations()
    with pytest.raises(mechgen.ModelError, match="which has no until"):
        m.stage("three")


# -- the emitted functions on each side of the switch ----------------------------------------
def _lambdified(view):
    eq = view.equations()
    args = (list(eq.q), list(eq.qd), list(eq.params), T)
    return {k: sp.lambdify(args, getattr(eq, k), modules="numpy")
            for k in ("phi", "phi_q", "nu", "gamma")}


@pytest.mark.parametrize("name", ["quick_return_stages", "quick_return_crank_slider"])
def test_functions_match_each_stage_and_finite_differences(name):
    model = example_model(name)
    mech = mechgen.load(os.path.join(GENERATED, f"{name}.py"))
    mod, m, n = mech.module, mech.m, mech.n
    rng = np.random.default_rng(15)
    views = [_lambdified(model.stage_view(s)) for s in model.stages]
    ts = model.switch_times[0]
    for t in (ts - 0.2, ts - 1e-3, ts, ts + 1e-3, ts + 0.2):
        ref = views[int(t >= ts)]
        for _ in range(2):
            q = mech.guess + rng.uniform(-1, 1, n)
            qd = rng.uniform(-3, 3, n)
            p = mech.p * (1 + 0.1 * rng.uniform(-1, 1, mech.p.size))
            got = {"phi": np.empty(m), "phi_q": np.empty((m, n)), "nu": np.empty(m),
                   "gamma": np.empty(m)}
            mod.phi(q, t, p, got["phi"])
            mod.phi_q(q, t, p, got["phi_q"])
            mod.nu(q, t, p, got["nu"])
            mod.gamma(q, qd, t, p, got["gamma"])
            for key, value in got.items():
                want = np.array(ref[key](q, qd, p, t), dtype=float).reshape(value.shape)
                np.testing.assert_allclose(value, want, rtol=1e-12, atol=1e-10,
                                           err_msg=f"{name} {key} at t={t}")
            # finite differences of Φ, staying on the side of the switch t is on
            h = 1e-6

            def phi(qq, tt):
                out = np.empty(m)
                mod.phi(qq, tt, p, out)
                return out

            J = np.column_stack([(phi(q + h * e, t) - phi(q - h * e, t)) / (2 * h)
                                 for e in np.eye(n)])
            np.testing.assert_allclose(got["phi_q"], J, atol=1e-6 * max(1, np.abs(J).max()))
            step = h if t >= ts else -h      # one-sided in t at the switch itself
            dt = (phi(q, t + step) - phi(q, t)) / step if t == ts else \
                (phi(q, t + h) - phi(q, t - h)) / (2 * h)
            np.testing.assert_allclose(got["nu"], -dt, atol=1e-5 * max(1, np.abs(dt).max()))
            # γ = Φ_q q̈ − d²Φ(q(t), t)/dt² along q(t) = q + qd s + qdd s²/2
            qdd = rng.uniform(-3, 3, n)
            hs = 1e-4
            if t == ts:      # one-sided at the switch itself (the later stage holds there)
                steps, tol = (0.0, hs, 2 * hs), 1e-2
            else:
                steps, tol = (-hs, 0.0, hs), 1e-4
            path = [phi(q + qd * s + 0.5 * qdd * s * s, t + s) for s in steps]
            d2 = (path[2] - 2 * path[1] + path[0]) / hs ** 2
            want = got["phi_q"] @ qdd - d2
            np.testing.assert_allclose(got["gamma"], want, atol=tol * max(1, np.abs(want).max()))


# -- printing and the module's docstring --------------------------------------------------------
def test_equations_print_each_stage_with_its_time_range():
    m = _crank_model()
    text = equations_text(m)
    assert "Stage 1 of 2 'out': t < 0.5" in text and "Stage 2 of 2 'back': t >= 0.5" in text
    first, second = text.split("Stage 2 of 2")
    assert "-T*w + Th2 = 0" in first and "Th2 - w*(1 - T) = 0" in second
    assert re.search(r"\[3\]  w +# 2 turn out", first)
    assert re.search(r"\[3\]  -w +# 3 turn back", second)
    latex = equations_text(m, latex=True)
    assert "% Stage 1 of 2 'out': t < 0.5" in latex and "% Stage 2 of 2 'back'" in latex
    assert r"\nu_{3} &= - w" in latex


def test_the_reference_quotes_the_printed_stages():
    from test_constraint_reference import DOC
    text = open(DOC, encoding="utf-8").read()
    quoted = re.search(r"<!-- stages printed: stages -->\n```text\n(.*?)```", text, re.S).group(1)
    model = mechgen.load_model(os.path.join(ROOT, "docs", "stage_examples.py"))
    out, keep = [], False
    for line in equations_text(model).splitlines():
        if line.startswith("Stage "):
            out.append(line)
        elif line.startswith(("Phi(q, t) = 0", "nu = -Phi_t")):
            keep = True
            out.append(line)
        elif not line.strip():
            keep = False
        elif keep:
            out.append(line)
    assert quoted == "\n".join(out) + "\n"


def test_module_states_its_stages(staged):
    mod = staged.module
    assert mod.SWITCH_TIMES == (0.5,)
    assert mod.STAGES == (("forward", -math.inf, 0.5), ("back", 0.5, math.inf))
    doc = mod.__doc__
    assert "Stages (2; the constraint set switches at t = 0.5)" in doc
    assert "1. forward: t < 0.5" in doc and "2. back: t >= 0.5" in doc
    assert "crank back: rotation_lock(manivela, base, velocidad*(1 - T))" in doc
    # a model without stages states none
    plain = open(os.path.join(GENERATED, "quick_return.py"), encoding="utf-8").read()
    assert "SWITCH_TIMES" not in plain and "Stages (" not in plain


def test_singularities_are_searched_stage_by_stage(handover):
    # det Φ_q changes sign at the switch (another row takes over) without any rank loss
    assert handover.singularities(0, 0.5) == []
    # a slider law that overshoots the stroke locks the mechanism in the slider stage where
    # X4 reaches its largest value, 9 * 3/5 + sqrt(25 - (10 - 9 * 4/5)^2) (lever tangent
    # to the crank circle)
    x_max = 5.4 + math.sqrt(25 - 2.8 ** 2)
    t_lock = 0.25 + math.asin((x_max - math.sqrt(24)) / 5) / (2 * math.pi)
    found = handover.with_params(amplitud=5.0).singularities(0, 1)
    assert found and found[0].kind == "lock" and abs(found[0] - t_lock) < 1e-8, found


def test_three_stages_switch_in_turn():
    m = Model("crank3")
    w = m.param("w", 2 * pi)
    base = m.ground("base", points=[(0, 0)])
    a = m.body("a", points=[(0, 0), (2, 0)], guess=(0, 0, 0))
    m.revolute(base[1], a[1])
    with m.stage("out", until=0.25):
        m.rotation_lock(a, w * T, name="turn out")
    with m.stage("dwell", until=0.5):
        m.rotation_lock(a, w / 4, name="dwell")
    with m.stage("back"):
        m.rotation_lock(a, w * (0.75 - T), name="turn back")
    assert m.switch_times == (0.25, 0.5)
    assert [s.range_text() for s in m.stages] == ["t < 0.25", "0.25 <= t < 0.5", "t >= 0.5"]
    eq = m.equations()
    th, thd = eq.q[2], eq.qd[2]
    f = sp.lambdify((th, T, w), eq.phi[2])
    nu = sp.lambdify((T, w), eq.nu[2])
    w0 = 2 * math.pi
    for t, angle, speed in ((0.1, w0 * 0.1, w0), (0.25, w0 / 4, 0.0), (0.4, w0 / 4, 0.0),
                            (0.5, w0 / 4, -w0), (0.9, w0 * (0.75 - 0.9), -w0)):
        assert abs(f(angle, t, w0)) < 1e-12 and abs(nu(t, w0) - speed) < 1e-12, t
    assert eq.gamma[2] == 0 and thd not in eq.phi_q.free_symbols
