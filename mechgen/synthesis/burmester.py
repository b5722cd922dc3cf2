"""Five poses: every real Burmester pair (centre point, circle point) exactly.

In complex numbers, with the pose j placing body point w at d_j + e_j w (e_j = exp(i th_j)),
the fixed pivot z and the radius R, the five equations |d_j + e_j w − z|² = R² read

    |d_j|² + conj(d_j) e_j w + d_j conj(e_j) w̄ − conj(d_j) z − d_j z̄ + K
        − e_j m1 − conj(e_j) m2 = 0

with w̄, z̄ taken as unknowns of their own, K = w w̄ + z z̄ − R², m1 = w z̄ and m2 = w̄ z. They
are linear in (w, w̄, z, z̄, K) once m1 and m2 are given: solved, x = x0 + m1 x1 + m2 x2, and
what is left is two conics, m1 = w z̄ and m2 = w̄ z, in (m1, m2). Their intersection (the
resultant of the two, a quartic in m1) holds the four Burmester pairs, complex ones included:
nothing is searched, nothing is missed. The real ones (w̄ = conj(w), z̄ = conj(z)) are
polished by Newton on the real equations and kept only where the five poses' equal-distance
equations hold to ``CHECK`` (relative to the poses' spread)."""
from __future__ import annotations

import numpy as np
from numpy.polynomial import Polynomial

from .poses import Frame, circle_residual, row_pencil

CHECK = 1e-10           # the equal-distance residual a pair must reach (relative)
REAL = 1e-5             # |w̄ − conj(w)| (relative) below which a root is taken as real
FAR = 1e7               # a pivot farther than this (relative) is at infinity: a slider
# moving-frame and ground shifts tried when the linear system is ill conditioned
_SHIFTS = ((0, 0), (0.37 + 0.21j, 0), (0, -0.29 + 0.43j), (-0.53 + 0.11j, 0.17 - 0.61j))


def five_poses(poses):
    """Every real Burmester pair of five poses: a list of (fixed (2,), moving (2,)) in the
    caller's units, sorted by the fixed pivot's x, each meeting the equal-distance
    equations to CHECK."""
    poses = np.asarray(poses, dtype=float)
    frame = Frame(poses)
    normal = frame.to(poses)
    found = []
    for w, z in _complex_pairs(normal):
        fixed, moving, ok = _polish(normal, np.array([z.real, z.imag]),
                                    np.array([w.real, w.imag]))
        if ok and not any(np.allclose(fixed, f, atol=1e-8) and np.allclose(moving, m, atol=1e-8)
                          for f, m in found):
            found.append((fixed, moving))
    found.sort(key=lambda fm: (fm[0][0], fm[0][1]))
    return [(frame.fixed_back(f), frame.moving_back(m)) for f, m in found]


def _complex_pairs(normal):
    """The candidate (w, z), real to REAL, from the quartic (poses in the Frame's units)."""
    d = normal[:, 0] + 1j * normal[:, 1]
    e = np.exp(1j * normal[:, 2])
    best = None
    for s, t in _SHIFTS:
        ds = d + e * s - t              # body origin moved to s, ground origin to t
        M = np.column_stack([np.conj(ds) * e, ds * np.conj(e), -np.conj(ds), -ds,
                             np.ones(5)])
        cond = np.linalg.cond(M)
        if best is None or cond < best[0]:
            best = (cond, s, t, M, ds)
        if cond < 1e8:
            break
    cond, s, t, M, ds = best
    if not np.isfinite(cond) or cond > 1e14:
        return []
    x0, x1, x2 = np.linalg.solve(M, np.column_stack([-np.abs(ds) ** 2, e, np.conj(e)])).T
    # Q1 = (x[0])(x[3]) − m1, Q2 = (x[1])(x[2]) − m2, each A m2² + B m2 + C in polynomials of m1
    quad = []
    for a, b, own in ((0, 3, 1), (1, 2, 2)):
        p = Polynomial([x0[a], x1[a]])
        r = Polynomial([x0[b], x1[b]])
        q, s_ = x2[a], x2[b]
        A = Polynomial([q * s_])
        B = p * s_ + r * q
        C = p * r
        if own == 1:
            C = C - Polynomial([0, 1])
        else:
            B = B - Polynomial([1])
        quad.append((A, B, C))
    (A1, B1, C1), (A2, B2, C2) = quad
    res = (A1 * C2 - A2 * C1) ** 2 - (A1 * B2 - A2 * B1) * (B1 * C2 - B2 * C1)
    coef = res.coef
    big = np.max(np.abs(coef)) if coef.size else 0.0
    if big == 0:
        return []
    keep = np.nonzero(np.abs(coef) > 1e-13 * big)[0]
    coef = coef[:keep[-1] + 1]
    if coef.size < 2:
        return []
    out = []
    for m1 in np.roots(coef[::-1]):
        m2 = _common_root(m1, quad)
        x = x0 + m1 * x1 + m2 * x2
        w, wb, z, zb = x[0], x[1], x[2], x[3]
        size = 1 + abs(w) + abs(z)
        if abs(wb - np.conj(w)) > REAL * size or abs(zb - np.conj(z)) > REAL * size:
            continue
        if size > FAR:
            continue
        out.append(((w + np.conj(wb)) / 2 + s, (z + np.conj(zb)) / 2 + t))
    return out


def _common_root(m1, quad):
    """The m2 that both quadratics share at m1 (the one that best meets the other)."""
    vals = [(A(m1), B(m1), C(m1)) for A, B, C in quad]
    cands = []
    for k, (a, b, c) in enumerate(vals):
        if abs(a) > 1e-14 * (abs(b) + abs(c)):
            cands += list(np.roots([a, b, c]))
        elif abs(b) > 0:
            cands.append(-c / b)
    (a1, b1, c1), (a2, b2, c2) = vals
    den = a2 * b1 - a1 * b2
    if den != 0:
        cands.append((a1 * c2 - a2 * c1) / den)
    if not cands:
        return 0.0

    def miss(m2):
        return sum(abs(a * m2 * m2 + b * m2 + c) / (abs(a * m2 * m2) + abs(b * m2) + abs(c)
                                                    + 1e-300) for a, b, c in vals)
    return min(cands, key=miss)


def _polish(normal, G, u, steps=12):
    """Newton on the four real equal-distance equations in (G, u); (G, u, converged)."""
    pencil = row_pencil(normal)             # (4, 3, 3): rows a + gx b + gy c
    x = np.concatenate([G, u])
    for _ in range(steps):
        f, J = _system(pencil, x)
        try:
            dx = np.linalg.solve(J, -f)
        except np.linalg.LinAlgError:
            break
        x = x + dx
        if np.linalg.norm(dx) <= 1e-15 * (1 + np.linalg.norm(x)):
            break
    ok = bool(np.all(np.isfinite(x))) and \
        circle_residual(normal, x[:2], x[2:]) <= CHECK * max(1.0, np.linalg.norm(x))
    return x[:2], x[2:], ok


def _system(pencil, x):
    gx, gy, ux, uy = x
    v = np.array([ux, uy, 1.0])
    rows = pencil[:, 0] + gx * pencil[:, 1] + gy * pencil[:, 2]       # (4, 3)
    f = rows @ v
    J = np.column_stack([pencil[:, 1] @ v, pencil[:, 2] @ v, rows[:, 0], rows[:, 1]])
    return f, J
