"""``synthesis.function``: a four-bar that generates a function, from (input angle, output
angle) pairs, by Freudenstein's equation.

Both angles are measured counter-clockwise from the ground line, input pivot O2 → output
pivot O4 (length d). With the crank pin A = O2 + a e^{i phi} and the output pin
B = O4 + c e^{i psi} (in the ground line's frame), |B − A| = b reads

    K1 cos psi − K2 cos phi + K3 = cos(phi − psi),
    K1 = d / a,  K2 = d / c,  K3 = (a² − b² + c² + d²) / (2 a c),

linear in K: three pairs fix it exactly, more in least squares. A negative K1 (K2) is a crank
(output link) pointing the other way: a = d / K1 < 0 puts the crank pin at |a| e^{i (phi + π)}."""
from __future__ import annotations

import math

import numpy as np

from .defects import coupler_pin, mode
from .dyads import Dyad
from .fourbar import FourBar


def function(pairs, pivots=((0.0, 0.0), (1.0, 0.0))) -> FourBar:
    """The FourBar through (input, output) angle ``pairs`` (radians), its input pivot at
    ``pivots[0]`` and its output pivot at ``pivots[1]``: exact for three pairs, least
    squares for more. Its coupler frame has its origin at the crank pin and its x axis
    towards the output pin (``poses``: that frame at each pair); ``residual`` is the largest
    difference (radians) between the output angle the linkage makes at each pair's input
    angle and the pair's."""
    P = _pairs(pairs)
    O2, O4 = _pivots(pivots)
    d = float(np.linalg.norm(O4 - O2))
    gamma = math.atan2(O4[1] - O2[1], O4[0] - O2[0])
    phi, psi = P[:, 0], P[:, 1]
    M = np.column_stack([np.cos(psi), -np.cos(phi), np.ones(len(P))])
    rhs = np.cos(phi - psi)
    if np.linalg.matrix_rank(M, tol=1e-12 * max(1.0, np.abs(M).max())) < 3:
        raise ValueError("pairs: Freudenstein's equations are singular for these pairs "
                         "(their input or output angles do not tell the link lengths apart)")
    if len(P) == 3:
        K = np.linalg.solve(M, rhs)
    else:
        K, *_ = np.linalg.lstsq(M, rhs, rcond=None)
    K1, K2, K3 = K
    if abs(K1) < 1e-12 or abs(K2) < 1e-12:
        raise ValueError(f"pairs: the solution needs an infinitely long "
                         f"{'crank' if abs(K1) < 1e-12 else 'output link'} (K = {K})")
    a, c = d / K1, d / K2
    b2 = a * a + c * c + d * d - 2 * a * c * K3
    if b2 <= 0:
        raise ValueError(f"pairs: no four-bar meets them (the coupler's length² is {b2:g})")
    b = math.sqrt(b2)
    A = O2 + a * np.column_stack([np.cos(phi + gamma), np.sin(phi + gamma)])
    Bw = O4 + c * np.column_stack([np.cos(psi + gamma), np.sin(psi + gamma)])
    poses, made = [], []
    for j in range(len(P)):
        sigma = mode(A[j], Bw[j], O4) or 1
        B = coupler_pin(A[j], O4, b, abs(c), sigma)
        if B is None:
            raise ValueError(f"pairs: the linkage found does not close at pair {j + 1}")
        poses.append((A[j, 0], A[j, 1], math.atan2(B[1] - A[j, 1], B[0] - A[j, 0])))
        out = math.atan2(*(B - O4)[::-1]) - gamma + (math.pi if c < 0 else 0.0)
        made.append(math.remainder(out - psi[j], 2 * math.pi))
    link = FourBar(Dyad(tuple(O2), (0.0, 0.0)), Dyad(tuple(O4), (b, 0.0)), poses)
    link.pairs = P
    link.residual = float(np.max(np.abs(made)))
    return link


def _pairs(pairs) -> np.ndarray:
    try:
        P = np.array([tuple(p) for p in pairs], dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"pairs: expected (input angle, output angle) pairs, got {pairs!r}") \
            from None
    if P.ndim != 2 or P.shape[1] != 2:
        raise ValueError("pairs: every pair must be two numbers (input angle, output angle)")
    if len(P) < 3:
        raise ValueError(f"pairs: {len(P)} given, at least 3 needed")
    bad = np.argwhere(~np.isfinite(P))
    if bad.size:
        k, w = bad[0]
        raise ValueError(f"pairs: pair {k + 1} has a non-finite "
                         f"{('input', 'output')[w]} angle ({P[k, w]})")
    for i in range(len(P)):
        for j in range(i + 1, len(P)):
            if abs(math.remainder(P[j, 0] - P[i, 0], 2 * math.pi)) < 1e-9:
                raise ValueError(f"pairs: pair {j + 1} repeats the input angle of pair {i + 1} "
                                 f"({P[j, 0]})")
    return P


def _pivots(pivots):
    try:
        O2, O4 = (np.array(p, dtype=float).reshape(2) for p in pivots)
    except (TypeError, ValueError):
        raise ValueError(f"pivots: expected ((x2, y2), (x4, y4)), got {pivots!r}") from None
    if not (np.all(np.isfinite(O2)) and np.all(np.isfinite(O4))):
        raise ValueError("pivots: non-finite coordinates")
    if np.allclose(O2, O4):
        raise ValueError("pivots: the input and output pivots coincide")
    return O2, O4
