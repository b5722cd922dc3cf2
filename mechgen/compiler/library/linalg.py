"""Small dense linear algebra of the generated solvers: partial- and full-pivoting
elimination, a rank-revealing solve, a determinant, and the sin/cos rotation the
generated block solvers use.

Everything below the marker line goes verbatim into every generated module; the imports
above it stand for what a generated module's header defines (the toy model's values here).
"""
import math

import numpy as np

from .toy import SING_RTOL, TINY, njit

# -- module body: below this line, the text as a generated module holds it --
# ---------------------------------------------------------------------------------------
# Linear algebra
# ---------------------------------------------------------------------------------------
@njit(cache=True)
def _max_abs(v):
    """max |v[i]|, NaN when an entry is NaN (0.0 for an empty v)."""
    s = 0.0
    for i in range(v.shape[0]):
        a = abs(v[i])
        if not a <= s:
            if a != a:  # NaN: return it, a later finite entry must not hide it
                return a
            s = a
    return s


@njit(cache=True)
def _gauss(A, b):
    """Solve the small square system A x = b in place (partial pivoting); x ends in b.
    Returns the number of usable pivots (the size when all went well); a pivot below
    SING_RTOL times the largest entry counts as zero."""
    k = A.shape[0]
    amax = 0.0
    for r in range(k):
        for j in range(k):
            if abs(A[r, j]) > amax:
                amax = abs(A[r, j])
    for c in range(k):
        piv = c
        big = abs(A[c, c])
        for r in range(c + 1, k):
            if abs(A[r, c]) > big:
                big = abs(A[r, c])
                piv = r
        if not (big > TINY and big > SING_RTOL * amax):
            return c
        if piv != c:
            # swap the rows and negate the one moved down: the same solution (negation is
            # exact), and det A stays the product of the pivots (see _diag_product)
            for j in range(k):
                A[c, j], A[piv, j] = A[piv, j], -A[c, j]
            b[c], b[piv] = b[piv], -b[c]
        for r in range(c + 1, k):
            f = A[r, c] / A[c, c]
            for j in range(c, k):
                A[r, j] -= f * A[c, j]
            b[r] -= f * b[c]
    for c in range(k - 1, -1, -1):
        s = b[c]
        for j in range(c + 1, k):
            s -= A[c, j] * b[j]
        b[c] = s / A[c, c]
    return k


@njit(cache=True)
def _diag_product(A):
    """The product of A's diagonal: after _gauss(A, b), the determinant of the A it was
    given (the block's det, whose sign the sweeps watch)."""
    d = 1.0
    for i in range(A.shape[0]):
        d *= A[i, i]
    return d


@njit(cache=True)
def _det(A):
    """Determinant of a small square matrix (overwritten) by partial-pivoting LU."""
    k = A.shape[0]
    d = 1.0
    for c in range(k):
        piv = c
        for r in range(c + 1, k):
            if abs(A[r, c]) > abs(A[piv, c]):
                piv = r
        if A[piv, c] == 0.0:
            return 0.0
        if piv != c:
            d = -d
            for j in range(c, k):
                A[c, j], A[piv, j] = A[piv, j], A[c, j]
        d *= A[c, c]
        for r in range(c + 1, k):
            f = A[r, c] / A[c, c]
            for j in range(c + 1, k):
                A[r, j] -= f * A[c, j]
    return d


@njit(cache=True)
def _fp_eliminate(A, b, cols, rtol):
    """Forward elimination with full pivoting, in place, of the row-equilibrated system
    A x = b (A is m × n): each row of A and its entry of b are first divided by the row's
    largest entry, so that pivots compare with 1 whatever the units of the equations.

    Returns (rank, smallest pivot kept): a pivot not above rtol counts as zero and ends the
    elimination. cols receives the column order; rows beyond the rank are the dropped
    (dependent) equations, whose b entries end as their scaled residuals."""
    m, n = A.shape
    for i in range(m):
        s = 0.0
        for j in range(n):
            a = abs(A[i, j])
            if not a <= s:  # also catches NaN
                s = a
        if not s < np.inf:
            return 0, 0.0
        if s > 0.0:
            for j in range(n):
                A[i, j] /= s
            b[i] /= s
    rank = 0
    small = np.inf
    for k in range(min(m, n)):
        best = 0.0
        pi = k
        pj = k
        for i in range(k, m):
            for j in range(k, n):
                if abs(A[i, j]) > best:
                    best = abs(A[i, j])
                    pi = i
                    pj = j
        if not best > rtol:
            break
        if pi != k:
            for j in range(n):
                A[k, j], A[pi, j] = A[pi, j], A[k, j]
            b[k], b[pi] = b[pi], b[k]
        if pj != k:
            for i in range(m):
                A[i, k], A[i, pj] = A[i, pj], A[i, k]
            cols[k], cols[pj] = cols[pj], cols[k]
        for i in range(k + 1, m):
            f = A[i, k] / A[k, k]
            if f != 0.0:
                for j in range(k, n):
                    A[i, j] -= f * A[k, j]
                b[i] -= f * b[k]
        rank += 1
        small = min(small, best)
    return rank, small


@njit(cache=True)
def _fp_solve(A, b, x, rtol):
    """Solve A x = b (A is m × n; A and b are overwritten) by _fp_eliminate.

    Returns the numeric rank: pivots not above rtol (rows scaled to 1) count as zero.
    Unknowns beyond the rank are set to zero and equations beyond it are dropped
    (redundant rows), so a consistent redundant system still solves; b[rank:] then holds
    the scaled residuals of the dropped equations (zero when they are consistent)."""
    m, n = A.shape
    cols = np.arange(n)
    rank, _small = _fp_eliminate(A, b, cols, rtol)
    y = np.zeros(n)
    for k in range(rank - 1, -1, -1):
        s = b[k]
        for j in range(k + 1, rank):
            s -= A[k, j] * y[j]
        y[k] = s / A[k, k]
    for k in range(n):
        x[cols[k]] = y[k]
    return rank


@njit(cache=True)
def _consistent(b, rank, x):
    """Whether the equations _fp_solve dropped (b[rank:]) hold at its solution x."""
    scale = 1.0 + _max_abs(x)
    for i in range(rank, b.shape[0]):
        if not abs(b[i]) <= SING_RTOL * scale:
            return False
    return True


@njit(cache=True, inline="always")
def _turn(s, c, d, y):
    """sin and cos of y = (the angle whose sin and cos are s, c) − d: a rotation by d (a
    Newton step, or the change since the last point of a sweep) while it is small (series
    to d⁵ and d⁴, error below 1e-20), else new calls."""
    if abs(d) < 1e-3:
        d2 = d * d
        sd = d * (1.0 - d2 * (1.0 / 6.0) * (1.0 - d2 * 0.05))
        cd = 1.0 - d2 * 0.5 * (1.0 - d2 * (1.0 / 12.0))
        return s * cd - c * sd, c * cd + s * sd
    return math.sin(y), math.cos(y)
