"""Issue 14's pictures: labels that collide with nothing (measured with the renderer),
one label for a shared joint, the ground link, the slider's side of its guide, one
period animated without a repeated frame, coupler points traced, time plots that state
what T is, no made-up units, twin axes and equal scale; and the README's files ignored.

The models of this file are built for positions only and solved in closed form here
(their guesses are exact assemblies), so that numba compiles no solver: fast tests.
"""
import os
import re
import shutil
import subprocess

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from matplotlib.patches import FancyArrow, Polygon  # noqa: E402

import models  # noqa: E402
from conftest import ROOT, example_model  # noqa: E402
from mechgen import MechgenError, plot  # noqa: E402
from mechgen.runtime.results import Solution, Sweep  # noqa: E402

SEED_LOOK = {"base": plot.Edge([3, 4, (12, 0), (-5, 0), (-5, 10), (-5, 8), 2, (-5, 2)]),
             "manivela": plot.Disk(1, 4.0)}


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


# -- two models: Jansen's leg (examples/strandbeest.py) and an in-line slider-crank ------
def strandbeest_model():
    """Jansen's leg (his "holy numbers") at crank angle 0: three bodies meet at the crank
    pin, three at the frame's second pivot, three at the foot's upper joint
    (examples/strandbeest.py)."""
    return example_model("strandbeest")


def slider_crank_model():
    """tests/models.py's in-line slider-crank: crank 1, rod 3, the slider's guide along the
    x axis through the crank's pivot (ground points (-2, 0), (6, 0)), θ = 2πT."""
    return models.slider_crank("inline_slider_crank", 1.0, 3.0,
                               ground=[(0, 0), (-2, 0), (6, 0)], drive="crank angle").m


def slider_crank_q(t):
    """The slider-crank's coordinates in closed form (X2 Y2 Th2 X3 Y3 Th3 X4 Y4 Th4):
    tests/models.slider_crank_q, whose rod angle is −asin(sin θ / 3) in line."""
    return np.array(models.slider_crank_q(t, 1.0, 3.0), dtype=float)


@pytest.fixture(scope="module")
def beest(build_dir):
    import mechgen
    from mechgen.compiler.build import build
    return mechgen.load(build(strandbeest_model(), os.path.join(build_dir, "pictures"),
                              level="position"))


@pytest.fixture(scope="module")
def slider_crank(build_dir):
    import mechgen
    from mechgen.compiler.build import build
    return mechgen.load(build(slider_crank_model(), os.path.join(build_dir, "pictures"),
                              level="position"))


def _sweep(mech, times, q_of):
    t = np.asarray(times, dtype=float)
    return Sweep(mech, t, np.array([q_of(x) for x in t]))


# -- geometry on screen -----------------------------------------------------------------------
def _boxes(d):
    """The labels' extents on screen: [(text, Bbox)]."""
    d.figure.canvas.draw()
    renderer = d.figure.canvas.get_renderer()
    return [(text, art.get_window_extent(renderer)) for text, art in d.labels]


def _segments(d, kinds):
    """Display-pixel segments of the drawing: hatching ("hatch": LineCollections), lines
    and arrows ("line": Line2D with a line style, FancyArrow outlines)."""
    ax, out = d.ax, []
    if "hatch" in kinds:
        for coll in ax.collections:
            if isinstance(coll, LineCollection):
                tf = coll.get_transform()
                out += [tf.transform(np.asarray(s, dtype=float)) for s in coll.get_segments()]
    if "line" in kinds:
        for line in ax.lines:
            if line.get_linestyle() not in ("None", "none", ""):
                out.append(line.get_transform().transform(np.asarray(line.get_xydata())))
        for p in ax.patches:
            if isinstance(p, FancyArrow):
                out += p.get_path().transformed(p.get_transform()).to_polygons()
    return out


def _touches(bbox, polyline):
    """True when a polyline comes inside the box (sampled finely along each segment)."""
    s = np.linspace(0.0, 1.0, 200)[:, None]
    for a, b in zip(polyline[:-1], polyline[1:]):
        pts = a + s * (b - a)
        if np.any((pts[:, 0] > bbox.x0) & (pts[:, 0] < bbox.x1) &
                  (pts[:, 1] > bbox.y0) & (pts[:, 1] < bbox.y1)):
            return True
    return False


def _check_labels(d):
    boxes = _boxes(d)
    assert boxes
    for i, (t1, b1) in enumerate(boxes):
        for t2, b2 in boxes[i + 1:]:
            assert not b1.overlaps(b2), f"labels {t1} and {t2} overlap"
    for seg in _segments(d, ("hatch",)):
        for text, bb in boxes:
            assert not _touches(bb, seg), f"label {text} sits on hatching"
    return dict(boxes)


def test_labels_of_the_quick_return_collide_with_nothing(qr):
    d = plot.draw(qr, qr.solve(0.0), artists=SEED_LOOK, labels=True, axes=True, legend=True)
    boxes = _check_labels(d)
    texts = [t for t, _ in d.labels]
    # the base's P1 and the lever's P1 are one pin: one label, and no line strikes it
    assert sorted(texts) == sorted(["P1·P1", "P2·P1", "P3", "P4", "P2", "P2", "P1", "P2"])
    for seg in _segments(d, ("line",)):
        assert not _touches(boxes["P1·P1"], seg), "the base's P1 is struck through"
    # every joint's pin stays visible: no label covers a joint's centre
    P = qr.solve(0.0).points()
    for _, kind, used in qr.module.JOINTS:
        for k in used:
            x, y = d.ax.transData.transform(P[k])
            for text, bb in boxes.items():
                assert not bb.contains(x, y), f"{text} hides {qr.point_names[k]}"
    d2 = plot.draw(qr, qr.solve(0.15), labels=True, axes=True)   # the CLI's look
    _check_labels(d2)


def test_labels_of_a_strandbeest_leg_merge_at_its_joints(beest):
    s = Solution(beest, 0.0, np.array(beest.module.GUESS, dtype=float))
    from mechgen.plot.scene import Scene
    P, scene = s.points(), Scene(beest)

    def at(label):
        return P[scene.point(label)]
    # the guess is an assembly: the joined points coincide
    for p, q in (("crank[2]", "upper[1]"), ("crank[2]", "lower[1]"), ("frame[2]", "hip[1]"),
                 ("cee[2]", "foot[1]"), ("upper[2]", "hip[2]"), ("eff[2]", "foot[2]")):
        assert np.allclose(at(p), at(q), atol=1e-9), (p, q)
    d = plot.draw(beest, s, frame="pose", labels=True, legend=True)
    _check_labels(d)
    texts = [t for t, _ in d.labels]
    # 18 points at 8 places: crank P2 = upper P1 = lower P1, frame P2 = hip P1 = cee P1,
    # lower P2 = cee P2 = foot P1, ...: one label at each, the foot's P3 alone
    assert sorted(texts) == sorted(["P1·P1", "P2·P1·P1", "P2·P1·P1", "P2·P2", "P3·P1",
                                    "P2·P2·P1", "P2·P2", "P3"])


def test_labels_placed_on_the_panels_as_laid_out(fourbar):
    s1 = fourbar.solve(0.0)
    s2 = fourbar.solve(0.0, guess={"Th3": -1.0, "Th4": -2.3, "X4": 3.0, "Y4": 0.0})
    for d in plot.draw_modes(fourbar, [s1, s2], labels=True):   # after tight_layout
        assert sorted(t for t, _ in d.labels) == ["P1·P1", "P2·P1", "P2·P1", "P2·P2"]
        _check_labels(d)
    d = plot.draw(fourbar, s1, labels=True)
    d.figure.set_size_inches(4.0, 3.0)           # the user's own layout, then placed anew
    d.update(fourbar.solve(0.3))
    d.place_labels()
    _check_labels(d)


def test_ground_link_of_the_fourbar(fourbar, tmp_path):
    d = plot.draw(fourbar, fourbar.solve(0.0))
    bars = [a for a in d.artists["ground"] if isinstance(a, Polygon) and a.get_zorder() < 1.2]
    assert len(bars) == 1                    # the fourth bar, from pivot to pivot
    xy = bars[0].get_xy()
    assert xy[:, 0].min() < 0.0 < 3.0 < xy[:, 0].max() and np.abs(xy[:, 1]).max() < 2 * d.size
    fig = d.figure
    fig.savefig(tmp_path / "fb.png", dpi=fig.dpi)
    from PIL import Image
    rgb = np.asarray(Image.open(tmp_path / "fb.png").convert("RGB")).astype(int)
    x, y = d.ax.transData.transform((1.5, 0.0))
    r, g, b = rgb[int(round(fig.get_size_inches()[1] * fig.dpi - y)), int(round(x))]
    assert abs(r - 217) < 12 and abs(g - 217) < 12 and abs(b - 217) < 12   # the ground grey
    # a custom ground drawing replaces it (the seed's base outline)
    d = plot.draw(fourbar, fourbar.solve(0.0), artists={"ground": plot.Edge([1, 2])})
    assert not [a for a in d.artists["ground"] if isinstance(a, Polygon)
                and a.get_zorder() < 1.2]


def _box_side(d, name):
    """The signs of y of the slider's box corners, globally, at the drawn configuration."""
    box = next(a for a in d.artists[name] if isinstance(a, Polygon))
    xy = box.get_transform().transform(box.get_xy())
    return d.ax.transData.inverted().transform(xy)[:, 1]


def test_slider_on_the_same_side_in_draw_and_animate(slider_crank):
    upper = _sweep(slider_crank, np.linspace(0.0, 0.5, 11), slider_crank_q)   # crank above
    lower = _sweep(slider_crank, np.linspace(0.5, 1.0, 11), slider_crank_q)   # crank below
    s = Solution(slider_crank, 0.25, slider_crank_q(0.25))
    sides = [_box_side(plot.draw(slider_crank, s, sweep=upper), "slider"),
             _box_side(plot.draw(slider_crank, s, sweep=lower), "slider"),
             _box_side(plot.animate(slider_crank, upper).drawing, "slider"),
             _box_side(plot.animate(slider_crank, lower).drawing, "slider")]
    for y in sides:        # on the guide's left (above it), whatever the motion framed
        assert y.min() > -1e-9 and y.max() > 0.05


def test_animation_of_one_period_has_no_repeated_frame(slider_crank):
    turn = _sweep(slider_crank, np.linspace(0.0, 1.0, 9), slider_crank_q)
    assert plot.animation.repeats_first(turn.points())
    assert len(plot.animate(slider_crank, turn)) == 8
    assert len(plot.animate(slider_crank, turn, periodic=False)) == 9
    half = _sweep(slider_crank, np.linspace(0.0, 0.5, 9), slider_crank_q)
    assert not plot.animation.repeats_first(half.points())
    assert len(plot.animate(slider_crank, half)) == 9
    assert len(plot.animate(slider_crank, half, periodic=True)) == 8
    a = plot.animate(slider_crank, turn, trace="rod[2]")
    frames = list(a.frames(dpi=40))
    assert len(frames) == 8
    assert len(a.traces[0].get_xdata()) == 9       # the last frame closes the traced path


def test_trace_of_a_coupler_point(fourbar):
    sw = fourbar.sweep(0.0, 1.0, 25)
    a = plot.animate(fourbar, sw, trace=["coupler.at(1.25, 0.8)", "coupler[2]"])
    frames = list(a.frames(dpi=30))
    assert len(frames) == 24
    xy = np.column_stack(a.traces[0].get_data())
    o = sw.points()[:, fourbar.point_names.index("coupler[0]")]
    th = sw["Th3"]
    want = o + np.column_stack([1.25 * np.cos(th) - 0.8 * np.sin(th),
                                1.25 * np.sin(th) + 0.8 * np.cos(th)])
    assert np.allclose(xy, want)
    # a coupler curve, not the rocker's circle that coupler[2] (a joint) draws
    pivot = np.array([3.0, 0.0])
    joint = np.column_stack(a.traces[1].get_data())
    assert np.ptp(np.hypot(*(joint - pivot).T)) < 1e-9
    assert np.ptp(np.hypot(*(xy - pivot).T)) > 0.3
    with pytest.raises(MechgenError, match="no body 'cupler'"):
        plot.animate(fourbar, sw, trace="cupler.at(1, 0)")
    with pytest.raises(MechgenError, match="two numbers"):
        plot.animate(fourbar, sw, trace="coupler.at(a, 0)")


# -- time plots --------------------------------------------------------------------------------
def test_time_axis_and_units(qr):
    sw = qr.sweep(0.0, 1.0, 21, level="velocity")
    ax = plot.plot(sw, "X4")[0].axes
    assert ax.get_xlabel() == "time T [s]" and ax.get_ylabel() == "X4"
    assert "length" not in ax.get_ylabel()
    ax = plot.plot(sw, "X4d", length="mm", time="min")[0].axes
    assert ax.get_xlabel() == "time T [min]" and ax.get_ylabel() == "X4d [mm/min]"
    assert plot.unit(qr, "X4", length=None) == "" and plot.unit(qr, "Th3d") == "rad/s"
    assert plot.unit(qr, "stroke_xd") == ""       # an output's unit is not known


def test_cli_plot_units(qr, build_dir, tmp_path, monkeypatch):
    from mechgen.cli import main
    seen = []
    real = plot.plot

    def spy(*args, **kwargs):
        lines = real(*args, **kwargs)
        seen.append([lines[0].axes.get_xlabel()] + [ln.axes.get_ylabel() for ln in lines])
        return lines
    monkeypatch.setattr(plot, "plot", spy)
    # the labels are the point: the plain-Python tier, not a compile of the fresh build
    monkeypatch.setenv("MECHGEN_TIER", "python")
    model = os.path.join(ROOT, "examples", "quick_return.py")
    assert main(["plot", model, "X4", "X4d", "-o", str(tmp_path / "p.png"), "--outdir",
                 build_dir, "-n", "11", "--length", "mm"]) == 0
    assert seen[-1] == ["time T [s]", "X4 [mm]", "X4d [mm/s]"]     # on twin axes


def test_different_sizes_on_twin_axes(qr):
    sw = qr.sweep(0.0, 1.0, 21, level="velocity")
    lines = plot.plot(sw, "X4", "X4d")
    left, right = lines[0].axes, lines[1].axes
    assert left is not right and right.get_shared_x_axes().joined(left, right)
    assert left.get_ylabel() == "X4" and right.get_ylabel() == "X4d"
    assert lines[0].get_color() != lines[1].get_color()
    # each axis' label in its line's colour says which is which: no legend over the lines
    assert left.yaxis.label.get_color() == lines[0].get_color()
    assert right.yaxis.label.get_color() == lines[1].get_color()
    assert left.get_legend() is None and right.get_legend() is None
    lines = plot.plot(sw, "X4", "X4d", "Y4")      # X4 and Y4 share the left axis: a legend
    assert lines[0].axes is lines[2].axes is not lines[1].axes
    assert len(lines[1].axes.get_legend().get_texts()) == 3
    # two outputs of unknown unit, sizes far apart (9.5 against 85): twin axes too
    lines = plot.plot(sw, "stroke_x", "stroke_xd")
    assert lines[0].axes is not lines[1].axes
    # alike (X4 and Y4, lengths of a size): one axis, one label for both
    lines = plot.plot(sw, "X4", "Y4", length="cm")
    assert lines[0].axes is lines[1].axes and lines[0].axes.get_ylabel() == "X4, Y4 [cm]"
    # the first quantity named keeps the left axis
    lines = plot.plot(sw, "X4d", "X4")
    assert lines[0].axes.get_ylabel() == "X4d" and lines[1].axes.get_ylabel() == "X4"
    assert lines[0].axes.yaxis.get_label_position() == "left"


def test_a_path_is_drawn_at_equal_scale(qr):
    from mechgen.plot.timeplot import is_path
    sw = qr.sweep(0.0, 1.0, 21, level="velocity")
    ax = plot.plot(sw, "Y3", x="X4")[0].axes           # lengths against a length
    assert ax.get_aspect() == 1.0
    ax = plot.plot(sw, "Th3d", x="Th3")[0].axes        # a phase portrait: free scales
    assert ax.get_aspect() == "auto"
    ax = plot.plot(sw, "stroke_x", x="X4", equal=True)[0].axes
    assert ax.get_aspect() == 1.0
    assert is_path(qr, ["Y4"], "X4") and not is_path(qr, ["Y4"], None)
    from mechgen.plot.timeplot import _xy_pair
    assert _xy_pair("foot_x", "foot_y") and _xy_pair("X", "Y") and _xy_pair("xG", "yG")
    assert not _xy_pair("X4", "Y3") and not _xy_pair("x", "x")


# -- Solution shows the outputs -----------------------------------------------------------------
def test_solution_shows_declared_outputs(qr):
    s = qr.solve(0.15, level="velocity")
    assert qr.outputs == ("stroke_x",)
    keys = list(s.keys())
    assert keys[-2:] == ["stroke_x", "stroke_xd"] and "stroke_xdd" not in keys
    assert keys == qr.sweep(0.15, 0.2, 2, level="velocity").columns()
    assert s.as_dict()["stroke_x"] == pytest.approx(s["X4"])
    assert "stroke_x -> 6.92194" in repr(s) and "stroke_xd -> -18.7395" in repr(s)
    assert "<td>stroke_xd</td>" in s._repr_html_()
    zero = Solution(qr, 0.0, -np.zeros(len(qr.coordinates)))
    assert "-> -0" not in repr(zero) and ">-0<" not in zero._repr_html_()   # no minus zero


# -- the files the README's and the site's examples write -----------------------------------------
def _readme_outputs():
    """Files the README's and the documentation site's commands and snippets write: -o /
    --csv / savefig / animate."""
    from docs_pages import all_pages_text
    text = all_pages_text()
    found = set(re.findall(r"^mechgen (?:draw|animate|plot|sweep)\b.*?(?:-o|--csv) (\S+)",
                           text, re.M))
    found |= set(re.findall(r"savefig\(\"([^\"/]+)\"\)", text))
    found |= set(re.findall(r"plot\.animate\([^\n]*?\"([^\"/]+\.(?:gif|mp4))\"", text))
    return sorted(found)


def test_readme_files_are_ignored():
    if shutil.which("git") is None or not os.path.exists(os.path.join(ROOT, ".git")):
        pytest.skip("not a git checkout")
    files = _readme_outputs()
    assert {"stroke.csv", "quick_return.png", "fourbar.gif", "stroke.png",
            "quick_return.gif"} <= set(files)
    for name in files:
        assert "/" not in name                     # written where the command runs
        got = subprocess.run(["git", "check-ignore", "-q", name], cwd=ROOT)
        assert got.returncode == 0, f"{name} (written by a README example) is not ignored"
    for kept in ("docs/quick_return.png", "docs/quick_return.gif", "docs/quick_return_x4.png"):
        got = subprocess.run(["git", "check-ignore", "-q", kept], cwd=ROOT)
        assert got.returncode == 1, f"{kept} must stay tracked"


def test_an_axis_of_mixed_units_does_not_read_as_one(qr):
    """A length (no unit stated) and an angle on one axis: 'Th3 [rad], X4', not
    'X4, Th3 [rad]', which reads as both in radians."""
    from mechgen.plot.timeplot import _axis_label
    assert _axis_label(qr, ["X4", "Th3"], None, "s") == "Th3 [rad], X4"
    assert _axis_label(qr, ["X4", "Th3"], "mm", "s") == "X4 [mm], Th3 [rad]"
