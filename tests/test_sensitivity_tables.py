"""Sensitivities of sweeps and design tables equal those of single solves: a sweep's point by
point, a design table's on every backend (threads, Dask, the CUDA simulator) those of each
design's own sweep. The references of the numbers themselves are in
test_sensitivity_references.py (mpmath closed forms)."""
import json
import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

import mechgen
from conftest import ROOT, example_model

PARAMS = {"a": [0.7, 0.8, 0.9], "b": [2.4, 2.6]}


@pytest.fixture(scope="module")
def fourbar(tmp_path_factory):
    return mechgen.compile(example_model("fourbar"), outdir=str(tmp_path_factory.mktemp("g")))


def test_a_sweep_equals_its_single_solves(fourbar):
    sw = fourbar.sweep(0.0, 0.9, 10, level="acceleration", sensitivities=True)
    for k in (0, 4, 9):
        s = fourbar.solve(float(sw.t[k]), guess=sw.Q[k], level="acceleration",
                          sensitivities=True)
        for order, (a, b) in enumerate(zip((sw.dq_dp, sw.dqd_dp, sw.dqdd_dp),
                                           (s.dq_dp, s.dqd_dp, s.dqdd_dp))):
            assert np.allclose(a[k], b, rtol=1e-12, atol=1e-12), order


def test_a_table_equals_each_designs_sweep(fourbar):
    tab = fourbar.sweep(0.0, 1.0, 9, level="acceleration", params=PARAMS,
                        sensitivities=["a", "d"], workers=2)
    assert tab.sensitivity("Th4", "a").shape == (3, 2, 9)
    for i, a in enumerate(PARAMS["a"]):
        for j, b in enumerate(PARAMS["b"]):
            sw = fourbar.with_params(a=a, b=b).sweep(0.0, 1.0, 9, level="acceleration",
                                                     sensitivities=["a", "d"])
            for name in ("Th4", "X3d", "Th3dd"):
                for p in ("a", "d"):
                    assert np.array_equal(tab.sensitivity(name, p)[i, j],
                                          sw.sensitivity(name, p)), (name, p, a, b)
    one = tab.sweep(a=0.8, b=2.6)
    assert one.sensitivity_params == ["a", "d"]
    with pytest.raises(KeyError):
        one.sensitivity("Th4", "b")         # not asked for


def test_a_table_without_sensitivities_says_how(fourbar):
    tab = fourbar.sweep(0.0, 1.0, 3, params=PARAMS)
    with pytest.raises(mechgen.MechgenError, match="sensitivities=True"):
        tab.sensitivity("Th4", "a")


def test_dask_table_equals_cpu(fourbar):
    distributed = pytest.importorskip("distributed")
    cluster = distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                       dashboard_address=None)
    client = distributed.Client(cluster)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            dask = fourbar.sweep(0.0, 1.0, 7, level="velocity", params=PARAMS, backend="dask",
                                 client=client, sensitivities=True)
        cpu = fourbar.sweep(0.0, 1.0, 7, level="velocity", params=PARAMS, sensitivities=True)
        for name in ("Th4", "Th3d"):
            for p in fourbar.parameter_names:
                assert np.allclose(dask.sensitivity(name, p), cpu.sensitivity(name, p),
                                   rtol=1e-12, atol=1e-12, equal_nan=True)
    finally:
        client.close()
        cluster.close()


def test_cuda_simulator_table_equals_cpu(tmp_path):
    env = dict(os.environ, NUMBA_ENABLE_CUDASIM="1", MECHGEN_TIER="python", PYTHONPATH=ROOT)
    out = subprocess.run([sys.executable, os.path.join(ROOT, "tests",
                                                       "sensitivity_backends_check.py"),
                          str(tmp_path)], env=env, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-3000:]
    r = json.loads(out.stdout.strip().splitlines()[-1])
    assert r["shape"] == [2, 2, 6]
    assert r["worst"] <= 1e-9
