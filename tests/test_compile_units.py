"""Compile units (issue 12): a solve calls the generated module one small compiled function
at a time (mechgen.runtime.kinematics.entry), so that a position solve compiles neither the full
Newton nor the derivative passes; the numbers and statuses are those of the library's
all-in-one entries (solve_point, solve_point_derivatives) for every method."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import GENERATED, ROOT
from mechgen.protocol import METHOD, POINT_INFO_SIZE
from mechgen.runtime.kinematics import entry

QR = os.path.join(GENERATED, "quick_return.py")


def _both(mod, q0, t, p, meth, level, tol=1e-10, maxit=50):
    """(status, q, qd, qdd, info) by the library entry and by mechgen.runtime.kinematics.entry."""
    out = []
    for how in ("library", "entry"):
        q = np.array(q0, dtype=float)
        qd, qdd, info = np.full(len(q), 7.0), np.full(len(q), 7.0), np.zeros(POINT_INFO_SIZE)
        args = (q, t, p, tol, 1e-12, maxit, meth, level, qd, qdd, info)
        status = (mod.solve_point_derivatives(*args) if how == "library"
                  else entry.solve_point_derivatives(mod, *args))
        out.append((status, q, qd, qdd, info))
    return out


@pytest.mark.parametrize("method", ["auto", "sorted", "full"])
def test_entry_points_give_the_library_numbers(qr, method):
    mod, meth = qr.module, METHOD[method]
    starts = [qr.guess, qr.guess + 0.3, qr.guess + np.array([0, 0, 0, 0, 0, 0, 40, 0, 0])]
    for q0 in starts:
        for t in (0.0, 0.15, 0.37):
            for level in (0, 1, 2):
                (s1, *a1), (s2, *a2) = _both(mod, q0, t, qr.p, meth, level)
                assert s1 == s2, (method, t, level)
                for x, y in zip(a1, a2):
                    assert np.array_equal(x, y, equal_nan=True), (method, t, level)


def test_a_failed_sorted_solve_falls_back_as_the_library_does(qr):
    """maxit=1: the sorted Newton gives up, auto goes on with the full Newton (method
    column 1), sorted reports the failure; both as the library's entry."""
    mod = qr.module
    for meth in (METHOD["auto"], METHOD["sorted"]):
        (s1, *a1), (s2, *a2) = _both(mod, qr.guess + 0.2, 0.2, qr.p, meth, 2, maxit=1)
        assert s1 == s2
        for x, y in zip(a1, a2):
            assert np.array_equal(x, y, equal_nan=True)


SCRIPT = r"""
import json, sys
import mechgen
mech = mechgen.load(sys.argv[1])
mod = mech.module
guess = dict(zip(mech.coordinates, mech.guess.copy()))   # Newton from it (no following)
mech.solve(0.15, guess=guess)
after_position = {name: len(getattr(mod, name).signatures) for name in
                  ("solve_point_sorted", "newton_full", "velocity_sorted", "acceleration_sorted",
                   "solve_point", "solve_point_derivatives", "sweep_fast")}
mech.solve(0.15, guess=guess, level="acceleration")
after_acceleration = {name: len(getattr(mod, name).signatures) for name in
                      ("newton_full", "velocity_full", "acceleration_full",
                       "solve_derivatives_sorted", "solve_point_derivatives")}
print(json.dumps([after_position, after_acceleration]))
"""


def test_a_position_solve_compiles_only_the_position_path(tmp_path):
    """In a fresh process with an empty numba cache: after solve(t, guess=), the full Newton, the
    derivative passes and the sweep have no compiled version; after an acceleration solve
    the sorted passes (in one call) have one and the full fallbacks still none."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "numba"),
               PYTHONPATH=ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    out = subprocess.run([sys.executable, "-c", SCRIPT, QR], capture_output=True, text=True,
                         env=env, timeout=300)
    assert out.returncode == 0, out.stderr
    pos, acc = json.loads(out.stdout.strip().splitlines()[-1])
    assert pos == {"solve_point_sorted": 1, "newton_full": 0, "velocity_sorted": 0,
                   "acceleration_sorted": 0, "solve_point": 0, "solve_point_derivatives": 0,
                   "sweep_fast": 0}
    assert acc == {"newton_full": 0, "velocity_full": 0, "acceleration_full": 0,
                   "solve_derivatives_sorted": 1, "solve_point_derivatives": 0}


class _Fake:
    """A module whose sorted passes give up where told: records the calls it gets."""
    SORTED, LEVEL = True, 2

    def __init__(self, fails):
        self.fails, self.calls = fails, []

    def _call(self, name, status=0):
        self.calls.append(name)
        return status

    def solve_point_sorted(self, q, t, p, tol, xtol, maxit, info):
        info[:6] = [1, 0.0, len(q), 0, 0.0, 1.0]
        return self._call("solve_point_sorted")

    def solve_derivatives_sorted(self, q, t, p, qd, qdd):
        from mechgen.protocol import ACCELERATION, SINGULAR, VELOCITY
        code = {"velocity": VELOCITY + SINGULAR, "acceleration": ACCELERATION + SINGULAR}
        return self._call("solve_derivatives_sorted", code.get(self.fails, 0))

    def acceleration_sorted(self, q, qd, t, p, out):
        return self._call("acceleration_sorted")

    def velocity_full(self, q, t, p, out):
        return self._call("velocity_full")

    def acceleration_full(self, q, qd, t, p, out):
        return self._call("acceleration_full")


@pytest.mark.parametrize("fails,method,calls,status", [
    (None, "auto", ["solve_point_sorted", "solve_derivatives_sorted"], 0),
    ("velocity", "auto", ["solve_point_sorted", "solve_derivatives_sorted", "velocity_full",
                          "acceleration_sorted"], 0),
    ("acceleration", "auto", ["solve_point_sorted", "solve_derivatives_sorted",
                              "acceleration_full"], 0),
    ("velocity", "sorted", ["solve_point_sorted", "solve_derivatives_sorted"], 12),
    ("acceleration", "sorted", ["solve_point_sorted", "solve_derivatives_sorted"], 22),
])
def test_a_sorted_pass_that_gives_up_falls_back_level_by_level(fails, method, calls, status):
    """As the library's solve_velocity and solve_acceleration: the full solve of the level
    that gave up (method auto), the sorted pass of the next level again; with method
    sorted the status of the pass that gave up."""
    from mechgen.protocol import ACCELERATION, SINGULAR, VELOCITY
    assert (VELOCITY + SINGULAR, ACCELERATION + SINGULAR) == (12, 22)
    mod = _Fake(fails)
    q, info = np.zeros(3), np.zeros(POINT_INFO_SIZE)
    got = entry.solve_point_derivatives(mod, q, 0.0, np.zeros(0), 1e-10, 1e-12, 50,
                                        METHOD[method], 2, np.zeros(3), np.zeros(3), info)
    assert (mod.calls, got) == (calls, status)
