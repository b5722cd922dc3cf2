"""The numeric library every generated module holds (mechgen/compiler/library/), tested on
its own against the toy crank-slider of library/toy.py and its closed forms: the linear
algebra against numpy, Newton and the velocity/acceleration solves, the continuation
sweep with its status codes; jitted, in a module composed as the renderer composes one
(header + model + library text), and with NUMBA_DISABLE_JIT=1. Also the shape of the
library: its bodies import nothing, name nothing of mechgen, lint clean."""
from __future__ import annotations

import ast
import builtins
import importlib.util
import io
import json
import math
import os
import re
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from mechgen import protocol
from mechgen.compiler import library
from mechgen.compiler.library import continuation, designs, linalg, solve, toy

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOL = 1e-10
P = np.array([1.0, 2.0, 1.0])          # crank 1, rod 2, 1 rad/s: the crank turns fully
GUESS = np.array(toy.GUESS)


def exact(t, p=P):
    """q, q̇, q̈ of the toy in closed form, on the branch cos ph > 0."""
    a, b, w = p
    th = w * t
    ph = math.asin(-a * math.sin(th) / b)
    x = a * math.cos(th) + b * math.cos(ph)
    thd, thdd = w, 0.0
    phd = -a * math.cos(th) * thd / (b * math.cos(ph))
    xd = -a * math.sin(th) * thd - b * math.sin(ph) * phd
    phdd = (a * math.sin(th) * thd ** 2 + b * math.sin(ph) * phd ** 2) / (b * math.cos(ph))
    xdd = -a * math.cos(th) * thd ** 2 - b * math.cos(ph) * phd ** 2 - b * math.sin(ph) * phdd
    return np.array([th, ph, x]), np.array([thd, phd, xd]), np.array([thdd, phdd, xdd])


def run_sweep(mod, ts, p=P, q0=GUESS, level=2, method=protocol.METHOD_AUTO):
    N, n = ts.size, toy.N_COORDS
    Q, QD, QDD = np.zeros((N, n)), np.zeros((N, n)), np.zeros((N, n))
    STATUS = np.full((N, protocol.STATUS_COLUMNS), -1, dtype=np.int16)
    REPORT = np.full(protocol.REPORT_SIZE, -1.0)
    count = mod.sweep(ts, np.array(q0, dtype=float), np.asarray(p, dtype=float), level, TOL,
                      TOL, 50, method, Q, QD, QDD, STATUS, REPORT)
    return count, Q, QD, QDD, (STATUS, REPORT)


# -- linear algebra ----------------------------------------------------------------------
def test_gauss_solves_as_numpy_and_counts_usable_pivots():
    rng = np.random.default_rng(1)
    A = rng.normal(size=(5, 5)) + 5 * np.eye(5)
    b = rng.normal(size=5)
    x = b.copy()
    assert linalg._gauss(A.copy(), x) == 5
    np.testing.assert_allclose(x, np.linalg.solve(A, b), rtol=1e-13, atol=1e-14)
    A[3] = 0.0
    assert linalg._gauss(A.copy(), b.copy()) < 5


def test_det_is_numpy_s():
    rng = np.random.default_rng(2)
    for k in (1, 2, 3, 6):
        A = rng.normal(size=(k, k))
        assert linalg._det(A.copy()) == pytest.approx(np.linalg.det(A), rel=1e-12)
    A = rng.normal(size=(4, 4))
    A[:, 2] = 0.0
    assert linalg._det(A) == 0.0


def test_fp_solve_full_rank():
    rng = np.random.default_rng(3)
    A = rng.normal(size=(4, 4))
    x_true = rng.normal(size=4)
    x = np.zeros(4)
    assert linalg._fp_solve(A.copy(), A @ x_true, x, protocol.PIVOT_RTOL) == 4
    np.testing.assert_allclose(x, x_true, rtol=1e-12)


def test_fp_solve_drops_redundant_rows_and_tells_whether_they_hold():
    rng = np.random.default_rng(4)
    A = rng.normal(size=(5, 3))
    A[3] = A[0] + 2.0 * A[1]            # two dependent equations
    A[4] = 1e3 * A[2]                   # (in other units)
    x_true = rng.normal(size=3)
    b = A @ x_true
    x = np.zeros(3)
    bb = b.copy()
    rank = linalg._fp_solve(A.copy(), bb, x, protocol.PIVOT_RTOL)
    assert rank == 3
    np.testing.assert_allclose(x, x_true, rtol=1e-11)
    assert linalg._consistent(bb, rank, x)
    bad = b.copy()
    bad[3] += 1.0                       # the dependent equation now disagrees
    rank = linalg._fp_solve(A.copy(), bad, x, protocol.PIVOT_RTOL)
    assert rank == 3 and not linalg._consistent(bad, rank, x)


def test_fp_solve_rank_deficient_gives_a_solution():
    rng = np.random.default_rng(5)
    A = rng.normal(size=(3, 3))
    A[:, 2] = A[:, 0] + A[:, 1]         # rank 2
    b = A @ rng.normal(size=3)
    x = np.full(3, np.nan)
    assert linalg._fp_solve(A.copy(), b.copy(), x, protocol.PIVOT_RTOL) == 2
    np.testing.assert_allclose(A @ x, b, atol=1e-12)
    assert np.count_nonzero(x == 0.0) == 1      # the unknown beyond the rank is set to zero


def test_fp_eliminate_smallest_pivot_of_the_scaled_rows():
    A = np.array([[2.0, 0.0], [0.0, 1e-3]])
    b = np.zeros(2)
    rank, small = linalg._fp_eliminate(A, b, np.arange(2), 0.0)
    assert rank == 2 and small == 1.0               # each row scaled to 1 first
    A = np.array([[1.0, 1.0], [1.0, 1.0 + 1e-8]])
    rank, small = linalg._fp_eliminate(A.copy(), np.zeros(2), np.arange(2), 0.0)
    assert rank == 2 and small == pytest.approx(1e-8, rel=1e-6)
    rank, _ = linalg._fp_eliminate(A.copy(), np.zeros(2), np.arange(2), protocol.SING_RTOL)
    assert rank == 1


def test_max_abs_propagates_nan():
    assert linalg._max_abs(np.array([1.0, -3.0, 2.0])) == 3.0
    assert math.isnan(linalg._max_abs(np.array([1.0, np.nan, 5.0])))
    assert linalg._max_abs(np.zeros(0)) == 0.0


@pytest.mark.parametrize("d", [0.0, 1e-7, -4e-4, 0.3])
def test_turn_rotates_sin_and_cos(d):
    y0 = 0.7
    s, c = linalg._turn(math.sin(y0), math.cos(y0), d, y0 - d)
    assert s == pytest.approx(math.sin(y0 - d), abs=2e-16)
    assert c == pytest.approx(math.cos(y0 - d), abs=2e-16)


# -- one configuration -------------------------------------------------------------------
@pytest.mark.parametrize("t", [0.0, 0.4, 2.0, 4.5])
def test_newton_full_converges_to_the_closed_form(t):
    q = GUESS.copy()
    info = np.zeros(protocol.POSITION_INFO_SIZE)
    assert solve.newton_full(q, t, P, TOL, TOL, 50, info) == protocol.OK
    np.testing.assert_allclose(q, exact(t)[0], atol=1e-10)
    assert 1 <= info[protocol.INFO_ITERATIONS] <= 10
    assert info[protocol.INFO_RESIDUAL] <= TOL
    assert info[protocol.INFO_RANK] == toy.N_COORDS


def test_newton_full_statuses():
    locked = np.array([1.2, 1.0, 1.0])  # crank longer than the rod: no configuration at th=1.2
    info = np.zeros(protocol.POSITION_INFO_SIZE)
    assert solve.newton_full(GUESS.copy(), 1.2, locked, TOL, TOL, 50, info) == \
        protocol.NO_CONVERGENCE
    assert info[protocol.INFO_ITERATIONS] == 50 and info[protocol.INFO_RESIDUAL] > TOL
    bad = np.array([np.nan, 1.0, 1.0])
    assert solve.newton_full(GUESS.copy(), 0.3, bad, TOL, TOL, 50, info) == protocol.NOT_FINITE


@pytest.mark.parametrize("method", [protocol.METHOD_AUTO, protocol.METHOD_SORTED,
                                    protocol.METHOD_FULL])
def test_solve_point_derivatives_against_the_closed_form(method):
    t = 0.9
    q, qd, qdd = GUESS.copy(), np.zeros(3), np.zeros(3)
    info = np.zeros(protocol.POINT_INFO_SIZE)
    status = solve.solve_point_derivatives(q, t, P, TOL, TOL, 50, method, 2, qd, qdd, info)
    assert status == protocol.OK
    q_, qd_, qdd_ = exact(t)
    np.testing.assert_allclose(q, q_, atol=1e-10)
    np.testing.assert_allclose(qd, qd_, atol=1e-9)
    np.testing.assert_allclose(qdd, qdd_, atol=1e-9)
    assert info[protocol.INFO_METHOD] == (1.0 if method == protocol.METHOD_FULL else 0.0)
    assert info[protocol.POINT_RESIDUAL] <= TOL and info[protocol.POINT_PIVOT] > 0.1


def test_full_and_sorted_velocity_and_acceleration_agree_with_the_closed_form():
    q_, qd_, qdd_ = exact(2.2)
    for velocity, acceleration in ((solve.velocity_full, solve.acceleration_full),
                                   (toy.velocity_sorted, toy.acceleration_sorted)):
        qd, qdd = np.zeros(3), np.zeros(3)
        assert velocity(q_, 2.2, P, qd) == protocol.OK
        assert acceleration(q_, qd, 2.2, P, qdd) == protocol.OK
        np.testing.assert_allclose(qd, qd_, atol=1e-12)
        np.testing.assert_allclose(qdd, qdd_, atol=1e-12)


def test_a_singular_configuration():
    """The toy with crank 2, rod 1 locks at sin th = 1/2 with the rod vertical."""
    p = np.array([2.0, 1.0, 1.0])
    q = np.array([math.pi / 6, -math.pi / 2, math.sqrt(3.0)])
    assert solve.pivot_ratio(q, math.pi / 6, p) < protocol.SING_RTOL
    assert solve.velocity_full(q, math.pi / 6, p, np.zeros(3)) == protocol.SINGULAR
    assert solve.solve_velocity(q, math.pi / 6, p, protocol.METHOD_AUTO, np.zeros(3)) == \
        protocol.SINGULAR
    assert abs(solve.jacobian_det_full(q, math.pi / 6, p)) < 1e-12
    info = np.zeros(protocol.POINT_INFO_SIZE)
    status = solve.solve_point_derivatives(q.copy(), math.pi / 6, p, TOL, TOL, 50,
                                           protocol.METHOD_FULL, 2, np.zeros(3), np.zeros(3),
                                           info)
    assert status == protocol.VELOCITY + protocol.SINGULAR


def test_jacobian_det_full_is_the_toy_s():
    q = exact(0.8)[0]
    assert solve.jacobian_det_full(q, 0.8, P) == pytest.approx(toy.jacobian_det(q, 0.8, P, np.zeros(2)),
                                                                rel=1e-12)


# -- sweeps ------------------------------------------------------------------------------
def test_sweep_follows_the_closed_form():
    ts = np.linspace(0.0, 2 * math.pi, 65)
    for level in (0, 1, 2):
        count, Q, QD, QDD, (STATUS, REPORT) = run_sweep(continuation, ts, level=level)
        assert count == ts.size
        assert np.all(STATUS[:, protocol.STATUS_CODE] == protocol.OK)
        assert np.all((1 <= STATUS[:, protocol.STATUS_ITERATIONS]) &
                      (STATUS[:, protocol.STATUS_ITERATIONS] <= 50))
        assert not REPORT.any()                 # no failure, no jump
        for k, t in enumerate(ts):
            q_, qd_, qdd_ = exact(t)
            np.testing.assert_allclose(Q[k], q_, atol=1e-9)
            if level >= 1:
                np.testing.assert_allclose(QD[k], qd_, atol=1e-8)
            if level >= 2:
                np.testing.assert_allclose(QDD[k], qdd_, atol=1e-8)
            else:
                assert not QDD[k].any()             # a level not asked for: not written


def test_sweep_stops_where_the_mechanism_locks():
    """Crank 1.2, rod 1: no configuration past th = asin(1/1.2); the sweep returns the count
    before it and the failing point's status, the time reached and the time that failed."""
    ts = np.linspace(0.0, 1.5, 31)
    lock = math.asin(1.0 / 1.2)
    count, Q, _, _, (STATUS, REPORT) = run_sweep(continuation, ts, p=(1.2, 1.0, 1.0))
    assert count == int(lock / 0.05) + 1
    assert STATUS[count, protocol.STATUS_CODE] == protocol.NO_CONVERGENCE
    assert REPORT[protocol.REPORT_STATUS] == protocol.NO_CONVERGENCE
    assert ts[count - 1] <= REPORT[protocol.REPORT_REACHED] <= lock
    assert lock <= REPORT[protocol.REPORT_FAILED] <= ts[count]
    assert REPORT[protocol.INFO_ITERATIONS] >= 1 and REPORT[protocol.INFO_RESIDUAL] > TOL
    assert np.all(STATUS[count + 1:] == -1)     # nothing written past the failure
    for k in range(count):
        np.testing.assert_allclose(Q[k], exact(ts[k], (1.2, 1.0, 1.0))[0], atol=1e-9)


def test_sweep_flags_the_points_past_a_branch_point():
    """Crank = rod: the branches ph = -th and ph = th - π meet at th = π/2 (a toggle); the
    sweep gets through, and flags what it reached there (a jump or a singular crossing)."""
    ts = np.linspace(0.0, math.pi, 41)
    count, _, _, _, (STATUS, REPORT) = run_sweep(continuation, ts, p=(1.0, 1.0, 1.0))
    assert count == ts.size
    status = STATUS[:, protocol.STATUS_CODE]
    flagged = np.flatnonzero(status != protocol.OK)
    assert flagged.size and set(status[flagged]) <= {protocol.JUMP, protocol.THROUGH_SINGULAR}
    step = ts[1] - ts[0]                          # the toggle's point and the next one
    assert np.all((ts[flagged] > math.pi / 2 - 1e-12) & (ts[flagged] < math.pi / 2 + step + 1e-12))
    assert (REPORT[protocol.REPORT_JUMP] > 0.0) == np.any(status == protocol.JUMP)
    assert REPORT[protocol.REPORT_STATUS] == protocol.OK


def test_sweep_designs_is_a_sweep_per_design():
    ts = np.linspace(0.0, 3.0, 31)
    P2 = np.array([P, [1.0, 2.5, 1.5]])
    N, n = ts.size, toy.N_COORDS
    Q, QD, QDD = np.zeros((2, N, n)), np.zeros((2, N, n)), np.zeros((2, N, n))
    STATUS = np.zeros((2, N, protocol.STATUS_COLUMNS), dtype=np.int16)
    done = designs.sweep_designs(ts, np.tile(GUESS, (2, 1)), P2, 2, TOL, TOL, 50,
                                 protocol.METHOD_AUTO, Q, QD, QDD, STATUS)
    assert list(done) == [N, N]
    for d in range(2):
        for k, t in enumerate(ts):
            q_, qd_, qdd_ = exact(t, P2[d])
            np.testing.assert_allclose(Q[d, k], q_, atol=1e-9)
            np.testing.assert_allclose(QDD[d, k], qdd_, atol=1e-8)



def _design_arrays(D, N):
    n = toy.N_COORDS
    return (np.zeros((D, N, n)), np.zeros((D, N, n)), np.zeros((D, N, n)),
            np.zeros((D, N, protocol.STATUS_COLUMNS), dtype=np.int16))


@pytest.mark.parametrize("start", [0, 1, 12, 31])
def test_the_careful_rest_of_a_design_goes_on_from_its_quick_paths_last_point(start):
    """sweep_designs_rest after a quick path that accepted ``start`` of the 31 points (its
    points there put in by hand from the closed form, the rows after them left holding
    the other branch, as a table's scratch arrays may): sweep() from the last accepted
    point gives the closed form at every later point, and leaves a design swept whole
    (start 31) as it is."""
    ts = np.linspace(0.0, 3.0, 31)
    P2 = np.array([P, [1.0, 2.5, 1.5]])
    N = ts.size
    Q, QD, QDD, STATUS = _design_arrays(2, N)
    for d in range(2):
        for k in range(N):
            Q[d, k], QD[d, k], QDD[d, k] = exact(ts[k], P2[d])
            if k >= start:                          # cos ph < 0: the other branch
                Q[d, k, 1] = math.pi - Q[d, k, 1]
                Q[d, k, 2] -= 2.0 * P2[d, 1] * math.cos(Q[d, k, 1] - math.pi)
    START = np.full(2, start, dtype=np.int64)
    done = designs.sweep_designs_rest(ts, np.tile(GUESS, (2, 1)), P2, 2, TOL, TOL, 50,
                                      protocol.METHOD_AUTO, Q, QD, QDD, STATUS, START)
    assert list(done) == [N, N]
    for d in range(2):
        for k, t in enumerate(ts):
            q_, qd_, qdd_ = exact(t, P2[d])
            np.testing.assert_allclose(Q[d, k], q_, atol=1e-9)
            np.testing.assert_allclose(QD[d, k], qd_, atol=1e-8)
            np.testing.assert_allclose(QDD[d, k], qdd_, atol=1e-8)
        if start == N:
            assert not STATUS[d].any()              # not touched: the quick path's


def test_the_quick_path_of_every_design_counts_what_it_accepted():
    """sweep_designs_fast: each design's sweep_fast() count (all 31 points of an easy
    sweep, on the closed form); none with METHOD_FULL."""
    ts = np.linspace(0.0, 3.0, 31)
    P2 = np.array([P, [1.0, 2.5, 1.5]])
    Q, QD, QDD, STATUS = _design_arrays(2, ts.size)
    START = np.full(2, -1, dtype=np.int64)
    designs.sweep_designs_fast(ts, np.tile(GUESS, (2, 1)), P2, TOL, TOL, 50,
                               protocol.METHOD_AUTO, Q, QD, QDD, STATUS, START)
    assert list(START) == [ts.size, ts.size]
    for d in range(2):
        for k, t in enumerate(ts):
            np.testing.assert_allclose(Q[d, k], exact(t, P2[d])[0], atol=1e-9)
    designs.sweep_designs_fast(ts, np.tile(GUESS, (2, 1)), P2, TOL, TOL, 50,
                               protocol.METHOD_FULL, Q, QD, QDD, STATUS, START)
    assert list(START) == [0, 0]


def test_each_design_starts_carried_to_its_parameters_then_walked_to_the_first_time():
    """carry_designs at the guess's time (0), then walk_designs to the table's first time
    (0.8): each design's start is the closed form at its own parameters there, on the
    guess's branch; start_designs, the two in one call, gives the same."""
    tw = np.linspace(0.0, 0.8, 9)
    P3 = np.array([[1.0, 2.0, 1.0], [1.2, 2.0, 1.0], [0.9, 2.4, 1.3]])
    q = exact(0.0)[0]
    Q0, S0 = np.zeros((3, toy.N_COORDS)), np.full(3, -1, dtype=np.int64)
    designs.carry_designs(0.0, q, GUESS, P, P3, TOL, TOL, 50, protocol.METHOD_AUTO, Q0, S0)
    assert list(S0) == [protocol.OK] * 3
    for d in range(3):
        np.testing.assert_allclose(Q0[d], exact(0.0, P3[d])[0], atol=1e-9)
    designs.walk_designs(tw, P3, TOL, TOL, 50, protocol.METHOD_AUTO, Q0, S0)
    assert list(S0) == [protocol.OK] * 3
    for d in range(3):
        np.testing.assert_allclose(Q0[d], exact(0.8, P3[d])[0], atol=1e-9)
    both, S1 = np.zeros_like(Q0), np.full(3, -1, dtype=np.int64)
    designs.start_designs(tw, q, GUESS, P, P3, TOL, TOL, 50, protocol.METHOD_AUTO, both, S1)
    assert np.array_equal(both, Q0) and np.array_equal(S1, S0)

def test_eval_points_and_outputs():
    ts = np.linspace(0.0, 1.0, 5)
    count, Q, QD, QDD, _ = run_sweep(continuation, ts)
    OUT = np.zeros((5, 3, 2))
    continuation.eval_points(Q, ts, P, OUT)
    np.testing.assert_allclose(OUT[:, 1, 0], np.cos(ts))
    np.testing.assert_allclose(OUT[:, 2, 0], Q[:, 2])
    for order, arr in enumerate((Q, QD, QDD)):
        O = np.zeros((5, 1))
        continuation.eval_outputs(Q, QD, QDD, ts, P, order, O)
        np.testing.assert_array_equal(O[:, 0], arr[:, 2])


# -- a module composed as the renderer composes one -----------------------------------------
def compose(**constants):
    """A module's text as the renderer writes it: imports, the header constants from
    protocol, the toy's model part (with ``constants`` changed), the library text."""
    header = "import math\nimport sys\n\nimport numpy as np\nfrom numba import njit\n\n"
    for comment, names in protocol.header_constants():
        header += f"# {comment}\n" + "".join(f"{n} = {v}\n" for n, v in names)
    model = library.body("toy.py")
    for name, value in constants.items():
        model, count = re.subn(rf"^{name} = .*$", f"{name} = {value!r}", model, count=1,
                               flags=re.M)
        assert count == 1, name
    return header + "\n\n" + model + "\n\n" + library.library_text()


@pytest.fixture(scope="module")
def unsorted(tmp_path_factory):
    """The toy as a module without block structure and with a coordinate not solved."""
    path = tmp_path_factory.mktemp("composed") / "toy_unsorted.py"
    path.write_text(compose(SORTED=False, ALL_SOLVED=False), encoding="utf-8")
    spec = importlib.util.spec_from_file_location("toy_unsorted", path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    yield mod
    del sys.modules[spec.name]


def test_composed_module_without_sorted_solvers_solves_by_the_full_newton(unsorted):
    assert unsorted.SORTED is False and unsorted.ALL_SOLVED is False
    for method in (protocol.METHOD_AUTO, protocol.METHOD_SORTED):
        q, info = GUESS.copy(), np.zeros(protocol.POSITION_INFO_SIZE)
        assert unsorted.solve_position(q, 0.6, P, TOL, TOL, 50, method, info) == protocol.OK
        assert info[protocol.INFO_METHOD] == 1.0        # never the sorted solver
        np.testing.assert_allclose(q, exact(0.6)[0], atol=1e-10)
    q, info = GUESS.copy(), np.zeros(protocol.POSITION_INFO_SIZE)
    solve.solve_position(q, 0.6, P, TOL, TOL, 50, protocol.METHOD_SORTED, info)
    assert info[protocol.INFO_METHOD] == 0.0            # the toy itself: sorted
    ts = np.linspace(0.0, 2.0, 21)
    a = run_sweep(unsorted, ts)
    b = run_sweep(continuation, ts)
    assert a[0] == b[0] == ts.size
    for x, y in zip(a[1:4], b[1:4]):
        np.testing.assert_allclose(x, y, atol=1e-9)


def test_fin_zeroes_what_a_pruned_module_does_not_solve(unsorted):
    assert unsorted._fin(np.inf) == 0.0 and unsorted._fin(2.5) == 2.5
    assert solve._fin(np.inf) == np.inf                 # ALL_SOLVED: as it is


# -- without the JIT ---------------------------------------------------------------------
NOJIT = textwrap.dedent("""
    import json, math
    import numpy as np
    from mechgen.compiler.library import continuation, solve, toy
    p = np.array([1.0, 2.0, 1.0])
    q, qd, qdd, info = np.array(toy.GUESS), np.zeros(3), np.zeros(3), np.zeros(6)
    status = solve.solve_point_derivatives(q, 0.9, p, 1e-10, 1e-10, 50, 0, 2, qd, qdd, info)
    ts = np.linspace(0.0, 2.0, 11)
    Q, QD, QDD = np.zeros((11, 3)), np.zeros((11, 3)), np.zeros((11, 3))
    S, R = np.zeros((11, 2), dtype=np.int16), np.zeros(8)
    count = continuation.sweep(ts, np.array(toy.GUESS), p, 2, 1e-10, 1e-10, 50, 0,
                               Q, QD, QDD, S, R)
    jitted = hasattr(solve.solve_point_derivatives, "py_func")
    print(json.dumps(dict(status=status, q=list(q) + list(qd) + list(qdd), count=count,
                          Q=Q.ravel().tolist(), QDD=QDD.ravel().tolist(), jitted=jitted)))
""")


def test_library_runs_the_same_without_the_jit():
    env = dict(os.environ, NUMBA_DISABLE_JIT="1",
               PYTHONPATH=os.pathsep.join([ROOT] + sys.path))
    done = subprocess.run([sys.executable, "-c", NOJIT], env=env, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    plain = json.loads(done.stdout.strip().splitlines()[-1])
    assert plain["jitted"] is False
    q, qd, qdd, info = GUESS.copy(), np.zeros(3), np.zeros(3), np.zeros(6)
    status = solve.solve_point_derivatives(q, 0.9, P, TOL, TOL, 50, 0, 2, qd, qdd, info)
    assert plain["status"] == status == protocol.OK
    np.testing.assert_allclose(plain["q"], np.concatenate([q, qd, qdd]), atol=1e-12)
    count, Q, _, QDD, _ = run_sweep(continuation, np.linspace(0.0, 2.0, 11))
    assert plain["count"] == count == 11
    np.testing.assert_allclose(plain["Q"], Q.ravel(), atol=1e-11)
    np.testing.assert_allclose(plain["QDD"], QDD.ravel(), atol=1e-9)


# -- the shape of the library --------------------------------------------------------------
def _free_names(tree):
    """Names a module body reads that none of its functions binds locally: what it needs
    from the module around it."""
    free = set()
    for fn in ast.walk(tree):
        if not isinstance(fn, ast.FunctionDef):
            continue
        bound = {a.arg for a in fn.args.args}
        for node in ast.walk(fn):
            if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
                bound.add(node.id)
        for node in ast.walk(fn):
            if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load) \
                    and node.id not in bound:
                free.add(node.id)
    for node in tree.body:
        for dec in getattr(node, "decorator_list", ()):
            free.update(n.id for n in ast.walk(dec) if isinstance(n, ast.Name))
    return free


def test_bodies_import_nothing_and_need_only_what_a_module_defines():
    trees = {name: ast.parse(library.body(name))
             for name in library.FILES + library.FORCE_FILES}
    defined = {node.name for tree in trees.values() for node in tree.body
               if isinstance(node, ast.FunctionDef)}
    header = {"math", "np", "njit"}      # what a generated module's header imports
    for name, tree in trees.items():
        assert not [n for n in ast.walk(tree) if isinstance(n, (ast.Import, ast.ImportFrom))], \
            f"the body of {name} imports"
        needed = _free_names(tree) - defined - header - set(dir(builtins))
        assert needed <= set(toy.__all__), f"{name} needs {sorted(needed - set(toy.__all__))}"
        assert not any("mechgen" in n or n == "protocol" for n in _free_names(tree))
    # the toy defines all the header constants, and no other name the library does not use
    constants = {n for _, names in protocol.HEADER_CONSTANTS for n in names}
    assert constants <= set(toy.__all__)
    used = set().union(*(_free_names(t) for t in trees.values()))
    assert set(toy.__all__) - used - constants - {"njit", "INLINE"} == set()


def test_library_files_import_only_numerics_the_toy_and_each_other():
    allowed = {"math", "numpy", "numba"}
    for name in library.FILES + library.FORCE_FILES + ("toy.py",):
        tree = ast.parse(library.source(name))
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                assert {a.name.split(".")[0] for a in node.names} <= allowed, name
            elif isinstance(node, ast.ImportFrom):
                if node.level == 1:
                    siblings = {f[:-3] for f in library.FILES + library.FORCE_FILES}
                    assert node.module in siblings | {"toy"}, (name, node.module)
                else:
                    assert (node.level, node.module) == (3, "protocol") and name == "toy.py" \
                        or node.level == 0 and node.module.split(".")[0] in allowed, name


def test_library_imported_by_itself_caches_nothing_on_disk():
    """numba's cache would not notice a change to the toy's constants (another file)."""
    import numba.core.caching
    dispatchers = [f for mod in (linalg, solve, continuation, toy) for f in vars(mod).values()
                   if hasattr(f, "py_func")]
    assert len(dispatchers) > 30
    for f in dispatchers:
        assert isinstance(f._cache, numba.core.caching.NullCache), f.__name__


def test_library_text_is_the_bodies_in_order():
    text = library.library_text()
    assert text == library.library_text()
    starts = [text.index(library.body(name)) for name in library.FILES]
    assert starts == sorted(starts) and starts[0] == 0
    assert library.MARKER not in text and "{%" not in text and "{{" not in text


def test_library_lints_clean():
    """pyflakes is in the `test` extra, so this runs (never skips) wherever the suite does."""
    import pyflakes.api as pyflakes
    from pyflakes.reporter import Reporter
    out = io.StringIO()
    for name in library.FILES + ("toy.py", "__init__.py"):
        pyflakes.check(library.source(name), name, Reporter(out, out))
    assert out.getvalue() == ""


def test_cholesky_solves_and_refuses_what_is_not_positive_definite():
    from mechgen.compiler.library import forces as linalg     # the force part's own
    rng = np.random.default_rng(7)
    B = rng.normal(size=(6, 6))
    A = B @ B.T + 0.1 * np.eye(6)
    b = rng.normal(size=6)
    L = A.copy()
    assert linalg._cholesky(L, 1e-12)
    x = b.copy()
    linalg._cholesky_solve(L, x)
    np.testing.assert_allclose(x, np.linalg.solve(A, b), rtol=1e-12, atol=1e-13)
    A[3, :] = A[:, 3] = 0.0          # a coordinate without mass or inertia
    assert not linalg._cholesky(A.copy(), 1e-12)
    assert not linalg._cholesky(-np.eye(3), 1e-12)


def test_the_force_blocks_solve_both_ways_on_the_toy():
    """library/forces.py's multipliers_sorted (Φ_qᵀ λ = r, blocks in the reverse solving
    order) and coordinates_sorted (Φ_q x = b, in the solving order) against numpy's dense
    solves, on the toy crank-slider's Φ_q at a few configurations."""
    from mechgen.compiler.library import forces as flib
    rng = np.random.default_rng(11)
    n = toy.N_COORDS
    A, y, r = np.empty((n, n)), np.empty(n), np.empty(n)
    for _ in range(5):
        q = np.array([rng.uniform(-3, 3), rng.uniform(-0.5, 0.5), 2.5])
        J = np.empty((n, n))
        toy.phi_q(q, 0.0, P, J)
        b, rhs = rng.normal(size=n), rng.normal(size=n)
        x, lam = np.empty(n), np.empty(n)
        assert flib.coordinates_sorted(J, b, x, A, y) >= toy.SING_RTOL
        np.testing.assert_allclose(x, np.linalg.solve(J, b), rtol=1e-12, atol=1e-12)
        assert flib.multipliers_sorted(J, rhs, lam, A, y, r) >= toy.SING_RTOL
        np.testing.assert_allclose(lam, np.linalg.solve(J.T, rhs), rtol=1e-12, atol=1e-12)
