"""Pictures of synthesis (mechgen.plot.synthesis): the poses, the centre- and circle-point
curves of four poses, Burmester points, the four-bar at every pose; and the circle-point
curve itself: the pose-1 positions of sampled moving pivots lie on it, other points not."""
import cmath

import matplotlib
import numpy as np
import pytest

from mechgen import synthesis
from mechgen.plot import synthesis as pictures

matplotlib.use("Agg")

GATE = [(0.845, 0.606, 0.360), (0.689, 0.823, 0.180), (0.368, 0.818, 0.054),
        (0.075, 0.592, 0.021), (-0.027, 0.263, 0.088)]


def value(C, x, y):
    """Σ C[i, k] x^i y^k over the sum of the terms' sizes (0 on the curve)."""
    terms = [C[i, k] * x ** i * y ** k for i in range(4) for k in range(4)]
    return sum(terms) / sum(abs(t) for t in terms)


def at_pose(pose, u):
    z = complex(pose[0], pose[1]) + cmath.exp(1j * pose[2]) * complex(*u)
    return z.real, z.imag


@pytest.mark.parametrize("seed", range(3))
def test_moving_pivots_lie_on_the_circle_point_curve(seed):
    rng = np.random.default_rng(40 + seed)
    poses = np.column_stack([rng.normal(size=4), rng.normal(size=4),
                             rng.uniform(-1, 1, size=4)])
    C = synthesis.circle_point_cubic(poses)
    K = synthesis.centre_point_cubic(poses)
    for d in synthesis.dyads(poses, samples=10):
        assert abs(value(C, *at_pose(poses[0], d.moving))) < 1e-12
        assert abs(value(K, *d.fixed)) < 1e-12
        off = at_pose(poses[0], np.array(d.moving) + 0.05)
        assert abs(value(C, *off)) > 1e-6


def labels(ax):
    return [t.get_text() for t in ax.figure.legends[0].get_texts()]


def test_four_poses_picture_has_curves_pivots_and_legend():
    import matplotlib.pyplot as plt
    poses = GATE[:4]
    link = synthesis.fourbars(poses, samples=4)[0]
    ax = pictures.figure(poses, link, centre=synthesis.centre_point_cubic(poses),
                         circle=synthesis.circle_point_cubic(poses), title="four")
    assert ax.get_aspect() == 1.0
    names = labels(ax)
    assert any("centre-point" in n for n in names) and any("circle-point" in n for n in names)
    assert "poses" in names and "coupler" in names
    assert len(ax.collections) >= 2                      # the two contours
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    for p in pictures.pins(link):                         # the whole four-bar is in view
        assert x0 <= p[0] <= x1 and y0 <= p[1] <= y1
    plt.close(ax.figure)


def test_five_poses_picture_notes_far_burmester_points():
    import matplotlib.pyplot as plt
    dyads = synthesis.dyads(GATE)
    link = synthesis.fourbars(GATE)[0]
    ax = pictures.figure(GATE, link, fixed=[d.fixed for d in dyads],
                         moving=[at_pose(GATE[0], d.moving) for d in dyads])
    notes = [t.get_text() for t in ax.texts if "beyond the picture" in t.get_text()]
    assert notes == ["1 Burmester pair(s) beyond the picture, fixed pivot at (35, -27.3)"]
    assert any("Burmester points: fixed" in n for n in labels(ax))
    plt.close(ax.figure)
