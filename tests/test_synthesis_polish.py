"""A four-bar synthesized from rounded positions, polished by mech.fit against the exact
path (issue: synthesis hands over a model that ``fit`` can polish): the hidden four-bar's
five coupler poses, rounded to 4 decimals as read off a drawing, give Burmester dyads a
little off; its Model (the dimensions as parameters) is then fitted through twenty points of
the hidden coupler curve all round, in closed form here (more equations than the dimensions and
phases: the linkage is determined), passes them to 1e-9 and has the hidden pivots."""
import cmath
import math

import numpy as np
import pytest

import mechgen
from mechgen import synthesis

HIDDEN = dict(O2=0j, O4=2.2 + 0.3j, a=0.7, b=2.4, c=2.0, uA=0.3 - 0.2j,
              uB=0.3 - 0.2j + 2.4 * cmath.exp(0.4j))


def pins(phi):
    """The hidden four-bar's crank pin A and coupler pin B at crank angle phi (one mode)."""
    h = HIDDEN
    A = h["O2"] + h["a"] * cmath.exp(1j * phi)
    L = abs(h["O4"] - A)
    k = (h["b"] ** 2 + L * L - h["c"] ** 2) / (2 * h["b"] * L)
    return A, A + h["b"] * cmath.exp(1j * (cmath.phase(h["O4"] - A) + math.acos(k)))


def frame(phi):
    """The coupler frame (x, y, angle) at crank angle phi."""
    A, B = pins(phi)
    th = cmath.phase(B - A) - cmath.phase(HIDDEN["uB"] - HIDDEN["uA"])
    o = A - cmath.exp(1j * th) * HIDDEN["uA"]
    return o.real, o.imag, th


@pytest.mark.slow
def test_fit_polishes_a_synthesized_four_bar(tmp_path):
    phis = np.linspace(0.3, 2.3, 5)
    poses = [tuple(round(v, 4) for v in frame(p)) for p in phis]
    links = [f for f in synthesis.fourbars(poses) if not f.defects]
    assert links, "no defect-free four-bar from the rounded poses"
    # the one nearest the hidden four-bar (its fixed pivots)
    best = min(links, key=lambda f: abs(complex(*f.input.fixed) - HIDDEN["O2"])
               + abs(complex(*f.output.fixed) - HIDDEN["O4"]))
    mech = mechgen.compile(best.model("polished"), outdir=str(tmp_path))
    target = np.array([frame(p)[:2] for p in np.linspace(0.0, 2 * math.pi, 20, endpoint=False)])
    k = mech.point_names.index("coupler[0]")
    start = np.array([mech.solve(t).points()[k] for t in best.times])
    assert np.max(np.abs(start - np.array(poses)[:, :2])) < 1e-9    # it meets its poses
    names = ("x_O2", "y_O2", "x_O4", "y_O4", "a", "c", "x_A", "y_A", "x_B", "y_B")
    params = {n: (mech.parameters[n] - 0.05, mech.parameters[n] + 0.05) for n in names}
    fit = mech.fit(point="coupler[0]", target=target, params=params, seed=2)
    assert fit.error < 1e-9, fit
    # the fitted mechanism, solved at the fitted times, passes each target (one mode)
    got = np.array([fit.mechanism.solve(float(t)).points()[k] for t in fit.times])
    assert np.max(np.hypot(*(got - target).T)) < 1e-8
    # and the pivots moved onto the hidden four-bar's
    assert abs(complex(fit.params["x_O4"], fit.params["y_O4"]) - HIDDEN["O4"]) < 1e-6
