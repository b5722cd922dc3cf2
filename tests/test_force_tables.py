"""Design tables at the force levels (issue 21, docs/reference/forces.md: "design tables and reduce=
accept driver names"): the drivers' efforts of every design against the closed-form slider-crank of
test_forces (its power form, with the slider's mass varied), reductions (peak torque per design in
one call) against the full table, each design's sweep against a single sweep, the backends against
each other, mech.optimize on a force objective against a scan of the closed form. The CUDA backend's
force tables: tests/test_cuda_forces.py."""
import math

import numpy as np
import pytest

from test_forces import M4, W, closed_form, power_torque, slider_crank

import mechgen

PERIOD = 2 * math.pi / W
MASSES = [1.0, 3.0, 5.5]


@pytest.fixture(scope="module")
def sc(tmp_path_factory):
    return mechgen.compile(slider_crank(), outdir=str(tmp_path_factory.mktemp("sct")),
                           tier="python")


def torque(t, mass4):
    """The power form of test_forces with the slider's mass ``mass4``: the slider only
    translates, level, so its share of T·θ̇ is mass4·ẍ·ẋ."""
    k = closed_form(t)
    xd = k["vC"][0]
    xdd = k["bodies"]["slider"][2][0]
    return power_torque(k) + (mass4 - M4) * xdd * xd / k["thd"]


def test_a_dynamic_table_gives_every_design_its_torque(sc):
    tab = sc.sweep(0.0, PERIOD, 120, params={"mass4": MASSES}, level="dynamic")
    assert tab.force_level == "dynamic" and "level dynamic" in repr(tab)
    tau = tab.driver("crank driver")
    assert tau.shape == (3, 120)
    assert np.array_equal(tab["crank driver"], tau)
    for i, mass in enumerate(MASSES):
        want = np.array([torque(t, mass) for t in tab.t])
        np.testing.assert_allclose(tau[i], want, rtol=1e-9, atol=1e-9 * np.abs(want).max())
        one = sc.with_params(mass4=mass).sweep(0.0, PERIOD, 120, level="dynamic")
        assert np.array_equal(one.driver("crank driver"), tau[i])     # the same numbers
        sw = tab.sweep(i)
        assert sw.force_level == "dynamic"
        assert np.array_equal(sw.reaction("B", on="rod"), one.reaction("B", on="rod"))


def test_reduce_keeps_the_peak_torque_of_every_design(sc):
    full = sc.sweep(0.0, PERIOD, 200, params={"mass4": MASSES}, level="dynamic")
    red = sc.sweep(0.0, PERIOD, 200, params={"mass4": MASSES}, level="dynamic",
                   reduce=["crank driver", "X4d"])
    assert not red.kept_points
    tau = full.driver("crank driver")
    r = red.reduced("crank driver")
    assert np.array_equal(r.max, tau.max(axis=1)) and np.array_equal(r.min, tau.min(axis=1))
    assert np.array_equal(r.tmax, full.t[np.argmax(tau, axis=1)])
    assert np.array_equal(r.tmin, full.t[np.argmin(tau, axis=1)])
    for what in ("min", "max", "tmin", "tmax"):         # from the kept points: the same
        assert np.array_equal(getattr(full.reduced("crank driver"), what), getattr(r, what))
    assert np.array_equal(red.reduced("X4d").max, full["X4d"].max(axis=1))
    # the closed form's peak (the grid's: the reduction is over the table's times)
    for i, mass in enumerate(MASSES):
        want = np.array([torque(t, mass) for t in full.t])
        assert r.max[i] == pytest.approx(want.max(), rel=1e-9)


def test_a_static_table_holds_the_press(sc):
    """Static: q̇ = q̈ = 0, so the slider's mass only weighs on the guide: the torque that
    holds the press and gravity is the same for every mass (the slider moves level)."""
    red = sc.sweep(0.0, PERIOD, 50, params={"mass4": MASSES}, level="static",
                   reduce=["crank driver"])
    one = sc.sweep(0.0, PERIOD, 50, level="static")
    r = red.reduced("crank driver")
    tau = one.driver("crank driver")
    np.testing.assert_allclose(r.max, tau.max(), rtol=1e-12)
    np.testing.assert_allclose(r.min, tau.min(), rtol=1e-12)


def test_force_tables_refuse_what_they_cannot_do(sc):
    with pytest.raises(ValueError, match="'crank driver' is a driver.*'static' or 'dynamic'"):
        sc.sweep(0.0, 1.0, 10, params={"mass4": MASSES}, reduce=["crank driver"],
                 level="acceleration")
    tab = sc.sweep(0.0, 1.0, 10, params={"mass4": MASSES}, level="acceleration")
    with pytest.raises(ValueError, match="needs a table at level 'static' or 'dynamic'"):
        tab.driver("crank driver")
    dyn = sc.sweep(0.0, 1.0, 10, params={"mass4": MASSES}, level="dynamic")
    with pytest.raises(ValueError, match="not a driver"):
        dyn.driver("B")
    with pytest.raises(ValueError, match="no constraint 'nope'"):
        dyn.driver("nope")
    with pytest.raises(ValueError, match="reduce: unknown|reduce:"):
        sc.sweep(0.0, 1.0, 10, params={"mass4": MASSES}, level="dynamic", reduce=["nope"])


def test_optimize_the_slider_mass_for_the_least_peak_torque(sc):
    """The peak torque over a cycle against the slider's mass: the optimizer's choice scores
    no worse than the best of a 401-point scan of the closed form."""
    ts = np.linspace(0.0, PERIOD, 60)

    def peak(tab):
        return np.max(np.abs(tab.driver("crank driver")), axis=-1)
    best = sc.optimize(peak, bounds={"mass4": (0.5, 6.0)}, t0=0.0, t1=PERIOD, n=60,
                       level="dynamic", seed=3, maxiter=15, popsize=8)
    scan = [np.max(np.abs([torque(t, m) for t in ts])) for m in np.linspace(0.5, 6.0, 401)]
    assert best.fun <= min(scan) * (1 + 1e-7)
    assert best.fun == pytest.approx(np.max(np.abs([torque(t, best.params["mass4"])
                                                    for t in ts])), rel=1e-9)


def test_the_hosts_force_reduction_on_threads_is_the_one_pass(sc, monkeypatch):
    """What the GPU's table hands the host (every design's points) is reduced a few
    designs at a time on threads: the same minima, maxima and their times as one pass."""
    import mechgen.runtime.tables.chunks as chunks
    from mechgen.runtime.tables.chunks import reduce_threads
    from mechgen.runtime.tables.reduce import reduce_chunk, reduce_slots
    tab = sc.sweep(0.0, PERIOD, 40, params={"mass4": np.linspace(0.5, 6.0, 7)},
                   level="acceleration")
    slots = reduce_slots(sc, ["crank driver", "X4"], 2, "dynamic")[1]
    done = np.full(7, 40, dtype=np.int64)
    args = (sc.module, slots, tab.t, tab.P, tab.Q.reshape(7, 40, -1),
            tab.QD.reshape(7, 40, -1), tab.QDD.reshape(7, 40, -1), done)
    whole = reduce_chunk(*args)
    monkeypatch.setattr(chunks, "FORCE_POINTS", 90)          # two designs a chunk
    for workers in (1, 3):
        parts = reduce_threads(*args, workers=workers)
        for a, b in zip(whole, parts):
            np.testing.assert_array_equal(a, b)
    expected = [max(abs(torque(t, m)) for t in tab.t) for m in np.linspace(0.5, 6.0, 7)]
    peak = np.maximum(np.abs(whole[0][:, 0]), np.abs(whole[1][:, 0]))
    np.testing.assert_allclose(peak, expected, rtol=1e-9)
