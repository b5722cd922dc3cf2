"""m.equations() against the equations the seeds print.

Seed 001 (Mech, quick-return) prints Φ (section 2), the Jacobian, VelocityTerms (= Φ_t),
Jacobian.Velocity + VelocityTerms and AccelerationTerms (= −γ); section 2B prints Φ of
the slider-driven version. Seed 000 (Maple) prints the loop-closure equations (1.1.2) and
(1.1.3). The printed text is kept verbatim below in Mathematica syntax and parsed with
sympy; where the text extraction lost a superscript or shifted a bracket, the fix is
marked "extraction:" and the printed *numbers* decide (see test_*_printed_solutions).
"""
import math
import random

import pytest
import sympy as sp
from sympy.parsing.mathematica import parse_mathematica

from conftest import example_model

# section 2 sets longitud = 3, velocidad = 2 N[Pi], anguloI = 0.0; section 2B drives the
# slider with 4.13931 + 5.40447 Sin[2 N[Pi] T] (centro, amplitud of the example)
SEED_PARAMS = {"longitud": 3, "velocidad": 2 * sp.pi, "anguloI": 0,
               "centro": sp.Float("4.13931"), "amplitud": sp.Float("5.40447")}


@pytest.fixture(scope="module")
def qr_eq():
    return example_model("quick_return").equations()


@pytest.fixture(scope="module")
def slider_eq():
    return example_model("quick_return_slider").equations()


def mma(text, eq):
    """Parse Mathematica text; map its symbols onto the model's (real) symbols by name."""
    expr = parse_mathematica(text)
    names = {str(s): s for s in (*eq.q, *eq.qd, *eq.qdd, *eq.params, eq.T)}
    return expr.xreplace({s: names[str(s)] for s in expr.free_symbols})


def with_seed_params(expr, eq, values=SEED_PARAMS):
    return sp.sympify(expr).subs({p: values[str(p)] for p in eq.params if str(p) in values})


def random_point(eq, rng):
    syms = [*eq.q, *eq.qd, *eq.qdd, eq.T]
    return {s: rng.uniform(-2.0, 2.0) for s in syms}


def same(ours, printed, eq, points=6):
    """Equal symbolically when the print holds no rounded float, and numerically at random
    points in every case (to the six digits Mech prints when it holds one)."""
    ours = with_seed_params(ours, eq)
    printed = sp.sympify(printed)
    rtol = 1e-12
    if printed.atoms(sp.Float):
        rtol = 2e-5     # e.g. Sin[6.28319 T] for sin(2 pi T): six digits inside the sine
    else:
        assert sp.simplify(sp.expand(ours - printed)) == 0, (ours, printed)
    rng = random.Random(20240601)
    for _ in range(points):
        at = random_point(eq, rng)
        a, b = float(ours.xreplace(at)), float(printed.xreplace(at))
        assert abs(a - b) <= rtol * (1 + abs(a) + abs(b)), (ours, printed, at, a, b)


# ---------------------------------------------------------------------------------
# Seed 001, section 2: MatrixForm[Constraints[A11]]
PRINTED_PHI = [
    "-X2",
    "5 - Y2",
    "0. - 6.28319 T + Th2",
    "-X3",
    "-Y3",
    "9 (-X2 + X3 - 3 Cos[Th2]) Cos[Th3] - 9 (Y2 - Y3 + 3 Sin[Th2]) Sin[Th3]",
    # extraction: the two squares of the distance row were lost ("(…) + (…)")
    "-25 + (Y3 - Y4 + 9 Cos[Th3])^2 + (X3 - X4 - 9 Sin[Th3])^2",
    "34 Sin[Th4]",
    "2 (10 - Y4) Cos[Th4] + 2 (5 + X4) Sin[Th4]",
]

# Jacobian[All,All], verbatim
PRINTED_JACOBIAN = """
{{-1, 0, 0, 0, 0, 0, 0, 0, 0}, {0, -1, 0, 0, 0, 0, 0, 0, 0},
  {0, 0, 1, 0, 0, 0, 0, 0, 0}, {0, 0, 0, -1, 0, 0, 0, 0, 0},
  {0, 0, 0, 0, -1, 0, 0, 0, 0},
  {-9 Cos[Th3], -9 Sin[Th3], 27 Cos[Th3] Sin[Th2] - 27 Cos[Th2] Sin[Th3],
   9 Cos[Th3], 9 Sin[Th3], -9 Cos[Th3] (Y2 - Y3 + 3 Sin[Th2]) -
   9 (-X2 + X3 - 3 Cos[Th2]) Sin[Th3], 0, 0, 0},
  {0, 0, 0, 2 (X3 - X4 - 9 Sin[Th3]), 2 (Y3 - Y4 + 9 Cos[Th3]),
   -18 Cos[Th3] (X3 - X4 - 9 Sin[Th3]) -
   18 (Y3 - Y4 + 9 Cos[Th3]) Sin[Th3], -2 (X3 - X4 - 9 Sin[Th3]),
   -2 (Y3 - Y4 + 9 Cos[Th3]), 0}, {0, 0, 0, 0, 0, 0, 0, 0, 34 Cos[Th4]},
  {0, 0, 0, 0, 0, 0, 2 Sin[Th4], -2 Cos[Th4],
   2 (5 + X4) Cos[Th4] - 2 (10 - Y4) Sin[Th4]}}
"""

# MatrixForm[VelocityTerms[A11]] (the extraction shows one 0 too many; Dimensions says 9)
PRINTED_VELOCITY_TERMS = ["0", "0", "-6.28319", "0", "0", "0", "0", "0", "0"]

# Jacobian[All,All].Velocity[All] + VelocityTerms[All], verbatim
PRINTED_PHI_DOT = """
{-X2d, -Y2d, -6.28319 + Th2d, -X3d, -Y3d,
  -9 X2d Cos[Th3] + 9 X3d Cos[Th3] - 9 Y2d Sin[Th3] + 9 Y3d Sin[Th3] +
  Th3d (-9 Cos[Th3] (Y2 - Y3 + 3 Sin[Th2]) -
  9 (-X2 + X3 - 3 Cos[Th2]) Sin[Th3]) +
  Th2d (27 Cos[Th3] Sin[Th2] - 27 Cos[Th2] Sin[Th3]),
  2 Y3d (Y3 - Y4 + 9 Cos[Th3]) - 2 Y4d (Y3 - Y4 + 9 Cos[Th3]) +
  2 X3d (X3 - X4 - 9 Sin[Th3]) - 2 X4d (X3 - X4 - 9 Sin[Th3]) +
  Th3d (-18 Cos[Th3] (X3 - X4 - 9 Sin[Th3]) -
  18 (Y3 - Y4 + 9 Cos[Th3]) Sin[Th3]), 34 Th4d Cos[Th4],
  -2 Y4d Cos[Th4] + 2 X4d Sin[Th4] +
  Th4d (2 (5 + X4) Cos[Th4] - 2 (10 - Y4) Sin[Th4])}
"""

# AccelerationTerms[A11] (= −γ).
PRINTED_ACCELERATION_TERMS = [
    "0", "0", "0", "0", "0",
    # extraction: a ")" moved from after the Th2d group's second term to after its first
    "-9 Th3d Y2d Cos[Th3] + 9 Th3d Y3d Cos[Th3] + 9 Th3d X2d Sin[Th3] - 9 Th3d X3d Sin[Th3] +"
    " Th2d (Th3d (-27 Cos[Th2] Cos[Th3] - 27 Sin[Th2] Sin[Th3]) +"
    " Th2d (27 Cos[Th2] Cos[Th3] + 27 Sin[Th2] Sin[Th3])) +"
    " Th3d (-9 Y2d Cos[Th3] + 9 Y3d Cos[Th3] + 9 X2d Sin[Th3] - 9 X3d Sin[Th3] +"
    " Th2d (-27 Cos[Th2] Cos[Th3] - 27 Sin[Th2] Sin[Th3]) +"
    " Th3d (-9 (-X2 + X3 - 3 Cos[Th2]) Cos[Th3] + 9 (Y2 - Y3 + 3 Sin[Th2]) Sin[Th3]))",
    # extraction: the squares of "162 Cos[Th3]" and "162 Sin[Th3]" were lost
    "X3d (2 X3d - 2 X4d - 18 Th3d Cos[Th3]) + X4d (-2 X3d + 2 X4d + 18 Th3d Cos[Th3]) +"
    " Y3d (2 Y3d - 2 Y4d - 18 Th3d Sin[Th3]) + Y4d (-2 Y3d + 2 Y4d + 18 Th3d Sin[Th3]) +"
    " Th3d (-18 X3d Cos[Th3] + 18 X4d Cos[Th3] - 18 Y3d Sin[Th3] + 18 Y4d Sin[Th3] +"
    " Th3d (162 Cos[Th3]^2 - 18 Cos[Th3] (Y3 - Y4 + 9 Cos[Th3]) +"
    " 18 (X3 - X4 - 9 Sin[Th3]) Sin[Th3] + 162 Sin[Th3]^2))",
    # extraction: printed "2 -34 Th4d Sin[Th4]", the square drifted to the front
    "-34 Th4d^2 Sin[Th4]",
    "2 Th4d X4d Cos[Th4] + 2 Th4d Y4d Sin[Th4] + Th4d (2 X4d Cos[Th4] + 2 Y4d Sin[Th4] +"
    " Th4d (-2 (10 - Y4) Cos[Th4] - 2 (5 + X4) Sin[Th4]))",
]

# The solutions the seed prints (SolveMech), used to decide between text and formula.
SEED_SOLUTIONS = [
    dict(T=0.0, X2=0., Y2=5., Th2=0., X3=0., Y3=0., Th3=-0.54042, X4=9.07905, Y4=10., Th4=0.),
    dict(T=0.5, X2=0., Y2=5., Th2=3.14159, X3=0., Y3=0., Th3=0.54042, X4=-0.181877, Y4=10.,
         Th4=0.),
    dict(T=0.85, X2=0., Y2=5., Th2=5.34071, X3=0., Y3=0., Th3=-0.600822, X4=9.37314, Y4=10.,
         Th4=0.),
    dict(T=0.85, X2=0., Y2=5., Th2=5.34071, X3=0., Y3=0., Th3=5.68236, X4=0.802632, Y4=10.,
         Th4=0.),
]
SEED_ACCELERATION_015 = dict(
    T=0.15, X2=0., Y2=5., Th2=0.942478, X3=0., Y3=0., Th3=-0.233107, X4=6.92194, Y4=10.,
    Th4=0., X2d=0., Y2d=0., Th2d=6.28319, X3d=0., Y3d=0., Th3d=2.27897, X4d=-18.7395, Y4d=0.,
    Th4d=0., X2dd=0., Y2dd=0., Th2dd=0., X3dd=0., Y3dd=0., Th3dd=1.64018, X4dd=-40.9024,
    Y4dd=0., Th4dd=0.)


def half_digit(value, digits=6):
    """Half a unit in the last of the six significant digits Mech prints (0 stays exact)."""
    if value == 0:
        return 0.0
    return 0.5 * 10 ** (math.floor(math.log10(abs(value))) - digits + 1)


def residual_bound(expr, values, eq):
    """First-order bound on |expr| caused by the rounding of the printed values."""
    syms = [s for s in (*eq.q, *eq.qd, *eq.qdd) if str(s) in values]
    at = {s: values[str(s)] for s in syms}
    at[eq.T] = values["T"]
    bound = sum(abs(float(sp.diff(expr, s).xreplace(at))) * half_digit(values[str(s)])
                for s in syms if s in expr.free_symbols)
    return float(expr.xreplace(at)), 2 * bound + 1e-9


# ---------------------------------------------------------------------------------
def test_coordinates_named_and_ordered_as_the_seed(qr_eq):
    assert [str(s) for s in qr_eq.q] == ["X2", "Y2", "Th2", "X3", "Y3", "Th3", "X4", "Y4", "Th4"]
    assert [str(s) for s in qr_eq.qd] == [f"{s}d" for s in map(str, qr_eq.q)]
    assert [str(s) for s in qr_eq.qdd] == [f"{s}dd" for s in map(str, qr_eq.q)]
    assert [str(p) for p in qr_eq.params] == ["longitud", "velocidad", "anguloI"]
    for key in ("q", "qd", "qdd", "phi", "phi_q", "phi_t", "nu", "gamma"):
        assert isinstance(qr_eq[key], sp.MatrixBase), key
    assert qr_eq.phi.shape == (9, 1) and qr_eq.phi_q.shape == (9, 9)
    assert qr_eq.gamma.shape == (9, 1) and qr_eq.nu.shape == (9, 1)


def test_parameters_stay_symbolic(qr_eq):
    names = {str(s) for s in qr_eq.phi.free_symbols}
    assert {"longitud", "velocidad", "anguloI", "T"} <= names
    velocidad, anguloI = (p for p in qr_eq.params if str(p) != "longitud")
    th2 = qr_eq.q[2]
    assert sp.expand(qr_eq.phi[2] - (th2 - velocidad * qr_eq.T - anguloI)) == 0
    assert qr_eq.nu[2] == velocidad


@pytest.mark.parametrize("row", range(9))
def test_phi_is_the_printed_phi(qr_eq, row):
    same(qr_eq.phi[row], mma(PRINTED_PHI[row], qr_eq), qr_eq)


def test_jacobian_is_the_printed_jacobian(qr_eq):
    printed = sp.Matrix(mma(PRINTED_JACOBIAN, qr_eq))
    assert printed.shape == (9, 9)
    for i in range(9):
        for j in range(9):
            same(qr_eq.phi_q[i, j], printed[i, j], qr_eq, points=3)


def test_jacobian_is_the_derivative_of_phi(qr_eq, slider_eq):
    for eq in (qr_eq, slider_eq):
        assert (eq.phi_q - eq.phi.jacobian(eq.q)).applyfunc(sp.expand) == sp.zeros(*eq.phi_q.shape)
        assert (eq.phi_t - eq.phi.diff(eq.T)) == sp.zeros(eq.phi.rows, 1)
        assert eq.nu == -eq.phi_t


def test_velocity_terms_are_phi_t(qr_eq):
    for row, text in enumerate(PRINTED_VELOCITY_TERMS):
        same(qr_eq.phi_t[row], mma(text, qr_eq), qr_eq)
        same(-qr_eq.nu[row], mma(text, qr_eq), qr_eq)


def test_jacobian_times_velocity_plus_velocity_terms(qr_eq):
    printed = mma(PRINTED_PHI_DOT, qr_eq)
    ours = qr_eq.phi_q * qr_eq.qd + qr_eq.phi_t
    assert len(printed) == 9
    for row in range(9):
        same(ours[row], printed[row], qr_eq)


@pytest.mark.parametrize("row", range(9))
def test_acceleration_terms_are_minus_gamma(qr_eq, row):
    same(-qr_eq.gamma[row], mma(PRINTED_ACCELERATION_TERMS[row], qr_eq), qr_eq, points=4)


def test_printed_solutions_satisfy_the_printed_phi(qr_eq):
    """Numbers win: every printed SolveMech configuration zeroes the transcribed Φ."""
    for values in SEED_SOLUTIONS:
        for row, text in enumerate(PRINTED_PHI):
            r, bound = residual_bound(mma(text, qr_eq), values, qr_eq)
            assert abs(r) <= bound + 2e-5 * (row == 2), (values["T"], row, r, bound)


def test_printed_acceleration_solution_satisfies_the_transcribed_terms(qr_eq):
    """SolveMech[0.15, Solution->Acceleration]: Φ_q q̇ + Φ_t = 0 and Φ_q q̈ + AccelerationTerms
    = 0 with the printed numbers, for the transcribed (printed) forms and for ours."""
    values = SEED_ACCELERATION_015
    J = sp.Matrix(mma(PRINTED_JACOBIAN, qr_eq))
    phi_dot = mma(PRINTED_PHI_DOT, qr_eq)
    acc = sp.Matrix([mma(t, qr_eq) for t in PRINTED_ACCELERATION_TERMS])
    printed_acc = J * qr_eq.qdd + acc
    ours_acc = with_seed_params(qr_eq.phi_q * qr_eq.qdd - qr_eq.gamma, qr_eq)
    ours_vel = with_seed_params(qr_eq.phi_q * qr_eq.qd + qr_eq.phi_t, qr_eq)
    for row in range(9):
        for expr in (phi_dot[row], ours_vel[row], printed_acc[row], ours_acc[row]):
            r, bound = residual_bound(sp.sympify(expr), values, qr_eq)
            assert abs(r) <= bound + 1e-4, (row, expr, r, bound)


# ---------------------------------------------------------------------------------
# Seed 001, section 2B: the slider-driven system, MatrixForm[Constraints[All]]
PRINTED_PHI_2B = [
    "-X2",
    "5 - Y2",
    "-X3",
    "-Y3",
    # extraction: printed with two stray "^2" (section 2's print of the same row has none;
    # the printed SolveMech[.0] of 2B zeroes only the form without them)
    "9 (-X2 + X3 - 3 Cos[Th2]) Cos[Th3] - 9 (Y2 - Y3 + 3 Sin[Th2]) Sin[Th3]",
    "-25 + (Y3 - Y4 + 9 Cos[Th3])^2 + (X3 - X4 - 9 Sin[Th3])^2",
    "34 Sin[Th4]",
    "2 (10 - Y4) Cos[Th4] + 2 (5 + X4) Sin[Th4]",
    "-4.13931 + X4 - 5.40447 Sin[6.28319 T]",
]
SEED_2B_SOLUTIONS = [
    dict(T=0.0, X2=0., Y2=5., Th2=1.7945, X3=0., Y3=0., Th3=0.083778, X4=4.13931, Y4=10., Th4=0.),
    dict(T=0.245, X2=0., Y2=5., Th2=-0.611293, X3=0., Y3=0., Th3=-0.643121, X4=9.54111, Y4=10.,
         Th4=0.),
]


@pytest.mark.parametrize("row", range(9))
def test_slider_driven_phi_is_the_printed_phi(slider_eq, row):
    same(slider_eq.phi[row], mma(PRINTED_PHI_2B[row], slider_eq), slider_eq)


def test_slider_driven_system_shape_and_driver(slider_eq):
    assert slider_eq.phi_q.shape == (9, 9)
    # only the driver row moves with T; its ν and γ are the slider's velocity and acceleration
    assert [i for i in range(9) if slider_eq.phi_t[i] != 0] == [8]
    nu, gamma = slider_eq.nu[8], slider_eq.gamma[8]
    amp = {str(p): p for p in slider_eq.params}["amplitud"]
    t = slider_eq.T
    assert sp.simplify(nu - amp * 2 * sp.pi * sp.cos(2 * sp.pi * t)) == 0
    assert sp.simplify(gamma + amp * 4 * sp.pi ** 2 * sp.sin(2 * sp.pi * t)) == 0
    # and γ of the kinematic rows is the same as in the crank-driven model
    qr = example_model("quick_return").equations()
    for i_slider, i_crank in ((4, 5), (5, 6), (6, 7), (7, 8)):
        assert sp.expand(slider_eq.gamma[i_slider] - qr.gamma[i_crank]) == 0


def test_slider_printed_solutions_zero_the_phi(slider_eq):
    for values in SEED_2B_SOLUTIONS:
        for row, text in enumerate(PRINTED_PHI_2B):
            r, bound = residual_bound(mma(text, slider_eq), values, slider_eq)
            assert abs(r) <= bound + 1e-5, (values["T"], row, r, bound)
    # the stray squares of the extracted print cannot be right: they miss by far
    wrong = mma("9 (-X2 + X3 - 3 Cos[Th2])^2 Cos[Th3] - 9 (Y2 - Y3 + 3 Sin[Th2])^2 Sin[Th3]",
                slider_eq)
    r, bound = residual_bound(wrong, SEED_2B_SOLUTIONS[0], slider_eq)
    assert abs(r) > 100 * bound


# ---------------------------------------------------------------------------------
# Seed 000: the vector loop split into real and imaginary parts at θ2 = π/3
def test_loop_closure_fourbar_gives_seed_000_equations():
    model = example_model("fourbar_loop")
    eq = model.equations()
    assert [str(s) for s in eq.q] == ["theta3", "theta4"]
    th3, th4 = eq.q
    at_t0 = eq.phi.subs({p: model.param_defaults[str(p)] for p in eq.params}).subs(eq.T, 0)
    printed = [-2.6000000000 + 2.5 * sp.cos(th3) - 2 * sp.cos(th4),                # (1.1.2)
               0.4000000000 * sp.sqrt(3) + 2.5 * sp.sin(th3) - 2 * sp.sin(th4)]    # (1.1.3)
    rng = random.Random(0)
    for ours, theirs in zip(at_t0, printed):
        assert ours.free_symbols == {th3, th4}
        for _ in range(5):
            at = {th3: rng.uniform(-4, 4), th4: rng.uniform(-4, 4)}
            assert abs(float((ours - theirs).subs(at))) < 1e-12, (ours, theirs)
    # (1.1.4): both printed solutions satisfy them (10 printed digits)
    for s3, s4 in ((0.5274103891, 1.792465604), (-1.048246730, -2.313301945)):
        for row in at_t0:
            assert abs(float(row.subs({th3: s3, th4: s4}))) < 1e-8
    # symbolically: a e^{iθ2} + b e^{iθ3} − c e^{iθ4} − d e^{iθ1}, real and imaginary parts
    p = {str(s): s for s in eq.params}
    th2 = p["theta2"] + p["omega"] * eq.T
    loop = (p["a"] * sp.exp(sp.I * th2) + p["b"] * sp.exp(sp.I * th3)
            - p["c"] * sp.exp(sp.I * th4) - p["d"] * sp.exp(sp.I * p["theta1"]))
    loop = sp.expand_complex(loop)
    assert sp.simplify(eq.phi[0] - sp.re(loop)) == 0
    assert sp.simplify(eq.phi[1] - sp.im(loop)) == 0


def test_mathematica_notation_of_sign():
    """`mechgen equations --mathematica` printed the rate of Abs(T - 1) as "sign[T - 1]",
    which is no Mathematica (its function is Sign)."""
    import sympy as sp
    from mechgen.model.printing import mathematica
    t = sp.Symbol("T")
    assert mathematica(sp.sign(t - 1)) == "Sign[T - 1]"
    assert mathematica(sp.Abs(t - 1)) == "Abs[T - 1]"
    assert mathematica(sp.atan2(t, 1 + t ** 2)) == "ArcTan[T^2 + 1, T]"
