"""``mechgen tolerance``: tolerance and clearance bands of quantities over a sweep
(docs/reference/sensitivities.md, mech.tolerance), drawn against time (mechgen.plot.bands)
with the stack-up table of
each quantity printed at the time where its worst-case band is widest."""
from __future__ import annotations

import argparse

import numpy as np

from ..errors import MechgenError
from .loading import mechanism
from .options import number, number_type, output_file, parse_guess, positive_type, written
from .tables import times

METHODS = ("worst", "rss", "montecarlo")
DESCRIPTION = (
    "Sweep the model from --t0 to --t1 and draw how far each NAME may move when the "
    "parameters move within their tolerances (--tol) and revolute joints have radial "
    "clearance (--clearance): the nominal curve, the linear worst case (shaded), the RSS "
    "band (±3σ, σ = tol/3, shaded darker) and the Monte Carlo envelope (dashed: the "
    "minimum and maximum over --samples random designs, each tolerance uniform in its "
    "interval and each clearance uniform in its disc, solved exactly). Without --method "
    "all three are drawn; with it, that one. The stack-up table of each NAME is printed "
    "at the time where its worst-case band is widest: each tolerance's and clearance's "
    "share |dNAME/dp|·tol (c·|dNAME/de| for a clearance).")


def parse_tol(items) -> dict:
    """--tol NAME=T (±T) or NAME=LOW:HIGH (the deviations, LOW <= 0 <= HIGH)."""
    out = {}
    for item in items or ():
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name or not text.strip():
            raise MechgenError(f"--tol takes NAME=T or NAME=LOW:HIGH, got {item!r}")
        try:
            if ":" in text:
                low, high = text.split(":")
                value = (number(low), number(high))
            else:
                value = number(text)
        except ValueError:
            raise MechgenError(f"--tol {item!r}: give NAME=T (±T) or NAME=LOW:HIGH with "
                               "numbers, e.g. longitud=0.01 or altura=-0.02:0.01") from None
        if name in out:
            raise MechgenError(f"--tol {name!r} is given twice")
        out[name] = value
    return out


def parse_clearance(items) -> dict:
    """--clearance JOINT=C: a revolute's radial clearance."""
    out = {}
    for item in items or ():
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise MechgenError(f"--clearance takes JOINT=C (a revolute's name), got {item!r}")
        try:
            out[name] = number(text)
        except ValueError:
            raise MechgenError(f"--clearance {item!r}: {text!r} is not a number") from None
    return out


def default_names(mech) -> list:
    """What is drawn when no NAME is given: the declared outputs of order 0, else the
    last coordinate (the output link's, in most models)."""
    outs = [o for o, order in zip(mech.outputs, mech.output_orders) if order == 0]
    return outs[:2] if outs else [mech.coordinates[-1]]


def stackup(band, name, bands, length=None, time=None) -> str:
    """The stack-up table of ``name`` at the point where its worst-case band is widest."""
    from ..plot.bands import label_of
    from ..plot.timeplot import model_units
    mech = band.mechanism
    length, time, _ = model_units(mech, length, time)     # the numbers stay in radians
    k = band.worst_index(name)
    shares = band.contributions(name)
    params, offsets = band.gradients(name)
    at = (lambda a: float(np.asarray(a, dtype=float).reshape(len(band.times), -1)[k, 0]))
    total = sum(at(v) for v in shares.values())
    nominal = at(bands[next(iter(bands))][name]["nominal"])
    rows = [("term", "tolerance", f"|d{name}/d term|", "contribution", "share")]
    for p, g in params.items():
        lo, hi = band.tolerances[p]
        tol = f"±{hi:g}" if lo == -hi else f"{lo:+g}/{hi:+g}"
        rows.append((p, tol, f"{abs(at(g)):.6g}", f"{at(shares[p]):.6g}",
                     f"{100 * at(shares[p]) / total:.1f} %" if total else "-"))
    for c, ge in offsets.items():
        g = float(np.sqrt(np.sum(np.asarray(ge, dtype=float).reshape(
            len(band.times), -1, 2)[k, 0] ** 2)))
        rows.append((c, f"clearance {band.clearances[c]:g}", f"{g:.6g}", f"{at(shares[c]):.6g}",
                     f"{100 * at(shares[c]) / total:.1f} %" if total else "-"))
    widths = [max(len(r[i]) for r in rows) for i in range(5)]
    lines = [f"{label_of(mech, name, length, time)} at T = {band.times[k]:.6g} (where the "
             f"worst-case band is widest): nominal {nominal:.10g}"]
    lines += ["  " + "  ".join(c.ljust(w) if i < 2 else c.rjust(w)
                               for i, (c, w) in enumerate(zip(r, widths))) for r in rows]
    for method, b in bands.items():
        got = b[name]
        low, high = at(got["low"]), at(got["high"])
        said = {"worst": "worst case", "rss": "RSS (±3σ)", "montecarlo": "Monte Carlo"}[method]
        extra = f"  ({b.used:,} of {b.samples:,} samples)" if method == "montecarlo" else ""
        lines.append(f"  {said:<12} {low:.10g} .. {high:.10g}  ({low - nominal:+.4g}, "
                     f"{high - nominal:+.4g}){extra}")
    return "\n".join(lines)


def cmd_tolerance(args):
    tols = parse_tol(args.tol)
    clears = parse_clearance(args.clearance)
    if not tols and not clears:
        raise MechgenError("give at least one --tol NAME=T or --clearance JOINT=C")
    if args.n < 2:
        raise MechgenError(f"-n must be at least 2 for a band over time, got {args.n}")
    methods = [args.method] if args.method else list(METHODS)
    if "montecarlo" not in methods and (args.samples is not None or args.seed is not None):
        raise MechgenError("--samples and --seed are for the Monte Carlo band (--method "
                           "montecarlo, or no --method)")
    if args.samples is not None and args.samples < 1:
        raise MechgenError(f"--samples must be at least 1, got {args.samples}")
    ts = times(args.t0, args.t1, args.n)
    if args.output:
        output_file(args.output)
    import matplotlib
    matplotlib.use("Agg")       # files only: no window
    import matplotlib.pyplot as plt

    from ..plot.bands import band_plot, terms
    from ..plot.timeplot import needed_level
    mech = mechanism(args)
    names = list(args.names) or default_names(mech)
    try:
        level = needed_level(mech, names)
    except KeyError as exc:
        raise MechgenError(exc.args[0]) from None
    sw = mech.sweep(ts[0], ts[-1], len(ts), level=level, guess=parse_guess(args.guess),
                    times=ts)
    mc = {"samples": 10_000 if args.samples is None else args.samples, "seed": args.seed,
          "backend": args.backend, "workers": args.workers}
    bands = {m: mech.tolerance(sw, tols, clearance=clears, method=m,
                               **(mc if m == "montecarlo" else {})) for m in methods}
    tables = [stackup(bands[methods[0]], name, bands, args.length, args.time) for name in names]
    # per NAME a row: its value with the bands (left), the bands less the nominal (right)
    fig, axes = plt.subplots(len(names), 2, sharex=True, squeeze=False,
                             figsize=(12.0, 1.2 + 3.3 * len(names)))
    try:
        for i, name in enumerate(names):
            for j, deviation in enumerate((False, True)):
                band_plot(bands, name, ax=axes[i, j], length=args.length, time=args.time,
                          title="", deviation=deviation, legend=(i, j) == (0, 0))
                if i < len(names) - 1:
                    axes[i, j].set_xlabel("")
        fig.suptitle(f"{mech.name}: tolerance bands ({terms(bands[methods[0]])})",
                     fontsize="medium")
        fig.tight_layout()
        path = output_file(args.output or f"{mech.name}_tolerance.png")
        with written(path) as tmp:
            fig.savefig(tmp, dpi=args.dpi)
    finally:
        plt.close(fig)
    print("\n\n".join(tables))
    print(f"wrote {path} ({', '.join(names)} over {len(sw)} points; "
          f"{', '.join(methods)})")


class _Intermixed(argparse.ArgumentParser):
    """A parser whose positionals may come after options (``MODEL.py --tol a=0.1 X4``):
    argparse gives a positional of nargs="*" nothing once it has passed it."""

    _mixing = False

    def parse_known_args(self, args=None, namespace=None):
        if self._mixing:
            return super().parse_known_args(args, namespace)
        self._mixing = True
        try:
            return self.parse_known_intermixed_args(args, namespace)
        finally:
            self._mixing = False


def add_command(sub, add_common):
    """Add ``tolerance`` to the ``mechgen`` parser."""
    p = sub.add_parser("tolerance", help="tolerance and clearance bands of quantities over "
                                         "time (worst case, RSS, Monte Carlo)",
                       description=DESCRIPTION)
    p.__class__ = _Intermixed           # NAMEs after the options, as well as before them
    add_common(p)
    p.add_argument("names", nargs="*", metavar="NAME",
                   help="quantities: a coordinate (X4), its rate (X4d, X4dd), a declared "
                        "output, or a point's global coordinate (coupler[3].x); default: "
                        "the declared outputs (the first two), else the last coordinate")
    p.add_argument("--tol", action="append", metavar="PARAM=T",
                   help="a parameter's tolerance: PARAM=T is ±T, PARAM=LOW:HIGH the "
                        "deviations (LOW <= 0 <= HIGH), e.g. altura=-0.02:0.01 (repeatable)")
    p.add_argument("--clearance", action="append", metavar="JOINT=C",
                   help="a revolute joint's radial clearance C: its pin centres may be any "
                        "|e| <= C apart (repeatable; JOINT: its name=, label or number)")
    p.add_argument("--method", choices=METHODS, default=None,
                   help="draw one band: worst (linear worst case), rss (±3σ, σ = tol/3) or "
                        "montecarlo (exact, random designs); default: all three")
    p.add_argument("--samples", type=int, default=None,
                   help="Monte Carlo designs (default 10000)")
    p.add_argument("--seed", type=int, default=None,
                   help="Monte Carlo random seed (default: a fresh one each run)")
    p.add_argument("--backend", choices=("cpu", "cuda", "dask"), default="cpu",
                   help="where the Monte Carlo's design table runs (default cpu)")
    p.add_argument("--workers", type=int, metavar="K",
                   help="cpu threads of the Monte Carlo's design table (default: every core)")
    p.add_argument("--t0", type=number_type, default=0.0, help="first time (default 0)")
    p.add_argument("--t1", type=number_type, default=1.0, help="last time (default 1)")
    p.add_argument("-n", type=int, default=101,
                   help="number of times, both ends included (default 101)")
    p.add_argument("--guess", action="append", metavar="NAME=VALUE",
                   help="start value of a coordinate (repeatable; picks an assembly mode)")
    p.add_argument("-o", "--output", metavar="FILE",
                   help="the picture to write (default: MODEL_NAME_tolerance.png here)")
    p.add_argument("--dpi", type=positive_type(2000), default=100, help="resolution")
    p.add_argument("--length", metavar="UNIT",
                   help="the unit of the model's lengths, e.g. mm (default: the model's "
                        "declared units, else none stated)")
    p.add_argument("--time", metavar="UNIT",
                   help="the unit of the model's time T (default: the model's, else s)")
    p.set_defaults(func=cmd_tolerance)
    return p


__all__ = ["add_command", "cmd_tolerance", "parse_clearance", "parse_tol"]
