"""The command line of docs/reference/sensitivities.md: ``mechgen sweep --sensitivities`` (columns
dX4/dp equal to sw.sensitivity) and ``mechgen tolerance`` (the bands' picture, the stack-up table
equal to band.contributions, one-line refusals that write nothing)."""
from __future__ import annotations

import csv
import os
import textwrap
from cli_runs import run

import numpy as np
import pytest

import mechgen

MODEL = textwrap.dedent('''
    """A four-bar with named joints and a coupler point."""
    import math
    from mechgen import Model, T, location

    m = Model("tol_cli_fourbar")
    a = m.param("a", 0.8)
    b = m.param("b", 2.5)
    c = m.param("c", 2.0)
    d = m.param("d", 3.0)
    ground = m.ground("ground", points=[(0, 0), (d, 0)])
    crank = m.body("crank", points=[(0, 0), (a, 0)], guess=(0, 0, 1.0))
    coupler = m.body("coupler", points=[(0, 0), (b, 0), (0.5, 0.8)], guess=(0.4, 0.7, 0.5))
    rocker = m.body("rocker", points=[(0, 0), (c, 0)], guess=(3, 0, 1.8))
    m.revolute(ground[1], crank[1], name="O2")
    m.revolute(crank[2], coupler[1], name="A")
    m.revolute(ground[2], rocker[1], name="O4")
    m.revolute(coupler[2], rocker[2], name="B")
    m.rotation_lock(crank, math.pi / 3 + 2 * math.pi * T, name="crank angle")
    m.output("px", location(coupler[3])[0])
''')


@pytest.fixture(autouse=True)
def _plain_python_tier(monkeypatch):
    """The commands' output is the point here, not numba: the plain tier, same numbers."""
    monkeypatch.setenv("MECHGEN_TIER", "python")


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    root = tmp_path_factory.mktemp("tol_cli")
    path = root / "fourbar_tol.py"
    path.write_text(MODEL)
    return str(path), str(root / "generated"), root


@pytest.fixture(scope="module")
def mech(files):
    path, outdir, _ = files
    return mechgen.compile(path, outdir=outdir, tier="python")


def read_csv(path):
    with open(path) as fh:
        rows = list(csv.reader(fh))
    return rows[0], np.array([[float(x) for x in r] for r in rows[1:]])


# -- mechgen sweep --sensitivities -------------------------------------------------------------
def test_sweep_adds_a_derivative_column_per_quantity_and_parameter(capsys, files, mech):
    path, outdir, root = files
    out = root / "sens.csv"
    code, said, err = run(capsys, "sweep", path, "--outdir", outdir, "-n", 9, "--level",
                          "velocity", "--columns", "Th4,Th4d,px", "--sensitivities", "a,d",
                          "-o", out)
    assert code == 0, err
    header, data = read_csv(out)
    assert header == ["T", "Th4", "Th4d", "px", "dTh4/da", "dTh4/dd", "dTh4d/da", "dTh4d/dd",
                      "dpx/da", "dpx/dd"]
    sw = mech.sweep(0, 1, 9, level="velocity", sensitivities=["a", "d"])
    for k, name in enumerate(header[1:], start=1):
        if "/" in name:
            q, p = name[1:].split("/d")
            want = sw.sensitivity(q, p)
        else:
            want = sw[name]
        np.testing.assert_allclose(data[:, k], want, rtol=1e-12, atol=1e-12, err_msg=name)


def test_sweep_sensitivities_all_and_on_the_terminal(capsys, files, mech):
    path, outdir, _ = files
    code, said, err = run(capsys, "sweep", path, "--outdir", outdir, "-n", 3, "--columns",
                          "X3", "--sensitivities", "all")
    assert code == 0, err
    head = said.splitlines()[0].split()
    assert head == ["T", "X3"] + [f"dX3/d{p}" for p in ("a", "b", "c", "d")]


def test_sweep_sensitivities_refuses_an_unknown_parameter(capsys, files):
    path, outdir, root = files
    out = root / "never.csv"
    code, said, err = run(capsys, "sweep", path, "--outdir", outdir, "-n", 3,
                          "--sensitivities", "a,zz", "-o", out)
    assert code == 1 and not os.path.exists(out)
    assert err.count("\n") == 1 and "zz" in err and "a, b, c, d" in err


# -- mechgen tolerance -----------------------------------------------------------------------
def test_tolerance_draws_the_bands_and_prints_the_stackup(capsys, files, mech):
    path, outdir, root = files
    png = root / "band.png"
    code, said, err = run(capsys, "tolerance", path, "--outdir", outdir, "--tol", "a=0.01",
                          "--tol", "b=-0.02:0.01", "--clearance", "O2=0.03", "-n", 11,
                          "--samples", 200, "--seed", 4, "-o", png, "Th4", "px")
    assert code == 0, err
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000
    assert f"wrote {png}" in said and "worst, rss, montecarlo" in said
    sw = mech.sweep(0, 1, 11)
    band = mech.tolerance(sw, {"a": 0.01, "b": (-0.02, 0.01)}, clearance={"O2": 0.03})
    table = said.split("\n\n")[0]
    k = band.worst_index("Th4")
    assert f"at T = {sw.t[k]:.6g}" in table.splitlines()[0]
    shares = band.contributions("Th4")
    for term, row in zip(("a", "b", "O2"), table.splitlines()[2:5]):
        cells = row.split()
        assert cells[0] == term
        assert float(cells[-3]) == pytest.approx(shares[term][k], rel=1e-5), row
    total = sum(v[k] for v in shares.values())
    worst = [r for r in table.splitlines() if r.strip().startswith("worst case")][0]
    low, high = float(worst.split()[2]), float(worst.split()[4])
    assert high - low == pytest.approx(2 * total, rel=1e-8)
    assert "Monte Carlo" in table and "200 of 200 samples" in table


def test_tolerance_one_method(capsys, files):
    path, outdir, root = files
    png = root / "rss.png"
    code, said, err = run(capsys, "tolerance", path, "--outdir", outdir, "--tol", "c=0.02",
                          "--method", "rss", "-n", 5, "-o", png)
    assert code == 0, err
    assert png.exists() and "RSS" in said and "Monte Carlo" not in said
    assert "px" in said.splitlines()[0]          # the declared output by default


@pytest.mark.parametrize("argv, words", [
    (["--tol", "a"], "--tol takes NAME=T"),
    (["--tol", "a=0.1:0.2"], "low = 0.1 > 0"),
    (["--tol", "zz=0.1"], "no such parameter"),
    (["--clearance", "crank angle=0.1"], "not a revolute"),
    (["--tol", "a=0.1", "--method", "worst", "--samples", "10"], "--samples and --seed"),
    ([], "at least one --tol"),
    (["--tol", "a=0.1", "nonsense"], "nonsense"),
])
def test_tolerance_refuses_in_one_line_and_writes_nothing(capsys, files, argv, words):
    path, outdir, root = files
    png = root / "refused.png"
    code, said, err = run(capsys, "tolerance", path, "--outdir", outdir, "-n", 5, "-o", png,
                          *argv)
    assert code == 1, (said, err)
    assert err.count("\n") == 1 and words in err, err
    assert not png.exists()
    assert not [f for f in os.listdir(root) if f.startswith(".refused")]


def test_tolerance_help_says_what_it_draws(capsys):
    code, said, _ = run(capsys, "tolerance", "--help")
    assert code == 0
    text = " ".join(said.split())
    for words in ("worst case", "RSS", "Monte Carlo", "Without --method all three",
                  "--clearance JOINT=C", "PARAM=LOW:HIGH", "stack-up"):
        assert words in text, words
