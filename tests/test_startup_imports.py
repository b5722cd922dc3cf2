"""A fresh process's first answer waits only for what it needs (issue 24): the runtime's
import leaves design tables, the force solvers, stages, events, locks and
importlib.metadata (and sympy, always) for later; numba's version read without
importlib.metadata is the version importlib.metadata reads."""
import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LATER = ("mechgen.runtime.tables.design", "mechgen.runtime.tables.backends", "mechgen.runtime.forces.solution",
         "mechgen.runtime.forces.sweep", "mechgen.runtime.kinematics.stages", "mechgen.runtime.analysis.events",
         "mechgen.runtime.analysis.locks", "mechgen.runtime.analysis.assembly", "importlib.metadata", "sympy",
         "numba", "scipy")


def test_the_runtime_imports_only_what_a_first_solve_needs(tmp_path):
    code = ("import sys, mechgen.bridge, mechgen.runtime.mechanism\n"
            "from mechgen.runtime.loading.tiers import cache_ready, numba_version\n"
            "numba_version()\n"
            f"print(' '.join(m for m in {LATER!r} if m in sys.modules))")
    env = dict(os.environ, PYTHONPATH=ROOT, MECHGEN_CACHE=str(tmp_path))
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         check=True)
    assert out.stdout.split() == []


def test_the_lazy_names_are_the_same_objects():
    from mechgen.runtime import forces
    from mechgen.runtime.forces import solution, sweep
    assert forces.force_solve is solution.force_solve
    assert forces.ForceSweep is sweep.ForceSweep
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        forces.nothing  # noqa: B018


def test_numba_version_matches_importlib_metadata():
    pytest.importorskip("numba")
    from importlib.metadata import version
    from mechgen.runtime.loading.tiers import _version_beside, numba_version
    import importlib.util
    assert numba_version() == version("numba")
    assert _version_beside(importlib.util.find_spec("numba").origin) == version("numba")
    assert _version_beside(None) == ""
