"""Nothing a link or a file says runs in the page, served in Debian's chromium: each payload is
shown as typed, no script of it runs, and the page's Content-Security-Policy (app/server/policy.py) is
never even called on, yet blocks markup that would reach the page by another road."""

from __future__ import annotations

import time
from pathlib import Path
from urllib.parse import quote

import pytest
from test_browser import open_page

pytestmark = pytest.mark.browser

# Each sets window.ran if it runs; each is short enough (40 characters) to be echoed whole in a
# notice (tests/app/test_text_is_text.py has srcdoc and longer ones, in-process).
RUNNING = (
    "<script>window.ran=1</script>",
    '<img src=x onerror="window.ran=1">',
    "<svg onload=window.ran=1>",
    '<iframe src="javascript:top.ran=1">',
    "javascript:window.ran=1",
)
# Every policy violation, as the page reports it, from before its first script.
WATCH = """
window.violations = [];
document.addEventListener('securitypolicyviolation',
  (e) => window.violations.push(e.violatedDirective + ' ' + e.blockedURI));
"""
SETTLE = 2.0  # [s] for an image's error or a frame's load to have fired, had it been made


class Watched:
    """A browser whose pages record their policy violations (for ``open_page``)."""

    def __init__(self, browser):
        self.browser = browser

    def new_page(self, **options):
        page = self.browser.new_page(**options)
        page.add_init_script(WATCH)
        return page


def nothing_ran(page) -> None:
    time.sleep(SETTLE)
    assert page.evaluate("() => window.ran") is None
    assert page.evaluate("() => window.violations") == []


@pytest.mark.parametrize("payload", RUNNING)
def test_a_links_keys_and_values_are_shown_as_typed_and_never_run(browser, url, payload):
    keys = ("h", "tab", "presentation", "double_acting", "site", "theme", "T_m")
    query = "?" + "&".join([f"{quote(payload)}=1"] + [f"{key}={quote(payload)}" for key in keys])
    page = open_page(Watched(browser), url, query=query)
    try:
        page.get_by_text("Some values in the link were ignored").first.wait_for(timeout=60_000)
        notices = page.get_by_text(f"“{payload}”")
        assert notices.count() >= 2  # as a key, and as the values the notices list
        nothing_ran(page)
        assert page.problems == []
    finally:
        page.close()


def test_a_links_value_of_any_length_gets_a_notice(browser, url):
    """Panel's Location reads a value of digits with int(), which refuses more than 4,300."""
    page = open_page(Watched(browser), url, query="?h=" + "9" * 5_000)
    try:
        page.get_by_text("Head h [m] (h) =").first.wait_for(timeout=60_000)
        assert page.problems == []
    finally:
        page.close()


def upload(page, which: int, name: str, content: bytes) -> None:
    files = [{"name": name, "mimeType": "text/csv", "buffer": content}]
    page.locator("input[type=file]").nth(which).focus()  # as a click does: uploads.js guards it
    page.locator("input[type=file]").nth(which).set_input_files(files=files)


@pytest.mark.parametrize("payload", RUNNING[:3])
def test_a_lab_file_its_name_and_lines_never_run(browser, url, payload):
    page = open_page(Watched(browser), url)
    try:
        upload(page, 0, f"{payload}.csv", f"{payload},0.5\n".encode())
        page.get_by_text("Could not use that file").first.wait_for(timeout=60_000)
        assert page.get_by_text(payload[:18]).count() >= 1  # the line, echoed as typed (cut)
        nothing_ran(page)
    finally:
        page.close()


@pytest.mark.parametrize("payload", RUNNING[:3])
def test_a_wind_file_its_name_and_cells_never_run(browser, url, payload):
    page = open_page(Watched(browser), url)
    try:
        page.get_by_text("Wind", exact=True).first.click()
        page.locator("input[type=file]").nth(1).wait_for(state="attached", timeout=120_000)
        upload(page, 1, f"{payload}.csv", f"t,V\n0,5\n60,{payload}\n".encode())
        page.get_by_text("This wind file cannot be used").first.wait_for(timeout=120_000)
        rows = "".join(f"{60 * i},{5 + (i % 7) / 3:.2f}\n" for i in range(121))
        upload(page, 1, f"{payload}.csv", f"t,V\n{rows}".encode())
        page.get_by_text(f"the measured record {payload}.csv").first.wait_for(timeout=120_000)
        nothing_ran(page)
        assert page.problems == []
    finally:
        page.close()


def tmy3_named(station: str) -> bytes:
    import pvlib

    header, rest = (
        (Path(pvlib.__file__).parent / "data" / "723170TYA.CSV").read_bytes().split(b"\n", 1)
    )
    fields = header.split(b",")
    fields[1] = f'"{station}"'.encode()
    return b",".join(fields) + b"\n" + rest


@pytest.mark.parametrize(
    "payload", ["<img src=x onerror=window.ran=1>", "<svg onload=window.ran=1>"]
)
def test_a_weather_file_its_name_and_station_never_run(browser, url, payload):
    page = open_page(Watched(browser), url, query="?tab=site")
    try:
        files = page.locator(".site-upload input[type=file]")
        files.wait_for(state="attached", timeout=120_000)
        files.focus()  # as a click does: uploads.js guards it
        files.set_input_files(
            files=[
                {"name": f"{payload}.csv", "mimeType": "text/csv", "buffer": tmy3_named(payload)}
            ]
        )
        page.get_by_text(f"({payload}, NC)").first.wait_for(timeout=120_000)  # as typed
        nothing_ran(page)
        assert page.problems == []
    finally:
        page.close()


def test_the_policy_blocks_markup_that_reached_the_page_by_another_road(browser, url):
    """Were a pane ever given markup, its handlers and scripts would not run: the page's own
    scripts carry the nonce its policy names, and nothing else does."""
    page = open_page(Watched(browser), url)
    try:
        page.evaluate(
            """() => {
          document.body.insertAdjacentHTML('beforeend', '<img src=x onerror="window.ran=1">');
          const script = document.createElement('script');
          script.textContent = 'window.ran = 2';
          document.body.appendChild(script);
        }"""
        )
        time.sleep(SETTLE)
        assert page.evaluate("() => window.ran") is None
        assert any(v.startswith("script-src") for v in page.evaluate("() => window.violations"))
    finally:
        page.close()


def test_every_tab_in_use_breaks_no_rule_of_the_policy(browser, url):
    page = open_page(Watched(browser), url)
    try:
        for tab in ("Mechanisms", "Wind", "Design map", "Site"):
            page.get_by_text(tab, exact=True).first.click()
            time.sleep(1.0)
        page.get_by_text("Dry days").first.wait_for(timeout=120_000)  # the site's year drawn
        time.sleep(SETTLE)
        assert page.evaluate("() => window.violations") == []
        assert page.problems == []
    finally:
        page.close()
