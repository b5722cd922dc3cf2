"""Audit 3 (assembly modes): mechgen never reports a configuration of the wrong assembly
mode, nor a mode twice, against closed forms written here.

Rack and pinion (examples/rack_pinion.py, Mech's RackAndPinion1): the pinion of radius r
turns at θ = ωT about (0, r); the rack slides on the x axis, its travel X = r θ. Its
rolling row reads the rack's rotation unwrapped, r (θ − Th_rack): a rack turned a whole
turn solves Φ with its travel one circumference 2πr further on, the same meshing teeth
further on, as mechgen.turns says of gears. At one time there are two poses: the rack as
built (Th = 0, X = r θ) and the rack turned half a turn on its guide (Th = π)."""
import math
import textwrap

import numpy as np
import pytest

import mechgen

RACK = '''
from mechgen import Model, T, pi
m = Model("rack_long")
r = m.param("r", 0.8)
omega = m.param("omega", pi)
base = m.ground("base", points=[(0, 0), (1, 0), (0, r)])
pinion = m.body("pinion", points=[(0, 0), (r, 0)], guess=(0, r, 0))
rack = m.body("rack", points=[(-12, 0), (12, 0)], guess=(0, 0, 0))
m.revolute(base[3], pinion[1], name="shaft")
m.translate(base.line(1, 2), rack.line(1, 2), name="guide")
m.rack_ratio(pinion[1], r, rack.line(1, 2), 12, name="mesh")
m.rotation_lock(pinion, omega * T, name="input")
'''


@pytest.fixture(scope="module")
def long_rack(tmp_path_factory):
    path = tmp_path_factory.mktemp("modes") / "rack_long.py"
    path.write_text(textwrap.dedent(RACK))
    return mechgen.compile(str(path), outdir=str(path.parent), tier="python")


@pytest.mark.parametrize("t", [0.0, 0.3])
def test_a_rack_has_two_poses_with_its_angle_in_range(long_rack, t):
    """A rack 24 long (the quasi-random starts reach ±12 along it) had 9 "assembly modes"
    at t = 0: the rack turned 2π k (Th = ±2π, ±3π, ±4π reported as such, outside
    (−π, π]) with X = r θ + 2π r k; now the two poses, their angles in (−π, π]."""
    r, theta = 0.8, math.pi * t
    modes = long_rack.assemblies(t)
    assert len(modes) == 2
    for s in modes:
        assert -math.pi < s["Th3"] <= math.pi
    assert modes[0]["Th3"] == pytest.approx(0.0, abs=1e-12)
    assert modes[0]["X3"] == pytest.approx(r * theta, abs=1e-9)     # the guess's mode first
    assert abs(modes[1]["Th3"]) == pytest.approx(math.pi, abs=1e-12)
    assert np.all(np.abs(long_rack.residual(modes[1].q, t)) < 1e-9)
