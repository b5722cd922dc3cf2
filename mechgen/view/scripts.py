"""The page's JavaScript (Bokeh CustomJS bodies): moving the glyphs to the time shown,
playing, switching the plots' quantities, and, in a page without a server, picking the
precomputed cycle nearest the sliders. Kept as text here so that the server page, the
standalone page and the notebook share it."""

# Moves every glyph to the time on the slider: a glyph's local vertices turned by its
# frame's angle and moved to its origin (view.geometry). Runs on a time change and when
# the cycle's columns change (a parameter moved): then it stamps window.mechgen_drawn
# (performance.now()) for the latency benchmark and the tests.
REDRAW = r"""
window.mechgen_arrived = performance.now();
const d = cycle.data;
const n = d.t ? d.t.length : 0;
const failed = n == 0;
message.visible = failed;
for (const r of renderers) { r.visible = !failed; }
if (!failed) {
  const t0 = d.t[0], t1 = d.t[n - 1];
  let i = Math.round((slider.value - t0) / (t1 - t0) * (n - 1));
  i = Math.max(0, Math.min(n - 1, i));
  function pose(f) {
    if (f == 0) { return [0.0, 0.0, 1.0, 0.0]; }
    const col = d["f" + f + "a"], a = col === undefined ? 0.0 : col[i];
    return [d["f" + f + "x"][i], d["f" + f + "y"][i], Math.cos(a), Math.sin(a)];
  }
  for (let m = 0; m < layers.length; m++) {
    const src = layers[m], g = src.data, vx = verts.data.vx, vy = verts.data.vy;
    const rows = g.frame.length;
    if (g.x !== undefined) {               // dots and labels: one point a row
      const x = new Array(rows), y = new Array(rows);
      for (let r = 0; r < rows; r++) {
        const [ox, oy, c, s] = pose(g.frame[r]);
        x[r] = ox + c * g.lx[r] - s * g.ly[r];
        y[r] = oy + s * g.lx[r] + c * g.ly[r];
      }
      g.x = x; g.y = y;
    } else {                               // patches and lines: vertices a row
      const xs = new Array(rows), ys = new Array(rows);
      for (let r = 0; r < rows; r++) {
        const a = g.start[r], k = g.count[r];
        const [ox, oy, c, s] = pose(g.frame[r]);
        const X = new Float64Array(k), Y = new Float64Array(k);
        for (let v = 0; v < k; v++) {
          X[v] = ox + c * vx[a + v] - s * vy[a + v];
          Y[v] = oy + s * vx[a + v] + c * vy[a + v];
        }
        xs[r] = X; ys[r] = Y;
      }
      g.xs = xs; g.ys = ys;
    }
    src.change.emit();
  }
  const tx = [], ty = [];
  for (let j = 0; j < ntraces; j++) { tx.push(d["tr" + j + "x"][i]); ty.push(d["tr" + j + "y"][i]); }
  // in place, then change.emit(): nothing of this goes back to a server
  marks.data.x = tx; marks.data.y = ty; marks.data.color = colors; marks.change.emit();
  for (let p = 0; p < plots.length; p++) {
    const xf = plots[p].glyph.x.field, yf = plots[p].glyph.y.field;
    if (d[xf] === undefined || d[yf] === undefined) { continue; }
    dots[p].data.x = [d[xf][i]]; dots[p].data.y = [d[yf][i]]; dots[p].change.emit();
  }
  clock.text = "T = " + d.t[i].toPrecision(4) + clock_unit;
}
if (failed) {            // no configuration to mark
  marks.data.x = []; marks.data.y = []; marks.data.color = []; marks.change.emit();
  for (const dot of dots) { dot.data.x = []; dot.data.y = []; dot.change.emit(); }
}
window.mechgen_drawn = performance.now();
window.mechgen_redraws = (window.mechgen_redraws || 0) + 1;
"""

# A server page's new cycle arrives packed: every column one after another in one array
# (and the drawing's vertices when a shape changed), so that it is one websocket message
# of three buffers, not two frames a column; unpacked into the cycle's columns in place
# (views into the array: no copy, and nothing sent back to the server), then REDRAW.
UNPACK = r"""
{
  const p = packed.data, v = p.values[0], names = p.names[0], n = p.n[0];
  const cols = cycle.data;
  for (const k of Object.keys(cols)) { delete cols[k]; }
  for (let k = 0; k < names.length; k++) {   // plain views (an NDArray's subarray is not)
    cols[names[k]] = new Float64Array(v.buffer, v.byteOffset + 8 * k * n, n);
  }
  if (p.vx[0].length) { verts.data.vx = p.vx[0]; verts.data.vy = p.vy[0]; }
  cycle.change.emit();
}
""" + REDRAW

# The play button: steps the time slider around the cycle (about six seconds a turn).
PLAY = r"""
if (window.mechgen_timer) { clearInterval(window.mechgen_timer); window.mechgen_timer = null; }
if (button.active) {
  window.mechgen_timer = setInterval(function () {
    const span = slider.end - slider.start;
    let v = slider.value + span / 180;
    if (v > slider.end) { v = slider.start; }
    slider.value = v;
  }, 33);
}
"""

# A plot's quantity or the quantity along x chosen: the line's fields and the axes' labels.
CHOOSE = r"""
for (let p = 0; p < plots.length; p++) {
  const y = selects[p].value, x = against.value;
  plots[p].glyph.x = {field: x};
  plots[p].glyph.y = {field: y};
  yaxes[p].axis_label = y + (units[y] ? " (" + units[y] + ")" : "");
  xaxes[p].axis_label = x + (units[x] ? " (" + units[x] + ")" : "");
}
cycle.change.emit();
"""

# A page without a server: the precomputed cycle nearest the sliders (view.standalone).
PICK = r"""
let index = 0;
for (let k = 0; k < sliders.length; k++) {
  const g = grids[k];
  let best = 0;
  for (let j = 1; j < g.length; j++) {
    if (Math.abs(g[j] - sliders[k].value) < Math.abs(g[best] - sliders[k].value)) { best = j; }
  }
  index = index * g.length + best;
}
const start = table.data.start[index], count = table.data.count[index];
const shape = table.data.shape[index];
const base = table.data.vbase[index], vend = table.data.vend[index];
verts.data = {vx: points.data.vx.slice(base, vend), vy: points.data.vy.slice(base, vend)};
const out = {};
for (const name of names) { out[name] = cycles.data[name].slice(start, start + count); }
for (let m = 0; m < layers.length; m++) {
  const src = shapes[m].data, rows = [];
  for (let r = 0; r < src.cycle.length; r++) { if (src.cycle[r] == shape) { rows.push(r); } }
  const g = {};
  for (const key of Object.keys(layers[m].data)) {
    const col = src[key];
    if (col === undefined) { continue; }
    g[key] = rows.map(r => col[r]);
  }
  if (g.start !== undefined) {        // into this drawing's vertices
    g.start = g.start.map(a => a - base);
    g.xs = rows.map(r => []); g.ys = rows.map(r => []);
  }
  layers[m].data = g;
}
message.text = table.data.message[index];
// what the solve of this cycle warned of its assembly mode (a singular configuration passed)
const warned = table.data.note ? table.data.note[index] : "";
note.text = about + (warned ? "\nNote: " + warned : "");
cycle.data = out;
"""
