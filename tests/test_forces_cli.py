"""Forces through the command line and the documents (issue 21): `mechgen forces`,
`mechgen sweep --level dynamic`, `mechgen equations`, the constraint reference's worked
example and the README's snippet, each against the closed form of tests/test_forces.py;
`mechgen solve --level static|dynamic` prints the driver efforts and reactions it solved,
against the power balance of a slider-crank written here."""
import math
from cli_runs import run, write

import numpy as np
import pytest

from test_forces import (C2, G, J2, M2, closed_form, newton_euler, power_torque,
                         slider_crank)


def test_equations_print_the_mass_matrix_and_loads():
    from mechgen.model.printing import equations_text
    text = equations_text(slider_crank())
    forces = text[text.index("Forces:"):]
    # the crank turns about its origin: M[Th2, Th2] = m |c|² + J
    assert f"[Th2, Th2]  {M2 * (C2[0] ** 2 + C2[1] ** 2) + J2:g}" in forces
    assert "[X4]   -500" in forces and "press: force(slider[1], (-500" in forces
    assert f"[Y4]   {-G:g}*mass4" in forces      # Q_c: the slider's weight, a parameter


MODEL_FILE = '''
from mechgen import Model, T
m = Model("cli_forces")
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


def test_cli_forces_prints_driver_and_reactions(tmp_path, capsys, monkeypatch):
    from mechgen.cli import main
    monkeypatch.setenv("MECHGEN_TIER", "python")
    path = tmp_path / "cli_forces.py"
    path.write_text(MODEL_FILE)
    assert main(["forces", str(path), "-t", "0.25", "--outdir", str(tmp_path / "gen")]) == 0
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if x.strip().startswith("crank driver:"))
    np.testing.assert_allclose(float(line.split()[-1]), power_torque(closed_form(0.25)),
                               rtol=1e-9)
    ne = newton_euler(closed_form(0.25))
    line = next(x for x in out.splitlines() if x.strip().startswith("C: revolute") and
                x.split(" on ")[1].split()[0] == "slider")
    np.testing.assert_allclose([float(v) for v in line.split()[-3:]], [*ne["FC"], 0.0],
                               rtol=1e-9, atol=1e-7)
    assert " on base " in out


def test_constraint_reference_forces_example_is_what_the_printer_gives():
    """docs/constraints.md's worked example of masses and loads cannot rot."""
    import os
    import re
    from mechgen.model.printing import equations_text
    doc = open(os.path.join(os.path.dirname(os.path.dirname(__file__)), "docs",
                            "constraints.md"), encoding="utf-8").read()
    code = re.search(r"<!-- forces example -->\n```python\n(.*?)```", doc, re.S).group(1)
    quoted = re.search(r"<!-- forces printed -->\n```text\n(.*?)```", doc, re.S).group(1)
    space = {}
    exec(code, space)
    text = equations_text(space["m"])
    assert text[text.index("Forces:"):] == quoted
    # the crank about its pin: M[Th2, Th2] = m |c|² + J
    assert f"[Th2, Th2]  {1.2 * (0.15 ** 2 + 0.02 ** 2) + 0.01:g}" in quoted


def test_the_guide_forces_snippet_prints_its_numbers(tmp_path, monkeypatch, capsys):
    import os
    from docs_pages import page, python_blocks
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    code = python_blocks(page("guide/forces.md"))[0]     # docs/guide/forces.md's first
    monkeypatch.chdir(root)
    monkeypatch.setenv("MECHGEN_CACHE", str(tmp_path))
    monkeypatch.setenv("MECHGEN_TIER", "python")
    exec(code, {})
    out = capsys.readouterr().out.split()
    peak, mean, residual, inertia = map(float, out)
    np.testing.assert_allclose([peak, mean, inertia], [41417.38, 859.44, 9009.50], atol=0.01)
    assert residual < 1e-9 * peak


def test_cli_sweep_dynamic_writes_force_columns(tmp_path, monkeypatch):
    import csv
    from mechgen.cli import main
    monkeypatch.setenv("MECHGEN_TIER", "python")
    path = tmp_path / "cli_forces.py"
    path.write_text(MODEL_FILE)
    out = tmp_path / "forces.csv"
    assert main(["sweep", str(path), "--level", "dynamic", "-n", "7", "--t1", "2",
                 "--outdir", str(tmp_path / "gen"), "-o", str(out)]) == 0
    rows = list(csv.DictReader(open(out)))
    assert len(rows) == 7
    for row in rows:
        t = float(row["T"])
        np.testing.assert_allclose(float(row["crank driver"]), power_torque(closed_form(t)),
                                   rtol=1e-9)
        ne = newton_euler(closed_form(t))
        got = [float(row[f"C on slider {k}"]) for k in ("fx", "fy", "m")]
        np.testing.assert_allclose(got, [*ne["FC"], 0.0], rtol=1e-9, atol=1e-7)


def test_cli_sweep_takes_force_columns_and_reduces_a_driver(tmp_path, capsys, monkeypatch):
    """`--columns` at a force level takes a driver's effort and a reaction by their table
    names (against the closed form and Newton–Euler); `--reduce` takes a driver's name in
    a design table (the peak torque of each design, as the Python table's); without a
    force level they are refused with the level to ask for."""
    import csv
    import os
    from mechgen.cli import main
    monkeypatch.setenv("MECHGEN_TIER", "python")
    path = tmp_path / "cli_forces.py"
    path.write_text(MODEL_FILE)
    gen = str(tmp_path / "gen")
    out = str(tmp_path / "forces.csv")
    assert main(["sweep", str(path), "--t0", "0", "--t1", "0.5", "-n", "6", "--level",
                 "dynamic", "--columns", "crank driver,C on slider fx", "--outdir", gen,
                 "-o", out]) == 0
    with open(out) as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["T", "crank driver", "C on slider fx"] and len(rows) == 7
    for row in rows[1:]:
        t, torque, fx = (float(v) for v in row)
        k = closed_form(t)
        np.testing.assert_allclose(torque, power_torque(k), rtol=1e-9)
        np.testing.assert_allclose(fx, newton_euler(k)["FC"][0], rtol=1e-9, atol=1e-7)
    capsys.readouterr()
    assert main(["sweep", str(path), "-n", "3", "--columns", "crank driver",
                 "--outdir", gen]) != 0
    assert "'crank driver' is a force column" in capsys.readouterr().err
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    example = os.path.join(root, "examples", "quick_return_forces.py")
    table = str(tmp_path / "table.csv")
    assert main(["sweep", example, "--t0", "0", "--t1", "1", "-n", "41", "--level", "static",
                 "--param", "longitud=2,3", "--reduce", "crank driver", "--outdir", gen,
                 "-o", table]) == 0
    with open(table) as fh:
        rows = list(csv.reader(fh))
    col = rows[0].index("crank driver_max")
    import mechgen
    tab = mechgen.load(os.path.join(gen, "quick_return_forces.py"), tier="python").sweep(
        0.0, 1.0, 41, params={"longitud": [2.0, 3.0]}, level="static",
        reduce=["crank driver"])
    np.testing.assert_allclose([float(r[col]) for r in rows[1:]],
                               tab.reduced("crank driver").max, rtol=1e-12)


FOURBAR = """
from mechgen import Model, T, pi, distance
m = Model("{name}")
base = m.ground("base", points=[(0, 0), (4, 0)])
crank = m.body("crank", points=[(0, 0), (1, 0)], guess=(0, 0, 1.0))
coupler = m.body("coupler", points=[(0, 0), (4, 0)], guess=(0.5, 0.8, 0.3))
rocker = m.body("rocker", points=[(0, 0), (3, 0)], guess=(4, 0, 1.6))
m.revolute(base[1], crank[0])
m.revolute(crank[2], coupler[0])
m.revolute(coupler[2], rocker[2])
m.revolute(base[2], rocker[0])
m.rotation_lock(crank, 2 * pi * T + 1.0, name="drive")
{extra}
"""


SLIDER_CRANK = """
from mechgen import Model, T
m = Model("sc3")
w = m.param("w", 2.0)
base = m.ground("base", points=[(0, 0), (1, 0)])
crank = m.body("crank", points=[(0, 0), (1, 0)], guess=(0, 0, 0.5))
rod = m.body("rod", points=[(0, 0), (3, 0)], guess=(0.9, 0.5, -0.2))
slider = m.body("slider", points=[(0, 0), (1, 0)], guess=(3.8, 0, 0), mass=2.0,
                inertia=0.3)
m.revolute(base[1], crank[0], name="A")
m.revolute(crank[2], rod[0], name="B")
m.revolute(rod[2], slider[0], name="C")
m.translate(base.line(1, 2), slider.line(1, 2), name="guide")
m.rotation_lock(crank, w * T + 0.5, name="motor")
m.force(slider[0], (-100, 0), name="load")
"""


@pytest.fixture
def _plain(monkeypatch):
    monkeypatch.setenv("MECHGEN_TIER", "python")


# -- solve at the force levels --------------------------------------------------------------
def slider_crank_closed_form(t, static):
    """Torque and pin C force on the slider of the slider-crank above: crank 1, rod 3 (both
    massless), slider 2 kg, load -100 along x; power balance τ θ̇ = (m ẍ - F) ẋ."""
    th, w = 2 * t + 0.5, 2.0
    s, c = math.sin(th), math.cos(th)
    root = math.sqrt(9 - s * s)
    x = c + root
    xd = w * (-s - s * c / root)
    xdd = w * w * (-c - (c * c - s * s) / root - (s * c) ** 2 / root ** 3)
    a = 0.0 if static else xdd
    fx = 2.0 * a + 100.0
    fy = fx * (-s) / (x - c)            # along the rod, from its crank end to the slider
    return (fx * xd) / w, fx, fy


@pytest.mark.usefixtures("_plain")
@pytest.mark.parametrize("level", ["dynamic", "static"])
def test_solve_at_a_force_level_prints_efforts_and_reactions(capsys, tmp_path, level):
    path = write(tmp_path, SLIDER_CRANK)
    code, out, err = run(capsys, "solve", path, "-t", "0.3", "--level", level,
                         "--outdir", str(tmp_path / "gen"))
    assert code == 0, err
    # before: the header said "(acceleration; ...)" and no effort or reaction was printed
    assert out.splitlines()[0].startswith(f"sc3 at T = 0.3 ({level};")
    values = {k.strip(): float(v) for k, v in
              (ln.split("->") for ln in out.splitlines()[1:] if "->" in ln)}
    tau, fx, fy = slider_crank_closed_form(0.3, level == "static")
    assert values["motor"] == pytest.approx(tau, rel=1e-9)
    assert values["C on slider fx"] == pytest.approx(fx, rel=1e-9)
    assert values["C on slider fy"] == pytest.approx(fy, rel=1e-9)
    assert values["guide on slider fy"] == pytest.approx(-fy, rel=1e-9)


@pytest.mark.usefixtures("_plain")
def test_solve_force_columns_and_csv_match_the_sweep(capsys, tmp_path):
    path = write(tmp_path, SLIDER_CRANK)
    gen = str(tmp_path / "gen")
    code, out, err = run(capsys, "solve", path, "-t", "0.3", "--level", "dynamic",
                         "--columns", "motor,C on slider fx", "--outdir", gen)
    # before: "mechgen: error: 'motor'"
    assert code == 0, err
    tau, fx, _ = slider_crank_closed_form(0.3, False)
    assert f"-> {tau:.10g}" in out and f"-> {fx:.10g}" in out
    one, many = tmp_path / "one.csv", tmp_path / "many.csv"
    assert run(capsys, "solve", path, "-t", "0.3", "--level", "dynamic", "-o", str(one),
               "--outdir", gen)[0] == 0
    assert run(capsys, "sweep", path, "--t0", "0.3", "--t1", "0.5", "-n", "2", "--level",
               "dynamic", "-o", str(many), "--outdir", gen)[0] == 0
    a, b = one.read_text().splitlines(), many.read_text().splitlines()
    assert a[0] == b[0]
    np.testing.assert_allclose(np.array(a[1].split(","), dtype=float),
                               np.array(b[1].split(","), dtype=float), rtol=1e-12, atol=1e-12)


@pytest.mark.usefixtures("_plain")
def test_solve_at_a_force_level_says_which_reactions_are_indeterminate(capsys, tmp_path):
    extra = 'm.rotation_lock(crank, 2 * pi * T + 1.0, name="drive2")\nm.moment(crank, 3.0)'
    path = write(tmp_path, FOURBAR.format(name="redf", extra=extra))
    code, out, err = run(capsys, "solve", path, "-t", "0.2", "--level", "static",
                         "--columns", "drive,drive2", "--outdir", str(tmp_path / "gen"))
    assert code == 0, err
    values = {k.strip(): float(v) for k, v in
              (ln.split("->") for ln in out.splitlines()[1:] if "->" in ln)}
    # the two drivers share the -3.0 that holds the crank against its moment
    assert values["drive"] + values["drive2"] == pytest.approx(-3.0, rel=1e-9)
    assert "indeterminate" in out and "drive2" in out.splitlines()[-1]
