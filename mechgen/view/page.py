"""The view's page, in Bokeh: the mechanism drawn as ``mechgen draw`` draws it (its glyphs
moved in the browser from the cycle's poses, view.scripts), the traced paths, a time
slider and a play button, a slider and a typed value for every parameter, two plots of
chosen quantities against time or any other quantity, and a message in place of the
drawing where the mechanism cannot assemble.

The page is the same with a server (view.server: a parameter change solves the cycle in
Python) and without one (view.standalone: the nearest precomputed cycle is picked in the
browser); ``Page.show(columns, picture, message)`` puts a new cycle in.
"""
from __future__ import annotations

import numpy as np
from bokeh.layouts import column, row
from bokeh.models import (Button, ColumnDataSource, CustomJS, Div, Label, Range1d, Select,
                          Slider, Spinner, Toggle)
from bokeh.plotting import figure

from ..units import of as units_of
from .cycle import unit_of
from .layers import INK, drawing_columns, label_data, placed, same_rows
from .scripts import CHOOSE, PLAY, REDRAW, UNPACK

WIDTH = 620              # the drawing's width in pixels
PLOT_WIDTH, PLOT_HEIGHT = 440, 250
AXIS_FONT = "11px"       # a y label of ~36 characters ("driver: crank driver (N·mm)") fits
BANNER = {"color": "#a01010", "background-color": "#fff0f0", "border": "1px solid #a01010",
          "padding": "6px", "white-space": "pre-wrap", "font-size": "13px"}


def _equal_size(extent, width=WIDTH):
    """(frame width, frame height) in pixels giving x and y the same scale."""
    dx, dy = extent[1] - extent[0], extent[3] - extent[2]
    height = int(round(width * dy / dx))
    if height > 1.2 * width:                 # a tall mechanism: cap the height instead
        height = int(1.2 * width)
        width = int(round(height * dx / dy))
    return width, height


class Page:
    """The Bokeh models of one view of an Explorer; ``layout`` is what to show."""

    def __init__(self, ex, server=True):
        self.ex = ex
        pic = ex.picture
        x0, x1, y0, y1 = ex.extent
        pad = 0.03 * max(x1 - x0, y1 - y0)
        extent = (x0 - pad, x1 + pad, y0 - pad, y1 + pad)
        fw, fh = _equal_size(extent)
        fig = figure(frame_width=fw, frame_height=fh, x_range=Range1d(extent[0], extent[1]),
                     y_range=Range1d(extent[2], extent[3]), match_aspect=True,
                     tools="pan,wheel_zoom,box_zoom,reset,save", toolbar_location="above",
                     title=f"{ex.mech.name}", name="drawing")
        length = units_of(ex.mech).length          # declared (mechgen.units), or None
        fig.xaxis.axis_label = f"x ({length})" if length else "x (L: the model's length unit)"
        fig.yaxis.axis_label = f"y ({length})" if length else "y (L)"
        fig.grid.grid_line_color = "#e4e4e4"
        self.figure = fig
        self.frame = extent             # what the reset tool shows: the whole drawing
        self.cycle = ColumnDataSource(ex.data, name="cycle")
        layers, cut, all_rows, verts = drawing_columns(pic)
        self.kinds = [k for k, _ in layers]
        self.verts = ColumnDataSource(verts, name="verts")
        self.layers, self.renderers = [], []
        for m, ((kind, _), rows) in enumerate(zip(layers, all_rows)):
            if m == cut:
                self._traces(fig)
            src = ColumnDataSource(placed(rows, verts, ex.data), name=f"layer{m}")
            if kind == "patches":
                r = fig.patches("xs", "ys", source=src, fill_color="fill_color",
                                fill_alpha="fill_alpha", line_color="line_color",
                                line_width="line_width")
            elif kind == "lines":
                r = fig.multi_line("xs", "ys", source=src, line_color="line_color",
                                   line_alpha="line_alpha", line_width="line_width")
            else:
                r = fig.scatter("x", "y", source=src, color="color", size="size")
            self.layers.append(src)
            self.renderers.append(r)
        if cut >= len(layers):
            self._traces(fig)
        self.labels = ColumnDataSource(placed(label_data(pic), None, ex.data), name="labels")
        self.renderers.append(fig.text(
            "x", "y", text="text", source=self.labels, x_offset="dx", y_offset="dy",
            text_color="color", text_font_size="11px", text_align="center",
            text_baseline="middle", text_font_style="bold"))
        self.layers.append(self.labels)
        self.message = Label(x=(extent[0] + extent[1]) / 2, y=(extent[2] + extent[3]) / 2,
                             text=ex.message, text_align="center", text_baseline="middle",
                             text_font_size="13px", text_color="#a01010",
                             background_fill_color="white", background_fill_alpha=0.9,
                             visible=bool(ex.message), name="message")
        fig.add_layout(self.message)
        time_unit = units_of(ex.mech).time if units_of(ex.mech).declared else ""
        self.clock_unit = f" {time_unit}" if time_unit else ""   # "T = 0.25 s"
        self.clock = Label(x=extent[0], y=extent[3], x_offset=6, y_offset=-22,
                           text=f"T = {ex.t0:.4g}{self.clock_unit}",
                           text_font_size="13px", text_color=INK, name="clock")
        fig.add_layout(self.clock)

        # time, play, parameters
        dt = (ex.t1 - ex.t0) / (ex.n - 1)
        self.time = Slider(start=ex.t0, end=ex.t1, step=dt, value=ex.t0, title="T",
                           format="0[.]0000", width=fw - 90, name="time")
        self.play = Toggle(label="▶ play", active=False, width=80, name="play")
        self.play.js_on_change("active", CustomJS(args=dict(button=self.play, slider=self.time),
                                                  code=PLAY))
        self.sliders, self.spinners = {}, {}
        for name, value in ex.params.items():
            lo, hi = ex.ranges[name]
            s = Slider(start=lo, end=hi, value=value, step=(hi - lo) / 500,
                       title=f"{name}   range [{lo:.4g}, {hi:.4g}]", format="0[.]0000",
                       width=300, name=f"param_{name}")
            sp = Spinner(value=value, step=(hi - lo) / 100, width=110, name=f"value_{name}",
                         title="value")
            s.js_link("value", sp, "value")
            sp.js_link("value", s, "value")
            self.sliders[name], self.spinners[name] = s, sp
        # plain text (a solver's account may hold "<", as a Piecewise's condition does)
        self.note = Div(text="Note: " + ex.warning if getattr(ex, "warning", "") else "",
                        width=420, name="note", render_as_text=True,
                        styles={"color": "#444444", "white-space": "pre-wrap"})
        # above the drawing, on a server page: the model file changed but does not build
        # (view.server); what a slider's move writes (the note, the message) leaves it
        self.banner = Div(text="", visible=False, name="banner", render_as_text=True,
                          width=fw, styles=BANNER)

        # the plots
        units = {q: unit_of(q, ex.mech) for q in ex.quantities}
        units["t"] = unit_of("t", ex.mech)
        options = ["t"] + ex.quantities
        self.against = Select(title="plots against", value="t", options=options, width=200,
                              name="against")
        self.selects, self.plot_lines, self.dots, yaxes, xaxes, plots = [], [], [], [], [], []
        colors = ("#1f5fa8", "#b9430e")
        for p, quantity in enumerate(ex.plots[:2]):
            f = figure(width=PLOT_WIDTH, height=PLOT_HEIGHT, tools="pan,wheel_zoom,reset,save",
                       toolbar_location="right", name=f"plot{p}")
            line = f.line("t", quantity, source=self.cycle, line_width=1.8, color=colors[p % 2])
            dot = ColumnDataSource({"x": [float(ex.data["t"][0])],
                                    "y": [float(ex.data[quantity][0])]})
            f.scatter("x", "y", source=dot, size=8, color=colors[p % 2])
            f.xaxis.axis_label_text_font_size = f.yaxis.axis_label_text_font_size = AXIS_FONT
            f.xaxis.axis_label = "t (" + units["t"] + ")"
            f.yaxis.axis_label = quantity + (f" ({units[quantity]})" if units[quantity] else "")
            sel = Select(title=f"plot {p + 1}", value=quantity, options=options, width=200,
                         name=f"quantity{p}")
            self.selects.append(sel)
            self.plot_lines.append(line)
            self.dots.append(dot)
            yaxes.append(f.yaxis[0])
            xaxes.append(f.xaxis[0])
            plots.append(f)
        self.marks = ColumnDataSource({"x": [float(ex.data[f"tr{j}x"][0]) for j in range(len(ex.traces))],
                                       "y": [float(ex.data[f"tr{j}y"][0]) for j in range(len(ex.traces))],
                                       "color": [b.edge for b, _ in ex.traces]}, name="marks")
        self.renderers.append(fig.scatter("x", "y", source=self.marks, size=7, color="color"))
        redraw = CustomJS(args=dict(cycle=self.cycle, layers=self.layers, verts=self.verts,
                                    slider=self.time,
                                    renderers=self.renderers, message=self.message,
                                    marks=self.marks, ntraces=len(ex.traces),
                                    colors=list(self.marks.data["color"]),
                                    plots=self.plot_lines, dots=self.dots, clock=self.clock,
                                    clock_unit=self.clock_unit),
                          code=REDRAW)
        self.redraw = redraw
        self.time.js_on_change("value", redraw)
        self.cycle.js_on_change("data", redraw)
        self.packed = ColumnDataSource({"values": [np.zeros(0)], "names": [[]], "n": [0],
                                        "vx": [np.zeros(0)], "vy": [np.zeros(0)]},
                                       name="packed")
        self.packed.js_on_change("data", CustomJS(args=dict(redraw.args, packed=self.packed),
                                                  code=UNPACK))
        redraw.args = dict(redraw.args, packed=self.packed)   # reachable from the page
        self.units, self.yaxes, self.xaxes = units, yaxes, xaxes
        self.server = server
        if server:        # the page holds only the columns shown: see show() and choose()
            self.cycle.data = self.shown(ex.data)
        else:
            choose = CustomJS(args=dict(plots=self.plot_lines, selects=self.selects,
                                        against=self.against, units=units, yaxes=yaxes,
                                        xaxes=xaxes, cycle=self.cycle), code=CHOOSE)
            for sel in self.selects + [self.against]:
                sel.js_on_change("value", choose)

        # assembly modes (a server answers them)
        self.mode_button = Button(label="assembly modes at T", width=180, name="modes",
                                  visible=server)
        self.modes = Select(title="assembly mode", options=[], width=260, name="mode",
                            visible=server)
        params = [row(self.sliders[n], self.spinners[n]) for n in self.sliders]
        legend = Div(text=self._legend(), width=420)
        controls = column(row(self.time, self.play), *params, self.note,
                          row(self.mode_button, self.modes), legend)
        # a server page reloads itself when the model file changed (view.server)
        self.reloader = Div(text="", visible=False, name="reloader")
        self.reloader.js_on_change("text", CustomJS(code="window.location.reload();"))
        controls.children.append(self.reloader)
        self.layout = row(column(self.banner, fig, controls),
                          column(row(*self.selects, self.against), *plots),
                          name="mechgen_view")
        self.plots = plots

    def __repr__(self):
        table = getattr(self, "table", None)
        said = f", {len(table[1].data['start'])} cycles precomputed" if table else ""
        return f"<mechgen view of '{self.ex.mech.name}'{said}>"

    def _traces(self, fig):
        """The traced paths, straight from the cycle's columns, in their bodies' colours."""
        for j, (body, _) in enumerate(self.ex.traces):
            self.renderers.append(fig.line(f"tr{j}x", f"tr{j}y", source=self.cycle,
                                           line_color=_hex(body.edge), line_width=1.6,
                                           line_alpha=0.8, name=f"trace{j}"))

    def _legend(self) -> str:
        """The bodies' colours and the traced points, as a small HTML key."""
        items = []
        for b in self.ex.scene.bodies:
            if not b.ground:
                items.append(f"<span style='display:inline-block;width:10px;height:10px;"
                             f"background:{_hex(b.fill)};border:1px solid {_hex(b.edge)}'>"
                             f"</span>&nbsp;{b.name}")
        traced = ", ".join(self.ex.trace) or "none"
        return ("<div style='font-size:12px'>" + " &nbsp; ".join(items) +
                f"<br>traced paths: {traced}</div>")

    def show(self, data, picture=None, message=""):
        """Put a newly solved cycle in (and new glyphs, when they were drawn again)."""
        if picture is not None:
            _, _, all_rows, verts = drawing_columns(picture)
            if not self.server:
                self.verts.data = verts                   # placed by the page's script
            for src, rows in zip(self.layers, all_rows):
                if not same_rows(src.data, rows):        # usually only the vertices move
                    src.data = rows
            labels = label_data(picture)
            if not same_rows(self.labels.data, labels):
                self.labels.data = labels
        self.message.text = message
        if not message:
            self.fit(self.ex.extent)
        warning = getattr(self.ex, "warning", "")
        self.note.text = "Why (the solver's account): " + \
            (getattr(self.ex, "detail", "") or message) if message else \
            "Note: " + warning if warning else ""
        if self.server:
            self.pack(self.shown(data), verts if picture is not None else None)
        else:
            self.cycle.data = data

    def fit(self, extent):
        """Grow the drawing's frame (``self.frame``, what the reset tool shows) to take
        in ``extent`` (xmin, xmax, ymin, ymax: a cycle whose parameters made the mechanism
        larger, or moved it), x and y kept at one scale in the frame's pixels; never
        shrunk (the drawing does not jump as a slider moves back). The view follows
        unless the user has zoomed or panned it: then it stays, and reset shows the
        grown frame."""
        fx0, fx1, fy0, fy1 = self.frame
        x0, x1, y0, y1 = extent
        pad = 0.03 * max(x1 - x0, y1 - y0)
        x0, x1, y0, y1 = x0 - pad, x1 + pad, y0 - pad, y1 + pad
        if x0 >= fx0 and x1 <= fx1 and y0 >= fy0 and y1 <= fy1:
            return
        scale = (fx1 - fx0) / (fy1 - fy0)       # x per y, the frame's
        x0, x1, y0, y1 = min(x0, fx0), max(x1, fx1), min(y0, fy0), max(y1, fy1)
        dx, dy = x1 - x0, y1 - y0
        if dx < dy * scale:
            x0, x1 = x0 - (dy * scale - dx) / 2, x1 + (dy * scale - dx) / 2
        else:
            y0, y1 = y0 - (dx / scale - dy) / 2, y1 + (dx / scale - dy) / 2
        xr, yr = self.figure.x_range, self.figure.y_range
        whole = (xr.start, xr.end, yr.start, yr.end) == self.frame
        self.frame = (x0, x1, y0, y1)
        xr.update(reset_start=x0, reset_end=x1)
        yr.update(reset_start=y0, reset_end=y1)
        if whole:                               # not zoomed nor panned: shown grown
            xr.update(start=x0, end=x1)
            yr.update(start=y0, end=y1)
        self.clock.update(x=x0, y=y1)
        self.message.update(x=(x0 + x1) / 2, y=(y0 + y1) / 2)

    def pack(self, data, verts=None):
        """Send a cycle's columns (and the drawing's vertices) as one array (UNPACK)."""
        names = list(data)
        n = len(data["t"])
        values = np.concatenate([np.asarray(data[k], dtype=float) for k in names]) \
            if n else np.zeros(0)
        none = np.zeros(0)
        self.packed.data = {"values": [values], "names": [names], "n": [n],
                            "vx": [verts["vx"] if verts else none],
                            "vy": [verts["vy"] if verts else none]}

    def shown(self, data) -> dict:
        """The columns a server page needs now: time, the frames' poses, the traced paths
        and the quantities the plots show (a thousand times each: sending all of them
        would double a slider's round trip)."""
        keep = {self.against.value} | {s.value for s in self.selects}
        return {k: v for k, v in data.items()
                if k in keep or k == "t" or k not in self.ex.quantities}

    def choose(self, data):
        """A plot's quantity (or the one along x) chosen on a server page: the lines'
        fields, the axes' labels and the columns, in Python (the column is sent then)."""
        x = self.against.value
        for line, sel, yaxis, xaxis in zip(self.plot_lines, self.selects, self.yaxes, self.xaxes):
            line.glyph.x, line.glyph.y = x, sel.value
            yaxis.axis_label = _label(sel.value, self.units)
            xaxis.axis_label = _label(x, self.units)
        self.pack(self.shown(data))


def _label(name, units) -> str:
    unit = units.get(name, "")
    return f"{name} ({unit})" if unit else name


def _hex(color):
    from matplotlib.colors import to_hex
    return to_hex(color)
