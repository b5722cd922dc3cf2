"""Audit 3, stages at the kinematic level: sweeps that end or start exactly at a switch,
times that hold a switch twice, design tables across a switch.

Reference: the seed's quick-return in closed form. Crank pin P = (L cos θ, 5 + L sin θ),
lever angle Th3 = atan2(-Px, Py), lever tip C = 9 (-sin Th3, cos Th3), slider
X4 = Cx + sqrt(25 - (10 - Cy)^2); the stage laws θ = w T (forward) and θ = w (1 - T)
(back), so that dX4/dT = ±w dX4/dθ (central differences in θ).
"""
from __future__ import annotations

import math
import os
import warnings

import numpy as np
import pytest

import mechgen
from conftest import GENERATED

W = 2 * math.pi


def _x4(theta, L=3.0):
    px, py = L * math.cos(theta), 5 + L * math.sin(theta)
    th3 = math.atan2(-px, py)
    cx, cy = -9 * math.sin(th3), 9 * math.cos(th3)
    return cx + math.sqrt(25 - (10 - cy) ** 2)


def _x4_theta(theta, h=1e-6):
    return (_x4(theta + h) - _x4(theta - h)) / (2 * h)


@pytest.fixture(scope="module")
def staged():
    return mechgen.load(os.path.join(GENERATED, "quick_return_stages.py"), tier="python")


@pytest.fixture(scope="module")
def handover():
    return mechgen.load(os.path.join(GENERATED, "quick_return_crank_slider.py"), tier="python")


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
