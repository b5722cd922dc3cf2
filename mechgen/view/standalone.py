"""``mechgen view MODEL.py --html out.html``: the view as one self-contained file (no
server, no Python): a table of cycles precomputed over a grid of the parameters' ranges,
from which the page shows the cycle nearest the sliders (view.scripts.PICK). The same
page is what ``mech.explore()`` shows in a notebook.

Size: a cycle is stored as float32 columns of the frames' poses, the traced paths and
the quantities the plots may show (the outputs with their derivatives, the drivers'
efforts and the quantities the plots start with); ``max_cycles`` bounds the grid."""
from __future__ import annotations

import itertools

import numpy as np
from bokeh.models import ColumnDataSource, CustomJS

from .cycle import DRIVER
from .layers import drawing_columns, layer_data, layers_of
from .page import Page
from .scripts import PICK

MAX_CYCLES = 125
MAX_STEPS = 41           # values of one parameter, when it is the only one varied


def _values(ex, name, steps):
    """``steps`` values over a parameter's range, its current value among them."""
    lo, hi = ex.ranges[name]
    return np.unique(np.append(np.linspace(lo, hi, steps), ex.params[name]))


def grid_of(ex, vary, steps, max_cycles):
    """{parameter: values} of the table: ``steps`` values over each varied parameter's
    range (its current value among them). Without ``steps``, as many as keep the grid
    (current values included) within max_cycles; where even two steps each would not,
    and the parameters to vary were not named, the first parameters that fit vary (the
    others keep their values: their sliders are disabled on the page)."""
    named = vary is not None
    vary = list(ex.params) if vary is None else list(vary)
    unknown = [v for v in vary if v not in ex.params]
    if unknown:
        raise ValueError(f"vary: '{ex.mech.name}' has no parameter "
                         f"{', '.join(map(repr, unknown))} (parameters: {', '.join(ex.params)})")
    if steps is None:
        def size(names, k):
            return int(np.prod([len(_values(ex, n, k)) for n in names]))
        fit = None
        for count in ([len(vary)] if named else range(len(vary), 0, -1)):
            fit = next(((count, k) for k in range(MAX_STEPS, 1, -1)
                        if size(vary[:count], k) <= max_cycles), None)
            if fit is not None:
                break
        count, steps = fit if fit is not None else (len(vary), 2)
        vary = vary[:count]
    out = {}
    for name in ex.params:
        if name in vary:
            out[name] = _values(ex, name, steps)
        else:
            out[name] = np.array([ex.params[name]])
    total = int(np.prod([len(v) for v in out.values()]))
    if total > 4 * max_cycles:
        raise ValueError(f"the table would hold {total} cycles; vary fewer parameters or "
                         f"take fewer steps (at most {4 * max_cycles})")
    return out


def _failing(ex, grid) -> dict:
    """{parameter values: time it stops} of the grid's designs that cannot run the cycle,
    from one design table (the compiled module's, all cores): a failing sweep of its own
    would explain its failure at length, a quarter of a second each."""
    varied = {k: v for k, v in grid.items() if len(v) > 1}
    if not varied:
        return {}
    fixed = {k: float(v[0]) for k, v in grid.items() if len(v) == 1}
    mech = ex.mech.with_params(**fixed)
    tab = mech.sweep(ex.t0, ex.t1, ex.n, params=varied, on_fail="ignore")
    out = {}
    for values, t, _ in tab.failures:
        key = tuple(float(values[k]) if k in values else fixed[k] for k in grid)
        out[key] = float(t)
    return out


def kept_columns(ex) -> list:
    """The columns a standalone cycle keeps (see the module's docstring)."""
    keep = {"t"} | set(ex.plots)
    for o in ex.mech.outputs:
        keep |= {o, o + "d", o + "dd"}
    keep |= {c for c in ex.names if c.startswith(DRIVER)}
    keep |= {c for c in ex.names if c[:1] == "f" and c[1:-1].isdigit()}
    keep |= {c for c in ex.names if c.startswith("tr") and c[2:-1].isdigit()}
    return [c for c in ex.names if c in keep]


def standalone_page(ex, vary=None, steps=None, max_cycles=MAX_CYCLES):
    """The page (a Bokeh layout) with its table of precomputed cycles."""
    grid = grid_of(ex, vary, steps, max_cycles)
    names = kept_columns(ex)
    ex.quantities = [q for q in ex.quantities if q in names]
    page = Page(ex, server=False)
    page.cycle.data = {name: np.asarray(ex.data[name], dtype=np.float32) for name in names}
    base = dict(ex.params)
    picture0 = ex.picture
    layers0, _ = layers_of(picture0)
    kinds = [k for k, _ in layers0]
    cols = {name: [] for name in names}
    shapes = [{key: [] for key in list(layer_data(k, p)[0]) + ["cycle"]} for k, p in layers0]
    points = {"vx": [], "vy": []}          # every drawing's vertices, one after another
    spans = {}                             # drawing -> (its first vertex, past its last)
    at = 0
    start, count, message, shape_of, seen = [], [], [], [], {}
    notes = []           # what each cycle's solve warned of its assembly mode (or "")
    first_at = 0
    initial = None
    failing = _failing(ex, grid)
    for index, values in enumerate(itertools.product(*grid.values())):
        params = dict(zip(grid, (float(v) for v in values)))
        stop = failing.get(tuple(params.values()))
        warned = ""
        if stop is None:
            data, _, said = ex.compute(params)
            warned = "" if said else getattr(ex, "warning", "")
            if not said:
                page.fit(ex.extent)         # the frame takes in every cycle's drawing
        else:            # a cycle the table says cannot be solved: its message alone
            varied = [k for k in grid if len(grid[k]) > 1]
            said = ex._cannot(ex.mech.with_params(**params), params, varied,
                              f"the cycle stops at T = {stop:.6g}")
            data = {name: np.zeros(0) for name in names}
        if all(params[k] == base[k] for k in base):
            initial = index
        n = len(data["t"])
        start.append(first_at)
        count.append(n)
        message.append(said)
        notes.append(warned)
        first_at += n
        for name in names:
            cols[name].append(np.asarray(data[name], dtype=np.float32))
        if id(ex.picture) in seen:       # the same glyphs as a cycle before
            shape_of.append(seen[id(ex.picture)])
            continue
        seen[id(ex.picture)] = len(seen)
        shape_of.append(seen[id(ex.picture)])
        layers, _, all_rows, verts = drawing_columns(ex.picture)
        if [k for k, _ in layers] != kinds:      # drawn otherwise: the first drawing's
            _, _, all_rows, verts = drawing_columns(picture0)
        spans[seen[id(ex.picture)]] = (at, at + len(verts["vx"]))
        points["vx"].append(verts["vx"])
        points["vy"].append(verts["vy"])
        for m, rows in enumerate(all_rows):
            if "start" in rows:            # into the table's vertices
                rows["start"] = [a + at for a in rows["start"]]
            for key, col in rows.items():
                shapes[m][key] += list(col)
            shapes[m]["cycle"] += [seen[id(ex.picture)]] * len(rows["frame"])
        at += len(verts["vx"])
    cycles = ColumnDataSource({k: np.concatenate(v) if v else np.zeros(0, np.float32)
                               for k, v in cols.items()}, name="table_cycles")
    table = ColumnDataSource({"start": start, "count": count, "message": message,
                              "note": notes,
                              "shape": shape_of, "vbase": [spans[k][0] for k in shape_of],
                              "vend": [spans[k][1] for k in shape_of]},
                             name="table")
    shape_sources = [ColumnDataSource(s, name=f"table_layer{m}") for m, s in enumerate(shapes)]
    vert_source = ColumnDataSource({k: np.concatenate(v) if v else np.zeros(0)
                                    for k, v in points.items()}, name="table_verts")
    sliders = [page.sliders[name] for name in grid]
    about = ("A page without a server: the cycles were computed beforehand for " +
             ", ".join(f"{k} in {len(v)} values" for k, v in grid.items() if len(v) > 1) +
             "; the nearest is shown.")
    for name in grid:
        if len(grid[name]) == 1:
            page.sliders[name].disabled = True
            page.spinners[name].disabled = True
    pick = CustomJS(args=dict(sliders=sliders, grids=[list(map(float, g)) for g in grid.values()],
                              table=table, cycles=cycles, names=names,
                              layers=page.layers[:len(kinds)], shapes=shape_sources,
                              verts=page.verts, points=vert_source,
                              message=page.message, cycle=page.cycle, note=page.note,
                              about=about), code=PICK)
    for s in sliders:
        s.js_on_change("value", pick)
    first = initial if initial is not None else 0     # the cycle the page opens on
    page.cycle.data = {name: cols[name][first] for name in names}
    page.message.text = message[first]
    page.note.text = about + ("\nNote: " + notes[first] if notes[first] else "")
    page.message.visible = bool(message[first])
    page.table = (grid, table, cycles)
    return page


def page_html(page, resources="inline") -> str:
    """The page as one HTML file: its layout in a Bokeh Document of its own that draws
    the mechanism once BokehJS has loaded it (document_ready), BokehJS embedded in the
    file (``resources="inline"``: it draws without the internet) or loaded from Bokeh's
    CDN (``"cdn"``)."""
    from bokeh.document import Document
    from bokeh.embed import file_html
    from bokeh.resources import CDN, INLINE
    doc = Document()
    doc.add_root(page.layout)
    doc.js_on_event("document_ready", page.redraw)
    return file_html(doc, INLINE if resources == "inline" else CDN,
                     title=f"mechgen view: {page.ex.mech.name}")


def write_html(ex, path, vary=None, steps=None, max_cycles=MAX_CYCLES):
    """Write the standalone page to ``path``; returns the page."""
    page = standalone_page(ex, vary, steps, max_cycles)
    html = page_html(page)
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(html)
    return page
