"""A six-bar (a four-bar plus a dyad) swept into a lock: the sweep stops with a
ConvergenceError that names the lock, at the crank angle where coupler and rocker fall in
line (closed form: a² + d² − 2ad cos θ = (b + c)²), never an AttributeError from the
explanation of the failure."""
import math

import pytest

import mechgen
from mechgen import Model, T, pi
from mechgen.runtime.analysis import locks
from mechgen.runtime.analysis.singular import NullSpace

A, B, C, D, THETA0 = 1.8, 2.5, 2.0, 3.0, 0.3


def six_bar():
    m = Model("sixbar_lock")
    a = m.param("a", A)
    b = m.param("b", B)
    c = m.param("c", C)
    d = m.param("d", D)
    g = m.ground("ground", points=[(0, 0), (d, 0), (d, 2.5)])
    crank = m.body("crank", points=[(0, 0), (a, 0)], guess=(0, 0, 0.3))
    coupler = m.body("coupler", points=[(0, 0), (b, 0)], guess=(1.7, 0.5, 0.6))
    rocker = m.body("rocker", points=[(0, 0), (c, 0)], guess=(3, 0, 1.6))
    link5 = m.body("link5", points=[(0, 0), (2.2, 0)], guess=(3.0, 2.0, 0.5))
    link6 = m.body("link6", points=[(0, 0), (2.0, 0)], guess=(3, 2.5, -0.3))
    m.revolute(g[1], crank[1])
    m.revolute(crank[2], coupler[1])
    m.revolute(g[2], rocker[1])
    m.revolute(coupler[2], rocker[2])
    m.revolute(rocker[2], link5[1])
    m.revolute(g[3], link6[1])
    m.revolute(link5[2], link6[2])
    m.rotation_lock(crank, THETA0 + 2 * pi * T, name="crank angle")
    return m


@pytest.fixture(scope="module")
def mech(tmp_path_factory):
    """On the plain-Python tier: the lock is found and explained in the runtime, from the
    generated text's statuses (the same as numba's: tests/test_tiers.py), without
    compiling the module (~20 s of CPU)."""
    return mechgen.compile(six_bar(), outdir=str(tmp_path_factory.mktemp("sixbar")),
                           tier="python")


def t_lock():
    """The first time the crank reaches the toggle where b and c are in line."""
    cos_theta = (A * A + D * D - (B + C) ** 2) / (2 * A * D)
    return (math.acos(cos_theta) - THETA0) / (2 * math.pi)


@pytest.mark.parametrize("level", ["position", "velocity"])
def test_a_six_bar_swept_into_a_lock_names_the_lock(mech, level):
    with pytest.raises(mechgen.ConvergenceError) as info:
        mech.sweep(0.0, 1.0, 50, level=level)
    err = info.value
    assert err.locks and abs(err.locks[0].t - t_lock()) < 1e-7
    assert "lock (toggle) position" in str(err)
    assert any("revolute(coupler[2], rocker[2])" in c for c in err.constraints)


def test_a_lock_whose_null_space_names_no_single_equation(mech, monkeypatch):
    """The crash of issue 20: the lock's null space holds no constraint acting alone on
    the free coordinates (lock == ()): the explanation falls back to the constraints
    involved (Singularity.grouped) instead of raising AttributeError."""
    real = locks.null_space

    def no_single_lock(*args, **kwargs):
        null = real(*args, **kwargs)
        return NullSpace(null.rank, null.ratio, null.constraints, null.coordinates, (),
                         null.grouped)

    monkeypatch.setattr(locks, "null_space", no_single_lock)
    with pytest.raises(mechgen.ConvergenceError) as info:
        mech.sweep(0.0, 1.0, 50)
    err = info.value
    assert err.locks and abs(err.locks[0].t - t_lock()) < 1e-7
    assert err.locks[0].lock == () and err.constraints == err.locks[0].grouped
    assert "4 revolute(coupler[2], rocker[2])" in err.constraints
