"""Defects an acceptance audit of the model language (API.md §1-3) found, each pinned by
a small model and a number worked out by hand:

- an output named like another output's derivative (``v`` and ``vd``) was accepted, and
  ``s["vd"]`` and a sweep's CSV column ``vd`` then gave one of the two silently;
- ``dt(expr)`` without a model, in a process where another model's body 2 has the
  velocity ``X2d``, counted the rate of a coordinate named ``X2d`` twice (2 X2dd);
- a quadratic closed form at its double root with B = AC = 0 (x² = 1 − T at T = 1)
  divided 0 by 0 in its reach margin: ZeroDivisionError from solve() and sweep();
- an expression holding the imaginary unit I (exported for m.loop) built, and failed at
  the first solve with numba's typing error instead of a ModelError naming it;
- ``mechgen build FILE --model NAME`` built every model of the file.
"""
import math
import warnings

import pytest
import sympy as sp

import mechgen
from mechgen import I, Model, ModelError, T, dt, exp


def test_an_output_may_not_take_the_name_of_another_outputs_derivative():
    m = Model("out_names")
    x = m.coordinate("x", 0.0)
    m.constraint(x - T ** 3)
    m.output("v", x)
    with pytest.raises(ModelError, match=r"'vd' clashes with the first derivative of output 'v'"):
        m.output("vd", 10 * x)
    with pytest.raises(ModelError, match=r"'vdd' clashes with the second derivative of output"):
        m.output("vdd", 10 * x)
    m.output("w_d", x)
    with pytest.raises(ModelError, match=r"output name 'w_': its first derivative w_d"):
        m.output("w_", x)
    with pytest.raises(ModelError, match=r"coordinate name 'vd' clashes with the first"):
        m.coordinate("vd")
    a = m.coordinate("ad", 0.0)
    m.constraint(a - T)
    with pytest.raises(ModelError, match=r"output name 'a': its first derivative ad clashes"):
        m.output("a", x)
    # the names that stay apart still solve to the hand values: v = t³, v' = 3t², v'' = 6t
    mech = mechgen.compile(m, tier="python")
    s = mech.solve(1.5, level="acceleration")
    assert s["v"] == pytest.approx(1.5 ** 3, abs=1e-12)
    assert s["vd"] == pytest.approx(3 * 1.5 ** 2, abs=1e-9)
    assert s["vdd"] == pytest.approx(6 * 1.5, abs=1e-9)


def test_dt_without_a_model_counts_each_rate_once():
    other = Model("with_body_two")            # its body 2 has the velocity X2d
    g = other.ground("g", points=[(0, 0)])
    b = other.body("b", points=[(0, 0)], guess=(0, 0, 0))
    other.revolute(g[1], b[1])
    other.rotation_lock(b, T)
    m = Model("coordinate_x2d")
    x = m.coordinate("X2d", 0.0)              # a coordinate named like that velocity
    m.constraint(x - T ** 2)
    rate = sp.Symbol("X2dd", real=True)
    assert sp.simplify(dt(x) - rate) == 0
    assert sp.simplify(dt(x * x) - 2 * x * rate) == 0
    assert dt(x, 2) == sp.Symbol("X2ddd", real=True)
    m.output("v", dt(x))
    s = mechgen.compile(m, tier="python").solve(1.25, level="velocity")
    assert s["v"] == pytest.approx(2 * 1.25, abs=1e-9)        # d/dt T² = 2T


def _toggle_model():
    m = Model("toggle_square")
    x = m.coordinate("x", 1.0)
    m.constraint(x ** 2 - (1 - T))               # x = ±√(1 − T): a double root at T = 1
    return m


@pytest.mark.parametrize("tier", ["python", "compiled"])
def test_a_quadratic_closed_form_at_its_double_root_does_not_divide_by_zero(tier):
    mech = mechgen.compile(_toggle_model(), tier=tier)
    s = mech.solve(1.0, guess={"x": 0.1})
    assert abs(s["x"]) < 1e-6                    # √(1 − 1) = 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", mechgen.BranchJumpWarning)
        sw = mech.sweep(0.0, 1.0, 3)
    expected = [math.sqrt(1 - t) for t in (0.0, 0.5, 1.0)]
    assert sw["x"] == pytest.approx(expected, abs=1e-6)


@pytest.mark.parametrize("declare", ["constraint", "driver", "point", "output"])
def test_an_expression_holding_i_is_a_model_error_naming_it(declare):
    m = Model("complex_here")
    g = m.ground("g", points=[(0, 0)])
    x = m.coordinate("x", 1.0)
    with pytest.raises(ModelError, match=r"is complex \(it holds I\)") as err:
        if declare == "constraint":
            m.constraint(x - I * T)
        elif declare == "driver":
            b = m.body("b", points=[(0, 0)], guess=(0, 0, 0))
            m.revolute(g[1], b[1])
            m.rotation_lock(b, I * T)
        elif declare == "point":
            m.body("b", points=[(0, 0), (1, I)], guess=(0, 0, 0))
        else:
            m.output("z", exp(I * x))
    where = {"constraint": "constraint 1", "driver": "rotation_lock",
             "point": "point 2 of body 'b'", "output": "output 'z'"}[declare]
    assert where in str(err.value) and "test_audit_lang.py" in str(err.value)


def test_the_seed_loop_form_keeps_taking_a_complex_loop():
    m = Model("loop_still")
    th3, th4 = m.coordinate("th3", 0.5), m.coordinate("th4", 1.8)
    th2 = sp.pi / 3 + T
    m.loop(0.8 * exp(I * th2) + 2.5 * exp(I * th3) - 2 * exp(I * th4) - 3)
    s = mechgen.compile(m, tier="python").solve(0.0)
    # seed 000, (1.1.4): θ3 = 0.5274103891, θ4 = 1.792465604
    assert s["th3"] == pytest.approx(0.5274103891, abs=1e-9)
    assert s["th4"] == pytest.approx(1.792465604, abs=1e-9)


TWO_MODELS = '''
from mechgen import Model, T
alpha = Model("alpha_one")
x = alpha.coordinate("x", 0.0)
alpha.constraint(x - T)
beta = Model("beta_two")
y = beta.coordinate("y", 0.0)
beta.constraint(y - 2 * T)
'''


def test_build_with_model_writes_only_that_model(tmp_path, capsys):
    from mechgen.cli import main
    path = tmp_path / "two.py"
    path.write_text(TWO_MODELS)
    out = tmp_path / "out"
    assert main(["build", str(path), "--model", "beta_two", "-o", str(out)]) == 0
    assert sorted(p.name for p in out.glob("*.py")) == ["beta_two.py"]
    assert main(["build", str(path), "--model", "gamma", "-o", str(out)]) != 0
    err = capsys.readouterr().err
    assert "no model named 'gamma'" in err and "alpha_one, beta_two" in err
    assert main(["build", str(path), "-o", str(out)]) == 0       # no --model: every model
    assert sorted(p.name for p in out.glob("*.py")) == ["alpha_one.py", "beta_two.py"]
    # the module built answers y = 2T
    s = mechgen.load(str(out / "beta_two.py"), tier="python").solve(0.75)
    assert s["y"] == pytest.approx(1.5, abs=1e-12)
