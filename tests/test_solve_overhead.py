"""A single solve made cheaper in Python keeps its numbers and its arrays (the per-call
overhead of mech.solve; benchmarks/bench_solve_overhead.py times it).

Each Solution owns its arrays: mutating one never changes another, the mechanism's later
solves or its way kept (mechgen.runtime.kinematics.follow). Numbers, at every level, against values
made here: the quick-return's closed form (tests/closed_forms.py, mpmath), and bit for
bit the documented algorithm written out with the generated module's own entry points
(Newton from the guess at t, then the derivative passes and the multipliers; without a
guess, the careful sweep from the guess's time over the cells of CELL and the last step
to t, then Newton at t) — never the runtime code that was changed."""
from __future__ import annotations

import math
import os

import numpy as np
import pytest

import mechgen
from mechgen.protocol import (INFO_ITERATIONS, INFO_METHOD, INFO_RANK, OK, POINT_INFO_SIZE,
                              POINT_PIVOT, POINT_RESIDUAL, REPORT_SIZE, SING_RTOL,
                              STATUS_COLUMNS)

from closed_forms import motion, quick_return
from conftest import GENERATED

TIMES = (0.0, 0.0625, 0.3, 0.37, 0.731, 0.97)


def _load(name):
    return mechgen.load(os.path.join(GENERATED, name + ".py"), tier="compiled")


@pytest.fixture(scope="module")
def quick():
    return _load("quick_return")


def _arrays(s):
    return [a for a in (s.q, s.qd, s.qdd, getattr(s, "lam", None), getattr(s, "_terms", None))
            if a is not None]


def _snapshot(s):
    return [a.copy() for a in _arrays(s)]


def _same(s, saved):
    now = _arrays(s)
    return len(now) == len(saved) and all(a.tobytes() == b.tobytes() for a, b in zip(now, saved))


# -- each Solution owns its arrays ---------------------------------------------------------
@pytest.mark.parametrize("name, level", [("quick_return", "position"),
                                         ("quick_return", "velocity"),
                                         ("quick_return", "acceleration"),
                                         ("quick_return_forces", "dynamic"),
                                         ("quick_return_forces", "static"),
                                         ("press_motor", "dynamic"),
                                         ("press_motor", "static")])
def test_successive_solves_return_independent_arrays(name, level):
    mech = _load(name)
    g = mech.guess.copy()
    # the same time twice (the way's last configuration), a new time (the last step's
    # scratch), a guess twice (Newton's scratch)
    sols = [mech.solve(0.3, level=level), mech.solve(0.3, level=level),
            mech.solve(0.41, level=level), mech.solve(0.3, level=level, guess=g),
            mech.solve(0.3, level=level, guess=g)]
    for i, a in enumerate(sols):
        for b in sols[i + 1:]:
            for x in _arrays(a):
                assert not any(np.shares_memory(x, y) for y in _arrays(b))
    saved = [_snapshot(s) for s in sols]
    for s in sols[::2]:                 # mutate some: the others and later solves keep theirs
        for x in _arrays(s):
            x[...] = np.nan
    for s, keep in zip(sols[1::2], saved[1::2]):
        assert _same(s, keep)
    again = mech.solve(0.3, level=level)
    assert _same(again, saved[1])
    assert _same(mech.solve(0.41, level=level), saved[2])
    assert np.array_equal(mech.guess, g)
    if level in ("dynamic", "static"):
        driver = next(label for _, kind, label, _, drives in mech.module.CONSTRAINTS if drives)
        assert again.driver(driver) == sols[1].driver(driver)


def test_a_solution_keeps_its_arrays_through_later_solves(quick):
    s = quick.solve(0.2, level="acceleration")
    keep = _snapshot(s)
    for t in np.linspace(0.0, 1.0, 50):
        quick.solve(t, level="acceleration")
        quick.solve(t, level="acceleration", guess=s)
    assert _same(s, keep)
    assert quick.last is not s


# -- the numbers: closed forms -------------------------------------------------------------
@pytest.mark.parametrize("t", TIMES)
def test_quick_return_solve_at_every_kinematic_level_is_the_closed_form(quick, t):
    q, qd, qdd = motion(quick_return, t)
    for level in ("position", "velocity", "acceleration"):
        for s in (quick.solve(t, level=level), quick.solve(np.float64(t), level=level),
                  quick.solve(t, level=level, guess=quick.guess)):
            assert np.abs(s.q - q).max() <= 1e-12
            if level != "position":
                assert np.abs(s.qd - qd).max() <= 1e-10 * (1 + np.abs(qd).max())
            if level == "acceleration":
                assert np.abs(s.qdd - qdd).max() <= 1e-9 * (1 + np.abs(qdd).max())


# -- the numbers: bit for bit the module's entry points ------------------------------------
def _newton(mech, q, t):
    """Newton at t from q (in place) by the module's sorted solver: its info row."""
    info = np.zeros(POINT_INFO_SIZE)
    status = mech.module.solve_point_sorted(q, t, mech.p, mech.tol, mech.xtol, mech.maxit,
                                            info)
    assert status == OK
    return info


def _followed(mech, t):
    """The configuration solve(t) reaches from the model's guess at 0 (follow's docstring):
    the guess solved at 0, one careful sweep over the cells k CELL (k = 0 … the last at or
    before t), then the two-point sweep from that cell to t."""
    from mechgen.runtime.kinematics.follow import CELL
    mod, n = mech.module, mech.n
    q0 = mech.guess.copy()
    _newton(mech, q0, 0.0)
    m = math.floor(t / CELL)
    while m and m * CELL > t:
        m -= 1

    def careful(ts, start):
        Q = np.empty((len(ts), n))
        S = np.zeros((len(ts), STATUS_COLUMNS), dtype=np.int16)
        none = np.empty((0, n))
        done = mod.sweep(ts, start.copy(), mech.p, 0, mech.tol, mech.xtol, mech.maxit, 0,
                         Q, none, none, S, np.zeros(REPORT_SIZE))
        assert done == len(ts) and not S[:, 0].any()
        return Q[-1]

    qc = careful(np.arange(m + 1) * CELL, q0) if m else q0
    return qc.copy() if m * CELL == t else careful(np.array([m * CELL, t]), qc).copy()


def _written_out(mech, q, t, level):
    """(qd, qdd, λ) at the position q: the module's derivative passes and multipliers
    (in the one pass of dynamics_sorted where the module has it; by the blocks written
    out, multipliers_point, or by force_rows)."""
    mod, n = mech.module, mech.n
    qd, qdd, lam = np.empty(n), np.empty(n), np.empty(mech.m)
    if level == "dynamic" and hasattr(mod, "dynamics_sorted"):
        piv = np.zeros(3)
        assert mod.dynamics_sorted(q, t, mech.p, qd, qdd, piv, lam,
                                   np.empty(len(mod.DRIVER_ROWS))) == OK
        assert piv[2] >= SING_RTOL
        return qd, qdd, lam
    if level != "static":
        assert mod.solve_derivatives_sorted(q, t, mech.p, qd, qdd) == OK
    if level in ("position", "velocity", "acceleration"):
        return qd, qdd, None
    if level == "static":
        qd = qdd = np.zeros(n)
    if mod.FORCE_POINT:
        assert mod.multipliers_point(q, qd, qdd, t, mech.p, lam) >= SING_RTOL
        return qd, qdd, lam
    terms, rows, piv = np.zeros((1, 3, n)), np.zeros((1, mech.m)), np.zeros(1)
    mod.force_rows(np.array([t]), q[None], qd[None], qdd[None], mech.p,
                   np.empty((1, mech.m, n)), terms, np.zeros((1, mech.m)), np.zeros((1, 3)),
                   np.zeros((1, len(mod.DRIVER_ROWS))), piv, rows)
    assert piv[0] >= SING_RTOL
    return qd, qdd, rows[0]


def _check_bits(s, mech, q, t, level):
    info = _newton(mech, q, t)
    qd, qdd, lam = _written_out(mech, q, t, level)
    assert s.t == t and s.q.tobytes() == q.tobytes()
    if level in ("velocity", "acceleration", "dynamic"):
        assert s.qd.tobytes() == qd.tobytes()
    if level in ("acceleration", "dynamic"):
        assert s.qdd.tobytes() == qdd.tobytes()
    if level in ("dynamic", "static"):
        assert s.lam.tobytes() == lam.tobytes()
    assert s.iterations == int(info[INFO_ITERATIONS])
    assert s.residual == float(info[POINT_RESIDUAL])
    assert s.method == ("full" if info[INFO_METHOD] else "sorted")
    assert s.singular is (int(info[INFO_RANK]) < mech.n or not info[POINT_PIVOT] >= SING_RTOL)


CASES = [("quick_return", lv) for lv in ("position", "velocity", "acceleration")] + \
        [(name, lv) for name in ("quick_return_forces", "press_motor")
         for lv in ("position", "acceleration", "dynamic", "static")]


@pytest.mark.parametrize("name, level", CASES)
def test_solve_is_bit_for_bit_the_modules_entry_points(name, level):
    base = _load(name)
    g = base.guess + 0.01                          # a guess near the motion at t = 0 …
    for t in TIMES:
        mech = base.with_params()                  # … and a fresh way from the guess
        _check_bits(mech.solve(t, level=level), mech, _followed(mech, t), t, level)
        _check_bits(mech.solve(t, level=level), mech, _followed(mech, t), t, level)   # again
        _check_bits(mech.solve(t, level=level, guess=g), mech, g.copy(), t, level)
    assert mech.solve(0.3, level=level).__class__.__name__ == \
        ("ForceSolution" if level in ("dynamic", "static") else "Solution")


def test_the_usual_arguments_and_the_others_give_the_same_solution(quick):
    """A float t and level name pass by a quick look-up; a numpy float, an int, the method
    and tolerances named, go through the full checks: the same numbers."""
    ref = quick.solve(0.25, level="acceleration")
    for s in (quick.solve(np.float64(0.25), level="acceleration"),
              quick.solve(0.25, level="acceleration", method="auto", tol=quick.tol, maxit=quick.maxit),
              quick.solve(np.float32(0.25), level="acceleration")):
        assert s.q.tobytes() == ref.q.tobytes() and s.qdd.tobytes() == ref.qdd.tobytes()
    assert quick.solve(1, level="velocity").q.tobytes() == quick.solve(1.0).q.tobytes()


@pytest.mark.parametrize("t, message", [(float("nan"), "t must be finite, got nan"),
                                        (np.float64("inf"), "t must be finite, got "),
                                        (float("inf"), "t must be finite, got inf"),
                                        ("x", "t must be a number, got 'x'")])
def test_a_bad_time_is_still_named(quick, t, message):
    with pytest.raises(ValueError, match=message):
        quick.solve(t)
    with pytest.raises(ValueError, match=message):
        quick.solve(t, level="nonsense")           # t is checked first, as before


def test_bad_level_method_and_guess_are_still_named(quick):
    with pytest.raises(ValueError, match="level must be one of"):
        quick.solve(0.1, level="jerk")
    with pytest.raises(ValueError, match="method must be one of"):
        quick.solve(0.1, method="newton")
    bad = quick.with_params()
    bad.method = "newton"                       # an attribute set wrong: named at the solve
    with pytest.raises(ValueError, match="method must be one of"):
        bad.solve(0.1)
    with pytest.raises(ValueError, match="tol must be positive"):
        quick.solve(0.1, tol=-1.0)
    with pytest.raises(ValueError, match="maxit must be a positive integer"):
        quick.solve(0.1, maxit=2.5)
    with pytest.raises(ValueError, match="guess holds NaN or infinite values"):
        quick.solve(0.1, guess=np.full(quick.n, np.inf))
    with pytest.raises(ValueError, match="guess holds NaN or infinite values"):
        quick.solve(0.1, guess=np.r_[np.full(quick.n - 1, 1e300), np.nan])


@pytest.mark.parametrize("name", ["quick_return", "fourbar", "quick_return_slider",
                                  "gear_train", "andrews_squeezer"])
def test_angle_coordinates_are_those_phi_is_periodic_in(name):
    """The coordinates a solve from a guess turns home by whole turns: those Φ takes the
    same values at q and q + 2π e_j, checked here at seeded random configurations."""
    from mechgen.runtime.analysis.assembly import angle_coordinates
    mech = _load(name)
    rng = np.random.default_rng(7)
    r0, r1 = np.empty(mech.m), np.empty(mech.m)
    expected = []
    for j in range(mech.n):
        same = True
        for _ in range(5):
            q = mech.guess + rng.uniform(-2.0, 2.0, mech.n)
            t = float(rng.uniform(0.0, 1.0))
            q2 = q.copy()
            q2[j] += 2 * np.pi
            mech.module.phi(q, t, mech.p, r0)
            mech.module.phi(q2, t, mech.p, r1)
            same &= bool(np.abs(r1 - r0).max() <= 1e-9 * (1 + np.abs(r0).max()))
        if same:
            expected.append(j)
    assert angle_coordinates(mech) == tuple(expected)
    assert angle_coordinates(mech.with_params()) == tuple(expected)
