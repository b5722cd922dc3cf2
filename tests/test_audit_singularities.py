"""Audit of mech.singularities (API.md section 4) against closed forms written here.

A change-point four-bar (a + b = c + d: crank a = 1, coupler b = 3, rocker c = 2, ground
d = 2), crank driven by θ = π/3 + 2πT, is singular at exactly one configuration per turn:
crank along the ground towards the rocker's pivot (θ = 2π), all four links on one line,
at T = 5/6. The lock positions of an offset slider-crank driven at the slider
(x = x0 + A T; crank r, rod l, offset e) are the dead centres x = √((l ± r)² − e²).
"""
import math
import os
import warnings

import pytest

import mechgen

GENERATED = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                         "generated")


@pytest.fixture(scope="module")
def change_point():
    mech = mechgen.load(os.path.join(GENERATED, "fourbar.py"), tier="python")
    return mech.with_params(a=1.0, b=3.0, c=2.0, d=2.0)


@pytest.mark.parametrize("t0, t1, n", [(0.0, 1.0, 201), (0.5, 0.9, 201), (0.0, 1.0, 11),
                                       (0.0, 1.0, 50), (0.9, 0.5, 201)])
def test_one_singular_configuration_is_reported_once(change_point, t0, t1, n):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        found = change_point.singularities(t0, t1, n=n)
    assert [s.t for s in found] == pytest.approx([5 / 6], abs=1e-8)


def test_crank_rocker_driven_by_its_crank_never_loses_rank():
    mech = mechgen.load(os.path.join(GENERATED, "fourbar.py"), tier="python")
    assert mech.singularities(0.0, 1.0) == []
    assert mech.singularities(0.0, 3.0) == []
