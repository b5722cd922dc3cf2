"""Counts and conditions of synthesis against references written here, on seeded random
problems:

- five poses: the real Burmester pairs synthesis.dyads finds from its quartic are exactly
  those an independent multi-start search finds (scipy's fsolve on the four equal-distance
  equations |P_j(u) − G|² = |P_1(u) − G|² from 400 starts at radii from 0.1 to 30 poses'
  spreads, deduplicated): the same number, pair for pair;
- four poses: every sampled centre point G satisfies the compatibility equation, the
  determinant of the three equal-distance equations (linear in the moving pivot (u, 1)),
  built here from the distances themselves;
- function generation: three (input, output) pairs of a random four-bar (the law of cosines)
  give back its links, and its output at each input, to 1e-12."""
import cmath
import math

import numpy as np
import pytest
from scipy.optimize import fsolve

from mechgen import synthesis


def equations(v, poses):
    G, u = complex(v[0], v[1]), complex(v[2], v[3])
    r = np.array([abs(complex(x, y) + cmath.exp(1j * th) * u - G) ** 2 for x, y, th in poses])
    return r[1:] - r[0]


def multi_start(poses, rng, starts=400):
    """(fixed, moving) pairs found by fsolve from random starts, in the poses' own centred
    and scaled frame (then carried back), deduplicated."""
    P = np.array(poses, dtype=float)
    centre = P[:, :2].mean(axis=0)
    scale = math.sqrt(np.mean(np.sum((P[:, :2] - centre) ** 2, axis=1)))
    Q = P.copy()
    Q[:, :2] = (Q[:, :2] - centre) / scale
    found = []
    for _ in range(starts):
        x0 = rng.normal(size=4)
        x0 *= 10 ** rng.uniform(-1, 1.5) / np.linalg.norm(x0)
        v, _, ok, _ = fsolve(equations, x0, args=(Q,), full_output=True, xtol=1e-13)
        if ok == 1 and np.max(np.abs(equations(v, Q))) < 1e-10 and np.linalg.norm(v) < 1e6 \
                and not any(np.allclose(v, w, atol=1e-6 * (1 + np.linalg.norm(w)))
                            for w in found):
            found.append(v)
    return [(w[:2] * scale + centre, w[2:] * scale) for w in found]


def random_poses(rng, kind):
    if kind == "random":
        return np.column_stack([rng.normal(size=5), rng.normal(size=5),
                                rng.uniform(-1.5, 1.5, size=5)])
    # a four-bar's coupler: a = 1 crank, random b, c, d; its frame at a random place
    b, c, d = rng.uniform(2.0, 3.5, size=3)
    phis = np.sort(rng.uniform(0, 2 * math.pi, size=5))
    uA = complex(*rng.normal(size=2))
    uB = uA + b * cmath.exp(1j * rng.uniform(-3, 3))
    out = []
    for phi in phis:
        A = cmath.exp(1j * phi)
        L = abs(d - A)
        k = (b * b + L * L - c * c) / (2 * b * L)
        if not -1 <= k <= 1:
            return None
        B = A + b * cmath.exp(1j * (cmath.phase(d - A) + math.acos(k)))
        th = cmath.phase(B - A) - cmath.phase(uB - uA)
        z = A - cmath.exp(1j * th) * uA
        out.append((z.real, z.imag, th))
    return np.array(out)


# seeds chosen to hold 0, 2 and 4 real pairs among them (random: 504 and 517 have none,
# 507 four, the rest two)
@pytest.mark.parametrize("seed, kind", [(500 + k, "random") for k in (0, 2, 4, 7, 14, 17)]
                         + [(600 + k, "coupler") for k in range(4)])
def test_real_pairs_agree_with_a_multi_start_search(seed, kind):
    rng = np.random.default_rng(seed)
    poses = random_poses(rng, kind)
    while poses is None:
        poses = random_poses(rng, kind)
    exact = synthesis.dyads(poses, sliders=False)
    searched = multi_start(poses, rng)
    assert len(exact) == len(searched)
    for fixed, moving in searched:
        assert any(np.allclose(d.fixed, fixed, rtol=1e-7, atol=1e-7) and
                   np.allclose(d.moving, moving, rtol=1e-7, atol=1e-7) for d in exact)
    for d in exact:
        r = equations(np.concatenate([d.fixed, d.moving]), poses)
        assert np.max(np.abs(r)) <= 1e-10 * max(1.0, np.linalg.norm(d.fixed)) ** 2
    if kind == "random" and seed in (504, 517):
        assert exact == []
    if seed == 507:
        assert len(exact) == 4


def compatibility(poses, G):
    """The three equal-distance equations at G are linear in (u, 1): their 3×3 matrix, from
    the equations at u = 0, (1, 0), (0, 1); its determinant over its size cubed."""
    def f(u):
        return equations(np.concatenate([G, u]), poses)
    c = f(np.zeros(2))
    M = np.column_stack([f(np.array([1.0, 0.0])) - c, f(np.array([0.0, 1.0])) - c, c])
    return np.linalg.det(M) / np.abs(M).max() ** 3


@pytest.mark.parametrize("seed", range(5))
def test_sampled_centre_points_satisfy_the_compatibility(seed):
    rng = np.random.default_rng(700 + seed)
    poses = np.column_stack([rng.normal(size=4), rng.normal(size=4),
                             rng.uniform(-1.2, 1.2, size=4)])
    dyads = synthesis.dyads(poses, samples=30)
    assert len(dyads) >= 20
    for d in dyads:
        assert abs(compatibility(poses, np.array(d.fixed))) < 1e-10
    # and a point off the curve does not
    G = np.array(dyads[0].fixed) + 0.1 * (1 + np.linalg.norm(dyads[0].fixed))
    assert abs(compatibility(poses, G)) > 1e-6


def output_angle(a, b, c, d, phi):
    """The output link's angle (O2 = 0, O4 = d) at crank angle phi (law of cosines)."""
    A = a * cmath.exp(1j * phi)
    L = abs(d - A)
    k = (b * b + L * L - c * c) / (2 * b * L)
    if not -1 <= k <= 1:
        return None
    B = A + b * cmath.exp(1j * (cmath.phase(d - A) + math.acos(k)))
    return cmath.phase(B - d)


@pytest.mark.parametrize("seed", range(6))
def test_function_generation_through_three_pairs_is_exact(seed):
    rng = np.random.default_rng(800 + seed)
    while True:
        link = (rng.uniform(0.5, 1.0),) + tuple(rng.uniform(1.5, 3.5, size=3))
        phis = rng.uniform(-math.pi, math.pi, size=3)
        pairs = [(p, output_angle(*link, p)) for p in phis]
        if all(q is not None for _, q in pairs) and \
                min(abs(math.remainder(x - y, 2 * math.pi))
                    for i, x in enumerate(phis) for y in phis[i + 1:]) > 0.2:
            break
    fb = synthesis.function(pairs, pivots=((0.0, 0.0), (link[3], 0.0)))
    assert np.allclose(fb.lengths, link, rtol=0, atol=1e-12 * max(link))
    assert fb.residual < 1e-12
    for phi, psi in pairs:
        out = output_angle(*fb.lengths, phi)
        assert abs(math.remainder(out - psi, 2 * math.pi)) < 1e-12
