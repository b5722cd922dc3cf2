"""Headless Chromium for the live view's tests (Debian's chromium and chromedriver, which
.ci/run installs): where they are, the mark that skips a test without them, and a driver."""
import shutil

import pytest

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
DRIVER = shutil.which("chromedriver")
need_browser = pytest.mark.skipif(
    CHROMIUM is None or DRIVER is None,
    reason="no headless browser: apt-get install chromium chromium-driver (.ci/run does)")


def chromium(*flags):
    """A Selenium driver of headless Chromium, 1400 × 1000, with ``flags`` added."""
    from selenium import webdriver
    from selenium.webdriver.chrome.options import Options
    from selenium.webdriver.chrome.service import Service
    opts = Options()
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1400,1000",
                *flags):
        opts.add_argument(arg)
    opts.binary_location = CHROMIUM
    return webdriver.Chrome(options=opts, service=Service(DRIVER))
