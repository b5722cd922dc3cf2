"""Never the wrong mechanism (issue 20), the long profile: random mechanisms of every family
of tests/random_families.py, each swept once (a random level, method, span and point
count from 7 to 721 a period, from the exact start of a random mode), single-solved at
random times with and without a guess, and run as a small design table; every point
judged against the closed form by tests/random_checks.py (the fast profile's judge).

Prints, per family and kind of run, how many were right, refused (raised, or a flagged
point: JUMP, THROUGH_SINGULAR, a failure), wrong (a point with status OK off the
closed form of its mode, or past a lock window) and crashed (raised anything else), the
share of the points their modes reach that were answered right, then the first wrong
runs with their parameters and times. Exits 1 on a wrong or crashed run, or a family
that answered less than --min-answered. Deterministic for a given --seed.

    PYTHONPATH=$PWD MECHGEN_TIER=compiled python benchmarks/random_mechanisms.py --count 10000

``--large``: the auto tier with an empty numba cache and every sweep counted too large for
Python, so that sweeps run on the mixed module (compiled loops, one-point solves in
Python: mechgen.runtime.loading.mixed) until the worker's cache is ready, then on the
whole compiled module (unset MECHGEN_TIER for it).
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from collections import Counter

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "tests"))

import random_checks as rc                       # noqa: E402
from random_families import FAMILIES             # noqa: E402


guarded = rc.guarded


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--count", type=int, default=10000,
                    help="random mechanisms in all, shared evenly by the families (10000)")
    ap.add_argument("--seed", type=int, default=20)
    ap.add_argument("--families", default=",".join(FAMILIES),
                    help="comma-separated (default: all): " + ", ".join(FAMILIES))
    ap.add_argument("--solves", type=int, default=2, help="random times solved per mechanism")
    ap.add_argument("--table-every", type=int, default=5,
                    help="a design table (4 designs) for every k-th mechanism (5)")
    ap.add_argument("--by-method", action="store_true",
                    help="count sweeps and solves per method (auto, sorted, full) too")
    ap.add_argument("--show", type=int, default=12, help="wrong runs printed per family")
    ap.add_argument("--min-answered", type=float, default=0.9,
                    help="the least share of the points a run's mode reaches from its start "
                         "(the closed form assembles) answered right, per family (0.9)")
    ap.add_argument("--large", action="store_true",
                    help="every sweep counted large, an empty numba cache (the mixed module)")
    args = ap.parse_args(argv)
    if args.large:
        import tempfile
        from mechgen.runtime.loading import tiers
        os.environ["NUMBA_CACHE_DIR"] = tempfile.mkdtemp(prefix="mechgen-profile-nc-")
        tiers.BIG_CALL = 1e-9
    names = [n.strip() for n in args.families.split(",") if n.strip()]
    per = max(1, args.count // len(names))
    counts, started = Counter(), time.perf_counter()
    shown = {}
    for name in names:
        fam, k = FAMILIES[name], list(FAMILIES).index(name)   # seeds per family
        t = time.perf_counter()
        fam.mech()
        fam.disc({n: 1.0 for n in fam.params}, np.zeros(1))
        print(f"# {name}: compiled in {time.perf_counter() - t:.1f} s", flush=True)
        t = time.perf_counter()
        wrongs = shown.setdefault(name, [])
        for i in range(per):
            rng = np.random.default_rng([args.seed, k, i])
            spec = rc.draw_spec(fam, rng)
            by = f"/{spec.method}" if args.by_method else ""
            kind = f"{name}/{spec.variant}/sweep{by}"
            rc.tally(counts, kind, guarded(spec, lambda: [rc.run_sweep(fam, spec)]), wrongs,
                     args.show)
            if args.solves:
                for kind, v in guarded(spec, lambda: rc.single_solves(fam, spec, rng, args.solves),
                                       pairs=True):
                    rc.tally(counts, kind if "/" in kind else f"{name}/solve-{kind}{by}", [v],
                             wrongs, args.show)
            if args.table_every and i % args.table_every == 0:
                rc.tally(counts, f"{name}/table",
                         guarded(spec, lambda: rc.run_table(fam, spec, rng, designs=4)),
                         wrongs, args.show)
                rc.tally(counts, f"{name}/table-carried",
                         guarded(spec, lambda: rc.run_carried_table(fam, spec, rng, designs=4)),
                         wrongs, args.show)
        print(f"# {name}: {per} mechanisms in {time.perf_counter() - t:.1f} s", flush=True)
    print(f"\nrandom mechanisms: {per * len(names)} ({per} a family), seed {args.seed}, "
          f"{time.perf_counter() - started:.0f} s")
    print("\n".join(line for line in rc.summary(counts) if "(mechanisms)" not in line))
    for name, wrongs in shown.items():
        if wrongs:
            print(f"\nfirst wrong runs of {name}:")
            for w in wrongs:
                print("  " + w)
    crashes = [d for d in rc.CRASHES]
    if crashes:
        print(f"\nruns that crashed ({len(crashes)}):")
        for d in crashes[:args.show]:
            print("  " + d)
    bad = sum(n for (kind, outcome), n in counts.items() if outcome in ("wrong", "crashed"))
    short = []
    for name in names:
        right = sum(n for (kind, o), n in counts.items()
                    if kind.startswith(name + "/") and o == "answered")
        reach = sum(n for (kind, o), n in counts.items()
                    if kind.startswith(name + "/") and o == "reachable")
        print(f"{name}: answered {right} of the {reach} points its runs' modes reach")
        if reach == 0 or right < args.min_answered * reach:
            short.append(name)
    if short:
        print(f"\nfamilies that refused too much (< {args.min_answered} answered): "
              + ", ".join(short))
    return 1 if bad or short else 0


if __name__ == "__main__":
    sys.exit(main())
