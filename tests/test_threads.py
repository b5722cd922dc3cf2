"""Threads sharing one Mechanism each get their own answer.

mech.solve keeps scratch on the mechanism (the info row of the compiled solve, the way
from the guess's two-point arrays, the force rows' arrays). Before the mechanism's lock,
two threads solving on one mechanism could read each other's times there: a solve at one
time returned the configuration of another, with no error (about 1 in 300 solves with a
short switch interval, the slider 9 units off). Each thread's answers are compared with
the same solves made one after another, bit for bit."""
from __future__ import annotations

import os
import sys
import threading

import numpy as np
import pytest

import mechgen

from conftest import GENERATED

TIMES = np.linspace(0.0, 1.0, 100)
LEVELS = ("position", "acceleration", "dynamic", "static")


@pytest.fixture(scope="module")
def mech():
    return mechgen.load(os.path.join(GENERATED, "quick_return_forces.py"), tier="compiled")


@pytest.fixture
def often():
    """The interpreter switches threads as often as it can while the test runs."""
    before = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)
    yield
    sys.setswitchinterval(before)


def _values(s):
    out = [s.q, s.qd, s.qdd, getattr(s, "lam", None)]
    return [a for a in out if a is not None] + [s.iterations, s.singular]


def _same(a, b):
    return len(a) == len(b) and all(np.array_equal(x, y) for x, y in zip(a, b))


def test_threads_sharing_a_mechanism_get_their_own_solves(mech, often):
    want = {lev: [_values(mech.solve(float(t), level=lev)) for t in TIMES] for lev in LEVELS}
    wrong, errors = [], []

    def work(lev, first):
        try:
            for _ in range(2):
                for k in range(first, len(TIMES), 2):
                    got = _values(mech.solve(float(TIMES[k]), level=lev))
                    if not _same(got, want[lev][k]):
                        wrong.append((lev, float(TIMES[k])))
        except Exception as exc:        # (a thread's error would otherwise pass unseen)
            errors.append(exc)

    threads = [threading.Thread(target=work, args=(lev, first))
               for lev in LEVELS for first in (0, 1)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    assert not errors, errors
    assert not wrong, f"{len(wrong)} solves answered another time's configuration: {wrong[:5]}"

