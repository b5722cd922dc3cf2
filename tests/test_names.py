"""Any identifier for a parameter, coordinate or output (issue 11): names the generated module
uses for itself (i, k, t, q, p, tol, level, ...), sympy's one-letter names (N, E, I, S) and
names of the code generator's own locals build, print and solve to the same numbers as the
same model with ordinary names; the module reads with the model's names where they are free.
"""
import os
import re

import numpy as np
import pytest

import mechgen
from mechgen import Model, T, location, sin
from mechgen.compiler.build import build, render
from mechgen.model.language import API_NAMES
from mechgen.model.printing import equations_text

# the parameters of the quick-return below, by role, with their defaults
PARAMS = {"x1": 0.0, "y2": 5.0, "x3": 5.0, "y3": 10.0, "x4": 12.0, "crank": 3.0, "lever": 9.0,
          "shoe": 2.0, "speed": 2 * np.pi, "scale": 1.0, "start": 0.0, "rod": 5.0,
          "gain": 1.0}
COORDS = ("slide", "twice", "swing", "kepler")
OUTPUTS = ("stroke", "rate", "turn", "lag", "ratio")
ORDINARY = {**{r: f"par_{r}" for r in PARAMS}, **{r: f"co_{r}" for r in COORDS},
            **{r: f"out_{r}" for r in OUTPUTS}}
# every name of the issue as a parameter
AS_PARAMETERS = dict(ORDINARY, **dict(zip(PARAMS, ("i", "j", "k", "n", "t", "p", "q", "N", "E",
                                                  "I", "S", "tol", "level"))))
# coordinates and outputs with such names (a coordinate q has the velocity qd, as the array)
AS_COORDINATES = dict(ORDINARY, slide="q", twice="t", swing="k", kepler="i", stroke="p",
                      rate="tol", turn="level", lag="N", ratio="j")
# names of the generated module's own locals, arguments, globals and builtins
AS_LOCALS = dict(ORDINARY, **dict(zip(PARAMS, ("out", "math", "np", "njit", "abs", "range",
                                              "info", "piv", "_t0", "_sin_Th3", "N_COORDS",
                                              "_iters", "__x"))),
                 slide="qp", twice="_u", swing="qd_", kepler="det", stroke="ts", rate="STATUS",
                 turn="Q", lag="maxit", ratio="xtol")


def quick_return(name, names):
    """The seed's quick-return with its numbers as parameters and four extra coordinates:
    explicit (slide, twice), a closed form (swing: sin(swing) = sin(Th3)/2) and a Newton
    whose sin and cos the fast sweep turns (kepler + 0.1 sin(kepler) = X4/10)."""
    m = Model(name)
    p = {role: m.param(names[role], value) for role, value in PARAMS.items()}
    base = m.ground("base", points=[(p["x1"], 0), (0, p["y2"]), (-p["x3"], p["y3"]),
                                    (p["x4"], p["y3"])])
    crank = m.body("manivela", points=[(0, 0), (p["crank"], 0)], guess=(0, 5, 0))
    lever = m.body("colisa", points=[(0, 0), (0, p["lever"])], guess=(0, 0, -0.5))
    shoe = m.body("deslizadera", points=[(0, 0), (p["shoe"], 0)], guess=(6, 10, 0))
    m.revolute(base[2], crank[1])
    m.rotation_lock(crank, base, p["speed"] * p["scale"] * T + p["start"], name="crank driver")
    m.revolute(base[1], lever[1])
    m.point_on_line(crank[2], lever.line(1, 2))
    m.relative_distance(lever[2], shoe[1], p["rod"])
    m.translate(base.line(3, 4), shoe.line(1, 2))
    c = {role: m.coordinate(names[role], guess=g)
         for role, g in zip(COORDS, (6.0, -1.0, -0.2, 0.6))}
    m.constraint(c["slide"] - shoe.x, name="slide")
    m.constraint(c["twice"] - 2 * lever.th, name="twice")
    m.constraint(sin(c["swing"]) - sin(lever.th) / 2, name="swing")
    m.constraint(c["kepler"] + 0.1 * p["gain"] * sin(c["kepler"]) - shoe.x / 10, name="kepler")
    m.output(names["stroke"], location(shoe[1])[0])
    m.output(names["rate"], mechgen.velocity(shoe[1])[0] * p["gain"])
    m.output(names["turn"], c["twice"] + c["swing"])
    m.output(names["lag"], c["kepler"] * c["slide"])
    m.output(names["ratio"], mechgen.acceleration(shoe[1])[0])
    return m


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """The four modules, the one whose names are the module's own locals and globals
    under numba (the names numba could stumble on), the others as plain Python (the same
    text: names that work there work compiled, and the compiles cost a minute)."""
    out = str(tmp_path_factory.mktemp("names"))
    models = {"ordinary": ORDINARY, "params": AS_PARAMETERS, "coords": AS_COORDINATES,
              "locals": AS_LOCALS}
    return {key: (names, mechgen.load(build(quick_return(f"names_{key}", names), out),
                                      tier="compiled" if key == "locals" else "python"))
            for key, names in models.items()}


def test_the_issue_names_are_accepted_by_the_model():
    """Each is kept as given: a real symbol of that name, with its default or guess."""
    m = Model("free")
    params = ("i", "j", "k", "n", "t", "p", "q", "N", "E", "I", "S", "tol", "level")
    for k, name in enumerate(params):
        sym = m.param(name, 1.0 + k)
        assert sym.name == name and sym.is_real and m.params[name] == (sym, 1.0 + k)
    coords = ("qq", "info", "out", "math", "abs", "_private")
    for k, name in enumerate(coords):
        sym = m.coordinate(name, guess=0.5 * k)
        assert sym.name == name and m.guess[sym] == 0.5 * k
    assert [c.name for c in m.coords] == list(coords)
    assert list(m.params) == list(params)


def test_keywords_t_and_the_api_stay_refused():
    m = Model("refused")
    for name in ("T", "lambda", "class", "pi", "sin", "location", "Model", "velocity"):
        with pytest.raises(mechgen.ModelError, match="reserved"):
            m.param(name, 1.0)
    # the refused names are mechgen's exported API (less sympy's one-letter constants),
    # kept in step with it
    assert API_NAMES == set(mechgen.__all__) - {"E", "I", "S", "N"}


def test_derived_names_of_coordinates_are_refused():
    m = Model("derived")
    m.coordinate("a")
    with pytest.raises(mechgen.ModelError, match="clashes with the velocity of coordinate 'a'"):
        m.param("ad", 1.0)
    with pytest.raises(mechgen.ModelError, match="clashes with the acceleration"):
        m.output("add", 1.0 * m.coords[0])
    m.param("bd", 1.0)
    with pytest.raises(mechgen.ModelError, match="its velocity bd clashes with the parameter"):
        m.coordinate("b")
    with pytest.raises(mechgen.ModelError, match="velocity of coordinate 'X2'"):
        mm = Model("bodies")
        mm.body("crank", points=[(0, 0)])
        mm.param("X2d", 1.0)


@pytest.mark.parametrize("key", ["params", "coords", "locals"])
def test_equations_print_with_the_model_names(key):
    names = {"params": AS_PARAMETERS, "coords": AS_COORDINATES, "locals": AS_LOCALS}[key]
    text = equations_text(quick_return("printed", names))
    words = set(re.findall(r"\w+", text))
    for role in list(PARAMS) + list(COORDS):
        if role in ("x1", "start"):     # defaults 0: they may cancel in Φ, never in Φ_q
            continue
        assert names[role] in words, (key, role, names[role])


@pytest.mark.parametrize("key", ["params", "coords", "locals"])
def test_same_numbers_as_with_ordinary_names(built, key):
    names, mech = built[key]
    _, ref = built["ordinary"]
    for t in (0.0, 0.13, 0.41, 0.77):
        s, r = mech.solve(t, level="acceleration"), ref.solve(t, level="acceleration")
        assert np.abs(s.q - r.q).max() <= 1e-12
        assert np.abs(s.qd - r.qd).max() <= 1e-12 * (1 + np.abs(r.qd).max())
        assert np.abs(s.qdd - r.qdd).max() <= 1e-12 * (1 + np.abs(r.qdd).max())
        for role in OUTPUTS:
            assert abs(s[names[role]] - r[ORDINARY[role]]) <= 1e-12 * (1 + abs(r[ORDINARY[role]]))
        for role in COORDS:
            assert s[names[role]] == s.q[list(mech.module.COORDINATES).index(names[role])]
            assert abs(s[names[role] + "d"] - r[ORDINARY[role] + "d"]) <= 1e-11
    sw = mech.sweep(0.0, 1.0, 81, level="acceleration")
    rw = ref.sweep(0.0, 1.0, 81, level="acceleration")
    assert np.abs(sw.Q - rw.Q).max() <= 1e-12
    assert np.abs(sw.QD - rw.QD).max() <= 1e-12 * (1 + np.abs(rw.QD).max())
    assert np.abs(sw.QDD - rw.QDD).max() <= 1e-12 * (1 + np.abs(rw.QDD).max())
    assert sw.status.max() == 0 and sw.info[:, 4].max() == 0


def test_the_fast_path_is_taken_with_any_names(built):
    """The written-out step (and its turned sin and cos) serves all four models."""
    for key, (names, mech) in built.items():
        n, ts = mech.n, np.linspace(0.0, 1.0, 81)
        Q, QD, QDD = np.zeros((81, n)), np.zeros((81, n)), np.zeros((81, n))
        done = mech.module.sweep_fast(ts, mech.guess.copy(), mech.p, 1e-10, 1e-10, 50,
                                      Q, QD, QDD, np.zeros((81, 2), dtype=np.int16))
        assert done == 81, key


def test_the_module_reads_with_the_model_names(built):
    text = render(quick_return("names_params", AS_PARAMETERS))
    # free names are kept; names the generated functions use (their arguments, the fast
    # sweep's loop variables) get a trailing underscore. (j is free here: this sweep
    # writes its loops over the coordinates out; the library's own loops over j do not
    # share a scope with the model's names)
    for kept in ("i", "j", "n", "N", "E", "I", "S", "level"):
        assert re.search(rf"^\s+{kept} = p\[\d+\]$", text, re.M), kept
    assert not re.search(r"^\s+for j in", text.split("def sweep_fast(")[1].split("\ndef ")[0],
                         re.M)
    for mangled in ("k", "t", "p", "q", "tol"):
        assert re.search(rf"^\s+{mangled}_ = p\[\d+\]$", text, re.M), mangled
        assert not re.search(rf"^\s+{mangled} = p\[\d+\]$", text, re.M), mangled
    text = render(quick_return("names_coords", AS_COORDINATES))
    assert re.search(r"^\s+q_ = q\[\d+\]$", text, re.M)
    assert re.search(r"^\s+qd_ = qd\[\d+\]$", text, re.M)       # the velocity of q
    # a sweep local named after a coordinate (_sw_det, _sw_qp) keeps the sweep's own
    text = render(quick_return("names_locals", AS_LOCALS))
    body = text[text.index("def sweep_fast("):text.index("def eval_points(")]
    assert "_sw_det = _sw_piv_0" in body and re.search(r"_sw_qp_\d+ = _sw_q_\d+", body)
    assert "_sw_det_ = det" in body                               # the kepler angle's memory
    assert re.search(r"^\s+u_ = q\[\d+\]$", text, re.M)           # _u: underscores to the end


def test_a_memory_named_like_the_sweeps_locals_gives_way(built, tmp_path):
    """The written sweep keeps q[5] as the local _sw_q_5; a coordinate named q_5 (its
    turned sin and cos remembered as _sw_q_5) gets _sw_q_5_ instead, and the sweep's
    numbers are the ordinary model's."""
    names = dict(ORDINARY, kepler="q_5")
    text = render(quick_return("names_scratch", names))
    body = text[text.index("def sweep_fast("):text.index("def eval_points(")]
    assert "_sw_q_5_ = q_5" in body and re.search(r"^\s+_sw_q_5 = ", body, re.M)
    mech = mechgen.load(build(quick_return("names_scratch", names), str(tmp_path)),
                        tier="compiled")
    plain = built["ordinary"][1]
    b = plain.sweep(0.0, 1.0, 201, level="acceleration")
    # the written sweep alone, compiled (the rest of the module is the ordinary one's)
    ts, n = b.t, mech.n
    Q, QD, QDD = np.zeros((201, n)), np.zeros((201, n)), np.zeros((201, n))
    done = mech.module.sweep_fast(ts, mech.guess.copy(), mech.p, 1e-10, 1e-10, 50, Q, QD, QDD,
                                  np.zeros((201, 2), dtype=np.int16))
    assert done > 100           # (it hands the rest, past a hard point, to sweep())
    for A, B in ((Q, b.Q), (QD, b.QD), (QDD, b.QDD)):
        np.testing.assert_allclose(A[:done], B[:done], rtol=1e-12, atol=1e-12)


def test_names_of_the_module_are_read_from_its_sources():
    from mechgen.compiler.codegen.names import identifiers, module_words
    words = module_words()
    for name in ("q", "t", "p", "out", "tol", "xtol", "maxit", "info", "piv", "ts", "q0",
                 "Q", "QD", "QDD", "STATUS", "math", "np", "njit", "abs", "range", "N_COORDS",
                 "_turn", "_gauss", "sweep", "SING_RTOL", "GAVE_UP", "BRANCH_RATIO"):
        assert name in words, name
    # the library's own locals are not: they never share a scope with a model's names
    for name in ("i", "n", "a", "level", "method"):
        assert name not in words, name
    # attributes, strings and comments are not names of the module
    assert identifiers("x = math.sin(y)  # a comment\ns = 'word'\n") == {"x", "math", "y", "s"}


def test_mangled_names_are_unique():
    from sympy import Symbol
    from mechgen.compiler.codegen.names import Names
    syms = [Symbol(x, real=True) for x in ("q", "q_", "_q", "k")]
    names = Names(syms, {"q", "k", "k_"})
    idents = [names.ident(s) for s in syms]
    assert idents == ["q__", "q_", "q___", "k__"]
    assert len(set(idents)) == len(idents)


def test_model_files_may_use_such_names(tmp_path):
    path = tmp_path / "named.py"
    path.write_text(
        "from mechgen import Model, T\n"
        "m = Model('named_file')\n"
        "k = m.param('k', 2.0)\n"
        "q = m.coordinate('q', guess=0.1)\n"
        "t = m.coordinate('t', guess=0.1)\n"
        "m.constraint(q - k * T, name='drive')\n"
        "m.constraint(t ** 3 + t - q, name='cubic')\n"
        "m.output('p', q + t)\n")
    # plain Python, as ``built``'s: the names numba could stumble on are compiled there
    mech = mechgen.load(build(mechgen.load_model(str(path)), str(tmp_path)), tier="python")
    s = mech.solve(0.5, level="acceleration")
    assert abs(s["q"] - 1.0) < 1e-12 and abs(s["t"] ** 3 + s["t"] - 1.0) < 1e-12
    assert abs(s["p"] - s["q"] - s["t"]) < 1e-12 and abs(s["qd"] - 2.0) < 1e-12
    assert os.path.exists(tmp_path / "named_file.py")
