"""``mechgen check``'s CANNOT ASSEMBLE names the dimensions where the contradicting
constraints are a four-bar's loop: the crank at its driven angle puts its end farther
from the rocker's pivot than coupler + rocker reach (a + d = 5.2 > b + c = 4.9), or
nearer than they fold to (|a − d| = 2.5 < c − b = 3)."""
from mechgen import Model, T, pi
from mechgen.compiler.check import check_report


def fourbar(a, b, c, d, start):
    m = Model("loop")
    pa, pb, pc, pd = (m.param(n, v) for n, v in zip("abcd", (a, b, c, d)))
    ground = m.ground("ground", points=[(0, 0), (pd, 0)])
    crank = m.body("crank", points=[(0, 0), (pa, 0)], guess=(0, 0, start))
    coupler = m.body("coupler", points=[(0, 0), (pb, 0)], guess=(-2, 0.5, 0.1))
    rocker = m.body("rocker", points=[(0, 0), (pc, 0)], guess=(d, 0, 2.5))
    m.revolute(ground[1], crank[1])
    m.revolute(crank[2], coupler[1])
    m.revolute(ground[2], rocker[1])
    m.revolute(coupler[2], rocker[2])
    m.rotation_lock(crank, start + 2 * pi * T, name="crank angle")
    return m


def _loop_line(text):
    return [x for x in text.splitlines() if "the loop cannot close" in x]


def test_a_crank_too_long_names_the_sum_that_fails():
    text, ok = check_report(fourbar(2.2, 2.5, 2.4, 3.0, pi), starts=8)
    assert not ok and "CANNOT ASSEMBLE" in text
    (line,) = _loop_line(text)
    assert "a (crank) + d (ground) = 5.2 >" in line
    assert "b (coupler)" in line and "c (rocker)" in line and "= 4.9" in line


def test_a_rocker_too_long_names_the_difference_that_fails():
    text, ok = check_report(fourbar(0.5, 1.0, 4.0, 3.0, 0.0), starts=8)
    assert not ok
    (line,) = _loop_line(text)
    assert "|a (crank) − d (ground)| = 2.5 < c (rocker) − b (coupler) = 3" in line


def test_a_four_bar_that_assembles_says_nothing_of_its_lengths():
    text, ok = check_report(fourbar(0.8, 2.5, 2.0, 3.0, pi / 3), starts=8)
    assert ok and not _loop_line(text)
