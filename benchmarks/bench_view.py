"""The live view's redraw latency, measured in the browser: the time from a parameter
slider's change to the new cycle's glyphs drawn in the page (headless chromium through
Selenium; a JS stamp, window.mechgen_drawn, set when the page has moved every glyph to
the new cycle's columns). Each change goes to the Bokeh server in this process, which
solves the whole cycle with the compiled module (Explorer.compute), draws the glyphs
again when a body's shape changed, and sends the new columns back.

Models: the quick-return (examples/quick_return.py, 1,000 times a cycle; `longitud`
changes the crank's shape, `velocidad` only the motion) and the Strandbeest leg with its
crank's length a parameter (benchmarks/strandbeest_view.py, 1,000 times).

Run: PYTHONPATH=$PWD MECHGEN_TIER=compiled python3 benchmarks/bench_view.py [--repeat 15]
"""
import argparse
import os
import shutil
import statistics
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, ROOT)

import mechgen  # noqa: E402
from mechgen.view.explorer import Explorer  # noqa: E402
from mechgen.view.server import ViewServer  # noqa: E402

CHANGE = """
const [name, value, done] = arguments;
const doc = Bokeh.documents[0];
const before = window.mechgen_redraws || 0;
const start = performance.now();
doc.get_model_by_name(name).value = value;
(function poll() {
  if ((window.mechgen_redraws || 0) > before) { done(window.mechgen_drawn - start); }
  else { setTimeout(poll, 1); }
})();
"""


def browser():
    from selenium import webdriver
    from selenium.webdriver.chrome.options import Options
    from selenium.webdriver.chrome.service import Service
    opts = Options()
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1400,1000"):
        opts.add_argument(arg)
    opts.binary_location = shutil.which("chromium")
    drv = webdriver.Chrome(options=opts, service=Service(shutil.which("chromedriver")))
    drv.set_script_timeout(60)
    return drv


def measure(drv, path, param, values, repeat, n=1000):
    srv = ViewServer(lambda: Explorer(mechgen.compile(path, tier="compiled"), n=n)).start()
    try:
        drv.get(srv.url)
        end = time.monotonic() + 120
        while not drv.execute_script("return window.mechgen_redraws || 0"):
            if time.monotonic() > end:
                raise SystemExit(f"the page of {path} never drew (see the server's messages)")
            time.sleep(0.05)
        drv.execute_async_script(CHANGE, f"param_{param}", values[-1])    # warm
        out = []
        for k in range(repeat):
            out.append(drv.execute_async_script(CHANGE, f"param_{param}",
                                                values[k % len(values)]))
        return out
    finally:
        srv.stop()


def compute_only(path, param, values, repeat, n=1000):
    """The server's share: Explorer.compute alone (the cycle solved, the glyphs drawn
    again when a shape changed, the columns made), in this process, no page."""
    ex = Explorer(mechgen.compile(path, tier="compiled"), n=n)
    ex.compute({param: values[-1]})
    out = []
    for k in range(repeat):
        t = time.perf_counter()
        ex.compute({param: values[k % len(values)]})
        out.append(1e3 * (time.perf_counter() - t))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=30)
    args = ap.parse_args()
    drv = browser()
    cases = [
        ("quick-return, longitud (shape changes)", os.path.join(ROOT, "examples", "quick_return.py"),
         "longitud", list(np.linspace(2.0, 3.6, 7))),
        ("quick-return, velocidad (motion only)", os.path.join(ROOT, "examples", "quick_return.py"),
         "velocidad", list(np.linspace(4.0, 8.0, 7))),
        ("Strandbeest leg, crank_length (shape)", os.path.join(HERE, "strandbeest_view.py"),
         "crank_length", list(np.linspace(13.0, 16.0, 7))),
    ]
    try:
        print(f"{'case':42s} {'min':>8s} {'median':>8s} {'p90':>8s} {'compute':>8s}   (ms, 1,000 "
              f"times a cycle, {args.repeat} changes; compute: the server's share, median)",
              flush=True)
        for label, path, param, values in cases:
            ms = measure(drv, path, param, values, args.repeat)
            own = compute_only(path, param, values, args.repeat)
            p90 = float(np.percentile(ms, 90))
            print(f"{label:42s} {min(ms):8.1f} {statistics.median(ms):8.1f} {p90:8.1f} "
                  f"{statistics.median(own):8.1f}", flush=True)
    finally:
        drv.quit()


if __name__ == "__main__":
    main()
