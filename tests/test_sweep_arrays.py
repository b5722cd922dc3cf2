"""mech.sweep stores only what its level needs (issue 12): a position sweep has no velocity
or acceleration arrays, each point has a small int16 status row, ``out=`` writes into the
caller's arrays (checked), and failures, flags, extrema, roots and interpolation work as
before. The numbers are checked against separate solves (mech.solve)."""
import math

import numpy as np
import pytest

import mechgen
from mechgen.protocol import JUMP, OK, STATUS_COLUMNS, THROUGH_SINGULAR
from mechgen.runtime.kinematics.sweeping import linspace

from test_robustness import T1


def test_a_position_sweep_has_no_velocity_arrays(qr):
    sw = qr.sweep(0.0, 1.0, 201)
    assert sw.level == "position" and sw.QD is None and sw.QDD is None
    assert sw.Q.shape == (201, qr.n) and sw.Q.dtype == np.float64
    with pytest.raises(KeyError, match=r"'X4d' needs a sweep at level velocity \(this sweep "
                                       r"is at level position\)"):
        sw["X4d"]
    with pytest.raises(KeyError, match="'X4dd' needs a sweep at level acceleration"):
        sw["X4dd"]
    with pytest.raises(KeyError, match="needs a sweep at level velocity"):
        sw["stroke_xd"]
    assert sw[5].qd is None and sw.columns()[-1] == "stroke_x"
    # a compact status row a point: the status code and the Newton iterations (none:
    # the quick-return's blocks are all explicit or closed forms)
    assert sw.status.dtype == np.int16 and sw.status.shape == (201,)
    assert np.all(sw.status == OK)
    assert np.all((0 <= sw.iterations) & (sw.iterations <= qr.maxit))
    # the wide rows of earlier versions, as a view built on demand
    info = sw.info
    assert info.shape == (201, 7) and np.all(info[:, 4] == OK)
    assert np.array_equal(info[:, 0], sw.iterations)
    assert np.all(sw.substeps >= 0) and np.array_equal(info[:, 5], sw.substeps)
    vel = qr.sweep(0.0, 1.0, 201, level="velocity")
    assert vel.QD.shape == (201, qr.n) and vel.QDD is None
    with pytest.raises(KeyError, match="'X4dd' needs a sweep at level acceleration"):
        vel["X4dd"]


def test_each_level_gives_the_separate_solves(qr):
    """Positions the same at every level, and all of them the solver's at each time."""
    ts = np.linspace(0.0, 1.0, 101)
    sws = {lev: qr.sweep(0.0, 1.0, 101, level=lev)
           for lev in ("position", "velocity", "acceleration")}
    for k in (0, 17, 50, 83, 100):
        s = qr.solve(ts[k], guess=sws["position"].Q[k], level="acceleration")
        for lev, sw in sws.items():
            assert sw.t[k] == ts[k]
            assert np.abs(sw.Q[k] - s.q).max() <= 1e-12
        assert np.abs(sws["velocity"].QD[k] - s.qd).max() <= 1e-10
        assert np.abs(sws["acceleration"].QDD[k] - s.qdd).max() <= 1e-8 * (1 + np.abs(s.qdd).max())
    assert np.abs(sws["position"].Q - sws["acceleration"].Q).max() <= 1e-12
    sw = qr.sweep(0.0, 0.5, 11, level="acceleration")       # mech.last: its last point
    assert qr.last.t == 0.5 and np.array_equal(qr.last.q, sw.Q[-1])
    assert np.array_equal(qr.last.qdd, sw.QDD[-1]) and qr.last is qr.last


def test_out_reuses_the_callers_arrays_with_the_same_numbers(qr):
    N, n = 301, qr.n
    fresh = qr.sweep(0.0, 1.0, N, level="acceleration")
    Q, QD, QDD = np.full((N, n), np.nan), np.full((N, n), np.nan), np.full((N, n), np.nan)
    S = np.full((N, STATUS_COLUMNS), -1, dtype=np.int16)
    sw = qr.sweep(0.0, 1.0, N, level="acceleration", out={"q": Q, "qd": QD, "qdd": QDD,
                                                           "status": S})
    assert sw.Q is Q and sw.QD is QD and sw.QDD is QDD
    for a, b in ((Q, fresh.Q), (QD, fresh.QD), (QDD, fresh.QDD), (sw.status, fresh.status),
                 (sw.iterations, fresh.iterations)):
        assert np.array_equal(a, b)
    # a tuple, or an earlier Sweep (its numbers are overwritten)
    Q2 = np.empty((N, n))
    pos = qr.sweep(0.0, 1.0, N, out=(Q2,))
    # (a position sweep predicts from its last points, not from derivatives: the same
    # positions to rounding, tests/test_position_sweep.py)
    assert pos.Q is Q2 and pos.QD is None and np.abs(Q2 - fresh.Q).max() < 1e-12
    again = qr.sweep(0.0, 0.5, N, level="acceleration", out=sw)
    assert again.Q is Q and np.shares_memory(again.status, S)
    half = qr.sweep(0.0, 0.5, N, level="acceleration")
    assert np.array_equal(again.Q, half.Q) and np.array_equal(again.QDD, half.QDD)
    # a position sweep into a full sweep's arrays leaves its velocities alone
    QD_before = QD.copy()
    qr.sweep(0.0, 1.0, N, out=again)
    assert np.array_equal(QD, QD_before) and np.abs(Q - fresh.Q).max() < 1e-12
    # analysis on a sweep written into given arrays
    sw = qr.sweep(0.0, 1.0, N, level="acceleration", out=sw)
    ext = sw.extrema("X4")
    assert len(ext) == 2
    x4 = sw.interpolate("X4")
    s = qr.solve(0.123, guess=sw[37].q)
    assert abs(x4(0.123) - s["X4"]) < 1e-9


@pytest.mark.parametrize("out, message", [
    ({"q": np.empty((10, 9))}, r"q must have shape \(11, 9\) for a sweep of 11 points, "
                               r"got \(10, 9\)"),
    ({"q": np.empty((11, 9), dtype=np.float32)}, "q must have dtype float64, got float32"),
    ({"qd": np.empty((11, 9), order="F")}, "qd must be C-contiguous"),
    ({"qdd": np.empty((11, 18))[:, ::2]}, "qdd must be C-contiguous"),
    ({"q": [[0.0] * 9] * 11}, "q must be a numpy array, got list"),
    ({"status": np.empty((11, 2))}, "status must have dtype int16, got float64"),
    ({"status": np.empty((11, 4), dtype=np.int16)}, r"status must have shape \(11, 3\)"),
    ({"Q": np.empty((11, 9))}, r"unknown key\(s\) 'Q'"),
    (np.empty((11, 9)), "out must be a dict"),
])
def test_out_is_checked(qr, out, message):
    with pytest.raises(ValueError, match="out: " + message if not message.startswith("out")
                       else message):
        qr.sweep(0.0, 1.0, 11, level="acceleration", out=out)


def test_out_refuses_read_only_arrays_and_smaller_sweeps(qr):
    Q = np.empty((11, 9))
    Q.flags.writeable = False
    with pytest.raises(ValueError, match="out: q is read-only"):
        qr.sweep(0.0, 1.0, 11, out=(Q,))
    pos = qr.sweep(0.0, 1.0, 11)
    with pytest.raises(ValueError, match="must have 11 points and level velocity or above "
                                         r"\(it has 11 points, level position\)"):
        qr.sweep(0.0, 1.0, 11, level="velocity", out=pos)
    with pytest.raises(ValueError, match="must have 12 points"):
        qr.sweep(0.0, 1.0, 12, out=pos)
    # a one-column status array: the codes only
    S1 = np.empty((11, 1), dtype=np.int16)
    sw = qr.sweep(0.0, 1.0, 11, out={"status": S1})
    assert sw.iterations is None and sw.substeps is None and np.all(sw.status == OK)


def test_a_failed_sweep_carries_what_it_solved(qr_slider):
    """The sweep stops at the lock: the error names it, and its .sweep holds the points
    before it (only the arrays of the level asked for)."""
    for level in ("position", "acceleration"):
        with pytest.raises(mechgen.ConvergenceError, match="reached t=0.24648") as info:
            qr_slider.sweep(0.0, 1.0, 101, level=level)
        part = info.value.sweep
        assert len(part) == 25 and part.level == level and np.all(part.status == OK)
        assert (part.QD is None) == (level == "position")
        assert abs(info.value.locks[0] - T1) < 1e-8
        assert info.value.iterations >= 1 and info.value.residual > 1e-10


def test_crossings_are_flagged_in_the_status(qr_slider):
    with pytest.warns(mechgen.BranchJumpWarning, match="singular configuration"):
        sw = qr_slider.sweep(0.0, T1, 11, guess=None)
    assert list(sw.crossings) == [T1]
    assert sw.status[-1] == THROUGH_SINGULAR and np.all(sw.status[:-1] == OK)
    assert sw.info[-1, 4] == THROUGH_SINGULAR and not np.any(sw.status == JUMP)
    with pytest.raises(mechgen.SingularError) as info:
        qr_slider.sweep(0.0, T1, 11, level="velocity")
    assert len(info.value.sweep) == 10 and info.value.sweep.QDD is None


def test_roots_and_interpolation_of_a_position_sweep(qr):
    sw = qr.sweep(0.0, 1.0, 81)
    roots = sw.roots("Th3")
    assert len(roots) == 2
    for r in roots:
        assert abs(r.value) < 1e-10
    # the lever is upright where the crank pin is above its pivot: cos 2πT = 0
    assert np.allclose([r.t for r in roots], [0.25, 0.75], rtol=0, atol=1e-10)
    with pytest.raises(ValueError):
        sw.interpolate("X4", method="hermite")


def test_the_times_are_numpys_linspace():
    for t0, t1, n in ((0.0, 1.0, 101), (0.3, -2.7, 7), (1.5, 1.5, 4), (2.0, 3.0, 1),
                      (-1e-3, 1e9, 1000), (0.1, 0.7, 2)):
        assert np.array_equal(linspace(t0, t1, n), np.linspace(t0, t1, n)), (t0, t1, n)
        assert linspace(t0, t1, n).dtype == np.float64


def test_sweep_arguments_are_still_checked(qr):
    with pytest.raises(ValueError, match="n must be a positive integer"):
        qr.sweep(0.0, 1.0, 0)
    with pytest.raises(ValueError, match="t1 must be finite"):
        qr.sweep(0.0, math.inf, 5)
    with pytest.raises(ValueError, match="level must be one of"):
        qr.sweep(0.0, 1.0, 5, level="jerk")
    sw = qr.sweep(np.float64(0.0), 1, 5.0)             # numbers of other types
    assert np.array_equal(sw.t, np.linspace(0.0, 1.0, 5))


def test_a_sweep_from_the_wide_rows_of_earlier_versions(qr):
    """Sweep(mech, t, Q, QD, QDD, info) with the 7-column float rows still reads them."""
    from mechgen.runtime.results import Sweep
    sw = qr.sweep(0.0, 1.0, 11)
    old = Sweep(qr, sw.t, sw.Q, None, None, sw.info)
    assert np.array_equal(old.status, sw.status)
    assert np.array_equal(old.iterations, sw.iterations)


def test_design_tables_keep_their_statuses(qr_slider):
    """A design table shares the compiled sweep: failed designs say where and why."""
    with pytest.warns(RuntimeWarning, match="1 of 2 designs"):
        tab = qr_slider.sweep(0.0, 0.2, 11, params={"centro": [4.13931, 9.0]},
                              level="acceleration")
    assert tab.ok.tolist() == [True, False]
    (values, t, status), = tab.failures
    assert values == {"centro": 9.0} and status != OK and 0.0 < t <= 0.2
    bad = tab.sweep(1)
    assert bad.t[-1] < t and np.all(bad.status == OK) and np.isnan(tab["X4"][1, -1])
    two = qr_slider.with_params(centro=9.0)
    assert all(two.residual(q, tt) <= 1e-10 for q, tt in zip(bad.Q, bad.t))
    one = tab.sweep(0)
    assert np.all(one.status == OK) and one.QDD.shape == (11, qr_slider.n)


def test_a_sweep_held_is_never_written_by_the_next(qr, monkeypatch):
    """Fresh arrays are views of one block; a Mechanism hands a large block out again only
    once no view of it is alive (here every block counts as large)."""
    from mechgen.runtime.kinematics import sweeping
    monkeypatch.setattr(sweeping, "_SPARE_MIN", 64)
    a = qr.sweep(0.0, 1.0, 501, level="acceleration")
    A, AD = a.Q.copy(), a.QD.copy()
    b = qr.sweep(0.0, 0.5, 501, level="acceleration")
    assert not np.shares_memory(a.Q, b.Q) and np.array_equal(a.Q, A)
    B, tb = b.Q.copy(), b.t.copy()
    del a
    c = qr.sweep(0.0, 1.0, 501)                 # a's block is free: c may reuse it
    assert np.array_equal(b.Q, B) and np.array_equal(b.t, tb)
    assert not np.shares_memory(b.Q, c.Q) and np.abs(c.Q - A).max() <= 1e-12
    C = c.Q.copy()
    d = qr.sweep(0.0, 1.0, 501, level="velocity")
    assert not np.shares_memory(c.Q, d.Q) and np.array_equal(c.Q, C)
    assert np.abs(d.Q - A).max() <= 1e-12 and np.abs(d.QD - AD).max() <= 1e-10
