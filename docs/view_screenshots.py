"""The README's pictures of the live view (mechgen view), taken in headless chromium:
docs/view_quick_return.png (the quick-return at T = 0.3, its time and parameter sliders,
the traced paths and two plots), docs/view_strandbeest.png (Jansen's leg with its foot's
path) and docs/view_cannot_assemble.png (the quick-return with a crank too long for
the slider's rod: the message and the range over which it assembles).

Run: PYTHONPATH=$PWD MECHGEN_TIER=compiled python3 docs/view_screenshots.py
"""
import os
import shutil
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, ROOT)

import mechgen  # noqa: E402
from mechgen.view.explorer import Explorer  # noqa: E402
from mechgen.view.server import ViewServer  # noqa: E402

SET = """
const doc = Bokeh.documents[0];
window.mechgen_before = window.mechgen_redraws || 0;
doc.get_model_by_name(arguments[0]).value = arguments[1];
"""


def browser(width, height):
    from selenium import webdriver
    from selenium.webdriver.chrome.options import Options
    from selenium.webdriver.chrome.service import Service
    opts = Options()
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                f"--window-size={width},{height}", "--force-device-scale-factor=1"):
        opts.add_argument(arg)
    opts.binary_location = shutil.which("chromium")
    return webdriver.Chrome(options=opts, service=Service(shutil.which("chromedriver")))


def wait(drv, script):
    end = time.monotonic() + 60
    while not drv.execute_script(script):
        if time.monotonic() > end:
            raise SystemExit(f"the page never answered {script!r}")
        time.sleep(0.05)


def shoot(path, out, settings, size=(1340, 880), **options):
    srv = ViewServer(lambda: Explorer(mechgen.compile(path, tier="compiled"), **options)).start()
    drv = browser(*size)
    try:
        drv.get(srv.url)
        wait(drv, "return window.mechgen_redraws || 0")
        for name, value in settings:
            drv.execute_script(SET, name, value)
            wait(drv, "return (window.mechgen_redraws || 0) > window.mechgen_before")
        time.sleep(0.5)
        drv.save_screenshot(out)
        print(f"wrote {out}")
    finally:
        drv.quit()
        srv.stop()


def main():
    qr = os.path.join(ROOT, "examples", "quick_return.py")
    shoot(qr, os.path.join(HERE, "view_quick_return.png"), [("time", 0.3)],
          trace=["deslizadera[1]", "manivela[2]", "colisa[2]"], plots=["stroke_x", "Th3d"])
    shoot(os.path.join(ROOT, "benchmarks", "strandbeest_view.py"),
          os.path.join(HERE, "view_strandbeest.png"), [("time", 0.6)], size=(1340, 1010),
          trace=["foot[3]", "crank[2]"], plots=["X8", "Th2"])
    shoot(qr, os.path.join(HERE, "view_cannot_assemble.png"), [("param_longitud", 4.4)])


if __name__ == "__main__":
    main()
