"""A Mechanism's state (mechgen.runtime.state.RuntimeState): one object holds the module,
parameters, guess, tolerances, path, last solution and scratch; the Mechanism's attributes
read through to it, a copy (with_params) has its own, and a way followed from a Solution
at another time runs on a copy of the state, leaving the mechanism's guess and path as they
were. Positions are checked against the four-bar's closed form (models.four_bar_q)."""
import math

import numpy as np
import pytest

import mechgen
from conftest import GENERATED
from models import four_bar_q
from mechgen.runtime.state import RuntimeState


@pytest.fixture
def mech():
    return mechgen.load(f"{GENERATED}/fourbar.py", tier="python")


def test_the_attributes_are_the_states(mech):
    state = mech.state
    assert isinstance(state, RuntimeState) and state.owner is mech
    assert mech.p is state.p and mech.guess is state.guess and mech.module is state.module
    mech.tol = 1e-9
    assert state.tol == 1e-9
    mech.set_guess(mech.guess + 0.01, t=0.2)
    assert mech.state.guess_t == 0.2 and state.path is None
    assert not any(hasattr(mech, name) for name in ("_tiers", "_path", "_lock", "_last"))


def test_a_copy_has_its_own_state(mech):
    mech.solve(0.4)
    other = mech.with_params()
    assert other.state is not mech.state and other.state.owner is other
    assert other.state.lock is not mech.state.lock and other.state.path is None
    assert other.state.tiers is mech.state.tiers         # the module is shared


def test_a_solution_at_another_time_is_followed_on_a_copy(mech):
    """A sweep from a Solution at another time follows its mode from the Solution's time
    (RuntimeState.with_guess): the mechanism's own guess and path stay as they were, and
    the sweep's positions are the closed form's on that mode."""
    far = mech.solve(0.35)
    path, guess, t0 = mech.state.path, mech.guess.copy(), mech.guess_t
    assert path is not None
    sw = mech.sweep(0.6, 0.9, 4, guess=far)
    assert mech.state.path is path and mech.guess_t == t0
    np.testing.assert_array_equal(mech.guess, guess)
    p = mech.parameters
    args = (p["a"], p["b"], p["c"], p["d"], p["theta2"], p["omega"])

    def off(q, t, mode):
        want = four_bar_q(float(t), *args, mode=mode)
        return max(abs(math.remainder(q[k] - want[k], 2 * math.pi)) if k % 3 == 2 else
                   abs(q[k] - want[k]) for k in range(9))
    mode = min((1, -1), key=lambda m: off(far.q, far.t, m))     # the Solution's mode
    assert off(far.q, far.t, mode) < 1e-8
    for t, q in zip(sw.t, sw.Q):
        assert off(q, t, mode) < 1e-8, (t, q)


def test_the_last_point_of_a_sweep_is_the_states_last(mech):
    sw = mech.sweep(0.0, 0.5, 6, level="velocity")
    last = mech.last
    assert last.t == sw.t[-1]
    np.testing.assert_array_equal(last.q, sw.Q[-1])
    np.testing.assert_array_equal(last.qd, sw.QD[-1])
    assert mech.state.last is last
