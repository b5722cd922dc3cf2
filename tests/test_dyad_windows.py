"""Blocks solved whatever their guess (RRR dyads, sign-picked circle-line and trig closed
forms) swept coarsely over stretches where they cannot assemble (issue 24's revert: a
dyad in closed form finds the far side of such a stretch in the same mode, with a
determinant of the same size, as readily as the near side).

Seeded numpy draws of the families of tests/random_families.py with a narrow lock window
(a four-bar whose coupler and rocker cannot reach about crank angle g + pi: an RRR dyad;
an offset slider-crank whose rod cannot reach the guide: a circle-line form; a six-bar
whose second dyad locks), swept at both assembly modes from the exact start:
- with two points placed symmetrically about the window's centre, so that the step
  between them lands on a margin as large as the one it left (the case a test on the
  margin's or the determinant's change alone passes);
- on coarse grids at random offsets, at level position and acceleration;
- as one-design tables.
Every point with status OK is judged against the family's closed form written in the
tests (random_checks.judge): on its mode and not past a window. A refusal is right."""
import math

import numpy as np
import pytest

import random_checks as rc
import random_families
from random_families import FAMILIES

# the families on the plain-Python tier: the generated text judged point by point, without
# numba compiling three modules (~45 s of CPU; the same numbers: tests/test_tiers.py)
random_families.TIER = "python"

SEED = 2024
CASES = 10          # draws per family and kind


def _window_centre(fam, p, sigma):
    """A time inside the family's lock window nearest t = 0 (None where the grid finds
    none within a period), from the closed form's discriminant."""
    per = fam.period(p)
    ts = np.linspace(0.0, per, 4001)
    d = fam.disc(p, ts, sigma)
    inside = np.flatnonzero(d < 0)
    if inside.size == 0 or inside.size == ts.size:
        return None, 0.0
    # the first run of negative discriminant: its middle and width
    start = inside[0]
    stop = start
    while stop + 1 < ts.size and d[stop + 1] < 0:
        stop += 1
    return 0.5 * (ts[start] + ts[stop]), ts[stop] - ts[start] + (ts[1] - ts[0])


def _draws(family, variant, rng):
    fam = FAMILIES[family]
    out = []
    for _ in range(200):
        if len(out) == CASES:
            break
        spec = rc.draw_spec(fam, rng, variant=variant)
        centre, width = _window_centre(fam, spec.params, spec.sigma)
        if centre is not None:
            out.append((spec, centre, width))
    return out


KINDS = [("fourbar", "lockwin"), ("slider_crank", "lockwin"), ("sixbar", "random")]


MIN_ANSWERED = 0.8  # of the points before a window (answered 1.0 at 9fb1c2e: no toggle)


def _no_wrong(verdicts):
    """No point wrong, no run crashed, and a refusal only where it is due: of the points
    each run's mode reaches from its start before the window (rc.answered), at least
    MIN_ANSWERED answered right (a code refusing every sweep passed without it)."""
    wrong = [v.detail for v in verdicts if v.outcome in ("wrong", "crashed")]
    assert not wrong, "\n".join(wrong)
    right, reach = rc.answered(verdicts)
    assert reach > 0 and right >= MIN_ANSWERED * reach, (right, reach)


@pytest.mark.parametrize("family,variant", KINDS)
def test_symmetric_step_over_a_window(family, variant):
    """Two points symmetric about the window's centre, with 0 to 3 points before them:
    the step between them lands where the margin is what it left."""
    fam = FAMILIES[family]
    rng = np.random.default_rng([SEED, KINDS.index((family, variant))])
    verdicts = []
    for spec, centre, width in _draws(family, variant, rng):
        step = width * float(rng.uniform(1.2, 12.0))
        before = int(rng.integers(0, 4))
        t0 = centre - (before + 0.5) * step
        if fam.disc(spec.params, np.array([t0]), spec.sigma)[0] <= 1e-9:
            continue            # the start itself does not assemble on this mode
        for level in ("position", "acceleration"):
            for method in ("sorted", "auto"):
                s = rc.Spec(family, variant, spec.params, spec.sigma, t0,
                            t0 + (before + 1) * step, before + 2, level, method)
                verdicts.append(rc.run_sweep(fam, s))
    assert verdicts
    _no_wrong(verdicts)


@pytest.mark.parametrize("family,variant", KINDS)
def test_coarse_sweeps_and_tables_over_a_window(family, variant):
    """Coarse grids (2 to 12 points a period) at random offsets over the window, both
    modes drawn, in sweeps at level position and acceleration and in one-design tables."""
    fam = FAMILIES[family]
    rng = np.random.default_rng([SEED + 1, KINDS.index((family, variant))])
    verdicts = []
    for spec, centre, width in _draws(family, variant, rng):
        per = fam.period(spec.params)
        n_turn = float(rng.uniform(2.0, 12.0))
        span = per * float(rng.uniform(0.5, 1.5))
        n = max(2, int(round(n_turn * span / per)) + 1)
        for level in ("position", "acceleration"):
            s = rc.Spec(family, variant, spec.params, spec.sigma, 0.0, span, n, level,
                        "sorted")
            verdicts.append(rc.run_sweep(fam, s))
        mech = fam.mech().with_params(**spec.params)
        q0 = fam.exact(spec.params, spec.sigma, np.array([0.0]), 0)[0][0]
        name = fam.params[0]
        tab = mech.sweep(0.0, span, n, params={name: [spec.params[name]]}, guess=q0,
                         level="position", on_fail="ignore")
        done = int(tab.done[0])
        verdicts.append(rc.judge(fam, spec.params, tab.t[:done],
                                 tab.Q.reshape(-1, len(tab.t), mech.n)[0, :done],
                                 sigma=spec.sigma, what=f"table {s}", planned=tab.t,
                                 t0=0.0))
    assert verdicts
    _no_wrong(verdicts)


def test_the_window_centre_is_found():
    """The helper finds the four-bar's window where the closed form says (crank angle
    g + pi), so that the tests above straddle it."""
    rng = np.random.default_rng(SEED)
    spec, centre, width = _draws("fourbar", "lockwin", rng)[0]
    p = spec.params
    th = p["th0"] + p["w"] * centre
    assert abs(math.remainder(th - p["g"] - math.pi, 2 * math.pi)) < 0.5 * abs(p["w"]) * width + 1e-3
