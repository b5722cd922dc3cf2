"""Audit of API.md section 4: a mode picked by mech.assemblies(t) and passed to a sweep
(``sweep(..., guess=mode)``, as Mechanism.assemblies says to follow one), a design table
or singularities starting at another time keeps that mode: a Solution is a configuration
at its own time (as set_guess takes it), carried to the sweep's first time along the
motion, not a Newton start at that time that falls into whichever mode is nearest.

Closed form for the quick-return of generated/quick_return.py (crank 3 about (0, 5), lever
about the origin through the crank pin, its tip 9 along it, a link of 5 to the slider on
y = 10): X4 = tip_x ± √(25 − (10 − tip_y)²); the two modes are the slider right (+) and
left (−) of the lever's tip.
"""
import math
import os
import warnings

import numpy as np
import pytest

import mechgen

GENERATED = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                         "generated")


def x4(t, sign):
    th = 2 * math.pi * t
    ax, ay = 3 * math.cos(th), 5 + 3 * math.sin(th)
    r = math.hypot(ax, ay)
    tx, ty = 9 * ax / r, 9 * ay / r
    return tx + sign * math.sqrt(25 - (10 - ty) ** 2)


def sign_of(value, t):
    return min((1, -1), key=lambda s: abs(value - x4(t, s)))


@pytest.fixture(scope="module")
def qr():
    return mechgen.load(os.path.join(GENERATED, "quick_return.py"), tier="python")


@pytest.mark.parametrize("ta", [0.35, 0.45, 0.55, 0.65])
def test_sweep_from_another_time_follows_the_mode_given(qr, ta):
    for mode in qr.assemblies(ta):
        sign = sign_of(mode["X4"], ta)
        assert mode["X4"] == pytest.approx(x4(ta, sign), abs=1e-9)
        sw = qr.sweep(0.0, 1.0, 21, guess=mode)
        assert np.allclose(sw["X4"], [x4(t, sign) for t in sw.t], atol=1e-9)


def test_design_table_from_another_time_follows_the_mode_given(qr):
    for mode in qr.assemblies(0.35):
        sign = sign_of(mode["X4"], 0.35)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            tab = qr.sweep(0.0, 1.0, 11, params={"longitud": [3.0]}, guess=mode)
        assert np.allclose(tab["X4"][0], [x4(t, sign) for t in tab.t], atol=1e-9)
        assert np.allclose(tab.sweep(0).mechanism.solve(0.35).q, mode.q, atol=1e-9)


def test_singularities_from_another_time_start_on_the_mode_given():
    """The slider-driven quick-return (generated/quick_return_slider.py) locks at the
    stroke's ends; singularities(guess=mode) from another time runs on that mode."""
    mech = mechgen.load(os.path.join(GENERATED, "quick_return_slider.py"), tier="python")
    for mode in mech.assemblies(0.1):
        from_mode = mech.singularities(0.1, 1.0, guess=mode)
        carried = mech.singularities(0.0, 1.0, guess=mode)
        assert [s.t for s in carried if s.t >= 0.1] == pytest.approx([s.t for s in from_mode],
                                                                      abs=1e-9)
