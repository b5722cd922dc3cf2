"""Whole turns of gears (a base module, numpy only: the compiler's ``mechgen check`` and the
runtime's ``assemblies`` share it).

A gear's rolling row is written wrapped (model/library2d/gears.py: mesh_angle), so it vanishes on
every meshing whole turns of the centre line apart: at one time, with the driven angles
where their drivers put them, those are other assemblies in name only, the same gears
meshed teeth further on, which the driver reaches at other times. What tells them apart
is the mesh count s (module's mesh_turns: (ψ − β)/2π unwrapped, an integer on a
solution). Two solutions mesh alike when whole turns b of the angles (which change no
pose) take the one's counts to the other's: s_a + C b = s_b, with D b = 0 so that the
drivers still hold (C: the change of each count per turn of each angle; D: the drivers'
coefficients of the angles).
"""
from __future__ import annotations

import itertools

import numpy as np

SPAN = 6            # whole turns searched either way, per angle
MOST = 5            # angles searched at most (13^5 vectors); beyond: assumed alike


def turn_coefficients(counts, q, angles):
    """C: (rows, len(angles)), the change of every mesh count when angle j turns once;
    ``counts(q)`` gives the counts at q."""
    base = counts(q)
    C = np.empty((base.size, len(angles)))
    for k, j in enumerate(angles):
        v = q.copy()
        v[j] += 2.0 * np.pi
        C[:, k] = counts(v) - base
    return C


def meshed_alike(s_a, s_b, C, D, tol=1e-6) -> bool:
    """Whether integer turns b (|b_j| <= SPAN, D b = 0) give s_a + C b = s_b."""
    need = np.asarray(s_b, dtype=float) - np.asarray(s_a, dtype=float)
    if need.size == 0 or np.all(np.abs(need) <= tol):
        return True
    G = C.shape[1]
    if G == 0:
        return False
    if G > MOST:
        return True
    grid = np.array(list(itertools.product(range(-SPAN, SPAN + 1), repeat=G)), dtype=float)
    ok = np.all(np.abs(grid @ C.T - need) <= tol, axis=1)
    if D.size:
        ok &= np.all(np.abs(grid @ D.T) <= tol * (1.0 + np.abs(D).max()), axis=1)
    return bool(ok.any())
