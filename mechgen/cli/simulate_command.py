"""``mechgen simulate MODEL.py --free NAME --t1 2 -n 2001``: motion under forces
(docs/reference/simulation.md, mechgen.runtime.forces.simulate): the table of positions, velocities,
accelerations and force columns at the output times, printed or written to a CSV file; the
integration's steps and what it conserved on stderr."""
from __future__ import annotations

import sys
import time

import numpy as np

from .loading import mechanism
from .options import number_type, output_file, parse_columns, written
from .tables import format_table, select, times, write_csv


def cmd_simulate(args):
    if args.csv:
        output_file(args.csv)
    ts = times(args.t0, args.t1, args.n)           # refused before anything is built
    mech = mechanism(args)
    free = [name for group in args.free or () for name in group.split(",") if name.strip()]
    sw = mech.simulate(ts[0], ts[-1], len(ts), free=[n.strip() for n in free],
                       rtol=args.rtol, atol=args.atol, method=args.method,
                       progress=_progress(ts[0], ts[-1]))
    header, data = sw.table()
    header, data = select(header, data, parse_columns(args.columns), 1)
    e = sw.energy()["total"]
    drift = float(np.max(np.abs(e - e[0]))) if len(e) else 0.0
    print(f"simulated {len(sw)} times in {sw.steps} steps ({sw.evaluations} evaluations of "
          f"the accelerations); total energy changed by up to {drift:.3g} (loads and "
          "drivers still prescribed do work)", file=sys.stderr)
    if args.csv:
        write_csv(args.csv, header, data)
        print(f"wrote {len(sw)} rows to {args.csv}")
    elif not (args.animate or args.plot):
        print(format_table(header, data))
    _pictures(args, mech, sw)


def _progress(t0, t1, every=1.0):
    """A progress line on stderr about every ``every`` seconds of a long run."""
    start = last = time.perf_counter()

    def report(t):
        nonlocal last
        now = time.perf_counter()
        if now - last >= every:
            last = now
            share = (t - t0) / (t1 - t0) if t1 != t0 else 1.0
            print(f"simulating: T = {t:.6g} of {t1:.6g} ({100 * share:.0f} %, "
                  f"{now - start:.1f} s)", file=sys.stderr, flush=True)
    return report


def _pictures(args, mech, sw):
    """--animate FILE (the motion as a film) and --plot NAMES (quantities over time)."""
    if not (args.animate or args.plot):
        return
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .. import plot
    if args.animate:
        path = output_file(args.animate)
        plot.check_movie_path(path)
        a = plot.animate(mech, sw, None, trace=tuple(args.trace or ()), periodic=False)
        with written(path) as tmp:
            a.save(tmp, dpi=80)
        plt.close(a.figure)
        print(f"wrote {path} ({len(a)} frames, T from {sw.t[0]:g} to {sw.t[-1]:g})")
    if args.plot:
        names = parse_columns(args.plot)
        lines = plot.plot(sw, *names)
        path = output_file(args.plot_file or f"{mech.name}_simulated.png")
        with written(path) as tmp:
            lines[0].figure.savefig(tmp, dpi=100)
        plt.close(lines[0].figure)
        print(f"wrote {path} ({', '.join(names)} over {len(sw)} times)")


def add_command(sub, common):
    p = sub.add_parser("simulate", help="motion under forces: release drivers and integrate",
                       description="The drivers named with --free stop prescribing their "
                                   "motion at --t0; from the kinematic state there the "
                                   "mechanism moves under its masses and loads (the other "
                                   "drivers still prescribe theirs), written at -n times "
                                   "from --t0 to --t1.")
    common(p)
    p.add_argument("--free", action="append", metavar="NAMES",
                   help="the drivers set free (comma-separated names or numbers; "
                        "repeatable); a model without a driver for a degree of freedom "
                        "moves from its guess without it")
    p.add_argument("--t0", type=number_type, default=0.0, help="start time (default 0)")
    p.add_argument("--t1", type=number_type, default=1.0, help="end time (default 1)")
    p.add_argument("-n", type=int, default=101, help="output times, both ends (default 101)")
    p.add_argument("--rtol", type=float, default=1e-8, help="relative tolerance (1e-8)")
    p.add_argument("--atol", type=float, default=1e-10, help="absolute tolerance (1e-10)")
    p.add_argument("--method", default="dopri5",
                   help="dopri5 (default: Dormand-Prince 5(4), compiled in the module), or "
                        "a scipy solve_ivp method: DOP853, RK45, Radau, BDF, LSODA")
    p.add_argument("-o", "--csv", metavar="FILE", dest="csv",
                   help="write the table to this CSV file instead of printing it")
    p.add_argument("--columns", action="append", metavar="NAMES",
                   help="only these columns after T, comma-separated (repeatable)")
    p.add_argument("--animate", metavar="FILE",
                   help="also write the motion as a film (.gif, or .mp4 with ffmpeg)")
    p.add_argument("--trace", action="append", metavar="POINT",
                   help="with --animate: draw this point's path (repeatable)")
    p.add_argument("--plot", action="append", metavar="NAMES",
                   help="also plot these quantities over time (comma-separated)")
    p.add_argument("--plot-file", metavar="FILE",
                   help="the --plot picture (default MODEL_simulated.png)")
    p.set_defaults(func=cmd_simulate)
