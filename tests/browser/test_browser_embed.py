"""The page offline and embedded (issue 40): the served HTML names no other host in any theme or
mode, and ``?embed=true`` shows the controls and the tabs without the template's header, in a
frame of a course page as the instructors' guide gives it."""

from __future__ import annotations

import math
import re
import urllib.request
from pathlib import Path
from urllib.parse import urlparse

import pytest
from test_browser import ARTIFACTS, handle, open_page, record_elsewhere, text, wait_for_readout

import windpump

from served import DEEP_TEXT

pytestmark = pytest.mark.browser

SEED = windpump.Design.seed_example()
GUIDE = Path(__file__).resolve().parents[2] / "docs" / "instructors.rst"

# Whether the template's header is shown (the title, the paper, the sidebar's toggle).
HEADER_SHOWN = """() => {
  const header = document.getElementById('header');
  return header !== null && header.getBoundingClientRect().height > 0
    && getComputedStyle(header).display !== 'none';
}"""


def served_html(url: str, query: str) -> str:
    with urllib.request.urlopen(url + query, timeout=120) as response:
        return response.read().decode("utf-8")


@pytest.mark.parametrize(
    "query", ["", "?theme=dark", "?presentation=true", "?theme=dark&presentation=true&embed=true"]
)
def test_the_served_page_names_no_other_host(url, query):
    """Panel's template loads its fonts, stylesheets and scripts from this server in both themes
    and presentation mode: no address with a host (``https://``, ``//``) in the page's HTML.
    What its models load later (their stylesheets) is checked on every browser test's pages
    (tests/conftest.py)."""
    page = served_html(url, query)
    assert "<title>Wind pump explorer</title>" in page
    assert re.findall(r"(?:https?:)?//[^\s\"'<>]+", page) == []  # every address relative to it
    assert 'href="static/extensions/panel/bundled/bootstraptemplate/' in page  # its own CSS


def move_the_head(page, design: windpump.Design, frame=None) -> None:
    """Five steps of the head's slider by keyboard (0.5 m up from ``design``'s); the readout
    follows as the core computes it."""
    where = frame if frame is not None else page
    handle(where, "Head h [m]").focus()
    for _ in range(5):
        page.keyboard.press("ArrowRight")
    seen = windpump.explore(design.replace(h=design.h + 0.5), 600.0, math.pi / 2, 3.0)
    expected = f"{1e3 * seen.mean_flow:.4f} L/s"
    if frame is None:
        wait_for_readout(page, "mean_flow", expected)
    else:
        frame.locator("[data-name=mean_flow]").filter(has_text=expected).wait_for(timeout=60_000)


@pytest.mark.parametrize(
    "width, height, query",
    [(800, 600, "?embed=true"), (390, 844, "?embed=true&theme=dark&presentation=true")],
)
def test_an_embedded_page_has_no_header_and_its_slider_moves_the_readouts(
    browser, url, width, height, query
):
    page = open_page(browser, url, width, height, query)
    assert page.problems == []
    assert not page.evaluate(HEADER_SHOWN)
    assert page.get_by_text("A simple wind-pump analysis").count() == 0  # the header's, not built
    flow = page.locator("[data-name=mean_flow]")
    assert flow.is_visible() and text(page, "mean_flow").endswith("L/s")
    head = handle(page, "Head h [m]")
    head.scroll_into_view_if_needed()
    assert head.is_visible()  # the controls in reach: beside the tabs, or below them on a phone
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(ARTIFACTS / f"embed_{width}x{height}.png"))
    before = text(page, "mean_flow")
    move_the_head(page, SEED)
    assert text(page, "mean_flow") != before and flow.is_visible()
    page.wait_for_function(
        "() => { const q = new URLSearchParams(location.search);"
        " return q.get('h') === '3.5' && q.get('embed') === 'true' }",
        timeout=30_000,
    )
    page.close()


def test_the_guides_snippet_embeds_the_page_in_a_course_page(browser, url):
    """The instructors' guide's ``<iframe>``, its address this server's, in a course page of its
    own: the page inside shows its readouts without a header, and a move answers there."""
    snippet = re.search(r"(<iframe src=.*?</iframe>)", GUIDE.read_text(encoding="utf-8"), re.S)
    assert snippet is not None, "the guide's snippet"
    frame_html = re.sub(r'src="[^"]*?/app\?', f'src="{url}?', snippet.group(1))
    width = int(re.search(r'width="(\d+)"', frame_html).group(1))
    height = int(re.search(r'height="(\d+)"', frame_html).group(1))
    course = browser.new_page(viewport={"width": width + 200, "height": height + 200})
    course.set_default_timeout(60_000)
    record_elsewhere(course, url, "the guide's snippet")
    course.set_content(f"<h1>Lab 3: a wind pump</h1>{frame_html}")
    frame = course.frame_locator("iframe")
    frame.locator("[data-name=mean_flow]").wait_for(timeout=120_000)
    inner = next(f for f in course.frames if f.url.startswith(url))
    assert "embed=true" in inner.url
    assert not inner.evaluate(HEADER_SHOWN)
    assert inner.evaluate(DEEP_TEXT, "[data-name=mean_flow]").endswith("L/s")
    assert inner.evaluate("() => [innerWidth, innerHeight]") == [width, height]
    linked = dict(p.split("=") for p in urlparse(inner.url).query.split("&") if p != "embed=true")
    move_the_head(course, SEED.replace(**{k: float(v) for k, v in linked.items()}), frame)
    course.screenshot(path=str(ARTIFACTS / "embed_in_a_course_page.png"))
    course.close()
