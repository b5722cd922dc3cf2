"""Second audit of the model language and command line (API.md §1-3): defects found,
each pinned by a small case."""
import subprocess
import sys

import mechgen


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
