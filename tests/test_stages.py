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
import warnings

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


# -- sweeps that end or start exactly at a switch, times that hold a switch twice, design
# tables across a switch. Reference: the seed's quick-return in closed form. Crank pin
# P = (L cos θ, 5 + L sin θ), lever angle Th3 = atan2(-Px, Py), lever tip
# C = 9 (-sin Th3, cos Th3), slider X4 = Cx + sqrt(25 - (10 - Cy)^2); the stage laws θ = w T
# (forward) and θ = w (1 - T) (back), so that dX4/dT = ±w dX4/dθ (central differences in θ)
W = 2 * math.pi


def _x4(theta, L=3.0):
    px, py = L * math.cos(theta), 5 + L * math.sin(theta)
    th3 = math.atan2(-px, py)
    cx, cy = -9 * math.sin(th3), 9 * math.cos(th3)
    return cx + math.sqrt(25 - (10 - cy) ** 2)


def _x4_theta(theta, h=1e-6):
    return (_x4(theta + h) - _x4(theta - h)) / (2 * h)


@pytest.mark.parametrize("ends", [(0.0, 0.5), (0.5, 0.0)])
@pytest.mark.parametrize("level", ["position", "velocity", "acceleration"])
def test_a_sweep_ending_at_the_switch_interpolates_the_later_stage_there(staged, ends, level):
    # sweep(0, 0.5, 11) holds t = 0.5 twice, its last row the 'back' stage's (X4d = +16.787,
    # as solve(0.5) gives); its interpolant gave the left limit there (-16.787), where the
    # reference says it gives the later stage's value, as a solve there does
    sw = staged.sweep(*ends, 11, level=level)
    right = -W * _x4_theta(math.pi)         # θ = w (1 - T): dX4/dT = -w dX4/dθ
    assert right == pytest.approx(16.787172386769743, rel=1e-8)
    assert staged.solve(0.5, level="velocity")["X4d"] == pytest.approx(right, rel=1e-8)
    f = sw.interpolate("X4")
    assert f(0.5) == pytest.approx(_x4(math.pi), abs=1e-12)
    assert f(0.5, 1) == pytest.approx(right, rel=1e-8)
    assert f.derivative()(0.5) == pytest.approx(right, rel=1e-8)
    assert f(0.5 - 1e-9, 1) == pytest.approx(-right, rel=2e-2)      # the left limit below it
    assert f(0.25) == pytest.approx(_x4(W * 0.25), abs=1e-4)
    if level != "position":
        assert sw.interpolate("X4d")(0.5) == pytest.approx(right, rel=1e-8)


def test_a_sweep_ending_at_the_switch_keeps_its_end_extreme(staged):
    # X4d jumps from -16.787 to +16.787 at the switch that ends the sweep: the sweep's end
    # (its last row, +16.787, the largest of its values) was lost from extrema()
    for ends, at in (((0.0, 0.5), "end"), ((0.5, 0.0), "start")):
        sw = staged.sweep(*ends, 11, level="acceleration")
        ex = sw.extrema("X4d")
        top = [e for e in ex if e.t == 0.5]
        assert len(top) == 1 and top[0].kind == "max" and top[0].at == at, ex
        assert top[0].value == pytest.approx(-W * _x4_theta(math.pi), rel=1e-8)
        assert top[0].value == pytest.approx(float(np.max(sw["X4d"])), abs=1e-12)
        # X4 continuous and turning round there: one extreme, the switch's minimum
        ex = sw.extrema("X4")
        at_switch = [e for e in ex if e.t == 0.5]
        assert len(at_switch) == 1 and at_switch[0].kind == "min"
        assert at_switch[0].value == pytest.approx(_x4(math.pi), abs=1e-12)


def test_times_that_hold_the_switch_twice_are_swept(staged):
    # a staged sweep's own times (the switch held twice) given back as times=: refused
    # ("needs strictly monotonic times"); now the same sweep
    a = staged.sweep(0, 1, 6, level="velocity")
    for ts in (a.t, a.t[::-1]):
        b = staged.sweep(None, None, None, times=ts, level="velocity")
        assert np.array_equal(b.t, ts) and len(b.switches) == 1
        order = slice(None) if ts[0] < ts[-1] else slice(None, None, -1)
        np.testing.assert_allclose(b.Q[order], a.Q, atol=1e-12)
        np.testing.assert_allclose(b.QD[order], a.QD, atol=1e-10)
    with pytest.raises(ValueError, match="strictly monotonic"):
        staged.sweep(None, None, None, times=[0.0, 0.2, 0.2, 0.8])     # not a switch time


_TABLE_SCRIPT = r"""
import json, sys, warnings
import numpy as np
import mechgen
from mechgen.model.loader import load_models, pick_model
model = pick_model(load_models(sys.argv[1]), None)
mech = mechgen.compile(model, outdir=sys.argv[2], tier="python")
warnings.simplefilter("ignore")
for level in ("velocity", "acceleration"):
    tab = mech.sweep(None, None, None, times=[0.0, 0.1, 0.25 - 1e-12, 0.25, 0.3],
                     level=level, params={"amplitud": [1.0, 1.5]})
    print(json.dumps([tab["X4"].tolist(), tab.done.tolist()]), flush=True)
"""


def test_a_design_table_with_times_just_below_and_at_a_switch_finishes(tmp_path):
    # the crank hands the slider over at t = 0.25; a table whose times hold 0.25 - 1e-12 and
    # 0.25 never returned at level acceleration (at velocity: unsolved from 0.25 on): the
    # step between them fails the branch tests whatever its size
    # (det Φ_q changes sign at the switch), and the continuation halved it below the time's
    # resolution (0.25 - 1e-12 + h == 0.25 - 1e-12) and tried again for ever
    import json
    import subprocess
    import sys
    from conftest import EXAMPLES
    script = tmp_path / "table.py"
    script.write_text(_TABLE_SCRIPT)
    env = dict(os.environ, MECHGEN_TIER="python", MECHGEN_CACHE=str(tmp_path / "cache"))
    try:
        out = subprocess.run([sys.executable, str(script),
                              os.path.join(EXAMPLES, "quick_return_crank_slider.py"),
                              str(tmp_path / "gen")], capture_output=True, text=True,
                             timeout=90, env=env)
    except subprocess.TimeoutExpired:
        pytest.fail("the design table across the switch did not return in 90 s")
    assert out.returncode == 0, out.stderr[-2000:]
    # at level velocity the old code gave up at 0.25 (done [3, 3]); at acceleration it hung
    lines = out.stdout.strip().splitlines()
    assert len(lines) == 2, out.stdout
    for x4, done in map(json.loads, lines):
        assert done == [5, 5]
        _check_handover(x4)


def _check_handover(x4):
    # crank stage: X4 of the closed form at θ = 2π t; slider stage: sqrt(24) + A sin(2π(t - 1/4))
    for row, amp in zip(x4, (1.0, 1.5)):
        assert row[:3] == pytest.approx([_x4(W * t) for t in (0.0, 0.1, 0.25 - 1e-12)],
                                        abs=1e-9)
        assert row[3:] == pytest.approx([math.sqrt(24) + amp * math.sin(W * (t - 0.25))
                                         for t in (0.25, 0.3)], abs=1e-9)


@pytest.mark.xfail(strict=True, reason="a design table's continuation does not know the stage "
                   "switches: the step across one fails its branch tests (the velocities "
                   "jump, det Phi_q changes sign), and every design is flagged JUMP, right "
                   "as its values are; mech.optimize then rejects every design")
def test_a_design_table_across_a_switch_flags_no_design(handover):
    from mechgen.protocol import OK
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tab = handover.sweep(0, 0.5, 11, params={"amplitud": [1.0, 1.5]})
    slider = tab.t >= 0.25
    for row, amp in zip(tab["X4"], (1.0, 1.5)):
        assert row[~slider] == pytest.approx([_x4(W * t) for t in tab.t[~slider]], abs=1e-9)
        assert row[slider] == pytest.approx(np.sqrt(24) + amp * np.sin(W * (tab.t[slider] - 0.25)),
                                            abs=1e-9)
    assert list(tab.status) == [OK, OK]          # was [5, 5]: JUMP


def test_a_turn_round_across_a_dwell_stage_is_an_extreme(tmp_path):
    # out (θ = w T) to t = 0.25, a dwell (θ = w/4) to 0.5, back (θ = w (3/4 - T)): the
    # largest angle, π/2, held through the dwell, was no extreme (the rate is 2π into the
    # first switch and 0 after it; 0 into the second and -2π after it): extrema('Th2') gave
    # only the ends (0 at t = 0, -π/2 at t = 1)
    from mechgen import Model, T, pi
    m = Model("audit_crank_dwell")
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
    mech = mechgen.compile(m, outdir=str(tmp_path), tier="python")
    for ends in ((0, 1), (1, 0)):
        sw = mech.sweep(*ends, 9, level="velocity")
        law = np.where(sw.stage == 0, W * sw.t, np.where(sw.stage == 1, W / 4,
                                                          W * (0.75 - sw.t)))
        np.testing.assert_allclose(sw["Th2"], law, atol=1e-12)
        ex = sw.extrema("Th2")
        assert [(e.kind, e.t) for e in ex] == [("min", 0.0), ("max", 0.25), ("min", 1.0)], ex
        assert ex[1].value == pytest.approx(math.pi / 2, abs=1e-12)
        assert [e.value for e in ex.maxima] == pytest.approx([math.pi / 2], abs=1e-12)
