"""Numerics: results must not depend on the units a model is written in, nor on
how fast its driver turns. The same quick-return (seed 001) written with every length
multiplied by S, or with its crank speed changed, is the same mechanism; its closed form
(below, independent of mechgen) gives the reference.

Quick-return at scale S: crank S·3 about (0, 5S), lever about the origin through the
crank pin P, its tip E = 9S P/|P|, a link 5S to the slider on y = 10S:
X4 = E_x + √((5S)² − (10S − E_y)²), Th3 = atan2(−P_x, P_y)."""
import math

import pytest

import mechgen

QR = '''from mechgen import Model, T, pi
m = Model("{name}")
S = {S!r}
longitud = m.param("longitud", 3.0*S)
velocidad = m.param("velocidad", {omega!r})
base = m.ground("base", points=[(0, 0), (0, 5*S), (-5*S, 10*S), (12*S, 10*S)])
manivela = m.body("manivela", points=[(0, 0), (longitud, 0)], guess=(0, 5*S, 0))
colisa = m.body("colisa", points=[(0, 0), (0, 9*S)], guess=(0, 0, -0.5))
deslizadera = m.body("deslizadera", points=[(0, 0), (2*S, 0)], guess=(6*S, 10*S, 0))
m.revolute(base[2], manivela[1])
m.rotation_lock(manivela, base, velocidad * T, name="crank driver")
m.revolute(base[1], colisa[1])
m.point_on_line(manivela[2], colisa.line(1, 2))
m.relative_distance(colisa[2], deslizadera[1], 5*S)
m.translate(base.line(3, 4), deslizadera.line(1, 2))
'''


def closed_form(t, S=1.0, omega=2 * math.pi):
    """(Th3, X4, Th3d, X4d) of the crank-driven quick-return at scale S (rates by a
    central difference of the closed form, step 1e-6 of a turn)."""
    def pos(u):
        th = omega * u
        px, py = 3 * S * math.cos(th), 5 * S + 3 * S * math.sin(th)
        r = math.hypot(px, py)
        ex, ey = 9 * S * px / r, 9 * S * py / r
        return math.atan2(-px, py), ex + math.sqrt((5 * S) ** 2 - (10 * S - ey) ** 2)
    h = 1e-6 * 2 * math.pi / omega
    (a1, x1), (a0, x0) = pos(t + h), pos(t - h)
    return (*pos(t), (a1 - a0) / (2 * h), (x1 - x0) / (2 * h))


def model(tmp_path, S, omega=2 * math.pi):
    name = "qr_" + f"{S:g}_{omega:g}".replace(".", "p").replace("+", "").replace("-", "m")
    path = tmp_path / f"{name}.py"
    path.write_text(QR.format(name=name, S=S, omega=omega))
    return mechgen.compile(str(path), tier="python")


def check(s, t, S, omega=2 * math.pi, rates=True):
    th3, x4, th3d, x4d = closed_form(t, S, omega)
    assert abs(math.remainder(s["Th3"] - th3, 2 * math.pi)) < 1e-12
    assert abs(s["X4"] - x4) < 1e-12 * S
    if rates:       # (the closed form's rates are a difference quotient: to ~1e-9)
        assert abs(s["Th3d"] - th3d) < 1e-7 * omega
        assert abs(s["X4d"] - x4d) < 1e-7 * omega * S


@pytest.mark.xfail(strict=True, reason=(
    "the singular test (pivot_ratio, velocity_full/acceleration_full's _fp_solve at "
    "SING_RTOL, the sorted passes' Guard on |det| vs SING_RTOL × row sums) equilibrates "
    "rows only: a length column and an angle column of Φ_q differ by the unit of length, "
    "so the pivot ratio falls as 1/S (8e-2 at S=1, 8e-7 at S=1e5) and a regular "
    "configuration written in micrometres counts as singular. Suggested fix: equilibrate "
    "the columns too (after the rows: each column of the row-scaled Φ_q by its largest "
    "entry, x unscaled after the solve; the sorted guards likewise with column scales) so "
    "that a change of units, a diagonal scaling, leaves the test unchanged"))
@pytest.mark.parametrize("S", [1e5, 1e-7])
def test_velocity_of_a_regular_configuration_does_not_depend_on_the_unit(tmp_path, S):
    """The quick-return in micrometres (crank 0.3 m = 3e5 µm: S = 1e5) or a 1-µm linkage
    in metres (S = 1e-7): a regular configuration (pivot ratio 8e-2 at S = 1). mechgen:
    SingularError 'the velocity is not determined by the constraints (Jacobian rank 8 of 9,
    pivot ratio 8.1e-07)' at every t, and s.singular at position level."""
    mech = model(tmp_path, S)
    s = mech.solve(0.13, level="velocity")
    assert not s.singular
    check(s, 0.13, S)


@pytest.mark.parametrize("S", [1e3, 1e5])
def test_full_newton_converges_whatever_the_unit(tmp_path, S):
    """newton_full stopped on max|Φ| <= tol, an absolute bound on rows whose size grows
    with the unit (‖r1 − r2‖² − d² is of order S², its rounding ~1e-16 S² above tol = 1e-10
    from S ~ 1e3): ConvergenceError 'did not converge in 50 iterations (residual 7.5e-09)
    ... start from a closer guess' for a well-posed model from a guess 0.1 % off. A
    residual within the rounding of Φ's rows (64 eps Σ_j |J_ij| (1 + |q_j|)) with the
    step within xtol is now met."""
    mech = model(tmp_path, S)
    th3, x4, _, _ = closed_form(0.13, S)
    guess = {"Th2": 2 * math.pi * 0.13, "Th3": th3 * 1.001, "X4": x4 * 1.001,
             "Y2": 5 * S, "Y4": 10 * S}
    s = mech.solve(0.13, guess=guess, method="full")
    check(s, 0.13, S, rates=False)


@pytest.mark.parametrize("omega", [300.0, 1e4])
def test_solve_follows_a_fast_driver(tmp_path, omega):
    """solve(t) without a guess follows the motion in cells of 1/16 time unit; a crank at
    300 rad/s turns three times in one cell and the careful sweep's one step over it ended
    in 'could not keep the assembly mode on the way to t=0.0625 (a jump of 2.21e-05 ...)':
    a SolveError for a regular, singularity-free cycle (omega=1000 solved, 300 and 1e4
    did not). The step between two cells is now taken again in substeps before it counts
    as a jump."""
    mech = model(tmp_path, 1.0, omega)
    for t in (0.37, 0.0625, 1.3):
        check(mech.solve(t, level="velocity"), t, 1.0, omega)


def test_same_mechanism_at_moderate_scales_and_speeds(tmp_path):
    """What holds now: metres to millimetres (S = 1e-3 … 1e2 of the seed's units), crank
    speeds 1e-3 … 1e4 rad/s, to 1e-12 of the size."""
    for S in (1e-3, 0.1, 100.0):
        mech = model(tmp_path, S)
        for t in (0.0, 0.13, 0.61):
            check(mech.solve(t, level="velocity"), t, S)
    mech = model(tmp_path, 1.0, 1e-3)
    check(mech.solve(500.0, level="velocity", guess=mech.guess), 500.0, 1.0, 1e-3)


def test_a_tolerance_below_the_rounding_is_treated_alike(tmp_path):
    """tol below the rounding of Φ (1e-16 on rows of size 25): the sorted solver returned
    status OK with residual 7.1e-15 > tol, the full Newton raised ConvergenceError with the
    wrong advice to start from a closer guess. Both now accept the rounding."""
    mech = model(tmp_path, 1.0)
    guess = {"Th2": 2 * math.pi * 0.3, "Th3": 0.3, "X4": 5.0, "Y2": 5.0, "Y4": 10.0}
    s = mech.solve(0.3, guess=guess, tol=1e-16, method="sorted")
    assert s.residual > 1e-16             # accepted above tol by the sorted solver...
    s = mech.solve(0.3, guess=guess, tol=1e-16, method="full")   # ...refused by the full one
    check(s, 0.3, 1.0, rates=False)
