"""Function generation (synthesis.function, Freudenstein) against a known four-bar: its
(input, output) angle pairs computed here in closed form (the law of cosines at the crank
pin), three pairs giving its links back exactly and more pairs in least squares; bad pairs
named."""
import cmath
import math

import numpy as np
import pytest

from mechgen import synthesis


def output_angle(a, b, c, d, phi, s=1):
    """The output link's angle (from the ground line) of the four-bar O2 = 0, O4 = d at
    crank angle phi, in mode s; None where the loop does not close."""
    A = a * cmath.exp(1j * phi)
    L = abs(d - A)
    k = (b * b + L * L - c * c) / (2 * b * L)
    if not -1 <= k <= 1:
        return None
    B = A + b * cmath.exp(1j * (cmath.phase(d - A) + s * math.acos(k)))
    return cmath.phase(B - d)


KNOWN = (1.0, 3.2, 2.4, 3.0)        # a, b, c, d: a Grashof crank-rocker


def pairs_of(phis, link=KNOWN, s=1):
    return [(p, output_angle(*link, p, s)) for p in phis]


@pytest.mark.parametrize("phis", [(0.4, 1.5, 2.7), (-2.0, 0.1, 2.5)])
def test_three_pairs_give_the_known_four_bar_exactly(phis):
    fb = synthesis.function(pairs_of(phis), pivots=((0, 0), (3.0, 0)))
    assert np.allclose(fb.lengths, KNOWN, rtol=0, atol=1e-12)
    assert fb.residual < 1e-12
    assert fb.grashof == "crank-rocker"
    for phi in np.linspace(-3, 3, 13):                  # the whole function, not just the pairs
        psi = output_angle(*fb.lengths, phi)
        assert abs(math.remainder(psi - output_angle(*KNOWN, phi), 2 * math.pi)) < 1e-11


def test_the_ground_line_sets_the_angles_and_the_scale():
    """Pivots elsewhere, the ground line turned: the angles are measured from it, the
    lengths scale with it."""
    O2, O4 = np.array([1.0, -2.0]), np.array([1.0, -2.0]) + 6.0 * np.array([0.6, 0.8])
    fb = synthesis.function(pairs_of((0.4, 1.5, 2.7)), pivots=(O2, O4))
    assert np.allclose(fb.lengths, 2 * np.array(KNOWN), atol=1e-11)
    assert np.allclose(fb.input.fixed, O2) and np.allclose(fb.output.fixed, O4)
    gamma = math.atan2(0.8, 0.6)
    for (phi, psi), pose in zip(pairs_of((0.4, 1.5, 2.7)), fb.poses):
        A = np.array(pose[:2])                      # the coupler frame's origin: the crank pin
        assert math.remainder(math.atan2(*(A - O2)[::-1]) - gamma - phi, 2 * math.pi) == \
            pytest.approx(0, abs=1e-12)


def test_more_pairs_by_least_squares():
    phis = np.linspace(0.2, 2.8, 7)
    exact = synthesis.function(pairs_of(phis), pivots=((0, 0), (3.0, 0)))
    assert np.allclose(exact.lengths, KNOWN, atol=1e-10) and exact.residual < 1e-10
    rng = np.random.default_rng(4)
    noisy = [(p, q + 1e-4 * rng.normal()) for p, q in pairs_of(phis)]
    fb = synthesis.function(noisy, pivots=((0, 0), (3.0, 0)))
    assert np.allclose(fb.lengths, KNOWN, atol=1e-2)
    assert 0 < fb.residual < 1e-3


def test_the_four_bar_it_returns_reaches_the_pairs_in_order():
    fb = synthesis.function(pairs_of((0.4, 1.5, 2.7, 4.0)), pivots=((0, 0), (3.0, 0)))
    assert not fb.defects
    assert np.allclose(fb.times, [0, 1.1, 2.3, 3.6], atol=1e-9)


@pytest.mark.parametrize("pairs, culprit", [
    ([(0.1, 0.2), (0.5, 0.6)], "at least 3"),
    ([(0.1, 0.2), (0.5, float("inf")), (0.9, 1.0)], "pair 2 has a non-finite output"),
    ([(0.1, 0.2), (0.5, 0.6), (0.1 + 2 * math.pi, 0.9)],
     "pair 3 repeats the input angle of pair 1"),
    ([(0.1, 0.2, 0.3), (0.5, 0.6, 0.7), (0.9, 1.0, 1.1)], "two numbers"),
])
def test_bad_pairs_are_named(pairs, culprit):
    with pytest.raises(ValueError, match=culprit):
        synthesis.function(pairs)
