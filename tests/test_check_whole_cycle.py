"""``mechgen check`` follows the assembly through one period of the drivers: a four-bar's
rocker driven through a full turn locks where the crank and the coupler line up, and the
check says so (False, with the time); a crank-rocker driven by its crank passes, and a
model with no turning driver says it was checked at t only."""
import math

from mechgen import Model, T, pi
from mechgen.cli import main
from mechgen.compiler.check import check_report


def fourbar(driven="rocker", a=0.8, b=2.5, c=2.0, d=3.0):
    m = Model(f"fourbar_{driven}")
    ground = m.ground("ground", points=[(0, 0), (d, 0)])
    crank = m.body("crank", points=[(0, 0), (a, 0)], guess=(0, 0, 1.0))
    coupler = m.body("coupler", points=[(0, 0), (b, 0)], guess=(0.4, 0.7, 0.5))
    rocker = m.body("rocker", points=[(0, 0), (c, 0)], guess=(3, 0, 1.8))
    m.revolute(ground[1], crank[1])
    m.revolute(crank[2], coupler[1])
    m.revolute(ground[2], rocker[1])
    m.revolute(coupler[2], rocker[2])
    if driven == "rocker":
        m.rotation_lock(rocker, 1.79247 + 2 * pi * T, name="rocker drive")
    else:
        m.rotation_lock(crank, pi / 3 + 2 * pi * T, name="crank drive")
    return m


def _rocker_limits(a=0.8, b=2.5, c=2.0, d=3.0):
    """The rocker's extreme angles from +x (crank and coupler in line: O2–B = b ± a; the
    angle at O4 of triangle O2-O4-B subtracted from π)."""
    return [math.pi - math.acos((c * c + d * d - s * s) / (2 * c * d)) for s in (b - a, b + a)]


def test_rocker_driven_through_a_full_turn_locks():
    text, ok = check_report(fourbar("rocker"), starts=8)
    assert not ok
    assert "check: False" in text and "LOCKS at t = " in text
    line = next(x for x in text.splitlines() if "LOCKS at t = " in x)
    t_lock = float(line.split("LOCKS at t = ")[1].split()[0])
    # the rocker turns up from 1.79247, 2π a period: it locks at its upper limit,
    # where crank and coupler fold (t ≈ 0.1242)
    upper = max(_rocker_limits())
    assert abs(1.79247 + 2 * math.pi * t_lock - upper) < 1e-5
    assert "rocker drive" in text


def test_crank_rocker_driven_by_its_crank_passes():
    text, ok = check_report(fourbar("crank"), starts=8)
    assert ok, text
    assert "whole cycle: assembled" in text


def test_no_cycle_checks_at_t_only(capsys, tmp_path):
    path = tmp_path / "rocker.py"
    path.write_text(
        "from mechgen import Model, T, pi\n"
        "m = Model('rocker')\n"
        "g = m.ground('g', points=[(0, 0), (3, 0)])\n"
        "a = m.body('a', points=[(0, 0), (0.8, 0)], guess=(0, 0, 1.0))\n"
        "b = m.body('b', points=[(0, 0), (2.5, 0)], guess=(0.4, 0.7, 0.5))\n"
        "c = m.body('c', points=[(0, 0), (2, 0)], guess=(3, 0, 1.8))\n"
        "m.revolute(g[1], a[1]); m.revolute(a[2], b[1]); m.revolute(g[2], c[1])\n"
        "m.revolute(b[2], c[2])\n"
        "m.rotation_lock(c, 1.79247 + 2*pi*T, name='rocker drive')\n")
    assert main(["check", str(path), "--starts", "4"]) == 1
    assert "LOCKS at t = " in capsys.readouterr().out
    assert main(["check", str(path), "--starts", "4", "--no-cycle"]) == 0
    assert "LOCKS" not in capsys.readouterr().out


def test_a_driver_that_does_not_turn_says_t_only():
    m2 = Model("oscillating")
    ground = m2.ground("ground", points=[(0, 0)])
    arm = m2.body("arm", points=[(0, 0), (1, 0)], guess=(0, 0, 0))
    m2.revolute(ground[1], arm[1])
    from mechgen import sin
    m2.rotation_lock(arm, 0.3 * sin(2 * pi * T), name="swing")
    text, ok = check_report(m2, starts=4)
    assert ok and "the check above holds at t = 0 only" in text
