"""Fixtures of the explorer's browser tests: the server's URL, the binary, a headless
Chromium driven by selenium, and a page that waits until it has drawn."""

import os
import subprocess
import time

import pytest
from selenium import webdriver
from selenium.webdriver.chrome.service import Service


@pytest.fixture(scope="session")
def url():
    return os.environ["STABOUND_URL"]


@pytest.fixture(scope="session")
def shots():
    d = os.environ.get("STABOUND_SHOTS", "target/browser-shots")
    os.makedirs(d, exist_ok=True)
    latency = os.path.join(d, "latency.txt")
    if os.path.exists(latency):
        os.remove(latency)
    return d


def cli(*args):
    """stdout of `stabound ARGS`, which must succeed."""
    out = subprocess.run(
        [os.environ["STABOUND_BIN"], *args], capture_output=True, check=True
    )
    return out.stdout


@pytest.fixture(scope="session")
def driver():
    o = webdriver.ChromeOptions()
    for a in ["--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1400,1000"]:
        o.add_argument(a)
    d = webdriver.Chrome(service=Service(os.environ.get("CHROMEDRIVER", "/usr/bin/chromedriver")), options=o)
    yield d
    d.quit()


def wait_idle(d, timeout=60):
    """Waits until the page has drawn its latest state (no request running or due)."""
    end = time.time() + timeout
    while time.time() < end:
        if d.execute_script("return window.explorer && window.explorer.seq > 0 && window.explorer.idle"):
            return
        time.sleep(0.02)
    raise AssertionError("the page did not finish drawing")


@pytest.fixture
def page(driver, url):
    def open_(query=""):
        driver.get(url + ("?" + query if query else ""))
        wait_idle(driver)
        return driver

    return open_
