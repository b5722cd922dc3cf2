"""Force design tables reducing a driver's effort with backend="cuda" (mechgen.runtime.
cuda_forces): the effort reduced in the kernel while each design is swept, no point
brought back; the designs the quick path does not finish (a hard point, a failure) or whose
multipliers are weak solved on the host by the CPU table. On numba's CUDA simulator in a
subprocess (tests/cuda_forces_check.py; numba reads NUMBA_ENABLE_CUDASIM when first
imported), against backend="cpu", the full table's efforts and closed forms."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT, cuda_sim_env


@pytest.fixture(scope="module")
def sim():
    env = cuda_sim_env(PYTHONPATH=ROOT)
    out = subprocess.run([sys.executable, os.path.join(ROOT, "tests", "cuda_forces_check.py")],
                         env=env, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-3000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


def _same_as_cpu(r, names):
    assert r["done"] == r["cpu_done"] and r["status"] == r["cpu_status"]
    assert not r["kept_points"]
    for n in names:
        assert r["diff_" + n] <= 1e-12, (n, r["diff_" + n])     # (the torque: relative)


def test_quick_return_reduces_on_the_gpu_and_the_host_finishes_the_rest(sim):
    from mechgen.protocol import OK
    r = sim["quick_return"]
    _same_as_cpu(r, ["crank driver", "X4", "Th3d"])
    assert r["calls"] == 1                      # one GPU table, no point brought back
    assert "Q" not in r["keys"] and "min" in r["keys"]
    # longitud 1, 2, 2.5 on the GPU; 3 (the careful sweep) and 4.5, 6 (cannot turn) on
    # the host, where 4.5 and 6 fail in mid-sweep
    assert r["host"] == [3, 4, 5] and r["gpu_done"][:3] == [40, 40, 40]
    assert r["status"][:4] == [OK] * 4 and all(s != OK for s in r["status"][4:])
    assert all(0 < d < 40 for d in r["done"][4:])
    assert r["vs_full"] <= 1e-12                # the extremes of tab.driver over every point


def test_weak_multipliers_send_the_design_to_the_host(sim):
    r = sim["weak_pivots"]
    assert r["host"] == [0, 1, 2]
    _same_as_cpu(r, ["crank driver", "X4", "Th3d"])


def test_static_reduces_on_the_gpu_too(sim):
    """sweep_fast_statics in the kernel: the same designs on the GPU as at level dynamic
    (3 needs the careful sweep, 4.5 and 6 fail: the host), the CPU table's numbers."""
    r = sim["static"]
    _same_as_cpu(r, ["crank driver", "X4"])
    assert r["calls"] == 1 and r["host"] == [3, 4, 5]
    assert r["vs_full"] <= 1e-12


def test_static_without_the_quick_path_keeps_the_points(sim):
    r = sim["static_unfused"]
    assert r["calls"] == 0                      # not the force kernel: every point back
    assert r["done"] == r["cpu_done"] and r["status"] == r["cpu_status"]
    assert max(r["diff_crank driver"], r["diff_X4"]) <= 1e-12


def test_outputs_reduced_beside_the_driver(sim):
    r = sim["outputs"]
    assert r["host"] == [2]                     # longitud 3: the careful sweep, on the host
    _same_as_cpu(r, ["crank driver", "tip_x", "tip_xd", "X4", "X4d"])
    assert r["tip_vs_X4"] <= 1e-12 and r["tipd_vs_X4d"] <= 1e-12


def test_without_the_fused_path_against_the_closed_form(sim):
    r = sim["slider_crank"]
    assert r["gpu_calls"] == 0                  # no fused quick path: the points come back
    _same_as_cpu(r, ["crank driver", "X4"])
    assert r["torque_vs_closed"] <= 1e-9        # relative to the peak torque
    assert r["tmax_vs_closed"] == 0.0


def test_which_tables_keep_their_points():
    """backends.cuda_keeps_points: only a driver's effort the GPU cannot reduce (level
    static, method full) keeps the points."""
    import mechgen
    from mechgen.protocol import METHOD
    from mechgen.runtime.tables.backends import cuda_keeps_points
    from mechgen.runtime.tables.reduce import reduce_slots
    mech = mechgen.load(os.path.join(ROOT, "generated", "quick_return_forces.py"))
    dyn = reduce_slots(mech, ["crank driver", "X4"], 2, "dynamic")[1]
    sta = reduce_slots(mech, ["crank driver"], 0, "static")[1]
    kin = reduce_slots(mech, ["X4"], 2)[1]
    assert not cuda_keeps_points(mech, dyn, 2, METHOD["auto"])
    assert cuda_keeps_points(mech, dyn, 2, METHOD["full"])
    assert not cuda_keeps_points(mech, sta, 0, METHOD["auto"])  # sweep_fast_statics
    assert cuda_keeps_points(mech, sta, 0, METHOD["full"])
    mixed = np.vstack([dyn[:1], sta])                        # two force levels at once
    assert cuda_keeps_points(mech, mixed, 2, METHOD["auto"])
    assert not cuda_keeps_points(mech, kin, 2, METHOD["auto"])
    assert not cuda_keeps_points(mech, None, 2, METHOD["auto"])
    assert np.any(dyn[:, 0] == 2)


@pytest.mark.parametrize("name", ["sweep_fast_forces", "sweep_fast_statics"])
def test_sweep_fast_forces_translates_with_its_rows_masked(name):
    """The fused quick paths of the committed force module: their λ rows indexed through
    the row mask like Q, the hook before the first row each writes in each step."""
    import mechgen
    from mechgen.runtime.tables.cuda import numba_module
    from mechgen.runtime.tables.cuda_twin import ROOTS, translate
    mod = numba_module(mechgen.load(os.path.join(ROOT, "generated", "quick_return_forces.py")))
    text = translate(mod, ROOTS + (name,))
    fused = text[text.index(f"def {name}("):]
    fused = fused[:fused.index("\ndef ", 1)]
    assert "LAM[k & _cu_ctx[6], 0] = " in fused and "FPIV[k & _cu_ctx[6]] = " in fused
    assert "FACTORS[k & _cu_ctx[6], 0] = " in fused
    hook = fused.index("_cu_point_forces(k - 1, ts, Q, QD, QDD, STATUS, LAM, FACTORS, FPIV, p, "
                       "_cu_ctx)")
    assert hook < fused.index("LAM[k & _cu_ctx[6]") < fused.index("Q[k & _cu_ctx[6], 0] = ")
    assert "np.zeros" not in fused and ".copy()" not in fused
    assert translate(mod) == translate(mod, ROOTS)          # the kinematic twin: as before


def test_the_twin_s_source_file_is_written_once_per_text_module_and_options(tmp_path):
    """numba's cache of the kernels needs their source in a file, checked against its time
    stamp: the same text, module and options give the same file, written once; another
    option, or another module file, another file."""
    import shutil
    import types
    from mechgen.runtime.tables.cuda_twin import source_file
    shutil.copy(os.path.join(ROOT, "generated", "quick_return.py"), tmp_path / "qr.py")
    module = types.SimpleNamespace(__name__="qr", __file__=str(tmp_path / "qr.py"))
    first = source_file(module, "def f():\n    return 1\n", (1, None))
    assert first.startswith(str(tmp_path / "__pycache__"))
    assert open(first).read() == "def f():\n    return 1\n"
    stamp = os.stat(first).st_mtime_ns
    assert source_file(module, "def f():\n    return 1\n", (1, None)) == first
    assert os.stat(first).st_mtime_ns == stamp
    assert source_file(module, "def f():\n    return 1\n", (1, 64)) != first
    (tmp_path / "qr.py").write_text(open(tmp_path / "qr.py").read() + "\nN = 1\n")
    assert source_file(module, "def f():\n    return 1\n", (1, None)) != first


def test_a_kernel_numba_cannot_cache_is_compiled_without_the_cache():
    """cuda_twin._kernel: with its source in a file, the kernel asks numba for its on-disk
    cache; where numba refuses (here: a jit that raises for cache=True), it is compiled
    without, the options kept; without a file it never asks."""
    from mechgen.runtime.tables.cuda_twin import _kernel
    calls = []

    class FakeCuda:
        @staticmethod
        def jit(**opts):
            calls.append(opts)
            if opts.get("cache"):
                raise RuntimeError("cannot cache function: no locator available")
            return lambda fn: ("compiled", fn, opts)

    def kernel():
        pass
    got = _kernel(FakeCuda, kernel, {"max_registers": 64}, cache=True)
    assert got == ("compiled", kernel, {"max_registers": 64})
    assert calls == [{"cache": True, "max_registers": 64}, {"max_registers": 64}]
    calls.clear()
    assert _kernel(FakeCuda, kernel, {}, cache=False) == ("compiled", kernel, {})
    assert calls == [{}]
