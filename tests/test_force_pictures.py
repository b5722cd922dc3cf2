"""The force pictures (issue 21): a driver's effort over a cycle with its mean and peak
(plot.effort), the polar diagram of a pin force (plot.polar), force arrows on a drawing
(plot.draw(forces=...), plot.force_arrows) and the command line (draw --forces, forces -o).

What the pictures hold is checked against the closed-form slider-crank of
tests/test_forces.py (its torque by the power form, its pin forces by Newton–Euler body by
body), never against mechgen's own equations; the artists are read back from matplotlib.
"""
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.patches import FancyArrow  # noqa: E402

import mechgen  # noqa: E402
from mechgen import MechgenError, plot  # noqa: E402
from mechgen.plot.arrows import LENGTH  # noqa: E402
from mechgen.plot.forceplots import number  # noqa: E402
from test_forces import (C4, G, M3, PRESS, TH0, W, J3, _cross, closed_form,  # noqa: E402
                         newton_euler, power_torque, slider_crank)

from conftest import EXAMPLES, GENERATED  # noqa: E402

PERIOD = 2 * math.pi / W


@pytest.fixture(scope="module")
def sc(tmp_path_factory):
    return mechgen.compile(slider_crank(), outdir=str(tmp_path_factory.mktemp("scp")),
                           tier="python")


@pytest.fixture(scope="module")
def turn(sc):
    return sc.sweep(0.0, PERIOD, 241, level="dynamic")


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _close(actual, expected, scale):
    np.testing.assert_allclose(actual, expected, rtol=1e-9, atol=1e-9 * scale)


# -- the effort over a cycle -------------------------------------------------------------
def test_effort_is_the_power_form_torque_against_the_crank_angle(turn):
    e = plot.effort(turn)
    torque = np.array([power_torque(closed_form(t)) for t in turn.t])
    angle = np.degrees(W * turn.t + TH0)             # the driven angle, absolute
    x, y = e.line.get_data()
    _close(y, torque, np.abs(torque).max())
    np.testing.assert_allclose(x, angle, rtol=0, atol=1e-9)
    # the mean line: the work per unit angle, trapezoids over the cycle
    mean = np.trapezoid(torque, angle) / (angle[-1] - angle[0])
    assert e.mean_line.get_ydata()[0] == pytest.approx(mean, rel=1e-9)
    assert e.mean == pytest.approx(mean, rel=1e-9)
    assert f"mean {number(mean)}" in e.mean_line.get_label()
    # the peak: the torque of largest size, marked where it is and labelled
    k = int(np.argmax(np.abs(torque)))
    px, py = e.peak_marker.get_data()
    assert px[0] == pytest.approx(angle[k]) and py[0] == pytest.approx(torque[k], rel=1e-9)
    assert number(torque[k]) in e.peak_text.get_text()
    assert "driven angle [°]" in e.ax.get_xlabel() and "torque" in e.ax.get_ylabel()
    assert len(e.fills) == 2
    # radians on request
    r = plot.effort(turn, "crank driver", degrees=False, fill=False, peak=False)
    np.testing.assert_allclose(r.line.get_xdata(), W * turn.t + TH0, atol=1e-12)
    assert r.peak_marker is None and r.fills == []


def test_effort_of_a_distance_driver_against_its_travel():
    """quick_return_slider drives X4 = centro + amplitud sin 2πT (relative_x): no masses, so
    the force is zero; the x axis is the travel since the first point, exactly."""
    mech = mechgen.load(os.path.join(GENERATED, "quick_return_slider.py"))
    sw = mech.sweep(0.0, 0.2, 21, level="dynamic")
    e = plot.effort(sw)
    amplitude = mech.parameters["amplitud"]
    np.testing.assert_allclose(e.line.get_xdata(), amplitude * np.sin(2 * np.pi * sw.t),
                               atol=1e-12)
    assert np.all(e.line.get_ydata() == 0) and e.mean == 0
    assert "since time 0 s" in e.ax.get_xlabel() and "force" in e.ax.get_ylabel()


def test_effort_refuses_what_it_cannot_plot(sc, turn):
    with pytest.raises(TypeError, match="level 'dynamic' or 'static'"):
        plot.effort(sc.sweep(0.0, 1.0, 5, level="acceleration"))
    with pytest.raises(ValueError, match="'A: revolute.*is not a driver"):
        plot.effort(turn, "A")
    with pytest.raises(ValueError, match="no constraint 'motor'"):
        plot.effort(turn, "motor")


# -- the polar diagram -------------------------------------------------------------------
def test_polar_diagram_is_the_newton_euler_pin_force(turn):
    p = plot.polar(turn, "C", on="slider", marks=8)
    fc = np.array([newton_euler(closed_form(t))["FC"] for t in turn.t])
    x, y = p.line.get_data()
    _close(np.column_stack([x, y]), fc, 600.0)
    _close(p.force, fc, 600.0)
    # the rays: eight evenly spaced crank angles over the closed cycle, their tips on the
    # drawn locus (the force there, linear between the sweep's points)
    assert len(p.rays) == 8
    np.testing.assert_allclose(np.diff(p.at), 45.0)
    for ray, a in zip(p.rays, p.at):
        tip = np.array(ray.get_xydata()[1])
        seg = np.column_stack([x, y])
        d = np.min([_point_segment(tip, seg[i], seg[i + 1]) for i in range(len(seg) - 1)])
        assert d <= 1e-9 * 600
        expected = newton_euler(closed_form((math.radians(a) - TH0) / W))["FC"]
        assert np.hypot(*(tip - expected)) < 0.02 * np.abs(fc).max()     # near, not on
    size = np.hypot(fc[:, 0], fc[:, 1])
    k = int(np.argmax(size))
    assert np.allclose(p.peak_marker.get_xydata()[0], fc[k])
    assert number(size[k]) in p.peak_marker.get_label()
    assert p.ax.get_aspect() == 1.0


def test_polar_in_the_body_frame_turns_with_it(turn):
    p = plot.polar(turn, "B", on="crank", local=True, marks=0)
    expected = []
    for t in turn.t:
        th = W * t + TH0
        f = -newton_euler(closed_form(t))["FB"]          # what pin B applies to the crank
        expected.append([math.cos(th) * f[0] + math.sin(th) * f[1],
                         -math.sin(th) * f[0] + math.cos(th) * f[1]])
    _close(np.column_stack(p.line.get_data()), np.array(expected), 600.0)
    assert "crank's frame" in p.ax.get_xlabel() and p.rays == []


def test_polar_names_an_unknown_body(turn):
    with pytest.raises(ValueError, match="no body 'wheel'.*bodies: base, crank, rod, slider"):
        plot.polar(turn, "B", on="wheel")


def _point_segment(p, a, b):
    ab = b - a
    u = np.clip((p - a) @ ab / max(ab @ ab, 1e-300), 0.0, 1.0)
    return float(np.hypot(*(a + u * ab - p)))


# -- arrows on a drawing -----------------------------------------------------------------
def _tip(arrow, tail):
    """A FancyArrow's tip: the vertex of its outline farthest from its tail."""
    verts = arrow.get_xy()
    return verts[int(np.argmax(np.hypot(*(verts - tail).T)))]


def test_pin_forces_on_the_drawing_are_newton_euler(sc):
    t = 0.4
    s = sc.solve(t, level="dynamic")
    k, ne = closed_form(t), newton_euler(closed_form(t))
    d = plot.draw(sc, s, forces=True)
    arrows = {(a.short, a.body): a for a in d.forces.arrows}
    # each revolute once, on its second body; the driver on the crank; loads on each body
    assert set(arrows) == {("A", "crank"), ("B", "rod"), ("C", "slider"),
                           ("crank driver", "crank"), ("loads", "crank"), ("loads", "rod"),
                           ("loads", "slider")}
    _close(arrows["A", "crank"].force, ne["FA"], 600)
    _close(arrows["B", "rod"].force, ne["FB"], 600)
    _close(arrows["C", "slider"].force, ne["FC"], 600)
    for name, at in (("A", (0, 0)), ("B", k["B"]), ("C", k["C"])):    # at the pins
        a = arrows[name, "crank" if name == "A" else "rod" if name == "B" else "slider"]
        np.testing.assert_allclose(a.at, at, atol=1e-9)
        assert a.moment == pytest.approx(0.0, abs=1e-9 * 600) and a.arc is None
    drive = arrows["crank driver", "crank"]
    assert drive.arrow is None and drive.moment == pytest.approx(ne["tau"], rel=1e-9)
    np.testing.assert_allclose(drive.at, (0, 0), atol=1e-12)
    assert number(abs(ne["tau"])) in drive.label.get_text()
    # the slider's loads: the press at C and its weight at its centroid, one resultant
    # drawn on its line of action
    loads = arrows["loads", "slider"]
    _close(loads.force, [PRESS[0], PRESS[1] - 3.0 * G], 600)
    # (three bodies carry loads, drawn in one ink: each label names its body)
    assert loads.label.get_text().startswith("loads on slider ")
    moment = _cross(k["C"] - loads.at, np.array(PRESS)) + \
        _cross(k["C"] + np.array(C4) - loads.at, np.array([0.0, -3.0 * G]))
    assert moment == pytest.approx(0.0, abs=1e-9 * 600)
    # lengths proportional to the sizes, the largest LENGTH of the drawing's larger side
    span = max(d.frame[1] - d.frame[0], d.frame[3] - d.frame[2])
    sizes = {key: math.hypot(*a.force) for key, a in arrows.items() if a.arrow is not None}
    top = max(sizes.values())
    for key, size in sizes.items():
        a = arrows[key]
        assert isinstance(a.arrow, FancyArrow)
        tip = _tip(a.arrow, a.at)
        assert np.hypot(*(tip - a.at)) == pytest.approx(size * d.forces.scale, rel=1e-9)
        np.testing.assert_allclose(tip, a.at + a.force * d.forces.scale, atol=1e-9 * span)
        assert number(size) in a.label.get_text() and a.short in a.label.get_text()
    assert d.forces.scale * top <= LENGTH * span * (1 + 1e-9)
    assert d.forces.scale * top >= LENGTH * span * 0.7     # (the frame grew to hold them)
    # every arrow inside the axes, every label apart from the others
    x0, x1 = d.ax.get_xlim()
    y0, y1 = d.ax.get_ylim()
    tips = d.forces.extent()
    assert np.all((tips[:, 0] >= x0) & (tips[:, 0] <= x1) & (tips[:, 1] >= y0) &
                  (tips[:, 1] <= y1))
    renderer = d.figure.canvas.get_renderer()
    boxes = [a.label.get_window_extent(renderer) for a in d.forces.arrows]
    for i, b in enumerate(boxes):
        for c in boxes[i + 1:]:
            assert not b.overlaps(c)
    assert "forces (dynamic)" in d.title.get_text()


def test_free_body_diagram_balances_with_the_inertia_force(sc):
    """The rod's free body: B and C from the pins, its weight, and −m a_G at its line of
    action: Σ F = 0 and Σ M = 0 about any point, as d'Alembert says."""
    t = 1.1
    s = sc.solve(t, level="dynamic")
    k, ne = closed_form(t), newton_euler(closed_form(t))
    d = plot.draw(sc, s, forces="rod", frame="pose")
    arrows = {a.short: a for a in d.forces.arrows}
    assert set(arrows) == {"B", "C", "loads", "−m·a"}
    assert d.title.get_text().endswith("forces on rod (dynamic)")
    rg, _, ag, _, al = k["bodies"]["rod"]
    _close(arrows["B"].force, ne["FB"], 600)
    _close(arrows["C"].force, -ne["FC"], 600)
    _close(arrows["−m·a"].force, -M3 * ag, 600)
    assert arrows["−m·a"].kind == "inertia"
    total = sum(a.force for a in arrows.values())
    assert np.hypot(*total) <= 1e-9 * 600
    # moments about the origin: each force at its point, plus the couples left, plus −J α
    mo = sum(_cross(a.at, a.force) + a.moment for a in arrows.values())
    # −m a_G drawn on its line of action carries −J α in it: r × (−m a) must equal
    # r_G × (−m a_G) − J α
    expected_inertia = _cross(rg, -M3 * ag) - J3 * al
    got_inertia = _cross(arrows["−m·a"].at, arrows["−m·a"].force) + arrows["−m·a"].moment
    assert got_inertia == pytest.approx(expected_inertia, abs=1e-9 * 600)
    assert mo == pytest.approx(0.0, abs=1e-8 * 600)


def test_slider_guide_force_at_its_centre_of_pressure(sc):
    t = 0.9
    s = sc.solve(t, level="dynamic")
    k, ne = closed_form(t), newton_euler(closed_form(t))
    d = plot.draw(sc, s, forces=["slider"])
    guide = next(a for a in d.forces.arrows if a.short == "guide")
    _close(guide.force, [0.0, ne["N"]], 600)
    # its moment about the slider's origin (C) is the guide's moment: (at − C) × (0, N)
    assert (guide.at[0] - k["C"][0]) * ne["N"] == pytest.approx(ne["guide"], abs=1e-9 * 600)
    assert guide.at[1] == pytest.approx(0.0, abs=1e-12)       # on the slider's line
    assert guide.moment == 0.0


def test_static_arrows_and_update_hides_them(sc):
    s = sc.solve(0.3, level="static")
    d = plot.draw(sc, s, forces=True)
    assert "forces (static)" in d.title.get_text()
    assert all(a.kind != "inertia" for a in d.forces.arrows)
    d.update(sc.solve(0.5))
    assert not any(a.get_visible() for a in d.artists["forces"])
    assert d.title.get_text() == "sc_forces   T = 0.5"
    d.update(s)
    assert all(a.get_visible() for a in d.artists["forces"])
    assert d.title.get_text() == "sc_forces   T = 0.3   forces (static)"


def test_drawing_forces_refuses_bad_input(sc, fourbar):
    with pytest.raises(TypeError, match="level 'dynamic' or 'static'"):
        plot.draw(sc, sc.solve(0.3), forces=True)
    with pytest.raises(MechgenError, match="no body named 'wheel'.*bodies: base, crank"):
        plot.draw(sc, sc.solve(0.3, level="dynamic"), forces="wheel")
    with pytest.raises(MechgenError, match="'fourbar' has no masses and no loads"):
        plot.draw(fourbar, fourbar.solve(0.1, level="dynamic"), forces=True)
    d = plot.draw(sc, 0.3, forces="crank")       # a time: solved at level "dynamic"
    assert d.forces.arrows and "dynamic" in d.title.get_text()


@pytest.mark.filterwarnings("ignore::mechgen.RedundancyWarning")   # expected: it is redundant
def test_redundant_reactions_are_starred(tmp_path):
    """The parallelogram with a third crank: the shares of the redundant pins are not
    unique (starred, with a note); the driver's torque is exact, the same as without the
    third crank."""
    from test_forces import parallelogram
    three = mechgen.compile(parallelogram(True), outdir=str(tmp_path), tier="python")
    two = mechgen.compile(parallelogram(False), outdir=str(tmp_path), tier="python")
    s = three.solve(0.1, level="static")
    assert s.indeterminate
    d = plot.draw(three, s, forces=True)
    starred = {a.short[:-1] for a in d.forces.arrows if a.short.endswith("*")}
    named = {label.split(":")[0] for label in s.indeterminate}
    assert starred and starred <= named
    assert all(a.short.rstrip("*") not in named or a.short.endswith("*")
               for a in d.forces.arrows)
    assert "not unique" in d.forces.note.get_text()
    drive = next(a for a in d.forces.arrows if a.short == "drive")
    assert drive.moment == pytest.approx(two.solve(0.1, level="static").driver("drive"),
                                         rel=1e-9)


ZERO_MODEL = '''
from mechgen import Model, T, Piecewise
m = Model("late_press")
base = m.ground("base", points=[(0, 0), (1, 0)])
crank = m.body("crank", points=[(0, 0), (0.2, 0)], guess=(0, 0, 0.3), mass=1.0)
m.revolute(base[1], crank[1], name="A")
m.rotation_lock(crank, 3.0 * T + 0.3, name="motor")
m.force(crank[2], (Piecewise((10.0, T > 0.5), (0.0, True)), 0.0), name="press")
'''


def test_forces_all_zero_at_an_instant_say_so(tmp_path):
    path = tmp_path / "late_press.py"
    path.write_text(ZERO_MODEL)
    mech = mechgen.compile(str(path), outdir=str(tmp_path / "gen"), tier="python")
    d = plot.draw(mech, mech.solve(0.2, level="static"), forces=True)
    assert d.forces.arrows == [] and "every force is zero at T = 0.2" in d.forces.note.get_text()
    d = plot.draw(mech, mech.solve(0.7, level="static"), forces=True)
    press = next(a for a in d.forces.arrows if a.short == "loads")
    np.testing.assert_allclose(press.force, [10.0, 0.0])


# -- the command line --------------------------------------------------------------------
MODEL_FILE = os.path.join(EXAMPLES, "quick_return_forces.py")


def _run(argv, capsys):
    from mechgen.cli import main
    code = main(argv)
    out = capsys.readouterr()
    return code, out.out, out.err


def test_cli_draw_forces_writes_a_png(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("MECHGEN_TIER", "python")
    gen = str(tmp_path / "gen")
    png = tmp_path / "f.png"
    code, out, err = _run(["draw", MODEL_FILE, "-t", "0.7", "--forces", "-o", str(png),
                           "--outdir", gen], capsys)
    assert code == 0, err
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "forces (dynamic), the largest" in out and "(O2 on manivela)" in out
    png2 = tmp_path / "s.png"
    code, out, err = _run(["draw", MODEL_FILE, "-t", "0.7", "--forces", "colisa", "--static",
                           "-o", str(png2), "--outdir", gen], capsys)
    assert code == 0, err and png2.exists()
    assert "(static)" in out
    for argv, said in (
            (["--forces", "lever"], "no body named 'lever' in 'quick_return_forces' (bodies: "
                                    "base, manivela, colisa, deslizadera)"),
            (["--static"], "--static goes with --forces")):
        code, out, err = _run(["draw", MODEL_FILE, "-t", "0.7", "-o", str(tmp_path / "x.png"),
                               "--outdir", gen] + argv, capsys)
        assert code == 1 and said in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "x.png").exists()


def test_cli_draw_forces_on_a_model_without_loads(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("MECHGEN_TIER", "python")
    code, out, err = _run(["draw", os.path.join(EXAMPLES, "fourbar.py"), "-t", "0.1",
                           "--forces", "-o", str(tmp_path / "x.png"), "--outdir",
                           str(tmp_path / "gen")], capsys)
    assert code == 1 and len(err.strip().splitlines()) == 1
    assert "'fourbar' has no masses and no loads, so every force is zero" in err


def test_cli_forces_plots_the_torque(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("MECHGEN_TIER", "python")
    path = tmp_path / "sc_forces.py"
    path.write_text(SC_FILE)
    png = tmp_path / "torque.png"
    code, out, err = _run(["forces", str(path), "-o", str(png), "--t1", repr(PERIOD), "-n",
                           "121", "--outdir", str(tmp_path / "gen")], capsys)
    assert code == 0, err
    assert png.read_bytes()[:4] == b"\x89PNG"
    t = np.linspace(0.0, PERIOD, 121)
    torque = np.array([power_torque(closed_form(x)) for x in t])
    mean = np.trapezoid(torque, t) / PERIOD
    said = float(out.split("mean ")[1].split(",")[0])
    assert said == pytest.approx(mean, rel=1e-9)
    code, out, err = _run(["forces", str(path), "--outdir", str(tmp_path / "gen")], capsys)
    assert code == 1 and "give -t T" in err and len(err.strip().splitlines()) == 1


SC_FILE = '''
from mechgen import Model, T
m = Model("sc_cli_forces")
base = m.ground("base", points=[(0, 0), (1, 0)])
crank = m.body("crank", points=[(0, 0), (0.2, 0)], guess=(0, 0, 0.3), mass=1.5,
               inertia=0.02, centroid=(0.08, 0.02))
rod = m.body("rod", points=[(0, 0), (0.6, 0)], guess=(0.19, 0.06, -0.1), mass=2.0,
             inertia=0.07, centroid=(0.25, -0.03))
slider = m.body("slider", points=[(0, 0), (1, 0)], guess=(0.79, 0, 0), mass=3.0,
                inertia=0.01, centroid=(0.05, 0.04))
m.revolute(base[1], crank[1], name="A")
m.revolute(crank[2], rod[1], name="B")
m.revolute(rod[2], slider[1], name="C")
m.translate(base.line(1, 2), slider.line(1, 2), name="guide")
m.rotation_lock(crank, 3.0 * T + 0.3, name="crank driver")
m.gravity(9.807)
m.force(slider[1], (-500.0, 120.0), name="press")
'''


# -- the worked example ------------------------------------------------------------------
def test_the_guide_quotes_the_worked_example(capsys, monkeypatch, tmp_path):
    """The user guide's forces page (docs/guide/forces.md) gives the numbers
    examples/quick_return_forces_demo.py prints (run here in the plain tier; the numbers
    are the compiled tier's bit for bit)."""
    import importlib.util
    import re
    monkeypatch.setenv("MECHGEN_CACHE", str(tmp_path))
    spec = importlib.util.spec_from_file_location(
        "qr_forces_demo", os.path.join(EXAMPLES, "quick_return_forces_demo.py"))
    demo = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(demo)
    mech = mechgen.compile(os.path.join(EXAMPLES, "quick_return_forces.py"),
                           outdir=str(tmp_path), tier="python")
    demo.analyse(mech)
    out = capsys.readouterr().out
    from docs_pages import page
    section = page("guide/forces.md").replace("−", "-")
    # every figure but the power balance's rounding (4e-16 here, machine-dependent)
    figures = [x for x in re.findall(r"-?\d+\.\d+(?:e-?\d+)?", out) if "e" not in x]
    assert len(figures) >= 16
    missing = [x for x in figures if x not in section]
    assert not missing, f"docs/guide/forces.md does not quote the demo's {missing}"
    ratio = float(re.search(r"at most (\S+) of the largest", out).group(1))
    assert ratio < 1e-12


def test_springs_and_dampers_are_drawn_between_their_points_and_move_with_them(tmp_path):
    """A spring drawn as a zigzag and a damper as a dashpot, each from its first point to
    its second, in the drawn configuration and after update()."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mechgen import Model, T
    from mechgen.plot import draw
    m = Model("drawn_loads")
    base = m.ground("base", points=[(0, 0), (2, 1)])
    bar = m.body("bar", points=[(0, 0), (1, 0)], guess=(0, 0, 0.3), mass=1, inertia=0.1)
    m.revolute(base[1], bar[1])
    m.rotation_lock(bar, 0.3 + T, name="turn")
    m.spring(base[2], bar[2], 10.0, 1.0, name="k")
    m.damper(base[2], bar[2], 2.0, name="c")
    mech = mechgen.compile(m, outdir=str(tmp_path), tier="python")
    assert mech.module.LOADS == (("k", "spring", (1, 3)), ("c", "damper", (1, 3)))
    d = draw(mech, mech.solve(0.0))
    for t in (0.0, 0.7):
        s = mech.solve(t)
        d.update(s)
        P = s.points()
        lines = [a for a in d.artists["joints"] if a.get_zorder() == 3.5]
        assert len(lines) == 3                 # the zigzag; the damper's rod and cylinder
        zig = np.column_stack(lines[0].get_data())
        assert np.allclose(zig[0], P[1]) and np.allclose(zig[-1], P[3])
        assert len(zig) > 10
        rod, cyl = (np.column_stack(a.get_data()) for a in lines[1:])
        assert np.allclose(rod[0], P[1]) and np.allclose(cyl[-1], P[3])
    plt.close(d.figure)


def test_force_arrows_name_the_body_and_point(tmp_path):
    """An arrow at a point is labelled body.point (crank.P1) beside its constraint's name;
    a driver's torque, at no one point, by its name."""
    from models import sprung_crank
    mech = mechgen.compile(sprung_crank("force_arrow_names"), outdir=str(tmp_path),
                           tier="python")
    s = mech.solve(0.1, level="dynamic")
    d = plot.draw(mech, s, forces=True)
    by = {a.short: a for a in d.forces.arrows}
    pivot = by["pivot"]
    assert pivot.where == "crank.P1"
    assert pivot.label.get_text().startswith("crank.P1 (pivot) ")
    drive = by["drive"]             # a torque on the crank: no one point, its name
    assert drive.where is None and drive.label.get_text().startswith("drive ")
