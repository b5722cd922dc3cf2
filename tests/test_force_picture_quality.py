"""Force pictures a designer would publish (issue 43): the polar diagram broken where a load
switches on or off (no chord drawn through the origin), every angle label with its degree
sign, present and clear of the curve, units on every axis and on the mean line of
plot.effort, the bodies of a drawing stacked so that none hides another (the crank over
the lever), and point labels that name the body (``colisa.P2``) in a forces drawing.

Everything is read back from the matplotlib artists.
"""
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.patches import Polygon  # noqa: E402

import mechgen  # noqa: E402
from mechgen import Model, Piecewise, T, cos, pi, plot, sin  # noqa: E402
from mechgen.plot.labels import crossings, renderer_of  # noqa: E402

from conftest import EXAMPLES  # noqa: E402

TOP = 100.0         # the switching load's size


def switching_model():
    """A crank turning once in T = 0 .. 1 with a load at its pin turning with it, reversed
    from T = 0.5 on: the pin's force jumps from (−100, 0) to (100, 0), straight across the
    origin of its polar diagram."""
    m = Model("switching_pin")
    base = m.ground("base", points=[(0, 0), (1, 0)])
    crank = m.body("crank", points=[(0, 0), (0.2, 0)], guess=(0, 0, 0.0))
    m.revolute(base[1], crank[1], name="A")
    m.rotation_lock(crank, 2 * pi * T, name="motor")
    s = Piecewise((-1.0, T > 0.5), (1.0, True))
    m.force(crank[2], (TOP * s * cos(2 * pi * T), TOP * s * sin(2 * pi * T)), name="press")
    return m


@pytest.fixture(scope="module")
def switching(tmp_path_factory):
    return mechgen.compile(switching_model(), outdir=str(tmp_path_factory.mktemp("sw")),
                           tier="python")


@pytest.fixture(scope="module")
def qr(tmp_path_factory):
    return mechgen.compile(os.path.join(EXAMPLES, "quick_return_forces.py"),
                           outdir=str(tmp_path_factory.mktemp("qrf")), tier="python")


@pytest.fixture(scope="module")
def turn(qr):
    return qr.sweep(0.0, 1.0, 361, level="dynamic")


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _segments(line):
    xy = np.asarray(line.get_xydata(), dtype=float)
    seg = np.stack([xy[:-1], xy[1:]], axis=1)
    return seg[np.all(np.isfinite(seg.reshape(len(seg), -1)), axis=1)]


def _distance_to_origin(seg):
    a, b = seg[:, 0], seg[:, 1]
    d = b - a
    t = np.clip(-np.einsum("ij,ij->i", a, d) / np.maximum(np.einsum("ij,ij->i", d, d),
                                                          1e-300), 0.0, 1.0)
    return np.hypot(*(a + t[:, None] * d).T)


# -- the polar diagram broken at a switch ------------------------------------------------
def test_polar_breaks_where_a_load_switches(switching):
    sw = switching.sweep(0.0, 1.0, 201, level="static")
    p = plot.polar(sw, "A", on="crank")
    seg = _segments(p.line)
    assert len(seg) >= 190                         # the circle itself is drawn
    # every drawn piece stays on the circle of radius TOP: no chord across the origin
    assert _distance_to_origin(seg).min() > 0.9 * TOP
    assert np.isnan(p.line.get_xydata()).any()     # the gap where it jumps
    np.testing.assert_allclose(np.hypot(*p.force.T), TOP, rtol=1e-9)   # numbers untouched


def test_polar_keeps_a_smooth_locus_whole(turn):
    p = plot.polar(turn, "O4", on="base")
    xy = np.asarray(p.line.get_xydata())
    f = np.asarray(turn.reaction("O4", on="base")[:, :2])
    jump = np.hypot(*np.diff(f, axis=0).T)
    # the quick-return's cutting force (500) switches at the stroke's ends: those steps
    # may be broken, nothing else
    assert np.isnan(xy).any(axis=1).sum() <= 2
    assert np.isfinite(xy).all(axis=1).sum() == len(f) and jump.max() > 0


# -- degree marks ------------------------------------------------------------------------
def test_effort_angle_ticks_carry_degrees(turn):
    e = plot.effort(turn, "crank driver")
    e.figure.canvas.draw()
    ticks = [t.get_text() for t in e.ax.get_xticklabels() if t.get_text()]
    assert ticks and all(t.endswith("°") for t in ticks), ticks
    assert "225°" in ticks and "270°" in ticks and "315°" in ticks


@pytest.mark.parametrize("marks", [8, 12])
@pytest.mark.parametrize("where", [("slot", "manivela"), ("O4", "base")])
def test_polar_labels_every_ray_with_degrees_clear_of_the_curve(turn, marks, where):
    fig, ax = plt.subplots(figsize=(7.2, 3.2))
    p = plot.polar(turn, where[0], on=where[1], ax=ax, marks=marks)
    fig.canvas.draw()
    texts = [t.get_text() for t in p.texts]
    assert len(texts) == len(p.at) == marks                 # every ray labelled
    assert all(t.endswith("°") for t in texts), texts
    step = 360 // marks
    assert set(texts) == {f"{a}°" for a in range(0, 360, step)}
    renderer = renderer_of(fig)
    curve = ax.transData.transform(np.asarray(p.line.get_xydata(), dtype=float))
    seg = np.stack([curve[:-1], curve[1:]], axis=1)
    seg = seg[np.all(np.isfinite(seg.reshape(len(seg), -1)), axis=1)]
    boxes = np.array([tuple(t.get_window_extent(renderer).extents) for t in p.texts])
    hit = crossings(boxes, seg)
    assert not hit.any(), [t for t, h in zip(texts, hit) if h]
    for i in range(len(boxes)):                              # nor on each other
        for j in range(i):
            a, b = boxes[i], boxes[j]
            assert not (a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]), \
                (texts[i], texts[j])


# -- units -------------------------------------------------------------------------------
def test_effort_says_its_units(turn):
    e = plot.effort(turn, "crank driver")
    y = e.ax.get_ylabel()
    assert "[" in y and "model units" in y, y
    assert "model units" in e.mean_line.get_label(), e.mean_line.get_label()
    assert e.ax.get_xlabel().endswith("[°]")
    title = e.ax.get_title()
    assert "T = " not in title and "time 0 .. 1 s" in title, title


def test_polar_axes_say_their_units(turn):
    p = plot.polar(turn, "O4", on="base")
    for label in (p.ax.get_xlabel(), p.ax.get_ylabel()):
        assert "model units" in label, label
    assert "T = " not in p.ax.get_title() and "time 0 .. 1 s" in p.ax.get_title()


# -- the drawing -------------------------------------------------------------------------
def _outline(d, body):
    return max((a for a in d.artists[body] if isinstance(a, Polygon)),
               key=lambda a: len(a.get_xy()))


def test_the_crank_is_drawn_over_the_lever_and_its_slot(qr):
    d = plot.draw(qr, qr.solve(0.7, level="dynamic"), forces=True)
    crank = _outline(d, "manivela")
    lever = [a.get_zorder() for a in d.artists["colisa"] if isinstance(a, Polygon)]
    assert crank.get_zorder() > max(lever)          # the lever and its white slot below
    block = [a.get_zorder() for a in d.artists["joints"] if isinstance(a, Polygon)]
    assert max(block) > crank.get_zorder()          # the crank pin's block still on top


def test_forces_drawing_labels_name_body_and_point(qr):
    d = plot.draw(qr, qr.solve(0.7, level="dynamic"), forces=True, labels=True)
    texts = [t for t, _ in d.labels]
    assert len(set(texts)) == len(texts), texts
    assert "manivela.P2·colisa.P3" in texts or any("manivela.P2" in t for t in texts), texts
    assert all("." in t for t in texts), texts
    # the artist shows the same names
    d.figure.canvas.draw()
    assert not [t for t in texts if t.startswith("P")]
    plain = plot.draw(qr, qr.solve(0.7), labels=True)
    assert any(t.startswith("P") for t, _ in plain.labels)     # plain drawings unchanged
    assert math.isfinite(d.forces.scale)
