"""Every number seed 001 prints for the quick-return, and seed 000's four-bar, reproduced
from the generated modules."""
import math

import pytest

import mechgen


def close(a, b, digits=6):
    """Mech prints 6 significant digits."""
    return abs(a - b) <= 0.6 * 10 ** (math.floor(math.log10(max(abs(b), 1e-300))) - digits + 1) + 1e-12


def same_angle(a, b, tol=1e-5):
    return abs(math.remainder(a - b, 2 * math.pi)) < tol


SEED_POSITIONS = {
    0.0: dict(X2=0, Y2=5, Th2=0, X3=0, Y3=0, Th3=-0.54042, X4=9.07905, Y4=10, Th4=0),
    0.5: dict(X2=0, Y2=5, Th2=3.14159, X3=0, Y3=0, Th3=0.54042, X4=-0.181877, Y4=10, Th4=0),
    0.85: dict(X2=0, Y2=5, Th2=5.34071, X3=0, Y3=0, Th3=-0.600822, X4=9.37314, Y4=10, Th4=0),
}


@pytest.mark.parametrize("t", sorted(SEED_POSITIONS))
def test_positions(qr, t):
    s = qr.solve(t)
    for name, value in SEED_POSITIONS[t].items():
        assert close(s[name], value), (name, s[name], value)
    assert s.residual < 1e-12


def test_second_assembly_mode_at_085(qr):
    s = qr.solve(0.85, guess={"X4": 1.0})
    assert close(s["X4"], 0.802632)
    assert same_angle(s["Th3"], 5.68236)          # ≡ -0.600822
    assert same_angle(s["Th2"], 5.34071)


def test_velocities_and_accelerations_at_015(qr):
    s = qr.solve(0.15, level="acceleration")
    expect = dict(Th2=0.942478, Th3=-0.233107, X4=6.92194, Th2d=6.28319, Th3d=2.27897,
                  X4d=-18.7395, Th3dd=1.64018, X4dd=-40.9024)
    for name, value in expect.items():
        assert close(s[name], value), (name, s[name], value)
    for name in ("X2d", "Y2d", "X3d", "Y3d", "Y4d", "Th4d", "X2dd", "Th2dd", "Y4dd", "Th4dd"):
        assert abs(s[name]) < 1e-12


def test_velocities_left_by_the_velocity_table(qr):
    """Section (7) prints SetGuess[] after veltab = SolveMech[postab, Solution->Velocity]
    (postab = SolveMech[{0,1},11]): T -> 1., the guessed positions, and the velocities of
    the table's last point, T = 1: Th2d -> 6.28319, Th3d -> 1.6632 (1.66320 to 6 digits),
    X4d -> -8.88405, the others 0."""
    sw = qr.sweep(0.0, 1.0, 11, level="velocity")
    assert sw.t[-1] == 1.0
    assert close(sw["Th2d"][-1], 6.28319) and close(sw["Th3d"][-1], 1.66320)
    assert close(sw["X4d"][-1], -8.88405)
    for name in ("X2d", "Y2d", "X3d", "Y3d", "Y4d", "Th4d"):
        assert abs(sw[name][-1]) < 1e-12
    s = qr.solve(1.0, level="velocity")                   # the same point, solved alone
    assert close(s["Th3d"], 1.66320) and close(s["X4d"], -8.88405)


def test_sweep_matches_seed(qr):
    sw = qr.sweep(0.0, 1.0, 20)            # SolveMech[{0, 1}, 20]: 20 times, both ends
    assert len(sw) == 20 and sw.t[0] == 0.0 and sw.t[-1] == 1.0
    assert close(sw["X4"][0], 9.07905) and close(sw["Th3"][0], -0.54042)
    assert close(sw["X4"][-1], 9.07905)
    # every point is the seed's assembly mode (the closed form of tests/closed_forms.py)
    from closed_forms import quick_return
    for k in range(20):
        assert abs(sw["X4"][k] - float(quick_return(sw.t[k])[6])) < 1e-10, k
    # 21 points put T = 0.5 on the grid: the seed's SolveMech[.5]
    assert close(qr.sweep(0.0, 1.0, 21)["X4"][10], -0.181877)


def test_slider_driven_version(qr_slider):
    s = qr_slider.solve(0.0)
    assert close(s["Th2"], 1.7945, 5) and close(s["Th3"], 0.083778, 5)
    assert close(s["X4"], 4.13931)


def test_slider_driven_lock_point_raises(qr_slider):
    with pytest.raises((mechgen.ConvergenceError, mechgen.SingularError)) as info:
        qr_slider.solve(0.249, guess={"Th2": -1.17501, "Th3": -0.643842, "X4": 9.54367})
    assert "0.249" in str(info.value)


FOURBAR = [(0.5274103891, 1.792465604), (-1.048246730, -2.313301945)]


@pytest.mark.parametrize("mode", [0, 1])
def test_fourbar_bodies(fourbar, mode):
    th3, th4 = FOURBAR[mode]
    s = fourbar.solve(0.0, guess={"Th3": th3 + 0.1, "Th4": th4 - 0.1})
    assert abs(s["Th3"] - th3) < 1e-9 and abs(s["Th4"] - th4) < 1e-9


@pytest.mark.parametrize("mode", [0, 1])
def test_fourbar_loop(fourbar_loop, mode):
    th3, th4 = FOURBAR[mode]
    s = fourbar_loop.solve(0.0, guess={"theta3": th3 + 0.1, "theta4": th4 - 0.1})
    assert abs(s["theta3"] - th3) < 1e-9 and abs(s["theta4"] - th4) < 1e-9
