"""Pictures (mechgen.plot, mechgen draw|animate|plot), rendered headless with Agg.

Each picture is checked as an image file of the expected size, and against the solved
geometry: the pixels where the joints are hold ink, an empty spot of the frame does not.
"""
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from PIL import Image  # noqa: E402

from conftest import EXAMPLES, GENERATED, ROOT  # noqa: E402
from mechgen import MechgenError, plot  # noqa: E402

INK = 110     # a pixel whose channels are all below this is ink (outlines, pins, hatching)


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _image(path):
    im = Image.open(path)
    im.load()
    return im


def _px(fig, ax, xy):
    """Data coordinates -> (column, row) of the saved image (saved at the figure's dpi)."""
    x, y = ax.transData.transform(np.asarray(xy, dtype=float))
    height = fig.get_size_inches()[1] * fig.dpi
    return int(round(x)), int(round(height - y))


def _size_ok(im, fig, dpi):
    """The image is the figure's size at dpi (matplotlib truncates to whole pixels)."""
    w_in, h_in = fig.get_size_inches()
    return all(abs(got - want * dpi) < 1.01 for got, want in zip(im.size, (w_in, h_in)))


def _rgb(color):
    return np.round(255 * np.array(matplotlib.colors.to_rgb(color))).astype(int)


def _window(rgb, col, row, half):
    return rgb[max(row - half, 0):row + half + 1, max(col - half, 0):col + half + 1]


def _has_ink(rgb, col, row, half):
    win = _window(rgb, col, row, half)
    return bool(np.any(np.all(win < INK, axis=-1)))


def _joint_points(mech):
    """POINTS indices the joints name (revolute, point_on_line, relative_distance...)."""
    out = set()
    for _, kind, used in mech.module.JOINTS:
        out.update(used)
    return sorted(out)


def _pin_half(drawing, fig):
    """A window half-size (pixels) that reaches a pin's outline from its centre."""
    w = drawing.size
    ax = drawing.ax
    x0, _ = ax.transData.transform((0.0, 0.0))
    x1, _ = ax.transData.transform((w, 0.0))
    return int(abs(x1 - x0) * 1.3) + 2


def _check_drawing(drawing, s, path, empty_spot):
    fig, ax = drawing.figure, drawing.ax
    fig.savefig(path, dpi=fig.dpi)
    im = _image(path)
    assert im.format == "PNG"
    assert _size_ok(im, fig, fig.dpi)
    rgb = np.asarray(im.convert("RGB")).astype(int)
    bbox = ax.get_window_extent()
    P = s.points()
    half = _pin_half(drawing, fig)
    for k in _joint_points(s.mechanism):
        col, row = _px(fig, ax, P[k])
        # the joint lies inside the axes, and ink is drawn there (its pin, pivot or block)
        assert bbox.x0 < col < bbox.x1, s.mechanism.point_names[k]
        assert im.size[1] - bbox.y1 < row < im.size[1] - bbox.y0, s.mechanism.point_names[k]
        assert _has_ink(rgb, col, row, half), f"no ink at {s.mechanism.point_names[k]}"
    col, row = _px(fig, ax, empty_spot)
    assert not _has_ink(rgb, col, row, half), "ink where nothing should be drawn"
    return rgb


# -- draw ---------------------------------------------------------------------------------
def test_draw_quick_return(qr, tmp_path):
    s = qr.solve(0.15)
    d = plot.draw(qr, s, labels=True, axes=True, legend=True)
    assert isinstance(d, plot.Drawing)
    assert set(d.artists) >= {"base", "manivela", "colisa", "deslizadera", "joints"}
    # the frame covers the whole motion: the slider's travel over the crank turn
    sw = qr.sweep(0.0, 1.0, 41)
    assert d.frame[0] < sw["X4"].min() and sw["X4"].max() + 2 < d.frame[1]
    _check_drawing(d, s, tmp_path / "qr.png", empty_spot=(10.0, 3.0))


def test_draw_fourbar(fourbar, tmp_path):
    s = fourbar.solve(0.0)
    d = plot.draw(fourbar, s, labels=True)
    rgb = _check_drawing(d, s, tmp_path / "fb.png", empty_spot=(1.5, -0.6))
    # the ground pivots stand on hatched bases, three bar widths below the ground points
    fig, ax = d.figure, d.ax
    for x in (0.0, 3.0):
        col, row = _px(fig, ax, (x, -3 * d.size))
        assert _has_ink(rgb, col, row, 2)


def test_drawing_moves_in_place(fourbar, tmp_path):
    s0, s1 = fourbar.solve(0.0), fourbar.solve(0.25)
    d = plot.draw(fourbar, s0, frame=(-1.5, 3.5, -1.5, 2.5), title=False)
    before = len(d.all_artists())
    d.update(s1)
    assert len(d.all_artists()) == before        # the same artists, moved
    _check_drawing(d, s1, tmp_path / "moved.png", empty_spot=(-1.2, 2.2))
    assert d.frame == (-1.5, 3.5, -1.5, 2.5)


def test_custom_artists(qr, tmp_path):
    seen = []

    def marker(ax, xy):
        seen.append(xy.copy())
        return ax.plot(xy[:, 0], xy[:, 1], "s", color="black", markersize=4)

    seed_look = {"base": plot.Edge([3, 4, (12, 0), (-5, 0), (-5, 10), (-5, 8), 2, (-5, 2)]),
                 "manivela": plot.Disk(1, 4.0), "deslizadera": [marker, plot.AUTO]}
    s = qr.solve(0.0)
    d = plot.draw(qr, s, artists=seed_look)
    # the function gets the body's origin and points P1, P2 in global coordinates
    P = s.points()
    names = qr.point_names
    origin, p2 = P[names.index("deslizadera[0]")], P[names.index("deslizadera[2]")]
    assert np.allclose(seen[-1], [origin, origin, p2])       # P1 is the origin
    # the crank disk (radius 4 about (0, 5)) is drawn: its fill reaches (-3.5, 5)
    fig, ax = d.figure, d.ax
    fig.savefig(tmp_path / "seed.png", dpi=fig.dpi)
    rgb = np.asarray(_image(tmp_path / "seed.png").convert("RGB")).astype(int)
    col, row = _px(fig, ax, (-3.5, 5.0))
    r, g, b = rgb[row, col]
    assert r > g + 40 and r > b + 40                       # the crank's pink
    # the base outline: hatched edges at (12, 5) and (5, 0)
    for xy in ((12.0, 5.0), (5.0, 0.0)):
        assert _has_ink(rgb, *_px(fig, ax, xy), 4)
    d.update(qr.solve(0.2))                                # a function is called again
    assert len(seen) == 2 and not np.allclose(seen[0], seen[1])


def test_bad_inputs(qr, fourbar_loop):
    with pytest.raises(MechgenError, match="no body named 'crank'"):
        plot.draw(qr, 0.0, artists={"crank": plot.Disk(1, 1.0)})
    with pytest.raises(MechgenError, match="no bodies with points"):
        plot.draw(fourbar_loop, fourbar_loop.solve(0.0))
    with pytest.raises(MechgenError, match="has no point 'colisa\\[7\\]'"):
        plot.animate(qr, qr.sweep(0.0, 0.1, 2), trace="colisa[7]")
    with pytest.raises(MechgenError, match="ffmpeg|.gif"):
        plot.animate(qr, qr.sweep(0.0, 0.1, 2), "film.avi")
    with pytest.raises(TypeError):
        plot.draw(qr, "noon")


# -- assembly modes side by side -------------------------------------------------------------
def test_draw_modes_fourbar(fourbar, tmp_path):
    """Seed 000's two four-bar figures: θ3, θ4 = 0.5274, 1.7925 and -1.0482, -2.3133."""
    s1 = fourbar.solve(0.0)
    s2 = fourbar.solve(0.0, guess={"Th3": -1.0, "Th4": -2.3, "X4": 3.0, "Y4": 0.0})
    assert s2["Th3"] == pytest.approx(-1.048246730, abs=1e-6)
    ds = plot.draw_modes(fourbar, [s1, s2])
    assert len(ds) == 2 and ds[0].frame == ds[1].frame
    assert ds[0].ax.get_title().startswith("mode 1: Th3 = 0.5274")
    fig = ds[0].figure
    fig.savefig(tmp_path / "modes.png", dpi=fig.dpi)
    rgb = np.asarray(_image(tmp_path / "modes.png").convert("RGB")).astype(int)
    half = _pin_half(ds[0], fig)
    k = fourbar.point_names.index("rocker[2]")          # the coupler-rocker joint
    for d, s, other in ((ds[0], s1, s2), (ds[1], s2, s1)):
        assert _has_ink(rgb, *_px(fig, d.ax, s.points()[k]), half)
        assert not _has_ink(rgb, *_px(fig, d.ax, other.points()[k]), half)


# -- animate ----------------------------------------------------------------------------------
def test_animate_quick_return_gif(qr, tmp_path):
    sw = qr.sweep(0.0, 1.0, 6)
    a = plot.animate(qr, sw, tmp_path / "qr.gif", fps=10)
    im = _image(tmp_path / "qr.gif")
    # one crank turn: T = 1 repeats T = 0 and is left out of the looping film
    assert im.format == "GIF" and im.n_frames == 5
    fig, ax = a.figure, a.drawing.ax
    assert _size_ok(im, fig, 80)
    fig.set_dpi(80)
    ax.apply_aspect()
    half = _pin_half(a.drawing, fig)
    P = sw.points()
    k = qr.point_names.index("deslizadera[0]")          # the slider's pin
    frames = []
    for f in range(im.n_frames):
        im.seek(f)
        rgb = np.asarray(im.convert("RGB")).astype(int)
        frames.append(rgb)
        assert _has_ink(rgb, *_px(fig, ax, P[f, k]), half), f"frame {f}"
    assert np.any(frames[0] != frames[2])                # the mechanism moved


def test_animate_fourbar_trace(fourbar, tmp_path):
    sw = fourbar.sweep(0.0, 1.0, 8)
    a = plot.animate(fourbar, sw, None, trace=["crank[2]"])     # the crank pin's circle
    assert len(a) == 7 and a.path is None                       # T = 1 repeats T = 0
    frames = list(a.frames(dpi=72))
    assert len(frames) == 7 and frames[0].shape[2] == 3
    fig, ax = a.figure, a.drawing.ax
    fig.set_dpi(72)
    ax.apply_aspect()
    k = fourbar.point_names.index("crank[2]")
    spot = _px(fig, ax, sw.points()[4, k])       # half a turn away from the start
    trace = _rgb(a.traces[0].get_color())

    def traced(rgb):
        win = _window(rgb.astype(int), *spot, 3)
        return bool(np.any(np.all(np.abs(win - trace) < 40, axis=-1)))
    assert not traced(frames[0]) and traced(frames[-1])
    a.save(tmp_path / "fb.gif", dpi=60)
    assert _image(tmp_path / "fb.gif").n_frames == 7


# -- plot -------------------------------------------------------------------------------------
def test_plot_stroke(qr, tmp_path):
    sw = qr.sweep(0.0, 1.0, 51)
    lines = plot.plot(sw, "X4")
    assert len(lines) == 1 and np.allclose(lines[0].get_ydata(), sw["X4"])
    ax = lines[0].axes
    # T is said to be the time; lengths have no unit unless one is named (never "[length]")
    assert ax.get_xlabel() == "time T [s]" and ax.get_ylabel() == "X4"
    fig = ax.figure
    fig.savefig(tmp_path / "x4.png", dpi=fig.dpi)
    im = _image(tmp_path / "x4.png")
    assert _size_ok(im, fig, fig.dpi)
    rgb = np.asarray(im.convert("RGB")).astype(int)
    color = _rgb(lines[0].get_color())
    for k in (0, 30, 50):                       # the curve passes through its points
        win = _window(rgb, *_px(fig, ax, (sw.t[k], sw["X4"][k])), 2)
        assert np.any(np.all(np.abs(win - color) < 50, axis=-1))


def test_plot_family_and_against(qr):
    family = [qr.with_params(longitud=L).sweep(0.0, 1.0, 21) for L in (1.5, 2.25, 3.0)]
    lines = plot.plot(family, "X4")
    assert [ln.get_label() for ln in lines] == ["longitud = 1.5", "longitud = 2.25",
                                                "longitud = 3"]
    assert lines[0].axes.get_legend() is not None
    # a shorter crank, a shorter stroke (seed 001, section 5)
    strokes = [np.ptp(ln.get_ydata()) for ln in lines]
    assert strokes[0] < strokes[1] < strokes[2]
    fig, ax = plt.subplots()
    sw = qr.sweep(0.0, 1.0, 21, level="velocity")
    lines = plot.plot(sw, "Th3d", x="Th3", ax=ax)
    assert lines[0].axes is ax
    assert np.allclose(lines[0].get_xdata(), sw["Th3"])
    assert ax.get_xlabel() == "Th3 [rad]" and ax.get_ylabel() == "Th3d [rad/s]"
    with pytest.raises(KeyError, match="Th3dd"):
        plot.plot(sw, "Th3dd")
    assert plot.unit(qr, "X4dd") == "length/s²" and plot.unit(qr, "stroke_x") == ""


# -- command line -----------------------------------------------------------------------------
@pytest.fixture(scope="module")
def cli_outdir(build_dir):
    """The session's build folder: a module another test compiled there is reused."""
    return build_dir


def _cli(*argv):
    from mechgen.cli import main
    return main([str(a) for a in argv])


def test_cli_pictures(tmp_path, cli_outdir, capsys):
    model = os.path.join(EXAMPLES, "quick_return.py")
    png = tmp_path / "qr.png"
    assert _cli("draw", model, "-t", 0.15, "-o", png, "--outdir", cli_outdir, "--labels") == 0
    assert os.path.exists(os.path.join(cli_outdir, "quick_return.py"))   # built there
    assert _image(png).format == "PNG"
    gif = tmp_path / "qr.gif"
    assert _cli("animate", model, "-o", gif, "--outdir", cli_outdir, "-n", 4,
                "--trace", "colisa[2]") == 0
    assert _image(gif).n_frames == 3           # T = 1 repeats T = 0: left out
    plotted = tmp_path / "stroke.png"
    assert _cli("plot", model, "X4", "X4d", "-o", plotted, "--outdir", cli_outdir,
                "-n", 21) == 0
    assert _image(plotted).format == "PNG"
    out = capsys.readouterr().out
    assert "wrote" in out and str(gif) in out


def test_cli_failures(tmp_path, cli_outdir, capsys, monkeypatch):
    model = os.path.join(EXAMPLES, "quick_return.py")
    assert _cli("plot", model, "X9", "-o", tmp_path / "p.png", "--outdir", cli_outdir) == 1
    assert "'X9' is neither a coordinate nor an output" in capsys.readouterr().err
    from matplotlib import animation
    monkeypatch.setattr(animation.writers, "is_available", lambda name: False)
    assert _cli("animate", model, "-o", tmp_path / "a.mp4", "--outdir", cli_outdir) == 1
    assert "needs ffmpeg" in capsys.readouterr().err
    assert _cli("draw", model, "-o", tmp_path / "nowhere" / "d.png",
                "--outdir", cli_outdir) == 1
    assert "does not exist" in capsys.readouterr().err


@pytest.mark.parametrize("command", ["draw", "animate", "plot"])
def test_cli_help(command, capsys):
    with pytest.raises(SystemExit) as exc:
        _cli(command, "--help")
    assert exc.value.code == 0
    text = capsys.readouterr().out
    assert "--output" in text and "--outdir" in text


def test_build_keeps_dash_o():
    from mechgen.cli import parser
    args = parser().parse_args(["build", "model.py", "-o", "somewhere"])
    assert args.outdir == "somewhere"


def test_drawing_never_imports_sympy():
    code = ("import sys, matplotlib; matplotlib.use('Agg'); import mechgen; "
            "from mechgen import plot; "
            f"m = mechgen.load({os.path.join(GENERATED, 'quick_return.py')!r}); "
            "plot.draw(m, m.solve(0.3), labels=True, axes=True); "
            "plot.plot(m.sweep(0, 1, 5), 'X4'); "
            "print('sympy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=ROOT, timeout=300)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().splitlines()[-1] == "False"


# -- the parts of the layer: plane geometry, the scene, the level a plot needs -----------------
def test_plane_geometry():
    from mechgen.plot.glyphs.shapes import hatch, hull, rot, rounded
    square = np.array([(0, 0), (2, 0), (2, 2), (0, 2), (1, 1), (1, 0)])  # an inner, an edge point
    h = hull(square)
    assert len(h) == 4 and set(map(tuple, h)) == {(0, 0), (2, 0), (2, 2), (0, 2)}
    area = 0.5 * np.sum(h[:, 0] * np.roll(h[:, 1], -1) - np.roll(h[:, 0], -1) * h[:, 1])
    assert area == pytest.approx(4.0)                  # positive: counter-clockwise
    assert rot(np.pi / 2) @ (1.0, 0.0) == pytest.approx([0.0, 1.0])
    bar = rounded([(0, 0), (3, 0)], 0.5)               # a bar of half-width 0.5, round ends
    assert bar[:, 0].min() == pytest.approx(-0.5) and bar[:, 0].max() == pytest.approx(3.5)
    assert np.abs(bar[:, 1]).max() == pytest.approx(0.5)
    ticks = hatch([(0, 0), (4, 0)], 1.0, 0.5)          # every 1.0, 0.5 long, on the right
    assert [a[0] for a, _ in ticks] == pytest.approx([0.5, 1.5, 2.5, 3.5])
    for a, b in ticks:
        assert a[1] == 0 and b[1] < 0 and np.hypot(*(b - a)) == pytest.approx(0.5)
    left = hatch([(0, 0), (4, 0)], 1.0, 0.5, side=-1.0)
    assert all(b[1] > 0 for _, b in left)


def test_scene_of_quick_return(qr):
    from mechgen.plot.scene import Scene
    st = Scene(qr, colors={"colisa": "blue"})
    assert [b.name for b in st.bodies] == ["base", "manivela", "colisa", "deslizadera"]
    base, colisa = st.by_name["base"], st.by_name["colisa"]
    assert base.ground and base.th is None and base.origin == -1
    assert qr.coordinates[colisa.th] == "Th3"
    assert colisa.edge == (0.0, 0.0, 1.0) and colisa.fill == pytest.approx((0.55, 0.55, 1.0))
    assert st.point("colisa[2]") == qr.point_names.index("colisa[2]") == st.point(7)
    assert st.point("colisa[0]") == colisa.origin
    sw = qr.sweep(0.0, 1.0, 5)
    org, ang = st.poses(sw.points(), sw.Q)
    assert org.shape == (5, 4, 2) and ang.shape == (5, 4)
    assert np.allclose(org[:, 2], sw.points()[:, colisa.origin])
    assert np.allclose(ang[:, 2], sw["Th3"]) and not np.any(ang[:, 0]) and not np.any(org[:, 0])
    with pytest.raises(MechgenError, match="colors: no body named 'crank'"):
        Scene(qr, colors={"crank": "red"})


def test_needed_level(qr):
    from mechgen.plot.timeplot import needed_level
    assert needed_level(qr, ["X4", "stroke_x"]) == "position"
    assert needed_level(qr, ["X4", "Th3d"]) == "velocity"
    assert needed_level(qr, ["stroke_xd"]) == "velocity"
    assert needed_level(qr, ["Th3", "X4dd"]) == "acceleration"
    with pytest.raises(KeyError, match="X9"):
        needed_level(qr, ["X9"])


def test_drawing_moves_all_but_the_ground(qr):
    d = plot.draw(qr, 0.1, frame="pose")
    moving = {id(a) for a in d.moving()}
    assert not moving & {id(a) for a in d.artists["base"]}
    assert {id(a) for a in d.artists["joints"] + d.artists["colisa"]} <= moving
    assert id(d.title) in moving


def test_public_names():
    assert sorted(plot.__all__) == sorted(
        ["draw", "draw_modes", "animate", "plot", "motion", "unit", "Drawing", "Animation",
         "Shape", "Disk", "Bar", "Edge", "Plate", "AUTO", "check_movie_path",
         "effort", "polar", "force_arrows", "EffortPlot", "PolarPlot", "ForceArrows",
         "band_plot"])
    for name in plot.__all__ + ["BAR", "MARGIN", "MOTION_POINTS", "PALETTE", "INK", "MOVIES"]:
        assert getattr(plot, name) is not None
    assert callable(plot.draw) and callable(plot.animate) and callable(plot.plot)
