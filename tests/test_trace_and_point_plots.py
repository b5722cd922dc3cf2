"""Issue 14's missing picture features: `draw --trace POINT` (the mechanism with a point's
path over a sweep), `plot "foot[3].x"` (a point's coordinate with no output declared, from
the module's compiled points), and unknown point names answered with every valid one."""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from PIL import Image  # noqa: E402

from mechgen import MechgenError, plot  # noqa: E402
from mechgen.plot.scene import Scene, point_coordinate  # noqa: E402
from mechgen.plot.timeplot import needed_level, quantity  # noqa: E402
from conftest import EXAMPLES  # noqa: E402
from test_cli_options import outdir, run  # noqa: E402,F401  (the seeded build folder)

QR = os.path.join(EXAMPLES, "quick_return.py")
FOURBAR = os.path.join(EXAMPLES, "fourbar.py")
COUPLER = (1.25, 0.8)


def coupler_point(fourbar, Q):
    """coupler.at(1.25, 0.8) from the coordinates (body 3: X3, Y3, Th3), by hand."""
    k = fourbar.coordinates.index
    x, y, th = Q[:, k("X3")], Q[:, k("Y3")], Q[:, k("Th3")]
    c, s = np.cos(th), np.sin(th)
    return np.column_stack([x + c * COUPLER[0] - s * COUPLER[1],
                            y + s * COUPLER[0] + c * COUPLER[1]])


# -- names --------------------------------------------------------------------------------
def test_point_coordinate_names():
    assert point_coordinate("foot[3].x") == ("foot[3]", 0)
    assert point_coordinate("coupler.at(1.2, 0.8).y") == ("coupler.at(1.2, 0.8)", 1)
    assert point_coordinate(" colisa[2] . y ") == ("colisa[2]", 1)
    for name in ("X4", "X4d", "stroke_x", "colisa[2].z", "colisa[2]"):
        assert point_coordinate(name) is None


def test_every_point_name_is_listed(qr, fourbar):
    names = Scene(qr).point_names()
    # manivela[1] coincides with manivela[0] (both local (0, 0)): the module holds it
    # once, but both names are valid and both are listed
    assert names == ["base[0]", "base[1]", "base[2]", "base[3]", "base[4]",
                     "manivela[0]", "manivela[1]", "manivela[2]",
                     "colisa[0]", "colisa[1]", "colisa[2]",
                     "deslizadera[0]", "deslizadera[1]", "deslizadera[2]"]
    st = Scene(qr)
    P, Q = qr.sweep(0, 1, 5).points(), qr.sweep(0, 1, 5).Q
    for name in names:                      # each one is located
        body, where = st.locate(name)
        assert where(P, Q).shape == (5, 2)
    assert np.all(st.locate("base[0]")[1](P, Q) == 0.0)     # the global origin
    assert np.allclose(st.locate("manivela[1]")[1](P, Q), [[0, 5]] * 5)
    with pytest.raises(MechgenError) as info:
        st.locate("colisa[7]")
    text = str(info.value)
    assert all(name in text for name in names) and "body.at(x, y)" in text
    assert "bodies: base, manivela, colisa, deslizadera" in text
    assert "crank[1]" in ", ".join(Scene(fourbar).point_names())


# -- draw with traces -----------------------------------------------------------------------
def test_draw_traces_a_coupler_point(fourbar):
    sw = fourbar.sweep(0.0, 1.0, 41)
    s = fourbar.solve(0.1)
    d = plot.draw(fourbar, s, sweep=sw, trace=["coupler.at(1.25, 0.8)", "crank[2]"])
    path, circle, dot, _ = d.artists["traces"]
    xy = np.column_stack(path.get_data())
    assert np.allclose(xy, coupler_point(fourbar, sw.Q), atol=1e-12)     # the sweep's points
    r = np.hypot(*np.column_stack(circle.get_data()).T)            # the crank pin: a circle
    assert np.ptp(r) < 1e-9
    # a dot where the drawing shows the point, moved with the drawing
    assert np.allclose(np.ravel(dot.get_data()), coupler_point(fourbar, s.q[None])[0])
    s2 = fourbar.solve(0.6)
    d.update(s2)
    assert np.allclose(np.ravel(dot.get_data()), coupler_point(fourbar, s2.q[None])[0])
    # the frame takes the whole path in
    x0, x1, y0, y1 = d.frame
    assert x0 < xy[:, 0].min() and xy[:, 0].max() < x1
    assert y0 < xy[:, 1].min() and xy[:, 1].max() < y1
    assert d.ax.get_xlim() == (x0, x1)
    plt.close(d.figure)


def test_draw_trace_without_a_sweep_follows_the_framing_motion(qr):
    s = qr.solve(0.15)
    d = plot.draw(qr, s, trace="colisa[2]", frame="pose")
    xy = np.column_stack(d.artists["traces"][0].get_data())
    assert np.allclose(xy[0], s.points()[Scene(qr).point("colisa[2]")])
    assert np.allclose(np.hypot(*xy.T), 9.0)            # colisa[2] turns about base[1]
    plt.close(d.figure)


def test_animate_keeps_its_traces(fourbar):
    a = plot.animate(fourbar, fourbar.sweep(0, 1, 9), trace="coupler.at(1.25, 0.8)")
    assert len(a.traces) == 1
    full = a.drawing.artists["traces"][0]
    assert full.get_linestyle() == "--"
    assert len(a.traces[0].get_xdata()) == 1         # the travelled part starts at frame 0
    plt.close(a.figure)


def test_cli_draw_trace(tmp_path, outdir, capsys):  # noqa: F811
    png = tmp_path / "fb.png"
    code, out, err = run(capsys, "draw", FOURBAR, "-t", "0.1", "--trace",
                         "coupler.at(1.25, 0.8)", "-o", png, "--outdir", outdir,
                         "--t0", "0", "--t1", "1", "-n", "31")
    assert code == 0, err
    assert Image.open(png).format == "PNG"
    assert "the path of coupler.at(1.25, 0.8) over T = 0 .. 1" in out
    code, out, err = run(capsys, "draw", FOURBAR, "--trace", "crank[9]",
                         "-o", tmp_path / "x.png", "--outdir", outdir)
    assert code == 1 and not os.path.exists(tmp_path / "x.png")
    for name in ("ground[0]", "crank[0]", "crank[1]", "crank[2]", "coupler[1]", "rocker[2]"):
        assert name in err
    code, out, err = run(capsys, "draw", "--help")
    assert "--trace" in out and "--t0" in out and "every point" in out


# -- plot a point's coordinate ----------------------------------------------------------------
def test_plot_a_point_coordinate(qr):
    sw = qr.sweep(0.0, 1.0, 21)
    x3, y3, th3 = sw["X3"], sw["Y3"], sw["Th3"]
    assert np.allclose(quantity(sw, "colisa[2].x"), x3 - 9 * np.sin(th3), atol=1e-12)
    assert np.allclose(quantity(sw, "colisa[2].y"), y3 + 9 * np.cos(th3), atol=1e-12)
    # seed 001: Location[deslizadera, {3, 8}] /. LastSolve[] (T = 0.5) = {2.81812, 18.}
    at = quantity(qr.sweep(0.5, 0.5, 1), "deslizadera.at(3, 8).x")
    assert abs(at[0] - 2.81812) < 5e-6
    assert quantity(qr.sweep(0.5, 0.5, 1), "deslizadera.at(3, 8).y")[0] == pytest.approx(18)
    assert needed_level(qr, ["colisa[2].x", "X4"]) == "position"
    assert needed_level(qr, ["colisa[2].x", "X4d"]) == "velocity"
    lines = plot.plot(sw, "colisa[2].x", "X4")
    assert np.allclose(lines[0].get_ydata(), x3 - 9 * np.sin(th3))
    assert lines[0].axes.get_ylabel().startswith("colisa[2].x")
    plt.close(lines[0].figure)
    # its path, y against x, at equal scale
    lines = plot.plot(sw, "colisa[2].y", x="colisa[2].x")
    assert lines[0].axes.get_aspect() == 1.0
    assert np.allclose(np.hypot(lines[0].get_xdata(), lines[0].get_ydata()), 9.0)
    plt.close(lines[0].figure)
    with pytest.raises(MechgenError, match="manivela\\[1\\]"):
        plot.plot(sw, "colisa[5].x")


def test_cli_plot_a_point_coordinate(tmp_path, outdir, capsys):  # noqa: F811
    png = tmp_path / "p.png"
    code, out, err = run(capsys, "plot", QR, "colisa[2].x", "deslizadera.at(3, 8).y",
                         "-o", png, "--outdir", outdir, "-n", "11")
    assert code == 0, err
    assert Image.open(png).format == "PNG"
    code, out, err = run(capsys, "plot", QR, "colisa[9].y", "-o", tmp_path / "q.png",
                         "--outdir", outdir)
    assert code == 1 and "colisa[2]" in err and "deslizadera[0]" in err
    code, out, err = run(capsys, "plot", "--help")
    assert "POINT.x" in out
    # the default file name holds no brackets
    here = os.getcwd()
    os.chdir(tmp_path)
    try:
        code, out, err = run(capsys, "plot", QR, "colisa[2].y", "--outdir", outdir, "-n", "5")
    finally:
        os.chdir(here)
    assert code == 0, err
    assert os.path.exists(tmp_path / "quick_return_colisa_2_y.png")
