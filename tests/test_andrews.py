"""Andrews' squeezing mechanism (examples/andrews_squeezer.py, issue 22): released at
rest under its motor torque and spring, integrated to t = 0.03 by mech.simulate, against
the published reference solution of the IVP test set (computed there by PSIDE at
tolerance 1e-14, in Hairer's relative angles), and against the work of the constant
torque (kinetic + potential energy gained = mom × the crank's turn)."""
import os

import numpy as np
import pytest

import mechgen

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# the test set's solution at t = 0.03: β, Θ, γ, Φ, δ, Ω, ε and their rates
REF_Q = [0.1581077119629904e2, -0.1575637105984298e2, 0.4082224013073101e-1,
         -0.5347301163226948, 0.5244099658805304, 0.5347301163226948, 0.1048080741042263e1]
REF_QD = [0.1139920302151208e4, -0.1424379294994111e4, 0.1103291221937134e2,
          0.1929337464421385e2, 0.5735699284790808, -0.1929337464421385e2,
          0.3231791658026955]
BETA0 = -0.0617138900142764496358948458001
MOM = 0.033


def hairer(sw, k, rate=""):
    """Hairer's seven relative angles from the bodies' absolute ones (Th2..Th8)."""
    th = [sw[f"Th{i}{rate}"][k] for i in range(2, 9)]
    return np.array([th[0], th[1] - th[0], th[2], th[3] - th[4], th[4], th[5] - th[6],
                     th[6]])


@pytest.fixture(scope="module")
def squeezer():
    mech = mechgen.load(os.path.join(ROOT, "generated", "andrews_squeezer.py"),
                        tier="compiled")
    return mech, mech.simulate(0.0, 0.03, 31, rtol=1e-10, atol=1e-10)


def test_the_squeezer_reaches_the_published_solution(squeezer):
    mech, sw = squeezer
    assert sw.free == ("11 hold Th2: hold(Th2, -0.06171389001427645)",)  # held by the build
    assert abs(sw["Th2"][0] - BETA0) < 1e-15 and np.all(sw.QD[0] == 0.0)   # from rest
    assert np.abs(hairer(sw, -1) - REF_Q).max() < 2e-8        # |β| ≈ 16: 1e-9 relative
    assert np.abs(hairer(sw, -1, "d") - REF_QD).max() < 2e-6  # |β̇| ≈ 1.1e3


def test_the_squeezer_gains_the_motors_work_and_keeps_its_constraints(squeezer):
    mech, sw = squeezer
    e = sw.energy()["total"]
    work = MOM * (sw["Th2"] - BETA0)
    assert np.abs((e - e[0]) - work).max() <= 1e-8 * work.max()
    r = np.empty(mech.m)
    held = [i for i, lab in enumerate(mech.constraint_labels) if "hold" in lab]
    for k in range(len(sw)):
        mech.module.phi(sw.Q[k], sw.t[k], mech.p, r)
        r[held] = 0.0
        assert np.abs(r).max() < 1e-12        # lengths of a few cm: 1e-10 relative

