"""A four-bar's position analysis in closed form, and its defects over a set of poses.

The linkage: input pivot O2, output pivot O4 (d = |O4 − O2|), input crank a (its angle phi
from the ground's x axis), coupler b, output link c. At input angle phi the crank pin is
A = O2 + a (cos phi, sin phi) and the coupler pin B the intersection of the circles (A, b)
and (O4, c) with the sign sigma = sign(cross(A − B, O4 − B)): the assembly mode, constant
along a motion until the coupler and output link line up (the transmission angle at 0 or
180°, |A − O4| = b + c or |b − c|), where the input can go no further in that mode. Those
input angles are exact: |A − O4|² = a² + d² + 2 a d cos(phi − psi0), psi0 the angle of
O2 − O4.

Defects over poses with input angles phi_j and modes sigma_j (pose 1 the start):
circuit: the sigma_j differ; branch: a pose in pose 1's mode that the input cannot reach
from pose 1 without passing such a toggle; order: the poses reachable from pose 1 are not
met in the given order while the input turns one way."""
from __future__ import annotations

import math

import numpy as np

TWO_PI = 2 * math.pi
EDGE = 1e-12


def cross(a, b) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def crank_pin(O2, a, phi) -> np.ndarray:
    return np.asarray(O2, float) + a * np.array([math.cos(phi), math.sin(phi)])


def coupler_pin(A, O4, b, c, sigma):
    """B for crank pin A in mode sigma (±1), or None where the loop does not close."""
    D = np.asarray(O4, float) - np.asarray(A, float)
    L = math.hypot(*D)
    if L == 0:
        return None
    x = (b * b - c * c + L * L) / (2 * L)
    h2 = b * b - x * x
    if h2 < -EDGE * b * b:
        return None
    h = math.sqrt(max(h2, 0.0))
    e = D / L
    n = np.array([-e[1], e[0]])
    return np.asarray(A, float) + x * e + sigma * h * n


def mode(A, B, O4) -> int:
    """The assembly mode sigma of a configuration (0 at a toggle)."""
    s = cross(np.asarray(A) - np.asarray(B), np.asarray(O4) - np.asarray(B))
    return int(np.sign(s))


def limits(O2, O4, a, b, c):
    """The input angles where the loop toggles (0, 2 or 4 of them), in [0, 2π)."""
    O2, O4 = np.asarray(O2, float), np.asarray(O4, float)
    d = math.hypot(*(O4 - O2))
    psi0 = math.atan2(*(O2 - O4)[::-1])
    out = []
    for r in (b + c, abs(b - c)):
        k = (r * r - a * a - d * d) / (2 * a * d)
        if -1 <= k <= 1:
            w = math.acos(k)
            out += [(psi0 + w) % TWO_PI, (psi0 - w) % TWO_PI]
    return sorted(set(out))


def feasible(O2, O4, a, b, c, phi) -> bool:
    A = crank_pin(O2, a, phi)
    L = math.hypot(*(np.asarray(O4, float) - A))
    return abs(b - c) <= L <= b + c


def reach(O2, O4, a, b, c, phi1, direction) -> float:
    """How far (radians) the input turns from phi1 in ``direction`` (±1) before a toggle
    (math.inf: it turns all the way round)."""
    best = math.inf
    for lim in limits(O2, O4, a, b, c):
        t = (direction * (lim - phi1)) % TWO_PI
        if t < 1e-12 or t > TWO_PI - 1e-12:
            # at the toggle: free only if the loop closes a little way on
            if feasible(O2, O4, a, b, c, phi1 + direction * 1e-7):
                continue
            return 0.0
        best = min(best, t)
    return best


def transmission(O2, O4, a, b, c, phi_lo, phi_hi):
    """(min, max) of the transmission angle (degrees, the angle ABO4 in [0, 180]) for input
    angles from phi_lo to phi_hi (phi_hi ≥ phi_lo): its extremes lie at the ends or where
    cos(phi − psi0) = ±1."""
    O2, O4 = np.asarray(O2, float), np.asarray(O4, float)
    psi0 = math.atan2(*(O2 - O4)[::-1])
    cands = [phi_lo, phi_hi]
    for target in (psi0, psi0 + math.pi):
        k = math.ceil((phi_lo - target) / TWO_PI)
        x = target + k * TWO_PI
        while x <= phi_hi:
            cands.append(x)
            x += TWO_PI
    mus = []
    for phi in cands:
        A = crank_pin(O2, a, phi)
        e = float(np.sum((A - O4) ** 2))
        cosmu = (b * b + c * c - e) / (2 * b * c)
        mus.append(math.degrees(math.acos(min(1.0, max(-1.0, cosmu)))))
    return min(mus), max(mus)


def analyse(O2, O4, a, b, c, phis, sigmas):
    """(defects, direction, times, span) for poses at input angles ``phis`` in modes
    ``sigmas``: the set of defects, the way the input turns (±1), the input's travel from
    pose 1 to each pose (NaN where it cannot reach one) and the input's angle interval
    (lo, hi) swept between the poses."""
    phis = np.asarray(phis, float)
    sig = list(sigmas)
    defects = set()
    if len(set(sig)) > 1:
        defects.add("circuit")
    phi1 = float(phis[0])
    L = {d: reach(O2, O4, a, b, c, phi1, d) for d in (1, -1)}
    full = math.isinf(L[1]) and math.isinf(L[-1])
    ahead = (phis - phi1) % TWO_PI                       # travel turning +1
    behind = (phi1 - phis) % TWO_PI                      # travel turning -1
    ahead[0] = behind[0] = 0.0
    x = np.full(len(phis), np.nan)                       # signed offset from pose 1
    for j in range(len(phis)):
        if sig[j] != sig[0]:
            continue
        if full or ahead[j] <= L[1]:
            x[j] = ahead[j]
        elif behind[j] <= L[-1]:
            x[j] = -behind[j]
        else:
            defects.add("branch")
    seen = x[~np.isnan(x)]
    direction = 1
    if full:
        up = np.all(np.diff(ahead[~np.isnan(x)]) > 0)
        down = np.all(np.diff(behind[~np.isnan(x)]) > 0)
        if not up and not down:
            defects.add("order")
        direction = 1 if up or not down else -1
        times = np.where(np.isnan(x), np.nan, ahead if direction == 1 else behind)
    else:
        up = np.all(np.diff(seen) > 0)
        down = np.all(np.diff(seen) < 0)
        if not up and not down:
            defects.add("order")
        direction = -1 if down and not up else 1
        times = direction * x
    reached = times[~np.isnan(times)]
    lo, hi = phi1 + direction * reached.min(), phi1 + direction * reached.max()
    return defects, direction, times, (min(lo, hi), max(lo, hi))
