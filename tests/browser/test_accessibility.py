"""WCAG 2.1 A and AA, checked by axe-core in chromium, and what a screen reader hears of a slider.

axe-core (through ``axe-playwright-python``, which bundles it: nothing is fetched) checks every
tab at a projector's 1280×720 and a phone's 390×844, light and dark, plain and in presentation
mode, once the tab's views are drawn and again after a slider's move: no violation of the
``wcag2a``, ``wcag2aa``, ``wcag21a`` and ``wcag21aa`` rules. One page per size and theme visits
the tabs in turn (opening a page and a tab's first run are most of the time), then switches
presentation mode on and visits them again.
"""

from __future__ import annotations

import json
import os

import pytest
from test_browser import handle, open_page

from windpump_app.pump import ORDER

from served import DEEP_TEXT, POLL_MS, show_view

pytestmark = pytest.mark.browser

# The browser extra's (pyproject.toml): skipped without it on a user's machine, never in CI
if os.environ.get("CI"):
    from axe_playwright_python.sync_playwright import Axe
else:
    Axe = pytest.importorskip("axe_playwright_python.sync_playwright").Axe

WCAG_21_AA = ["wcag2a", "wcag2aa", "wcag21a", "wcag21aa"]
# Rules about the page's stylesheets and media, not its elements: each axe run fetches every
# stylesheet again for them (~3 s of a ~6 s run on the Site tab). Checked once a page, after every
# tab has added its stylesheets; the rest on every tab, in every state.
PAGE_RULES = ("css-orientation-lock", "no-autoplay-audio")
EVERY_RULE = {"runOnly": {"type": "tag", "values": WCAG_21_AA}, "resultTypes": ["violations"]}
ELEMENT_RULES = {**EVERY_RULE, "rules": {rule: {"enabled": False} for rule in PAGE_RULES}}

# Each tab and what says its content is drawn (its first run done).
TAB_READY = {
    "Wind pump": None,  # its views: show_view, one by one
    "Mechanisms": "() => Bokeh.documents[0].get_model_by_name('linkage_figure') !== null",
    "Wind": f"() => /^[0-9,]+$/.test(({DEEP_TEXT})('[data-name=day_litres]') || '')",
    "Design map": (
        "() => { const m = Bokeh.documents[0].get_model_by_name('maptab_flow');"
        " return m !== null && m.data.image.length > 0 }"
    ),
    "Site": f"() => /%/.test(({DEEP_TEXT})('[data-name=site_lolp]') || '')",
}
# Panel's light theme writes a warning alert's text #997404 on #fff3cd, 3.9:1 (AA asks 4.5:1), in
# every component's shadow root (its theme's ":host" variables, out of the page's CSS's reach): the
# Site tab's year, yellow when some demand goes undelivered, fails. Its fix belongs in the theme
# (--warning-text-color #664d03, 7.2:1; --info-text-color #055160 too: 4.3:1 now).
LIGHT_WARNING = pytest.mark.xfail(
    strict=True,
    raises=AssertionError,
    reason="color-contrast: Panel's light warning alert, #997404 on #fff3cd (Site tab's year)",
)
COMBINATIONS = [
    pytest.param(1280, 720, "", id="1280x720-light", marks=LIGHT_WARNING),
    pytest.param(1280, 720, "?theme=dark", id="1280x720-dark"),
    pytest.param(390, 844, "", id="390x844-light", marks=LIGHT_WARNING),
    pytest.param(390, 844, "?theme=dark", id="390x844-dark"),
]


def violations(page, where: str, options: dict = ELEMENT_RULES) -> list[str]:
    """axe's WCAG 2.1 A/AA violations on ``page`` as it stands, one line each: ``where``, the
    rule, its impact and the elements' targets (a target through shadow roots is a list)."""
    if page.evaluate("() => typeof window.axe") == "undefined":
        found = Axe().run(page, options=options).response["violations"]
    else:  # axe is in the page already: run it again (Axe.run would load its 0.5 MB again)
        found = page.evaluate(f"() => axe.run({json.dumps(options)})")["violations"]
    return [
        f"{where}: {rule['id']} ({rule['impact']}, {len(rule['nodes'])} elements): "
        + "; ".join(" > ".join(map(str, node["target"])) for node in rule["nodes"][:5])
        for rule in found
    ]


def visit(page, tab: str) -> None:
    """Choose ``tab`` and wait until it is drawn (the pump's tab: scrolled through its views)."""
    page.get_by_role("tab", name=tab, exact=True).click()
    page.get_by_role("tab", name=tab, selected=True).wait_for(timeout=60_000)
    if TAB_READY[tab] is None:
        for view in ORDER:
            show_view(page, view)
    else:
        page.wait_for_function(TAB_READY[tab], timeout=120_000, polling=POLL_MS)
    page.wait_for_timeout(500)  # laid out after its data


@pytest.mark.parametrize("width, height, query", COMBINATIONS)
def test_every_tab_meets_wcag_21_aa(browser, url, width, height, query):
    page = open_page(browser, url, width, height, query)
    found = []
    try:
        flow = page.evaluate(DEEP_TEXT, "[data-name=mean_flow]")
        for tab in TAB_READY:
            visit(page, tab)
            found += violations(page, tab)
            if tab == "Wind pump":  # a move: the readouts, views and the slider's value redrawn
                handle(page, "Head h [m]").focus()
                page.keyboard.press("ArrowRight")
                page.locator(".bk-slider-title", has_text="Head h [m]: 3.1").wait_for()
                page.wait_for_function(
                    f"() => ({DEEP_TEXT})('[data-name=mean_flow]') !== {json.dumps(flow)}"
                )
                found += violations(page, "Wind pump after a move")
        page.get_by_role("button", name="Presentation mode").click()
        for tab in TAB_READY:
            visit(page, tab)
            found += violations(page, f"{tab}, presentation mode")
        found += violations(page, "the page's stylesheets", EVERY_RULE)
        assert found == [], "\n".join(found)
        assert page.problems == [], page.problems
        assert page.elsewhere == []
    finally:
        page.close()


def test_a_slider_says_its_value_as_shown_and_its_unit(browser, url):
    """A screen reader hears a slider's name, its value as the page shows it and the value's unit
    in words; aria-valuenow is that number (noUiSlider's own said 3.8 where the page showed 3.75)."""
    page = open_page(browser, url, 1280, 720)
    try:
        head = page.get_by_role("slider", name="Head h [m]", exact=True)
        rod = page.get_by_role("slider", name="L/R, rod / crank", exact=True)
        assert page.locator(".bk-slider-title", has_text="L/R, rod / crank: 3.75").count() == 1
        page.wait_for_function(
            "(h) => h.getAttribute('aria-valuetext') === '3.0 metres'",
            arg=head.element_handle(),
            timeout=30_000,
        )
        assert rod.get_attribute("aria-valuetext") == "3.75"  # a ratio: no unit
        assert rod.get_attribute("aria-valuenow") == "3.75"
        assert (head.get_attribute("aria-valuemin"), head.get_attribute("aria-valuemax")) == (
            "0",
            "30",
        )
        head.focus()
        page.keyboard.press("ArrowRight")
        page.locator(".bk-slider-title", has_text="Head h [m]: 3.1").wait_for(timeout=30_000)
        page.wait_for_function(
            "(h) => h.getAttribute('aria-valuetext') === '3.1 metres'",
            arg=head.element_handle(),
            timeout=30_000,
        )
        assert head.get_attribute("aria-valuenow") == "3.1"
        # a slider drawn later, with the machine's view: the run's time, in seconds
        scrubber = page.get_by_role("slider", name="time t [s]", exact=True)
        page.wait_for_function(
            "(s) => s.getAttribute('aria-valuetext') === '0 seconds'",
            arg=scrubber.element_handle(),
            timeout=30_000,
        )
        assert page.problems == []
    finally:
        page.close()
