"""Design tables on every backend (mechgen.runtime.tables.backends, dask_backend, reduce, refine,
synthesis): all cores == one core bit for bit, dask == cpu, reductions == the full table's,
failed designs marked, bad input refused, exact extremes, dimensional synthesis, the CLI."""
import math
import os
import sys

import numpy as np
import pytest

import mechgen
from conftest import ROOT
from mechgen.protocol import JUMP, OK, THROUGH_SINGULAR

# the crank longer than its pivot's distance from the lever's (5) cannot turn: 6.0 fails
LENGTHS = np.r_[np.linspace(1.0, 3.5, 23), 6.0]
GOOD = (OK, JUMP, THROUGH_SINGULAR)


def _same(a, b):
    return a.shape == b.shape and np.array_equal(a, b, equal_nan=True)


@pytest.fixture(scope="module")
def serial(qr):
    return qr.sweep(0.0, 1.0, 40, params={"longitud": LENGTHS, "velocidad": [2 * math.pi, 3.0]},
                    level="velocity", workers=1, on_fail="ignore")


def test_all_cores_equal_one_core_bit_for_bit(qr, serial):
    for workers in (2, None):
        tab = qr.sweep(0.0, 1.0, 40, params={"longitud": LENGTHS, "velocidad": [2 * math.pi, 3.0]},
                       level="velocity", workers=workers, on_fail="ignore")
        for name in ("Q", "QD", "INFO", "done", "status"):
            assert _same(getattr(tab, name), getattr(serial, name)), name
    # and each design is the single sweep of it
    ref = qr.with_params(longitud=LENGTHS[5], velocidad=3.0).sweep(0.0, 1.0, 40, level="velocity")
    assert np.array_equal(serial["X4d"][5, 1], ref["X4d"])


def test_failed_designs_are_marked_never_dropped(serial):
    assert serial.shape == (24, 2) and serial.status.shape == (24, 2)
    # the long crank fails at a full turn (velocidad 2π), not in 3 radians
    assert list(serial.ok[-1]) == [False, True] and serial.ok[:-1].all()
    assert serial.status[-1, 0] not in GOOD
    assert all(s in GOOD for s in serial.status.ravel()[:-2])
    assert len(serial.failures) == 1 and serial.failures[0][0]["longitud"] == 6.0
    k = int(serial.done.reshape(24, 2)[-1, 0])
    assert np.all(np.isnan(serial["X4"][-1, 0, k:])) and np.all(np.isfinite(serial["X4"][-1, 0, :k]))


@pytest.mark.parametrize("workers", [1, None])
def test_reductions_equal_the_full_tables(qr, serial, workers):
    names = ["X4", "X4d", "Th3", "stroke_x", "stroke_xd"]
    red = qr.sweep(0.0, 1.0, 40, params={"longitud": LENGTHS, "velocidad": [2 * math.pi, 3.0]},
                   level="velocity", workers=workers, reduce=names, on_fail="ignore")
    assert not red.kept_points and red.reductions == tuple(names)
    assert _same(red.status, serial.status) and _same(red.done, serial.done)
    for name in names:
        full = serial[name]                                     # NaN past a failure
        r = red.reduced(name)
        assert _same(r.min, np.nanmin(full, axis=-1)) and _same(r.max, np.nanmax(full, axis=-1))
        assert _same(r.tmin, serial.t[np.nanargmin(full, axis=-1)])
        assert _same(r.tmax, serial.t[np.nanargmax(full, axis=-1)])
        assert _same(r.ok, serial.ok)
        back = serial.reduced(name)                             # from the kept points
        assert _same(back.min, r.min) and _same(back.tmax, r.tmax)
    with pytest.raises(mechgen.MechgenError, match="reductions"):
        red["X4"]
    with pytest.raises(KeyError, match="pass reduce"):
        red.reduced("Y4")
    header, data = red.table()
    assert header[:4] == ["longitud", "velocidad", "status", "X4_min"] and data.shape == (48, 23)


def quick_return_x4(t, L):
    """The slider's X4 in closed form (tests/closed_forms.py) with the crank length L."""
    from closed_forms import quick_return
    return quick_return(t, longitud=L)[6]


def closed_form_extreme(L, t0):
    """The time and value where dX4/dt = 0 near t0, from the closed form."""
    import mpmath as mp
    with mp.workdps(40):
        t = mp.findroot(lambda u: mp.diff(lambda v: quick_return_x4(v, L), u), mp.mpf(t0))
        return float(t), float(quick_return_x4(t, L))


def test_exact_extremes_agree_with_the_closed_form(qr):
    tab = qr.sweep(0.0, 1.0, 30, params={"longitud": [1.5, 2.5, 6.0]}, level="acceleration",
                   on_fail="ignore")
    ext = tab.extremes("X4")
    for i, L in enumerate((1.5, 2.5)):
        for t, v in ((ext.tmin[i], ext.min[i]), (ext.tmax[i], ext.max[i])):
            t_ref, v_ref = closed_form_extreme(L, t)
            assert abs(t - t_ref) < 1e-12 and abs(v - v_ref) < 1e-13 * (1 + abs(v_ref)), (L, t, v)
        # the global ones: no sample of the closed form lies beyond them
        grid = [float(quick_return_x4(k / 400, L)) for k in range(400)]
        assert min(grid) >= ext.min[i] - 1e-13 and max(grid) <= ext.max[i] + 1e-13
        # a single sweep's extrema (refined between its points) find the same
        ev = qr.with_params(longitud=L).sweep(0.0, 1.0, 30, level="velocity").extrema("X4")
        assert ev.minima.value[0] == pytest.approx(ext.min[i], abs=1e-12)
        assert ev.maxima.value[0] == pytest.approx(ext.max[i], abs=1e-12)
    grid = tab.reduced("X4")
    assert np.all(ext.max[:2] >= grid.max[:2]) and not ext.ok[2]


def test_bad_input_is_refused_clearly(qr):
    with pytest.raises(ValueError, match="'longitud'.*empty"):
        qr.sweep(0, 1, 5, params={"longitud": []})
    with pytest.raises(ValueError, match="'longitud'.*finite.*inf"):
        qr.sweep(0, 1, 5, params={"longitud": [1.0, np.inf]})
    with pytest.raises(ValueError, match="'anguloI'"):
        qr.sweep(0, 1, 5, params={"longitud": [1.0], "anguloI": float("nan")})
    with pytest.raises(ValueError, match="reduce.*'X9'"):
        qr.sweep(0, 1, 5, params={"longitud": [1.0, 2.0]}, reduce=["X9"])
    with pytest.raises(ValueError, match="reduce.*'X4d'.*velocity"):
        qr.sweep(0, 1, 5, params={"longitud": [1.0, 2.0]}, reduce=["X4d"])
    with pytest.raises(ValueError, match="backend"):
        qr.sweep(0, 1, 5, params={"longitud": [1.0, 2.0]}, backend="gpu")
    with pytest.raises(ValueError, match="workers"):
        qr.sweep(0, 1, 5, params={"longitud": [1.0, 2.0]}, workers=0)
    with pytest.raises(ValueError, match="design tables"):
        qr.sweep(0, 1, 5, backend="dask")
    with pytest.raises(ValueError, match="one length"):
        qr.sweep(0, 1, 5, params={"longitud": [1.0, 2.0], "velocidad": [1.0]}, grid=False)
    with pytest.raises(mechgen.MechgenError, match="cuda"):
        qr.sweep(0, 1, 5, params={"longitud": [1.0, 2.0]}, backend="cuda")


def test_listed_designs(qr):
    tab = qr.sweep(0, 1, 9, params={"longitud": [2.0, 3.0, 2.5], "velocidad": [3.0, 2.0, 1.0]},
                   grid=False)
    assert tab.shape == (3,) and tab["X4"].shape == (3, 9)
    ref = qr.with_params(longitud=3.0, velocidad=2.0).sweep(0, 1, 9)
    assert np.array_equal(tab.sweep(longitud=3.0, velocidad=2.0)["X4"], ref["X4"])
    assert np.array_equal(tab.design_params()[2], [2.5, 1.0])
    # a position table keeps no derivative arrays; its outputs still evaluate
    assert tab.QD is None and tab.QDD is None
    assert np.array_equal(tab["stroke_x"], tab["X4"])
    assert np.array_equal(tab.reduced("stroke_x").max, np.max(tab["X4"], axis=1))
    sub = tab.take([2, 0])
    assert np.array_equal(sub["X4"], tab["X4"][[2, 0]]) and sub.params["longitud"].tolist() == [2.5, 2.0]


def test_optimize_a_stroke(qr):
    """The crank length that gives the slider a stroke of 8; cranks of 5 or more cannot
    turn (rejected, never scored)."""
    seen = []

    def objective(tab):
        assert tab.ok.all()                        # rejected designs never get here
        x4 = tab.extremes("X4")
        seen.append(len(tab))
        return (x4.max - x4.min - 8.0) ** 2

    best = qr.optimize(objective, bounds={"longitud": (1.0, 6.0)}, t0=0.0, t1=1.0, n=24,
                       level="acceleration", popsize=6, maxiter=15, seed=3)
    assert best.rejected > 0 and best.evaluated == best.rejected + sum(seen)
    ev = best.mechanism.sweep(0.0, 1.0, 60, level="velocity").extrema("X4")
    assert ev.maxima.value[0] - ev.minima.value[0] == pytest.approx(8.0, abs=1e-8)
    # and in the closed form: the crank length found gives the slider a stroke of 8
    L = best.params["longitud"]
    lo = closed_form_extreme(L, ev.minima.t[0])[1]
    hi = closed_form_extreme(L, ev.maxima.t[0])[1]
    assert hi - lo == pytest.approx(8.0, abs=1e-8)
    assert best.params["longitud"] < 5.0 and best.seconds > 0 and "designs evaluated" in repr(best)
    with pytest.raises(ValueError, match="low < high"):
        qr.optimize(objective, bounds={"longitud": (2.0, 1.0)}, t0=0, t1=1, n=10)


def test_command_line_design_table(qr, tmp_path, capsys):
    """In this process, on the committed module (the CLI renders the model, finds the same
    text and keeps the file: numba's cache holds)."""
    from mechgen.cli import main
    model = os.path.join(ROOT, "examples", "quick_return.py")
    common = [model, "--outdir", os.path.join(ROOT, "generated")]
    code = main(["sweep", *common, "-n", "20", "--param", "longitud=1:3:3", "--reduce", "X4,X4d",
                 "--progress", "--workers", "2", "-o", str(tmp_path / "t.csv")])
    err = capsys.readouterr().err
    assert code in (0, None) and "designs solved: 3/3" in err and "100%" in err
    rows = np.genfromtxt(tmp_path / "t.csv", delimiter=",", names=True)
    assert list(rows["longitud"]) == [1.0, 2.0, 3.0] and "X4d_tmax" in rows.dtype.names
    ref = qr.sweep(0, 1, 20, params={"longitud": [1.0, 2.0, 3.0]}, level="velocity")
    assert np.allclose(rows["X4_max"], np.nanmax(ref["X4"], axis=1), rtol=1e-12, atol=0)
    assert main(["sweep", *common, "-n", "5", "--param", "longitud=1:3:2",
                 "--backend", "cuda"]) != 0
    assert "cuda" in capsys.readouterr().err
    assert main(["sweep", *common, "-n", "5", "--reduce", "X4"]) != 0
    assert "design tables" in capsys.readouterr().err


# -- dask: one LocalCluster of two worker processes for the module ------------------------------
@pytest.fixture(scope="module")
def client():
    import distributed                   # in the test extra: never skipped
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=None)
    cl = distributed.Client(cluster)
    yield cl
    cl.close()
    cluster.close()


def test_dask_equals_cpu(qr, serial, client):
    tab = qr.sweep(0.0, 1.0, 40, params={"longitud": LENGTHS, "velocidad": [2 * math.pi, 3.0]},
                   level="velocity", backend="dask", client=client, on_fail="ignore")
    for name in ("Q", "QD", "INFO", "done", "status"):
        assert _same(getattr(tab, name), getattr(serial, name)), name
    red = qr.sweep(0.0, 1.0, 40, params={"longitud": LENGTHS, "velocidad": [2 * math.pi, 3.0]},
                   level="velocity", backend="dask", reduce=["X4d", "stroke_x"], on_fail="ignore")
    for name in ("X4d", "stroke_x"):                           # the default client this time
        a, b = red.reduced(name), serial.reduced(name)
        for what in ("min", "max", "tmin", "tmax", "ok", "status"):
            assert _same(getattr(a, what), getattr(b, what)), (name, what)
    with pytest.warns(RuntimeWarning, match="longitud=6"):
        qr.sweep(0.0, 1.0, 10, params={"longitud": [2.0, 6.0]}, backend="dask", client=client)
    # a mechanism on the plain-Python tier ships the same file; the workers compile it
    py = mechgen.load(os.path.join(ROOT, "generated", "quick_return.py"), tier="python")
    tab = py.sweep(0.0, 1.0, 40, params={"longitud": LENGTHS[:4]}, level="velocity",
                   backend="dask", client=client)
    assert py.tier == "python" and _same(tab.Q, serial.Q[0:8:2])     # velocidad 2π: every other row


def test_dask_force_table_equals_cpu(client):
    """level="dynamic" with reduce= on the driver (docs/reference/forces.md) over the cluster: the
    workers solve the multipliers of their chunks; the same numbers as this process's."""
    qf = mechgen.load(os.path.join(ROOT, "generated", "quick_return_forces.py"))
    kw = dict(params={"longitud": [2.5, 3.0, 3.5], "corte": [0.0, 500.0]}, level="dynamic")
    red = qf.sweep(0.0, 1.0, 30, backend="dask", client=client,
                   reduce=["crank driver", "X4"], **kw)
    here = qf.sweep(0.0, 1.0, 30, reduce=["crank driver", "X4"], **kw)
    for name in ("crank driver", "X4"):         # the same code on the workers: bit for bit
        a, b = red.reduced(name), here.reduced(name)
        assert np.array_equal(a.max, b.max) and np.array_equal(a.min, b.min)
    # the full table's efforts come from the separate pass over its points (force_rows),
    # the reduction's from the sweeps' own step (sweep_designs_forces): equal to rounding
    full = qf.sweep(0.0, 1.0, 30, **kw)
    tau = full.driver("crank driver")
    r = red.reduced("crank driver")
    np.testing.assert_allclose(r.max, tau.max(axis=-1), rtol=1e-13)
    np.testing.assert_allclose(r.min, tau.min(axis=-1), rtol=1e-13)
    assert np.array_equal(red.reduced("X4").max, full["X4"].max(axis=-1))


def test_cuda_backend_on_the_simulator():
    """backend="cuda" through the design-table dispatch into the real kernels of
    mechgen.runtime.tables.cuda, on numba's CUDA simulator (a subprocess: numba reads
    NUMBA_ENABLE_CUDASIM when first imported; tests/cuda_sim_check.py contract): its full
    table and its reductions equal the CPU's, the design that fails in mid-sweep included."""
    import json
    import subprocess
    env = dict(os.environ, NUMBA_ENABLE_CUDASIM="1", PYTHONPATH=ROOT)
    out = subprocess.run([sys.executable, os.path.join(ROOT, "tests", "cuda_sim_check.py"),
                          "contract"], env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-3000:]
    r = json.loads(out.stdout.strip().splitlines()[-1])["contract"]
    assert r["ok"] == [[True, True], [True, True], [True, True], [False, True]]
    assert r["failed_partial"] and r["failed_nan_after"]       # NaN past the failed time
    for key in ("status_same", "ok_same", "done_same", "reduce_status_same", "reduce_done_same"):
        assert r[key], key
    for key in ("diff_X4", "diff_X4d", "diff_Th3", "diff_stroke_xd", "reduce_diff",
                "reduce_vs_full"):
        assert r[key] <= 1e-12, (key, r[key])                 # docs/cuda.md: the CPU's source


def test_a_table_in_the_python_tier(qr, monkeypatch):
    """A mechanism still on the plain-Python tier asks its tiers first (a big table switches
    to the compiled module: mechgen.runtime.loading.tiers.expect), then gives the compiled numbers."""
    py = mechgen.load(os.path.join(ROOT, "generated", "quick_return.py"), tier="python")
    assert py.tier == "python"
    asked = []
    monkeypatch.setattr(py.state.tiers, "expect",
                        lambda mech, points, kind="sweep": asked.append((points, kind)))
    args = dict(params={"longitud": [2.0, 3.0, 6.0]}, level="velocity", on_fail="ignore")
    tab = py.sweep(0.0, 1.0, 7, workers=2, **args)
    assert asked == [(21, "design")]
    ref = qr.sweep(0.0, 1.0, 7, **args)
    assert _same(tab.status, ref.status) and _same(tab.done, ref.done)
    for name in ("Q", "QD", "INFO"):                         # bit for bit, as the tiers promise
        assert _same(getattr(tab, name), getattr(ref, name)), name


def test_guided_chunks_cover_every_design_once_big_ones_first():
    from mechgen.runtime.tables.chunks import CHUNK_POINTS, guided_chunks
    for D, N, workers, most in ((2000, 1000, 2, None), (7, 1000, 2, None), (1, 5, 16, None),
                                (100000, 10, 2, None), (2000, 1000, 2, 40), (0, 10, 2, None)):
        spans = guided_chunks(D, N, workers, most)
        ends = [0] + [b for _, b in spans]
        assert [a for a, _ in spans] == ends[:-1] and ends[-1] == D
        sizes = [b - a for a, b in spans]
        assert all(s >= 1 for s in sizes)
        assert sizes[:-1] == sorted(sizes[:-1], reverse=True)     # (the last: what is left)
        assert max(sizes, default=1) <= max(1, CHUNK_POINTS // N) and \
            max(sizes, default=1) <= (most or D or 1)
    # the last chunks are small: the threads finish within a small share of the table
    sizes = [b - a for a, b in guided_chunks(2000, 1000, 2)]
    assert sizes[0] == 100 and sizes[-1] <= 5
