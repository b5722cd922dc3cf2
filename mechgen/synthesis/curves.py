"""Three and four poses: the families of RR dyads, sampled.

Three poses: every body point (circle point) has its three positions on one circle, whose
centre is its fixed pivot: a two-parameter family, sampled on a disc of body points.
Four poses: the fixed pivots lie on the centre-point curve, the circular cubic
det N(G) = 0 of the three equal-distance rows (poses.equal_distance_rows); it passes through
the poles, and each line through the pole P12 meets it in two more points, the roots of a
quadratic. Lines through P12 swept over half a turn give its points; ``samples`` of those
near the poses are kept, spread along it. A given fixed or moving pivot gives its partner."""
from __future__ import annotations

import itertools
import math

import numpy as np

from .poses import Frame, circle_residual, equal_distance_rows, pole, positions, row_pencil

ON_CURVE = 1e-9         # relative smallest singular value of N(G) on the centre-point curve
WINDOW = 6.0            # sampled pivots lie within this many spreads of the poses' centre
GOLDEN = math.pi * (3 - math.sqrt(5))


def cubic(poses) -> np.ndarray:
    """The centre-point curve of four poses: C (4×4) with det N(G) = Σ C[i, k] gx^i gy^k."""
    pencil = row_pencil(poses)                   # (3, 3, 3): row j = a + gx b + gy c
    if pencil.shape[0] != 3:
        raise ValueError("the centre-point curve is drawn for four poses")
    C = np.zeros((4, 4))
    power = ((0, 0), (1, 0), (0, 1))
    for pick in itertools.product(range(3), repeat=3):
        rows = [pencil[j, pick[j]] for j in range(3)]
        i = sum(power[p][0] for p in pick)
        k = sum(power[p][1] for p in pick)
        C[i, k] += np.linalg.det(np.array(rows))
    return C


def inverted(poses) -> np.ndarray:
    """The poses of the inverted motion seen from the body held in pose 1: pose j becomes
    pose1 ∘ pose_j⁻¹ (the ground's frame placed, as the body moves from pose 1 to pose j,
    relative to the body left in pose 1)."""
    poses = np.asarray(poses, dtype=float)
    x1, y1, t1 = poses[0]
    out = []
    for x, y, th in poses:
        c, s = math.cos(th), math.sin(th)
        inv = np.array([-(c * x + s * y), s * x - c * y])      # R(-th) (-(x, y))
        c1, s1 = math.cos(t1), math.sin(t1)
        xy = np.array([c1 * inv[0] - s1 * inv[1] + x1, s1 * inv[0] + c1 * inv[1] + y1])
        out.append((xy[0], xy[1], t1 - th))
    return np.array(out)


def circle_cubic(poses) -> np.ndarray:
    """The circle-point curve of four poses, drawn where the body is in pose 1: C (4×4)
    with Σ C[i, k] x^i y^k = 0 at the pose-1 positions of the moving pivots (the
    centre-point curve of the inverted motion)."""
    return cubic(inverted(poses))


def moving_for(poses, G):
    """The moving pivot about fixed pivot G, or None where the equal-distance rows leave
    it undetermined or G is off the centre-point curve (four or five poses)."""
    N = equal_distance_rows(poses, G)
    scale = np.abs(N).max()
    if not np.isfinite(scale) or scale == 0:
        return None
    _, sv, vt = np.linalg.svd(N / scale)
    if N.shape[0] >= 3 and sv[2] > ON_CURVE * sv[0]:
        return None
    v = vt[-1] if N.shape[0] >= 3 else vt[2]
    if abs(v[2]) < 1e-12 * np.abs(v[:2]).max():
        return None
    return v[:2] / v[2]


def fixed_for(poses, u):
    """The fixed pivot of body point u: the centre of the circle through its positions
    (None where they are collinear, or off one circle for four or more poses)."""
    P = positions(poses, u)
    A = 2 * (P[1:] - P[0])
    b = np.sum(P[1:] ** 2, axis=1) - np.sum(P[0] ** 2)
    G, *_ = np.linalg.lstsq(A, b, rcond=None)
    spread = np.abs(P - P.mean(axis=0)).max()
    if not np.all(np.isfinite(G)) or np.linalg.norm(G - P[0]) > 1e8 * max(spread, 1e-300):
        return None
    if circle_residual(poses, G, u) > ON_CURVE * max(1.0, np.linalg.norm(G - P[0])):
        return None
    return G


def three_poses(poses, samples):
    """``samples`` (fixed, moving) pairs for three poses: moving pivots on a sunflower disc
    of 1.5 spreads about the body's origin."""
    frame = Frame(poses)
    out = []
    k = 0
    while len(out) < samples and k < 4 * samples + 8:
        r = 1.5 * math.sqrt((k + 0.5) / samples)
        u = frame.moving_back(r * np.array([math.cos(k * GOLDEN), math.sin(k * GOLDEN)]))
        k += 1
        G = fixed_for(poses, u)
        if G is not None and np.linalg.norm(frame.fixed_in(G)) <= 100:
            out.append((G, u))
    return out


def four_poses(poses, samples):
    """``samples`` (fixed, moving) pairs for four poses, their fixed pivots on the
    centre-point curve within WINDOW spreads of the poses, spread along it."""
    frame = Frame(poses)
    normal = frame.to(poses)
    P = None
    for i, j in ((0, 1), (0, 2), (1, 2), (0, 3), (1, 3), (2, 3)):
        P = pole(normal, i, j)
        if P is not None:
            break
    if P is None:
        return []
    pencil = row_pencil(normal)
    base = pencil[:, 0] + P[0] * pencil[:, 1] + P[1] * pencil[:, 2]
    found = []
    lines = max(64, 8 * samples)
    for n in range(lines):
        phi = math.pi * (n + 0.5) / lines
        v = np.array([math.cos(phi), math.sin(phi)])
        step = v[0] * pencil[:, 1] + v[1] * pencil[:, 2]
        c = _det_poly(base, step)               # det(base + t step) = c0 + c1 t + c2 t² + c3 t³
        quad = c[1:][::-1]                      # t (c3 t² + c2 t + c1): the root t = 0 is P
        quad = np.trim_zeros(np.where(np.abs(quad) > 1e-14 * np.abs(quad).max(), quad, 0), "f")
        if quad.size < 2:
            continue
        for t in np.roots(quad):
            if abs(t.imag) > 1e-9 * (1 + abs(t)) or abs(t.real) < 1e-9:
                continue
            G = P + t.real * v
            if np.linalg.norm(G) > WINDOW:
                continue
            u = moving_for(normal, G)
            if u is not None and np.linalg.norm(u) <= 100:
                found.append((phi, G, u))
    picked = _spread_out([g for _, g, _ in found], samples)
    return [(frame.fixed_back(found[k][1]), frame.moving_back(found[k][2])) for k in picked]


def _det_poly(base, step):
    """Coefficients c0..c3 of det(base + t step) for 3×3 base and step."""
    c = np.zeros(4)
    for pick in itertools.product((0, 1), repeat=3):
        rows = np.array([(base, step)[pick[j]][j] for j in range(3)])
        c[sum(pick)] += np.linalg.det(rows)
    return c


def _spread_out(points, count):
    """Indices (sorted) of ``count`` of ``points`` chosen far from each other (greedy
    farthest-point sampling from the first)."""
    if len(points) <= count:
        return list(range(len(points)))
    X = np.array(points)
    chosen = [0]
    dist = np.linalg.norm(X - X[0], axis=1)
    while len(chosen) < count:
        k = int(np.argmax(dist))
        chosen.append(k)
        dist = np.minimum(dist, np.linalg.norm(X - X[k], axis=1))
    return sorted(chosen)
