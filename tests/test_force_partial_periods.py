"""A flywheel over less than a period says so, and an unknown integration method names the
choices (issue 43): the flywheel's ΔE is the fluctuation over one period of the cycle, a
turn of the crank."""
import math
import warnings

import pytest

import mechgen
from mechgen import Model, T


@pytest.fixture(scope="module")
def mech(tmp_path_factory):
    """A crank turning 5π rad/s (a period of 0.4) against a spring and a moment."""
    m = Model("partial_period")
    g = m.ground("g", points=[(0, 0), (0, 2)])
    crank = m.body("crank", points=[(0, 0), (1, 0)], guess=(0, 0, 0), mass=1.0,
                   inertia=0.1, centroid=(0.5, 0))
    m.revolute(g[1], crank[1])
    m.rotation_lock(crank, 5 * math.pi * T, name="drive")
    m.spring(crank[2], g[2], 100.0, 0.5, name="spr")
    return mechgen.compile(m, outdir=str(tmp_path_factory.mktemp("gen")), tier="python")


def test_a_flywheel_over_a_third_of_a_period_is_refused_naming_the_period(mech):
    sw = mech.sweep(0, 0.12, 31, level="dynamic")          # 0.3 of the period 0.4
    with pytest.raises(ValueError, match=r"0\.3 of a turn.*period.*0\.4"):
        sw.flywheel(0.05)


def test_a_flywheel_over_a_period_and_a_half_warns(mech):
    sw = mech.sweep(0, 0.6, 151, level="dynamic")
    with pytest.warns(UserWarning, match=r"1\.5 of a turn.*whole number of periods"):
        sw.flywheel(0.05)


def test_a_flywheel_over_one_period_is_quiet(mech):
    sw = mech.sweep(0, 0.4, 101, level="dynamic")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = sw.flywheel(0.05)
    assert out["energy"] > 0


def test_an_unknown_integration_method_names_the_choices(mech):
    """``--method nosuch`` printed scipy's dict of classes."""
    with pytest.raises(ValueError, match=r"no integration method 'nosuch'.*RK45.*LSODA") as e:
        mech.simulate(0.0, 0.2, 5, free=["drive"], method="nosuch")
    assert "<class" not in str(e.value)
