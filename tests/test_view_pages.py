"""`mechgen view` (docs/reference/view.md) as a user drives it, checked on the Bokeh documents and
pages it builds, without a browser (tests/test_view.py drives one): the server page with the model
file watched while it is edited, what the page says where it cannot show the view, the assembly
modes button, the standalone page's notes, plot units, pitch circles, a trace of a local point, a
page of a six-parameter model. Found in headless chromium (selenium) on examples/fourbar.py; checked
here on the plain tier."""
import math
import os
import shutil

import numpy as np
import pytest

from conftest import EXAMPLES

pytest.importorskip("bokeh")


@pytest.fixture
def fourbar_file(tmp_path, monkeypatch):
    monkeypatch.setenv("MECHGEN_TIER", "python")
    path = tmp_path / "fourbar.py"
    shutil.copy(os.path.join(EXAMPLES, "fourbar.py"), path)
    return path


def _maker(path, outdir):
    import mechgen
    from mechgen.view.explorer import Explorer
    return lambda: Explorer(mechgen.compile(str(path), outdir=str(outdir), tier="python"),
                            n=40, compiled=False)


def _write(path, text):
    """Write the model file so that the watch sees a change (its stamp: mtime and size)."""
    before = os.stat(path).st_mtime_ns
    path.write_text(text)
    st = os.stat(path)
    os.utime(path, ns=(st.st_atime_ns, max(st.st_mtime_ns, before + 10**6)))


def _texts(doc):
    """Every Div's text in a document (what the page says in words)."""
    from bokeh.models import Div
    return [m.text for m in doc.models if isinstance(m, Div) and m.text]


def test_a_model_file_saved_broken_is_said_above_the_drawing_and_stays_said(fourbar_file,
                                                                             tmp_path):
    # `mechgen view fourbar.py`, the file saved with a syntax error: the page kept drawing
    # the old model and said so only in the note under the six parameter sliders (off
    # the screen of a 1340x900 window), and the next slider move wrote over that note
    # (Page.show): nothing on the page said the file was broken any more
    from bokeh.document import Document
    from mechgen.view.server import Session
    good = fourbar_file.read_text()
    doc = Document()
    s = Session(doc, _maker(fourbar_file, tmp_path / "gen"), watch=str(fourbar_file))
    _write(fourbar_file, good.replace('m.param("c", 2.0)', 'm.param("c", 2.0'))
    s.look()
    banner = s.page.banner
    assert banner.visible and "does not build" in banner.text and "syntax error" in \
        banner.text and "fourbar.py:9" in banner.text
    assert s.page.layout.children[0].children[0] is banner       # above the drawing
    said = banner.text
    s.moved("a", 0.9)                  # a slider moved on the model as it last built
    assert s.page.banner.visible and s.page.banner.text == said
    assert s.page.reloader.text == ""  # not reloaded onto a broken file
    # fixed: the page reloads itself (a fresh session builds the new model)
    _write(fourbar_file, good.replace('m.param("c", 2.0)', 'm.param("c", 2.2)'))
    s.look()
    assert s.page.reloader.text != ""
    fresh = Session(Document(), _maker(fourbar_file, tmp_path / "gen"),
                    watch=str(fourbar_file))
    assert fresh.ex.params["c"] == 2.2 and not fresh.page.banner.visible


def test_a_page_opened_while_the_model_file_is_broken_says_why_and_recovers(fourbar_file,
                                                                            tmp_path):
    # a page opened (or reloaded with F5) while the watched file did not build showed
    # "500: Internal Server Error" and nothing else: Session() raised, the cause only in
    # the terminal, and the page never came back once the file was fixed
    from bokeh.document import Document
    from mechgen.view.server import Session
    good = fourbar_file.read_text()
    _write(fourbar_file, good.replace("m.revolute(coupler[2], rocker[2])",
                                      "m.revolute(coupler[2], rockr[2])"))
    doc = Document()
    s = Session(doc, _maker(fourbar_file, tmp_path / "gen"), watch=str(fourbar_file))
    said = " ".join(_texts(doc))
    assert "fourbar.py does not build" in said and "rockr" in said and ":22" in said
    assert doc.session_callbacks               # still watching the file
    _write(fourbar_file, good)
    s.look()
    assert s.reloader.text != ""               # built: the page reloads onto the view


def test_the_pages_note_is_plain_text(fourbar_file, tmp_path):
    # the note under the sliders (a solver's account of a failure, a mode's warning) was
    # a Div rendering HTML: an account quoting a condition `v < 0` of a Piecewise cut
    # the rest of the text off as a tag
    from mechgen.view.page import Page
    page = Page(_maker(fourbar_file, tmp_path / "gen")(), server=True)
    assert page.note.render_as_text and page.banner.render_as_text


def test_the_view_opens_on_a_model_with_a_point_placed_by_parameters():
    # `mechgen view examples/internal_gear.py --model planetary` (and internal_gear, and
    # their --html and mech.explore()) failed: "'frame.at(-2*rq - rs, 0)': body.at(x, y)
    # takes two numbers": the default traced paths look up every point the module
    # names, and a point the model placed with frame.at(expr, 0) was parsed as a local
    # position to trace, not found as the module's own point
    import mechgen
    from conftest import GENERATED
    from mechgen.plot.scene import Scene
    from mechgen.view.explorer import Explorer
    mech = mechgen.load(os.path.join(GENERATED, "planetary.py"), tier="python")
    label = "frame.at(-2*rq - rs, 0)"
    assert label in mech.point_names
    scene = Scene(mech)
    sw = mech.sweep(0, 1, 5)
    body, path = scene.locate(label)
    assert body.name == "frame"
    P = sw.points()
    k = mech.point_names.index(label)
    assert abs(path(P, sw.Q) - P[:, k]).max() == 0.0
    # -2*rq - rs at the defaults rq = 0.75, rs = 1: the ring's point at x = -2.5
    assert abs(P[0, k, 0] + 2.5) < 1e-12 and abs(P[0, k, 1]) < 1e-12
    ex = Explorer(mech, n=20, compiled=False)
    assert ex.trace                     # and traced paths were chosen


def test_the_views_ring_gear_is_not_filled_black():
    # the view drew the frame's ring gear (an internal gear: its pitch circle drawn with
    # facecolor "none" and alpha 1) as an opaque black disk over the whole planetary
    # train: the patch's alpha replaced the "none" face's zero alpha; draw() leaves it
    # unfilled
    import mechgen
    from conftest import GENERATED
    from mechgen.view.geometry import Picture
    mech = mechgen.load(os.path.join(GENERATED, "planetary.py"), tier="python")
    s = mech.solve(0.1)
    pic = Picture(mech, s.q, 0.1, mech.sweep(0, 1, 11))
    ring = [p for p in pic.pieces if p["kind"] == "patch" and p["owner"] == "frame"
            and len(p["xy"]) > 20]
    assert ring, [(p["owner"], len(p["xy"])) for p in pic.pieces]
    for p in ring:
        assert p["fill"] is None or p["fill_alpha"] == 0.0, p
    from mechgen.view.layers import drawing_columns
    for rows in drawing_columns(pic)[2]:
        for owner, fill, alpha in zip(rows["owner"], rows.get("fill_color", []),
                                      rows.get("fill_alpha", [])):
            assert not (fill == "#000000" and alpha > 0), (owner, fill, alpha)


def test_the_cannot_assemble_message_says_the_value_that_fails(fourbar_file, tmp_path):
    # fourbar (a = 0.8, b = 2.5, c = 2) turns its crank fully for d <= b + c - a = 3.7
    # (closed form: the crank pin's distance to the rocker's pivot reaches d + a); the
    # spinner set to d = 3.70001 said "Cannot assemble over the cycle for d = 3.7", a
    # value that does run (the message rounded it to 4 digits)
    ex = _maker(fourbar_file, tmp_path / "gen")()
    data, _, message = ex.compute({"d": 3.70001})
    assert len(data["t"]) == 0
    assert "for d = 3.70001." in message, message
    data, _, message = ex.compute({"d": 3.69})
    assert message == "" and len(data["t"]) == 40


def test_view_trace_keeps_the_comma_of_a_local_point():
    # `mechgen view fourbar.py --trace "coupler.at(1.25, 0.8)"` (README, and the option's
    # own help: 'foot.at(1, 2)') was cut at the comma: "no point 'coupler.at(1.25'"
    from mechgen.cli.view_command import _names
    assert _names(["coupler.at(1.25, 0.8)"]) == ["coupler.at(1.25, 0.8)"]
    assert _names(["colisa[2], foot.at(1, 2)", "crank[1]"]) == \
        ["colisa[2]", "foot.at(1, 2)", "crank[1]"]
    assert _names(["X4,X4d"]) == ["X4", "X4d"]
    assert _names(None) is None


def test_the_server_pages_assembly_modes_button_reaches_its_callback():
    # `mechgen view`: a click on "assembly modes at T" did nothing: the callback was
    # registered after the layout joined the document, which Bokeh 3.9 never subscribes
    # (the click arrived as a ButtonClick event that no callback received); the mode
    # selector stayed empty, so no other assembly mode could be chosen
    pytest.importorskip("bokeh")
    import mechgen
    from bokeh.document import Document
    from bokeh.events import ButtonClick
    from mechgen.view.explorer import Explorer
    from mechgen.view.server import Session
    mech = mechgen.compile(os.path.join(EXAMPLES, "fourbar.py"), tier="python")
    doc = Document()
    s = Session(doc, lambda: Explorer(mech, n=40, compiled=False))
    s.page.time.value = 0.25
    doc.callbacks.trigger_event(ButtonClick(s.page.mode_button))
    options = s.page.modes.options
    assert len(options) == 2, options
    # choosing the second mode draws the cycle in it: the rocker below the ground line
    s.page.modes.value = options[1]
    i = int(np.argmin(np.abs(s.data["t"] - 0.25)))
    th2 = math.pi / 3 + 2 * math.pi * s.data["t"][i]
    A = np.array([0.8 * math.cos(th2), 0.8 * math.sin(th2)])
    D = np.array([3.0, 0.0])
    v = D - A
    L = np.linalg.norm(v)
    x = (2.5 ** 2 - 2.0 ** 2 + L * L) / (2 * L)
    B = A + x * v / L - math.sqrt(2.5 ** 2 - x * x) * np.array([-v[1], v[0]]) / L
    th4 = math.atan2(B[1], B[0] - 3.0)
    assert abs(math.remainder(s.data["Th4"][i] - th4, 2 * math.pi)) < 1e-7


def test_the_standalone_page_keeps_each_cycles_note_of_a_singular_passage():
    # `mechgen view --html` / mech.explore(): a cycle whose solve passed a singular
    # configuration (a four-bar at its change point, a = 1.5: it may go on in the other
    # assembly mode, and here does) was shown with no note, where the server page says so
    pytest.importorskip("bokeh")
    import mechgen
    from mechgen.view.explorer import Explorer
    from mechgen.view.standalone import standalone_page
    mech = mechgen.compile(os.path.join(EXAMPLES, "fourbar.py"), tier="python")
    ex = Explorer(mech, n=60, compiled=False, ranges={"a": (0.5, 1.5)})
    page = standalone_page(ex, vary=["a"], steps=3)
    grid, table, _ = page.table
    notes = dict(zip(grid["a"], table.data["note"]))
    assert notes[0.8] == "" and notes[0.5] == ""
    assert "singular" in notes[1.5]
    # the page's script writes the picked cycle's note under the sliders
    from mechgen.view.scripts import PICK
    assert "table.data.note" in PICK and "note.text" in PICK


def test_the_views_plot_units_read_an_output_ending_in_d_as_itself():
    # the live view labelled an output named "speed" "speed (per T)" and its rate
    # "speedd" "(per T²)": the unit came from stripping every trailing d of the name
    import mechgen
    from mechgen.view.cycle import unit_of
    model = mechgen.Model("feed_units")
    g = model.ground("g", points=[(0, 0)])
    crank = model.body("crank", points=[(0, 0), (1, 0)], guess=(0, 0, 0))
    model.revolute(g[1], crank[1])
    model.rotation_lock(crank, 2 * mechgen.pi * mechgen.T)
    model.output("feed", mechgen.location(crank[2])[0])
    model.output("speed", mechgen.dt(mechgen.location(crank[2])[0]))
    mech = mechgen.compile(model, tier="python")
    assert unit_of("speed", mech) == ""
    assert unit_of("speedd", mech) == "per T"
    assert unit_of("feed", mech) == "" and unit_of("feedd", mech) == "per T"
    assert unit_of("feeddd", mech) == "per T²"
    assert unit_of("Th2d", mech) == "rad/T" and unit_of("X2dd", mech) == "L/T²"


def test_the_views_pitch_circles_are_circles_not_20_gons():
    # the live view drew every circle as a 20-gon: gear_train's pitch circle of radius
    # 3 strayed 0.037 (a fifth of a bar's width) from the circle, its teeth ticks
    # standing off the polygon; pins keep 20 vertices
    import mechgen
    from mechgen.view.geometry import Picture
    mech = mechgen.compile(os.path.join(EXAMPLES, "gear_train.py"), tier="python")
    s = mech.solve(0.1)
    pic = Picture(mech, s.q, 0.1, mech.sweep(0, 1, 11))
    w = pic.drawing.size
    found = {}
    for p in pic.pieces:
        if p["kind"] != "patch" or p["owner"] != "BC":
            continue
        xy = p["xy"]                      # local to BC's frame, its centre at the origin
        r = np.hypot(xy[:, 0], xy[:, 1])
        if np.ptp(r) < 1e-9 and r[0] > 1.0:
            # the polygon's chords: the mid-chord distance to the circle
            mid = (xy + np.roll(xy, -1, axis=0)) / 2
            sag = r[0] - np.hypot(mid[:, 0], mid[:, 1]).min()
            found[round(r[0], 6)] = sag
    assert set(found) >= {3.0, 1.5}, found
    assert all(sag <= 0.03 * w + 1e-12 for sag in found.values()), (found, w)
    pins = [p for p in pic.pieces if p["kind"] == "patch" and len(p["xy"]) == 20]
    assert pins                                # the pins' 20 vertices (tests/test_view.py)


def _grid_explorer(params):
    from types import SimpleNamespace
    from mechgen.view.explorer import default_range
    return SimpleNamespace(params=params, ranges={k: default_range(v) for k, v in params.items()},
                           mech=SimpleNamespace(name="m"))


def test_a_page_without_a_server_of_a_six_parameter_model_is_written_by_default():
    # `mechgen view examples/fourbar.py --html page.html` (and fourbar's mech.explore())
    # failed: "the table would hold 729 cycles; vary fewer parameters or take fewer
    # steps" though the user had chosen neither: two steps each plus the current value
    # (the middle of its range) made 3**6 cycles
    from mechgen.view.standalone import MAX_CYCLES, grid_of
    fourbar = {"a": 0.8, "b": 2.5, "c": 2.0, "d": 3.0, "theta2": math.pi / 3,
               "omega": 2 * math.pi}
    grid = grid_of(_grid_explorer(fourbar), None, None, MAX_CYCLES)
    sizes = {k: len(v) for k, v in grid.items()}
    assert int(np.prod(list(sizes.values()))) <= MAX_CYCLES
    assert all(float(fourbar[k]) in list(v) for k, v in grid.items())   # opens on them
    assert sum(n > 1 for n in sizes.values()) >= 4, sizes
    # the quick-return's three as before: five values each, 125 cycles
    qr = {"longitud": 3.0, "velocidad": 2 * math.pi, "anguloI": 0.0}
    assert [len(v) for v in grid_of(_grid_explorer(qr), None, None, MAX_CYCLES).values()] == \
        [5, 5, 5]
    # named parameters and steps: as asked (an error where far too many)
    assert len(grid_of(_grid_explorer(qr), ["longitud"], 7, MAX_CYCLES)["longitud"]) == 7
    with pytest.raises(ValueError, match="would hold"):
        grid_of(_grid_explorer(fourbar), None, 5, MAX_CYCLES)
