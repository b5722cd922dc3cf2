"""Design tables (docs/reference/runtime.md) and docs/reference/forces.md ("design tables
and reduce= accept driver names"): an offset slider-crank whose slider is the rod's end on a guide
(crank r, rod l, guide at height e, a 2 kg mass at the rod's end, a press force of -100
along the guide), built here in the plain-Python tier.

- backend="cuda" must mark a table's points as the CPU does: a design swept through a
  toggle (r + e = l: the rod square to the guide at t = 0.75) has those points marked
  THROUGH_SINGULAR in tab.sweep(d).status on every backend (the CUDA kernel wrote them,
  the table dropped them). Run on numba's CUDA simulator in a subprocess.
- a driver named by its number in reduce= (docs/reference/forces.md: "a constraint is named
by its name=
  or its number") gives a table that prints, and whose reduction answers to the
  driver's name too.
- tab.extremes of a driver's effort on a force table says what to use instead (it said
  "needs a table at level 'static' or 'dynamic'" of a table at level "dynamic").
- mech.assemblies(0) finds both ends of the rod on the guide (it merged them as a
  'flip': the rod's end on the guide moves, a point a constraint places).
- mech.optimize passes on its table's and its objective's errors (scipy's
  differential_evolution replaced every ValueError and TypeError by its own RuntimeError),
  and finds the closed-form design of a stroke and a time ratio.
"""
import json
import re
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import mechgen
from conftest import ROOT, cuda_sim_env

MODEL = textwrap.dedent('''
    from mechgen import Model, T, pi, location
    m = Model("audit_sc2")
    r = m.param("r", 1.0)
    l = m.param("l", 3.0)
    e = m.param("e", 0.0)
    g = m.ground("g", points=[(0, 0), (0, e), (1, e)])
    crank = m.body("crank", points=[(0, 0), (r, 0)], guess=(0, 0, 0))
    rod = m.body("rod", points=[(0, 0), (l, 0)], guess=(1, 0, 0), mass=2.0, centroid=(l, 0))
    m.revolute(g[1], crank[1])
    m.rotation_lock(crank, 2 * pi * T, name="drive")
    m.revolute(crank[2], rod[1])
    m.point_on_line(rod[2], g.line(2, 3))
    m.force(rod[2], (-100.0, 0), name="press")
    m.output("xs", location(rod[2])[0])
''')


def _model_file(tmp_path):
    path = tmp_path / "audit_sc2.py"
    path.write_text(MODEL)
    return str(path)


@pytest.fixture(scope="module")
def sc2(tmp_path_factory):
    d = tmp_path_factory.mktemp("audit_tables")
    return mechgen.compile(mechgen.load_model(_model_file(d)), outdir=str(d), tier="python")


def _x(t, r, l, e):
    th = 2 * np.pi * t
    return r * np.cos(th) + np.sqrt(l * l - (e - r * np.sin(th)) ** 2)


def test_closed_form_and_torque(sc2):
    """The table's slider and driver torque against the closed form (τ ω = (m ẍ − F) ẋ)."""
    rs, es = [0.5, 1.5, 2.01], [0.0, 1.0]
    tab = sc2.sweep(0, 1, 49, params={"r": rs, "e": es}, level="dynamic", on_fail="ignore")
    x, tq = tab["xs"], tab["drive"]
    h = 1e-5
    for i, r in enumerate(rs):
        for j, e in enumerate(es):
            k = int(tab.done.reshape(tab.shape)[i, j])
            t = tab.t[:k]
            assert np.allclose(x[i, j, :k], _x(t, r, 3.0, e), atol=1e-12)
            xd = (_x(t + h, r, 3.0, e) - _x(t - h, r, 3.0, e)) / (2 * h)
            xdd = (_x(t + h, r, 3.0, e) - 2 * _x(t, r, 3.0, e) + _x(t - h, r, 3.0, e)) / h**2
            tau = (2.0 * xdd + 100.0) * xd / (2 * np.pi)
            assert np.allclose(tq[i, j, :k], tau, rtol=1e-4, atol=1e-4 * np.abs(tau).max())
    # r + e > l cannot turn: fails where the rod cannot reach the guide (t = 0.75 ± ...)
    assert list(tab.ok[2]) == [True, False] and tab.ok[:2].all()


def test_driver_by_number_in_reduce(sc2):
    kw = dict(params={"r": [1.0, 2.5], "e": 1.0}, level="dynamic", on_fail="ignore")
    by_name = sc2.sweep(0, 1, 25, reduce=["drive", "xs"], **kw)
    number = next(c[0] for c in sc2.module.CONSTRAINTS if c[4])
    by_number = sc2.sweep(0, 1, 25, reduce=[number, "xs"], **kw)
    assert "reduced" in repr(by_number)                    # TypeError before
    assert np.array_equal(by_number.reduced(number).max, by_name.reduced("drive").max)
    assert np.array_equal(by_number.reduced("drive").max, by_name.reduced("drive").max)
    assert np.array_equal(by_name.reduced(number).tmin, by_name.reduced("drive").tmin)
    with pytest.raises(mechgen.MechgenError, match="reductions"):
        by_number["xs"]
    with pytest.raises(KeyError, match="was not reduced"):
        by_number.reduced("Th3")


def test_extremes_of_a_driver_says_what_to_use(sc2):
    tab = sc2.sweep(0, 1, 25, params={"r": [1.0, 1.5]}, level="dynamic")
    with pytest.raises(mechgen.MechgenError, match=r"tab.reduced\('drive'\)"):
        tab.extremes("drive")
    assert np.isfinite(tab.extremes("xs").max).all()


CUDA_CHECK = textwrap.dedent('''
    import json, sys, warnings
    import numpy as np
    import mechgen
    warnings.simplefilter("ignore")
    path, outdir = sys.argv[1], sys.argv[2]
    mech = mechgen.compile(mechgen.load_model(path), outdir=outdir, tier="python")
    kw = dict(params={"r": [1.0, 2.0, 2.5], "e": [1.0, -0.5]}, level="position")
    c = mech.sweep(0, 1, 37, **kw)
    g = mech.sweep(0, 1, 37, backend="cuda", **kw)
    out = dict(status=[c.status.ravel().tolist(), g.status.ravel().tolist()],
               done=[c.done.tolist(), g.done.tolist()],
               Q=bool(np.array_equal(c.Q, g.Q, equal_nan=True)),
               INFO=bool(np.array_equal(c.INFO, g.INFO)),
               points=[[np.flatnonzero(t.sweep(*np.unravel_index(d, t.shape)).status).tolist()
                        for d in range(len(t))] for t in (c, g)])
    print(json.dumps(out))
''')


def test_cuda_table_marks_points_as_the_cpu_does(tmp_path):
    path = _model_file(tmp_path)
    script = tmp_path / "check.py"
    script.write_text(CUDA_CHECK)
    env = cuda_sim_env(PYTHONPATH=ROOT, MECHGEN_CACHE=str(tmp_path / "cache"))
    out = subprocess.run([sys.executable, str(script), path, str(tmp_path)], env=env,
                         capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-3000:]
    r = json.loads(out.stdout.strip().splitlines()[-1])
    assert r["status"][0] == r["status"][1] and r["done"][0] == r["done"][1] and r["Q"]
    # r = 2, e = 1 (design 2) and r = 2.5, e = -0.5 (design 5) pass a toggle on the grid
    assert r["points"][0][2] and r["points"][0][5]
    assert r["points"][1] == r["points"][0]
    assert r["INFO"]


def test_assemblies_keeps_a_half_turned_rod_whose_end_moves(sc2):
    """At t = 0 the rod (origin at the crank pin) reaches the guide at x = 4 or x = −2:
    two assemblies, differing only in Th3 by π (every other coordinate equal). A table's
    guess= for the left-hand mode is looked for there (docs/reference/runtime.md: every distinct
    assembly)."""
    xs = sorted(round(float(s["xs"]), 9) for s in sc2.assemblies(0.0))
    assert xs == [-2.0, 4.0]


@pytest.mark.parametrize("bad, match", [
    (dict(level="velocty"), "level must be one of"),
    (dict(workers=0), "workers must be a positive integer"),
    (dict(backend="gpu"), "backend must be one of"),
    (dict(guess={"Zz": 1.0}), "not a coordinate"),
])
def test_optimize_says_what_is_wrong(sc2, bad, match):
    """A bad argument of mech.optimize (or a ValueError of the objective) came back as
    scipy's "The map-like callable must be of the form f(func, iterable) ..." RuntimeError:
    differential_evolution replaces a TypeError or ValueError of the function it calls."""
    args = dict(t0=0, t1=1, n=9, maxiter=1, popsize=3, polish=False)
    args.update(bad)
    with pytest.raises(ValueError, match=match):
        sc2.optimize(lambda tab: tab.reduced("xs").max, {"r": (0.5, 2.5)}, **args)


def test_optimize_passes_the_objectives_own_error(sc2):
    def objective(tab):
        raise ValueError("my objective's message")
    with pytest.raises(ValueError, match="my objective's message"):
        sc2.optimize(objective, {"r": (0.5, 2.5)}, 0, 1, 9, maxiter=1, popsize=3)


def test_optimize_finds_the_closed_form_design(sc2):
    """Stroke 3 and time ratio 1.2 of the offset slider-crank (l = 3): the exact extremes
    in closed form are where crank and rod line up (fsolve here: r = 1.452743151657,
    e = 0.647002322977)."""
    from scipy.optimize import fsolve

    def stroke_ratio(r, e, l=3.0):
        xmax, xmin = np.sqrt((l + r) ** 2 - e * e), np.sqrt((l - r) ** 2 - e * e)
        fwd = (np.pi + np.arctan2(e, xmin) - np.arctan2(e, xmax)) / (2 * np.pi)
        return xmax - xmin, fwd / (1 - fwd)

    want = fsolve(lambda v: np.array(stroke_ratio(*v)) - [3.0, 1.2], [1.5, 0.5], xtol=1e-12)

    def objective(tab):
        x = tab.extremes("xs")
        fwd = (x.tmin - x.tmax) % 1.0
        return ((x.max - x.min) / 3.0 - 1) ** 2 + (fwd / (1 - fwd) / 1.2 - 1) ** 2

    best = sc2.optimize(objective, {"r": (0.5, 2.5), "e": (0.0, 1.5)}, 0, 1, 40,
                        level="acceleration", seed=3, popsize=6, maxiter=30)
    assert np.allclose(best.x, want, atol=1e-9), (best.x, want)


def test_check_counts_the_half_turned_rod_as_a_mode_as_assemblies_does(tmp_path, capsys):
    """`mechgen check` counts modes as mech.assemblies does: both ends of the rod on the
    guide (x = 4 and x = -2 at t = 0), while the quick-return's slider reversed on its
    guide (its axis' end moves, no point a constraint places) still counts once."""
    from mechgen.cli import main
    code = main(["check", _model_file(tmp_path)])
    out = capsys.readouterr().out
    assert code == 0
    assert "assembly modes at t = 0: 2 found" in out
    assert re.search(r"2\s+3\.14159", out)
    code = main(["check", os.path.join(ROOT, "examples", "quick_return.py")])
    out = capsys.readouterr().out
    assert code == 0 and "assembly modes at t = 0: 2 found" in out
