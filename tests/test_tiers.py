"""The tiers of a loaded module (mechgen.runtime.loading.tiers): the generated module run as plain
Python answers exactly as numba's compiled code does (values bit for bit, statuses, the
errors raised), the background worker fills numba's cache and the switch to it happens,
two workers on one module are safe, and a model file whose module is built loads
without sympy (mechgen.compile(path))."""
from __future__ import annotations

import math
import os
import shutil
import subprocess
import sys
import textwrap
import warnings

import numpy as np
import pytest

import mechgen
from conftest import EXAMPLES, GENERATED, ROOT

SEEDS = ("quick_return", "quick_return_slider", "fourbar", "fourbar_loop")


def pair(name):
    path = os.path.join(GENERATED, name + ".py")
    return mechgen.load(path, tier="python"), mechgen.load(path, tier="compiled")


@pytest.fixture(scope="module")
def twins():
    return {name: pair(name) for name in SEEDS}


def same(a, b, what=""):
    """Bit for bit, as README and DESIGN.md promise: equal values, NaN where NaN; None alike."""
    if a is None or b is None:
        assert a is None and b is None, what
        return
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape, what
    bad = ~((a == b) | (np.isnan(a) & np.isnan(b)))
    assert not bad.any(), (what, np.argwhere(bad)[:5].tolist(), a[bad][:5], b[bad][:5])


def outcome(fn):
    """(result, None) or (None, the error raised), warnings recorded aside."""
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        try:
            result, error = fn(), None
        except mechgen.MechgenError as exc:
            result, error = None, exc
    return result, error, [(w.category, str(w.message)) for w in rec]


def agree(py, comp, call):
    """call(mech) gives the same answer, warnings and error on both tiers."""
    rp, ep, wp = outcome(lambda: call(py))
    rc, ec, wc = outcome(lambda: call(comp))
    assert wp == wc
    assert type(ep) is type(ec)
    if ec is not None:
        assert str(ep) == str(ec)
        for attr in ("t", "level", "constraints", "iterations", "residual"):
            assert getattr(ep, attr, None) == getattr(ec, attr, None), attr
        same(getattr(ep, "q", None), getattr(ec, "q", None), "error q")
        sp_, sc = getattr(ep, "sweep", None), getattr(ec, "sweep", None)
        if sc is not None:
            compare(sp_, sc)
        return None, None
    compare(rp, rc)
    return rp, rc


def compare(rp, rc):
    if isinstance(rc, mechgen.Solution):
        for x in ("q", "qd", "qdd"):
            same(getattr(rp, x), getattr(rc, x), x)
        assert (rp.iterations, rp.singular, rp.method) == (rc.iterations, rc.singular, rc.method)
        same(rp.residual, rc.residual)
    elif isinstance(rc, mechgen.Sweep):
        same(rp.t, rc.t)
        for x in ("Q", "QD", "QDD"):
            same(getattr(rp, x), getattr(rc, x), x)
        same(rp.info, rc.info, "info (statuses, iterations, methods)")
        same(rp.jumps, rc.jumps)
        same(rp.crossings, rc.crossings)
    elif type(rc).__name__ == "DesignTable":
        for x in ("t", "P", "Q", "QD", "QDD", "INFO", "done"):
            same(getattr(rp, x), getattr(rc, x), x)
    elif isinstance(rc, str):
        assert rp == rc
    elif isinstance(rc, (list, tuple)):
        assert len(rp) == len(rc)
        for a, b in zip(rp, rc):
            compare(a, b)
    else:
        same(rp, rc)


def test_the_python_tier_runs_without_numba_or_sympy():
    code = textwrap.dedent(f"""
        import sys, mechgen
        m = mechgen.load({os.path.join(GENERATED, "quick_return.py")!r}, tier="python")
        s = m.solve(0.15, level="acceleration")
        sw = m.sweep(0, 1, 21, level="acceleration")
        assert m.tier == "python" and len(sw) == 21 and s.residual < 1e-10
        print(sorted(x for x in ("numba", "sympy", "scipy") if x in sys.modules))
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env=dict(os.environ, PYTHONPATH=ROOT), check=True)
    assert out.stdout.strip() == "[]"


@pytest.mark.parametrize("name", SEEDS)
def test_tiers_agree_on_the_seeds(twins, name):
    py, comp = twins[name]
    assert (py.tier, comp.tier) == ("python", "compiled")
    level = mechgen.protocol.LEVELS[comp.built_level]
    for t in (0.0, 0.15, 0.37, 0.85):
        for method in ("auto", "full"):
            s, _ = agree(py, comp, lambda m: m.solve(t, level=level, method=method))
            if s is not None:
                agree(py, comp, lambda m: m.points_at(s.q, t))
                agree(py, comp, lambda m: m.output_values(s.q, s.qd, s.qdd, t))
                agree(py, comp, lambda m: m.jacobian(s.q, t))
                agree(py, comp, lambda m: m.pivot_ratio(s.q, t))
    for lev in ("position", level):
        for method in ("auto", "full"):
            agree(py, comp, lambda m: m.sweep(0.0, 1.0, 41, level=lev, method=method))
    agree(py, comp, lambda m: m.assemblies(0.3, starts=8))
    name, value = comp.parameter_names[0], float(comp.p[0])
    agree(py, comp, lambda m: m.design_sweep(0.0, 1.0, 11, {name: [value, 1.1 * value]},
                                             level=level, on_fail="ignore"))


# -- the hard cases of tests/test_robustness.py ----------------------------------------------
C, A = 4.13931, 5.40447
XMAX = 5.4 + math.sqrt(17.16)
T1 = math.asin((XMAX - C) / A) / (2 * math.pi)
NEAR_T1 = {"Th2": -0.64, "Th3": -0.64, "X4": 9.54}


@pytest.mark.parametrize("method", ["auto", "sorted", "full"])
def test_tiers_agree_at_a_toggle(twins, method):
    py, comp = twins["quick_return_slider"]
    for level in ("position", "velocity", "acceleration"):
        agree(py, comp, lambda m: m.solve(T1, guess=NEAR_T1, method=method, level=level))
        agree(py, comp, lambda m: m.solve(T1 - 1e-6, guess=NEAR_T1, method=method, level=level))
    for t in (0.3, 0.5):          # no configuration there
        agree(py, comp, lambda m: m.solve(t, guess=NEAR_T1, method=method))


def test_tiers_agree_on_sweeps_into_a_lock(twins):
    py, comp = twins["quick_return_slider"]
    agree(py, comp, lambda m: m.sweep(0.0, 1.0, 101))                 # stops at the lock
    for level in ("position", "velocity", "acceleration"):
        agree(py, comp, lambda m: m.sweep(0.0, T1, 11, level=level))  # onto the toggle
        agree(py, comp, lambda m: m.sweep(None, None, None, times=[0.245, 0.255],
                                          guess=NEAR_T1, level=level))
    agree(py, comp, lambda m: m.singularities(0.0, 1.0, n=51))


def test_tiers_agree_where_a_fourbar_cannot_assemble(twins):
    py, comp = twins["fourbar"]
    names = py.parameter_names
    params = {"a": 3.0, "b": 0.5, "c": 0.5, "d": 1.0}
    params = {k: v for k, v in params.items() if k in names}
    assert params, names
    pyb, compb = py.with_params(**params), comp.with_params(**params)
    assert pyb.tier == "python" and compb.tier == "compiled"
    for guess in (None, np.linspace(-2, 2, py.n)):
        for method in ("auto", "full"):
            agree(pyb, compb, lambda m: m.solve(0.0, guess=guess, method=method))
    agree(pyb, compb, lambda m: m.sweep(0.0, 1.0, 5))


@pytest.fixture(scope="module")
def redundant(tmp_path_factory):
    from mechgen.compiler.build import build
    from mechgen.model.loader import load_models
    from test_robustness import PARALLELOGRAM
    d = tmp_path_factory.mktemp("redundant_tiers")
    src = d / "parallelogram_extra.py"
    src.write_text(PARALLELOGRAM)
    path = build(load_models(str(src))[0], str(d / "gen"))
    return mechgen.load(path, tier="python"), mechgen.load(path, tier="compiled")


def test_tiers_agree_on_redundant_constraints(redundant):
    py, comp = redundant
    agree(py, comp, lambda m: m.solve(0.0, level="acceleration"))    # the warning once each
    agree(py, comp, lambda m: m.with_params(e=1.3).solve(0.0))       # they disagree
    agree(py, comp, lambda m: m.rank_loss(m.solve(0.0).q, 0.0))


def test_plain_math_answers_as_numba_does():
    from mechgen.runtime.loading.plain import MATH
    assert math.isnan(MATH.sqrt(-1.0)) and math.isnan(MATH.sin(math.inf))
    assert math.isnan(MATH.acos(2.0)) and math.isnan(MATH.log(-1.0))
    assert MATH.exp(1e6) == math.inf and MATH.log(0.0) == -math.inf
    assert MATH.sqrt(4.0) == 2.0 and MATH.floor(2.5) == 2 and math.isnan(MATH.floor(math.nan))


def test_tier_knob():
    path = os.path.join(GENERATED, "fourbar_loop.py")
    with pytest.raises(ValueError, match="tier must be one of"):
        mechgen.load(path, tier="fast")
    from mechgen.runtime.loading.loader import import_path
    assert mechgen.load(import_path(path)).tier == "compiled"   # an imported module
    assert mechgen.load(path, tier="python").tier == "python"


# -- the background worker and the switch ----------------------------------------------------
def _run(code, env, timeout=300):
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True,
                          text=True, env=env, timeout=timeout)


@pytest.fixture
def fresh(tmp_path):
    """A copy of the four-bar loop's module and an empty numba cache."""
    path = tmp_path / "fourbar_loop.py"
    shutil.copy(os.path.join(GENERATED, "fourbar_loop.py"), path)
    env = dict(os.environ, PYTHONPATH=ROOT, NUMBA_CACHE_DIR=str(tmp_path / "nc"),
               MECHGEN_TIER="auto")
    return str(path), env


def test_two_workers_then_the_switch(fresh):
    path, env = fresh
    cmd = [sys.executable, "-m", "mechgen.runtime.loading.warmup", path, "position"]
    workers = [subprocess.Popen(cmd, env=env, stderr=subprocess.PIPE, text=True) for _ in range(2)]
    for w in workers:
        _, err = w.communicate(timeout=300)
        assert w.returncode == 0, err
    code = f"""
        import os, sys
        import numpy as np
        from mechgen.runtime.loading.tiers import cache_ready
        import mechgen
        assert cache_ready({path!r})
        m = mechgen.load({path!r})                  # auto: the cache is ready, no worker
        assert m.tier == "python" and m.state.tiers.worker is None
        first = m.solve(0.1)
        while m.tier == "python":                   # its calls cost SWITCH_AFTER seconds
            m.solve(0.1)
        again = m.solve(0.1)
        assert np.array_equal(again.q, first.q)      # compiled now: bit for bit the Python tier's
        # a solve calls solve_point_sorted (solve_point_full where it gives up)
        names = ("solve_point_sorted", "solve_point_full", "solve_point")
        stats = [getattr(m.module, k).stats for k in names if hasattr(m.module, k)]
        print(sum(sum(s.cache_hits.values()) for s in stats),
              sum(sum(s.cache_misses.values()) for s in stats))
    """
    out = _run(code, env)
    assert out.returncode == 0, out.stderr
    hits, misses = out.stdout.split()
    assert int(misses) == 0 and int(hits) >= 1       # loaded from the worker's cache


def test_a_large_call_compiles_what_it_needs(fresh):
    path, env = fresh
    code = f"""
        import numpy as np
        import mechgen
        from mechgen.runtime.loading import tiers
        m = mechgen.load({path!r})
        assert m.tier == "python" and m.state.tiers.worker is not None
        small = m.sweep(0, 1, 50, level="acceleration")
        tiers.BIG_CALL = 1e-9                        # any sweep is large now
        big = m.sweep(0, 1, 50, level="acceleration")
        assert m.tier == "compiled"
        for x in ("Q", "QD", "QDD", "info"):       # bit for bit, the tiers' promise
            assert np.array_equal(getattr(big, x), getattr(small, x), equal_nan=True), x
        assert not tiers.cache_ready({path!r})      # the worker was stopped before the end
        state = m.state.tiers
        assert state.worker is not None          # and started again for the rest
        # the loop compiled here, the one-point solves left to Python until the cache is
        # ready: the mixed module (mechgen.runtime.loading.mixed)
        assert state.mixed and m.module.sweep_fast.signatures
        assert not hasattr(m.module.solve_point_sorted, "signatures")
        point = m.solve(0.3, level="acceleration")
        state.worker.wait(timeout=280)              # the worker fills the cache ...
        assert tiers.cache_ready({path!r})
        import time
        end = time.monotonic() + 60
        while state.mixed and time.monotonic() < end:   # ... and after SWITCH_AFTER
            m.solve(0.3, level="acceleration")      # seconds of plain calls, the whole
        assert not state.mixed                      # module
        again = m.solve(0.3, level="acceleration")  # compiled (loaded from the cache)
        assert m.module.solve_point_sorted.signatures
        for x in ("q", "qd", "qdd"):
            assert np.array_equal(getattr(again, x), getattr(point, x)), x
        state.stop_worker()
        print("ok")
    """
    out = _run(code, env)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "ok"


# -- a model file loads without sympy when its module is built -------------------------------
def test_a_built_model_file_loads_without_sympy(tmp_path):
    src = tmp_path / "quick_return.py"
    shutil.copy(os.path.join(EXAMPLES, "quick_return.py"), src)
    out_dir = str(tmp_path / "gen")
    first = mechgen.compile(str(src), outdir=out_dir, tier="python")
    assert first.model is not None
    code = f"""
        import sys, mechgen
        m = mechgen.compile({str(src)!r}, outdir={out_dir!r}, tier="python")
        s = m.solve(0.15, level="acceleration")
        print(s.q[6], "sympy" in sys.modules, "numba" in sys.modules)
        x4 = m.evaluate(mechgen.Symbol("X4") * 2, s)          # the symbolic side, on demand
        print(x4 == 2 * s.q[6], "sympy" in sys.modules, m.model is not None)
    """
    out = _run(code, dict(os.environ, PYTHONPATH=ROOT))
    assert out.returncode == 0, out.stderr
    line1, line2 = out.stdout.splitlines()
    x4, had_sympy, had_numba = line1.split()
    assert float(x4) == first.solve(0.15)["X4"]        # repr round-trips: the same answer
    assert (had_sympy, had_numba) == ("False", "False")
    assert line2.split() == ["True", "True", "True"]
    # an edit builds again (and the new module answers the new model)
    src.write_text(src.read_text().replace('m.param("longitud", 3.0)', 'm.param("longitud", 2.5)'))
    edited = mechgen.compile(str(src), outdir=out_dir, tier="python")
    assert edited.parameters["longitud"] == 2.5


def test_a_module_from_before_the_tiers_loads_compiled(tmp_path):
    """A module whose header has no plain-Python indirection (an older build) loads with
    numba in "auto"; asking for the python tier says to rebuild."""
    import re
    from mechgen.protocol import STAMP, content_digest
    text = open(os.path.join(GENERATED, "fourbar_loop.py"), encoding="utf-8").read()
    start, end = text.index("try:\n"), text.index("MODEL_NAME = ")
    text = text[:start] + "from numba import njit\n\n" + text[end:]
    body = re.sub(r"^# content-sha256: \w+\n", "", text)
    old = tmp_path / "fourbar_loop.py"
    old.write_text(STAMP.format(digest=content_digest(body)) + body)
    assert mechgen.load(str(old), tier="auto").tier == "compiled"
    with pytest.raises(mechgen.MechgenError, match="before the plain-Python tier"):
        mechgen.load(str(old), tier="python")
