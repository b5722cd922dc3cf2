"""The view without the internet (issue 42): ``mechgen view --html`` and ``mech.explore()``
embed BokehJS in the page (bokeh.resources.INLINE), so that a machine with no network (a
lab, a plane) still draws the mechanism. Each page is loaded in headless Chromium whose
every host name resolves to nothing and whose proxy is a dead address, and the slider
block of the quick-return must be drawn where mech.solve puts it at T = 0."""
import os
import re
import time

import pytest

from conftest import EXAMPLES, GENERATED

pytest.importorskip("bokeh", reason="the view needs bokeh (pip install bokeh)")
webdriver = pytest.importorskip("selenium.webdriver",
                                reason="the browser tests need selenium (pip install selenium)")

import mechgen  # noqa: E402
from mechgen.cli import main  # noqa: E402

MODEL = os.path.join(EXAMPLES, "quick_return.py")
from browsers import chromium, need_browser  # noqa: E402
BLOCK = """
if (typeof Bokeh === 'undefined' || !Bokeh.documents.length) { return null; }
const doc = Bokeh.documents[0];
for (let m = 0; m < 40; m++) {
  const src = doc.get_model_by_name('layer' + m);
  if (src === null) { continue; }
  const g = src.data;
  for (let r = 0; r < g.frame.length; r++) {
    if (g.owner[r] == 'deslizadera' && g.xs !== undefined) {
      return [Math.min(...g.xs[r]), Math.min(...g.ys[r])];
    }
  }
}
return null;
"""
REMOTE = re.compile(r"<script[^>]*\ssrc=[\"']?(https?:)?//", re.I)


@pytest.fixture(scope="module")
def offline():
    """Chromium with the network off: no host name resolves, every request would go to
    a proxy at a port where nothing listens."""
    drv = chromium("--host-resolver-rules=MAP * ~NOTFOUND", "--proxy-server=127.0.0.1:9",
                   "--proxy-bypass-list=<-loopback>")
    yield drv
    drv.quit()


@pytest.fixture(scope="module")
def mech():
    return mechgen.compile(MODEL, outdir=GENERATED, tier="compiled")


def drawn(drv, mech, timeout=60.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        block = drv.execute_script(BLOCK)
        if block is not None:
            want = mech.solve(0.0)["X4"]
            assert abs(block[0] - want) < 1e-5 and abs(block[1] - 10) < 1e-5, (block, want)
            return
        time.sleep(0.2)
    raise AssertionError("the page drew no mechanism without the network")


@need_browser
def test_the_network_is_really_off(offline):
    from selenium.common.exceptions import WebDriverException
    with pytest.raises(WebDriverException, match="ERR_"):
        offline.get("https://cdn.bokeh.org/bokeh/release/bokeh-3.9.2.min.js")


@need_browser
def test_the_html_page_draws_offline(offline, mech, tmp_path):
    out = str(tmp_path / "view.html")
    assert main(["view", MODEL, "--html", out, "--vary", "longitud", "--steps", "3",
                 "-n", "50"]) == 0
    text = open(out, encoding="utf-8").read()
    assert not REMOTE.search(text)
    offline.get("file://" + out)
    drawn(offline, mech)


@need_browser
def test_explore_in_a_notebook_draws_offline(offline, mech, tmp_path):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(
        "import mechgen\n"
        f"mech = mechgen.compile({MODEL!r}, outdir={GENERATED!r}, tier='compiled')\n"
        "page = mech.explore(vary=['longitud'], steps=3, n=50)\n")]
    nbclient.NotebookClient(nb, timeout=300, kernel_name="python3",
                            resources={"metadata": {"path": str(tmp_path)}}).execute()
    # the notebook's outputs as a browser shows them: scripts run, HTML in place
    parts = []
    for o in nb.cells[0].outputs:
        data = o.get("data", {})
        if "application/javascript" in data:
            parts.append(f"<script>{data['application/javascript']}</script>")
        if "text/html" in data:
            parts.append(data["text/html"])
    page = "<!DOCTYPE html><html><head><meta charset='utf-8'></head><body>" + \
        "\n".join(parts) + "</body></html>"
    assert "cdn.bokeh.org" not in page and not REMOTE.search(page)
    assert "<iframe srcdoc=" in page
    path = tmp_path / "notebook.html"
    path.write_text(page, encoding="utf-8")
    offline.get("file://" + str(path))
    from selenium.webdriver.common.by import By
    offline.switch_to.frame(offline.find_element(By.TAG_NAME, "iframe"))
    try:
        drawn(offline, mech)
    finally:
        offline.switch_to.default_content()
