"""The Strandbeest leg against pylinkage, side by side in one process: one crank turn at
10^4 points (by default), positions only and positions with velocities and accelerations.

    python benchmarks/bench_pylinkage.py                 # 10^4 points, 7 interleaved rounds
    python benchmarks/bench_pylinkage.py --points 100000 --rounds 5

pylinkage (not a dependency of mechgen; the benchmark says so and stops where it is not
installed) solves each dyad by a circle intersection in its numba loop: ``step_fast``
(positions) and ``step_fast_with_kinematics`` (with velocities and accelerations). mechgen:
the generated module's compiled sweep into preallocated arrays (``sweep_fast``, as
pylinkage's loop fills its own arrays) and ``mech.sweep`` (the Python API, which also
allocates its result arrays and checks the sweep). The same leg (examples/strandbeest.py,
Jansen's numbers), the same crank turn; both traces are compared at the foot (pylinkage's
joint G, mechgen's foot point 3) so that the two compute the same thing. Printed: ms per
turn (best of interleaved rounds) and the ratio pylinkage / mechgen.
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "examples"))


def pylinkage_leg(n):
    """Jansen's leg in pylinkage: the crank output A, then C, E, D, F, G by dyads; the crank
    turns 2π/n a step. (linkage, crank)."""
    from pylinkage.actuators import Crank
    from pylinkage.components import Ground
    from pylinkage.dyads import RRRDyad
    from pylinkage.simulation import Linkage

    import strandbeest as sb
    O = Ground(*sb.O, name="O")
    B = Ground(*sb.B, name="B")
    crank = Crank(anchor=O, radius=sb.m_, angular_velocity=2 * math.pi / n, name="A")
    A = crank.output
    C = RRRDyad(B, A, distance1=sb.b, distance2=sb.j, x=sb.C[0], y=sb.C[1], name="C")
    E = RRRDyad(B, A, distance1=sb.c, distance2=sb.k, x=sb.E[0], y=sb.E[1], name="E")
    D = RRRDyad(B, C, distance1=sb.d, distance2=sb.e, x=sb.D[0], y=sb.D[1], name="D")
    F = RRRDyad(D, E, distance1=sb.f, distance2=sb.g, x=sb.F[0], y=sb.F[1], name="F")
    G = RRRDyad(E, F, distance1=sb.i, distance2=sb.h, x=sb.G[0], y=sb.G[1], name="G")
    link = Linkage([O, B, crank, C, E, D, F, G], name="strandbeest")
    link.set_input_velocity(crank, omega=2 * math.pi)
    return link, crank


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--points", type=int, default=10_000)
    ap.add_argument("--rounds", type=int, default=7)
    args = ap.parse_args(argv)
    import importlib.util
    if importlib.util.find_spec("pylinkage") is None:
        print("pylinkage is not installed (pip install pylinkage): nothing to compare")
        return
    import mechgen
    from mechgen.compiler.build import build
    from mechgen.model.loader import load_models
    import tempfile

    N = args.points
    model = load_models(os.path.join(ROOT, "examples", "strandbeest.py"))[0]
    mech = mechgen.load(build(model, tempfile.mkdtemp(prefix="mechgen-bench-")), tier="compiled")
    mod, n = mech.module, mech.n
    ts = np.arange(N) / N                        # one turn, the crank at 2π k / N
    q0 = np.array(mod.GUESS, dtype=float)
    Q, QD, QDD = np.zeros((N, n)), np.zeros((N, n)), np.zeros((N, n))
    S, none = np.zeros((N, 3), dtype=np.int16), np.zeros((0, n))

    link, crank = pylinkage_leg(N)
    start = link.get_coords()

    def reset():
        link.set_coords(start)

    def py_pos():
        reset()
        return link.step_fast(iterations=N)

    def py_kin():
        reset()
        return link.step_fast_with_kinematics(iterations=N)

    def mg(level):
        qd, qdd = (QD, QDD) if level else (none, none)

        def run():
            done = mod.sweep_fast(ts, q0, mech.p, mech.tol, mech.xtol, mech.maxit, Q, qd, qdd, S)
            if done != N:
                raise RuntimeError(f"sweep_fast stopped at {done} of {N}")
        return run

    def api(level):
        return lambda: mech.sweep(None, None, None, level=level, times=ts)

    cases = {"pylinkage step_fast": py_pos, "pylinkage step_fast_with_kinematics": py_kin,
             "mechgen sweep_fast, position": mg(0), "mechgen sweep_fast, acceleration": mg(2),
             "mechgen mech.sweep, position": api("position"),
             "mechgen mech.sweep, acceleration": api("acceleration")}
    for fn in cases.values():      # compile and warm every path
        fn()
    best = {}
    for _ in range(args.rounds):
        for name, fn in cases.items():
            t0 = time.perf_counter()
            fn()
            best[name] = min(best.get(name, np.inf), (time.perf_counter() - t0) * 1e3)

    # the same motion: the foot point G against pylinkage's G (its last joint; pylinkage's
    # row k is the crank turned k + 1 steps)
    traj = py_pos()[:-1]
    sw = mech.sweep(None, None, None, level="position", times=ts)
    foot = sw.points()[1:, mech.point_names.index("foot[3]"), :]
    diff = float(np.abs(foot - traj[:, -1, :]).max() / np.abs(foot).max())

    print(f"Strandbeest leg, one crank turn at {N} points, best of {args.rounds} interleaved "
          "rounds (ms per turn)")
    for name, ms in best.items():
        print(f"  {name:40s} {ms:8.3f}")
    r = best
    print(f"positions: step_fast / sweep_fast {r['pylinkage step_fast'] / r['mechgen sweep_fast, position']:.2f}"
          f", / mech.sweep {r['pylinkage step_fast'] / r['mechgen mech.sweep, position']:.2f}")
    kin = r["pylinkage step_fast_with_kinematics"]
    for level in ("position", "acceleration"):
        print(f"step_fast_with_kinematics / mechgen {level}: sweep_fast "
              f"{kin / r[f'mechgen sweep_fast, {level}']:.2f}, mech.sweep "
              f"{kin / r[f'mechgen mech.sweep, {level}']:.2f}")
    print(f"largest difference of the foot's path, mechgen against pylinkage: {diff:.1e} "
          "(relative to its largest coordinate)")


if __name__ == "__main__":
    main()
