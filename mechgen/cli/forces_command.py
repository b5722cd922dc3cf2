"""``mechgen forces MODEL.py -t T [--static]``: every driver effort, joint reaction and
contact force (cams, gears, racks) at one time (mechgen.runtime.forces); ``-o FILE``: a
driver's effort against the quantity it drives over --t0 .. --t1, with its mean and peak
(mechgen.plot.effort)."""
from __future__ import annotations

from ..errors import MechgenError
from ..runtime.forces.contact import CAM_KINDS
from ..units import effort_kind
from ..units import of as units_of
from .loading import mechanism
from .options import number_type, output_file, parse_guess, positive_type, written


def cmd_forces(args):
    if args.t is None and args.output is None:
        raise MechgenError("forces: give -t T (print the forces at T) or -o FILE (plot a "
                           "driver's effort over --t0 .. --t1), or both")
    mech = mechanism(args)
    level = "static" if args.static else "dynamic"
    if args.t is not None:
        print_forces(mech, args, level)
    if args.output is not None:
        plot_effort(mech, args, level)


def plot_effort(mech, args, level):
    from .plot_commands import _pictures
    path = output_file(args.output)
    if args.n < 2:
        raise MechgenError(f"-n must be at least 2, got {args.n}")
    plt, plot = _pictures()
    plot.forceplots.pick_driver(mech, args.driver)      # an unknown driver fails first
    sw = mech.sweep(args.t0, args.t1, args.n, level=level, guess=parse_guess(args.guess),
                    method=args.method)
    e = plot.effort(sw, args.driver)
    with written(path) as tmp:
        e.figure.savefig(tmp, dpi=args.dpi)
    plt.close(e.figure)
    print(f"wrote {path} ({e.line.get_label()} over T = {sw.t[0]:g} .. {sw.t[-1]:g}, "
          f"{len(sw)} points, {level}: mean {e.mean:.10g}, peak {e.peak:.10g})")


def print_forces(mech, args, level):
    s = mech.solve(args.t, guess=parse_guess(args.guess), level=level, method=args.method)
    units = units_of(mech)
    time = f" {units.time}" if units.declared else ""
    print(f"{mech.name} at T = {s.t:g}{time} ({level}: Phi_q^T lambda = Q"
          f"{'' if args.static else ' - M qdd - h'})")
    print(f"units: forces in {units.force}, moments in {units.of('torque')}, lengths in "
          f"{units.length}" if units.declared else
          "units: model units (the model declares none: Model(..., units=\"SI\"))")
    kinds = {label: kind for _, kind, label, _, driver in mech.module.CONSTRAINTS if driver}
    if kinds:
        print("drivers (effort; its power = effort x the rate of the driven quantity)")
        width = max(len(d) for d in kinds)
        for label, kind in kinds.items():
            unit = units.of(effort_kind(kind)) if units.declared else ""
            try:
                effort = f"{s.driver(label) + 0.0:.10g}{' ' + unit if unit else ''}"
            except ValueError:      # a form of equation whose effort is not defined:
                effort = "(not defined for this form of equation; its reactions below)"
            print(f"  {label:<{width}}  {effort}")
    what = f"[{units.force}], fy [{units.force}], moment [{units.of('torque')}]" \
        if units.declared else ", fy, moment"
    print(f"reactions: (fx {what} about the body's origin) that each constraint "
          "applies to each body")
    rows = [(f"{label} on {body}", v) for (label, body), v in s.reactions().items()]
    width = max((len(k) for k, _ in rows), default=0)
    for key, (fx, fy, mo) in rows:
        print(f"  {key:<{width}}  {fx + 0.0:>16.10g} {fy + 0.0:>16.10g} {mo + 0.0:>16.10g}")
    contacts = s.contacts()
    if contacts:
        print("contact forces (a cam's along the normal, positive pushing; gears' tooth "
              "force: the mesh's\n  torque on a gear / its pitch radius; a rack's: the force "
              "on it along its axis)")
        width = max(len(k) for k in contacts)
        for label, value in contacts.items():
            lost = ("  (pulling: the follower has lost contact)"
                    if value < 0 and _is_cam(mech, label) else "")
            print(f"  {label:<{width}}  {value + 0.0:>16.10g}{lost}")
    if s.indeterminate:
        print("indeterminate (redundant constraints; minimum-norm multipliers shown): "
              + "; ".join(s.indeterminate))


def _is_cam(mech, label):
    return any(lab == label and kind in CAM_KINDS
               for _, kind, lab, _, _ in mech.module.CONSTRAINTS)


def add_command(sub, common):
    p = sub.add_parser("forces", help="driver efforts and joint reactions at one time; "
                                      "a driver's effort over a cycle (-o)",
                       description="Solve the model at time T (positions, velocities, "
                                   "accelerations; positions only with --static), then its "
                                   "multipliers, and print every driver's torque or force "
                                   "and every constraint's reaction on each body. With -o "
                                   "FILE, plot a driver's effort against the quantity it "
                                   "drives over --t0 .. --t1 instead (or as well, with -t).")
    common(p)
    p.add_argument("-t", type=number_type, default=None,
                   help="the time: a number or an expression such as 0.5/pi")
    p.add_argument("-o", "--output", metavar="FILE",
                   help="plot a driver's effort (torque or force) against the quantity it "
                        "drives over --t0 .. --t1, with its mean and peak (PNG, SVG, PDF)")
    p.add_argument("--driver", metavar="NAME",
                   help="with -o: which driver (default: the model's only one)")
    p.add_argument("--t0", type=number_type, default=0.0,
                   help="with -o: the first time (default 0)")
    p.add_argument("--t1", type=number_type, default=1.0,
                   help="with -o: the last time (default 1): one cycle")
    p.add_argument("-n", type=int, default=361,
                   help="with -o: number of times, both ends included (default 361)")
    p.add_argument("--dpi", type=positive_type(2000), default=100, help="with -o: dots per inch")
    p.add_argument("--static", action="store_true",
                   help="statics: the loads at rest (velocities and accelerations zero)")
    p.add_argument("--guess", action="append", metavar="NAME=VALUE",
                   help="start value of a coordinate (repeatable; picks an assembly mode)")
    p.add_argument("--method", choices=("auto", "sorted", "full"), default="auto",
                   help="the position solver (as for solve)")
    p.set_defaults(func=cmd_forces)
