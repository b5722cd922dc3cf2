"""The command line: ``mechgen build | equations | check | solve | sweep | draw | animate | plot``."""
from __future__ import annotations

import argparse
import os
import sys

from ..errors import MechgenError
from ..protocol import LEVELS
from .options import parse_guess as _parse_guess
from .plot_commands import add_commands


def _models(args):
    from ..model.loader import load_models, pick_model
    models = load_models(args.model_file)
    if getattr(args, "all_models", False):
        return models
    return [pick_model(models, args.model, args.model_file)]


def _build_if_needed(model, outdir, **kwargs) -> str:
    """Write the module unless the file already holds exactly this text."""
    from ..compiler.build import render, write_module
    path = os.path.join(outdir, f"{model.name}.py")
    text = render(model, **kwargs)
    try:
        with open(path, encoding="utf-8") as fh:
            if fh.read() == text:
                return path
    except OSError:
        pass
    return write_module(text, path)


def mechanism(args):
    """Build (when out of date) and load the model the arguments name."""
    from ..runtime import load
    model = _models(args)[0]
    path = _build_if_needed(model, args.outdir)
    return load(path)


def _format_table(header, rows) -> str:
    cells = [[f"{v:.6g}" if isinstance(v, float) else str(v) for v in row] for row in rows]
    widths = [max(len(h), *(len(r[k]) for r in cells)) if cells else len(h)
              for k, h in enumerate(header)]
    out = ["  ".join(h.rjust(w) for h, w in zip(header, widths))]
    out += ["  ".join(c.rjust(w) for c, w in zip(r, widths)) for r in cells]
    return "\n".join(out)


# -- commands -------------------------------------------------------------------------
def cmd_build(args):
    from ..compiler.build import build
    models = _models(args)
    outputs = [o.strip() for o in args.outputs.split(",") if o.strip()] if args.outputs else None
    for model in models:
        kwargs = dict(sort=not args.no_sort, level=args.level, outputs=outputs,
                      closed_forms=args.closed_forms)
        path = build(model, args.outdir, **kwargs)
        print(f"wrote {path}")


def cmd_equations(args):
    from ..model.printing import equations_text
    for model in _models(args):
        sys.stdout.write(equations_text(model, numeric=args.numeric, latex=args.latex,
                                        mathematica_style=args.mathematica))


def cmd_check(args):
    from ..compiler.check import check_report
    ok = True
    for model in _models(args):
        text, good = check_report(model, t=args.t)
        sys.stdout.write(text)
        ok = ok and good
    return 0 if ok else 1


def cmd_solve(args):
    mech = mechanism(args)
    s = mech.solve(args.t, guess=_parse_guess(args.guess), level=args.level, method=args.method)
    rows = [("T", s.t)] + [(k, s[k]) for k in s.keys()]
    if mech.outputs:
        have = LEVELS.index(s.level)
        for k, o in enumerate(mech.outputs):
            for suffix, d in (("", 0), ("d", 1), ("dd", 2)):
                if mech.output_orders[k] + d <= have:
                    rows.append((o + suffix, s[o + suffix]))
    print(f"{mech.name} at T = {s.t:g} ({s.level}; {s.iterations} Newton iterations, "
          f"residual {s.residual:.2g}, {s.method} solver{', SINGULAR' if s.singular else ''})")
    width = max(len(k) for k, _ in rows)
    for k, v in rows:
        print(f"  {k:<{width}} -> {v:.10g}")


def cmd_sweep(args):
    mech = mechanism(args)
    from .options import parse_param_option
    params = parse_param_option(args.param)
    if any(not isinstance(v, float) for v in params.values()):   # a design table
        progress = sys.stderr.isatty() if args.progress is None else args.progress
        tab = mech.design_sweep(args.t0, args.t1, args.n, params, level=args.level,
                                guess=_parse_guess(args.guess), method=args.method,
                                progress=progress or None)
        header, data = tab.table()
        if args.csv:
            tab.to_csv(args.csv)
            print(f"wrote {data.shape[0]} rows ({len(tab)} designs) to {args.csv}")
        else:
            print(_format_table(header, [list(map(float, r)) for r in data]))
        return
    if params:
        mech = mech.with_params(**params)
    sw = mech.sweep(args.t0, args.t1, args.n, level=args.level, guess=_parse_guess(args.guess),
                    method=args.method)
    header, data = sw.table()
    if args.csv:
        sw.to_csv(args.csv)
        print(f"wrote {len(sw)} rows to {args.csv}")
    else:
        print(_format_table(header, [list(map(float, r)) for r in data]))


def _add_common(p, outdir=True):
    p.add_argument("model_file", metavar="MODEL.py", help="the model file")
    p.add_argument("--model", help="which model, when the file defines several")
    if outdir:
        p.add_argument("-o", "--outdir", default="generated",
                       help="folder of generated modules (default: generated/)")


def _add_solve_opts(p):
    p.add_argument("--level", choices=LEVELS, default="position")
    p.add_argument("--guess", action="append", metavar="NAME=VALUE",
                   help="start value of a coordinate (repeatable)")
    p.add_argument("--method", choices=("auto", "sorted", "full"), default="auto",
                   help="sorted blocks (falling back to full Newton), or one of them only")


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="mechgen", description=__doc__.split("\n")[0] + "\n"
                                 "Kinematics of planar mechanisms: symbolic equations compiled "
                                 "to numba solvers.")
    from .. import __version__
    ap.add_argument("--version", action="version", version=f"mechgen {__version__}")
    sub = ap.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True

    p = sub.add_parser("build", help="write the generated solver module(s)")
    _add_common(p)
    p.add_argument("--no-sort", action="store_true",
                   help="full Newton only (no block sorting): the reference path")
    p.add_argument("--level", choices=LEVELS, default="acceleration",
                   help="highest derivative level to emit (default acceleration)")
    p.add_argument("--outputs", help="comma-separated outputs to compile (default: all declared)")
    p.add_argument("--closed-forms", choices=("all", "cheap", "none"), default="cheap",
                   help="blocks of a standard form (a sin y + b cos y + c, a quadratic) solved "
                        "without iterating: all of them, only where that removes all run-time "
                        "trigonometry (default), or none")
    p.set_defaults(func=cmd_build, all_models=True)

    p = sub.add_parser("equations", help="print Φ, Φ_q, ν and γ, labelled by constraint")
    _add_common(p, outdir=False)
    p.add_argument("--latex", action="store_true", help="LaTeX instead of plain text")
    p.add_argument("--numeric", action="store_true", help="substitute parameter defaults")
    p.add_argument("--mathematica", action="store_true",
                   help="Mech's notation (Cos[Th3]), to read beside seed 001's printouts")
    p.set_defaults(func=cmd_equations)

    p = sub.add_parser("check", help="counts, degrees of freedom, rank, redundant constraints")
    _add_common(p, outdir=False)
    p.add_argument("-t", type=float, default=0.0, help="time at which to check (default 0)")
    p.set_defaults(func=cmd_check)

    p = sub.add_parser("solve", help="solve at one time")
    _add_common(p)
    p.add_argument("-t", type=float, required=True, help="the time")
    _add_solve_opts(p)
    p.set_defaults(func=cmd_solve)

    p = sub.add_parser("sweep", help="solve over a range of times")
    _add_common(p)
    p.add_argument("--t0", type=float, default=0.0)
    p.add_argument("--t1", type=float, default=1.0)
    p.add_argument("-n", type=int, default=21, help="number of points, both ends included")
    p.add_argument("--csv", help="write the table to this CSV file instead of printing it")
    p.add_argument("--param", action="append", metavar="NAME=VALUES",
                   help="a design table: NAME=V1,V2,... or NAME=START:STOP:STEP varies a "
                        "parameter, NAME=V fixes it (repeatable)")
    p.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                   help="progress line on stderr for design tables (default: on a terminal)")
    _add_solve_opts(p)
    p.set_defaults(func=cmd_sweep)

    add_commands(sub, _add_common, mechanism)
    return ap


def main(argv=None) -> int:
    args = parser().parse_args(argv)
    try:
        code = args.func(args)
    except MechgenError as exc:
        print(f"mechgen: {type(exc).__name__}: {exc}", file=sys.stderr)
        return 1
    except (ValueError, KeyError, OSError) as exc:
        print(f"mechgen: error: {exc}", file=sys.stderr)
        return 1
    return int(code or 0)


