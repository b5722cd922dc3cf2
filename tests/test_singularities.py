"""Singular configurations and toggles (docs/reference/runtime.md) against closed forms written
here: mech.singularities, and the extremes, roots and design tables that pass near or
through a toggle.

A change-point four-bar (a + b = c + d: crank a = 1, coupler b = 3, rocker c = 2, ground
d = 2), crank driven by θ = π/3 + 2πT, is singular at exactly one configuration per turn:
crank along the ground towards the rocker's pivot (θ = 2π), all four links on one line,
at T = 5/6.

Near a toggle: the four-bar of generated/fourbar.py with a = 1, b = 2, c = 2, d = 2.9999
(a Grashof crank-rocker a hair from its change point a + d = b + c), θ = 0.3 + 2πT: near
θ = π the coupler and the rocker nearly line up and the two assembly modes lie close. The
rocker's extremes are where crank and coupler line up: B, at c from O4 = (d, 0), is b + a
(extended) or b − a (folded) from O2 = (0, 0); the exact extremes and roots of a coarse
sweep (sw.extrema, sw.roots) and of a design table (tab.extremes) stay on the sweep's
assembly mode and reach them.
"""
import math
import os
import warnings

import pytest

import mechgen

GENERATED = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                         "generated")


@pytest.fixture(scope="module")
def change_point():
    mech = mechgen.load(os.path.join(GENERATED, "fourbar.py"), tier="python")
    return mech.with_params(a=1.0, b=3.0, c=2.0, d=2.0)


@pytest.mark.parametrize("t0, t1, n", [(0.0, 1.0, 201), (0.5, 0.9, 201), (0.0, 1.0, 11),
                                       (0.0, 1.0, 50), (0.9, 0.5, 201)])
def test_one_singular_configuration_is_reported_once(change_point, t0, t1, n):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        found = change_point.singularities(t0, t1, n=n)
    assert [s.t for s in found] == pytest.approx([5 / 6], abs=1e-8)


def test_crank_rocker_driven_by_its_crank_never_loses_rank():
    mech = mechgen.load(os.path.join(GENERATED, "fourbar.py"), tier="python")
    assert mech.singularities(0.0, 1.0) == []
    assert mech.singularities(0.0, 3.0) == []


A, B, C, D, PHASE = 1.0, 2.0, 2.0, 2.9999, 0.3


def rocker_extremes():
    """(t in [0, 1), Th4) of the rocker's two extremes on the guess's mode (B above the
    ground line at the extended position, below it at the folded one: the mode whose B
    lies left of the line from the crank pin to O4)."""
    out = []
    for r, sign in ((B + A, 1.0), (B - A, -1.0)):
        x = (r * r - C * C + D * D) / (2 * D)
        for y in (math.sqrt(r * r - x * x), -math.sqrt(r * r - x * x)):
            theta = math.atan2(sign * y, sign * x)            # the crank along ±B
            ax, ay = A * math.cos(theta), A * math.sin(theta)
            if (D - ax) * (y - ay) - (0.0 - ay) * (x - ax) > 0:    # B left of A -> O4
                t = ((theta - PHASE) / (2 * math.pi)) % 1.0
                out.append((t, math.atan2(y, x - D)))
    return sorted(out)


@pytest.fixture(scope="module")
def near_change_point():
    mech = mechgen.load(os.path.join(GENERATED, "fourbar.py"), tier="python").with_params(
        a=A, b=B, c=C, d=D, theta2=PHASE)
    ax, ay = A * math.cos(PHASE), A * math.sin(PHASE)
    q = mech.solve(0.0).q
    bx, by = D + C * math.cos(q[8]), C * math.sin(q[8])
    assert (D - ax) * (by - ay) + ay * (bx - ax) > 0      # the guess's mode: B left of A -> O4
    return mech


@pytest.mark.parametrize("n", [5, 7, 11])
def test_extrema_of_a_coarse_sweep_near_a_toggle_keep_its_mode(near_change_point, n):
    sw = near_change_point.sweep(0.0, 1.0, n, level="velocity")
    ev = sw.extrema("Th4").interior
    expected = rocker_extremes()
    assert len(ev) == 2
    for e, (t, th4) in zip(ev, expected):
        assert e.t == pytest.approx(t, abs=1e-9)
        assert math.remainder(e.value - th4, 2 * math.pi) == pytest.approx(0.0, abs=1e-9)
    roots = sw.roots("Th4d")
    assert [r.t for r in roots] == pytest.approx([t for t, _ in expected], abs=1e-9)


def test_table_extremes_near_a_toggle_are_exact(near_change_point):
    """tab.extremes refines off the grid on the design's own mode; before, Newton from a
    Taylor predictor gave up near the toggle and the grid value stood as the extreme
    (0.05 rad short at 5 points a turn, 0.003 at 25)."""
    tab = near_change_point.sweep(0.0, 1.0, 5, params={"d": [D]}, level="acceleration")
    ext = tab.extremes("Th4")
    (t_min, v_min), (t_max, v_max) = sorted(rocker_extremes(), key=lambda e: e[1])
    assert ext.tmax[0] == pytest.approx(t_max, abs=1e-9)
    assert ext.max[0] == pytest.approx(v_max, abs=1e-9)
    assert ext.tmin[0] == pytest.approx(t_min, abs=1e-9)
    assert ext.min[0] == pytest.approx(v_min, abs=1e-9)


def test_table_extremes_of_the_quick_return():
    """A design whose slider's maximum Newton did not reach (it stayed at the grid point,
    2.4e-5 short): the closed form's (tests/closed_forms.py) by mpmath."""
    import mpmath as mp
    from closed_forms import quick_return
    L = 3.5050251256281406
    qr = mechgen.load(os.path.join(GENERATED, "quick_return.py"), tier="python")
    tab = qr.sweep(0.0, 1.0, 60, params={"longitud": [L]}, level="acceleration")
    ext = tab.extremes("X4")
    with mp.workdps(30):
        t = mp.findroot(lambda u: mp.diff(lambda v: quick_return(v, L)[6], u), mp.mpf(0.885))
        t_ref, x_ref = float(t), float(quick_return(t, L)[6])
    assert ext.tmax[0] == pytest.approx(t_ref, abs=1e-11)
    assert ext.max[0] == pytest.approx(x_ref, abs=1e-12)


def test_a_design_through_a_singular_configuration_is_warned_about(near_change_point):
    """d = 3 puts the four-bar on its change point at θ = π (a + d = b + c): the design's
    sweep passes a singular configuration, where it may go on in the other mode (it does:
    its rocker ends 2 rad from the closed form of its starting mode). A single sweep warns;
    the table warns too, naming the design, besides its status."""
    import warnings
    from mechgen.errors import BranchJumpWarning
    with pytest.warns(BranchJumpWarning, match=r"1 of 2 designs .* d=3\b"):
        tab = near_change_point.sweep(0.0, 1.0, 9, params={"d": [2.9, 3.0]})
    assert tab.ok.all() and list(tab.status) == [0, 6]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        near_change_point.sweep(0.0, 1.0, 9, params={"d": [2.9, 2.99]})
        near_change_point.sweep(0.0, 1.0, 9, params={"d": [2.9, 3.0]}, on_fail="ignore")


def test_optimize_rejects_a_design_solved_through_a_singular_configuration(near_change_point):
    """mech.optimize's objective never sees a design whose table passed a singular
    configuration (d = 3: the change point, where the rocker went on in the other mode):
    it scores +inf and counts as rejected, like a design that cannot be solved."""
    import numpy as np
    from mechgen.runtime.tables.synthesis import _Scorer
    seen = []

    def objective(tab):
        seen.append(tab.design_params()[:, 0].copy())
        return np.asarray(tab.reduced("Th4").max, dtype=float).reshape(-1)

    scorer = _Scorer(near_change_point, objective, ["d"],
                     dict(t0=0.0, t1=1.0, n=9, level="position", reduce=["Th4"]))
    score = scorer(np.array([[2.9], [3.0]]))
    assert np.isfinite(score[0]) and score[1] == np.inf
    assert scorer.rejected == 1 and [list(d) for d in seen] == [[2.9]]
