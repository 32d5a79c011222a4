"""The explorer in a real browser: first page after a fresh start, slider move to new readout, bytes
on the wire, and a class of 30 pages opening at once.

Run: python benchmarks/bench_app.py   (needs Debian's chromium at /usr/bin/chromium)

1. First page: a fresh `panel serve app/`, then the time from opening the page to the mean-flow
   readout showing, for the first page and for a second one (the goal: the same).
2. Page weight: the bytes the first page transfers (compressed as sent) against the same files
   uncompressed.
3. Slider to readout: the head slider moved with the keyboard 30 times; each move is timed from the
   key press to the readout showing the value windpump computes for the new head, and the websocket
   bytes the server sent meanwhile are added up. The baseline, timed in the same run, is the same
   page with display decimation off (`?resolution=full`: every sample of every trace sent).
4. A class: 30 pages opened at once on one server; each page's time to its readout.
Every readout is checked against windpump, so a fast wrong page cannot pass.
"""

from __future__ import annotations

import asyncio
import math
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
import windpump  # noqa: E402

from served import CHROMIUM, CHROMIUM_FLAGS, DEEP_TEXT, served_app  # noqa: E402

MOVES = 30
CLASS = 30
SEED = windpump.Design.seed_example()
READOUT = f"() => ({DEEP_TEXT})('[data-name=mean_flow]')"


def expected_readout(head: float) -> str:
    return (
        f"{1e3 * windpump.explore(SEED.replace(h=head), 600.0, math.pi / 2, 3.0).mean_flow:.4f} L/s"
    )


def open_timed(browser, url):
    """Open the page; return (seconds to the right readout, bytes on the wire, bytes unpacked)."""
    page = browser.new_page(viewport={"width": 1400, "height": 1000})
    finished = []
    page.on("requestfinished", lambda request: finished.append(request))
    start = time.perf_counter()
    page.goto(url)
    page.wait_for_function(
        f"(e) => ({READOUT})() === e", arg=expected_readout(SEED.h), timeout=300_000
    )
    seconds = time.perf_counter() - start
    wire = sum(r.sizes()["responseBodySize"] + r.sizes()["responseHeadersSize"] for r in finished)
    unpacked = 0
    for request in finished:
        try:
            unpacked += len(request.response().body())
        except Exception:  # a body already released: count what went over the wire
            unpacked += request.sizes()["responseBodySize"]
    page.close()
    return seconds, wire, unpacked


def slider_moves(browser, url):
    page = browser.new_page(viewport={"width": 1400, "height": 1000})
    received = []
    page.on(
        "websocket", lambda ws: ws.on("framereceived", lambda frame: received.append(len(frame)))
    )
    page.goto(url)
    page.wait_for_function(f"() => ({READOUT})() !== null", timeout=300_000)
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
        page.wait_for_function(f"(e) => ({READOUT})() === e", arg=target, timeout=60_000)
        latencies.append(time.perf_counter() - start)
        time.sleep(0.3)  # let the rest of the update arrive before counting its bytes
        sizes.append(sum(received))
    page.close()
    return latencies, sizes


async def a_class(url):
    """CLASS pages opened at once: each one's seconds from opening to its correct readout."""
    from playwright.async_api import async_playwright

    target = expected_readout(SEED.h)

    async def student(browser):
        page = await browser.new_page()
        start = time.perf_counter()
        await page.goto(url, timeout=600_000)
        await page.wait_for_function(f"(e) => ({READOUT})() === e", arg=target, timeout=600_000)
        seconds = time.perf_counter() - start
        await page.close()
        return seconds

    async with async_playwright() as playwright:
        browser = await playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_FLAGS)
        try:
            return await asyncio.gather(*(student(browser) for _ in range(CLASS)))
        finally:
            await browser.close()


def main():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_FLAGS)
        with served_app() as (url, _server):
            first, wire, unpacked = open_timed(browser, url)
            second, *_ = open_timed(browser, url)
            print("1. after a fresh `panel serve app/` (readout checked against windpump)")
            print(
                f"   first page {first:6.2f} s, second page {second:6.2f} s, ratio {first / second:.2f}"
            )
            print("2. first page's weight")
            print(
                f"   {wire / 1e6:.2f} MB on the wire, {unpacked / 1e6:.2f} MB unpacked ({unpacked / wire:.1f}x)"
            )
        rows = {}
        for name, query in [
            ("explorer (min/max bands)", ""),
            ("baseline: every sample sent", "?resolution=full"),
        ]:
            with served_app() as (url, _server):
                slider_moves(browser, url + query)  # warm-up
                rows[name] = slider_moves(browser, url + query)
        browser.close()

    print(f"3. seed example, {MOVES} moves of the head slider; readouts checked against windpump")
    print(f"   {'':32s}{'median':>10s}{'90th pct':>10s}{'bytes/update':>14s}")
    for name, (latencies, sizes) in rows.items():
        p90 = statistics.quantiles(latencies, n=10)[-1]
        print(
            f"   {name:32s}{statistics.median(latencies) * 1e3:8.0f} ms{p90 * 1e3:8.0f} ms"
            f"{statistics.median(sizes) / 1e3:11.1f} KB"
        )
    (fast, fast_bytes), (slow, slow_bytes) = rows.values()
    print(
        f"   ratios: latency {statistics.median(slow) / statistics.median(fast):.1f}x, "
        f"bytes {statistics.median(slow_bytes) / statistics.median(fast_bytes):.0f}x"
    )

    with served_app() as (url, _server):
        seconds = sorted(asyncio.run(a_class(url)))
    print(f"4. {CLASS} pages opened at once on one server, each to its checked readout")
    print(
        f"   median {statistics.median(seconds):.1f} s, slowest {seconds[-1]:.1f} s "
        f"(goal: every page within 30 s)"
    )


if __name__ == "__main__":
    main()
