"""The live view under a real hand (issue 43): the `longitud` slider's handle dragged in
quick bursts with Selenium's ActionChains (real pointer drags, not values set from a
script), the time slider dragged, and numbers typed into the value box; after each burst,
once the page settles, the drawn slider block and the cycle's traced path are checked
against mech.solve at the parameter value and time the page shows. Changes that arrive
faster than the server solves are coalesced (the latest wins): the page must end at the
last value, with no error in the server's log (Bokeh's PATCH-DOC AssertionError, "Failed
sending message as connection was closed"). The quick-return's default plots show
quantities that move."""
import logging
import os
import time

import numpy as np
import pytest

from conftest import EXAMPLES, GENERATED

bokeh = pytest.importorskip("bokeh", reason="the view needs bokeh (pip install bokeh)")
webdriver = pytest.importorskip("selenium.webdriver",
                                reason="the browser tests need selenium (pip install selenium)")

import mechgen  # noqa: E402

MODEL = os.path.join(EXAMPLES, "quick_return.py")
from browsers import chromium, need_browser  # noqa: E402

pytestmark = need_browser

# a widget's element inside its shadow root (Bokeh 3 draws each widget in one)
PART = """
const m = Bokeh.documents[0].get_model_by_name(arguments[0]);
const v = Bokeh.index.find_one(m);
return v.shadow_el.querySelector(arguments[1]);
"""
STATE = """
const doc = Bokeh.documents[0];
const L = doc.get_model_by_name('param_longitud').value;
const box = doc.get_model_by_name('value_longitud').value;
const t = doc.get_model_by_name('time').value;
let block = null;
for (let m = 0; m < 40; m++) {
  const src = doc.get_model_by_name('layer' + m);
  if (src === null) { continue; }
  const g = src.data;
  for (let r = 0; r < g.frame.length; r++) {
    if (g.owner[r] == 'deslizadera' && g.xs !== undefined) {
      block = [Math.min(...g.xs[r]), Math.min(...g.ys[r])];
    }
  }
}
const d = doc.get_model_by_name('cycle').data;
const k = d.t.length - 1;
const message = doc.get_model_by_name('message');
return [L, box, t, block, [d.t[0], d.tr0x[0]], [d.t[k >> 1], d.tr0x[k >> 1]],
        message.visible ? message.text : ''];
"""


class Errors(logging.Handler):
    """Every warning or error the server side logs (bokeh, tornado)."""

    def __init__(self):
        super().__init__(logging.WARNING)
        self.records = []

    def emit(self, record):
        self.records.append(f"{record.name}: {record.getMessage()}")


@pytest.fixture(scope="module")
def mech():
    return mechgen.compile(MODEL, outdir=GENERATED, tier="compiled")


@pytest.fixture(scope="module")
def errors():
    handler = Errors()
    for name in ("bokeh", "tornado"):
        logging.getLogger(name).addHandler(handler)
    yield handler
    for name in ("bokeh", "tornado"):
        logging.getLogger(name).removeHandler(handler)


@pytest.fixture(scope="module")
def server(mech, errors):
    from mechgen.view.explorer import Explorer
    from mechgen.view.server import ViewServer
    srv = ViewServer(lambda: Explorer(mech, n=1000, trace=["deslizadera[1]"]))
    srv.start()
    yield srv
    srv.stop()


@pytest.fixture(scope="module")
def page(server):
    drv = chromium()
    drv.get(server.url)
    end = time.monotonic() + 60
    while not drv.execute_script("return window.mechgen_redraws || 0"):
        assert time.monotonic() < end, "the page never drew"
        time.sleep(0.05)
    yield drv
    drv.quit()


def assembles(mech, L):
    try:
        mech.with_params(longitud=L).sweep(0.0, 1.0, 1000)
    except mechgen.MechgenError:
        return False
    return True


def settled(drv, mech, timeout=30.0, tol=1e-7):
    """Wait until the page shows the slider block and the traced path of mech.solve at
    the longitud and time it shows (and the value box agrees with the slider), or says
    that the mechanism cannot assemble at a longitud where its sweep fails; returns
    (longitud, t). Fails naming what the page still shows at the timeout."""
    end = time.monotonic() + timeout
    last = None
    while time.monotonic() < end:
        L, box, t, block, (t0, x0), (tm, xm), message = drv.execute_script(STATE)
        last = (L, box, t, block, x0, xm, message)
        if message and abs(box - L) < 1e-12 and not assembles(mech, L):
            return L, t             # the page says it cannot assemble, and it cannot
        if block is not None and None not in block and x0 is not None and xm is not None \
                and abs(box - L) < 1e-12:
            m = mech.with_params(longitud=L)
            want = m.solve(t)["X4"]
            if abs(block[0] - want) < tol and abs(block[1] - 10) < tol and \
                    abs(x0 - m.solve(t0)["X4"]) < tol and abs(xm - m.solve(tm)["X4"]) < tol:
                return L, t
        time.sleep(0.1)
    raise AssertionError(f"the page did not settle on mech.solve's pose: it shows longitud, "
                         f"box, t, block, path = {last}")


def handle(drv, name):
    return drv.execute_script(PART, name, ".noUi-handle")


RECTS = """
const m = Bokeh.documents[0].get_model_by_name(arguments[0]);
const v = Bokeh.index.find_one(m);
v.el.scrollIntoView({block: 'center'});
const track = v.shadow_el.querySelector('.noUi-target').getBoundingClientRect();
const knob = v.shadow_el.querySelector('.noUi-handle').getBoundingClientRect();
return [track.left, track.right, knob.left + knob.width / 2];
"""


def drag(drv, name, steps):
    """A real drag of a slider's handle: pressed, moved by each of ``steps`` pixels in
    turn without a pause (kept on the track), released."""
    from selenium.webdriver.common.action_chains import ActionChains
    left, right, x = drv.execute_script(RECTS, name)
    chain = ActionChains(drv, duration=0).click_and_hold(handle(drv, name))
    for dx in steps:
        dx = int(min(max(x + dx, left + 3), right - 3) - x)
        x += dx
        chain.move_by_offset(dx, 0)
    chain.release().perform()


def type_value(drv, text):
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.keys import Keys
    box = drv.execute_script(PART, "value_longitud", "input")
    ActionChains(drv, duration=0).click(box).key_down(Keys.CONTROL).send_keys("a") \
        .key_up(Keys.CONTROL).send_keys(text).send_keys(Keys.ENTER).perform()


def test_rapid_drags_and_typing_end_on_the_solved_pose(page, mech, errors):
    rng = np.random.default_rng(43)
    L0, _ = settled(page, mech)
    assert L0 == pytest.approx(3.0)
    seen = set()
    for burst in range(6):
        steps = [int(s) for s in rng.integers(-40, 41, size=12)]
        drag(page, "param_longitud", steps)
        L, t = settled(page, mech)
        seen.add(round(L, 6))
        drag(page, "time", [int(s) for s in rng.integers(-60, 61, size=6)])
        L2, t2 = settled(page, mech)
        assert L2 == L
    assert len(seen) > 3, f"the drags moved the slider to only {sorted(seen)}"
    for text, want in (("2.75", 2.75), ("3.6", 3.6), ("2.1", 2.1)):
        type_value(page, text)
        L, _ = settled(page, mech)
        assert L == pytest.approx(want, abs=1e-12), f"typed {text}, the page shows {L}"
    # typing and dragging in one burst: the drag, after the typing, wins
    type_value(page, "2.5")
    drag(page, "param_longitud", [15, 15, -5, 30])
    L, _ = settled(page, mech)
    assert L != pytest.approx(2.5)
    bad = [r for r in errors.records if "AssertionError" in r or "Failed sending" in r
           or "error" in r.lower()]
    assert not bad, "the server logged:\n" + "\n".join(bad[:10])


def test_the_default_plots_show_quantities_that_move(tmp_path):
    """The shaper with forces declares no output: plot 1 was its last coordinate, the
    ram's angle Th4, which is 0 all the cycle; now a coordinate that moves, and plot 2
    the crank's torque."""
    from mechgen.view.explorer import Explorer
    forces = mechgen.compile(os.path.join(EXAMPLES, "quick_return_forces.py"),
                             outdir=str(tmp_path), tier="python")
    ex = Explorer(forces, n=60, compiled=False)
    assert ex.plots[1] == "driver: crank driver"
    for name in ex.plots:
        values = np.asarray(ex.data[name])
        assert np.ptp(values) > 1e-6 * (1 + np.max(np.abs(values))), (name, ex.plots)
