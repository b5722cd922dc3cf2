"""No silent numbers at the force levels (issue 43): a spring whose two ends meet within
round-off has no direction, and every path says so as the single solve does (a
SingularError, or NaN and ``force_singular``), never a finite effort that depends on the
sweep's step."""
import math
import warnings

import numpy as np
import pytest

import mechgen
from mechgen import Model, T


def spring_meets(name="spring_meets_roundoff"):
    """A crank of length 1 turning 5π rad/s from the x axis, a spring from its tip to the
    ground point (0, 1): at t = 0.1 the tip is at (cos(π/2), 1) = (6e-17, 1), the ends a
    round-off apart."""
    m = Model(name)
    g = m.ground("g", points=[(0, 0), (0, 1)])
    crank = m.body("crank", points=[(0, 0), (1, 0)], guess=(0, 0, 0), mass=1.0,
                   inertia=0.1, centroid=(0.5, 0))
    m.revolute(g[1], crank[1])
    m.rotation_lock(crank, 5 * math.pi * T, name="drive")
    kk = m.param("kk", 100.0)
    m.spring(crank[2], g[2], kk, 0.5, name="spr")
    return m


@pytest.fixture(scope="module")
def mech(tmp_path_factory):
    return mechgen.compile(spring_meets(), outdir=str(tmp_path_factory.mktemp("gen")),
                           tier="python")


def _flagged_or_raised(call, t=0.1):
    """The effort at t from ``call`` (a sweep's driver array and times): NaN where it
    returns one; True where it raised a SingularError naming the spring."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ts, effort, singular = call()
    except mechgen.SingularError as e:
        assert "spr" in str(e)
        return True
    k = int(np.argmin(np.abs(ts - t)))
    assert abs(ts[k] - t) < 1e-12
    return bool(np.isnan(effort[k]) and singular[k])


def test_the_single_solve_raises_naming_the_spring(mech):
    with pytest.raises(mechgen.SingularError, match=r"divide by zero.*spr.*no direction"):
        mech.solve(0.1, level="dynamic")
    with pytest.raises(mechgen.SingularError, match=r"spr"):
        mech.solve(0.1, level="static")
    assert np.isfinite(mech.solve(0.05, level="dynamic").driver("drive"))


@pytest.mark.parametrize("n", [3, 5, 11, 21])
@pytest.mark.parametrize("method", [None, "full"])       # the quick path, the careful one
@pytest.mark.parametrize("level", ["dynamic", "static"])
def test_a_sweep_point_without_direction_is_flagged_at_every_n(mech, n, method, level):
    def call():
        sw = mech.sweep(0, 0.2, n, level=level, method=method)
        return sw.t, sw.driver("drive"), sw.force_singular
    assert _flagged_or_raised(call)
    if n == 3:                  # the other points keep their numbers
        with pytest.warns(UserWarning, match="no force balance"):
            sw = mech.sweep(0, 0.2, n, level=level, method=method)
        assert np.all(np.isfinite(sw.driver("drive")[[0, -1]]))


def test_the_sweep_warns_naming_springs(mech):
    with pytest.warns(UserWarning, match=r"spring or damper whose two ends meet.*spr"):
        mech.sweep(0, 0.2, 5, level="dynamic")


@pytest.mark.parametrize("level", ["dynamic", "static"])
def test_a_design_table_flags_it_on_every_path(mech, level):
    kks = {"kk": np.array([50.0, 100.0, 150.0])}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tab = mech.sweep(0, 0.2, 5, params=kks, level=level)
        red = mech.sweep(0, 0.2, 5, params=kks, level=level, reduce=["drive"])
    efforts = tab.driver("drive")
    assert np.all(np.isnan(efforts[:, 2]))
    assert np.all(np.isfinite(efforts[:, [0, 1, 3, 4]]))
    with pytest.warns(UserWarning, match="no force balance"):
        one = tab.sweep(1)
    assert np.isnan(one.driver("drive")[2]) and one.force_singular[2]
    # reduce= on the driver: its extremes from the points that have a direction only
    peak = red.reduced("drive")
    np.testing.assert_allclose(peak.max, np.nanmax(efforts, axis=1), rtol=1e-12)
    np.testing.assert_allclose(peak.min, np.nanmin(efforts, axis=1), rtol=1e-12)
