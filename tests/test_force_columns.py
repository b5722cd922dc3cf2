"""Force columns and the forces command (docs/reference/forces.md:
`mechgen sweep --level dynamic|static` writes driver efforts and reactions as CSV
columns; `mechgen forces` prints every driver effort and joint reaction)."""
import csv

import numpy as np

import mechgen
from mechgen import Model, T, sin

MASS = 2.0


def _slide():
    """A block on a horizontal guide pushed by relative_x(block[1], 0.5 sin T): the push is
    m·ẍ = −m·0.5 sin T, zero at T = 0 only."""
    m = Model("audit_slide")
    base = m.ground("base", points=[(0, 0), (1, 0)])
    block = m.body("block", points=[(0, 0), (1, 0)], guess=(0, 0, 0), mass=MASS,
                   inertia=0.1)
    m.translate(base.line(1, 2), block.line(1, 2), name="guide")
    m.relative_x(block[1], 0.5 * sin(T), name="push")
    m.gravity(9.81)
    return m


def test_a_reaction_on_the_ground_zero_at_the_first_point_keeps_its_columns(tmp_path):
    # the columns were chosen from the first point's reactions: a sweep from T = 0 had no
    # "push on base" columns (the frame's load from the push silently left out of the
    # CSV), one from T = 0.5 had them, and `--columns "push on base fx"` failed with
    # "'push on base fx' is not in list"
    mech = mechgen.compile(_slide(), outdir=str(tmp_path), tier="python")
    sw = mech.sweep(0.0, 1.0, 5, level="dynamic")
    path = sw.to_csv(str(tmp_path / "slide.csv"))
    with open(path) as fh:
        rows = list(csv.DictReader(fh))
    assert "push on base fx" in rows[0]
    for row in rows:
        t = float(row["T"])
        push = -MASS * 0.5 * np.sin(t)                 # the force on the block along x
        assert abs(float(row["push"]) - push) < 1e-12
        assert abs(float(row["push on block fx"]) - push) < 1e-12
        assert abs(float(row["push on base fx"]) + push) < 1e-12
    later = mech.sweep(0.5, 1.0, 3, level="dynamic")
    assert sw.table()[0] == later.table()[0]            # the same columns either way


def test_the_cli_takes_a_ground_column_that_is_zero_at_the_first_point(tmp_path, monkeypatch,
                                                                        capsys):
    from mechgen.cli import main
    monkeypatch.setenv("MECHGEN_TIER", "python")
    path = tmp_path / "slide.py"
    path.write_text("from mechgen import Model, T, sin\n"
                    "m = Model('audit_slide_cli')\n"
                    "base = m.ground('base', points=[(0, 0), (1, 0)])\n"
                    "block = m.body('block', points=[(0, 0), (1, 0)], guess=(0, 0, 0), "
                    "mass=2.0, inertia=0.1)\n"
                    "m.translate(base.line(1, 2), block.line(1, 2), name='guide')\n"
                    "m.relative_x(block[1], 0.5 * sin(T), name='push')\n")
    out = tmp_path / "push.csv"
    assert main(["sweep", str(path), "--t0", "0", "--t1", "1", "-n", "3", "--level", "dynamic",
                 "--columns", "push on base fx", "--outdir", str(tmp_path / "gen"),
                 "-o", str(out)]) == 0
    with open(out) as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["T", "push on base fx"]
    np.testing.assert_allclose([float(r[1]) for r in rows[1:]],
                               [MASS * 0.5 * np.sin(t) for t in (0.0, 0.5, 1.0)], atol=1e-12)


def test_the_forces_command_prints_the_reactions_of_a_driver_without_an_effort(
        tmp_path, monkeypatch, capsys):
    # a driver row that does not separate into g(q) − f(T) has no effort (the sweep's
    # table leaves its column out); `mechgen forces` printed the header "drivers" and
    # stopped with an error, leaving out every reaction (well defined)
    from mechgen.cli import main
    monkeypatch.setenv("MECHGEN_TIER", "python")
    path = tmp_path / "arm.py"
    path.write_text("from mechgen import Model, T\n"
                    "m = Model('audit_arm_cli')\n"
                    "base = m.ground('base', points=[(0, 0)])\n"
                    "arm = m.body('arm', points=[(0, 0), (1, 0)], guess=(0, 0, 0.3), "
                    "mass=2.0, inertia=0.1, centroid=(0.5, 0))\n"
                    "m.revolute(base[1], arm[1], name='pin')\n"
                    "m.constraint(arm.th * (1 + T) - 0.3 - T, name='drive')\n"
                    "m.gravity(10)\n")
    capsys.readouterr()
    assert main(["forces", str(path), "-t", "0.7", "--static",
                 "--outdir", str(tmp_path / "gen")]) == 0
    out = capsys.readouterr().out
    assert "not defined" in out
    th = (0.3 + 0.7) / 1.7
    line = next(x for x in out.splitlines() if "pin" in x and "on arm" in x)
    np.testing.assert_allclose([float(v) for v in line.split()[-3:]], [0.0, 20.0, 0.0],
                               atol=1e-9)
    line = next(x for x in out.splitlines() if "drive" in x and "on arm" in x)
    np.testing.assert_allclose(float(line.split()[-1]), 2.0 * 10 * 0.5 * np.cos(th), rtol=1e-9)


def test_a_name_that_several_constraints_answer_to_is_refused_not_the_first_taken(tmp_path):
    # two constraints named "P", or a constraint named "1" that is not constraint 1: the
    # force results took the first constraint the text matched, silently (reaction("P")
    # the pin's, driver("1") "not a driver" although the user named the driver "1")
    import pytest
    m = Model("audit_names")
    base = m.ground("base", points=[(0, 0)])
    arm = m.body("arm", points=[(0, 0), (1, 0)], guess=(0, 0, 0.3), mass=2.0, inertia=0.1,
                 centroid=(0.5, 0))
    m.revolute(base[1], arm[1], name="P")
    m.rotation_lock(arm, 0.3 + T, name="P")
    m.gravity(10)
    mech = mechgen.compile(m, outdir=str(tmp_path), tier="python")
    s = mech.solve(0.2, level="static")
    with pytest.raises(ValueError, match="names 2 constraints"):
        s.reaction("P", on="arm")
    with pytest.raises(ValueError, match="names 2 constraints"):
        s.driver("P")
    np.testing.assert_allclose(s.reaction(1, on="arm"), [0.0, 20.0, 0.0], atol=1e-12)
    torque = 2.0 * 10 * 0.5 * np.cos(0.5)
    np.testing.assert_allclose(s.driver(2), torque, rtol=1e-12)
    np.testing.assert_allclose(s.reaction("P: rotation_lock(arm, T + 0.3)", on="arm"),
                               [0.0, 0.0, torque], rtol=1e-12)
    with pytest.raises(ValueError, match="names 2 constraints"):
        mech.sweep(0, 1, 3, level="static").driver("P")

    m = Model("audit_numbers")
    base = m.ground("base", points=[(0, 0)])
    arm = m.body("arm", points=[(0, 0), (1, 0)], guess=(0, 0, 0.3), mass=2.0, inertia=0.1,
                 centroid=(0.5, 0))
    m.revolute(base[1], arm[1], name="2")
    m.rotation_lock(arm, 0.3 + T, name="1")
    m.gravity(10)
    mech = mechgen.compile(m, outdir=str(tmp_path), tier="python")
    s = mech.solve(0.2, level="static")
    with pytest.raises(ValueError, match="names 2 constraints"):
        s.driver("1")
    np.testing.assert_allclose(s.driver(2), torque, rtol=1e-12)


def _arm_file(tmp_path):
    path = tmp_path / "arm_table.py"
    path.write_text("from mechgen import Model, T, sin\n"
                    "m = Model('audit_arm_table')\n"
                    "M = m.param('M', 2.0)\n"
                    "base = m.ground('base', points=[(0, 0)])\n"
                    "arm = m.body('arm', points=[(0, 0), (1, 0)], guess=(0, 0, 0.3), mass=M, "
                    "inertia=0.1, centroid=(0.5, 0))\n"
                    "m.revolute(base[1], arm[1], name='pin')\n"
                    "m.rotation_lock(arm, 0.3 + T + 0.2 * sin(2 * T), name='drive')\n"
                    "m.gravity(10)\n")
    return path


def _arm_torque(t, mass):
    th, a = 0.3 + t + 0.2 * np.sin(2 * t), -0.8 * np.sin(2 * t)
    return (0.1 + mass * 0.25) * a + mass * 10 * 0.5 * np.cos(th)


def test_a_design_table_at_a_force_level_writes_its_drivers_efforts(tmp_path, monkeypatch,
                                                                    capsys):
    # `mechgen sweep --param M=1,3 --level dynamic` wrote the kinematic columns only, and
    # `--columns drive` failed with "'drive' is not in list" (tab["drive"] and
    # tab.driver("drive") had the efforts); a column a design table has not (a reaction)
    # is now a clear error
    from mechgen.cli import main
    monkeypatch.setenv("MECHGEN_TIER", "python")
    path = _arm_file(tmp_path)
    gen = str(tmp_path / "gen")
    out = tmp_path / "table.csv"
    for level in ("dynamic", "static"):
        assert main(["sweep", str(path), "--t0", "0", "--t1", "1", "-n", "3", "--level", level,
                     "--param", "M=1,3", "--outdir", gen, "-o", str(out)]) == 0
        with open(out) as fh:
            rows = list(csv.DictReader(fh))
        assert len(rows) == 6 and "drive" in rows[0]
        for row in rows:
            t, mass = float(row["T"]), float(row["M"])
            want = _arm_torque(t, mass) if level == "dynamic" else \
                mass * 10 * 0.5 * np.cos(0.3 + t + 0.2 * np.sin(2 * t))
            np.testing.assert_allclose(float(row["drive"]), want, rtol=1e-12)
    assert main(["sweep", str(path), "--t0", "0", "--t1", "1", "-n", "3", "--level", "dynamic",
                 "--param", "M=1,3", "--columns", "drive", "--outdir", gen, "-o",
                 str(out)]) == 0
    with open(out) as fh:
        assert next(csv.reader(fh)) == ["M", "T", "drive"]
    capsys.readouterr()
    assert main(["sweep", str(path), "-n", "3", "--level", "dynamic", "--param", "M=1,3",
                 "--columns", "pin on arm fx", "--outdir", gen]) != 0
    assert "'pin on arm fx' not in this table" in capsys.readouterr().err
    mech = mechgen.compile(str(path), outdir=gen, tier="python")
    tab = mech.sweep(0, 1, 3, level="dynamic", params={"M": [1.0, 3.0]})
    header, data = tab.table()
    np.testing.assert_allclose(data[:, header.index("drive")], tab.driver("drive").reshape(-1))
    assert "drive" not in mech.sweep(0, 1, 3, level="acceleration",
                                     params={"M": [1.0, 3.0]}).table()[0]


def test_the_flywheel_of_a_driver_that_goes_back_and_forth_is_refused(tmp_path):
    # a driver whose mean rate over the sweep is zero (an oscillating arm): the flywheel's
    # inertia ΔE / (cs ω̄²) came back as 1.8e36, no error
    import pytest
    m = Model("audit_swing")
    base = m.ground("base", points=[(0, 0)])
    arm = m.body("arm", points=[(0, 0), (1, 0)], guess=(0, 0, 0.3), mass=2.0, inertia=0.1,
                 centroid=(0.5, 0))
    m.revolute(base[1], arm[1], name="pin")
    m.rotation_lock(arm, 0.3 + 0.5 * sin(T), name="drive")
    m.gravity(10)
    mech = mechgen.compile(m, outdir=str(tmp_path), tier="python")
    sw = mech.sweep(0, 2 * np.pi, 101, level="dynamic")
    with pytest.raises(ValueError, match="mean rate"):
        sw.flywheel(0.05)
