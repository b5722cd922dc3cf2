"""numba compiles what a call needs, when it needs it: a process whose large sweep cannot
wait for the background worker compiles (or loads from numba's cache) just the sweep's
functions, and never waits for a worker of another process that holds the module's lock
(mechgen.runtime.loading.tiers); the worker itself runs at the lowest priority on one
core (mechgen.runtime.loading.warmup)."""
from __future__ import annotations

import glob
import json
import os
import shutil
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import mechgen
from conftest import GENERATED, ROOT

SECOND = textwrap.dedent("""
    import json, sys
    import mechgen
    mech = mechgen.load(sys.argv[1], tier="auto")
    sw = mech.sweep(0.0, 1.0, 100000, level="acceleration")
    k = [0, 31234, 99999]
    print(json.dumps({"tier": mech.tier, "t": sw.t[k].tolist(), "q": sw.Q[k].tolist(),
                      "qdd": sw.QDD[k].tolist()}))
    state = getattr(mech, "state", None)      # (the runtime's state, or older: _tiers)
    (state.tiers if state is not None else mech._tiers).stop_worker()
""")


@pytest.fixture
def fresh(tmp_path, monkeypatch):
    """A copy of the four-bar's module and an empty numba cache: (path, environment)."""
    folder = tmp_path / "mod"
    folder.mkdir()
    path = str(folder / "fourbar.py")
    shutil.copy(os.path.join(GENERATED, "fourbar.py"), path)
    cache = str(tmp_path / "nc")
    monkeypatch.setenv("NUMBA_CACHE_DIR", cache)
    env = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPATH=ROOT)
    env.pop("MECHGEN_TIER", None)
    return path, env


def test_second_process_never_waits_for_anothers_worker(fresh):
    """The module's lock held by another process (a worker compiling everything): a
    10^5-point sweep still compiles what it needs and answers, with the plain tier's
    numbers, and writes the sweep's functions to the cache, not the design table's."""
    from mechgen.runtime.loading.tiers import Lock, cache_ready, state_paths
    path, env = fresh
    lock = Lock(state_paths(path)[1])
    assert lock.acquire(wait=False)
    try:
        res = subprocess.run([sys.executable, "-c", SECOND, path], env=env, cwd=ROOT,
                             capture_output=True, text=True, timeout=300)
        assert res.returncode == 0, res.stderr[-2000:]
        assert not cache_ready(path)        # the whole module is the worker's to mark
    finally:
        lock.release()
    got = json.loads(res.stdout.strip().splitlines()[-1])
    assert got["tier"] == "compiled"
    plain = mechgen.load(path, tier="python")
    for t, q, qdd in zip(got["t"], got["q"], got["qdd"]):
        ref = plain.solve(t, level="acceleration")
        assert np.allclose(ref.q, q, rtol=0, atol=1e-9)
        assert np.allclose(ref.qdd, qdd, rtol=1e-8, atol=1e-8)
    cached = {os.path.basename(f).split("-")[0].split(".", 1)[1]
              for f in glob.glob(os.path.join(env["NUMBA_CACHE_DIR"], "**", "*.nbi"),
                                 recursive=True)}
    assert "sweep_fast" in cached
    assert not cached & {"start_designs", "sweep_designs", "_carry", "newton_full"}, cached
    # the sweep's start is one point: solved in Python (mechgen.runtime.loading.mixed)
    assert not cached & {"solve_point_sorted", "unwrap_turns", "pivot_ratio"}, cached


def test_worker_yields_the_machine():
    """The worker's process: nice 19, one core (where the system has several)."""
    code = textwrap.dedent("""
        import os
        from mechgen.runtime.loading.warmup import yield_machine
        before = len(os.sched_getaffinity(0))
        yield_machine()
        print(os.nice(0), before, len(os.sched_getaffinity(0)))
    """)
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                         text=True, env=dict(os.environ, PYTHONPATH=ROOT), check=True)
    nice, before, after = map(int, out.stdout.split())
    assert nice == 19
    assert after == min(before, 1)


SENSITIVITIES = textwrap.dedent("""
    import json, sys
    import numpy as np
    import mechgen
    from mechgen.runtime.loading import tiers
    from mechgen.runtime.sensitivity.companion import companion
    mech = mechgen.compile(sys.argv[1], outdir=sys.argv[2], tier="auto")
    tiers.BIG_CALL = 1e-9                     # any sweep is large now
    names = list(mech.parameter_names)
    sw = mech.sweep(0.0, 1.0, 200, level="acceleration", sensitivities=names)
    sol = mech.solve(0.3, level="acceleration", sensitivities=names)
    comp = companion(mech)[0]
    mech.state.tiers.stop_worker()
    print(json.dumps({"mixed": mech.state.tiers.mixed,
                      "rows": len(comp.sensitivities_rows.signatures),
                      "point": hasattr(comp.sensitivities_at, "signatures"),
                      "sweep": [d.tolist() for d in sw.sensitivities.full],
                      "solution": [d.tolist() for d in sol.sensitivities.full]}))
""")


def test_a_sensitivity_sweep_compiles_its_loop_and_leaves_points_to_python(fresh, tmp_path):
    """The sensitivity module follows the mixed module: its loop over a sweep's points
    compiled, a single solution's derivatives in Python, both as the plain tier's."""
    path, env = fresh
    model = os.path.join(ROOT, "examples", "quick_return.py")
    res = subprocess.run([sys.executable, "-c", SENSITIVITIES, model, str(tmp_path / "gen")],
                         env=env, cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr[-2000:]
    got = json.loads(res.stdout.strip().splitlines()[-1])
    assert got["mixed"] and got["rows"] == 1 and not got["point"]
    plain = mechgen.compile(model, outdir=str(tmp_path / "gen"), tier="python")
    names = list(plain.parameter_names)
    ref_sw = plain.sweep(0.0, 1.0, 200, level="acceleration", sensitivities=names)
    ref = plain.solve(0.3, level="acceleration", sensitivities=names)
    for mine, theirs in zip(got["sweep"], ref_sw.sensitivities.full):
        assert np.array_equal(np.array(mine), theirs, equal_nan=True)
    for mine, theirs in zip(got["solution"], ref.sensitivities.full):
        assert np.array_equal(np.array(mine), theirs)


def test_a_one_point_function_called_in_a_loop_is_compiled_once_it_costs_as_much(fresh):
    """In a mixed module a one-point function stays plain Python until its calls have cost
    the budget, then answers compiled (a caller holding the function too), bit for bit."""
    from mechgen.runtime.loading.loader import import_path
    from mechgen.runtime.loading.mixed import mixed_module, promoting
    from mechgen.runtime.loading.plain import python_module
    path, _ = fresh
    plain, compiled = python_module(path), import_path(path)
    mixed = mixed_module(plain, compiled)
    assert mixed.sweep_fast is compiled.sweep_fast          # a loop: compiled at once
    assert mixed.phi_q is not compiled.phi_q and not compiled.phi_q.signatures
    mixed.phi_q = promoting(mixed, "phi_q", plain.phi_q, compiled.phi_q, after=0.02)
    held = mixed.phi_q
    q = np.array(compiled.GUESS, dtype=float)
    p = np.array(compiled.PARAMETER_DEFAULTS, dtype=float)
    first = np.empty((compiled.N_EQS, compiled.N_COORDS))
    held(q, 0.1, p, first)
    assert not compiled.phi_q.signatures                     # plain still
    J = np.empty_like(first)
    for _ in range(100000):
        held(q, 0.1, p, J)
        if mixed.phi_q is compiled.phi_q:
            break
    assert mixed.phi_q is compiled.phi_q                    # the module's name promoted
    held(q, 0.1, p, J)
    assert compiled.phi_q.signatures                         # and the holder's calls too
    assert np.array_equal(J, first)


TABLE = textwrap.dedent("""
    import json, sys
    import numpy as np
    import mechgen
    from mechgen.runtime.loading import tiers
    mech = mechgen.load(sys.argv[1], tier="auto")
    tiers.BIG_CALL = 1e-9                     # any table is large now
    tab = mech.design_sweep(float(sys.argv[2]), 1.0, 201, {"a": [0.7, 0.8, 0.9]},
                            level="acceleration")
    mech.state.tiers.stop_worker()
    print(json.dumps({"mixed": mech.state.tiers.mixed, "Q": tab.Q.tolist(),
                      "QDD": tab.QDD.tolist(), "ok": bool(np.all(tab.status == 0))}))
""")


def _cached(env):
    return {os.path.basename(f).split("-")[0].split(".", 1)[1]
            for f in glob.glob(os.path.join(env["NUMBA_CACHE_DIR"], "**", "*.nbi"),
                               recursive=True)}


@pytest.mark.parametrize("t0", [0.0, 0.25])
def test_a_table_of_easy_designs_compiles_no_careful_sweep(fresh, t0):
    """A first design table whose designs all take the quick path compiles the quick path
    and the carrying of the guess's mode, not the careful sweep (sweep(), the design loop
    that goes on with it); one starting after the guess's time (t0 0.25) compiles the
    careful position sweep that takes each design there (walk_designs), and nothing
    else more. Its numbers are the plain tier's, bit for bit."""
    from mechgen.runtime.loading.tiers import Lock, state_paths
    path, env = fresh
    lock = Lock(state_paths(path)[1])       # no worker: what is cached is the table's
    assert lock.acquire(wait=False)
    try:
        res = subprocess.run([sys.executable, "-c", TABLE, path, str(t0)], env=env, cwd=ROOT,
                             capture_output=True, text=True, timeout=300)
    finally:
        lock.release()
    assert res.returncode == 0, res.stderr[-2000:]
    got = json.loads(res.stdout.strip().splitlines()[-1])
    assert got["mixed"] and got["ok"]
    cached = _cached(env)
    assert {"sweep_designs_fast", "carry_designs", "sweep_fast"} <= cached, cached
    assert not cached & {"sweep_designs_rest", "sweep_designs", "start_designs"}, cached
    assert ("sweep" in cached) == ("walk_designs" in cached) == (t0 > 0.0), cached
    plain = mechgen.load(path, tier="python")
    ref = plain.design_sweep(t0, 1.0, 201, {"a": [0.7, 0.8, 0.9]}, level="acceleration")
    assert np.array_equal(np.array(got["Q"]), ref.Q)
    assert np.array_equal(np.array(got["QDD"]), ref.QDD)


FORCE_SWEEP = textwrap.dedent("""
    import json, sys
    import mechgen
    from mechgen.runtime.loading import tiers
    mech = mechgen.load(sys.argv[1], tier="auto")
    tiers.BIG_CALL = 1e-9                     # any sweep is large now
    sw = mech.sweep(0.0, 1.0, 201, level=sys.argv[2])
    mech.state.tiers.stop_worker()
    print(json.dumps({"mixed": mech.state.tiers.mixed, "Q": sw.Q.tolist(),
                      "effort": sw.driver("crank driver").tolist()}))
""")


@pytest.mark.parametrize("level, loop", [("dynamic", "sweep_fast_forces"),
                                         ("static", "sweep_fast_statics")])
def test_a_force_sweep_compiles_its_own_quick_path_not_the_kinematic_one(tmp_path,
                                                                         monkeypatch, level,
                                                                         loop):
    """A large force sweep before the cache is ready compiles the quick path that solves
    the multipliers on its way, not the kinematic sweep_fast it does not call; its
    numbers are the plain tier's, bit for bit."""
    from mechgen.runtime.loading.tiers import Lock, state_paths
    folder = tmp_path / "mod"
    folder.mkdir()
    path = str(folder / "quick_return_forces.py")
    shutil.copy(os.path.join(GENERATED, "quick_return_forces.py"), path)
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "nc"))   # (the lock's place)
    env = dict(os.environ, PYTHONPATH=ROOT)
    env.pop("MECHGEN_TIER", None)
    lock = Lock(state_paths(path)[1])       # no worker: what is cached is the sweep's
    assert lock.acquire(wait=False)
    try:
        res = subprocess.run([sys.executable, "-c", FORCE_SWEEP, path, level], env=env,
                             cwd=ROOT, capture_output=True, text=True, timeout=300)
    finally:
        lock.release()
    assert res.returncode == 0, res.stderr[-2000:]
    got = json.loads(res.stdout.strip().splitlines()[-1])
    assert got["mixed"]
    cached = _cached(env)
    assert loop in cached and "sweep_fast" not in cached, " ".join(sorted(cached))
    plain = mechgen.load(path, tier="python")
    ref = plain.sweep(0.0, 1.0, 201, level=level)
    assert np.array_equal(np.array(got["Q"]), ref.Q)
    assert np.array_equal(np.array(got["effort"]), ref.driver("crank driver"))
