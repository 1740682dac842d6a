"""The live web view (docs/web.md) in headless Chromium against
`addipos serve --web --realtime 1`: what the bus says appears on the
page, the motion shows on the way, the page is read-only and carries its
Content-Security-Policy, the browser logs no error, and the path is drawn.

`ADDIPOS_WEB_SCREENSHOT=FILE` also saves the page as it is after the
path test (docs/img/web-view.png is made so, docs/web.md)."""

import io
import os
import time
import urllib.error
import urllib.request

import pytest
from PIL import Image
from selenium.webdriver.common.by import By

from conftest import wait_for

# RADIUS, STATUS and ERROR of group 1 (docs/objects.md).
RADIUS_1 = "1300/1/1/6"
STATUS_1 = "1300/1/1/3"
ERROR_1 = "1300/1/1/1"
LEFT_1 = "1300/1/1/9"


def text(browser, element_id: str) -> str:
    return browser.find_element(By.ID, element_id).text


def number_or_none(browser, element_id: str):
    try:
        return float(text(browser, element_id))
    except Exception:
        return None


@pytest.fixture(scope="module")
def page(served, browser):
    browser.get(served.url)
    wait_for(lambda: text(browser, "link") == "live", 10)
    return browser


def test_a_radius_written_on_the_bus_appears_within_a_second(served, page):
    # Group 1 in use (STATUS read), so that its tool table shows.
    served.call("R", STATUS_1, "i")
    assert served.call("W", RADIUS_1, "d", "2.5") == "ok"
    written = time.monotonic()
    wait_for(lambda: number_or_none(page, "tool-1-0-radius") == 2.5, 1.0, 0.01)
    assert time.monotonic() - written <= 1.0


def test_status_and_error_are_what_the_bus_reads(served, page):
    for element, addr in (("status-1", STATUS_1), ("error-1", ERROR_1)):
        on_bus = served.call("R", addr, "i")
        wait_for(lambda: text(page, element) == on_bus, 2)
    bits = text(page, "error-1-bits")
    assert bits == "none" if served.call("R", ERROR_1, "i") == "0" else bits != "none"


def test_a_two_second_line_shows_the_way_and_ends_on_the_end_point(served, page):
    start = float(text(page, "pos-X"))
    end = start + 100.0
    # 100 mm at 3000 mm/min: two seconds of real time.
    assert served.call("LIN", f"X{end:g}", "F3000") == "ok"
    seen = []
    deadline = time.monotonic() + 15
    while time.monotonic() < deadline:
        x = number_or_none(page, "pos-X")
        if x is not None and (not seen or x != seen[-1]):
            seen.append(x)
        if x == end:
            break
        time.sleep(0.02)
    on_the_way = [x for x in seen if start < x < end]
    assert len(on_the_way) >= 5, seen
    assert all(b >= a for a, b in zip(seen, seen[1:])), f"went backwards: {seen}"
    assert seen[-1] == end, seen
    wait_for(lambda: text(page, "queue") == "0", 5)
    assert served.call("QUEUE") == "0"


def test_the_path_is_drawn_in_the_colours_of_addipos_plot(served, page):
    # A corrected contour (left of the path, the radius written above),
    # with an arc, at 6000 mm/min.
    for request in (
        ("W", LEFT_1, "i", "0"),
        ("W", STATUS_1, "i", "1"),
        ("LIN", "X100", "Y30", "F6000"),
        ("CIR", "CCW", "X70", "Y60", "I-30", "J0"),
        ("LIN", "X40", "Y60"),
        ("LIN", "X40", "Y10"),
        ("W", STATUS_1, "i", "0"),
        ("LIN", "X60", "Y0"),
    ):
        assert served.call(*request) == "ok", request
    wait_for(lambda: text(page, "pos-X") == "60.0000" and text(page, "pos-Y") == "0.0000", 15)
    wait_for(lambda: text(page, "queue") == "0", 5)
    assert served.call("R", ERROR_1, "i") == "0", "the correction ran without a fault"
    time.sleep(0.3)  # the last update drawn
    shot = page.find_element(By.ID, "path-box").screenshot_as_png
    raw = Image.open(io.BytesIO(shot)).convert("RGB").tobytes()
    pixels = [tuple(raw[i:i + 3]) for i in range(0, len(raw), 3)]

    def near(rgb, want, tol=40):
        return all(abs(a - b) <= tol for a, b in zip(rgb, want))

    corrected = sum(1 for p in pixels if near(p, (0x88, 0xCC, 0xFF)))
    executed = sum(1 for p in pixels if near(p, (0xDD, 0x22, 0x22)))
    assert corrected > 500, f"{corrected} light-blue pixels"
    assert executed > 100, f"{executed} red pixels"
    target = os.environ.get("ADDIPOS_WEB_SCREENSHOT")
    if target:
        page.save_screenshot(target)


def test_the_view_is_read_only_and_every_answer_carries_the_policy(served):
    for path in ("", "state", "app.js", "style.css", "nothing"):
        req = urllib.request.Request(served.url + path)
        try:
            with urllib.request.urlopen(req, timeout=5) as r:
                csp = r.headers["Content-Security-Policy"]
        except urllib.error.HTTPError as e:
            assert e.code == 404 and path == "nothing"
            csp = e.headers["Content-Security-Policy"]
        assert csp and "default-src 'self'" in csp, path
    for method in ("POST", "PUT", "DELETE"):
        req = urllib.request.Request(served.url + "state", data=b"{}", method=method)
        with pytest.raises(urllib.error.HTTPError) as refused:
            urllib.request.urlopen(req, timeout=5)
        assert refused.value.code == 405, method
        assert "default-src 'self'" in refused.value.headers["Content-Security-Policy"]


def test_the_browser_logged_no_error(page):
    errors = [e for e in page.get_log("browser") if e["level"] in ("SEVERE", "ERROR")]
    assert errors == []
