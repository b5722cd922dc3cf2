"""simulate integrates forward in time (issue 43): t1 before t0 is a ValueError that says
so, at the public call, where it integrated backwards without a word; the refinement of a
simulated sweep's extremes, which integrates back from an output on purpose, still does."""
import math

import pytest

import mechgen
from mechgen import Model, T

G, L1, MB, JB = 9.81, 1.2, 2.0, 0.15


def pendulum():
    m = Model("sim_direction_pendulum")
    base = m.ground("base", points=[(0, 0)])
    bar = m.body("bar", points=[(0, 0), (L1, 0)], guess=(0, 0, -0.3), mass=MB, inertia=JB,
                 centroid=(L1 / 2, 0))
    m.revolute(base[1], bar[1])
    w = m.param("w", 0.0)
    m.rotation_lock(bar, -0.3 + w * T, name="hold")
    m.gravity(G)
    return m


@pytest.fixture(scope="module")
def mech(tmp_path_factory):
    return mechgen.compile(pendulum(), outdir=str(tmp_path_factory.mktemp("gen")),
                           tier="python")


def test_t1_before_t0_is_refused(mech):
    with pytest.raises(ValueError, match=r"simulate: t1 = 0.5 is before t0 = 1.*forward"):
        mech.simulate(1.0, 0.5, 11, free=["hold"])


def test_forward_still_runs(mech):
    sw = mech.simulate(0.0, 0.5, 6, free=["hold"])
    assert sw.t[0] == 0.0 and sw.t[-1] == 0.5
    assert sw["Th2d"][-1] < 0.0                     # it falls


def test_the_refinement_still_integrates_back_from_an_output(mech):
    """Extremes refined between the outputs, from the output nearest (before or after)."""
    sw = mech.simulate(0.0, 3.0, 31, free=["hold"], rtol=1e-10, atol=1e-12)
    low = sw.extrema("Th2").minima
    assert len(low) == 2
    for e in low:
        assert abs(e.value - (-math.pi + 0.3)) < 5e-8
