"""``mechgen view MODEL.py``: explore a mechanism live in the browser (mechgen.view): the
page's address is printed and opened (not with --no-browser); the model file is watched
and the page redrawn when it changes. ``--html FILE`` writes a self-contained page
instead (cycles precomputed over the parameters' ranges, no server)."""
from __future__ import annotations

import argparse

from ..errors import MechgenError
from .options import model_file, module_folder, number_type, output_file, written

LIVE_TIMES = 1000        # times in a cycle the server solves at every parameter change
HTML_TIMES = 200         # in each precomputed cycle of a standalone page (its size)


def _ranges(items):
    """{name: (low, high)} from NAME=LOW:HIGH options."""
    out = {}
    for item in items or ():
        name, eq, span = item.partition("=")
        low, colon, high = span.partition(":")
        try:
            if not (eq and colon):
                raise ValueError
            out[name.strip()] = (float(number_type(low)), float(number_type(high)))
        except (ValueError, TypeError):
            raise MechgenError(f"--range {item}: write NAME=LOW:HIGH, e.g. longitud=1:4") from None
    return out


def _split_top(text):
    """``text`` cut at the commas outside brackets: "a[1], foot.at(1, 2)" gives "a[1]"
    and "foot.at(1, 2)" (a point's local coordinates keep their comma)."""
    parts, depth, word = [], 0, []
    for ch in text:
        if ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth = max(0, depth - 1)
        if ch == "," and depth == 0:
            parts.append("".join(word))
            word = []
        else:
            word.append(ch)
    parts.append("".join(word))
    return parts


def _names(groups):
    return [n.strip() for g in groups or () for n in _split_top(g) if n.strip()] or None


def explorer_factory(args):
    """A function building the Explorer the arguments describe (again when the file
    changes): the model file compiled (its module loaded on the compiled tier)."""
    from ..bridge import compile_file
    from ..view.explorer import Explorer
    path = model_file(args.model_file)
    outdir = module_folder(args.outdir)
    ranges, trace, plots = _ranges(args.range), _names(args.trace), _names(args.plot)
    n = args.n if args.n is not None else (HTML_TIMES if args.html else LIVE_TIMES)
    if n < 2:
        raise MechgenError(f"-n must be at least 2, got {n}")

    def make():
        mech = compile_file(path, outdir, name=args.model, tier="compiled")
        return Explorer(mech, t0=args.t0, t1=args.t1, n=n, trace=trace, plots=plots,
                        ranges=ranges, path=path)
    return make


def _steps(text) -> int:
    """--steps: two values or more (0 or 1 vary nothing; a negative count is no count)."""
    if not text.strip().isdigit() or int(text) < 2:
        raise argparse.ArgumentTypeError(f"{text!r}: give 2 or more values per parameter")
    return int(text)


def cmd_view(args):
    from ..view import need_bokeh
    need_bokeh()
    make = explorer_factory(args)
    if args.html:
        from ..view.standalone import write_html
        path = output_file(args.html, "--html")
        with written(path) as tmp:
            page = write_html(make(), tmp, vary=_names(args.vary), steps=args.steps)
        grid = page.table[0]
        print(f"wrote {path} (no server: {int(len(page.table[1].data['start']))} cycles "
              f"precomputed over " + ", ".join(f"{k} [{v[0]:.4g}, {v[-1]:.4g}]"
                                                for k, v in grid.items() if len(v) > 1) + ")")
        return 0
    from ..view.server import ViewServer
    make()                           # a model that cannot be viewed fails here, clearly
    server = ViewServer(make, watch=args.model_file, port=args.port).start()
    print(f"mechgen view: {server.url}  (Ctrl-C stops; {args.model_file} is watched)",
          flush=True)
    if not args.no_browser:
        import webbrowser
        webbrowser.open(server.url)
    server.serve_forever()
    return 0


def add_command(sub, common):
    p = sub.add_parser("view", help="explore the mechanism live in the browser",
                       description="Serve a page on 127.0.0.1 (its address is printed): the "
                                   "mechanism drawn, sliders for time and every parameter, "
                                   "traced paths, plots; every parameter change solves the "
                                   "cycle again. The model file is watched: save it and the "
                                   "page is redrawn. --html writes a page that needs no "
                                   "server instead.")
    common(p)
    p.add_argument("--t0", type=number_type, default=0.0, help="start of the cycle (default 0)")
    p.add_argument("--t1", type=number_type, default=1.0, help="end of the cycle (default 1)")
    p.add_argument("-n", type=int, default=None,
                   help=f"times in the cycle (default {LIVE_TIMES}; {HTML_TIMES} with --html)")
    p.add_argument("--trace", action="append", metavar="POINTS",
                   help="points whose paths to draw, e.g. 'colisa[2]' or 'foot.at(1, 2)' "
                        "(comma-separated; repeatable; default the longest paths)")
    p.add_argument("--plot", action="append", metavar="NAMES",
                   help="the quantities the two plots start with (comma-separated)")
    p.add_argument("--range", action="append", metavar="NAME=LOW:HIGH",
                   help="a parameter slider's range (default ±50 %% of its value)")
    p.add_argument("--port", type=int, default=None, help="the port (default: a free one)")
    p.add_argument("--no-browser", action="store_true", help="print the address only")
    p.add_argument("--html", metavar="FILE",
                   help="write a self-contained page (no server) with cycles precomputed "
                        "over the parameters' ranges, then exit")
    p.add_argument("--vary", action="append", metavar="NAMES",
                   help="with --html: the parameters the table varies (default all)")
    p.add_argument("--steps", type=_steps, default=None,
                   help="with --html: values per varied parameter (default: as many as "
                        "keep the table within 125 cycles)")
    p.set_defaults(func=cmd_view)
