"""``mechgen forces MODEL.py -t T [--static]``: every driver effort, joint reaction and
contact force (cams, gears, racks) at one time (mechgen.runtime.forces)."""
from __future__ import annotations

from ..runtime.forces.contact import CAM_KINDS
from .loading import mechanism
from .options import number_type, parse_guess


def cmd_forces(args):
    mech = mechanism(args)
    level = "static" if args.static else "dynamic"
    s = mech.solve(args.t, guess=parse_guess(args.guess), level=level, method=args.method)
    print(f"{mech.name} at T = {s.t:g} ({level}: Phi_q^T lambda = Q"
          f"{'' if args.static else ' - M qdd - h'})")
    drivers = [label for _, _, label, _, driver in mech.module.CONSTRAINTS if driver]
    if drivers:
        print("drivers (effort; its power = effort x the rate of the driven quantity)")
        width = max(len(d) for d in drivers)
        for label in drivers:
            print(f"  {label:<{width}}  {s.driver(label) + 0.0:.10g}")
    print("reactions: (fx, fy, moment about the body's origin) that each constraint "
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
    p = sub.add_parser("forces", help="driver efforts and joint reactions at one time",
                       description="Solve the model at time T (positions, velocities, "
                                   "accelerations; positions only with --static), then its "
                                   "multipliers, and print every driver's torque or force "
                                   "and every constraint's reaction on each body.")
    common(p)
    p.add_argument("-t", type=number_type, required=True,
                   help="the time: a number or an expression such as 0.5/pi")
    p.add_argument("--static", action="store_true",
                   help="statics: the loads at rest (velocities and accelerations zero)")
    p.add_argument("--guess", action="append", metavar="NAME=VALUE",
                   help="start value of a coordinate (repeatable; picks an assembly mode)")
    p.add_argument("--method", choices=("auto", "sorted", "full"), default="auto",
                   help="the position solver (as for solve)")
    p.set_defaults(func=cmd_forces)
