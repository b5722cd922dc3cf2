"""A model's units as a first-class choice (docs/reference/model.md "Units", issue 43): declared
with ``Model(..., units=...)``, stated in the generated module's header (UNITS) and read back by the
runtime, so that CSV headers, the pictures, ``mechgen forces`` and the live view say them;
``m.gravity()`` is standard gravity in them.

The reference for the numbers is dimensional analysis, not mechgen: the shaper of
examples/quick_return_forces.py written in millimetres with masses in tonnes (mm-N-s) must
give its driver torque in N·mm equal to the SI model's N·m times 1000, its forces in N
equal, its lengths times 1000."""
import csv
import math

import numpy as np
import pytest

import mechgen
from mechgen import Model, Piecewise, T, pi, velocity
from mechgen.units import STANDARD_GRAVITY, parse


def shaper(units, name):
    """examples/quick_return_forces.py in ``units`` ("SI": m, kg; "mm-N-s": mm, t), with
    standard gravity taken from the units (m.gravity())."""
    L = 1000.0 if units == "mm-N-s" else 1.0        # length of a metre
    M = 1e-3 if units == "mm-N-s" else 1.0          # mass of a kilogram
    m = Model(name, units=units)
    longitud = m.param("longitud", 3.0 * L)
    velocidad = m.param("velocidad", 2 * pi)
    corte = m.param("corte", 500.0)                 # N in both
    base = m.ground("base", points=[(0, 0), (0, 5 * L), (-5 * L, 10 * L), (12 * L, 10 * L)])
    manivela = m.body("manivela", points=[(0, 0), (longitud, 0)], guess=(0, 5 * L, 0),
                      mass=2.0 * M, inertia=1.5 * M * L * L, centroid=(longitud / 2, 0))
    colisa = m.body("colisa", points=[(0, 0), (0, 9 * L)], guess=(0, 0, -0.5),
                    mass=5.0 * M, inertia=33.75 * M * L * L, centroid=(0, 4.5 * L))
    deslizadera = m.body("deslizadera", points=[(0, 0), (2 * L, 0)], guess=(6 * L, 10 * L, 0),
                         mass=3.0 * M, inertia=1.0 * M * L * L, centroid=(1 * L, 0.2 * L))
    m.revolute(base[2], manivela[1], name="O2")
    m.rotation_lock(manivela, base, velocidad * T, name="crank driver")
    m.revolute(base[1], colisa[1], name="O4")
    m.point_on_line(manivela[2], colisa.line(1, 2), name="slot")
    m.relative_distance(colisa[2], deslizadera[1], 5 * L, name="link")
    m.translate(base.line(3, 4), deslizadera.line(1, 2), name="guide")
    m.gravity()
    speed = velocity(deslizadera[1])[0]
    m.force(deslizadera[1], (Piecewise((corte, speed < 0), (0, True)), 0), name="cutting")
    return m


@pytest.fixture(scope="module")
def pair(tmp_path_factory):
    out = str(tmp_path_factory.mktemp("gen"))
    si = mechgen.compile(shaper("SI", "shaper_si"), outdir=out, tier="python")
    mm = mechgen.compile(shaper("mm-N-s", "shaper_mm"), outdir=out, tier="python")
    return si, mm


TIMES = (0.0, 1.0, 37)      # one crank turn, away from the slider's dead centres


def test_the_torque_in_newton_millimetres_is_the_si_torque_times_1000(pair):
    si, mm = pair
    a = si.sweep(*TIMES, level="dynamic")
    b = mm.sweep(*TIMES, level="dynamic")
    ta, tb = a.driver("crank driver"), b.driver("crank driver")
    assert np.all(np.isfinite(ta)) and np.max(np.abs(ta)) > 100      # a real load
    np.testing.assert_allclose(tb, 1000.0 * ta, rtol=1e-9, atol=1e-9 * np.max(np.abs(tb)))
    fa, fb = a.reaction("O2", on="manivela"), b.reaction("O2", on="manivela")
    top = np.max(np.abs(fa[:, :2]))
    np.testing.assert_allclose(fb[:, :2], fa[:, :2], rtol=1e-9, atol=1e-9 * top)   # N, N
    np.testing.assert_allclose(b["X4"], 1000.0 * a["X4"], rtol=1e-12, atol=1e-9)


def test_standard_gravity_in_the_models_units():
    assert shaper("SI", "g_si").gravity_vector[1] == pytest.approx(-STANDARD_GRAVITY, 1e-15)
    assert shaper("mm-N-s", "g_mm").gravity_vector[1] == pytest.approx(-9806.65, 1e-15)
    assert parse({"length": "cm", "mass": "g", "time": "s"}).gravity == \
        pytest.approx(980.665, 1e-15)
    m = Model("no_units")
    with pytest.raises(mechgen.ModelError, match=r"declares none.*units=\"SI\""):
        m.gravity()


@pytest.mark.parametrize("spec, said", [
    ("cgs", r"'cgs' is not a system mechgen knows"),
    ({"length": "mm", "mass": "kg"}, r"give time too"),
    ({"length": "mm", "mass": "kg", "time": "s", "force": "N"}, r"unknown key\(s\) 'force'"),
    ({"length": "furlong", "mass": "kg", "time": "s"}, r"length 'furlong' is not one"),
    ({"length": "m", "mass": "kg", "time": "s", "angle": "grad"}, r"angle 'grad'"),
])
def test_units_not_understood_are_refused_naming_them(spec, said):
    with pytest.raises(mechgen.ModelError, match=rf"model 'bad': .*{said}"):
        Model("bad", units=spec)


def test_derived_units_are_named():
    mm = parse("mm-N-s")
    assert (mm.force, mm.of("torque"), mm.of("inertia"), mm.of("length", 2)) == \
        ("N", "N·mm", "t·mm²", "mm/s²")
    si = parse("SI")
    assert (si.of("energy"), si.of("power"), si.of("angle", 1)) == ("J", "W", "rad/s")
    assert parse({"length": "mm", "mass": "kg", "time": "s"}).force == "mN"
    assert parse({"length": "m", "mass": "kg", "time": "s", "angle": "deg"}).of("angle", 1) \
        == "deg/s"


def test_the_header_states_units_only_where_declared(pair):
    si, mm = pair
    assert mm.module.UNITS == {"length": "mm", "mass": "t", "time": "s", "angle": "rad"}
    assert si.module.UNITS["length"] == "m"
    from mechgen.compiler.render import render
    m = shaper("SI", "plain")
    m.units = parse(None)
    text = render(m)
    assert "UNITS" not in text          # a model without a declaration: nothing new


def test_csv_and_forces_printout_say_the_units(pair, tmp_path, capsys):
    si, mm = pair
    sw = mm.sweep(*TIMES, level="dynamic")
    path = tmp_path / "mm.csv"
    sw.to_csv(str(path))
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    head = rows[0]
    for name in ("T [s]", "X4 [mm]", "Th3 [rad]", "X4d [mm/s]", "Th3dd [rad/s²]",
                 "crank driver [N·mm]", "O2 on manivela fx [N]", "O2 on manivela m [N·mm]"):
        assert name in head, (name, head)
    k = head.index("crank driver [N·mm]")
    torque = np.array([float(r[k]) for r in rows[1:]])
    ref = si.sweep(*TIMES, level="dynamic").driver("crank driver")
    np.testing.assert_allclose(torque, 1000 * ref, rtol=1e-9, atol=1e-6)


def test_degrees_are_shown_not_computed(tmp_path):
    m = shaper("SI", "shaper_deg")
    m.units = parse({"length": "m", "mass": "kg", "time": "s", "angle": "deg"})
    mech = mechgen.compile(m, outdir=str(tmp_path), tier="python")
    sw = mech.sweep(0.0, 0.5, 5, level="velocity")
    assert abs(sw["Th2"][-1] - math.pi) < 1e-9         # computed in radians
    path = tmp_path / "deg.csv"
    sw.to_csv(str(path))
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    k = rows[0].index("Th2 [deg]")
    assert float(rows[-1][k]) == pytest.approx(180.0, abs=1e-7)
    assert "Th2d [deg/s]" in rows[0] and "X4 [m]" in rows[0]


def test_a_design_tables_csv_says_the_units(pair, tmp_path):
    # a long table (every point) and a table of reductions: lengths in mm equal to the SI
    # model's metres times 1000, the extremes' times in s
    si, mm = pair
    rows = {}
    for name, mech, scale in (("si", si, 1.0), ("mm", mm, 1000.0)):
        long = mech.sweep(0.0, 1.0, 9, params={"corte": [400.0, 500.0]}, level="position")
        red = mech.sweep(0.0, 1.0, 9, params={"corte": [400.0, 500.0]}, level="position",
                         reduce=["X4"])
        for kind, tab in (("long", long), ("reduced", red)):
            path = tmp_path / f"{name}_{kind}.csv"
            tab.to_csv(str(path))
            with open(path, newline="") as fh:
                rows[name, kind] = list(csv.reader(fh))
    head = rows["mm", "long"][0]
    assert "X4 [mm]" in head and "T [s]" in head and "corte" in head, head
    k, j = head.index("X4 [mm]"), rows["si", "long"][0].index("X4 [m]")
    np.testing.assert_allclose([float(r[k]) for r in rows["mm", "long"][1:]],
                               [1000 * float(r[j]) for r in rows["si", "long"][1:]],
                               rtol=1e-9)
    head = rows["mm", "reduced"][0]
    for name in ("X4_min [mm]", "X4_max [mm]", "X4_tmin [s]", "X4_tmax [s]"):
        assert name in head, (name, head)
    k, j = head.index("X4_max [mm]"), rows["si", "reduced"][0].index("X4_max [m]")
    np.testing.assert_allclose([float(r[k]) for r in rows["mm", "reduced"][1:]],
                               [1000 * float(r[j]) for r in rows["si", "reduced"][1:]],
                               rtol=1e-9)


def test_a_tolerance_band_picture_says_the_models_units(pair, tmp_path):
    # plot.band_plot's axes in the declared units (mm, s), the numbers as computed; a
    # model showing degrees has its angle's band drawn in degrees (the band's radians × 180/π)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from mechgen import plot
    si, mm = pair
    band = mm.tolerance(mm.sweep(*TIMES), {"longitud": 1.0}, method="worst")
    ax = plot.band_plot(band, "X4")
    assert ax.get_ylabel() == "X4 [mm]" and ax.get_xlabel() == "time T [s]"
    nominal = [ln for ln in ax.get_lines() if ln.get_label() == "nominal"][0]
    np.testing.assert_allclose(nominal.get_ydata(), band["X4"]["nominal"], rtol=1e-12)
    plt.close(ax.figure)
    m = shaper("SI", "shaper_deg_band")
    m.units = parse({"length": "m", "mass": "kg", "time": "s", "angle": "deg"})
    deg = mechgen.compile(m, tier="python", outdir=str(tmp_path))
    band = deg.tolerance(deg.sweep(*TIMES), {"longitud": 0.01}, method="worst")
    ax = plot.band_plot(band, "Th3")
    assert ax.get_ylabel() == "Th3 [deg]"
    nominal = [ln for ln in ax.get_lines() if ln.get_label() == "nominal"][0]
    np.testing.assert_allclose(nominal.get_ydata(), np.degrees(band["Th3"]["nominal"]),
                               rtol=1e-12)
    plt.close(ax.figure)


def test_a_drawing_gives_the_time_and_lengths_in_the_models_units(pair, tmp_path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from mechgen import plot
    si, mm = pair
    d = plot.draw(mm, mm.solve(0.25))
    assert d.title.get_text().startswith("shaper_mm   T = 0.25 s"), d.title.get_text()
    assert (d.ax.get_xlabel(), d.ax.get_ylabel()) == ("x [mm]", "y [mm]")
    plt.close(d.ax.figure)
    plain = mechgen.compile("examples/fourbar.py", outdir=str(tmp_path), tier="python")
    d = plot.draw(plain, plain.solve(0.25))          # no units declared: no unit said
    assert d.title.get_text() == f"{plain.name}   T = 0.25", d.title.get_text()
    assert (d.ax.get_xlabel(), d.ax.get_ylabel()) == ("", "")
    plt.close(d.ax.figure)


def test_the_live_views_clock_gives_the_time_in_the_models_unit(pair, tmp_path):
    # the page's clock label (and the script that moves it) say "T = ... s" where the
    # model declares its units, bare "T = ..." where it does not
    pytest.importorskip("bokeh")
    from mechgen.view.explorer import Explorer
    from mechgen.view.page import Page
    si, mm = pair
    page = Page(Explorer(mm), server=True)
    assert page.clock.text == "T = 0 s" and page.redraw.args["clock_unit"] == " s"
    assert "+ clock_unit" in page.redraw.code
    plain = mechgen.compile("examples/fourbar.py", outdir=str(tmp_path), tier="python")
    page = Page(Explorer(plain), server=True)
    assert page.clock.text == "T = 0" and page.redraw.args["clock_unit"] == ""
