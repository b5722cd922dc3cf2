"""Burmester synthesis (mechgen.synthesis, docs/reference/synthesis.md) against references written
here: a known four-bar's coupler poses computed in closed form (complex numbers, the law of cosines
at the crank pin), its two dyads looked for among the solutions; every dyad's circle checked pose by
pose; the number of real Burmester pairs against a multi-start Newton search; the defects against a
brute-force sweep of the crank that follows the coupler pin by continuity; the built model solved at
the four-bar's times against the poses."""
import cmath
import math

import numpy as np
import pytest
from scipy.optimize import fsolve

from mechgen import synthesis

RNG_SEEDS = range(6)


# -- the test's own four-bar ------------------------------------------------------------------
def pins(link, phi, s):
    """Crank pin A and coupler pin B (complex) at crank angle phi, mode s = ±1 (B on the
    side of O4 − A turned by s times the triangle's angle at A); None where it fails."""
    O2, O4, a, b, c = (link[k] for k in ("O2", "O4", "a", "b", "c"))
    A = O2 + a * cmath.exp(1j * phi)
    L = abs(O4 - A)
    k = (b * b + L * L - c * c) / (2 * b * L)
    if not -1 <= k <= 1:
        return None
    B = A + b * cmath.exp(1j * (cmath.phase(O4 - A) + s * math.acos(k)))
    return A, B


def pose_of(link, A, B):
    """The coupler frame (x, y, angle) from its pins: uA, uB are the pins in that frame."""
    uA, uB = link["uA"], link["uB"]
    th = cmath.phase(B - A) - cmath.phase(uB - uA)
    origin = A - cmath.exp(1j * th) * uA
    return (origin.real, origin.imag, th)


def poses_of(link, phis, modes):
    return [pose_of(link, *pins(link, p, s)) for p, s in zip(phis, modes)]


def random_crank_rocker(rng):
    """A Grashof crank-rocker (the crank the shortest link) placed and turned at random,
    its coupler frame at a random place on the coupler."""
    while True:
        a = rng.uniform(0.5, 1.0)
        b, c, d = rng.uniform(1.5, 3.5, size=3)
        if a + max(b, c, d) < sum((b, c, d)) - max(b, c, d) - 0.3:
            break
    O2 = complex(*rng.normal(size=2))
    O4 = O2 + d * cmath.exp(1j * rng.uniform(-math.pi, math.pi))
    uA = complex(*rng.normal(size=2))
    uB = uA + b * cmath.exp(1j * rng.uniform(-math.pi, math.pi))
    return dict(O2=O2, O4=O4, a=a, b=b, c=c, uA=uA, uB=uB)


def xy(z):
    return np.array([z.real, z.imag])


def has_dyad(dyads, fixed, moving, tol):
    return any(np.allclose(d.fixed, xy(fixed), atol=tol) and
               np.allclose(d.moving, xy(moving), atol=tol) for d in dyads)


def distances(poses, fixed, moving):
    out = []
    for x, y, th in poses:
        P = complex(x, y) + cmath.exp(1j * th) * complex(*moving)
        out.append(abs(P - complex(*fixed)))
    return np.array(out)


def equations(v, poses):
    r = distances(poses, v[:2], v[2:]) ** 2
    return r[1:] - r[0]


def newton_count(poses, rng, starts=300):
    """Real Burmester pairs found by Newton (scipy's fsolve) from random starts."""
    found = []
    for _ in range(starts):
        v, _, ok, _ = fsolve(equations, rng.normal(scale=3, size=4), args=(poses,),
                             full_output=True, xtol=1e-13)
        if ok == 1 and np.max(np.abs(equations(v, poses))) < 1e-9 and \
                np.linalg.norm(v) < 1e4 and not any(np.allclose(v, w, atol=1e-6) for w in found):
            found.append(v)
    return found


# -- five poses -------------------------------------------------------------------------------
@pytest.mark.parametrize("seed", RNG_SEEDS)
def test_five_poses_give_back_the_four_bars_dyads(seed):
    rng = np.random.default_rng(seed)
    link = random_crank_rocker(rng)
    phis = np.sort(rng.uniform(0, 2 * math.pi, size=5))
    poses = poses_of(link, phis, [1] * 5)
    dyads = synthesis.dyads(poses)
    assert has_dyad(dyads, link["O2"], link["uA"], 1e-9)
    assert has_dyad(dyads, link["O4"], link["uB"], 1e-9)
    assert len(dyads) in (2, 4)
    for d in dyads:
        assert d.kind == "RR"
        r = distances(poses, d.fixed, d.moving)
        assert np.max(np.abs(r - r[0])) <= 1e-10 * max(1.0, r[0])


@pytest.mark.parametrize("seed", range(4))
def test_the_count_of_real_burmester_pairs_agrees_with_a_newton_search(seed):
    rng = np.random.default_rng(100 + seed)
    poses = np.column_stack([rng.normal(size=5), rng.normal(size=5),
                             rng.uniform(-1.5, 1.5, size=5)])
    exact = synthesis.dyads(poses)
    searched = newton_count(poses, rng)
    assert len(exact) % 2 == 0 and len(exact) <= 4
    for v in searched:                       # every pair Newton finds is among the exact ones
        assert has_dyad(exact, complex(*v[:2]), complex(*v[2:]), 1e-7)
    for d in exact:
        r = distances(poses, d.fixed, d.moving)
        assert np.max(np.abs(r - r[0])) <= 1e-10 * max(1.0, r[0])
    assert len(searched) <= len(exact)


def test_a_slider_cranks_coupler_asks_for_a_slider():
    """The coupler of an offset slider-crank: its slider pin's positions lie on the guide."""
    poses = []
    for phi in (0.2, 0.9, 1.7, 2.6, 3.5):
        A = cmath.exp(1j * phi)
        B = complex(A.real + math.sqrt(9 - (A.imag - 0.3) ** 2), 0.3)
        poses.append((A.real, A.imag, cmath.phase(B - A)))
    dyads = synthesis.dyads(poses)
    assert has_dyad(dyads, 0j, 0j, 1e-9)                 # the crank
    pr = [d for d in dyads if d.kind == "PR"]
    assert len(pr) == 1
    assert np.allclose(pr[0].moving, (3, 0), atol=1e-9)
    assert abs(pr[0].fixed[1] - 0.3) < 1e-9 and abs(pr[0].direction[1]) < 1e-9
    assert pr[0].residual < 1e-12


# -- four and three poses ---------------------------------------------------------------------
def compatibility(poses, G):
    """det of the three equal-distance equations, linear in the moving pivot (u, 1), built
    here from |P_j − G|² − |P_1 − G|² evaluated at three body points."""
    def f(u):
        return equations(np.concatenate([G, u]), poses)
    c = f(np.zeros(2))
    M = np.column_stack([f(np.array([1.0, 0])) - c, f(np.array([0, 1.0])) - c, c])
    return np.linalg.det(M) / np.abs(M).max() ** 3


def test_four_poses_sample_the_centre_point_curve():
    rng = np.random.default_rng(11)
    link = random_crank_rocker(rng)
    poses = poses_of(link, [0.3, 1.1, 2.0, 3.3], [1] * 4)
    dyads = synthesis.dyads(poses, samples=25)
    assert len(dyads) == 25
    for d in dyads:
        assert abs(compatibility(poses, np.array(d.fixed))) < 1e-10
        r = distances(poses, d.fixed, d.moving)
        assert np.max(np.abs(r - r[0])) <= 1e-10 * max(1.0, r[0])
    assert abs(compatibility(poses, xy(link["O2"]))) < 1e-10       # the hidden pivots are on it
    chosen = synthesis.dyads(poses, fixed=[xy(link["O2"]), xy(link["O4"])])
    assert np.allclose(chosen[0].moving, xy(link["uA"]), atol=1e-9)
    assert np.allclose(chosen[1].moving, xy(link["uB"]), atol=1e-9)
    with pytest.raises(ValueError, match="centre-point curve"):
        synthesis.dyads(poses, fixed=[xy(link["O2"]) + 0.1])


def test_three_poses_a_family_and_any_chosen_pivot():
    rng = np.random.default_rng(12)
    link = random_crank_rocker(rng)
    poses = poses_of(link, [0.3, 1.4, 2.2], [1] * 3)
    dyads = synthesis.dyads(poses, samples=30)
    assert len(dyads) == 30
    for d in dyads:
        r = distances(poses, d.fixed, d.moving)
        assert np.max(np.abs(r - r[0])) <= 1e-10 * max(1.0, r[0])
    by_fixed = synthesis.dyads(poses, fixed=[xy(link["O4"])])[0]
    assert np.allclose(by_fixed.moving, xy(link["uB"]), atol=1e-9)
    by_moving = synthesis.dyads(poses, moving=[xy(link["uA"])])[0]
    assert np.allclose(by_moving.fixed, xy(link["O2"]), atol=1e-9)


@pytest.mark.parametrize("poses, culprit", [
    ([(0, 0, 0), (1, 0, 0.2)], "at least 3"),
    ([(0, 0, 0), (1, 0, 0.2), (0, 0, 0)], "pose 3 repeats pose 1"),
    ([(0, 0, 0), (1, 0, 0.2), (1, float("nan"), 0.4)], "pose 3 has a non-finite y"),
    ([(0, 0, 0), (1, 0, 0.2), (1, 1, 0.4), (2, 1, 0.1), (3, 0, 0.5), (3, 1, 0.7)], "at most 5"),
    ([(0, 0, 0), (1, 0), (1, 1, 0.4)], "pose 2"),
])
def test_bad_poses_are_named(poses, culprit):
    with pytest.raises(ValueError, match=culprit):
        synthesis.dyads(poses)
    with pytest.raises(ValueError, match=culprit):
        synthesis.fourbars(poses)


# -- defects against a brute-force sweep ------------------------------------------------------
def brute_force(link, poses, modes, steps=20000):
    """The defects found by turning the crank from pose 1 both ways in small steps, the
    coupler pin followed by continuity (the nearer of the two closures), until the loop
    will not close or a whole turn is done; a pose is reached where the coupler frame
    passes through it."""
    phi1 = cmath.phase(complex(*pose_pin(link, poses[0])) - link["O2"])
    A0, start = pins(link, phi1, modes[0])
    hits = {}
    full = True
    for way in (1, -1):
        B = start
        prev = np.array(pose_of(link, A0, start))
        for k in range(1, steps + 1):
            t = 2 * math.pi * k / steps
            cands = [p for s in (1, -1) if (p := pins(link, phi1 + way * t, s)) is not None]
            if not cands:
                full = False
                break
            A, B = min(cands, key=lambda p: abs(p[1] - B))
            here = np.array(pose_of(link, A, B))
            for j, p in enumerate(poses[1:], start=1):
                if (way, j) not in hits and _passes(prev, here, p):
                    hits[(way, j)] = t
            prev = here
    found = set()
    sigma = [np.sign(_cross(link, p)) for p in poses]
    if len(set(sigma)) > 1:
        found.add("circuit")
    reach = {0: (0.0, 0.0)}
    for j in range(1, len(poses)):
        if sigma[j] != sigma[0]:
            continue
        if (1, j) in hits or (-1, j) in hits:
            reach[j] = (hits.get((1, j), math.inf), hits.get((-1, j), math.inf))
        else:
            found.add("branch")
    order = sorted(reach)
    if full:
        ok = any(all(reach[i][w] < reach[j][w] for i, j in zip(order, order[1:]))
                 for w in (0, 1))
    else:
        x = [r[0] if r[0] < math.inf else -r[1] for r in (reach[j] for j in order)]
        ok = all(np.diff(x) > 0) or all(np.diff(x) < 0)
    if not ok:
        found.add("order")
    return found


def pose_pin(link, pose):
    return xy(complex(pose[0], pose[1]) + cmath.exp(1j * pose[2]) * link["uA"])


def _cross(link, pose):
    z = complex(pose[0], pose[1])
    A = z + cmath.exp(1j * pose[2]) * link["uA"]
    B = z + cmath.exp(1j * pose[2]) * link["uB"]
    u, v = A - B, link["O4"] - B
    return u.real * v.imag - u.imag * v.real


def _passes(prev, here, p):
    """Whether the coupler frame went through pose p between two steps of the sweep."""
    span = np.linalg.norm(here - prev) + 1e-12
    d1, d2 = np.linalg.norm(prev - p), np.linalg.norm(here - p)
    return d1 + d2 <= span * (1 + 1e-6) + 1e-9 or min(d1, d2) < 1e-9


def the_four_bar(link, poses):
    return synthesis.four_bar((xy(link["O2"]), xy(link["uA"])),
                              (xy(link["O4"]), xy(link["uB"])), poses)


def two_arc_linkage():
    """a = 1, d = 1.5, b = 1, c = 0.3: the crank pin closes the loop on two separate arcs."""
    return dict(O2=0j, O4=1.5 + 0j, a=1.0, b=1.0, c=0.3, uA=0j, uB=1.0 + 0j)


@pytest.mark.parametrize("case, expected", [
    ("ordered", set()),
    ("two modes", {"circuit"}),
    ("out of order", {"order"}),
    ("two arcs", {"branch"}),
    ("rocker out of order", {"order"}),
])
def test_defects_agree_with_a_brute_force_sweep(case, expected):
    rng = np.random.default_rng(21)
    link = random_crank_rocker(rng)
    if case == "ordered":
        phis, modes = [0.2, 1.0, 2.1, 3.0, 4.4], [1] * 5
    elif case == "two modes":
        phis, modes = [0.2, 1.0, 2.1, 3.0, 4.4], [1, 1, -1, 1, 1]
    elif case == "out of order":
        phis, modes = [0.2, 2.1, 1.0, 3.0, 4.4], [1] * 5
    else:
        link = two_arc_linkage()
        # the arcs: |A − O4| in [0.7, 1.3], cos phi in [0.52, 0.92]: ±(0.40 .. 1.02) rad
        phis = [0.6, 0.8, -0.7, 0.9] if case == "two arcs" else [0.6, 0.9, 0.7, 0.8]
        modes = [1] * 4
    poses = poses_of(link, phis, modes)
    link4 = the_four_bar(link, poses)
    assert set(link4.defects) == expected
    assert brute_force(link, poses, modes) == expected


@pytest.mark.parametrize("seed", range(8))
def test_defects_of_random_poses_agree_with_the_brute_force(seed):
    rng = np.random.default_rng(300 + seed)
    link = random_crank_rocker(rng) if seed % 2 else two_arc_linkage()
    phis, modes = [], []
    while len(phis) < 4:
        phi, s = rng.uniform(-math.pi, math.pi), int(rng.choice([1, 1, 1, -1]))
        if pins(link, phi, s) is not None:
            phis.append(phi)
            modes.append(s)
    poses = poses_of(link, phis, modes)
    assert set(the_four_bar(link, poses).defects) == brute_force(link, poses, modes, 8000)


def test_transmission_and_grashof_against_a_sweep():
    rng = np.random.default_rng(5)
    link = random_crank_rocker(rng)
    phis = [0.2, 1.0, 2.1, 3.0]
    poses = poses_of(link, phis, [1] * 4)
    fb = the_four_bar(link, poses)
    assert fb.grashof == "crank-rocker" and not fb.defects
    assert np.allclose(fb.lengths, (link["a"], link["b"], link["c"], abs(link["O4"] - link["O2"])))
    phi1 = cmath.phase(complex(*pose_pin(link, poses[0])) - link["O2"])
    mus = []
    for t in np.linspace(0, fb.times[-1], 20001):
        A, B = pins(link, phi1 + fb.direction * t, 1)
        mus.append(math.degrees(abs(cmath.phase((A - B) / (link["O4"] - B)))))
    assert fb.transmission[0] == pytest.approx(min(mus), abs=1e-3)
    assert fb.transmission[1] == pytest.approx(max(mus), abs=1e-3)
    assert synthesis.grashof((1, 3, 2.5, 3.2)) == "crank-rocker"
    assert synthesis.grashof((2, 3, 2.5, 1)) == "drag-link"
    assert synthesis.grashof((2, 1, 2.5, 3)) == "double-rocker"
    assert synthesis.grashof((1, 3, 1.2, 1.5)) == "triple-rocker"
    assert synthesis.grashof((1, 2, 1, 2)) == "change-point"


def test_fourbars_of_five_poses_hold_the_defect_free_original():
    rng = np.random.default_rng(3)
    link = random_crank_rocker(rng)
    poses = poses_of(link, [0.3, 1.0, 1.8, 2.9, 4.0], [1] * 5)
    links = synthesis.fourbars(poses)
    assert links and not links[0].defects
    mine = [f for f in links if np.allclose(f.input.fixed, xy(link["O2"]), atol=1e-9)
            and np.allclose(f.output.fixed, xy(link["O4"]), atol=1e-9)]
    assert len(mine) == 1 and not mine[0].defects
    assert np.allclose(mine[0].times, np.array([0.3, 1.0, 1.8, 2.9, 4.0]) - 0.3, atol=1e-9)


# -- the model --------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def built(tmp_path_factory):
    import mechgen
    rng = np.random.default_rng(8)
    link = random_crank_rocker(rng)
    phis = [0.5, 1.3, 2.2, 3.6, 5.0]
    poses = poses_of(link, phis, [-1] * 5)
    fb = [f for f in synthesis.fourbars(poses)
          if np.allclose(f.input.fixed, xy(link["O2"]), atol=1e-9)][0]
    mech = mechgen.compile(fb.model(), outdir=str(tmp_path_factory.mktemp("burmester")),
                           tier="python")
    return fb, poses, mech


def test_the_model_puts_the_coupler_frame_at_every_pose(built):
    fb, poses, mech = built
    assert not fb.defects
    k = mech.coordinates.index("X3")
    assert mech.coordinates[k:k + 3] == ("X3", "Y3", "Th3")
    for t, pose in zip(fb.times, poses):
        s = mech.solve(t)
        assert abs(s["X3"] - pose[0]) < 1e-9 and abs(s["Y3"] - pose[1]) < 1e-9
        assert abs(math.remainder(s["Th3"] - pose[2], 2 * math.pi)) < 1e-9
