"""backend="cuda" design tables (mechgen.runtime.tables.cuda) on numba's CUDA simulator: the
same values and statuses as the CPU design table, reductions as numpy's min/max of it.

numba reads NUMBA_ENABLE_CUDASIM when it is first imported, so the simulator runs in a
subprocess (tests/cuda_sim_check.py); sizes are tiny (the simulator runs each CUDA thread
as a Python thread)."""
import json
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from conftest import ROOT, cuda_sim_env
from mechgen.errors import MechgenError


@pytest.fixture(scope="module")
def sim():
    env = cuda_sim_env(PYTHONPATH=ROOT)
    out = subprocess.run([sys.executable, os.path.join(ROOT, "tests", "cuda_sim_check.py")],
                         env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-3000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("case", ["quick_return/position", "quick_return/velocity",
                                  "fourbar/acceleration"])
def test_cuda_table_matches_cpu(sim, case):
    name, level = case.split("/")
    r = sim[name][level]
    assert r["failed"] >= 1                   # a design that cannot assemble is in the grid
    assert r["diff"] <= 1e-12                 # Q (QD, QDD) of every solved point and the
    assert r["rows_same"]                     # failed one; per-point statuses the same
    assert r["below_none"]                    # no derivative arrays below the level
    assert r["done"] == r["cpu_done"] == r["reduce_done"]
    assert r["status"] == r["cpu_status"] == r["reduce_status"]
    assert r["names"] == r["asked"] and r["asked"]
    assert r["reduce_diff"] <= 1e-12          # min, max and their times
    assert r["nan_ok"]                        # a design that solved no time: NaN
    assert 0 < r["second_pass"] < r["designs"]  # both kernels ran: some designs needed sweep()
    assert r["dispatch"] is True              # mech.sweep(..., backend="cuda") equals the CPU table


def test_fourbar_fails_in_mid_sweep_and_passes_a_singular_configuration(sim):
    from mechgen.protocol import OK, THROUGH_SINGULAR
    r = sim["fourbar"]["acceleration"]
    assert r["partial"] >= 1                  # its extremes: over the times it solved
    assert 0 < min(d for d in r["done"] if d) < 6
    assert OK in r["status"] and THROUGH_SINGULAR in r["status"]
    assert r["full_same"]                     # method="full": the second kernel alone


def test_benchmark_runs_on_the_simulator(sim):
    r = sim["bench"]
    assert r["simulated"] and r["points"] == 90
    assert r["max_diff_gen_hand"] <= 1e-12 and r["max_diff_gen_cpu"] <= 1e-12
    assert r["status_mismatches"] == 0 and r["failed"] == 0


def test_python_tier_translates_the_same_file(sim):
    r = sim["python_tier"]
    assert r["tier"] == "python" and r["same"] and r["done"] == [3, 3]


def test_no_cuda_import_until_asked():
    """Importing the backend (or loading and sweeping a module) costs nothing of CUDA."""
    code = ("import sys, mechgen, mechgen.runtime.tables.cuda, mechgen.runtime.tables.cuda_twin; "
            "m = mechgen.load(sys.argv[1]); "
            "assert 'numba.cuda' not in sys.modules, 'numba.cuda imported'")
    out = subprocess.run([sys.executable, "-c", code, os.path.join(ROOT, "generated",
                                                                  "quick_return.py")],
                         env=dict(os.environ, PYTHONPATH=ROOT), capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr[-2000:]


def test_slots(qr):
    from mechgen.runtime.tables.cuda import flat_slots, quantity_slots, slot_names
    n, m = len(qr.coordinates), len(qr.outputs)
    names = ["X4", "X4d", "X4dd", "stroke_x", "stroke_xd", "stroke_xdd"]
    slots = quantity_slots(qr, names, "acceleration")
    assert slots.dtype == np.int64
    assert slots.tolist() == [[0, 6, 0], [0, 6, 1], [0, 6, 2], [1, 0, 0], [1, 0, 1], [1, 0, 2]]
    assert slot_names(qr, slots) == names
    flat, nord = flat_slots(qr, slots, 2)
    assert flat.tolist() == [6, n + 6, 2 * n + 6, 3 * n, 3 * n + m, 3 * n + 2 * m] and nord == 3
    assert flat_slots(qr, slots[:3], 2)[1] == 0          # no outputs: none evaluated
    with pytest.raises(MechgenError, match="level velocity"):
        quantity_slots(qr, ["X4d"], "position")
    with pytest.raises(MechgenError, match="level velocity"):
        flat_slots(qr, slots[1:2], 0)
    with pytest.raises(MechgenError, match=r"row 0 \[0, 99, 0\]"):
        flat_slots(qr, np.array([[0, 99, 0]]), 2)
    with pytest.raises(MechgenError, match="rows"):
        flat_slots(qr, np.array([6]), 2)
    with pytest.raises(KeyError):
        quantity_slots(qr, ["X9"], "position")


def test_no_gpu_is_one_clear_error(qr):
    from numba import cuda
    from numba.core import config
    if config.ENABLE_CUDASIM or cuda.is_available():
        pytest.skip("a GPU (or the simulator) is present")
    from mechgen.runtime.tables.cuda import run_table_cuda
    with pytest.raises(MechgenError, match=r"backend='cuda' needs an NVIDIA GPU.*is_available\(\) is False"):
        run_table_cuda(qr, np.linspace(0, 1, 3), qr.p[None, :], qr.guess, "position",
                       qr.tol, qr.maxit)


def test_translation_refuses_what_it_cannot_express(tmp_path):
    from mechgen.runtime.tables.cuda_twin import TranslationError, translate
    (tmp_path / "cu_bad_mod.py").write_text(textwrap.dedent("""
        import numpy as np
        from numba import njit
        N_COORDS = 2

        @njit
        def helper(q):
            return np.ones(N_COORDS)

        @njit
        def sweep(ts, q0, p, Q):
            for k in range(ts.shape[0]):
                Q[k, 0] = helper(q0)[0]
    """))
    sys.path.insert(0, str(tmp_path))
    try:
        import cu_bad_mod
        with pytest.raises(TranslationError, match=r"np\.ones.*helper\(\)"):
            translate(cu_bad_mod)
    finally:
        sys.path.remove(str(tmp_path))


@pytest.mark.parametrize("name", ["quick_return", "quick_return_slider", "fourbar",
                                  "fourbar_loop"])
def test_every_example_translates(name):
    """The rules cover every function the sweep reaches in each committed module."""
    import importlib.util
    from mechgen.runtime.tables.cuda_twin import translate
    path = os.path.join(ROOT, "generated", name + ".py")
    spec = importlib.util.spec_from_file_location(f"_cu_{name}", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    text = translate(mod)
    for fn in ("sweep", "sweep_fast", "position_sorted", "newton_full", "_fp_solve"):
        assert f"def {fn}(" in text
    assert "np.zeros" not in text and "np.empty" not in text and ".copy()" not in text
    assert "cuda.local.array" in text and "_cu_point(" in text
