"""The picture commands: ``mechgen draw | animate | plot`` (matplotlib, headless)."""
from __future__ import annotations

import math
import os
import re

from ..errors import MechgenError
from ..protocol import LEVELS
from .loading import mechanism
from .options import number_type, output_file, parse_guess, positive_type, written
from .progress import RenderProgress


def _pictures():
    """pyplot (headless) and mechgen.plot. Imported when a picture command runs, not with
    the parser: the other commands then start without loading matplotlib."""
    import matplotlib
    matplotlib.use("Agg")  # files only: no window, no display needed
    import matplotlib.pyplot as plt

    from .. import plot
    return plt, plot


def _bodies(value):
    """--labels / --axes: a bare flag means every body, else comma-separated names."""
    if value is None:
        return False
    if value == "all":
        return True
    return [v.strip() for v in value.split(",") if v.strip()]


def _output(args, mech, default):
    return output_file(args.output or default.format(name=mech.name))


def _sweep(mech, args, level=LEVELS[0], guess=None):
    if args.n < 1:
        raise MechgenError(f"-n must be at least 1, got {args.n}")
    try:
        return mech.sweep(args.t0, args.t1, args.n, level=level, guess=guess)
    except MechgenError as exc:
        partial = getattr(exc, "sweep", None)
        if partial is None or len(partial) < 2:
            raise
        print(f"mechgen: warning: the sweep stopped at T = {exc.t:.6g} "
              f"({len(partial)} of {args.n} points): {exc}")
        return partial


def cmd_draw(args):
    plt, plot = _pictures()
    mech = mechanism(args)
    path = _output(args, mech, "{name}.png")
    guess = parse_guess(args.guess)
    trace = tuple(args.trace or ())
    for label in trace:                         # an unknown point fails before any solve
        plot.scene.Scene(mech).locate(label)
    if args.static and args.forces is None:
        raise MechgenError("--static goes with --forces (the forces at rest)")
    forces = None if args.forces is None else _bodies(args.forces)
    if forces:
        plot.forceplots.require_forces(mech, "--forces")
        if forces is not True:         # an unknown body fails before any solve
            plot.arrows.check_bodies(mech, forces)
    level = LEVELS[0] if forces is None else "static" if args.static else "dynamic"
    s = mech.solve(args.t, guess=guess, level=level)
    # the paths over --t0 .. --t1, in the drawn configuration's assembly mode
    sw = _sweep(mech, args, guess=s.q) if trace else None
    d = plot.draw(mech, s, sweep=sw, trace=trace, labels=_bodies(args.labels),
                  axes=_bodies(args.axes), legend=args.legend, width=args.width, forces=forces)
    with written(path) as tmp:
        d.figure.savefig(tmp, dpi=args.dpi)
    plt.close(d.figure)
    paths = f"; the path of {', '.join(trace)} over T = {sw.t[0]:g} .. {sw.t[-1]:g}" \
        if trace else ""
    print(f"wrote {path} ({mech.name} at T = {s.t:g}{paths}{_forces_said(d.forces, level)})")


def _forces_said(arrows, level):
    """What the force arrows show, for the line the draw command prints."""
    if arrows is None:
        return ""
    if not arrows.arrows:
        return f"; every force is zero ({level})"
    big = max(arrows.arrows, key=lambda a: math.hypot(*a.force))
    return (f"; {len(arrows.arrows)} forces ({level}), the largest "
            f"{math.hypot(*big.force):.6g} ({big.short} on {big.body})")


def cmd_animate(args):
    plt, plot = _pictures()
    mech = mechanism(args)
    path = _output(args, mech, "{name}.gif")
    plot.check_movie_path(path)
    sw = _sweep(mech, args, guess=parse_guess(args.guess))
    a = plot.animate(mech, sw, None, trace=tuple(args.trace or ()), fps=args.fps,
                     labels=_bodies(args.labels), axes=_bodies(args.axes), legend=args.legend,
                     width=args.width)
    with written(path) as tmp:
        a.save(tmp, dpi=args.dpi, progress=RenderProgress(os.path.basename(path)))
    plt.close(a.figure)
    last = sw.t[len(a) - 1]
    same = "" if len(a) == len(sw) else f"; T = {sw.t[-1]:g} repeats T = {sw.t[0]:g}, left out"
    print(f"wrote {path} ({len(a)} frames, T from {sw.t[0]:g} to {last:g}{same})")


def cmd_plot(args):
    plt, plot = _pictures()
    mech = mechanism(args)
    names = list(args.names) + ([args.x] if args.x else [])
    try:
        level = plot.timeplot.needed_level(mech, names)
    except KeyError as exc:
        raise MechgenError(exc.args[0]) from None
    if args.n < 2:          # one point draws no curve: an empty picture
        raise MechgenError(f"-n must be at least 2 for a plot (a curve), got {args.n}")
    sw = _sweep(mech, args, level=level, guess=parse_guess(args.guess))
    lines = plot.plot(sw, *args.names, x=args.x, length=args.length, time=args.time)
    fig = lines[0].figure
    words = [re.sub(r"\W+", "_", n).strip("_") for n in args.names]   # foot[3].x: foot_3_x
    path = _output(args, mech, "{name}_" + "_".join(words) + ".png")
    with written(path) as tmp:
        fig.savefig(tmp, dpi=args.dpi)
    plt.close(fig)
    print(f"wrote {path} ({', '.join(args.names)} over {len(sw)} points)")


def add_commands(sub, add_common):
    """Add draw, animate and plot to the ``mechgen`` parser. ``-o/--output`` names the
    picture; ``--outdir`` the folder of generated modules (as on every command)."""

    def common(p, image):
        add_common(p)
        p.add_argument("-o", "--output", metavar="FILE",
                       help=f"the picture to write (default: MODEL_NAME{image} here)")
        p.add_argument("--guess", action="append", metavar="NAME=VALUE",
                       help="start value of a coordinate (repeatable; picks an assembly mode)")
        p.add_argument("--dpi", type=positive_type(2000), default=100 if image == ".png" else 80,
                       help="resolution, dots per inch")

    def span(p, n):
        p.add_argument("--t0", type=number_type, default=0.0,
                       help="first time (default 0); a number or an expression such as 2*pi")
        p.add_argument("--t1", type=number_type, default=1.0,
                       help="last time (default 1); a number or an expression")
        p.add_argument("-n", type=int, default=n, help=f"number of times, both ends "
                                                       f"included (default {n})")

    def looks(p):
        p.add_argument("--labels", nargs="?", const="all", metavar="BODIES",
                       help="write P1, P2, ... (every body, or comma-separated names)")
        p.add_argument("--axes", nargs="?", const="all", metavar="BODIES",
                       help="draw local axes (every body, or comma-separated names)")
        p.add_argument("--legend", action="store_true", help="name the bodies in a legend")
        p.add_argument("--width", type=positive_type(100), default=8.0,
                       help="figure width in inches")

    def trace(p, when):
        p.add_argument("--trace", action="append", metavar="POINT",
                       help=f"draw the path of a point{when}: body[k] (the k-th point of a "
                            "body, body[0] its origin), e.g. colisa[2], or body.at(x, y) for "
                            "a point the model does not name, e.g. coupler.at(1.2, 0.8) "
                            "(repeatable; an unknown name lists every point of the model)")

    p = sub.add_parser("draw", help="draw the mechanism at one time (PNG, SVG, PDF)",
                       description="Draw the mechanism at time T: bodies, joints, slots, "
                                   "sliders; framed by its motion over one time unit, or "
                                   "with --trace by the paths over --t0 .. --t1.")
    common(p, ".png")
    p.add_argument("-t", type=number_type, default=0.0,
                   help="the time (default 0); a number or an expression")
    trace(p, " over --t0 .. --t1 (in -n points)")
    span(p, 101)
    looks(p)
    p.add_argument("--forces", nargs="?", const="all", metavar="BODIES",
                   help="force arrows, scaled and labelled (inverse dynamics at T): the pin "
                        "force at every revolute, the drivers' efforts and the loads; or the "
                        "free body diagram of the bodies named (comma-separated)")
    p.add_argument("--static", action="store_true",
                   help="with --forces: the forces at rest (velocities and accelerations "
                        "zero)")
    p.set_defaults(func=cmd_draw)

    p = sub.add_parser("animate", help="animate the mechanism over a time range (GIF, MP4)",
                       description="Animate the mechanism from --t0 to --t1 in -n frames "
                                   "(GIF with pillow; MP4 when ffmpeg is installed).")
    common(p, ".gif")
    span(p, 100)
    p.add_argument("--fps", type=positive_type(1000), default=25.0,
                   help="frames per second (default 25)")
    trace(p, "")
    looks(p)
    p.set_defaults(func=cmd_animate)

    p = sub.add_parser("plot", help="plot quantities against time (PNG, SVG, PDF)",
                       description="Plot coordinates (X4), their derivatives (X4d, X4dd), "
                                   "declared outputs, or a point's global x or y (colisa[2].x, "
                                   "coupler.at(1.2, 0.8).y) against T, or against --x NAME.")
    common(p, ".png")
    p.add_argument("names", nargs="+", metavar="NAME",
                   help="quantities to plot: X4, X4d, an output, or POINT.x / POINT.y for a "
                        "point (body[k] or body.at(x, y)) with nothing declared")
    p.add_argument("--x", metavar="NAME", help="plot against this quantity instead of T")
    p.add_argument("--length", metavar="UNIT", help="the unit of the model's lengths, e.g. mm "
                                                   "(default: the model's units=, else none "
                                                   "stated)")
    p.add_argument("--time", metavar="UNIT", default=None,
                   help="the unit of the model's time T (default: the model's units=, "
                        "else s)")
    span(p, 101)
    p.set_defaults(func=cmd_plot)
