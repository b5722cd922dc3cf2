"""``mechgen synthesize POSES.csv [--points 5] [-o fourbar.py] [--png FILE]``: every four-bar
that guides a body through 3, 4 or 5 poses (Burmester, docs/reference/synthesis.md) as a table
(pivots, link lengths, Grashof type, defects, transmission angle range); ``-o`` writes the best
defect-free one as a model file that ``mechgen build`` compiles, ``--png`` draws the poses, the
curves or Burmester points and that four-bar at every pose.

POSES.csv: one pose a line, ``x, y, angle`` (radians; ``--degrees`` for degrees), blank
lines and ``#`` comments skipped, a first line of names (``x,y,angle``) allowed."""
from __future__ import annotations

import csv
import math
import os

from ..errors import MechgenError
from .options import module_folder, number, output_file, written


def read_poses(path, degrees=False):
    """The poses of a CSV file: a list of (x, y, angle radians); a MechgenError naming the
    file and line of the first bad row."""
    try:
        with open(path, newline="", encoding="utf-8") as fh:
            lines = list(fh)
    except FileNotFoundError:
        raise MechgenError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise MechgenError(f"{path}: cannot be read ({exc})") from None
    poses, first = [], True
    for lineno, line in enumerate(lines, start=1):
        text = line.split("#", 1)[0].strip()
        if not text:
            continue
        cells = [c.strip() for c in next(csv.reader([text]))]
        if first and cells and all(_is_name(c) for c in cells):
            first = False
            continue                                # a header line: x, y, angle
        first = False
        if len(cells) != 3:
            raise MechgenError(f"{path}:{lineno}: expected three values x, y, angle, got "
                               f"{len(cells)} ({text!r})")
        values = []
        for what, c in zip(("x", "y", "angle"), cells):
            try:
                v = number(c)
            except ValueError:
                raise MechgenError(f"{path}:{lineno}: {what} {c!r} is not a number") from None
            if not math.isfinite(v):
                raise MechgenError(f"{path}:{lineno}: {what} is {c!r}, not a finite number")
            values.append(v)
        if degrees:
            values[2] = math.radians(values[2])
        poses.append(tuple(values))
    if not poses:
        raise MechgenError(f"{path}: no poses in it (one a line: x, y, angle)")
    return poses


def _is_name(cell) -> bool:
    try:
        number(cell)
        return False
    except ValueError:
        return bool(cell) and cell[0].isalpha()


def _chosen(args, poses):
    n = len(poses)
    if args.points is None:
        if n > 5:
            raise MechgenError(f"{args.poses}: {n} poses; at most 5 are met exactly "
                               "(--points K uses the first K)")
        if n < 3:
            raise MechgenError(f"{args.poses}: {n} pose{'s' * (n != 1)}; at least 3 needed")
        return poses
    k = args.points
    if k > n:
        raise MechgenError(f"--points {k}: {args.poses} has only {n} poses")
    if not 3 <= k <= 5:
        raise MechgenError(f"--points {k}: synthesis takes 3, 4 or 5 poses")
    return poses[:k]


def cmd_synthesize(args):
    from .. import synthesis
    if args.output:
        output_file(args.output)
    if args.png:
        output_file(args.png, "--png")
    poses = _chosen(args, read_poses(args.poses, args.degrees))
    try:
        links = synthesis.fourbars(poses, samples=args.samples)
    except ValueError as exc:
        raise MechgenError(f"{args.poses}: {exc}") from None
    outdir = module_folder(args.outdir) if args.outdir else None
    check = (synthesis.SolverCheck(tier="python", outdir=outdir)
             if (args.verify or args.output) else None)
    verdicts = {}
    if args.verify:
        verdicts = {id(f): check(f) for f in links}
    print(f"{len(poses)} poses from {args.poses}; {len(links)} four-bars "
          f"({'every real Burmester pair' if len(poses) == 5 else 'sampled pivots'}, "
          "each dyad once as the crank)")
    if links:
        print(table(links, verdicts))
    best = None
    for f in links:
        if not f.defects and (check is None or not check(f).defects):
            best = f
            break
    if best is None and args.output:
        raise MechgenError(f"no defect-free four-bar among the {len(links)} found: "
                           f"{args.output} not written")
    if best is not None:
        print(f"best defect-free: #{links.index(best) + 1}: {best}")
    if args.output:
        name = synthesis.identifier(args.name or os.path.splitext(
            os.path.basename(args.output))[0])
        text = synthesis.model_source(best, name, os.path.basename(args.poses))
        with written(args.output) as tmp, open(tmp, "w", encoding="utf-8") as fh:
            fh.write(text)
        print(f"wrote {args.output} (model {name!r}: mechgen build {args.output})")
    if args.png:
        _picture(args.png, poses, best or (links[0] if links else None), args.poses)
    return 0


def table(links, verdicts=None) -> str:
    """The four-bars as a text table: pivots, lengths, Grashof type, defects, transmission;
    with ``verdicts`` (SolverCheck's, by id) the solver's defects, a '!' where they differ
    from the closed form's."""
    head = ["#", "O2 (fixed)", "O4 (fixed)", "A (moving)", "B (moving)", "a", "b", "c", "d",
            "Grashof", "defects", "transmission"]
    rows = []
    for k, f in enumerate(links, start=1):
        flags = ", ".join(sorted(f.defects)) or "none"
        v = (verdicts or {}).get(id(f))
        if v is not None and v.defects != f.defects:
            flags = "! " + (", ".join(sorted(v.defects)) or "none") + f" (closed form: {flags})"
        lo, hi = f.transmission
        rows.append([str(k), _pt(f.input.fixed), _pt(f.output.fixed), _pt(f.input.moving),
                     _pt(f.output.moving)] + [f"{x:.4g}" for x in f.lengths]
                    + [f.grashof, flags, f"{lo:.1f}–{hi:.1f}°"])
    widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(head)]
    right = {0, 5, 6, 7, 8}
    out = []
    for r in [head] + rows:
        out.append("  ".join(c.rjust(w) if i in right else c.ljust(w)
                             for i, (c, w) in enumerate(zip(r, widths))).rstrip())
    return "\n".join(out)


def _pt(p) -> str:
    return f"({p[0]:.4g}, {p[1]:.4g})"


def _picture(path, poses, link, source):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .. import synthesis
    from ..plot import synthesis as pictures
    from ..synthesis.poses import place
    extra = {}
    if len(poses) == 4:
        extra = dict(centre=synthesis.centre_point_cubic(poses),
                     circle=synthesis.circle_point_cubic(poses))
    elif len(poses) == 5:
        dyads = [d for d in synthesis.dyads(poses) if d.kind == "RR"]
        extra = dict(fixed=[d.fixed for d in dyads],
                     moving=[place(poses[0], d.moving) for d in dyads])
    title = f"{len(poses)} poses from {os.path.basename(source)}"
    if link is not None:
        lo, hi = link.transmission
        title += (f": four-bar {link.grashof}, {', '.join(sorted(link.defects)) or 'no defects'}"
                  f", transmission {lo:.0f}–{hi:.0f}°")
    ax = pictures.figure(poses, link, title=title, **extra)
    with written(path) as tmp:
        ax.figure.savefig(tmp, dpi=100)
    plt.close(ax.figure)
    print(f"wrote {path}")


def _count(text) -> int:
    import argparse
    if not text.strip().isdigit():
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number")
    return int(text)


def add_command(sub):
    p = sub.add_parser("synthesize", help="four-bars through 3, 4 or 5 poses (Burmester): "
                                          "a table, a model file, a picture",
                       description="Every four-bar whose coupler passes through the poses "
                                   "of POSES.csv (one a line: x, y, angle in radians): for "
                                   "five poses every real Burmester pair, for three or four "
                                   "sampled pivots; each with its Grashof type, its defects "
                                   "(circuit, branch, order) and its transmission angle "
                                   "range, defect-free ones first.")
    p.add_argument("poses", metavar="POSES.csv",
                   help="the poses: x, y, angle per line (a header line and # comments "
                        "allowed)")
    p.add_argument("--points", type=_count, metavar="K",
                   help="use the first K poses (3, 4 or 5; default: all, at most 5)")
    p.add_argument("--degrees", action="store_true", help="angles in degrees, not radians")
    p.add_argument("--samples", type=_count, default=6, metavar="N",
                   help="3 or 4 poses: pivots sampled along the family or curve (default "
                        "6: N×(N−1) four-bars)")
    p.add_argument("-o", "--output", metavar="FILE",
                   help="write the best defect-free four-bar (its defects confirmed by "
                        "its compiled model swept) as a model file for mechgen build")
    p.add_argument("--name", help="the model's name in -o's file (default: the file's)")
    p.add_argument("--outdir", metavar="DIR", default=None,
                   help="folder of the generated module that --verify and -o check the "
                        "four-bars with (default: a temporary folder, removed after)")
    p.add_argument("--png", metavar="FILE",
                   help="draw the poses, the centre- and circle-point curves (4 poses) or "
                        "the Burmester points (5) and the best four-bar at every pose")
    p.add_argument("--verify", action="store_true",
                   help="decide every four-bar's defects with its compiled model too "
                        "(one module built, swept for each; slower)")
    p.set_defaults(func=cmd_synthesize)
