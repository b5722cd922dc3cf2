"""RRR dyad blocks (mechgen.compiler.solver.dyads): the four-bar's coupler and rocker solved as a
circle-circle intersection against the same model's Newton block (closed_forms="none")
and against the intersection written out here, at random configurations, in both
assembly modes, where the circles do not meet and across a toggle.

The reference: the rocker pivot D = (d, 0), the crank pin B = a (cos θ2, sin θ2); the
joint C lies b from B and c from D, left of B→D (mode +1) or right of it (mode -1).
"""
import math
import os
import sys

import numpy as np
import pytest

import mechgen
from mechgen.compiler.build import build
from mechgen.model.loader import load_models
from mechgen.protocol import GAVE_UP, OK

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
FOURBAR = os.path.join(ROOT, "examples", "fourbar.py")


@pytest.fixture(scope="module")
def pair(tmp_path_factory):
    """(dyad, newton): the four-bar built with its dyad block and with Newton, as plain
    Python: the same text's numbers without two compiles (~28 s of CPU); numba runs the
    same dyad text in generated/fourbar.py (the ``fourbar`` fixture's tests)."""
    model = load_models(FOURBAR)[0]
    out = tmp_path_factory.mktemp("dyads")
    dyad = mechgen.load(build(model, str(out / "dyad")), tier="python")
    newton = mechgen.load(build(model, str(out / "newton"), closed_forms="none"),
                          tier="python")
    return dyad, newton


def joint(a, b, c, d, th2, mode):
    """C, the coupler's angle and the rocker's (module docstring)."""
    bx, by = a * math.cos(th2), a * math.sin(th2)
    ex, ey = d - bx, by * -1.0
    L = math.hypot(ex, ey)
    along = (b * b - c * c + L * L) / (2 * L)
    h = math.sqrt(b * b - along * along)
    cx = bx + along * ex / L - mode * h * ey / L
    cy = by + along * ey / L + mode * h * ex / L
    return (cx, cy), math.atan2(cy - by, cx - bx), math.atan2(cy, cx - d)


def random_fourbar(rng):
    """Random sides a, b, c, d, crank angle θ2, the parameter vector and |BD|."""
    a, b, c, d = rng.uniform(0.3, 1.0), rng.uniform(1.5, 3.5), rng.uniform(1.5, 3.0), \
        rng.uniform(2.0, 3.5)
    th2 = rng.uniform(-math.pi, math.pi)
    L = math.hypot(d - a * math.cos(th2), a * math.sin(th2))
    return a, b, c, d, th2, np.array([a, b, c, d, th2, 0.0]), L


def guess_near(mech, a, th2, th3, th4, rng, spread):
    """A guess in the mode of (th3, th4), its angles off by up to ``spread``."""
    q = np.zeros(mech.n)
    names = mech.coordinates
    for name, v in (("Th2", th2), ("X3", a * math.cos(th2)), ("Y3", a * math.sin(th2)),
                    ("Th3", th3), ("Th4", th4)):
        q[names.index(name)] = v
    q[names.index("X4")] = mech.p[list(mech.parameters).index("d")]
    for name in ("Th3", "Th4"):
        q[names.index(name)] += rng.uniform(-spread, spread)
    return q


def test_the_plan_names_the_dyad(pair):
    dyad, newton = pair
    doc = dyad.module.__doc__
    assert "Th3, Th4 (RRR dyad at revolute(coupler[2], rocker[2]), sign " in doc
    assert "Newton on Th3, Th4" in newton.module.__doc__


def test_random_configurations_both_modes(pair):
    """The dyad's numbers equal Newton's to 1e-13 and the reference's, in either mode, the
    mode always the guess's."""
    dyad, newton = pair
    rng = np.random.default_rng(20260)
    info = np.zeros(dyad.module.POSITION_INFO_SIZE)
    checked = 0
    while checked < 300:
        a, b, c, d, th2, p, L = random_fourbar(rng)
        if not abs(b - c) + 0.05 < L < b + c - 0.05:
            continue                       # keep away from the toggles (tested below)
        for mode in (1, -1):
            (cx, cy), th3, th4 = joint(a, b, c, d, th2, mode)
            q0 = guess_near(dyad, a, th2, th3, th4, rng, 0.05)
            results = []
            for mech in (dyad, newton):
                q = q0.copy()
                assert mech.module.position_sorted(q, 0.0, p, 1e-12, 1e-12, 50, info) == OK
                results.append(q)
            qd, qn = results
            assert np.abs(qd - qn).max() < 1e-13
            j3, j4 = dyad.coordinates.index("Th3"), dyad.coordinates.index("Th4")
            assert abs(qd[j3] - th3) < 1e-12 and abs(qd[j4] - th4) < 1e-12
            # the joint where the reference puts it
            assert abs(qd[dyad.coordinates.index("X4")] + c * math.cos(qd[j4]) - cx) < 1e-12
            checked += 1


def test_the_position_solve_hands_over_its_reach_margin(pair):
    """position_sorted leaves the dyad's reach margin in info[INFO_REACH], which sweep()
    reads instead of calling reach(): sin² of the angle at the crank pin B between B→D and
    B→C, from the triangle's sides (b, c, |BD|), and reach()'s value at the solution. An
    info vector of POSITION_INFO_SIZE (a caller of the module's own) is not written past
    its end."""
    dyad, _ = pair
    mod = dyad.module
    rng = np.random.default_rng(7)
    buf = np.full(mod.POINT_INFO_SIZE + 2, 7.0)
    for _ in range(50):
        a, b, c, d, th2, p, L = random_fourbar(rng)
        if not abs(b - c) + 0.05 < L < b + c - 0.05:
            continue
        cos_b = (b * b + L * L - c * c) / (2 * b * L)         # the law of cosines at B
        (_, _), th3, th4 = joint(a, b, c, d, th2, 1)
        q = guess_near(dyad, a, th2, th3, th4, rng, 0.05)
        info = np.zeros(mod.POINT_INFO_SIZE)
        assert mod.position_sorted(q, 0.0, p, 1e-12, 1e-12, 50, info) == OK
        assert abs(info[mod.INFO_REACH] - (1.0 - cos_b * cos_b)) < 1e-12
        assert abs(info[mod.INFO_REACH] - mod.reach(q, 0.0, p)) < 1e-12
        q = guess_near(dyad, a, th2, th3, th4, rng, 0.05)
        assert mod.position_sorted(q, 0.0, p, 1e-12, 1e-12, 50,
                                   buf[:mod.POSITION_INFO_SIZE]) == OK
        assert np.all(buf[mod.POSITION_INFO_SIZE:] == 7.0)


def test_the_angles_keep_the_guess_s_turns(pair):
    """An angle guessed a whole turn away comes back there, as Newton's does."""
    dyad, newton = pair
    info = np.zeros(dyad.module.POSITION_INFO_SIZE)
    q0 = np.array(dyad.module.GUESS)
    j3 = dyad.coordinates.index("Th3")
    q0[j3] += 4 * math.pi
    for mech in (dyad, newton):
        q = q0.copy()
        assert mech.module.position_sorted(q, 0.1, dyad.p, 1e-12, 1e-12, 50, info) == OK
        assert 3 * math.pi < q[j3] < 5 * math.pi


def test_no_assembly_gives_up(pair):
    """Circles that do not meet: the dyad gives up (the full Newton takes over) and the
    solve fails as it does with the Newton block, naming the failure."""
    dyad, newton = pair
    info = np.zeros(dyad.module.POSITION_INFO_SIZE)
    p = np.array(dyad.p)
    names = list(dyad.parameters)
    p[names.index("b")], p[names.index("c")] = 1.0, 0.5     # b + c < |B - D| = 2.69
    q = np.array(dyad.module.GUESS)
    assert dyad.module.position_sorted(q, 0.0, p, 1e-10, 1e-10, 50, info) == GAVE_UP
    assert np.all(q == np.array(dyad.module.GUESS))       # q written only on success
    errors = []
    for mech in (dyad, newton):
        with pytest.raises(mechgen.MechgenError) as err:
            mech.with_params(b=1.0, c=0.5).solve(0.0)
        errors.append(type(err.value))
    assert errors[0] is errors[1]


def test_a_toggle_is_met_as_newton_meets_it(pair):
    """A non-Grashof four-bar whose coupler and rocker fold flat at θ2 = θc (|B − D| =
    b + c): the sweep cannot go on past the lock, and says so at the same time with the
    dyad as with Newton; up to it both give the reference's configuration in the first
    point's mode; the quick path of a position sweep keeps that mode to the lock."""
    dyad, newton = pair
    params = dict(a=1.0, b=1.5, c=1.2, d=3.0, theta2=0.0, omega=1.0)
    # |B - D|² = a² + d² - 2ad cos θ2 = (b + c)²: the toggle's crank angle
    tc = math.acos((1.0 + 9.0 - 2.7 ** 2) / 6.0)
    messages, parts = [], []
    for mech in (dyad, newton):
        m = mech.with_params(**params)
        (cx, cy), th3, th4 = joint(1.0, 1.5, 1.2, 3.0, 0.0, 1)
        guess = {"Th2": 0.0, "X3": 1.0, "Y3": 0.0, "Th3": th3, "X4": 3.0, "Y4": 0.0,
                 "Th4": th4}
        with pytest.raises(mechgen.ConvergenceError) as err:
            m.sweep(0.0, 2.0, 801, level="position", guess=guess)
        messages.append(str(err.value))
        ts = np.linspace(0.0, tc - 1e-3, 500)
        sw = m.sweep(None, None, None, times=ts, level="position", guess=guess)
        parts.append(sw)
        ref = np.array([joint(1.0, 1.5, 1.2, 3.0, t, 1)[1:] for t in ts])
        j3, j4 = m.coordinates.index("Th3"), m.coordinates.index("Th4")
        assert np.abs(sw.Q[:, [j3, j4]] - ref).max() < 1e-9
        # the quick path alone: the whole way in the first point's mode
        Q, S = np.zeros((len(ts), m.n)), np.zeros((len(ts), 3), dtype=np.int16)
        z = np.zeros((0, m.n))
        done = m.module.sweep_fast(ts, sw.Q[0].copy(), m.p, 1e-10, 1e-10, 50, Q, z, z, S)
        assert np.abs(Q[:done, [j3, j4]] - ref[:done]).max() < 1e-9
        assert done > 0.9 * len(ts)
    assert abs(parts[0].Q - parts[1].Q).max() < 1e-11
    reached = [float(msg.split("reached t=")[1].split(" ")[0]) for msg in messages]
    assert abs(reached[0] - reached[1]) < 1e-6 and abs(reached[0] - tc) < 1e-3
    assert all("lock (toggle)" in msg for msg in messages)


def test_every_example_and_the_chain_build_their_dyads():
    """Where a two-angle block has the loop form, the plan solves it as a dyad: the
    Strandbeest's three, the four-bars', a chain of 50 four-bars' 50."""
    from mechgen.compiler.solver.plan import make_plan
    sys.path.insert(0, os.path.join(ROOT, "benchmarks"))
    from chain_model import chain
    expect = {"strandbeest.py": 3, "fourbar.py": 1, "fourbar_loop.py": 1,
              "fourbar_joints.py": None}
    for name, count in expect.items():
        model = load_models(os.path.join(ROOT, "examples", name))[0]
        plan = make_plan(model, model.equations())
        dyads = [b for b in plan.blocks if b.method == "dyad_rrr"]
        if count is not None:
            assert len(dyads) == count, name
        assert all(b.sign in (1, -1) for b in dyads)
    model = chain(50)
    plan = make_plan(model, model.equations())
    assert sum(b.method == "dyad_rrr" for b in plan.blocks) == 50


def test_a_solver_in_parts_hands_over_the_smallest_margin(tmp_path):
    """A chain of ten four-bars, its position solver split into parts: info[INFO_REACH]
    is the smallest margin over all parts, that of reach() and of the ten dyads' own
    triangles (sin² of the angle at each crank pin, from the sides b, c, |BD|). Plain tier:
    the same text, no compile."""
    sys.path.insert(0, os.path.join(ROOT, "benchmarks"))
    from chain_model import chain
    mech = mechgen.load(build(chain(10), str(tmp_path)), tier="python")
    mod = mech.module
    assert "def _position_part1(" in open(mod.__file__).read()
    names, info = mech.coordinates, np.zeros(mod.POINT_INFO_SIZE)
    b, c = 2.5, 2.0
    for t in (0.0, 0.3, 0.7):
        q = mech.solve(t).q.copy()
        info[mod.INFO_REACH] = -5.0
        assert mod.position_sorted(q, t, mech.p, 1e-12, 1e-12, 50, info) == OK
        smallest = 1.0
        for k in range(10):
            # the crank pin B: coupler k's origin (body 3k + 3); the rocker's pivot D
            bx, by = q[names.index(f"X{3 * k + 3}")], q[names.index(f"Y{3 * k + 3}")]
            L = math.hypot(3.0 * (k + 1) - bx, by)
            cos_b = (b * b + L * L - c * c) / (2 * b * L)
            smallest = min(smallest, 1.0 - cos_b * cos_b)
        assert abs(info[mod.INFO_REACH] - smallest) < 1e-12
        assert abs(info[mod.INFO_REACH] - mod.reach(q, t, mech.p)) < 1e-12
