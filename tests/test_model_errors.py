"""Malformed models: each raises mechgen.ModelError whose message names the culprit, and,
when the model comes from a file, whose ``where`` is that file's line; joints, loads and
masses that act on nothing, complex numbers, and symbols or axes of another model are
refused where they are written."""
import os
from cli_runs import write

import numpy as np
import pytest
import sympy as sp

import mechgen
from models import massive_slider_crank as slider_crank
from mechgen import Line, Model, ModelError, T
from mechgen.compiler.build import build, render
from mechgen.model.loader import load_models, pick_model

HERE = os.path.abspath(__file__)


def seed_model(name="quick_return"):
    """The quick-return's bodies without constraints."""
    m = Model(name)
    m.param("longitud", 3.0)
    base = m.ground("base", points=[(0, 0), (0, 5), (-5, 10), (12, 10)])
    manivela = m.body("manivela", points=[(0, 0), (3, 0)], guess=(0, 5, 0))
    colisa = m.body("colisa", points=[(0, 0), (0, 9)], guess=(0, 0, -0.5))
    deslizadera = m.body("deslizadera", points=[(0, 0), (2, 0)], guess=(6, 10, 0))
    return m, base, manivela, colisa, deslizadera


def raises(match, func, *args, **kwargs):
    with pytest.raises(ModelError, match=match) as info:
        func(*args, **kwargs)
    return info.value


# -- points, bodies, axes -----------------------------------------------------------------
def test_unknown_point_index():
    m, base, manivela, colisa, _ = seed_model()
    err = raises(r"body 'colisa' has 2 points; point 3 does not exist", colisa.__getitem__, 3)
    assert err.where and err.where.startswith(HERE + ":")       # this test file's line
    raises(r"body 'colisa' has 2 points; point -1", colisa.__getitem__, -1)
    raises(r"body 'colisa': a point index must be an integer, got 1.5", colisa.__getitem__, 1.5)
    raises(r"body 'base' has 4 points; point 5", lambda: m.point_on_line(manivela[2],
                                                                         base.line(3, 5)))


def test_point_of_another_model():
    m, base, *_ = seed_model()
    other, _, _, other_colisa, _ = seed_model("other_model")
    err = raises(r"revolute: argument 2 \(point colisa\[1\]\) belongs to model 'other_model', "
                 r"not to model 'quick_return'", m.revolute, base[1], other_colisa[1])
    assert "use the bodies of this model" in str(err)
    # two models of the same name: the message says where the other one was declared
    twin, _, _, twin_colisa, _ = seed_model()
    err = raises(r"another model also named 'quick_return' \(declared at ", m.revolute,
                 base[1], twin_colisa[1])
    raises(r"rotation_lock: argument 2 \(body base\) belongs to model 'quick_return'",
           other.rotation_lock, other_colisa, base, 0.3)
    raises(r"Line\(base\[1\], colisa\[1\]\): the points belong to different models",
           Line, base[1], other_colisa[1])


def test_body_looked_up_before_it_is_declared():
    m = Model("early")
    m.ground("base", points=[(0, 0)])
    raises(r"model 'early' has no body named 'colisa' \(declared: base\)", m.__getitem__,
           "colisa")
    m.body("colisa", points=[(0, 0), (0, 9)])
    assert m["colisa"].name == "colisa"


def test_constraint_with_the_wrong_kind_of_argument():
    m, base, manivela, colisa, deslizadera = seed_model()
    raises(r"revolute: argument 1 must be a point such as body\[1\], got body colisa",
           m.revolute, colisa, base[1])
    raises(r"point_on_line: argument 2 must be an axis .* got point base\[1\]",
           m.point_on_line, manivela[2], base[1])
    raises(r"translate: argument 1 must be an axis .* got point colisa\[1\]",
           m.translate, colisa[1], deslizadera.line(1, 2))
    raises(r"rotation_lock: argument 1 must be a body, got point colisa\[1\]",
           m.rotation_lock, colisa[1], 0.3)
    raises(r"relative_distance: the distance: cannot read 'x\+' as a number",
           m.relative_distance, colisa[2], deslizadera[1], "x+")
    raises(r"relative_x: argument 1 must be a point .* got 3", m.relative_x, 3, 4)
    raises(r"revolute: too many arguments \(base\[2\] is one too many\)",
           m.revolute, colisa[1], base[1], base[2])
    assert not m.constraints                      # nothing half-added


def test_axis_without_direction():
    m, base, manivela, colisa, _ = seed_model()
    raises(r"axis colisa.line\(1, 1\) has no direction", colisa.line, 1, 1)
    raises(r"has no direction", Line, colisa[1], direction=(0, 0))
    raises(r"Line takes a second point or direction=", Line, colisa[1])
    raises(r"Line: the first argument must be a point .* got body colisa", Line, colisa, base[1])


def test_equation_without_a_coordinate():
    m, base, manivela, colisa, _ = seed_model()
    raises(r"constraint 1 revolute\(colisa\[1\], colisa\[1\]\): its x equation reads 0 = 0 "
           r"and involves no coordinate", m.revolute, colisa[1], colisa[1])
    raises(r"constraint 1 rotation_lock\(base, .*\): its equation .* involves no coordinate",
           m.rotation_lock, base, 0.5)
    raises(r"constraint\(T - 1\): the expression holds no coordinate of model 'quick_return'",
           m.constraint, T - 1)


# -- names and parameters -------------------------------------------------------------------
def test_parameter_name_clashes():
    m, *_ = seed_model()
    raises(r"parameter name 'X2' clashes with the coordinate of body 'manivela'", m.param,
           "X2", 1.0)
    raises(r"parameter name 'longitud' clashes with the parameter of the same name", m.param,
           "longitud", 2.0)
    raises(r"parameter name 'manivela' clashes with the body", m.param, "manivela", 1.0)
    raises(r"parameter name 'T' is reserved", m.param, "T", 1.0)
    raises(r"parameter name 'pi' is reserved", m.param, "pi", 1.0)
    raises(r"parameter name 'lambda' is reserved", m.param, "lambda", 1.0)
    # a parameter that takes the name of a body's future coordinate
    m.param("X5", 1.0)
    raises(r"coordinate of body 'extra' name 'X5' clashes with the parameter", m.body,
           "extra", points=[(0, 0)])
    assert "extra" not in m.bodies and len(m.coords) == 9       # the model is unchanged
    raises(r"coordinate name 'Th3' clashes with the coordinate of body 'colisa'",
           m.coordinate, "Th3")


def test_names_that_are_not_identifiers():
    raises(r"Model name 'my model' must be a Python identifier", Model, "my model")
    raises(r"Model name 'class' must be a Python identifier", Model, "class")
    m = Model("names")
    raises(r"body name 'my body' must be an identifier", m.body, "my body", points=[])
    raises(r"body name '2nd' must be an identifier", m.ground, "2nd", points=[])
    raises(r"parameter name '' must be an identifier", m.param, "", 1.0)


def test_parameter_defaults_must_be_numbers():
    m = Model("defaults")
    raises(r"parameter 'w': the default must be a number, got 'abc'", m.param, "w", "abc")
    raises(r"parameter 'w': the default must be a number, got T", m.param, "w", T)
    raises(r"parameter 'w': the default must be finite", m.param, "w", float("inf"))
    raises(r"parameter 'w': the default must be a number, got True", m.param, "w", True)
    assert not m.params                           # failed declarations leave no trace
    assert m.param("w", sp.pi / 2) is not None             # a number, symbolic or not


def test_undeclared_symbols():
    m, base, manivela, colisa, _ = seed_model()
    zz = sp.Symbol("zz")
    raises(r"constraint\(expr\): zz is not a declared parameter, coordinate or T of model",
           m.constraint, colisa.x - zz)
    raises(r"rotation_lock: the angle: omega is not a declared parameter or T",
           m.rotation_lock, manivela, base, sp.Symbol("omega") * T)
    raises(r"point 2 of body 'crank': L is not a declared parameter", m.body, "crank",
           points=[(0, 0), (sp.Symbol("L"), 0)])
    raises(r"point 1 of body 'c2': X3 is not a declared parameter \(points may hold "
           r"parameters only\)", m.body, "c2", points=[(colisa.x, 0)])


def test_guesses():
    m = Model("guesses")
    raises(r"body 'c': guess must be \(x, y, th\), got \(1, 2\)", m.body, "c",
           points=[(0, 0)], guess=(1, 2))
    raises(r"body 'c': guess must be \(x, y, th\)", m.body, "c", points=[(0, 0)], guess=3)
    raises(r"body 'c': guess of Th2 may not depend on T", m.body, "c", points=[(0, 0)],
           guess=(0, 0, T))
    raises(r"coordinate 'theta': guess: cannot read", m.coordinate, "theta", guess="?")
    assert not m.bodies and not m.coords


def test_points_must_be_pairs():
    m = Model("pairs")
    raises(r"point 1 of body 'c' must be a pair \(x, y\), got \(1, 2, 3\)", m.body, "c",
           points=[(1, 2, 3)])
    raises(r"body 'c': points must be a list of \(x, y\) pairs, got 'abc'", m.body, "c",
           points="abc")


def test_two_grounds():
    m, *_ = seed_model()
    raises(r"model 'quick_return' already has a ground \('base'\); one ground per model",
           m.ground, "floor", points=[(0, 0)])


def test_outputs():
    m, base, manivela, colisa, _ = seed_model()
    raises(r"output 'tip': give one scalar per output", m.output, "tip",
           mechgen.location(colisa[2]))
    m.output("tip_x", mechgen.location(colisa[2])[0])
    raises(r"output name 'tip_x' clashes with the output", m.output, "tip_x", colisa.x)
    raises(r"output 'w': zz is not a declared parameter, coordinate", m.output, "w",
           sp.Symbol("zz"))
    m.output("w", colisa.th)                      # the failed declaration left 'w' free


def test_empty_and_unconstrained_models():
    raises(r"model 'empty' has no coordinates: declare a body or a coordinate",
           Model("empty").equations)
    m, *_ = seed_model()
    raises(r"model 'quick_return' has no constraints", m.equations)


# -- square systems: `check` reports, `build` refuses fewer equations than coordinates ------
def fourbar_without_driver():
    m = Model("free4")
    g = m.ground("ground", points=[(0, 0), (3, 0)])
    crank = m.body("crank", points=[(0, 0), (0.8, 0)], guess=(0, 0, 1.0))
    coupler = m.body("coupler", points=[(0, 0), (2.5, 0)], guess=(0.4, 0.7, 0.5))
    rocker = m.body("rocker", points=[(0, 0), (2, 0)], guess=(3, 0, 1.8))
    m.revolute(g[1], crank[1])
    m.revolute(crank[2], coupler[1])
    m.revolute(g[2], rocker[1])
    m.revolute(coupler[2], rocker[2])
    return m


def test_non_square_model_expands_but_does_not_build():
    from mechgen.compiler.build import render
    m = fourbar_without_driver()
    eq = m.equations()                              # `mechgen check` needs these
    assert eq.phi_q.shape == (8, 9)
    err = raises(r"model 'free4' is not square: 8 equations for 9 coordinates", render, m)
    text = str(err)
    assert "1 equation missing: add a driver or a constraint" in text
    assert "no driver" in text
    # the coordinates the equations leave free (crank, coupler and rocker angles, the
    # coupler's origin), not the pinned ones
    assert "Left free at the guess: Th2, X3, Y3, Th3, Th4." in text
    assert err.where == m._where


def test_redundant_model_builds(tmp_path):
    """More equations than coordinates is allowed: the solver handles consistent redundancy."""
    from mechgen.compiler.build import render
    m = fourbar_without_driver()
    m.rotation_lock(m["crank"], 1.0 + T)
    m.relative_y(m["crank"][1], 0, name="redundant")        # the revolute already holds it
    assert m.equations().phi_q.shape == (10, 9)
    assert "def phi(" in render(m)


# -- model files -------------------------------------------------------------------------------
def test_file_that_raises_names_its_line(tmp_path):
    path = write(tmp_path, """
        from mechgen import Model
        m = Model("broken")
        base = m.ground("base", points=[(0, 0)])
        crank = m.body("crank", points=[(0, 0), (1, 0)])
        m.revolute(base[1], crnk[1])
    """)
    err = raises(r"the model file raised NameError: name 'crnk' is not defined", load_models,
                 path)
    assert err.where == f"{path}:5"
    assert str(err).startswith(f"{path}:5: ")


def test_model_error_in_a_file_names_its_line(tmp_path):
    path = write(tmp_path, """
        from mechgen import Model
        m = Model("broken")
        base = m.ground("base", points=[(0, 0)])
        colisa = m.body("colisa", points=[(0, 0), (0, 9)])

        m.point_on_line(base[1], colisa.line(1, 3))
    """)
    err = raises(r"body 'colisa' has 2 points; point 3 does not exist", load_models, path)
    assert err.where == f"{path}:6"


def test_wrong_argument_in_a_file_names_its_line(tmp_path):
    path = write(tmp_path, """
        from mechgen import Model
        m = Model("broken")
        base = m.ground("base", points=[(0, 0)])
        colisa = m.body("colisa", points=[(0, 0), (0, 9)])
        m.revolute(colisa,
                   base[1])
    """)
    err = raises(r"revolute: argument 1 must be a point such as body\[1\], got body colisa",
                 load_models, path)
    assert err.where in (f"{path}:5", f"{path}:6")     # the statement (3.11+: its first line)


def test_syntax_error_file(tmp_path):
    path = write(tmp_path, """
        from mechgen import Model
        m = Model("broken"
        x = 1
    """)
    err = raises(r"syntax error", load_models, path)
    assert err.where.startswith(f"{path}:")


def test_file_without_models_and_missing_file(tmp_path):
    path = write(tmp_path, "x = 1\n")
    err = raises(r"the file defines no mechgen.Model at module level", load_models, path)
    assert err.where == path
    raises(r"does not exist", load_models, str(tmp_path / "nope.py"))


def test_non_square_file_names_the_model_line(tmp_path):
    from mechgen.compiler.build import render
    path = write(tmp_path, """
        from mechgen import Model
        # a slider without its driver
        m = Model("loose")
        base = m.ground("base", points=[(0, 0), (1, 0)])
        block = m.body("block", points=[(0, 0), (1, 0)])
        m.translate(base.line(1, 2), block.line(1, 2))
    """)
    model = load_models(path)[0]
    err = raises(r"model 'loose' is not square: 2 equations for 3 coordinates", render, model)
    assert err.where == f"{path}:3"
    assert "Left free at the guess: X2." in str(err)


def test_pick_model(tmp_path):
    path = write(tmp_path, """
        from mechgen import Model, T
        a = Model("first")
        b = Model("second")
    """)
    models = load_models(path)
    assert [m.name for m in models] == ["first", "second"]
    raises(r"the file defines several models \(first, second\); choose one with --model",
           pick_model, models, None)
    raises(r"no model named 'third' in the file \(it defines first, second\)", pick_model,
           models, "third")
    assert pick_model(models, "second").name == "second"


@pytest.fixture
def _plain_tier(monkeypatch, tmp_path):
    monkeypatch.setenv("MECHGEN_TIER", "python")
    monkeypatch.setenv("MECHGEN_CACHE", str(tmp_path / "cache"))


# -- joints, loads and masses that act on nothing ------------------------------------------
@pytest.mark.parametrize("call", [
    lambda m, b: m.revolute(b[1], b[2]),
    lambda m, b: m.relative_distance(b[1], b[2], 0.2),
    lambda m, b: m.orthogonal(b.line(1, 2), b.line(1, 2)),
    lambda m, b: m.parallel(b.line(1, 2), Line(b[0], direction=(0, 1))),
], ids=["revolute", "distance", "orthogonal", "parallel"])
def test_a_joint_between_a_body_and_itself_is_refused(call):
    """revolute(crank[1], crank[2]) (its rows -0.2 cos Th2, -0.2 sin Th2 can never hold),
    relative_distance within one body (0.04 - 0.04 = 0 always) and orthogonal(a, a) were
    accepted, leaving a model that fails (or is short of an equation) when solved."""
    m, base, crank, rod, slider = slider_crank()
    with pytest.raises(ModelError, match=r"fixed in body 'crank'.* relates two bodies") as info:
        call(m, crank)
    assert info.value.where.startswith(__file__)
    assert len(m.constraints) == 5
    m.relative_y(crank[1], crank[2], 0.0, name="level")   # one body's angle: allowed


def test_loads_that_act_on_nothing_are_refused():
    """A force at a point of the ground, a moment on the ground (or +M and -M on one
    body), a spring or damper with both ends in one body were accepted and then dropped
    from every equation: the forces solved as if they were not there."""
    m, base, crank, rod, slider = slider_crank()
    for call, words in [
        (lambda: m.force(base[2], (100, 0), name="press"),
         r"point base\[2\] is fixed in the ground"),
        (lambda: m.moment(base, 5.0), r"moment\(base, \.\.\.\): it acts on the ground"),
        (lambda: m.moment(crank, crank, 5.0), r"body 'crank' twice"),
        (lambda: m.spring(rod[1], rod[2], 100, 0.5), r"both ends are fixed in body 'rod'"),
        (lambda: m.spring(base[1], base[3], 100, 0.5), r"both ends are fixed in body 'base'"),
        (lambda: m.damper(slider[1], slider[2], 3), r"both ends are fixed in body 'slider'"),
    ]:
        with pytest.raises(ModelError, match=words):
            call()
    assert not m.loads
    m.moment(crank, base, 5.0, name="motor")            # between a body and the ground: fine


def test_springs_and_dampers_of_no_or_negative_stiffness_are_refused():
    m, base, crank, rod, slider = slider_crank()
    kk = m.param("kk", -5.0)
    for call, words in [
        (lambda: m.spring(slider[1], base[3], 0, 0.5), r"the stiffness k 0 is zero"),
        (lambda: m.spring(slider[1], base[3], -100, 0.5), r"the stiffness k -100 is negative"),
        (lambda: m.spring(slider[1], base[3], kk, 0.5), r"k kk is negative \(-5 at the param"),
        (lambda: m.spring(slider[1], base[3], 100, -0.5), r"free length -0.5 is negative"),
        (lambda: m.damper(slider[1], base[3], -2), r"the coefficient c -2 is negative"),
        (lambda: m.damper(slider[1], base[3], 0), r"the coefficient c 0 is zero"),
    ]:
        with pytest.raises(ModelError, match=words):
            call()
    assert not m.loads
    m.spring(slider[1], base[3], 100, 0, name="zero free length")      # allowed


def test_a_complex_mass_is_a_model_error():
    """mass=1+2j raised a bare TypeError (Cannot convert complex to float)."""
    m = Model("cmass")
    with pytest.raises(ModelError, match=r"body 'c': mass: 1\.0 \+ 2\.0\*I is complex"):
        m.body("c", points=[(0, 0)], mass=1 + 2j)
    with pytest.raises(ModelError, match=r"body 'c': inertia: .* is complex"):
        m.body("c", points=[(0, 0)], mass=1, inertia=mechgen.sqrt(-2))
    assert not m.bodies


def test_a_model_without_a_ground_says_so():
    m = Model("floating")
    a = m.body("a", points=[(0, 0), (1, 0)], guess=(0, 0, 0))
    b = m.body("b", points=[(0, 0), (1, 0)], guess=(1, 0, 0))
    m.revolute(a[2], b[1])
    m.rotation_lock(a, T)
    with pytest.raises(ModelError, match=r"not square.*The model has no ground \(m\.ground"):
        render(m)


@pytest.mark.parametrize("call", [
    lambda m, b: m.force(b[1], (mechgen.I, 0)),
    lambda m, b: m.moment(b, 2 * mechgen.I),
    lambda m, b: m.gravity(9.81 * mechgen.I),
    lambda m, b: m.spring(b[1], m["base"][1], mechgen.sqrt(-4), 1),
    lambda m, b: m.body("d", points=[(0, 0)], guess=(mechgen.I, 0, 0)),
    lambda m, b: m.body("d", points=[(0, 0)], mass=1, centroid=(0, mechgen.I)),
    lambda m, b: m.coordinate("d", guess=1 + mechgen.I),
], ids=["force", "moment", "gravity", "spring", "guess", "centroid", "coordinate"])
def test_complex_loads_guesses_and_centroids_are_model_errors(call):
    m, base, crank, rod, slider = slider_crank()
    with pytest.raises(ModelError, match=r"is complex \(it holds I\)"):
        call(m, slider)
    assert not m.loads and m.gravity_vector is None and len(m.coords) == 9


def test_gravity_of_negative_magnitude_is_refused():
    """m.gravity(-9.81) (downwards twice over) made gravity point up, with no word."""
    m, *_ = slider_crank()
    with pytest.raises(ModelError, match=r"g = -9\.81 is negative: g is the magnitude"):
        m.gravity(-9.81)
    assert m.gravity_vector is None
    m.gravity(9.81, direction=(0, 1))          # upwards, said so: fine
    assert m.gravity_vector == (0, 9.81)


def test_a_force_along_an_axis_of_another_model_is_refused():
    """force(p, f, along=<an axis of another model>) was accepted: its direction, written
    in that model's Th2, was read as this model's Th2 (another body)."""
    other, *_, other_rod, _ = slider_crank("other")
    m, base, crank, rod, slider = slider_crank()
    with pytest.raises(ModelError, match=r"along= rod.line\(1, 2\) belongs to model 'other'"):
        m.force(slider[1], 10.0, along=other_rod.line(1, 2))
    assert not m.loads
    m.force(slider[1], 10.0, along=rod.line(1, 2))


def test_a_numpy_integer_indexes_a_point():
    """body[np.int64(2)] (a loop over np.arange) was refused: 'a point index must be an
    integer, got np.int64(2)'."""
    m, base, crank, rod, slider = slider_crank()
    assert crank[np.int64(2)].label == "crank[2]"
    assert repr(rod.line(np.int32(1), np.int64(2))) == "rod.line(1, 2)"
    with pytest.raises(ModelError, match="must be an integer"):
        crank[np.float64(2.0)]


@pytest.mark.xfail(strict=True, reason="a body's coordinate symbols are sympy Symbols named "
                   "X<n>, Y<n>, Th<n>: another model's are the same symbols, so an expression "
                   "written with them cannot be told apart (needs model-owned symbols)")
def test_an_expression_in_another_models_coordinates_is_refused():
    """Two models in one file: B.output('o', location(a1[2])[0]) with a1 a body of model A
    is accepted and reads B's X2, Th2 (B's body 2, another body)."""
    from mechgen import location
    a = Model("model_a")
    a.ground("g", points=[(0, 0)])
    a1 = a.body("a1", points=[(0, 0), (1, 0)])
    b = Model("model_b")
    b.ground("g", points=[(0, 0)])
    b.body("b1", points=[(0, 0), (2, 0)])
    with pytest.raises(ModelError, match="model_a"):
        b.output("o", location(a1[2])[0])


@pytest.mark.usefixtures("_plain_tier")
def test_a_spring_whose_ends_meet_is_a_singular_error_not_a_zero_division(tmp_path):
    """A spring of free length 0.5 from a crank's tip to the ground point the tip passes
    at t=0: solve(0, level="static"/"dynamic"), the force sweep and simulate raised a bare
    ZeroDivisionError from the generated code (both tiers). Away from it the torque is
    the spring's moment: k (L - L0) / L * sin(2t), L = 2 sin(t) (100 (0.19967 - 0.5)
    / 0.19967 * 0.19867 = -29.883 at t = 0.1)."""
    m = Model("spring_meets")
    g = m.ground("g", points=[(0, 0), (1, 0)])
    crank = m.body("crank", points=[(0, 0), (1, 0)], guess=(0, 0, 0.0), mass=1.0,
                   inertia=0.1, centroid=(0.5, 0))
    m.revolute(g[1], crank[1])
    m.rotation_lock(crank, 2 * T, name="drive")
    kk = m.param("kk", 100.0)
    m.spring(crank[2], g[2], kk, 0.5, name="spr")
    mech = mechgen.load(build(m, str(tmp_path)), tier="python")
    kks = {"kk": np.array([50.0, 100.0])}
    for call in (lambda: mech.sweep(0, 1, 3, params=kks, level="dynamic").driver("drive"),
                 lambda: mech.sweep(0, 1, 3, params=kks, level="dynamic", reduce=["drive"]),
                 lambda: mech.solve(0.0, level="static"),
                 lambda: mech.solve(0.0, level="dynamic"),
                 lambda: mech.sweep(0, 1, 3, level="dynamic"),
                 lambda: mech.simulate(0, 0.2, 3, free=["drive"])):
        with pytest.raises(mechgen.SingularError, match=r"divide by zero.*spr \(spring\)"):
            call()
    L = 2 * np.sin(0.1)
    expected = 100.0 * (L - 0.5) / L * np.sin(0.2)
    assert abs(abs(mech.solve(0.1, level="dynamic").driver("drive")) - abs(expected)) < 1e-9
