"""A four-bar's defects decided by mechgen's own solver (synthesis.verify: its model
compiled once, run on with_params for each four-bar, swept from pose 1 both ways) against the
closed form (FourBar.defects) on seeded cases: poses from two assembly modes (circuit), a
toggle between two poses (branch), poses out of order, defect-free ones, and every four-bar of
a five-pose problem. The poses are made here from a known linkage in complex numbers.

The model runs in the plain-Python tier (tier="python"): building it takes half a second,
numba's compile of it ten; a sweep that ends at a lock costs about 0.3 s there."""
import cmath
import math

import numpy as np
import pytest

from mechgen import synthesis


def pins(link, phi, s):
    """Crank pin A and coupler pin B (complex) at crank angle phi in mode s (±1)."""
    A = link["O2"] + link["a"] * cmath.exp(1j * phi)
    L = abs(link["O4"] - A)
    k = (link["b"] ** 2 + L * L - link["c"] ** 2) / (2 * link["b"] * L)
    if not -1 <= k <= 1:
        return None
    return A, A + link["b"] * cmath.exp(1j * (cmath.phase(link["O4"] - A) + s * math.acos(k)))


def poses_of(link, phis, modes):
    out = []
    for phi, s in zip(phis, modes):
        A, B = pins(link, phi, s)
        th = cmath.phase(B - A) - cmath.phase(link["uB"] - link["uA"])
        z = A - cmath.exp(1j * th) * link["uA"]
        out.append((z.real, z.imag, th))
    return out


def xy(z):
    return (z.real, z.imag)


def four_bar(link, poses):
    return synthesis.four_bar((xy(link["O2"]), xy(link["uA"])),
                              (xy(link["O4"]), xy(link["uB"])), poses)


def crank_rocker(rng):
    """A Grashof crank-rocker (the crank shortest) placed, turned and framed at random."""
    while True:
        a = rng.uniform(0.5, 1.0)
        b, c, d = rng.uniform(1.5, 3.5, size=3)
        if a + max(b, c, d) < b + c + d - max(b, c, d) - 0.3:
            break
    O2 = complex(*rng.normal(size=2))
    uA = complex(*rng.normal(size=2))
    return dict(O2=O2, O4=O2 + d * cmath.exp(1j * rng.uniform(-3, 3)), a=a, b=b, c=c,
                uA=uA, uB=uA + b * cmath.exp(1j * rng.uniform(-3, 3)))


# a = 1, d = 1.5, b = 1, c = 0.3: the crank closes the loop on two arcs, ±(0.40 .. 1.02) rad
TWO_ARCS = dict(O2=0j, O4=1.5 + 0j, a=1.0, b=1.0, c=0.3, uA=0.2 + 0.1j, uB=1.2 + 0.1j)


@pytest.fixture(scope="module")
def check():
    return synthesis.SolverCheck(tier="python")


CASES = [
    ("ordered", 0, [0.2, 1.0, 2.1, 3.0, 4.4], [1] * 5, set()),
    ("ordered, other mode", 1, [0.2, 1.0, 2.1, 3.0], [-1] * 4, set()),
    ("clockwise", 2, [4.4, 3.0, 2.1, 1.0, 0.2], [1] * 5, set()),
    ("two modes", 0, [0.2, 1.0, 2.1, 3.0, 4.4], [1, 1, -1, 1, 1], {"circuit"}),
    ("two modes, other seed", 3, [0.5, 1.5, 2.5, 3.5], [-1, 1, -1, -1], {"circuit"}),
    ("out of order", 0, [0.2, 2.1, 1.0, 3.0, 4.4], [1] * 5, {"order"}),
    ("a toggle between", None, [0.6, 0.8, -0.7, 0.9], [1] * 4, {"branch"}),
    ("a toggle, other mode", None, [-0.6, -0.5, 0.8, -0.45], [-1] * 4, {"branch"}),
    ("a rocker out of order", None, [0.6, 0.9, 0.7, 0.8], [1] * 4, {"order"}),
    ("circuit and branch", None, [0.6, 0.8, -0.7, 0.9], [1, -1, 1, 1], {"circuit", "branch"}),
]


@pytest.mark.parametrize("case, seed, phis, modes, expected", CASES, ids=[c[0] for c in CASES])
def test_the_solver_and_the_closed_form_agree(check, case, seed, phis, modes, expected):
    link = TWO_ARCS if seed is None else crank_rocker(np.random.default_rng(seed))
    poses = poses_of(link, phis, modes)
    fb = four_bar(link, poses)
    verdict = fb.verify(check)
    assert set(verdict.defects) == expected
    assert set(fb.defects) == expected
    reached = ~np.isnan(np.array(fb.times))
    assert np.array_equal(~np.isnan(np.array(verdict.times)), reached)
    assert np.allclose(np.array(verdict.times)[reached],
                       fb.direction * np.array(fb.times)[reached], atol=1e-9)
    assert (len(set(verdict.modes)) > 1) == ("circuit" in expected)
    if seed is None:                    # the two-arc linkage stops at a lock each way
        assert not verdict.full and None not in verdict.stops
        assert verdict.stops[0] > 0 > verdict.stops[1]
    else:
        assert verdict.full and verdict.stops == (None, None)


def test_every_four_bar_of_five_poses(check):
    """The gate's five poses (examples/burmester_five_poses.py): twelve four-bars, the
    solver's defects those of the closed form for each."""
    poses = [(0.845, 0.606, 0.360), (0.689, 0.823, 0.180), (0.368, 0.818, 0.054),
             (0.075, 0.592, 0.021), (-0.027, 0.263, 0.088)]
    links = synthesis.fourbars(poses)
    assert len(links) == 12
    kinds = set()
    for fb in links:
        assert check(fb).defects == fb.defects, fb
        kinds |= fb.defects or {"none"}
    assert kinds == {"none", "circuit"}


def test_one_module_serves_every_four_bar(check):
    """The check built its model once (the first four-bar's) and answers others with it;
    defects_by_solver takes the check to reuse (a first four-bar builds it here: the test
    runs alone, or first in its worker, as well as after the others)."""
    first = crank_rocker(np.random.default_rng(4))
    check(four_bar(first, poses_of(first, [0.2, 1.0, 2.1], [1, 1, 1])))
    mech = check.mech
    assert mech is not None and mech.tier == "python"
    link = crank_rocker(np.random.default_rng(9))
    fb = four_bar(link, poses_of(link, [0.1, 0.7, 1.9], [1, -1, 1]))
    assert synthesis.defects_by_solver(fb, check) == {"circuit"}
    assert check.mech is mech
