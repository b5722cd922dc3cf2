"""The drawing's glyphs as Bokeh columns: layers in drawing order (view.geometry's
pieces sorted by depth, the traced paths between the bodies and the pins), each row a
glyph in the frame it moves with, and one table of local vertices for all of them, which
the page's script (view.scripts) turns by the frames' poses at the time shown."""
from __future__ import annotations

import numpy as np

TRACE_Z = 4.4            # traced paths: over the bodies, under the pins (as in draw())
INK = "#222222"


def layers_of(picture):
    """The glyphs as Bokeh layers, in drawing order: [(kind, rows, owner)], kind
    "patches", "lines" or "dots"; traced paths go between the layers below TRACE_Z and
    those above it (the index where they go is returned too)."""
    pieces = sorted(picture.pieces, key=lambda p: p["z"])
    out, cut = [], None
    for p in pieces:
        kind = {"patch": "patches", "line": "lines", "segs": "lines", "dots": "dots"}[p["kind"]]
        if cut is None and p["z"] >= TRACE_Z:
            cut = len(out)
            out.append(None)                  # the place of the traced paths
        if not out or out[-1] is None or out[-1][0] != kind:
            out.append((kind, []))
        out[-1][1].append(p)
    if cut is None:
        cut = len(out)
        out.append(None)
    layers = [x for x in out if x is not None]
    return layers, cut


def layer_data(kind, pieces):
    """A layer's columns: (rows, vertices). ``rows``: frame, owner (a body's name or
    "joints") and style a row, and where its local vertices lie in ``vertices``
    (start, count); ``vertices``: vx, vy, every row's in a row (two flat arrays are one
    message each: far quicker to send than a list of short arrays). Dots carry their
    one point in the row (lx, ly) and have no vertices."""
    cols = {"frame": [], "owner": []}
    style = {"patches": ("fill_color", "fill_alpha", "line_color", "line_width"),
             "lines": ("line_color", "line_alpha", "line_width"),
             "dots": ("color", "size")}[kind]
    for s in style:
        cols[s] = []
    flat, at = [], 0
    if kind == "dots":
        cols["lx"], cols["ly"] = [], []
    else:
        cols["start"], cols["count"] = [], []
    for p in pieces:
        rows = p["segs"] if p["kind"] == "segs" else \
            (list(p["xy"]) if p["kind"] == "dots" else [p["xy"]])
        for xy in rows:
            xy = np.asarray(xy, dtype=float)
            if kind == "dots":
                cols["lx"].append(float(xy[0]))
                cols["ly"].append(float(xy[1]))
            else:
                flat.append(xy)
                cols["start"].append(at)
                cols["count"].append(len(xy))
                at += len(xy)
            cols["frame"].append(p["frame"])
            cols["owner"].append(p.get("owner", ""))
            if kind == "patches":
                cols["fill_color"].append(p["fill"] or "#ffffff")
                cols["fill_alpha"].append(p["fill_alpha"] if p["fill"] else 0.0)
                cols["line_color"].append(p["line"] or INK)
                cols["line_width"].append(p["width"])
            elif kind == "lines":
                cols["line_color"].append(p["line"] or INK)
                cols["line_alpha"].append(p["alpha"])
                cols["line_width"].append(p["width"])
            else:
                cols["color"].append(p["line"] or INK)
                cols["size"].append(p["size"])
    if kind == "dots":
        cols["x"], cols["y"] = list(cols["lx"]), list(cols["ly"])
        return cols, {"vx": np.zeros(0), "vy": np.zeros(0)}
    V = np.concatenate(flat) if flat else np.zeros((0, 2))
    # the drawn vertices: the page's script fills them (empty lists cost nothing to send)
    cols["xs"], cols["ys"] = [[] for _ in cols["frame"]], [[] for _ in cols["frame"]]
    return cols, {"vx": V[:, 0].copy(), "vy": V[:, 1].copy()}


def drawing_columns(picture):
    """Every layer's columns with one vertex table for all of them (one message when a
    body's shape changes): (layers, cut, [rows], vertices); see layers_of, layer_data."""
    layers, cut = layers_of(picture)
    out, xs, ys, at = [], [], [], 0
    for kind, pieces in layers:
        rows, v = layer_data(kind, pieces)
        if "start" in rows:
            rows["start"] = [a + at for a in rows["start"]]
            at += len(v["vx"])
            xs.append(v["vx"])
            ys.append(v["vy"])
        out.append(rows)
    verts = {"vx": np.concatenate(xs) if xs else np.zeros(0),
             "vy": np.concatenate(ys) if ys else np.zeros(0)}
    return layers, cut, out, verts


def placed(cols, verts, data, i=0) -> dict:
    """A layer's rows with their drawn vertices at time index i of the cycle's columns
    (what the page's script does in the browser, done once in Python for the first paint)."""
    def pose(f):
        if f == 0 or f"f{f}x" not in data or not len(data[f"f{f}x"]):
            return 0.0, 0.0, 1.0, 0.0
        a = float(data[f"f{f}a"][i]) if f"f{f}a" in data else 0.0
        return float(data[f"f{f}x"][i]), float(data[f"f{f}y"][i]), np.cos(a), np.sin(a)
    out = dict(cols)
    if "x" in cols:
        xy = [pose(f) for f in cols["frame"]]
        out["x"] = [ox + c * x - s * y for (ox, oy, c, s), x, y in zip(xy, cols["lx"], cols["ly"])]
        out["y"] = [oy + s * x + c * y for (ox, oy, c, s), x, y in zip(xy, cols["lx"], cols["ly"])]
        return out
    xs, ys = [], []
    for f, a, k in zip(cols["frame"], cols["start"], cols["count"]):
        ox, oy, c, s = pose(f)
        x, y = verts["vx"][a:a + k], verts["vy"][a:a + k]
        xs.append(ox + c * x - s * y)
        ys.append(oy + s * x + c * y)
    out["xs"], out["ys"] = xs, ys
    return out


def label_data(picture) -> dict:
    labels = picture.labels
    return {"lx": [0.0] * len(labels), "ly": [0.0] * len(labels),
            "frame": [lab["frame"] for lab in labels], "text": [lab["text"] for lab in labels],
            "dx": [lab["dx"] for lab in labels], "dy": [-lab["dy"] for lab in labels],
            "color": [lab["color"] or INK for lab in labels],
            "x": [0.0] * len(labels), "y": [0.0] * len(labels)}


def same_rows(old, new) -> bool:
    """Whether a layer's rows are unchanged but for the drawn vertices (which the page's
    script recomputes): then only its vertices are sent."""
    keys = [k for k in new if k not in ("xs", "ys", "x", "y")]
    return set(old) == set(new) and all(list(old[k]) == list(new[k]) for k in keys)
