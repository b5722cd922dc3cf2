"""Other parameters keep the guess's assembly mode: ``with_params``, its solves and sweeps,
and every design of a design table start where the guess's mode goes as the parameters
move from the guess's to theirs (the library's carry_params), never where a Newton from
the guess happens to fall; where that way is blocked they say so.

Each check is against a closed form written here (circle intersections at t = 0: the
quick-return's slider, four-bars at random dimensions, seeded); each fails on a mechgen
that starts from the guess at the new parameters."""
from __future__ import annotations

import math
import os
import warnings

import numpy as np
import pytest

import mechgen
from mechgen.errors import BranchJumpWarning
from mechgen.protocol import JUMP, OK, STATUS_CODE, THROUGH_SINGULAR

from conftest import GENERATED


@pytest.fixture(scope="module")
def qr():
    return mechgen.load(os.path.join(GENERATED, "quick_return.py"), tier="python")


@pytest.fixture(scope="module")
def fourbar():
    return mechgen.load(os.path.join(GENERATED, "fourbar.py"), tier="python")


def qr_slider(L):
    """The quick-return's Th3 and X4 at t = 0 (crank pin at (L, 5)) on the guess's mode:
    the slider to the right of the lever's tip (the seed's X4 = 9.079 at L = 3)."""
    th3 = -math.atan2(L, 5.0)
    tip = 9.0 * np.array([L, 5.0]) / math.hypot(L, 5.0)
    return th3, tip[0] + math.sqrt(25.0 - (10.0 - tip[1]) ** 2)


LONG = np.linspace(1.0, 6.5, 12)     # the guess (X4 = 6) lies nearer the left root from
                                     # longitud 4.45 on: a Newton from it goes there


def test_with_params_keeps_the_quick_returns_slider_on_its_side(qr):
    for L in LONG:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            m = qr.with_params(longitud=float(L))
            s = m.solve(0.0)
            sw = m.sweep(0.0, 0.01, 2)
        th3, x4 = qr_slider(L)
        assert abs(s["Th3"] - th3) < 1e-9 and abs(s["X4"] - x4) < 1e-9, L
        assert abs(sw["X4"][0] - x4) < 1e-9, L


def test_a_design_table_starts_each_design_on_the_guess_s_mode(qr):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")         # designs past 4.45 cannot turn a whole turn
        tab = qr.sweep(0.0, 0.01, 2, params={"longitud": LONG})
    x4 = np.array([qr_slider(L)[1] for L in LONG])
    assert np.abs(tab["X4"][:, 0] - x4).max() < 1e-9
    assert np.all(tab.INFO[:, 0, STATUS_CODE] == OK)
    # the reduction and the listed designs, the same starts
    red = qr.sweep(0.0, 0.01, 2, params={"longitud": LONG}, reduce=["X4"])
    assert np.abs(red.reduced("X4").max - np.maximum(x4, tab["X4"][:, 1])).max() < 1e-12


def test_a_table_from_a_later_time_starts_where_solve_follows_the_motion(qr):
    """The table's first time after the guess's: each design carried at t = 0, then
    followed in time, as with_params(...).solve(t0) goes."""
    Ls = np.array([2.0, 3.0, 4.0, 4.4])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tab = qr.sweep(0.3, 0.35, 3, params={"longitud": Ls})
    for i, L in enumerate(Ls):
        s = qr.with_params(longitud=float(L)).solve(0.3)
        assert np.abs(tab.Q[i, 0] - s.q).max() < 1e-8, L
        assert np.abs(qr.with_params(longitud=float(L)).sweep(0.3, 0.35, 3).Q[0] - s.q).max() \
            < 1e-12


def qr_slider_at(L, t, side):
    """The quick-return's X4 at time t (crank angle 2πt): the slider right (side +1) or
    left (−1) of the lever's tip."""
    pin = np.array([L * math.cos(2 * math.pi * t), 5.0 + L * math.sin(2 * math.pi * t)])
    tip = 9.0 * pin / math.hypot(*pin)
    return tip[0] + side * math.sqrt(25.0 - (10.0 - tip[1]) ** 2)


def test_a_design_s_mechanism_stays_on_the_mode_of_the_table_s_guess(qr):
    """A table given guess= (the slider left of the lever, not the model's right): each
    design's sweep and its mechanism's later solves keep that side, and so does the
    mechanism mech.optimize returns from tables given that guess."""
    Ls = [2.0, 3.0, 3.5]
    tab = qr.sweep(0.0, 0.2, 3, params={"longitud": Ls}, guess={"X4": 2.0})
    for i, L in enumerate(Ls):
        assert abs(tab["X4"][i, 0] - qr_slider_at(L, 0.0, -1)) < 1e-9, L
        m = tab.sweep(i).mechanism
        for t in (0.1, 0.37):
            assert abs(m.solve(t)["X4"] - qr_slider_at(L, t, -1)) < 1e-9, (L, t)
        assert abs(qr.with_params(longitud=L).solve(0.37)["X4"] - qr_slider_at(L, 0.37, 1)) \
            < 1e-9, L                   # without the table's guess: the model's side
    best = qr.optimize(lambda tab: -tab["X4"][:, 0], {"longitud": (2.0, 3.5)}, 0.0, 0.2, 3,
                       guess={"X4": 2.0}, popsize=4, maxiter=2, polish=False, seed=1)
    L = best.params["longitud"]
    assert abs(best.mechanism.solve(0.0)["X4"] - qr_slider_at(L, 0.0, -1)) < 1e-9
    assert abs(-best.fun - qr_slider_at(L, 0.0, -1)) < 1e-9


def fourbar_at_zero(a, b, c, d, th, mode):
    """(Th3, Th4) of the four-bar at crank angle th: B to the left (mode +1) or right (−1)
    of the line from the crank pin A to the rocker's pivot D; None where it cannot
    assemble."""
    A = np.array([a * math.cos(th), a * math.sin(th)])
    D = np.array([d, 0.0])
    v = D - A
    L = math.hypot(*v)
    x = (b * b - c * c + L * L) / (2 * L)
    h2 = b * b - x * x
    if h2 <= 0:
        return None
    u = v / L
    B = A + x * u + mode * math.sqrt(h2) * np.array([-u[1], u[0]])
    return math.atan2(*(B - A)[::-1]), math.atan2(*(B - D)[::-1])


def margin(a, b, c, d, th):
    """How far the four-bar at crank angle th is from a toggle (B on the line AD): 0 at
    one, negative where it cannot assemble."""
    L = math.hypot(d - a * math.cos(th), a * math.sin(th))
    return min(b + c - L, L - abs(b - c)) / (b + c)


def wrapped(x):
    return (x + math.pi) % (2 * math.pi) - math.pi


def test_random_four_bars_carried_to_other_dimensions_keep_their_mode(fourbar):
    """A guess set at random dimensions in a random mode; other dimensions along a way
    that stays away from toggles: the carried configuration is the closed form's in the
    same mode, by the sorted solver and by the full Newton, where a full Newton from the
    guess lands in the other mode at some (counted: the test would not see the
    difference otherwise; the sorted solver's dyad takes its mode from the guess's
    angles, which keep it here)."""
    rng = np.random.default_rng(20261127)
    names = ("a", "b", "c", "d", "theta2")
    checked = flipped = 0
    while checked < 60:
        p0 = np.array([rng.uniform(0.3, 2.0), rng.uniform(1.0, 4.0), rng.uniform(1.0, 4.0),
                       rng.uniform(1.0, 4.0), rng.uniform(-math.pi, math.pi)])
        p1 = p0 * rng.uniform(0.4, 2.5, 5)
        p1[4] = p0[4] + rng.uniform(-2.5, 2.5)
        way = [p0 + s * (p1 - p0) for s in np.linspace(0.0, 1.0, 41)]
        if min(margin(*p) for p in way) < 0.05:
            continue
        mode = rng.choice([-1.0, 1.0])
        th3, th4 = fourbar_at_zero(*p0, mode)
        m0 = fourbar.with_params(**dict(zip(names, p0)))
        a, _, _, _, th = p0
        exact = np.array([0.0, 0.0, th, a * math.cos(th), a * math.sin(th), th3, p0[3], 0.0,
                          th4])
        # a rough guess, as a user gives one: its mode is where Newton takes it at p0
        m0.set_guess(exact + rng.uniform(-0.3, 0.3, 9))
        q0 = m0.solve(0.0).q
        mode = 1.0 if abs(wrapped(q0[5] - fourbar_at_zero(*p0, 1.0)[0])) < 1e-6 else -1.0
        assert abs(wrapped(q0[5] - fourbar_at_zero(*p0, mode)[0])) < 1e-9
        m1 = m0.with_params(**dict(zip(names, p1)))
        want = fourbar_at_zero(*p1, mode)
        for method in ("auto", "full"):
            with warnings.catch_warnings():
                warnings.simplefilter("error")
                q = m1.solve(0.0, method=method).q
            got = (q[m1.state.index["Th3"]], q[m1.state.index["Th4"]])
            assert max(abs(wrapped(g - w)) for g, w in zip(got, want)) < 1e-9, \
                (p0, p1, mode, method)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            tab = m0.sweep(0.0, 0.0, 1, params={k: [v] for k, v in zip(names, p1)},
                           on_fail="ignore")
        assert np.abs(tab.Q[0, 0] - q).max() < 1e-9
        newton = m1.solve(0.0, guess=m0.guess, method="full").q
        flipped += abs(wrapped(newton[m1.state.index["Th3"]] - want[0])) > 1e-6
        checked += 1
    assert flipped >= 3, flipped


def test_a_way_through_parameters_that_do_not_assemble_is_said(fourbar):
    """The crank pointing at the rocker's pivot: a from 1 to 5 passes a = 3, where the
    crank pin sits on the pivot (no assembly for a in (2.5, 3.5)). The mode at a = 5
    cannot be carried there: the solve warns and solves from the guess, the table flags
    the design."""
    m0 = fourbar.with_params(a=1.0, theta2=0.0, omega=0.0)
    m0.set_guess(m0.solve(0.0, guess={"Th3": 1.0, "Th4": 2.0}))
    m1 = m0.with_params(a=5.0)
    with pytest.warns(BranchJumpWarning, match="could not be carried"):
        s = m1.solve(0.0)
    assert s.residual < 1e-9
    with pytest.warns(BranchJumpWarning):
        tab = m0.sweep(0.0, 0.1, 3, params={"a": [1.5, 5.0]})
    assert tab.INFO[0, 0, STATUS_CODE] == OK
    assert tab.INFO[1, 0, STATUS_CODE] in (JUMP, THROUGH_SINGULAR)
    assert tab.status[1] in (JUMP, THROUGH_SINGULAR)


def test_a_table_of_a_model_with_stages_starts_across_a_switch():
    """Stages (a switch at t = 0.5): a table from t = 0.6 starts each design where
    with_params(...).solve(0.6) is (the guess's mode followed across the switch, then
    carried to the design)."""
    m = mechgen.load(os.path.join(GENERATED, "quick_return_stages.py"), tier="python")
    values = [3.0, 3.3, 2.6]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tab = m.sweep(0.6, 0.7, 3, params={"longitud": values})
    for i, L in enumerate(values):
        s = m.with_params(longitud=L).solve(0.6)
        assert np.abs(tab.Q[i, 0] - s.q).max() < 1e-9, L
        assert tab.status[i] == OK
