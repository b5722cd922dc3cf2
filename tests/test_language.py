"""The model language (docs/reference/model.md): names, dt(), closed forms, symbols a model does not
own, star imports, rebuilding when a data file changes, functions such as Abs and sign in
outputs and constraints; each pinned by a small model and a number worked out by hand:

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
import subprocess
import sys
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
    assert where in str(err.value) and "test_language.py" in str(err.value)


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


def test_star_import_of_mechgen_gives_every_exported_name():
    # `from mechgen import *` at the top of a model file raised ModuleNotFoundError
    # (mechgen.runtime.design): __all__ listed DesignTable, Reduction, OptimizeResult at
    # their modules' old places
    code = ("from mechgen import *\n"
            "m = Model('star'); x = m.coordinate('x', 0.0); m.constraint(x - sin(T))\n"
            "print(DesignTable.__name__, Reduction.__name__, OptimizeResult.__name__)\n")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=str(__import__("pathlib").Path(mechgen.__file__).parents[1]))
    assert res.returncode == 0, res.stderr
    assert res.stdout.split() == ["DesignTable", "Reduction", "OptimizeResult"]
    for name in mechgen.__all__:
        assert getattr(mechgen, name) is not None


def test_the_rate_of_an_output_holding_accelerations_says_it_is_not_available():
    # s["ad"] for an output a = acceleration(...) at level acceleration said "needs a
    # solve at level acceleration", the level the solution had: it needs the jerk
    import pytest
    from mechgen import Model, T, acceleration, velocity
    m = Model("jerk_names")
    g = m.ground("g", points=[(0, 0)])
    b = m.body("b", points=[(0, 0), (1, 0)], guess=(0, 0, 0))
    m.revolute(g[1], b[1])
    m.rotation_lock(b, T ** 2)
    m.output("a", acceleration(b[2])[1])
    m.output("v", velocity(b[2])[1])
    mech = mechgen.compile(m, tier="python")
    s = mech.solve(0.5, level="acceleration")
    # y = sin(t²): y' = 2t cos t², y'' = 2 cos t² − 4t² sin t²
    import math
    assert s["a"] == pytest.approx(2 * math.cos(0.25) - math.sin(0.25), abs=1e-12)
    assert s["vd"] == pytest.approx(s["a"], abs=1e-12)
    for name in ("ad", "add", "vdd"):
        with pytest.raises(KeyError, match="not available.*no third derivative"):
            s[name]
    with pytest.raises(KeyError, match="not available"):
        mech.sweep(0, 1, 3, level="acceleration")["ad"]
    with pytest.raises(KeyError, match=r"'vd' needs a solve at level acceleration \(this "
                                       r"solve is at level velocity\)"):
        mech.solve(0.5, level="velocity")["vd"]


def test_dt_without_a_model_keeps_a_parameter_named_like_another_models_coordinate():
    # dt() without model= took every name any model of the process had as a coordinate:
    # model bmod's parameter L, named like model amod's coordinate L, got a rate Ld.
    # Where bmod also has a coordinate Ld that gave a wrong number with no error.
    import math
    import pytest
    from mechgen import Model, ModelError, T, dt, sin
    a = Model("dt_amod")
    la = a.coordinate("L", 1.0)
    a.constraint(la - T)
    b = Model("dt_bmod")
    length = b.param("L", 2.0)
    x = b.coordinate("x", 0.0)
    ld = b.coordinate("Ld", 0.0)
    b.constraint(x - sin(T))
    b.constraint(ld - 5 * T)
    b.output("v", dt(length * x))
    s = mechgen.compile(b, tier="python").solve(0.3, level="velocity")
    assert s["v"] == pytest.approx(2 * math.cos(0.3), abs=1e-12)      # L x' = 2 cos t
    # L alone is a coordinate in one model and a parameter in another: ambiguous
    with pytest.raises(ModelError, match=r"dt: which of L are coordinates depends on the "
                                         r"model .*dt\(expr, model=m\)"):
        dt(length ** 2)
    assert dt(length ** 2, model=b) == 0
    assert dt(la * T, model=a) == la + T * sp_symbol("Ld")


def sp_symbol(name):
    import sympy
    return sympy.Symbol(name, real=True)


def test_a_symbol_named_like_a_declared_one_but_not_it_is_explained():
    # sympy.Symbol("a") or the text "0.5*T" are not the model's a and T (sympy tells them
    # apart by assumptions): the error said "a is not a declared parameter" of a model
    # that had declared it, and "T is not ... T"
    import pytest
    import sympy
    from mechgen import Model, ModelError
    m = Model("namesakes")
    m.param("a", 2.0)
    g = m.ground("g", points=[(0, 0)])
    with pytest.raises(ModelError, match=r"a \(parameter\): a symbol named like the "
                                         r"model's but not it"):
        m.body("b", points=[(0, sympy.Symbol("a"))], guess=(0, 0, 0))
    b = m.body("b", points=[(0, 0)], guess=(0, 0, 0))
    m.revolute(g[1], b[1])
    with pytest.raises(ModelError, match=r"T \(time\): a symbol named like the model's"):
        m.rotation_lock(b, "0.5*T")
    with pytest.raises(ModelError, match=r"zz is not a declared parameter, coordinate or T "
                                         r"of model 'namesakes'$"):
        m.output("o", sympy.Symbol("zz"))


def test_compile_by_path_rebuilds_when_a_data_file_the_model_reads_changes(tmp_path,
                                                                           monkeypatch):
    # mechgen.compile("model.py") checked the file's text and local imports only: a model
    # reading its dimensions from dims.json kept the module built from the old numbers
    # (x = 2T after dims.json said k = 5) with no error
    import pytest
    monkeypatch.setenv("MECHGEN_CACHE", str(tmp_path / "cache"))
    (tmp_path / "dims.json").write_text('{"k": 2.0}')
    model = tmp_path / "dims_model.py"
    model.write_text(
        "import json, os\n"
        "from mechgen import Model, T\n"
        "dims = json.load(open(os.path.join(os.path.dirname(__file__), 'dims.json')))\n"
        "m = Model('audit_dims')\n"
        "x = m.coordinate('x', 0.0)\n"
        "m.constraint(x - dims['k'] * T)\n")
    assert mechgen.compile(str(model), tier="python").solve(1.0)["x"] == pytest.approx(2.0)
    (tmp_path / "dims.json").write_text('{"k": 5.0}')
    assert mechgen.compile(str(model), tier="python").solve(1.0)["x"] == pytest.approx(5.0)
    assert mechgen.compile(str(model), tier="python").solve(1.0)["x"] == pytest.approx(5.0)


def test_outputs_and_constraints_with_abs_sign_max_mod_build_and_give_their_rates():
    # Abs and sign are names mechgen exports for models; an output |x| (or Max, Mod,
    # floor, frac) failed the build with sympy's "Unsupported by NumbaPrinter:
    # DiracDelta" (a traceback from the command line), a constraint |x| = ... failed
    # likewise, and mech.evaluate(dt(Abs(x), 2), s) raised NameError 'DiracDelta'
    import math
    import pytest
    import sympy
    from mechgen import Abs, Model, T, dt, sign, sin
    m = Model("piecewise_rates")
    x = m.coordinate("x", 0.0)
    y = m.coordinate("y", 3.0)
    m.constraint(x - sin(T))
    m.constraint(Abs(y) - 2 - sin(T))               # y = 2 + sin t from the guess 3
    m.output("mag", Abs(x))
    m.output("sq", sign(x) * x ** 2)
    m.output("top", sympy.Max(x, 0.1))
    m.output("wrap", sympy.Mod(-3 * x, 1))
    m.output("part", sympy.frac(2 * x))
    m.output("step", sympy.floor(4 * x))
    mech = mechgen.compile(m, tier="python")
    t = -0.5                                          # x = sin t < 0
    s = mech.solve(t, level="acceleration")
    sx, cx = math.sin(t), math.cos(t)
    assert (s["y"], s["yd"], s["ydd"]) == pytest.approx((2 + sx, cx, -sx), abs=1e-12)
    expect = {"mag": (-sx, -cx, sx), "sq": (-sx * sx, -2 * sx * cx, -2 * (cx * cx - sx * sx)),
              "top": (0.1, 0.0, 0.0), "wrap": ((-3 * sx) % 1, -3 * cx, 3 * sx),
              "part": ((2 * sx) % 1, 2 * cx, -2 * sx), "step": (math.floor(4 * sx), 0, 0)}
    for name, values in expect.items():
        got = (s[name], s[name + "d"], s[name + "dd"])
        assert got == pytest.approx(values, abs=1e-12), name
    xs = m.coords[0]
    assert mech.evaluate(dt(Abs(xs), 2), s) == pytest.approx(sx, abs=1e-12)
    assert mech.evaluate(dt(sympy.Mod(3 * xs, 1), 2), s) == pytest.approx(-3 * sx, abs=1e-12)
