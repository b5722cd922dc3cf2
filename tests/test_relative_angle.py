"""relative_angle between axes that stretch (an axis joining points of two bodies) holds
the angle asked for, never that angle + π.

Its row was |u1||u2| sin(θ − angle), which also vanishes at θ = angle + π: from a guess
nearer that, solve() returned the opposite direction (Th2 = 3.4416 for 0.3) with no
error. The row is now θ − angle wrapped to (−π, π] (an atan2), whose one root is the
angle. Numbers against hand values: the angle itself, its derivatives (the driver's), and
the torque that holds a bar against gravity, m g (L/2) cos θ."""
import math

import numpy as np
import pytest

import mechgen
from mechgen import Line, Model, T, sin

MASS, G, L = 2.0, 9.81, 2.0


def _bar(th0):
    """A bar of length L pinned to the ground at its end; the angle from the ground's x
    axis to the line from the pin to the bar's tip (an axis on two bodies) is driven,
    0.3 + 0.5 sin T."""
    m = Model("angle_bar")
    g = m.ground("g", points=[(0, 0), (1, 0)])
    bar = m.body("bar", points=[(0, 0), (L, 0)], guess=(0, 0, th0), mass=MASS,
                 inertia=MASS * L ** 2 / 12, centroid=(L / 2, 0))
    m.revolute(g[1], bar[1], name="pin")
    m.relative_angle(g.line(1, 2), Line(g[1], bar[2]), 0.3 + 0.5 * sin(T), name="tilt")
    m.gravity(G)
    return m


@pytest.fixture(scope="module")
def driven():
    return mechgen.compile(_bar(0.3), tier="python")


@pytest.mark.parametrize("th0", [0.3, 0.3 + math.pi, 0.3 + 0.9 * math.pi,
                                 0.3 - 0.9 * math.pi, 0.3 + 3 * math.pi])
def test_the_angle_held_is_the_one_asked_for_whatever_the_guess(driven, th0):
    for t in (0.0, 0.7, 2.0):
        want = 0.3 + 0.5 * math.sin(t)
        s = driven.solve(t, guess={"Th2": th0 + 0.5 * math.sin(t)})
        turns = (s["Th2"] - want) / (2 * math.pi)
        assert abs(turns - round(turns)) < 1e-12, (th0, t, s["Th2"])


def test_the_angles_derivatives_are_the_drivers(driven):
    for t in (0.0, 0.4, 1.3):
        s = driven.solve(t, level="acceleration")
        assert s["Th2d"] == pytest.approx(0.5 * math.cos(t), abs=1e-12)
        assert s["Th2dd"] == pytest.approx(-0.5 * math.sin(t), abs=1e-12)


def test_the_driver_holds_the_bar_against_gravity(driven):
    for t in (0.0, 0.4, 1.3):
        th = 0.3 + 0.5 * math.sin(t)
        s = driven.solve(t, level="static")
        assert s.driver("tilt") == pytest.approx(MASS * G * (L / 2) * math.cos(th), rel=1e-12)
        # the dynamic effort adds I_pin θ̈, I_pin = m L² / 3
        d = driven.solve(t, level="dynamic")
        want = MASS * G * (L / 2) * math.cos(th) + MASS * L ** 2 / 3 * (-0.5 * math.sin(t))
        assert d.driver("tilt") == pytest.approx(want, rel=1e-12, abs=1e-12)


def test_a_sweep_keeps_the_angle_from_a_guess_opposite_it(driven):
    driven.set_guess({"Th2": 0.3 + math.pi})
    try:
        sw = driven.sweep(0.0, 6.0, 61)
    finally:
        driven.set_guess()
    want = 0.3 + 0.5 * np.sin(sw.t)
    turns = (sw["Th2"] - want) / (2 * np.pi)
    assert np.abs(turns - np.round(turns)).max() < 1e-12
