"""A position sweep's quick path (issue 12): sweep_fast() with no velocity or acceleration
rows takes derivatives at its first two points only, predicts by the quadratic through its
last three points and evaluates det Φ_q only where its sign could have changed; a sign
change sends it back to the point it evaluated last. Checked against the full sweep's
positions and statuses, and against det Φ_q at every point it vouches for."""
import math

import numpy as np
import pytest

from mechgen.protocol import OK
from mechgen.runtime.kinematics.guesses import start_vector


def _fast(mech, ts, level, guess=None):
    mod, n, N = mech.module, mech.n, len(ts)
    Q, S = np.zeros((N, n)), np.zeros((N, 2), dtype=np.int16)
    QD = np.zeros((N, n) if level else (0, n))
    QDD = np.zeros((N, n) if level else (0, n))
    done = mod.sweep_fast(np.asarray(ts, dtype=float), start_vector(mech, guess), mech.p, 1e-10,
                          1e-10, 50, Q, QD, QDD, S)
    return done, Q, S


@pytest.mark.parametrize("name, t1", [("qr", 1.0), ("qr_slider", 0.2), ("fourbar", 1.0),
                                       ("fourbar_loop", 1.0)])
def test_position_sweep_agrees_with_the_full_sweep(request, name, t1):
    mech = request.getfixturevalue(name)
    for N in (7, 400, 5000):
        ts = np.linspace(0.0, t1, N)
        (done, Q, S), (done_full, Qf, _) = _fast(mech, ts, 0), _fast(mech, ts, 2)
        if N >= 400:        # (in 7 points the quadratic predicts too coarsely: sweep()
            assert done == done_full == N       # takes over, as the test below sees)
        both = min(done, done_full)     # (a position sweep's closed forms read no guess)
        assert np.abs(Q[:both] - Qf[:both]).max() < 1e-11 * (1.0 + np.abs(Qf).max())
        assert np.all(S[:done, 0] == OK)
        # and through mech.sweep: the same numbers, the same statuses
        pos, full = mech.sweep(0.0, t1, N), mech.sweep(0.0, t1, N, level="acceleration")
        assert np.abs(pos.Q - full.Q).max() < 1e-11 * (1.0 + np.abs(full.Q).max())
        assert np.array_equal(pos.status, full.status)


def test_uneven_and_repeated_times(qr):
    ts = np.r_[0.0, 0.001, 0.003, 0.01, np.cumsum(np.linspace(0.001, 0.02, 60)) + 0.01]
    done, Q, _ = _fast(qr, ts, 0)
    # the closed forms read no guess: the quick path evaluates det Φ_q every
    # BRANCH_DET_EVERY points only, and where the steps grow to 0.02 det Φ_q changes by
    # more than half between two evaluations near its zero: it goes back to the last one
    # evaluated and sweep() takes the rest over
    assert done >= 3 * len(ts) // 4
    from closed_forms import quick_return                   # the reference, written apart
    exact = np.array([[float(x) for x in quick_return(t)] for t in ts])
    assert np.abs(Q[:done] - exact[:done]).max() < 1e-11
    sw = qr.sweep(None, None, None, times=ts)
    assert len(sw) == len(ts) and np.abs(sw.Q - exact).max() < 1e-11
    # a repeated time predicts no motion from it: sweep() takes over, the numbers hold
    ts = np.r_[ts[:3], ts[2:]]
    sw = qr.sweep(None, None, None, times=ts)
    assert len(sw) == len(ts) and np.abs(sw.Q[2] - sw.Q[3]).max() < 1e-12
    exact = np.array([[float(x) for x in quick_return(t)] for t in ts])
    assert np.abs(sw.Q - exact).max() < 1e-11


PARALLELOGRAM = dict(a=1.0, b=3.0, c=1.0, d=3.0, theta2=0.5, omega=2 * math.pi)
GUESS = {"Th2": 0.5, "X3": math.cos(0.5), "Y3": math.sin(0.5), "Th3": 0.05, "X4": 3.0,
         "Y4": 0.0, "Th4": 0.55}
CROSS = (math.pi - 0.5) / (2 * math.pi)         # θ2 = π: the first change point


@pytest.mark.parametrize("N", [1001, 3000])
def test_a_sign_change_goes_back_to_the_last_evaluated_point(fourbar, N):
    """The parallelogram four-bar passes a change point at θ2 = π: the quick path vouches
    only for points before it, each with det Φ_q of the first point's sign."""
    mech = fourbar.with_params(**PARALLELOGRAM)
    ts = np.linspace(0.0, 1.0, N)
    done, Q, _ = _fast(mech, ts, 0, GUESS)
    assert 0.8 * CROSS < ts[done - 1] < CROSS
    det = [mech.module.jacobian_det(Q[k], ts[k], mech.p, np.zeros(2)) for k in range(done)]
    assert np.all(np.sign(det) == np.sign(det[0]))


def test_a_crossing_at_the_last_point_is_seen(fourbar):
    mech = fourbar.with_params(**PARALLELOGRAM)
    ts = np.linspace(0.0, CROSS + 0.004, 300)     # crossed within the last step
    done, _, _ = _fast(mech, ts, 0, GUESS)
    assert done < len(ts)


def test_position_sweep_through_a_change_point_is_flagged(fourbar):
    mech = fourbar.with_params(**PARALLELOGRAM)
    with pytest.warns(Warning, match="singular configuration"):
        sw = mech.sweep(0.0, 0.6, 61, guess=GUESS)
    assert len(sw) == 61 and np.allclose(sw.crossings, [0.43])
