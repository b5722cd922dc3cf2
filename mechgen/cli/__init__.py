"""The command line: mechgen build | equations | check | solve | sweep | singularities | forces |
draw | animate | plot | tolerance | view | synthesize.

One meaning per option on every command: ``-o FILE`` is the file the command writes (a
CSV table, a picture), except ``build -o DIR`` (the contract's); ``--outdir DIR`` is the
folder of generated modules wherever a command builds one.
"""
from __future__ import annotations

import argparse
import os
import sys
import warnings

from ..errors import MechgenError
from ..protocol import LEVELS
from . import (forces_command, plot_commands, simulate_command, solve_commands,
               synthesize_command, tolerance_command, view_command)
from .loading import models
from .options import module_folder, number_type
from .tables import FORCE_LEVELS

DESCRIPTION = ("Kinematics of planar mechanisms: symbolic equations compiled to numba "
               "solvers. Each command takes a model file (MODEL.py); COMMAND --help says "
               "more.")


# -- commands -------------------------------------------------------------------------
def cmd_build(args):
    from ..compiler.build import commit_module, prepare_module, write_module   # late: see
    from ..compiler.render import render                                     # cli.loading
    outdir = module_folder(args.outdir)
    outputs = [o.strip() for o in args.outputs.split(",") if o.strip()] if args.outputs else None
    kwargs = dict(sort=not args.no_sort, level=args.level, outputs=outputs,
                  closed_forms=args.closed_forms)
    if getattr(args, "sensitivities", False) and outputs:
        raise MechgenError("--sensitivities needs every coordinate: build without --outputs")
    # every model rendered before any file is written: one that fails writes none
    built = []
    if args.force:
        texts = [(model, os.path.join(outdir, f"{model.name}.py"), render(model, **kwargs))
                 for model in models(args)]
        for model, path, text in texts:
            built.append((model, write_module(text, path)))
            print(f"wrote {built[-1][1]}")
    else:
        # an unchanged model keeps its module file (and numba's compiled cache of it)
        for model in models(args):
            built.append((model, prepare_module(model, outdir, **kwargs)))
        for k, (model, prepared) in enumerate(built):
            path, written = commit_module(*prepared)
            built[k] = (model, path)
            print(f"wrote {path}" if written
                  else f"{path} is up to date (--force writes it again)")
    if getattr(args, "sensitivities", False):
        from ..compiler.sensitivities import build_sensitivities
        for model, path in built:
            print(f"wrote {build_sensitivities(model, path)}")


def cmd_equations(args):
    from ..model.forces.holds import held
    from ..model.printing import equations_text
    for model in models(args):
        sys.stdout.write(equations_text(held(model), numeric=args.numeric, latex=args.latex,
                                        mathematica_style=args.mathematica))


def cmd_check(args):
    from ..compiler.check import check_report
    ok = True
    for model in models(args):
        text, good = check_report(model, t=args.t, starts=args.starts,
                                  cycle=not args.no_cycle)
        sys.stdout.write(text)
        ok = ok and good
    return 0 if ok else 1


# -- the parser -----------------------------------------------------------------------
def _starts(text) -> int:
    """--starts: a count, 0 or more."""
    if not text.strip().isdigit():
        raise argparse.ArgumentTypeError(f"{text!r} is not a count (0, 1, 2, ...)")
    return int(text)


def _add_common(p, outdir=True):
    """The model file, --model and --outdir (accepted on every command, as the README
    says: ``outdir=False`` for a command that builds no module, where it changes nothing)."""
    p.add_argument("model_file", metavar="MODEL.py", help="the model file")
    p.add_argument("--model", help="which model, when the file defines several")
    if outdir:
        p.add_argument("--outdir", metavar="DIR", default="generated",
                       help="folder of generated modules, built there when missing or out "
                            "of date (default: generated/)")
    elif outdir is False:
        p.add_argument("--outdir", metavar="DIR", default="generated",
                       help="accepted as on every command; this one builds no module, so "
                            "it changes nothing")


def _add_solve_opts(p):
    p.add_argument("--level", choices=LEVELS + FORCE_LEVELS, default=None,
                   help="solve positions, velocities too, or accelerations too (default: "
                        "position, or what --columns needs); static or dynamic: then the "
                        "driver efforts and joint reactions too")
    p.add_argument("--guess", action="append", metavar="NAME=VALUE",
                   help="start value of a coordinate, e.g. X4=1 or Th3=pi/2 (repeatable; "
                        "picks an assembly mode)")
    p.add_argument("--method", choices=("auto", "sorted", "full"), default="auto",
                   help="sorted blocks falling back to full Newton (auto, the default), or "
                        "one of them only")


def parser() -> argparse.ArgumentParser:
    from .. import __version__
    ap = argparse.ArgumentParser(prog="mechgen", description=DESCRIPTION)
    ap.add_argument("--version", action="version", version=f"mechgen {__version__}",
                    help="print the version and exit")
    sub = ap.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True

    p = sub.add_parser("build", help="write the generated solver module(s)",
                       description="Write one module per model of the file, DIR/NAME.py.")
    _add_common(p, outdir=None)
    p.add_argument("-o", "--outdir", metavar="DIR", default="generated",
                   help="folder of generated modules (default: generated/)")
    p.add_argument("--no-sort", action="store_true",
                   help="full Newton only (no block sorting): the reference path")
    p.add_argument("--force", action="store_true",
                   help="render and write the module even when the model has not changed "
                        "(by default an unchanged model's module, and numba's compiled cache "
                        "of it, are kept)")
    p.add_argument("--level", choices=LEVELS, default="acceleration",
                   help="highest derivative level to emit (default acceleration)")
    p.add_argument("--outputs", metavar="NAMES",
                   help="comma-separated outputs to compile (default: all declared)")
    p.add_argument("--closed-forms", choices=("all", "cheap", "none"), default="cheap",
                   help="blocks of a standard form (a sin y + b cos y + c, a quadratic, an "
                        "RRR dyad) solved without iterating: all of them (cheap, the default, "
                        "is the same), or none (Newton on every block)")
    p.add_argument("--sensitivities", action="store_true",
                   help="also write DIR/NAME_sensitivities.py, the derivatives with respect "
                        "to the parameters (otherwise built when a call first asks for them)")
    p.set_defaults(func=cmd_build, all_models=True)

    p = sub.add_parser("equations", help="print Phi, Phi_q, nu and gamma, labelled by "
                                         "constraint")
    _add_common(p, outdir=False)
    p.add_argument("--latex", action="store_true", help="LaTeX instead of plain text")
    p.add_argument("--numeric", action="store_true", help="substitute parameter defaults")
    p.add_argument("--mathematica", action="store_true",
                   help="Mech's notation (Cos[Th3]), to read beside seed 001's printouts")
    p.set_defaults(func=cmd_equations)

    p = sub.add_parser("check", help="counts, degrees of freedom, rank, assembly modes, "
                                     "redundant, missing or contradictory constraints",
                       description="Check a model before building it; exits non-zero when "
                                   "a constraint is missing, a coordinate is left free, the "
                                   "model cannot be assembled at the time given or locks "
                                   "within one period of its turning drivers, or its "
                                   "redundant equations hold there but cannot keep holding "
                                   "(a driver fighting a constraint or another driver).")
    _add_common(p, outdir=False)
    p.add_argument("-t", type=number_type, default=0.0,
                   help="time at which to check (default 0); a number or an expression")
    p.add_argument("--starts", type=_starts, default=128,
                   help="quasi-random starts of the search for assembly modes (default 128)")
    p.add_argument("--no-cycle", action="store_true",
                   help="check at -t only (by default the assembly is followed through one "
                        "period of the drivers that turn, and a driver that locks fails)")
    p.set_defaults(func=cmd_check)

    solve_commands.add_commands(sub, _add_common, _add_solve_opts)
    plot_commands.add_commands(sub, _add_common)
    forces_command.add_command(sub, _add_common)
    simulate_command.add_command(sub, _add_common)
    tolerance_command.add_command(sub, _add_common)
    view_command.add_command(sub, _add_common)
    synthesize_command.add_command(sub)
    return ap


def _quiet_stdout():
    """After a closed pipe (mechgen sweep ... | head): send what is left to /dev/null, so
    that the interpreter's last flush raises nothing either."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):
        pass        # no real file behind stdout (a test's capture): nothing to quiet


def _model_line(exc, args) -> str:
    """ " at FILE:LINE" of the model file's innermost line in exc's traceback, or ""."""
    import traceback
    path = os.path.abspath(getattr(args, "model_file", "") or "")
    for frame in reversed(traceback.extract_tb(exc.__traceback__)):
        if os.path.abspath(frame.filename) == path:
            return f" at {path}:{frame.lineno} (in the model file)"
    return ""


def _format_warning(message, category, filename, lineno, line=None) -> str:
    """A warning as the command prints it: its kind and its words, not the line of
    mechgen's own source that raised it."""
    return f"mechgen: warning: {category.__name__}: {message}\n"


def main(argv=None) -> int:
    """Run one command; returns the exit status (0, 1 on a failure, 2 on a usage error)."""
    args = parser().parse_args(argv)
    previous = warnings.formatwarning
    warnings.formatwarning = _format_warning
    try:
        return _run(args)
    finally:
        warnings.formatwarning = previous


def _run(args) -> int:
    try:
        code = args.func(args)
    except BrokenPipeError:
        _quiet_stdout()
        return 0
    except KeyboardInterrupt as exc:     # Ctrl-C, or a model file that raises it
        print(f"mechgen: interrupted{_model_line(exc, args)}", file=sys.stderr)
        return 130
    except MechgenError as exc:
        kind = "error" if type(exc) is MechgenError else type(exc).__name__
        print(f"mechgen: {kind}: {exc}", file=sys.stderr)
        return 1
    except (ValueError, KeyError, OSError) as exc:
        print(f"mechgen: error: {exc}", file=sys.stderr)
        return 1
    except Exception as exc:        # a defect of mechgen's: still one line, no traceback
        if os.environ.get("MECHGEN_TRACEBACK"):
            raise
        print(f"mechgen: internal error: {type(exc).__name__}: {exc}{_model_line(exc, args)} "
              "(set MECHGEN_TRACEBACK=1 to see where)", file=sys.stderr)
        return 1
    return int(code or 0)
