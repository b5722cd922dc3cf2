"""The plain-Python tier's whole-row elimination (runtime/loading/plain_linalg.py) against the
library's own loop run as Python: bit for bit, on full, rank-deficient, tied, wide, tall,
NaN and infinite systems."""
import numpy as np
import pytest

from mechgen.compiler.library.linalg import _fp_eliminate
from mechgen.runtime.loading.plain_linalg import fp_eliminate

loop = getattr(_fp_eliminate, "py_func", _fp_eliminate)


def systems():
    rng = np.random.default_rng(7)
    yield rng.normal(size=(9, 9)), 0.0
    yield rng.normal(size=(6, 9)), 1e-12                  # wide
    yield rng.normal(size=(9, 5)), 1e-12                  # tall
    a = rng.normal(size=(8, 3))
    yield a @ rng.normal(size=(3, 8)), 1e-10              # rank 3
    yield rng.integers(-2, 3, size=(10, 10)).astype(float), 0.0   # ties everywhere
    yield np.zeros((4, 4)), 0.0
    a = rng.normal(size=(7, 7))
    a[2, 3] = np.nan
    yield a, 0.0
    a = rng.normal(size=(7, 7))
    a[:, 4] = np.nan
    yield a, 0.0
    a = rng.normal(size=(5, 5))
    a[1, 1] = np.inf
    yield a, 0.0
    yield rng.normal(size=(60, 60)) * 10.0 ** rng.integers(-6, 6, size=(60, 1)), 1e-13


@pytest.mark.parametrize("k", range(10))
def test_whole_rows_give_the_loop_s_bits(k):
    A, rtol = list(systems())[k]
    b = np.arange(A.shape[0], dtype=float) - 1.5
    A1, b1, c1 = A.copy(), b.copy(), np.arange(A.shape[1])
    A2, b2, c2 = A.copy(), b.copy(), np.arange(A.shape[1])
    r1 = loop(A1, b1, c1, rtol)
    r2 = fp_eliminate(A2, b2, c2, rtol)
    assert r1[0] == r2[0]
    assert r1[1] == r2[1] or (np.isnan(r1[1]) and np.isnan(r2[1]))
    assert np.array_equal(A1, A2, equal_nan=True)
    assert np.array_equal(b1, b2, equal_nan=True)
    assert np.array_equal(c1, c2)


def test_the_python_tier_uses_it(monkeypatch, qr):
    """The plain-Python module calls the whole-row form, and its pivot ratio is the
    compiled module's."""
    import os
    from mechgen.runtime.loading import plain_linalg
    from mechgen.runtime.loading.plain import python_module
    from conftest import GENERATED
    calls = []

    def spy(*args):
        calls.append(args[0].shape)
        return fp_eliminate(*args)

    monkeypatch.setitem(plain_linalg.REPLACEMENTS, "_fp_eliminate", spy)
    mod = python_module(os.path.join(GENERATED, "quick_return.py"))
    s = qr.solve(0.15)
    ratio = mod.pivot_ratio(s.q.copy(), 0.15, qr.p.copy())
    assert calls and calls[0] == (9, 9)
    assert ratio == qr.pivot_ratio(s.q, 0.15)
