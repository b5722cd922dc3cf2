"""User names and free text that reach the generated module (labels, docs, names like a
coordinate, a keyword or a table column): models written wrong raise a ModelError naming
the culprit at the line that wrote it, never a module that builds and then fails to load
or returns numbers of a model other than the one written."""
import numpy as np
import pytest

import mechgen
from models import massive_slider_crank as slider_crank
from mechgen import Model, ModelError, T
from mechgen.compiler.build import build


@pytest.fixture(autouse=True)
def _plain_tier(monkeypatch, tmp_path):
    monkeypatch.setenv("MECHGEN_TIER", "python")
    monkeypatch.setenv("MECHGEN_CACHE", str(tmp_path / "cache"))


# -- free text that reaches the generated module ------------------------------------------
@pytest.mark.parametrize("name", ["line1\nline2", "a\rb", "a\x00b", "a\u2028b"])
def test_a_label_with_a_line_break_or_a_control_character_is_refused(name):
    """A constraint named 'line1\\nline2' built a module Python could not read
    (SyntaxError at load, 'rebuild it with mechgen build'); '\\r' one whose content stamp
    no longer matched once read back; the same for a load's and a stage's name."""
    m, base, crank, rod, slider = slider_crank()
    with pytest.raises(ModelError, match="control character") as info:
        m.relative_y(slider[1], 0, name=name)
    assert info.value.where.startswith(__file__)
    with pytest.raises(ModelError, match="control character"):
        m.force(slider[1], (1, 0), name=name)
    with pytest.raises(ModelError, match="control character"):
        m.stage(name, until=0.5)
    assert len(m.constraints) == 5 and not m.loads and not m.stages
    m.relative_y(slider[1], 0, name="ünïcode, 'quotes' \"\"\" and {{ braces }}: fine")


def test_a_model_doc_holding_quotes_backslashes_and_control_characters_builds(tmp_path):
    """A model file whose docstring held \"\"\" (a raw docstring quoting code) or a
    backslash escape Python refuses (\\N{x}) built a module that raised SyntaxError when
    loaded; a NUL or a carriage return one whose stamp did not match."""
    m = Model("doc_quotes")
    x = m.coordinate("x", guess=0.1)
    m.constraint(x - T, name="drive")
    m.doc = 'Quoting code: """inner""" and \'\'\'other\'\'\', \\N{x} \\ and a ""\r\nNUL\x00.'
    mech = mechgen.load(build(m, str(tmp_path)), tier="python")
    assert 'Quoting code: """inner""" and \'\'\'other\'\'\', \\N{x} \\ and a ""\nNUL.' \
        in mech.module.__doc__
    assert abs(mech.solve(0.25)["x"] - 0.25) < 1e-12


def test_a_module_that_would_not_parse_is_never_written(tmp_path, monkeypatch):
    """The last guard: whatever reaches the text unescaped, build refuses before it writes."""
    import mechgen.compiler.context as context
    monkeypatch.setattr(context, "docstring_text", lambda doc: str(doc))
    m = Model("doc_raw")
    x = m.coordinate("x", guess=0.1)
    m.constraint(x - T, name="drive")
    m.doc = 'ends the string """ here'
    with pytest.raises(mechgen.MechgenError, match="would not parse"):
        build(m, str(tmp_path))
    assert not any(p.suffix == ".py" or p.name.startswith(".mechgen") for p in tmp_path.iterdir())


def test_a_body_named_like_its_own_coordinate_leaves_no_trace():
    """m.body("X2", ...) (body 2) was refused only after its name was claimed: the next
    body, m.body("Y3"), then failed with 'coordinate X2 clashes with the body of the same
    name' though no body X2 existed."""
    m = Model("own")
    with pytest.raises(ModelError, match=r"body name 'X2' clashes with the coordinate X2 of "
                                         r"this body"):
        m.body("X2", points=[(0, 0)])
    with pytest.raises(ModelError, match=r"Th2d"):
        m.body("Th2d", points=[(0, 0)])
    assert m.body("Y3", points=[(0, 0)]).number == 2


def test_a_model_name_too_long_for_a_file_name_is_a_model_error(tmp_path):
    """Model('n' * 300) built to an OSError (File name too long) from the file system."""
    with pytest.raises(ModelError, match=r"is 300 bytes long.*within 150 bytes"):
        Model("n" * 300)
    with pytest.raises(ModelError, match=r"is 152 bytes long"):
        Model("é" * 76)
    m = Model("m" * 150)
    x = m.coordinate("x", guess=0.1)
    m.constraint(x - T, name="drive")
    mech = mechgen.load(build(m, str(tmp_path)), tier="python")
    assert abs(mech.solve(0.5)["x"] - 0.5) < 1e-12


# -- user names the runtime binds as keywords or as table columns --------------------------
def _self_index_model():
    m = Model("self_index")
    a, b = m.param("self", 1.0), m.param("index", 2.0)
    x = m.coordinate("x", guess=0.1)
    m.constraint(x - a * T - b, name="drive")
    return m


def test_parameters_named_self_and_index_take_values(tmp_path):
    """with_params(self=3) raised TypeError (multiple values for argument 'self'), and
    so did every design table's sweep(k) of a model with such a parameter."""
    mech = mechgen.load(build(_self_index_model(), str(tmp_path)), tier="python")
    assert abs(mech.with_params(self=3.0).solve(1.0)["x"] - 5.0) < 1e-12     # 3 T + 2
    assert abs(mech.with_params(index=3.0).solve(1.0)["x"] - 4.0) < 1e-12    # T + 3
    tab = mech.sweep(0, 1, 3, params={"self": np.array([1.0, 2.0]),
                                      "index": np.array([5.0, 6.0])})
    np.testing.assert_allclose(tab.sweep(1, 1)["x"], [6.0, 7.0, 8.0], atol=1e-12)
    np.testing.assert_allclose(tab.sweep(self=2.0, index=5.0)["x"], [5.0, 6.0, 7.0],
                               atol=1e-12)
    np.testing.assert_allclose(tab.sweep(0, 1)["x"], [6.0, 6.5, 7.0], atol=1e-12)


def _driven_like_its_coordinate(pin="A"):
    m = Model("col_clash")
    base = m.ground("base", points=[(0, 0)])
    crank = m.body("crank", points=[(0, 0), (1, 0)], guess=(0, 0, 0.1), mass=2.0,
                   inertia=0.1, centroid=(0.5, 0))
    w = m.param("w", 2.0)
    phi = m.coordinate("phi", guess=0.1)
    m.revolute(base[1], crank[1], name=pin)
    m.constraint(phi - crank.th, name="angle")
    m.constraint(phi - w * T - 0.1, name="phi")          # the driver, named as its coordinate
    m.gravity(9.81)
    return m


def test_a_driver_named_like_a_coordinate_gets_a_column_of_its_own(tmp_path):
    """The dynamic sweep's table (CSV, mechgen sweep --level dynamic) held two columns
    'phi', the coordinate and the driver's effort; a reader by name (header.index, the
    CLI's column selection, pandas) took the angle for the torque."""
    mech = mechgen.load(build(_driven_like_its_coordinate(), str(tmp_path)), tier="python")
    sw = mech.sweep(0, 1, 5, level="dynamic")
    header, data = sw.table()
    assert len(set(header)) == len(header) and header.count("phi") == 1
    np.testing.assert_allclose(data[:, header.index("phi")], sw["phi"], atol=0)
    effort = data[:, header.index("phi effort")]
    np.testing.assert_allclose(effort, sw.driver("phi"), atol=0)
    # the crank at constant speed: the torque holds up its weight, m g (L/2) cos(phi)
    np.testing.assert_allclose(np.abs(effort), 2.0 * 9.81 * 0.5 * np.abs(np.cos(sw["phi"])),
                               rtol=1e-9)
    tab = mech.sweep(0, 1, 5, params={"w": np.array([1.0, 2.0])}, level="dynamic")
    header, data = tab.table()
    assert len(set(header)) == len(header) and "phi effort" in header
    np.testing.assert_allclose(data[5:, header.index("phi effort")], effort, rtol=1e-12)
    from mechgen.cli.tables import force_column
    assert force_column(mech, "phi effort") and force_column(mech, "phi")
    # reduce= reads names as the tables do: "phi" the angle (it reduced the torque)
    red = mech.sweep(0, 1, 5, params={"w": np.array([2.0])}, level="dynamic",
                     reduce=["phi", "phi effort"])
    assert abs(red.reduced("phi").max[0] - 2.1) < 1e-12
    assert abs(red.reduced("phi").min[0] - 0.1) < 1e-12
    assert abs(red.reduced("phi effort").max[0] - effort.max()) < 1e-9


def test_two_constraints_of_one_name_get_distinct_reaction_columns(tmp_path):
    """Two constraints named 'angle' (the revolute and the angle's equation) gave two sets
    of columns 'angle on crank fx', ...: they are named by their numbers instead."""
    mech = mechgen.load(build(_driven_like_its_coordinate(pin="angle"), str(tmp_path)),
                        tier="python")
    sw = mech.sweep(0, 1, 3, level="dynamic")
    header, data = sw.table()
    assert len(set(header)) == len(header), [h for h in header if header.count(h) > 1]
    np.testing.assert_allclose(data[:, header.index("1 on crank fx")],
                               sw.reaction(1, on="crank")[:, 0], atol=0)
