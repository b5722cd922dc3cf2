"""Extremes and roots at a sweep's ends, and on a sweep over exactly one period (a closed
cycle), against closed forms written here:

- the slider-crank of examples/fourbar_joints.py (``slider_crank_gen``: a = 1, b = 3,
  θ = 0.3 + 2πT): x(θ) = a cos θ + √(b² − a² sin² θ), maximum a + b at θ = 0, minimum
  b − a at θ = π, x'(θ) = −a sin θ (1 + a cos θ / √(b² − a² sin² θ));
- the cam of examples/cam_cycloidal.py: Y3 = d0 + s(2πT), s a rise over 120°, a dwell at
  h over [120°, 180°], a return over 120° and a dwell at 0 over [300°, 360°].
"""
import math
import os

import numpy as np
import pytest

import mechgen

GENERATED = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                         "generated")
A, B, PHASE, OMEGA = 1.0, 3.0, 0.3, 2 * math.pi
T_TOP = -PHASE / OMEGA                       # θ = 0: the slider's far dead centre
T_BOTTOM = (math.pi - PHASE) / OMEGA          # θ = π: its near dead centre


def x_of(theta):
    return A * math.cos(theta) + math.sqrt(B * B - (A * math.sin(theta)) ** 2)


def t_of(theta):
    return (theta - PHASE) / OMEGA


@pytest.fixture(scope="module")
def crank():
    return mechgen.load(os.path.join(GENERATED, "slider_crank_gen.py"))


@pytest.fixture(scope="module")
def cam():
    return mechgen.load(os.path.join(GENERATED, "cam_cycloidal.py"))


def kinds(ev):
    return [(e.kind, e.at) for e in ev]


@pytest.mark.parametrize("level", ["position", "velocity"])
def test_a_full_turn_from_the_dead_centre_is_one_cycle(crank, level):
    sw = crank.sweep(T_TOP, T_TOP + 1.0, 21, level=level)
    ev = sw.extrema("travel")
    assert ev.periodic
    # the maximum at θ = 0 is the sweep's first (and last) point: reported once, at t0
    assert kinds(ev) == [("max", "interior"), ("min", "interior")]
    assert ev[0].t == sw.t[0] and abs(ev[0].value - (A + B)) < 1e-12
    assert abs(ev[1].t - T_BOTTOM) < 1e-10 and abs(ev[1].value - (B - A)) < 1e-12
    assert not ev.ends
    if level == "velocity":
        r = sw.roots("traveld")               # x' = 0 at both dead centres, once each
        assert r.periodic and [e.kind for e in r] == ["falling", "rising"]
        assert r[0].t == sw.t[0] and abs(r[1].t - T_BOTTOM) < 1e-10


def test_a_cycle_that_starts_at_the_near_dead_centre(crank):
    sw = crank.sweep(T_BOTTOM, T_BOTTOM + 1.0, 16, level="velocity")
    ev = sw.extrema("travel")
    assert ev.periodic and kinds(ev) == [("min", "interior"), ("max", "interior")]
    assert ev[0].t == sw.t[0] and abs(ev[0].value - (B - A)) < 1e-12
    assert abs(ev[1].t - (T_TOP + 1.0)) < 1e-10 and abs(ev[1].value - (A + B)) < 1e-12


def test_a_part_of_a_turn_has_extremes_at_both_ends(crank):
    # θ from 0 to 3π/2: the maximum at the start (a dead centre), the minimum inside, and
    # at the end (θ = 3π/2, x' = a > 0) a maximum of the sweep that is not stationary
    t1 = t_of(1.5 * math.pi)
    sw = crank.sweep(T_TOP, t1, 19, level="velocity")
    ev = sw.extrema("travel")
    assert not ev.periodic
    assert kinds(ev) == [("max", "start"), ("min", "interior"), ("max", "end")]
    assert ev[0].t == sw.t[0] and abs(ev[0].value - (A + B)) < 1e-12
    assert abs(ev[1].t - T_BOTTOM) < 1e-10 and abs(ev[1].value - (B - A)) < 1e-12
    assert ev[2].t == sw.t[-1] and abs(ev[2].value - x_of(1.5 * math.pi)) < 1e-12
    assert [e.at_end for e in ev] == [True, False, True] and len(ev.ends) == 2
    assert "max (start)" in repr(ev) and "the sweep's end" in repr(ev[2])
    # the velocity is zero at the start: a root there, falling (x' < 0 for θ in (0, π))
    r = sw.roots("traveld")
    assert [(e.kind, e.at) for e in r] == [("falling", "start"), ("rising", "interior")]
    assert r[0].t == sw.t[0] and abs(r[1].t - T_BOTTOM) < 1e-10
    # backwards in time: the same extremes, the ends swapped
    back = crank.sweep(t1, T_TOP, 19, level="velocity").extrema("travel")
    assert kinds(back) == [("max", "end"), ("min", "interior"), ("max", "start")]
    assert abs(back[0].value - (A + B)) < 1e-12 and abs(back[2].value - x_of(1.5 * math.pi)) < 1e-12


def test_ends_of_a_monotonic_stretch(crank):
    # θ from π/4 to 3π/4: x falls all the way; the start is the maximum, the end the minimum
    sw = crank.sweep(t_of(math.pi / 4), t_of(0.75 * math.pi), 7)
    ev = sw.extrema("travel")
    assert kinds(ev) == [("max", "start"), ("min", "end")]
    assert abs(ev[0].value - x_of(math.pi / 4)) < 1e-12
    assert abs(ev[1].value - x_of(0.75 * math.pi)) < 1e-12
    assert len(sw.roots("travel")) == 0        # x > 0 throughout: no root, no end root


def test_two_turns_close_a_cycle_and_one_and_a_half_do_not(crank):
    sw = crank.sweep(T_TOP, T_TOP + 2.0, 41, level="velocity")
    ev = sw.extrema("travel")                 # two periods are a period: a closed cycle
    assert ev.periodic
    assert kinds(ev) == [("max", "interior"), ("min", "interior"), ("max", "interior"),
                         ("min", "interior")]
    assert np.allclose(ev.t, [T_TOP, T_BOTTOM, T_TOP + 1, T_BOTTOM + 1], atol=1e-10)
    sw = crank.sweep(T_TOP, T_TOP + 1.5, 31, level="velocity")
    ev = sw.extrema("travel")
    assert not ev.periodic
    assert kinds(ev) == [("max", "start"), ("min", "interior"), ("max", "interior"),
                         ("min", "end")]
    assert np.allclose(ev.t, [T_TOP, T_BOTTOM, T_TOP + 1, T_BOTTOM + 1], atol=1e-10)


# -- the cam: dwells through the wrap ------------------------------------------------------
H, E, RB = 2.0, 1.0, 5.0
D0 = math.sqrt(RB * RB - E * E)
HIGH = (1 / 3, 1 / 2)        # the dwell at the top, in fractions of a turn
LOW = (5 / 6, 1.0)           # the dwell at the bottom, ending at the wrap


def _in(t, window):
    f = t % 1.0
    return window[0] - 1e-12 <= f <= window[1] + 1e-12 or (window[1] == 1.0 and f < 1e-12)


@pytest.mark.parametrize("t0", [0.45, 0.9])
def test_a_cam_dwell_through_the_wrap_is_one_extreme(cam, t0):
    # a sweep over one turn that starts inside a dwell: the dwell wraps through the
    # sweep's ends and is one extreme of the cycle, reported once, inside the dwell
    start = cam.sweep(0.0, t0, 20)[-1].q      # the roller on the cam's near side
    sw = cam.sweep(t0, t0 + 1.0, 73, level="velocity", guess=start)
    ev = sw.extrema("Y3")
    assert ev.periodic and kinds(ev) in ([("max", "interior"), ("min", "interior")],
                                         [("min", "interior"), ("max", "interior")])
    top, bottom = ev.maxima[0], ev.minima[0]
    assert abs(top.value - (D0 + H)) < 1e-10 and _in(top.t, HIGH)
    assert abs(bottom.value - D0) < 1e-10 and _in(bottom.t, LOW)
    assert all(sw.t[0] <= e.t < sw.t[-1] for e in ev)


def test_a_cam_sweep_that_starts_and_ends_in_dwells(cam):
    # from inside the low dwell to the end of the high dwell: both ends are extremes
    sw = cam.sweep(0.9, 1.5, 37, level="velocity")
    ev = sw.extrema("Y3")
    assert not ev.periodic and kinds(ev) == [("min", "start"), ("max", "end")]
    assert abs(ev[0].value - D0) < 1e-10 and abs(ev[1].value - (D0 + H)) < 1e-10
