"""Never the wrong mechanism (issue 20), the fast profile: random mechanisms of every
family of tests/random_families.py (four-bars Grashof and not, near-miss toggles and
narrow lock windows, offset slider-cranks driven by the crank and by the slider, inverted
slider-cranks, six-bars, a geared five-bar, a disc cam on a roller arm), swept at every
level and method, single-solved at random times with and without a guess, in design
tables on the cpu and dask backends and on numba's CUDA simulator, each point judged
against a closed form written in the test (tests/random_checks.py): a point with status
OK on another assembly mode, or past a lock window, fails.

hypothesis draws seeds (derandomize=True: the same mechanisms every run); each family is
one parameterised model built once per session and run on the plain-Python tier (the
same generated text as numba's, the same numbers: tests/test_tiers.py; ~100 s of CPU less
than compiling the seven modules); the dask workers and the CUDA simulator's kernels still
compile the file. The long profile is benchmarks/random_mechanisms.py (the same checks,
>= 10,000 mechanisms, compiled). Run with -s to see the counts.

On the code this suite was written against, these fail (issue 20): the issue's
slider-driven slider-crank; single solves with a guess whose angles are wrapped to
(-pi, pi] (method "full"; every method for the geared five-bar); solves without a guess
(not continued from the start); coarse sweeps of slider-cranks that step over a lock
window (methods "sorted" and "auto")."""
import json
import math
import os
import subprocess
import sys
from collections import Counter

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

import random_checks as rc
import random_families
from conftest import ROOT, cuda_sim_env
from random_families import FAMILIES, FOURBAR, SliderDriven

random_families.TIER = "python"         # (see the docstring)

COUNTS = Counter()
SETTINGS = settings(max_examples=4, deadline=None, derandomize=True, database=None,
                    phases=(Phase.explicit, Phase.generate),
                    suppress_health_check=list(HealthCheck))
SEEDS = st.integers(0, 2 ** 32 - 1)


@pytest.fixture(scope="module", autouse=True)
def report_counts():
    yield
    print("\nrandom mechanisms (fast profile):\n" + "\n".join(rc.summary(COUNTS)))


def _no_wrong(kind, verdicts):
    wrongs = []
    rc.tally(COUNTS, kind, verdicts, wrongs)
    wrongs += [v.detail for v in verdicts if v.outcome == "crashed"]
    assert not wrongs, "\n".join(wrongs)


# -- the issue's reproducers, exactly -----------------------------------------------------------
def test_issue_slider_driven_slider_crank_coarse_sweep():
    """a = 1, b = 3.2, e = 0.4, x2 - 0.6 sin(2 pi T), the crank at 0.3037 (θ̇ = 14, θ̈ = -913):
    sweep(0, 0.45, 9, level="velocity", guess=solve(0, level="acceleration")) put 8 of 9
    points on the other mode."""
    fam = FAMILIES["slider_driven"]
    p, th2 = SliderDriven.issue_params()
    mech = fam.mech().with_params(**p)
    s = mech.solve(0, level="acceleration")
    assert s["Th2"] == pytest.approx(th2, abs=1e-9)
    sigma = next(m for m in fam.modes()
                 if abs(fam.exact(p, m, np.array([0.0]), 0)[0][0][2] - th2) < 1e-9)
    _, qd, qdd = (a[0] for a in fam.exact(p, sigma, np.array([0.0])))   # the closed form's
    assert abs(qd[2]) > 10 and abs(qdd[2]) > 500                     # (θ̇ 14.02, θ̈ -913)
    assert s["Th2d"] == pytest.approx(qd[2], abs=1e-6)
    assert s["Th2dd"] == pytest.approx(qdd[2], abs=1e-5)
    try:
        sw, raised = mech.sweep(0, 0.45, 9, level="velocity", guess=s), False
    except rc.REFUSALS as err:
        sw, raised = err.sweep, True
    v = rc.judge(fam, p, sw.t, sw.Q, sw.QD, None, sw.status, sigma=sigma, raised=raised,
                 what="issue slider-driven slider-crank")
    _no_wrong("issue/slider_driven", [v])


@SETTINGS
@given(seed=SEEDS)
def test_issue_near_miss_fourbars_at_37_points(seed):
    """b + c = (a + d)(1 + 1.2e-4), never locks: a velocity sweep over a turn at 37 points
    from the exact configuration, and the same as a one-design design table."""
    rng = np.random.default_rng(seed)
    p = FOURBAR.draw(rng, "grashof")
    s = (p["a"] + p["d"]) * (1 + 1.2e-4)
    diff = float(rng.uniform(0, 0.9)) * (p["d"] - p["a"])
    p.update(b=(s + diff) / 2, c=(s - diff) / 2)
    sigma = FOURBAR.modes()[int(rng.integers(2))]
    spec = rc.Spec("fourbar", "nearmiss-1.2e-4", p, sigma, 0.0, FOURBAR.period(p), 37,
                   "velocity", "auto")
    _no_wrong("issue/nearmiss-37 sweep", [rc.run_sweep(FOURBAR, spec)])
    mech = FOURBAR.mech().with_params(**p)
    q0 = FOURBAR.exact(p, sigma, np.array([0.0]), 0)[0][0]
    tab = mech.sweep(0.0, spec.t1, 37, params={"w": [p["w"]]}, guess=q0, level="velocity",
                     on_fail="ignore")
    sw = tab.sweep(0)
    _no_wrong("issue/nearmiss-37 table", [rc.judge(
        FOURBAR, p, sw.t, sw.Q, sw.QD, None, sw.status, sigma=sigma,
        raised=int(tab.done[0]) < 37, what=f"{spec} one-design table")])


# -- the long profile's last wrong answers (seed 100), exactly ----------------------------------
GEARED_100 = dict(r1=1.19713179963806, r2=3.59139539891418, be=-2.2946012684431145,
                  cph=0.685391593104179, a1=0.7225782573574897, a2=1.4123402751294927,
                  l1=7.421827383358391, l2=4.654509399208768, th0=2.5445378269426087,
                  w=-10.79824107478333)


def test_long_profile_geared_wrapped_guesses():
    """A guess near the mode at t, angles wrapped to (-pi, pi]: the gear's rolling row
    changed by exactly one driver's turn when gear 1 turned by 2 pi (r1/(r1 + r2) = 1/4,
    a quarter turn of the mesh angle, looks linear) and was taken for a driver: gear 1 was
    turned a whole turn off its driver, and Newton meshed gear 2 a third of a turn off
    (Th3 5.048 for -3.329). 0 of 60 may land elsewhere."""
    fam = FAMILIES["geared_fivebar"]
    p = GEARED_100
    mech = fam.mech().with_params(**p)
    rng = np.random.default_rng(5)
    verdicts = []
    for t in (0.10762548569768501, *rng.uniform(-1, 2, 5)):
        here = fam.exact(p, (-1.0,), np.array([t]), 0)[0][0]
        for _ in range(10):
            g = rc.wrap(here + 0.01 * rng.uniform(-1, 1, here.shape), fam.angle_mask)
            s = mech.solve(float(t), guess=g)
            verdicts.append(rc.judge(fam, p, [t], s.q[None], sigma=(-1.0,), status=[0],
                                     what=f"geared wrapped guess t={t}"))
    _no_wrong("long/geared wrapped", verdicts)


def test_long_profile_inverted_table_design_past_a_lock():
    """An inverted slider-crank whose crank cannot pass [2.397, 2.772], swept at 7 points:
    point 4 lies 0.002 short of the fold, where the guide turns fast, and the quick path's
    Taylor step leapt over the window onto the configuration past it with the same signs
    (Th3 -12.28 at t = 2.98, status OK). Now det Φ_q's change is limited there too: the
    sweep stops at the lock, naming it."""
    fam = FAMILIES["inverted"]
    p = dict(ox=0.18195950426606416, oy=1.9329721321145426, a=0.5611501410790659,
             e=-1.393161756501745, th0=-2.332018370487136, w=-0.9575468096599912)
    mech = fam.mech().with_params(**p)
    q0 = fam.exact(p, (-1.0,), np.array([0.0]), 0)[0][0]
    for level in ("position", "velocity"):       # (acceleration: the velocity sweep's path)
        with pytest.raises(rc.REFUSALS, match="lock") as err:
            mech.sweep(0, 3.5719723773449354, 7, level=level, method="sorted", guess=q0)
        sw = err.value.sweep
        assert sw.t[-1] < 2.3968
        _no_wrong("long/inverted 7 points", [rc.judge(
            fam, p, sw.t, sw.Q, status=sw.status, sigma=(-1.0,), raised=True,
            what=f"inverted 7 points {level}")])


def test_long_profile_sixbar_first_step_over_a_window():
    """A six-bar whose second dyad cannot assemble for t in about [0.02, 0.11], swept in
    position at 5 points: its first step turns the crank 1.2 rad straight over the window.
    A solver that always finds the far side (a dyad in closed form) landed there in the
    same mode with a determinant of the same size, status OK (long profile, seed 300).
    The sweep must stop at the lock, not pass it; and so must a one-design table."""
    fam = FAMILIES["sixbar"]
    p = dict(d=2.9841376775231647, a=1.390057334701142, b=2.2632701173270853,
             c=2.9474170129120187, th0=1.5817111548201597, w=-7.793372914128042,
             p=0.5983992670255278, q=1.8847723519396546, gx=2.4312773624481396,
             gy=3.5291428618909, f=4.368141471040536, h=1.438935592207744)
    spec = rc.Spec("sixbar", "random", p, (1.0, 1.0), 0.0, 0.6206273122916859, 5,
                   "position", "sorted")
    verdict = rc.run_sweep(fam, spec)
    _no_wrong("long/sixbar window", [verdict])
    assert verdict.outcome == "refused"
    mech = fam.mech().with_params(**p)
    q0 = fam.exact(p, (1.0, 1.0), np.array([0.0]), 0)[0][0]
    tab = mech.sweep(0.0, spec.t1, 5, params={"f": [p["f"]], "q": [p["q"]]}, guess=q0,
                     level="position", on_fail="ignore")
    done = int(tab.done[0])
    _no_wrong("long/sixbar window table", [rc.judge(
        fam, p, tab.t[:done], tab.Q.reshape(-1, len(tab.t), mech.n)[0, :done],
        sigma=(1.0, 1.0), what="sixbar window table")])


# -- every family, level and method: sweeps, single solves, design tables -------------------------
CASES = [(f, meth) for f in FAMILIES for meth in rc.METHODS]


@pytest.mark.parametrize("family,method", CASES)
@SETTINGS
@given(seed=SEEDS)
def test_random_sweeps_stay_on_their_mode(family, method, seed):
    fam = FAMILIES[family]
    rng = np.random.default_rng(seed)
    spec = rc.draw_spec(fam, rng, method=method)
    _no_wrong(f"{family}/{spec.variant}/sweep", [rc.run_sweep(fam, spec)])


@pytest.mark.parametrize("kind", rc.SOLVES)
@pytest.mark.parametrize("family", list(FAMILIES))
@SETTINGS
@given(seed=SEEDS)
def test_random_single_solves_stay_on_their_mode(family, kind, seed):
    """guess: near its mode at t; wrapped: the same, angles in (-pi, pi]; none: after
    set_guess(the exact start) and solve(t0), the mode connected to the start."""
    fam = FAMILIES[family]
    rng = np.random.default_rng(seed)
    spec = rc.draw_spec(fam, rng)
    _no_wrong(f"{family}/solve-{kind}",
              [v for _, v in rc.single_solves(fam, spec, rng, count=3, kinds=(kind,))])


@pytest.mark.parametrize("family", list(FAMILIES))
@settings(SETTINGS, max_examples=2)
@given(seed=SEEDS)
def test_random_design_tables_stay_on_their_mode(family, seed):
    fam = FAMILIES[family]
    rng = np.random.default_rng(seed)
    spec = rc.draw_spec(fam, rng)
    _no_wrong(f"{family}/table", rc.run_table(fam, spec, rng, designs=4))


@pytest.mark.parametrize("family", list(FAMILIES))
@settings(SETTINGS, max_examples=2)
@given(seed=SEEDS)
def test_random_design_tables_carry_the_guess_s_mode(family, seed):
    """Designs far from the guess's dimensions: on the guess's mode where the way there
    keeps clear of toggles (rc.run_carried_table)."""
    fam = FAMILIES[family]
    rng = np.random.default_rng(seed)
    spec = rc.draw_spec(fam, rng)
    _no_wrong(f"{family}/table-carried", rc.run_carried_table(fam, spec, rng, designs=4))


@pytest.mark.parametrize("family,variant", [("fourbar", "nearmiss"), ("fourbar", "lockwin"),
                                            ("slider_crank", "lockwin"), ("inverted", "lockwin")])
@settings(SETTINGS, max_examples=8)
@given(seed=SEEDS)
def test_near_toggles_and_lock_windows_coarse(family, variant, seed):
    """The hard cases: coarse sweeps (7 to 40 points a period, over 1.3 periods) of
    near-miss toggles and of narrow lock windows the crank cannot pass (the right answer
    there: a refusal)."""
    fam = FAMILIES[family]
    rng = np.random.default_rng(seed)
    spec = rc.draw_spec(fam, rng, variant=variant)
    spec.n = int(rng.integers(7, 41))
    spec.t1 = 1.3 * fam.period(spec.params)
    _no_wrong(f"{family}/{variant}/coarse sweep", [rc.run_sweep(fam, spec)])


MIN_ANSWERED = 0.9  # (every family answered 1.0 of its reachable points at 9fb1c2e)


@pytest.mark.parametrize("family", list(FAMILIES))
def test_random_runs_answer_where_their_mode_assembles(family):
    """Refusing is not free: seeded draws of the family, a sweep and two single solves
    each, judged; none wrong or crashed, and of the points each run's mode reaches from
    its start without a lock window (the closed form assembles all the way), at least
    MIN_ANSWERED answered right. A code that refuses every sweep and solve passes every
    other test here (0 wrong)."""
    fam = FAMILIES[family]
    verdicts = []
    for i in range(4):
        rng = np.random.default_rng([40, list(FAMILIES).index(family), i])
        spec = rc.draw_spec(fam, rng)
        verdicts += rc.guarded(spec, lambda: [rc.run_sweep(fam, spec)])
        verdicts += [v for _, v in rc.guarded(spec, lambda: rc.single_solves(fam, spec, rng, 2),
                                              pairs=True)]
    _no_wrong(f"{family}/answered", verdicts)
    assert not [v.detail for v in verdicts if v.outcome == "crashed"]
    right, reach = rc.answered(verdicts)
    assert reach > 0 and right >= MIN_ANSWERED * reach, (right, reach)


# -- the judge itself can fail -------------------------------------------------------------------
def test_the_judge_catches_a_mode_change_and_a_step_over_a_lock():
    """Hand-made sweeps: the other mode with status OK is wrong; flagged it is refused; a
    point past a lock window with status OK is wrong, and the closed form satisfies the
    loop (|C - B| = b, |C - D| = c) so the reference is a four-bar."""
    rng = np.random.default_rng(7)
    FOURBAR.mech()
    p = FOURBAR.draw(rng, "grashof")
    ts = np.linspace(0, FOURBAR.period(p), 9)
    good = FOURBAR.exact(p, (1.0,), ts)
    bad = FOURBAR.exact(p, (-1.0,), ts)
    B = np.stack([good[0][:, 3], good[0][:, 4]], axis=1)
    C = B + p["b"] * np.stack([np.cos(good[0][:, 5]), np.sin(good[0][:, 5])], axis=1)
    D = np.stack([good[0][:, 6], good[0][:, 7]], axis=1)
    assert np.allclose(np.hypot(*(C - D).T), p["c"], atol=1e-12)
    Qd = good[1]
    fd = rc.wrap(FOURBAR.exact(p, (1.0,), ts + 1e-6, 0)[0] - FOURBAR.exact(p, (1.0,), ts - 1e-6, 0)[0],
                 FOURBAR.angle_mask) / 2e-6
    assert np.abs(fd - Qd).max() < 1e-5 * (1 + np.abs(Qd).max())
    assert rc.judge(FOURBAR, p, ts, *good, sigma=(1.0,)).outcome == "right"
    mixed = [np.where(np.arange(9)[:, None] < 5, g, b) for g, b in zip(good, bad)]
    assert rc.judge(FOURBAR, p, ts, *mixed, sigma=(1.0,)).outcome == "wrong"
    status = np.where(np.arange(9) == 5, 6, 0)
    assert rc.judge(FOURBAR, p, ts, *mixed, status=status, sigma=(1.0,)).outcome == "refused"
    shifted = [g.copy() for g in good]
    shifted[0][3, 2] += 2 * math.pi                         # an angle modulo 2 pi: still right
    assert rc.judge(FOURBAR, p, ts, *shifted, sigma=(1.0,)).outcome == "right"
    shifted[0][3, 5] += 1e-6
    assert rc.judge(FOURBAR, p, ts, *shifted, sigma=(1.0,)).outcome == "wrong"
    lw = FOURBAR.draw(np.random.default_rng(3), "lockwin")
    lw["w"] = abs(lw["w"])
    # start half a turn from the window (crank angle g + pi): the crank meets it at 1.0
    ang = math.atan2(math.sin(lw["g"] + math.pi - lw["th0"]), math.cos(lw["g"] + math.pi - lw["th0"]))
    tw = (ang % (2 * math.pi)) / lw["w"]
    ts = tw + np.linspace(0.5, 1.7, 7) * FOURBAR.period(lw)
    ref = FOURBAR.exact(lw, (1.0,), ts)
    at, between = rc.locks_between(FOURBAR, lw, ts, (1.0,))
    assert between.any() and not at.any()
    assert rc.judge(FOURBAR, lw, ts, *ref, sigma=(1.0,)).outcome == "wrong"


# -- backends: dask and numba's CUDA simulator ----------------------------------------------------
@pytest.fixture(scope="module")
def client():
    distributed = pytest.importorskip("distributed")
    cluster = distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                       dashboard_address=None)
    cl = distributed.Client(cluster)
    yield cl
    cl.close()
    cluster.close()


@pytest.mark.parametrize("variant", ["grashof", "nearmiss", "lockwin"])
def test_dask_design_tables_stay_on_their_mode(client, variant):
    rng = np.random.default_rng(11)
    for _ in range(2):
        spec = rc.draw_spec(FOURBAR, rng, variant=variant)
        _no_wrong("fourbar/table-dask", rc.run_table(FOURBAR, spec, rng, designs=3,
                                                    backend="dask", client=client))


def test_cuda_simulator_design_tables_stay_on_their_mode():
    """numba reads NUMBA_ENABLE_CUDASIM when first imported: the tables run in a
    subprocess (tests/random_cuda_sim.py, tiny) and are judged here."""
    env = cuda_sim_env(PYTHONPATH=os.pathsep.join([ROOT, os.path.join(ROOT, "tests")]))
    out = subprocess.run([sys.executable, os.path.join(ROOT, "tests", "random_cuda_sim.py")],
                         env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-3000:]
    runs = json.loads(out.stdout.strip().splitlines()[-1])
    assert len(runs) >= 3
    verdicts = []
    for r in runs:
        if r.get("refused"):
            verdicts.append(rc.Verdict("refused"))
            continue
        for d, pd in enumerate(r["designs"]):
            k = r["done"][d]
            arr = [None if a is None else np.asarray(a, dtype=float)[d, :k]
                   for a in (r["Q"], r["QD"], r["QDD"])]
            verdicts.append(rc.judge(FOURBAR, pd, np.asarray(r["t"])[:k], *arr,
                                     status=np.asarray(r["status"])[d, :k],
                                     raised=k < len(r["t"]), what=f"cuda {r['spec']} design {d}"))
    _no_wrong("fourbar/table-cuda-sim", verdicts)
