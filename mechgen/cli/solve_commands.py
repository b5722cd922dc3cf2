"""The solving commands: ``mechgen solve | sweep | singularities``."""
from __future__ import annotations

import argparse
import contextlib
import sys

import numpy as np

from ..errors import MechgenError
from ..runtime.unit_columns import column_units, labelled
from ..units import of as units_of
from .loading import mechanism
from .options import (number_type, output_file, parse_columns, parse_guess,
                      parse_param_option)
from .tables import FORCE_LEVELS, format_table, needed_level, select, times, write_csv


def _emit(args, header, data, keep, what, sweep=None, mech=None):
    """Print the table, or write it to the -o/--csv file and say so; with ``sweep`` and
    --sensitivities, the columns d<name>/d<param> of each quantity printed after them.
    Where ``mech`` (or the sweep's) declares its units, each column says its unit
    ("X4 [mm]", runtime.unit_columns)."""
    header, data = select(header, data, parse_columns(args.columns), keep)
    if sweep is not None and getattr(args, "sensitivities", None):
        header, data = with_sensitivities(sweep, header, data, keep)
    mech = mech if sweep is None else sweep.mechanism
    if mech is not None:
        header, data = labelled(mech, header, data)
    if args.csv:
        write_csv(args.csv, header, data)
        print(f"wrote {what} to {args.csv}")
    else:
        print(format_table(header, data))


def parse_sensitivities(text):
    """--sensitivities: ``all`` (True) or comma-separated parameter names; None."""
    if text is None:
        return None
    names = [n.strip() for n in text.split(",") if n.strip()]
    if not names:
        raise MechgenError("--sensitivities takes parameter names (a,b) or all")
    return True if names == ["all"] else names


def with_sensitivities(sw, header, data, keep=1):
    """The table with d<name>/d<param> after it: for each quantity column (after the
    first ``keep``), each parameter the sweep carries, ∂name/∂param (sw.sensitivity)."""
    params = sw.sensitivity_params
    cols, names = [], []
    for name in header[keep:]:
        for p in params:
            cols.append(np.asarray(sw.sensitivity(name, p), dtype=float))
            names.append(f"d{name}/d{p}")
    if not cols:
        return header, data
    return list(header) + names, np.column_stack([data] + cols)


def cmd_solve(args):
    """One time: a column of names and values (or a one-row CSV)."""
    if args.csv:
        output_file(args.csv)
    mech = mechanism(args)
    columns = parse_columns(args.columns)
    level = needed_level(mech, columns, args.level)
    s = mech.solve(args.t, guess=parse_guess(args.guess), level=level, method=args.method)
    if level in FORCE_LEVELS:       # the columns of sweep --level: efforts, reactions
        from ..runtime.forces.sweep import of_solution
        header, data = of_solution(s).table()
        rows = list(zip(header, data[0]))
    else:
        rows = [("T", s.t)] + [(k, s[k]) for k in s.keys()]     # the outputs included
    if columns:
        by_name = dict(rows)
        rows = [("T", s.t)] + [(c, by_name[c]) for c in columns if c != "T"]
    if args.csv:
        header, data = labelled(mech, [k for k, _ in rows], np.array([[v for _, v in rows]]))
        write_csv(args.csv, header, data)
        print(f"wrote {mech.name} at T = {s.t:g} ({len(rows) - 1} columns) to {args.csv}")
        return
    said = level if level in FORCE_LEVELS else s.level
    print(f"{mech.name} at T = {s.t:g} ({said}; {s.iterations} Newton iterations, "
          f"residual {s.residual:.2g}, {s.method} solver{', SINGULAR' if s.singular else ''})")
    width = max(len(k) for k, _ in rows)
    names = [k for k, _ in rows]
    _, data = labelled(mech, names, np.array([[v for _, v in rows]]))   # (deg where asked)
    said = column_units(mech, names) if units_of(mech).declared else [""] * len(names)
    for k, v, u in zip(names, data[0], said):
        print(f"  {k:<{width}} -> {float(v) + 0.0:.10g}{' ' + u if u else ''}")  # never -0
    if getattr(s, "indeterminate", ()):
        print("indeterminate (redundant constraints; minimum-norm multipliers shown): "
              + "; ".join(s.indeterminate))


def cmd_sweep(args):
    """Times from --t0 to --t1: a table, or a CSV file; a design table with --param. On a
    failure, the points reached before it, then the error."""
    if args.csv:
        output_file(args.csv)
    ts = times(args.t0, args.t1, args.n)
    params = parse_param_option(args.param)     # refused before anything is built
    which = parse_sensitivities(args.sensitivities)
    if which is not None and (args.level in FORCE_LEVELS or
                              any(not isinstance(v, float) for v in params.values())):
        raise MechgenError("--sensitivities goes with a kinematic sweep (not a design table, "
                           "not --level static or dynamic)")
    mech = mechanism(args)
    unknown = [p for p in (which if isinstance(which, list) else ()) if p not in
               mech.parameter_names]
    if unknown:
        raise MechgenError(f"--sensitivities: {', '.join(unknown)}: not a parameter of "
                           f"'{mech.name}' (its parameters: "
                           f"{', '.join(mech.parameter_names) or 'none'})")
    reduce = parse_columns(args.reduce)
    # the level follows from the reduced quantities (a table of reductions has columns
    # X4_min, ...), else from the columns asked for
    level = needed_level(mech, reduce or parse_columns(args.columns), args.level)
    if any(not isinstance(v, float) for v in params.values()):   # a design table
        progress = sys.stderr.isatty() if args.progress is None else args.progress
        with backend_client(args) as client:
            tab = mech.design_sweep(ts[0], ts[-1], len(ts), params, level=level, times=ts,
                                    guess=parse_guess(args.guess), method=args.method,
                                    progress=progress or None, backend=args.backend,
                                    workers=args.workers if args.backend == "cpu" else None,
                                    client=client, reduce=reduce)
        header, data = tab.table()
        keep = len(tab.names) + (1 if tab.kept_points else 0)
        _emit(args, header, data, keep,
              f"{data.shape[0]} rows ({len(tab)} designs)", mech=mech)
        return
    if args.backend != "cpu" or args.reduce or args.workers is not None:
        raise MechgenError("--backend, --workers and --reduce are for design tables: vary a "
                           "parameter with --param NAME=V1,V2,...")
    if params:
        mech = mech.with_params(**params)
    try:
        sw = mech.sweep(ts[0], ts[-1], len(ts), level=level, guess=parse_guess(args.guess),
                        method=args.method, times=ts, sensitivities=which)
    except MechgenError as exc:
        partial = getattr(exc, "sweep", None)
        if partial is not None and len(partial):
            header, data = partial.table()
            _emit(args, header, data, 1, f"the {len(partial)} of {len(ts)} rows reached "
                                          "before the failure", mech=mech)
            sys.stdout.flush()
        raise
    header, data = sw.table()
    _emit(args, header, data, 1, f"{len(sw)} rows", sweep=sw)


@contextlib.contextmanager
def backend_client(args):
    """The dask client of --backend dask: the --scheduler's, or a LocalCluster of
    --workers processes (2 by default) for this command; None for the other backends."""
    if args.backend != "dask":
        yield None
        return
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise MechgenError("--backend dask needs dask.distributed: pip install 'dask[distributed]'") from None
    if args.scheduler:
        with Client(args.scheduler) as client:
            yield client
        return
    with LocalCluster(n_workers=args.workers or 2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        yield client


def cmd_singularities(args):
    """Times where the Jacobian loses rank along the branch the guess starts on."""
    mech = mechanism(args)
    found = mech.singularities(args.t0, args.t1, n=args.n, guess=parse_guess(args.guess))
    span = f"T from {args.t0:g} to {args.t1:g}"
    if not found:
        print(f"{mech.name}: no singular configuration for {span} (the branch the guess "
              f"starts on, {args.n} samples)")
        return
    print(f"{mech.name}: {len(found)} singular configuration(s) for {span} (the branch the "
          f"guess starts on, {args.n} samples)")
    for s in found:
        kind = {"lock": "lock (toggle) position: the driven motion cannot pass",
                "crossing": "crossing: the branch passes a dead centre or branch point"}
        print(f"  T = {s.t:.10g}  {kind.get(s.kind, s.kind)}")
        null = getattr(s, "null", None)
        if s.coordinates:
            who = " and ".join(s.lock) if s.lock else "the constraints"
            print(f"      {who} cannot fix {', '.join(s.coordinates)}")
        grouped = getattr(null, "grouped", None) or s.constraints
        print(f"      constraints losing rank: {'; '.join(grouped)}")


def add_commands(sub, common, solve_options):
    """Add solve, sweep and singularities to the ``mechgen`` parser."""
    def table_options(p):
        p.add_argument("-o", "--csv", metavar="FILE", dest="csv",
                       help="write the table to this CSV file instead of printing it")
        p.add_argument("--columns", action="append", metavar="NAMES",
                       help="only these columns after T, comma-separated (e.g. X4,X4d; "
                            "repeatable); the level follows from them unless --level says")

    def span(p, n):
        p.add_argument("--t0", type=number_type, default=0.0,
                       help="first time (default 0); a number or an expression such as "
                            "2*pi (write --t0=-pi for a negative one)")
        p.add_argument("--t1", type=number_type, default=1.0,
                       help="last time (default 1); a number or an expression")
        p.add_argument("-n", type=int, default=n,
                       help=f"number of times, both ends included (default {n})")

    p = sub.add_parser("solve", help="solve at one time",
                       description="Solve the model at time T and print every coordinate "
                                   "(and derivative, and output) at the level asked for.")
    common(p)
    p.add_argument("-t", type=number_type, required=True,
                   help="the time: a number or an expression such as 0.5/pi")
    table_options(p)
    solve_options(p)
    p.set_defaults(func=cmd_solve)

    p = sub.add_parser("sweep", help="solve over a range of times",
                       description="Solve at -n times from --t0 to --t1 (both ends "
                                   "included), each started from the one before.")
    common(p)
    span(p, 21)
    table_options(p)
    p.add_argument("--param", action="append", metavar="NAME=VALUES",
                   help="a design table: NAME=V1,V2,..., NAME=START:STOP:COUNT (COUNT "
                        "values, both ends included) or NAME=START:STOP:step=H varies a "
                        "parameter, NAME=V fixes it (repeatable)")
    p.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                   help="progress bar on stderr for design tables (default: on a terminal)")
    p.add_argument("--backend", choices=("cpu", "cuda", "dask"), default="cpu",
                   help="where a design table runs: cpu (this machine's cores, the default), "
                        "cuda (a GPU) or dask (a cluster: --scheduler, or a local one)")
    p.add_argument("--workers", type=int, metavar="K",
                   help="cpu: threads (default: every core); dask without --scheduler: "
                        "local worker processes (default 2)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="--backend dask: the dask.distributed scheduler to use")
    p.add_argument("--sensitivities", metavar="PARAMS",
                   help="add the columns dX4/dPARAM (exact derivatives, "
                        "docs/reference/sensitivities.md) of every "
                        "quantity printed: comma-separated parameters, or all")
    p.add_argument("--reduce", action="append", metavar="NAMES",
                   help="a design table of reductions: per design the min, max and their "
                        "times of these quantities (comma-separated, e.g. X4,X4d; a "
                        "driver's name at --level static or dynamic: its effort), not "
                        "every point")
    solve_options(p)
    p.set_defaults(func=cmd_sweep)

    p = sub.add_parser("singularities", help="times where the Jacobian loses rank",
                       description="Lock (toggle) positions and dead-centre crossings "
                                   "between --t0 and --t1 along the branch the guess starts "
                                   "on, each with the constraints that lose rank.")
    common(p)
    span(p, 201)
    p.add_argument("--guess", action="append", metavar="NAME=VALUE",
                   help="start value of a coordinate (repeatable; picks the branch)")
    p.set_defaults(func=cmd_singularities)
