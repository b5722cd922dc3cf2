"""Audit of what a user sees (pictures, the live view): defects found and fixed."""
import math
import os

import numpy as np
import pytest

from conftest import EXAMPLES


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
