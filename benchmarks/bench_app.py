"""The explorer in a real browser: slider move to new readout, and bytes sent per update.

Run: python benchmarks/bench_app.py   (needs Debian's chromium at /usr/bin/chromium)

Serves `panel serve app/` on loopback, opens the seed example in headless chromium, and moves the
head slider with the keyboard 30 times (alternately up and down). For each move it times the
key press to the mean-flow readout showing the value the core computes for the new head, and adds
up the websocket frames the server sent meanwhile. The baseline, timed in the same run, is the
same page with the display decimation switched off (every sample of every trace sent), so the
ratio shows what the min/max bands buy. Both sides' readouts are checked against windpump.
"""

from __future__ import annotations

import math
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
import windpump  # noqa: E402

from served import CHROMIUM, CHROMIUM_FLAGS, DEEP_TEXT, served_app  # noqa: E402

MOVES = 30
SEED = windpump.Design.seed_example()


def expected_readout(head: float) -> str:
    return (
        f"{1e3 * windpump.explore(SEED.replace(h=head), 600.0, math.pi / 2, 3.0).mean_flow:.4f} L/s"
    )


def measure(browser, url):
    page = browser.new_page(viewport={"width": 1400, "height": 1000})
    received = []
    page.on(
        "websocket", lambda ws: ws.on("framereceived", lambda frame: received.append(len(frame)))
    )
    page.goto(url)
    page.wait_for_function(f"() => ({DEEP_TEXT})('[data-name=mean_flow]') !== null", timeout=60_000)
    title = page.locator(".bk-slider-title", has_text="Head h [m]")
    page.locator(".bk-input-group", has=title).locator(".noUi-handle").focus()
    time.sleep(1)
    latencies, sizes, head = [], [], SEED.h
    for move in range(MOVES):
        key, head = ("ArrowRight", head + 0.1) if move % 2 == 0 else ("ArrowLeft", head - 0.1)
        target = expected_readout(round(head, 1))
        received.clear()
        start = time.perf_counter()
        page.keyboard.press(key)
        page.wait_for_function(
            f"(e) => ({DEEP_TEXT})('[data-name=mean_flow]') === e", arg=target, timeout=60_000
        )
        latencies.append(time.perf_counter() - start)
        time.sleep(0.3)  # let the rest of the update arrive before counting its bytes
        sizes.append(sum(received))
    page.close()
    return latencies, sizes


def main():
    from playwright.sync_api import sync_playwright

    rows = {}
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_FLAGS)
        for name, query in [
            ("explorer (min/max bands)", ""),
            ("baseline: every sample sent", "?resolution=full"),
        ]:
            with served_app() as (url, _server):
                measure(browser, url + query)  # warm-up: compiled kernels, caches
                rows[name] = measure(browser, url + query)
        browser.close()

    print(f"seed example, {MOVES} moves of the head slider; readouts checked against windpump")
    print(f"{'':32s}{'median':>10s}{'90th pct':>10s}{'bytes/update':>14s}")
    for name, (latencies, sizes) in rows.items():
        p90 = statistics.quantiles(latencies, n=10)[-1]
        print(
            f"{name:32s}{statistics.median(latencies) * 1e3:8.0f} ms{p90 * 1e3:8.0f} ms"
            f"{statistics.median(sizes) / 1e3:11.1f} KB"
        )
    (fast, fast_bytes), (slow, slow_bytes) = rows.values()
    print(
        f"ratios: latency {statistics.median(slow) / statistics.median(fast):.1f}x, "
        f"bytes {statistics.median(slow_bytes) / statistics.median(fast_bytes):.0f}x"
    )


if __name__ == "__main__":
    main()
