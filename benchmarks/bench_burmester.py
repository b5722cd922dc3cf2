"""Five-position Burmester synthesis: what the exact elimination costs, against a multi-start
Newton search in the same process, and how often the search misses a real pair.

    python benchmarks/bench_burmester.py                 # 100 seeded problems
    python benchmarks/bench_burmester.py --problems 300 --starts 16 64 256 1024

The problems (seeded): half of them five poses of a random four-bar's coupler frame (two
or four real pairs), half five random poses (none, two or four). For each, the time of
``synthesis.dyads(poses, sliders=False)`` (every real pair from the quartic, Newton-polished
and checked; the best of 3 calls) and of a Newton search from S random starts (all starts
iterated at once on numpy's batched solve, radii 0.1 to 30 spreads in the poses' scaled
frame, 30 iterations, deduplicated): the median and 90th percentile of the times, the
problems on which the search found fewer pairs than the exact count ("missed") and the pairs
it missed in all. The exact count is the reference: tests/test_burmester_counts.py checks it
against a 400-start fsolve search.
"""
from __future__ import annotations

import argparse
import cmath
import math
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))

from mechgen import synthesis  # noqa: E402


def coupler_poses(rng):
    """Five poses of a random crank-driven four-bar's coupler frame (None: it does not
    close at one of the crank angles drawn)."""
    b, c, d = rng.uniform(2.0, 3.5, size=3)
    uA = complex(*rng.normal(size=2))
    uB = uA + b * cmath.exp(1j * rng.uniform(-3, 3))
    out = []
    for phi in np.sort(rng.uniform(0, 2 * math.pi, size=5)):
        A = cmath.exp(1j * phi)
        L = abs(d - A)
        k = (b * b + L * L - c * c) / (2 * b * L)
        if not -1 <= k <= 1:
            return None
        B = A + b * cmath.exp(1j * (cmath.phase(d - A) + math.acos(k)))
        th = cmath.phase(B - A) - cmath.phase(uB - uA)
        z = A - cmath.exp(1j * th) * uA
        out.append((z.real, z.imag, th))
    return np.array(out)


def problems(count, seed=2024):
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < count:
        if len(out) % 2:
            out.append(np.column_stack([rng.normal(size=5), rng.normal(size=5),
                                        rng.uniform(-1.5, 1.5, size=5)]))
        else:
            p = coupler_poses(rng)
            if p is not None:
                out.append(p)
    return out


def newton_search(poses, starts, rng, iterations=30):
    """Real pairs (G, u) found by Newton from ``starts`` random starts, all at once."""
    P = np.asarray(poses, dtype=float)
    centre = P[:, :2].mean(axis=0)
    scale = math.sqrt(np.mean(np.sum((P[:, :2] - centre) ** 2, axis=1)))
    d = (P[:, :2] - centre) / scale
    c, s = np.cos(P[:, 2]), np.sin(P[:, 2])
    x = rng.normal(size=(starts, 4))
    x *= (10 ** rng.uniform(-1, 1.5, size=starts) / np.linalg.norm(x, axis=1))[:, None]
    for _ in range(iterations):
        G, u = x[:, :2], x[:, 2:]
        # positions of u in every pose: (starts, 5, 2), their offsets from G
        px = c * u[:, :1] - s * u[:, 1:] + d[:, 0]
        py = s * u[:, :1] + c * u[:, 1:] + d[:, 1]
        rx, ry = px - G[:, :1], py - G[:, 1:]
        r2 = rx * rx + ry * ry
        f = r2[:, 1:] - r2[:, :1]
        # d r2 / d(G, u) per pose
        dg = np.stack([-2 * rx, -2 * ry], axis=2)
        du = np.stack([2 * (rx * c + ry * s), 2 * (-rx * s + ry * c)], axis=2)
        J = np.concatenate([dg, du], axis=2)
        J = J[:, 1:] - J[:, :1]
        with np.errstate(all="ignore"):
            try:
                step = np.linalg.solve(J, -f[:, :, None])[:, :, 0]
            except np.linalg.LinAlgError:
                step = np.stack([np.linalg.lstsq(j, -g, rcond=None)[0] for j, g in zip(J, f)])
        step[~np.isfinite(step)] = 0.0
        x = x + step
    G, u = x[:, :2], x[:, 2:]
    px = c * u[:, :1] - s * u[:, 1:] + d[:, 0]
    py = s * u[:, :1] + c * u[:, 1:] + d[:, 1]
    r2 = (px - G[:, :1]) ** 2 + (py - G[:, 1:]) ** 2
    res = np.max(np.abs(r2[:, 1:] - r2[:, :1]), axis=1)
    size = np.linalg.norm(x, axis=1)
    good = np.isfinite(res) & (res < 1e-9 * np.maximum(1.0, size) ** 2) & (size < 1e6)
    found = []
    for v in x[good]:
        if not any(np.allclose(v, w, atol=1e-6 * (1 + np.linalg.norm(w))) for w in found):
            found.append(v)
    return [(w[:2] * scale + centre, w[2:] * scale) for w in found]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--problems", type=int, default=100)
    ap.add_argument("--starts", type=int, nargs="+", default=[16, 64, 256, 1024])
    args = ap.parse_args(argv)
    cases = problems(args.problems)
    synthesis.dyads(cases[0], sliders=False)            # imports and first calls done
    exact_t, counts = [], []
    for poses in cases:
        best = math.inf
        for _ in range(3):
            t0 = time.perf_counter()
            found = synthesis.dyads(poses, sliders=False)
            best = min(best, time.perf_counter() - t0)
        exact_t.append(best)
        counts.append(len(found))
    hist = {k: counts.count(k) for k in sorted(set(counts))}
    print(f"{len(cases)} five-pose problems; real pairs per problem: "
          + ", ".join(f"{k}: {v}" for k, v in hist.items()))
    head = (f"{'method':28s} {'median ms':>10s} {'p90 ms':>8s} {'missed problems':>16s} "
            f"{'missed pairs':>13s} {'extra':>6s}")
    print(head)
    print("-" * len(head))
    t = np.array(exact_t) * 1e3
    print(f"{'exact (quartic + Newton)':28s} {np.median(t):10.3f} {np.percentile(t, 90):8.3f} "
          f"{'0 (reference)':>16s} {'0':>13s} {'0':>6s}")
    for starts in args.starts:
        rng = np.random.default_rng(starts)
        times, missed, lost, extra = [], 0, 0, 0
        for poses, n in zip(cases, counts):
            t0 = time.perf_counter()
            found = newton_search(poses, starts, rng)
            times.append(time.perf_counter() - t0)
            if len(found) < n:
                missed += 1
                lost += n - len(found)
            extra += max(0, len(found) - n)
        t = np.array(times) * 1e3
        print(f"{f'Newton, {starts} starts':28s} {np.median(t):10.3f} "
              f"{np.percentile(t, 90):8.3f} {f'{missed} / {len(cases)}':>16s} "
              f"{f'{lost} / {sum(counts)}':>13s} {extra:6d}")


if __name__ == "__main__":
    main()
