"""A design table's varied parameters are checked design by design (issue 43): a spring's
negative stiffness or free length, a damper's negative coefficient or a negative mass in
one design of a force table is refused naming the design's index and values, as
``with_params`` refuses it for one mechanism (tests/test_force_parameter_limits.py).
And the force arrows of a drawing name the body and point they act at (colisa.P2)."""
import numpy as np
import pytest

import mechgen
from mechgen import Model, T


def sprung(name="force_design_limits"):
    """A crank turning 2π rad/s with mass mm, a spring ``spr`` (k = kk, free length L0)
    and a damper ``dmp`` (c = cc) from its tip to the ground point (0, 3)."""
    m = Model(name)
    g = m.ground("g", points=[(0, 0), (0, 3)])
    mm = m.param("mm", 1.0)
    crank = m.body("crank", points=[(0, 0), (1, 0)], guess=(0, 0, 0), mass=mm,
                   inertia=0.1, centroid=(0.5, 0))
    m.revolute(g[1], crank[1], name="pivot")
    m.rotation_lock(crank, 2 * np.pi * T, name="drive")
    kk, L0, cc = m.param("kk", 100.0), m.param("L0", 0.5), m.param("cc", 2.0)
    m.spring(crank[2], g[2], kk, L0, name="spr")
    m.damper(crank[2], g[2], cc, name="dmp")
    return m


@pytest.fixture(scope="module")
def mech(tmp_path_factory):
    return mechgen.compile(sprung(), outdir=str(tmp_path_factory.mktemp("gen")),
                           tier="python")


@pytest.mark.parametrize("params, said", [
    (dict(kk=[100.0, 50.0, -100.0]), r"design 2 \(kk=-100\): spring 'spr'.*negative"),
    (dict(cc=[1.0, -1.0], kk=[10.0, 20.0]),
     r"design 2 \(cc=-1, kk=10\): damper 'dmp'.*negative"),
    (dict(L0=[0.5, -0.5]), r"design 1 \(L0=-0.5\): spring 'spr'.*free length"),
    (dict(mm=[1.0, 2.0, -1.0]), r"design 2 \(mm=-1\): body 'crank' has a negative mass"),
])
def test_a_refused_design_is_named(mech, params, said):
    with pytest.raises(ValueError, match=rf"model 'force_design_limits': {said}"):
        mech.sweep(0.0, 1.0, 5, params=params, level="dynamic")


def test_allowed_designs_run_and_kinematic_tables_are_not_judged(mech):
    tab = mech.sweep(0.0, 1.0, 5, params=dict(kk=[100.0, 0.0, 50.0]), level="dynamic")
    assert np.all(tab.ok)
    # the kinematics does not read the springs: nothing to refuse there
    tab = mech.sweep(0.0, 1.0, 5, params=dict(kk=[100.0, -100.0]), level="position")
    assert np.all(tab.ok)


def test_force_arrows_name_the_body_and_point(mech):
    import matplotlib
    matplotlib.use("Agg")
    from mechgen import plot
    s = mech.solve(0.1, level="dynamic")
    d = plot.draw(mech, s, forces=True)
    by = {a.short: a for a in d.forces.arrows}
    pivot = by["pivot"]
    assert pivot.where == "crank.P1"
    assert pivot.label.get_text().startswith("crank.P1 (pivot) ")
    drive = by["drive"]             # a torque on the crank: no one point, its name
    assert drive.where is None and drive.label.get_text().startswith("drive ")
    d.figure.savefig("/tmp/force_arrow_names.png", dpi=70)
