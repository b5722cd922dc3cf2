"""The derivatives of a driver's effort with respect to the parameters
(docs/reference/sensitivities.md: a driver effort's derivative on a force solution), against a
closed form written here: an offset slider-crank whose slider alone has mass M and carries a
constant force P along its guide, the crank turned at ω. A power balance gives the crank torque
    τ ω = M ẍ ẋ − P ẋ   →   τ = (M ẍ − P) ẋ / ω,
x(T) the slider's closed-form position; its derivatives in r, l, e, M, P by mpmath."""
import math

import mpmath as mp
import numpy as np
import pytest

import mechgen
from mechgen import Model, T

OMEGA, THETA0 = 2 * math.pi, 0.4
P0 = dict(r=1.0, l=3.5, e=0.6, M=2.5, P=40.0)


def model():
    m = Model("sens_slider_forces")
    r, l, e, M, P = (m.param(k, v) for k, v in P0.items())
    ground = m.ground("ground", points=[(0, 0), (0, e), (1, e)])
    crank = m.body("crank", points=[(0, 0), (r, 0)], guess=(0, 0, 0.4))
    rod = m.body("rod", points=[(0, 0), (l, 0)], guess=(0.9, 0.4, 0.1))
    slider = m.body("slider", points=[(0, 0), (1, 0)], guess=(4.3, 0.6, 0), mass=M,
                    inertia=1.0)
    m.revolute(ground[1], crank[1])
    m.revolute(crank[2], rod[1])
    m.revolute(rod[2], slider[1])
    m.translate(ground.line(2, 3), slider.line(1, 2))
    m.rotation_lock(crank, THETA0 + OMEGA * T, name="crank driver")
    m.force(slider[1], (P, 0), name="push")
    return m


def x_of(t, r, l, e):
    th = THETA0 + OMEGA * t
    return r * mp.cos(th) + mp.sqrt(l * l - (e - r * mp.sin(th)) ** 2)


def torque(t, r, l, e, M, P):
    xd = mp.diff(lambda u: x_of(u, r, l, e), t, 1)
    xdd = mp.diff(lambda u: x_of(u, r, l, e), t, 2)
    return (M * xdd - P) * xd / OMEGA


def torque_p(t, name):
    with mp.workdps(40):
        values = {k: mp.mpf(v) for k, v in P0.items()}

        def f(v):
            return torque(mp.mpf(t), **dict(values, **{name: v}))
        return float(mp.diff(f, values[name]))


@pytest.fixture(scope="module")
def mech(tmp_path_factory):
    return mechgen.compile(model(), outdir=str(tmp_path_factory.mktemp("g")), tier="python")


@pytest.mark.parametrize("t", [0.05, 0.3, 0.71])
def test_the_torque_and_its_derivatives_match_the_closed_form(mech, t):
    s = mech.solve(t, level="dynamic", sensitivities=True)
    with mp.workdps(40):
        ref = float(torque(mp.mpf(t), **{k: mp.mpf(v) for k, v in P0.items()}))
    assert s.driver("crank driver") == pytest.approx(ref, rel=1e-9, abs=1e-9)
    for name in P0:
        got = s.sensitivity("crank driver", name)
        assert got == pytest.approx(torque_p(t, name), rel=1e-8, abs=1e-8), name


def test_a_force_sweep_carries_the_same_derivatives(mech):
    sw = mech.sweep(0.0, 0.9, 7, level="dynamic", sensitivities=["r", "M"])
    got = sw.sensitivity("crank driver", "r")
    for k, t in enumerate(sw.t):
        assert got[k] == pytest.approx(torque_p(float(t), "r"), rel=1e-8, abs=1e-8)


def test_static_efforts_hold_the_rates_at_zero(mech):
    """At level static q̇ = q̈ = 0: τ = −P x_θ, whose derivative in M is 0."""
    s = mech.solve(0.3, level="static", sensitivities=True)
    assert s.sensitivity("crank driver", "M") == 0.0
    with mp.workdps(40):
        def tau(r):
            th = mp.mpf(THETA0 + OMEGA * 0.3)
            return -P0["P"] * mp.diff(
                lambda a: r * mp.cos(a) + mp.sqrt(P0["l"] ** 2 - (P0["e"] - r * mp.sin(a)) ** 2),
                th)
        ref = float(mp.diff(tau, mp.mpf(P0["r"])))
    assert s.sensitivity("crank driver", "r") == pytest.approx(ref, rel=1e-8)
    assert np.isfinite(s.dq_dp).all()
