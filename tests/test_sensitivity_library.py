"""The sensitivity library (mechgen/compiler/library/sensitivity.py) on the toy model, whose
right sides are derived by hand in toy.py: its block solve and its chain position →
velocity → acceleration against the toy's closed form differentiated by central
differences of the closed form itself (not of mechgen)."""
import math

import numpy as np
import pytest

from mechgen.compiler.library import sensitivity as S
from mechgen.compiler.library import toy

BROW, BVAR, BSTART = (np.array(v, dtype=np.int64) for v in ([2, 1, 0], [0, 1, 2], [0, 1, 2, 3]))


def closed(t, a, b, w):
    """q, q̇, q̈ of the toy crank-slider (a < b): th = w t, sin ph = −a sin th / b."""
    th = w * t
    ph = math.asin(-a * math.sin(th) / b)
    x = a * math.cos(th) + b * math.cos(ph)
    q = np.array([th, ph, x])
    J = np.zeros((3, 3))
    toy.phi_q(q, t, np.array([a, b, w]), J)
    nu = np.zeros(3)
    toy.nu(q, t, np.array([a, b, w]), nu)
    qd = np.linalg.solve(J, nu)
    g = np.zeros(3)
    toy.gamma(q, qd, t, np.array([a, b, w]), g)
    return q, qd, np.linalg.solve(J, g)


def pairs(q):
    """sin and cos of the coordinates (rows 0 and 1), computed here."""
    return np.array([np.sin(q), np.cos(q)])


@pytest.mark.parametrize("t", [0.0, 0.4, 1.7, 2.9])
def test_chain_matches_the_closed_form(t):
    p = np.array([1.0, 2.0, 1.3])
    q, qd, qdd = closed(t, *p)
    D = [np.zeros((3, 3)) for _ in range(3)]
    sel = np.arange(3, dtype=np.int64)
    status = S.sensitivities_point(q, qd, qdd, t, p, 2, BROW, BVAR, BSTART, sel, *D,
                                   np.empty((3, 3)), np.empty((3, 3)), np.empty(21),
                                   S.wanted(sel), pairs(q))
    assert status == S.SENS_OK
    for c in range(3):
        h = 1e-5
        up, dn = p.copy(), p.copy()
        up[c] += h
        dn[c] -= h
        fu, fd = closed(t, *up), closed(t, *dn)
        for order in range(3):
            ref = (fu[order] - fd[order]) / (2 * h)
            assert np.allclose(D[order][:, c], ref, rtol=1e-7, atol=1e-7), (order, c)


def test_only_the_selected_columns_are_written():
    p = np.array([1.0, 2.0, 1.3])
    q, qd, qdd = closed(0.4, *p)
    D = [np.full((3, 3), 7.0) for _ in range(3)]
    sel = np.array([1], dtype=np.int64)
    S.sensitivities_point(q, qd, qdd, 0.4, p, 2, BROW, BVAR, BSTART, sel, *D,
                          np.empty((3, 3)), np.empty((3, 3)), np.empty(21), S.wanted(sel),
                          pairs(q))
    for d in D:
        assert np.all(d[:, [0, 2]] == 7.0) and np.all(d[:, 1] != 7.0)


def test_a_lost_rank_is_refused():
    """a > b: the toy locks where |sin th| = b / a (cos ph = 0)."""
    a, b = 2.0, 1.0
    th = math.asin(b / a)
    q = np.array([th, -math.pi / 2, a * math.cos(th)])
    J, X = np.zeros((3, 3)), np.zeros((3, 3))
    toy.phi_q(q, 0.0, np.array([a, b, 1.0]), J)
    status = S.solve_columns(J, np.eye(3), X, BROW, BVAR, BSTART, np.arange(3, dtype=np.int64),
                             np.empty(21))
    assert status == S.SENS_SINGULAR
    # one block of everything (an unsorted module) says the same
    status = S.solve_columns(J, np.eye(3), X, np.arange(3, dtype=np.int64),
                             np.arange(3, dtype=np.int64), np.array([0, 3], dtype=np.int64),
                             np.arange(3, dtype=np.int64), np.empty(21))
    assert status == S.SENS_SINGULAR


def test_one_dense_block_equals_the_sorted_blocks():
    p = np.array([1.0, 2.0, 1.3])
    q, _, _ = closed(0.9, *p)
    J = np.zeros((3, 3))
    toy.phi_q(q, 0.9, p, J)
    B = np.arange(9.0).reshape(3, 3) - 4
    X1, X2 = np.zeros((3, 3)), np.zeros((3, 3))
    sel = np.arange(3, dtype=np.int64)
    S.solve_columns(J, B, X1, BROW, BVAR, BSTART, sel, np.empty(21))
    S.solve_columns(J, B, X2, np.array([0, 1, 2]), np.array([0, 1, 2]), np.array([0, 3]), sel,
                    np.empty(21))
    assert np.allclose(X1, np.linalg.solve(J, B), rtol=1e-13, atol=1e-13)
    assert np.allclose(X2, X1, rtol=1e-13, atol=1e-13)


def test_the_one_pass_position_derivatives_equal_the_block_solve_of_minus_phi_p():
    """position_sensitivities (Φ_p and the blocks in one pass) against solve_sorted on −Φ_p,
    column by column, the unwanted columns untouched."""
    p = np.array([1.0, 2.0, 1.3])
    for t in (0.1, 0.9, 2.2):
        q, _, _ = closed(t, *p)
        B = np.zeros((3, 3))
        toy.phi_p(q, t, p, B)
        ref = np.zeros((3, 3))
        assert toy.solve_sorted(q, t, p, -B, np.arange(3, dtype=np.int64), ref) == 0
        for c in range(3):
            X = np.full((3, 3), 7.0)
            want = np.zeros(3, dtype=np.bool_)
            want[c] = True
            assert toy.position_sensitivities(q, pairs(q), t, p, want, X) == 0
            assert np.allclose(X[:, c], ref[:, c], rtol=1e-14, atol=1e-14)
            assert np.all(np.delete(X, c, axis=1) == 7.0)


def test_turned_pairs_stay_sin_and_cos_along_a_sweep():
    """trig_pairs turns sin and cos from the last point by the step's series: against
    numpy's sin and cos, steps small and large, over more than 8 points, a step back."""
    rng = np.random.default_rng(3)
    angles = np.cumsum(np.concatenate([rng.uniform(-0.05, 0.05, 40), [0.3, -0.049, 1e-9],
                                       rng.uniform(-0.01, 0.01, 20)]))
    Q = np.zeros((angles.size, 3))
    Q[:, 0] = angles
    Q[:, 1] = -0.5 * angles + 2.0
    sc = np.zeros((2, 3))
    for k in range(angles.size):
        S.trig_pairs(Q[k], sc, Q[k - 1] if k else Q[k], k)
        for i in (0, 1):
            assert abs(sc[0, i] - math.sin(Q[k, i])) < 4e-16
            assert abs(sc[1, i] - math.cos(Q[k, i])) < 4e-16
