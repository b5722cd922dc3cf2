"""The live view (mechgen view, docs/reference/view.md) driven in a real headless browser (Debian's
chromium through Selenium) on the quick-return: the time and `longitud` sliders move, and
the drawn slider block, crank pin and traced path are checked against the mechanism's
closed form (tests/closed_forms.py) and against mech.solve; the same for the standalone
page (--html, no server); a design that cannot assemble shows its message and the range
where it can (closed form: the lever's end must stay within 5 of the slider's guide);
mech.explore() runs in a notebook (nbclient). One server and one browser for the module."""
import math
import os
import re
import time

import numpy as np
import pytest

from closed_forms import quick_return
from conftest import EXAMPLES, GENERATED

bokeh = pytest.importorskip("bokeh", reason="the view needs bokeh (pip install bokeh)")
webdriver = pytest.importorskip("selenium.webdriver",
                                reason="the browser tests need selenium (pip install selenium)")

import mechgen  # noqa: E402
from mechgen.cli import main  # noqa: E402

MODEL = os.path.join(EXAMPLES, "quick_return.py")
from browsers import chromium, need_browser  # noqa: E402

# the page's models, gathered in the browser: every layer's rows of one owner (a body's
# name, or "joints"), their drawn vertices; a traced path; the message
ROWS = """
const doc = Bokeh.documents[0], out = [];
for (let m = 0; m < 40; m++) {
  const src = doc.get_model_by_name('layer' + m);
  if (src === null) { continue; }
  const g = src.data;
  for (let r = 0; r < g.frame.length; r++) {
    if (g.owner[r] != arguments[0] || g.xs === undefined) { continue; }
    out.push([Array.from(g.xs[r]), Array.from(g.ys[r])]);
  }
}
return out;
"""
SET = """
const doc = Bokeh.documents[0];
window.mechgen_before = window.mechgen_redraws || 0;
doc.get_model_by_name(arguments[0]).value = arguments[1];
"""
CYCLE = """
const d = Bokeh.documents[0].get_model_by_name('cycle').data;
return [Array.from(d.t), Array.from(d[arguments[0]]), Array.from(d[arguments[1]])];
"""


def x4(t, longitud):
    return float(quick_return(t, longitud=longitud)[6])


def crank_pin(t, longitud):
    th = 2 * math.pi * t
    return longitud * math.cos(th), 5 + longitud * math.sin(th)


@pytest.fixture(scope="module")
def browser():
    drv = chromium()
    yield drv
    drv.quit()


@pytest.fixture(scope="module")
def mech():
    """Compiled into generated/, as `mechgen view` does by default (the same text as the
    committed module, kept: numba's cache of it is shared with the suite's other users
    of generated/quick_return.py instead of compiling a copy)."""
    return mechgen.compile(MODEL, outdir=GENERATED, tier="compiled")


@pytest.fixture(scope="module")
def server(mech):
    from mechgen.view.explorer import Explorer
    from mechgen.view.server import ViewServer
    srv = ViewServer(lambda: Explorer(mechgen.compile(MODEL, outdir=GENERATED, tier="compiled"),
                                      n=1000, trace=["deslizadera[1]", "manivela[2]"]))
    srv.start()
    yield srv
    srv.stop()


def wait(drv, script, timeout=30.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = drv.execute_script(script)
        if value:
            return value
        time.sleep(0.05)
    raise AssertionError(f"the page never answered {script!r}")


def set_value(drv, name, value):
    drv.execute_script(SET, name, value)
    wait(drv, "return (window.mechgen_redraws || 0) > window.mechgen_before")


def check_drawing(drv, t, longitud, tol=1e-9):
    """The slider block, the crank's pin and the traced paths as drawn, against the
    closed form at (t, longitud)."""
    # the slider block: the box from deslizadera[1] to [2] (2 long), sitting on y = 10
    boxes = drv.execute_script(ROWS, "deslizadera")
    assert boxes, "no slider block drawn"
    xs, ys = np.array(boxes[0][0]), np.array(boxes[0][1])
    want = x4(t, longitud)
    assert abs(xs.min() - want) < tol and abs(xs.max() - (want + 2)) < tol
    assert abs(ys.min() - 10) < tol
    # the crank's pin at its end: a circle about the closed form's crank pin
    pins = [np.array(p) for p in drv.execute_script(ROWS, "joints")]
    px, py = crank_pin(t, longitud)
    centres = [(p[0].mean(), p[1].mean()) for p in pins if len(p[0]) == 20]
    assert min(math.hypot(cx - px, cy - py) for cx, cy in centres) < 1e-6
    # the traced paths: the slider's along y = 10, the crank pin's circle
    tt, trx, tr_y = drv.execute_script(CYCLE, "tr0x", "tr0y")
    tt = np.array(tt)
    assert len(tt) == 1000
    for k in (0, 137, 500, 999):
        assert abs(trx[k] - x4(tt[k], longitud)) < tol and abs(tr_y[k] - 10) < tol
    _, cx, cy = drv.execute_script(CYCLE, "tr1x", "tr1y")
    r = np.hypot(np.array(cx), np.array(cy) - 5)
    assert np.abs(r - longitud).max() < tol


@need_browser
def test_the_server_page_moves_with_the_time_and_longitud_sliders(browser, server, mech):
    browser.get(server.url)
    wait(browser, "return window.mechgen_redraws || 0")
    check_drawing(browser, 0.0, 3.0)
    set_value(browser, "time", 0.3)
    t = round(0.3 * 999) / 999            # the slider's step: 1/999
    check_drawing(browser, t, 3.0)
    set_value(browser, "param_longitud", 2.2)
    check_drawing(browser, t, 2.2)
    # and as mech.solve says, at the same values
    s = mech.with_params(longitud=2.2).solve(t)
    box = np.array(browser.execute_script(ROWS, "deslizadera")[0][0])
    assert abs(box.min() - s["X4"]) < 1e-9
    # the play button steps the time slider around the cycle
    browser.execute_script("Bokeh.documents[0].get_model_by_name('play').active = true")
    time.sleep(0.4)
    browser.execute_script("Bokeh.documents[0].get_model_by_name('play').active = false")
    assert browser.execute_script("return Bokeh.documents[0].get_model_by_name('time').value") != t
    set_value(browser, "time", t)
    # the plots show the cycle's quantities at the time shown
    _, stroke, _ = browser.execute_script(CYCLE, "stroke_x", "stroke_x")
    assert abs(stroke[round(t * 999)] - s["X4"]) < 1e-9


@need_browser
def test_a_design_that_cannot_assemble_says_so_and_where_it_can(browser, server):
    browser.get(server.url)
    wait(browser, "return window.mechgen_redraws || 0")
    set_value(browser, "param_longitud", 4.5)
    text = browser.execute_script(
        "const m = Bokeh.documents[0].get_model_by_name('message');"
        "return m.visible ? m.text : '';")
    assert "Cannot assemble" in text and "longitud = 4.5" in text, text
    # the lever's end reaches 9 cos(asin(L/5)) high at its widest; the slider's rod (5)
    # reaches it from y = 10 while that is >= 5: L <= 5 sin(acos(5/9))
    limit = 5 * math.sin(math.acos(5 / 9))
    said = text.split("assembles for longitud from ")[1].split("\n")[0]
    lo, hi = (float(v) for v in said.rstrip(".").split(" to "))
    assert lo == pytest.approx(1.5) and abs(hi - limit) < (4.5 - 1.5) / 24     # 25 designs
    hidden = browser.execute_script("return Bokeh.documents[0].get_model_by_name('trace0')"
                                    ".visible")
    assert hidden is False
    set_value(browser, "param_longitud", 3.0)
    check_drawing(browser, 0.0, 3.0)


@need_browser
def test_the_standalone_page_works_without_a_server(browser, tmp_path, capsys):
    out = str(tmp_path / "view.html")
    assert main(["view", MODEL, "--html", out, "--vary", "longitud", "--steps", "7",
                 "--trace", "deslizadera[1],manivela[2]"]) == 0
    assert "wrote" in capsys.readouterr().out
    text = open(out, encoding="utf-8").read()
    # everything inline: no script or stylesheet fetched from elsewhere
    assert "<script" in text and not re.search(r"<script[^>]*\ssrc=", text)
    assert not re.search(r"<link[^>]*\shref=", text)
    browser.get("file://" + out)
    wait(browser, "return window.mechgen_redraws || 0")
    grid = np.linspace(1.5, 4.5, 7)          # the default range, 7 steps
    set_value(browser, "param_longitud", grid[2])
    set_value(browser, "time", 0.25)
    tt, _, _ = browser.execute_script(CYCLE, "t", "t")
    assert len(tt) == 200
    t = tt[round(0.25 * 199)]
    boxes = browser.execute_script(ROWS, "deslizadera")
    xs = np.array(boxes[0][0])
    # float32 columns: to single precision
    assert abs(xs.min() - x4(t, grid[2])) < 1e-5
    _, cx, cy = browser.execute_script(CYCLE, "tr1x", "tr1y")
    assert np.abs(np.hypot(np.array(cx), np.array(cy) - 5) - grid[2]).max() < 1e-5
    # past the limit the page says why (the message precomputed with the cycle)
    set_value(browser, "param_longitud", 4.5)
    text = browser.execute_script("return Bokeh.documents[0].get_model_by_name('message').text")
    assert "Cannot assemble" in text


@need_browser
def test_an_edit_of_the_model_file_redraws_the_page(browser, tmp_path):
    from mechgen.view.explorer import Explorer
    from mechgen.view.server import ViewServer
    model = tmp_path / "guide.py"
    model.write_text(open(MODEL, encoding="utf-8").read(), encoding="utf-8")
    out = str(tmp_path / "generated")
    # the plain-Python tier and a short cycle: nothing to compile for the edited model
    srv = ViewServer(lambda: Explorer(mechgen.compile(str(model), outdir=out, tier="python"),
                                      n=40, compiled=False), watch=str(model)).start()
    try:
        browser.get(srv.url)
        wait(browser, "return window.mechgen_redraws || 0")
        box = browser.execute_script(ROWS, "deslizadera")[0]
        assert abs(min(box[1]) - 10) < 1e-9
        text = model.read_text(encoding="utf-8")
        edited = text.replace("(-5, 10), (12, 10)", "(-5, 10.5), (12, 10.5)")
        assert edited != text
        model.write_text(edited.replace("guess=(6, 10, 0)", "guess=(6, 10.5, 0)"),
                         encoding="utf-8")
        # the slider's guide raised by half a unit: the page redraws it there
        from selenium.common.exceptions import JavascriptException
        end = time.monotonic() + 90
        while True:
            try:       # the page reloads itself: Bokeh is briefly not there
                boxes = browser.execute_script(ROWS, "deslizadera")
            except JavascriptException:
                boxes = None
            if boxes and abs(min(boxes[0][1]) - 10.5) < 1e-9:
                break
            assert time.monotonic() < end, "the page was not redrawn after the edit"
            time.sleep(0.2)
    finally:
        srv.stop()


def test_explore_runs_in_a_notebook(tmp_path):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(
        "import mechgen\n"
        f"mech = mechgen.compile({MODEL!r}, outdir={GENERATED!r}, tier='compiled')\n"
        "page = mech.explore(vary=['longitud'], steps=3, n=50)\n"
        "print(len(page.table[1].data['start']), 'cycles')")]
    nbclient.NotebookClient(nb, timeout=300, kernel_name="python3",
                            resources={"metadata": {"path": str(tmp_path)}}).execute()
    outputs = nb.cells[0].outputs
    shown = "".join(o.get("data", {}).get("text/html", "") for o in outputs)
    assert "<iframe srcdoc=" in shown     # the whole page, BokehJS inline (test_view_offline)
    printed = "".join(o.get("text", "") for o in outputs if o.output_type == "stream")
    assert "3 cycles" in printed


def test_the_other_assembly_mode_is_followed_over_the_cycle(mech):
    from mechgen.view.explorer import Explorer
    ex = Explorer(mech, n=200, trace=["deslizadera[1]"])
    modes = ex.modes(0.85)
    assert len(modes) == 2
    # the slider left of the lever's end (closed form side=-1), followed back to T = 0
    other = [q for label, q in modes if q[6] < 5]
    assert len(other) == 1
    data, _, message = ex.compute(guess=ex.follow_back(other[0], 0.85))
    assert message == ""
    for k in (0, 50, 170, 199):
        want = float(quick_return(data["t"][k], side=-1)[6])
        assert abs(data["X4"][k] - want) < 1e-9 and abs(data["tr0x"][k] - want) < 1e-9
    # a parameter change keeps to that mode
    data, _, _ = ex.compute({"longitud": 2.5})
    assert abs(data["X4"][100] - float(quick_return(data["t"][100], longitud=2.5, side=-1)[6])) < 1e-9
    # and so does a long move of the slider (the mode carried from the last cycle's
    # parameters to the new ones, not a Newton from its start at the new ones)
    for L in (1.2, 4.1):
        data, _, message = ex.compute({"longitud": L})
        assert message == ""
        for k in (0, 100):
            want = float(quick_return(data["t"][k], longitud=L, side=-1)[6])
            assert abs(data["X4"][k] - want) < 1e-9, (L, k)


def test_a_mode_that_cannot_be_carried_is_noted_under_the_drawing():
    """A slider moved across parameters where the chosen mode cannot be carried (the
    four-bar's crank pointing at the rocker's pivot, a from 1 to 5: no assembly for a in
    (2.5, 3.5)): the cycle is drawn, solved from the guess, and the page's note says that
    its mode may be another; a cycle carried without trouble clears it."""
    from mechgen.view.explorer import Explorer
    from mechgen.view.page import Page
    fb = mechgen.load(os.path.join(GENERATED, "fourbar.py"))
    m0 = fb.with_params(a=1.0, theta2=0.0, omega=0.0)
    m0.set_guess(m0.solve(0.0, guess={"Th3": 1.0, "Th4": 2.0}))
    ex = Explorer(m0, n=5)
    page = Page(ex)
    assert ex.warning == "" and page.note.text == ""
    data, _, message = ex.compute({"a": 5.0})
    assert message == "" and len(data["t"]) == 5
    assert "could not be carried" in ex.warning
    page.show(data, None, message)
    assert page.note.text.startswith("Note: ") and "could not be carried" in page.note.text
    data, _, message = ex.compute({"a": 1.2})
    page.show(data, None, message)
    assert message == "" and ex.warning == "" and page.note.text == ""


def test_the_frame_grows_to_take_in_a_larger_mechanism():
    """Parameters that make the mechanism larger (the four-bar's pivots 4 apart instead
    of 3, its coupler and rocker longer): the drawing's ranges grow to take in every
    glyph over the new cycle, x and y kept at the frame's one scale; a smaller one after
    it leaves them as they are."""
    from mechgen.view.explorer import Explorer
    from mechgen.view.page import Page
    ex = Explorer(mechgen.load(os.path.join(GENERATED, "fourbar.py")), n=40)
    page = Page(ex)
    xr, yr = page.figure.x_range, page.figure.y_range
    scale = (xr.end - xr.start) / (yr.end - yr.start)
    assert xr.end < 4.0
    data, again, message = ex.compute({"b": 3.3, "c": 2.7, "d": 4.0})
    assert message == "" and again
    page.show(data, ex.picture, message)
    x0, x1, y0, y1 = ex.extent
    assert xr.start <= x0 and xr.end >= x1 >= 4.0 and yr.start <= y0 and yr.end >= y1
    assert abs((xr.end - xr.start) / (yr.end - yr.start) - scale) < 1e-12 * scale
    assert (xr.reset_end, page.clock.x, page.clock.y) == (xr.end, xr.start, yr.end)
    grown = (xr.start, xr.end, yr.start, yr.end)
    data, _, message = ex.compute({"b": 2.5, "c": 2.0, "d": 3.0})
    page.show(data, ex.picture, message)
    assert (xr.start, xr.end, yr.start, yr.end) == grown
    # a view the user zoomed stays zoomed; reset shows the frame grown again
    xr.update(start=0.5, end=1.5)
    yr.update(start=-0.3, end=0.7)
    data, _, message = ex.compute({"b": 3.6, "c": 2.9, "d": 4.4})
    page.show(data, ex.picture, message)
    assert (xr.start, xr.end, yr.start, yr.end) == (0.5, 1.5, -0.3, 0.7)
    assert xr.reset_end >= ex.extent[1] >= 4.4 and xr.reset_end > grown[1]
    # the page without a server: its frame takes in every precomputed cycle's drawing
    from mechgen.view.standalone import standalone_page
    ex = Explorer(mechgen.load(os.path.join(GENERATED, "fourbar.py")), n=40,
                  ranges={"d": (2.5, 3.6)})
    page = standalone_page(ex, vary=["d"], steps=3)
    xr = page.figure.x_range
    assert xr.start <= -0.8 and xr.end >= 3.6      # the crank's circle, the far pivot


def test_a_model_with_masses_offers_its_driver_torque(tmp_path):
    from mechgen.view.explorer import Explorer
    # the plain-Python tier and a short cycle: nothing to compile
    mech = mechgen.compile(os.path.join(EXAMPLES, "quick_return_forces.py"), tier="python")
    ex = Explorer(mech, n=101, compiled=False)
    assert "driver: crank driver" in ex.quantities and ex.plots[1] == "driver: crank driver"
    # the column is the torque at the cycle's times: the power balance of the example's
    # closed form, its masses, gravity and the cutting force on the return stroke
    from closed_forms import quick_return_torque
    bodies = {"manivela": (2.0, 1.5, (1.5, 0)), "colisa": (5.0, 33.75, (0, 4.5)),
              "deslizadera": (3.0, 1.0, (1, 0.2))}
    for k in (20, 70):
        want = quick_return_torque(k / 100, bodies, cut=500.0)
        assert abs(ex.data["driver: crank driver"][k] - want) < 1e-7 * (1 + abs(want))


def test_view_refuses_bad_options_clearly(capsys):
    assert main(["view", MODEL, "--range", "longitud=1", "--no-browser"]) == 1
    assert "NAME=LOW:HIGH" in capsys.readouterr().err
    assert main(["view", MODEL, "--range", "nope=1:2", "--no-browser"]) == 1
    assert "no parameter 'nope'" in capsys.readouterr().err
