"""The web view in a real browser: an `addipos serve --web --realtime 1`
and a headless Chromium driven through WebDriver (Debian's `chromium`
and `chromium-driver`, which .ci/run installs)."""

import contextlib
import os
import shutil
import socket
import subprocess
import tempfile
import time
import urllib.request
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def addipos_bin() -> str:
    return os.environ.get("ADDIPOS_BIN", str(ROOT / "target" / "debug" / "addipos"))


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Served:
    """A running `addipos serve` with its UOI and web addresses."""

    def __init__(self, uoi: int, web: int, proc: subprocess.Popen):
        self.uoi = f"127.0.0.1:{uoi}"
        self.url = f"http://127.0.0.1:{web}/"
        self.proc = proc

    def call(self, *request: str) -> str:
        """One request on the bus through `addipos call`; its answer."""
        out = subprocess.run(
            [addipos_bin(), "call", "--timeout", "10", self.uoi, *request],
            capture_output=True, text=True, timeout=30, check=True,
        )
        return out.stdout.strip()


def wait_for(what, limit_s: float, step_s: float = 0.02):
    """`what()` once it is true, else fails after `limit_s`."""
    end = time.monotonic() + limit_s
    while time.monotonic() < end:
        v = what()
        if v:
            return v
        time.sleep(step_s)
    raise AssertionError(f"not within {limit_s} s")


@contextlib.contextmanager
def serving():
    """`addipos serve --web --realtime 1` on free loopback ports."""
    uoi, web = free_port(), free_port()
    data = tempfile.mkdtemp(prefix="addipos-web-")
    proc = subprocess.Popen(
        [addipos_bin(), "serve", "--no-persist", "--data-dir", data,
         "--listen", str(uoi), "--web", str(web), "--realtime", "1"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )
    s = Served(uoi, web, proc)

    def up():
        try:
            with urllib.request.urlopen(s.url + "state", timeout=1) as r:
                return r.status == 200
        except OSError:
            return False

    try:
        wait_for(up, 20, 0.1)
        yield s
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
        shutil.rmtree(data, ignore_errors=True)


def chromium_paths():
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    driver = shutil.which("chromedriver") or (
        "/usr/bin/chromedriver" if os.path.exists("/usr/bin/chromedriver") else None)
    return browser, driver


@pytest.fixture(scope="module")
def served():
    with serving() as s:
        yield s


@pytest.fixture(scope="module")
def browser():
    path, driver_path = chromium_paths()
    if not path or not driver_path:
        pytest.skip("Chromium or chromedriver is not installed (Debian packages chromium, "
                    "chromium-driver; .ci/run installs them): the browser tests did not run")
    with chromium(path, driver_path) as driver:
        yield driver


@contextlib.contextmanager
def chromium(path: str, driver_path: str):
    """Headless Chromium under WebDriver, its console log kept."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    opts = webdriver.ChromeOptions()
    opts.binary_location = path
    for arg in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage",
                "--disable-gpu", "--window-size=1280,900", "--no-first-run"):
        opts.add_argument(arg)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(executable_path=driver_path), options=opts)
    driver.set_page_load_timeout(30)
    try:
        yield driver
    finally:
        driver.quit()
