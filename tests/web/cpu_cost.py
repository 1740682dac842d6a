"""What the web view costs the server: CPU of `addipos serve --realtime 1
--web` during a 1 ms real-time run with OTC, first with no page open,
then with a page open in headless Chromium (docs/performance.md).

    target/ci-venv/bin/python tests/web/cpu_cost.py target/release/addipos [SECONDS]

Not a test (timing depends on the machine): it prints the figures."""

import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import conftest  # noqa: E402


def cpu_seconds(pid: int) -> float:
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def share_of_a_core(pid: int, seconds: float) -> float:
    c0, t0 = cpu_seconds(pid), time.monotonic()
    time.sleep(seconds)
    return (cpu_seconds(pid) - c0) / (time.monotonic() - t0)


def otc_run(served) -> None:
    """OTC RADIUS AUTO on group 1 with a grinding disc, corrected on the
    left, then a long run of half circles (about a minute at F1200)."""
    for request in (
        "W 1300/1/1/8 i 1", "W 1300/1/1/6 d 2", "W 1300/3/1/30 i 2",
        "W 1300/3/1/32 d 5000", "W 1300/3/1/2 i 0", "W 1300/3/1/4 d 20000",
        "W 1300/3/1/50 i 5000", "W 1300/3/1/51 i 1", "W 1300/1/1/9 i 0",
        "W 1300/1/1/3 i 1", "W 1300/3/1/1 i 1",
    ):
        assert served.call(*request.split()) == "ok", request
    for _ in range(25):
        assert served.call("CIR", "CCW", "X0", "Y20", "I0", "J10", "F1200") == "ok"
        assert served.call("CIR", "CCW", "X0", "Y0", "I0", "J-10") == "ok"


# 100,000 elements (lines and arcs along a spiral) and a trail through
# them, added as the event stream adds them, in updates of 20,000.
MANY = """
const spooled = [], executed = [];
let h = 0, v = 0;
for (let i = 0; i < 100000; i++) {
  const a = i * 0.01, r = 20 + i * 0.002;
  const to = [r * Math.cos(a), r * Math.sin(a)];
  spooled.push({from: [h, v], to: to, arc: i % 2 ? [[0, 0], true] : null, rapid: i % 97 === 0});
  executed.push(to);
  h = to[0]; v = to[1];
}
for (let k = 0; k < 100000; k += 20000) {
  window.addiposDraw.add(spooled.slice(k, k + 20000), executed.slice(k, k + 20000));
}
"""


def frame(browser, after: int) -> tuple:
    """The first frame drawn after frame number `after`: (ms, whole)."""
    def drawn():
        n = browser.execute_script("return document.getElementById('path').dataset.frames")
        return n is not None and int(n) > after
    conftest.wait_for(drawn, 30)
    d = browser.execute_script("return Object.assign({}, document.getElementById('path').dataset)")
    return float(d["frameMs"]), d["frameWhole"] == "true", int(d["frames"])


def draw_cost(browser) -> None:
    """Frame times of the page's drawing with 100,000 elements."""
    frames = lambda: int(browser.execute_script(  # noqa: E731
        "return document.getElementById('path').dataset.frames || 0"))
    before = frames()
    browser.execute_script(MANY)
    whole_ms, whole, n = frame(browser, before)
    browser.execute_script(
        "window.addiposDraw.add([{from: [1, 1], to: [2, 2], arc: null, rapid: false}], [[2, 2]])")
    step_ms, step_whole, n = frame(browser, n)
    print(f"100,000 elements drawn: {whole_ms:.1f} ms (whole picture: {whole}); "
          f"one element more: {step_ms:.1f} ms (whole picture: {step_whole})")


def main() -> None:
    os.environ["ADDIPOS_BIN"] = sys.argv[1]
    seconds = float(sys.argv[2]) if len(sys.argv) > 2 else 10.0
    with conftest.serving() as served:
        otc_run(served)
        time.sleep(1)
        pid = served.proc.pid
        idle = share_of_a_core(pid, seconds)
        with conftest.chromium(*conftest.chromium_paths()) as browser:
            browser.get(served.url)
            conftest.wait_for(
                lambda: browser.find_element("id", "link").text == "live", 10)
            time.sleep(1)
            viewed = share_of_a_core(pid, seconds)
            otc = browser.find_element("id", "otc-1").text
            queue = browser.find_element("id", "queue").text
    # The drawing on an idle server's page: only the elements added here.
    with conftest.serving() as idle_server:
        with conftest.chromium(*conftest.chromium_paths()) as browser:
            browser.get(idle_server.url)
            conftest.wait_for(
                lambda: browser.find_element("id", "link").text == "live", 10)
            time.sleep(0.5)
            draw_cost(browser)
    print(f"server CPU, no page open:  {idle * 100:.2f} % of one core")
    print(f"server CPU, one page open: {viewed * 100:.2f} % of one core")
    print(f"the view's cost:           {(viewed - idle) * 100:.2f} % of one core")
    print(f"page: queue {queue}; {otc}")


if __name__ == "__main__":
    main()
