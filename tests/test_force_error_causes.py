"""Force errors name their real cause (issue 43): gravity whose direction has zero length
(its direction given by parameters) is said to be that, not "a spring or damper whose
ends meet"; with_params refuses it."""
import math

import pytest

import mechgen
from mechgen import Model, T


def weighed(name, gx, gy):
    """A crank turning 2π rad/s under gravity along (gx, gy) (parameters), with a spring
    ``spr`` from its tip to the ground point (0, 3) whose ends never meet."""
    m = Model(name)
    g = m.ground("g", points=[(0, 0), (0, 3)])
    crank = m.body("crank", points=[(0, 0), (1, 0)], guess=(0, 0, 0), mass=1.0,
                   inertia=0.1, centroid=(0.5, 0))
    m.revolute(g[1], crank[1])
    m.rotation_lock(crank, 2 * math.pi * T, name="drive")
    m.gravity(9.81, direction=(m.param("gx", gx), m.param("gy", gy)))
    m.spring(crank[2], g[2], 100.0, 0.5, name="spr")
    return m


@pytest.fixture(scope="module")
def outdir(tmp_path_factory):
    return str(tmp_path_factory.mktemp("gen"))


def test_with_params_refuses_a_gravity_direction_of_zero_length(outdir):
    mech = mechgen.compile(weighed("gravity_down", 0.0, -1.0), outdir=outdir, tier="python")
    assert math.isfinite(mech.solve(0.1, level="dynamic").driver("drive"))
    with pytest.raises(ValueError, match=r"gravity: the length of its direction.*is zero"):
        mech.with_params(gx=0.0, gy=0.0)
    assert mech.with_params(gx=1.0, gy=0.0).parameters["gx"] == 1.0


def test_a_zero_direction_at_the_defaults_is_named_not_the_springs(outdir):
    mech = mechgen.compile(weighed("gravity_nowhere", 0.0, 0.0), outdir=outdir,
                           tier="python")
    for call in (lambda: mech.solve(0.1, level="dynamic"),
                 lambda: mech.sweep(0, 1, 11, level="dynamic"),
                 lambda: mech.solve(0.1, level="static")):
        with pytest.raises(mechgen.SingularError) as info:
            call()
        said = str(info.value)
        assert "gravity: the length of its direction" in said and "is zero" in said
        assert "ends meet" not in said and "'spr'" not in said


# -- a runaway motor -------------------------------------------------------------------------
def test_a_runaway_motor_is_said_to_run_away_not_to_chatter():
    """The press of examples/press_motor.py with its motor's sign turned (−T0 (1 + ω/ω0)
    with T0 < 0: a torque that grows with the speed) speeds up without bound: the error
    says so, with the time, the body and its speed, not "a load that switches on and
    off"."""
    from conftest import GENERATED
    mech = mechgen.load(f"{GENERATED}/press_motor.py").with_params(T0=-400.0)
    with pytest.raises(mechgen.ConvergenceError) as info:
        mech.simulate(0.0, 1.0, 11, free=["crank driver"])
    said = str(info.value)
    assert "runs away" in said and "without bound" in said and "switches" not in said
    assert "body 'crank'" in said and "rad/s" in said and "near t=0.5" in said
    assert info.value.t is not None and 0.5 < info.value.t < 0.6


def test_a_load_that_chatters_is_still_said_to_chatter():
    """A press whose work (300 kN) stops the motor at once: the work switches on and off."""
    from conftest import GENERATED
    mech = mechgen.load(f"{GENERATED}/press_motor.py").with_params(press=300000.0)
    with pytest.raises(mechgen.ConvergenceError, match="switches on and off") as info:
        mech.simulate(0.0, 0.1, 2, free=["crank driver"])
    assert "runs away" not in str(info.value)
