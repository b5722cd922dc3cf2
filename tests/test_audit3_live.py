"""Audit of `mechgen view` (API.md §7) as a user drives it: the server page with the model
file watched while it is edited, and what the page says where it cannot show the view.
Found in headless chromium (selenium) on examples/fourbar.py; checked here on the Bokeh
documents the server builds, on the plain tier."""
import os
import shutil

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
