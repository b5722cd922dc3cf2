"""Whole-row numpy forms of the generated module's O(n³) library loops, for the plain-Python
tier (runtime/loading/plain.py puts them in place of the module's own).

Interpreted, the library's elimination with full pivoting (``_fp_eliminate``) costs a
Python bytecode loop per multiply: 9 s for the 450 × 450 Jacobian of a chain of 50
four-bar loops, where numba takes milliseconds. The forms here do the same arithmetic on
whole rows: every element gets the same operations in the same order (a division, a
product, a subtraction), the pivot is the same element (the first largest in row-major
order, NaN never chosen), so that the results are bit for bit those of the loop
(tests/test_plain_linalg.py checks them against the library's own Python).
"""
from __future__ import annotations

import numpy as np


def _row_scale(row) -> float:
    """The library's row scale: the largest |entry|, its loop kept where a NaN is (a NaN
    resets it there, as `not a <= s` does)."""
    if not np.isnan(row).any():
        return float(np.abs(row).max()) if row.shape[0] else 0.0
    s = 0.0
    for a in np.abs(row):
        if not a <= s:
            s = a
    return s


def fp_eliminate(A, b, cols, rtol):
    """``_fp_eliminate`` (compiler/library/linalg.py) on whole rows: forward elimination
    with full pivoting, in place, of the row-equilibrated system A x = b. Returns
    (rank, smallest pivot kept)."""
    m, n = A.shape
    for i in range(m):
        s = _row_scale(A[i])
        if not s < np.inf:
            return 0, 0.0
        if s > 0.0:
            A[i] /= s
            b[i] /= s
    rank = 0
    small = np.inf
    for k in range(min(m, n)):
        sub = np.abs(A[k:, k:])
        if np.isnan(sub).any():
            sub = np.where(np.isnan(sub), -1.0, sub)
        at = int(np.argmax(sub))
        best = float(sub.flat[at])
        pi, pj = k, k
        if best > 0.0:
            pi, pj = k + at // (n - k), k + at % (n - k)
        else:
            best = 0.0
        if not best > rtol:
            break
        if pi != k:
            A[[k, pi]] = A[[pi, k]]
            b[k], b[pi] = b[pi], b[k]
        if pj != k:
            A[:, [k, pj]] = A[:, [pj, k]]
            cols[k], cols[pj] = cols[pj], cols[k]
        f = A[k + 1:, k] / A[k, k]
        rows = np.nonzero(f != 0.0)[0]
        if rows.shape[0]:
            f = f[rows]
            rows = rows + (k + 1)
            A[rows, k:] -= np.outer(f, A[k, k:])
            b[rows] -= f * b[k]
        rank += 1
        small = min(small, best)
    return rank, small


# the module's own name of each function -> its whole-row form
REPLACEMENTS = {"_fp_eliminate": fp_eliminate}
