"""The Site tab as a student meets it: served, in Debian's chromium, driven by playwright."""

from __future__ import annotations

import time

import pytest
from test_browser import ARTIFACTS, SIZES, open_page, press, text, wait_for_readout
from test_layout import CANVAS_TEXT, SCROLLS

import windpump

from served import DEEP_TEXT

pytestmark = pytest.mark.browser

SEED = windpump.Design.seed_example()
QUERY = "(name) => new URLSearchParams(location.search).get(name)"
SITE_FIGURES = ("monthly", "level", "lolp")


def site_readouts(demand: float, tank: float = 5.0) -> dict[str, str]:
    """The readouts the tab shows for the paper's design at Greensboro, attended (the core's)."""
    record = windpump.sample_site("greensboro").at_height(10.0)
    year = windpump.supply(SEED, record, demand, tank, restart="attended")
    return {
        "site_lolp": f"{100 * year.lolp:.1f} %",
        "dry_days": f"{year.dry_days:d}",
        "dry_spell": f"{year.longest_dry_spell:d} days",
    }


def test_the_site_tab_shows_the_year_and_follows_the_demand(browser, url):
    page = open_page(browser, url, width=1280, height=720, query="?demand=12")
    try:
        page.get_by_role("tab", name="Site").click()
        for name, shown in site_readouts(12.0).items():
            wait_for_readout(page, name, shown)
        # the figures follow the readouts, once the page has painted them (site_tab.AfterPaint)
        bars = "() => window.Bokeh.documents[0].get_model_by_name('sitetab_monthly')?.data.pumped"
        page.wait_for_function(f"() => ({bars})()?.length === 12", timeout=60_000)
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "site_1280x720.png"))
        before = text(page, "site_lolp")

        press(page, "Demand [m³/day]", "ArrowRight", 5)  # 12.0 -> 12.5
        page.wait_for_function(f"() => ({QUERY})('demand') === '12.5'", timeout=60_000)
        expected = site_readouts(12.5)
        for name, shown in expected.items():
            wait_for_readout(page, name, shown)
        assert expected["site_lolp"] != before
        assert page.problems == []
    finally:
        page.close()


# A readout's label and value font sizes [px], found through the shadow roots by its data-name
READOUT_SIZES = """(name) => {
  const walk = (root) => {
    const hit = root.querySelector(`[data-name=${name}]`);
    if (hit) return hit;
    for (const el of root.querySelectorAll('*')) {
      if (el.shadowRoot) { const found = walk(el.shadowRoot); if (found) return found; }
    }
    return null;
  };
  const value = walk(document), label = value.parentNode.querySelector('.label');
  return [label, value].map(el => parseFloat(getComputedStyle(el).fontSize));
}"""


def test_a_link_opens_the_site_tab_and_presentation_enlarges_its_readouts(browser, url):
    """``?tab=site`` opens on the Site tab; presentation mode enlarges every tab's readouts,
    labels by a quarter and numbers by half, as the pump's (the Site tab's stayed at 14 and 20 px)."""
    for query, zoom in (("?tab=site", 1.0), ("?tab=site&presentation=true", 1.25)):
        page = open_page(browser, url, 1280, 720, query)
        try:
            page.wait_for_function(
                f"() => /%/.test(({DEEP_TEXT})('[data-name=site_lolp]') || '')", timeout=60_000
            )
            assert page.get_by_role("tab", name="Site").get_attribute("aria-selected") == "true"
            for name in ("site_lolp", "mean_flow"):  # the Site tab's and the pump tab's
                value = 20 * (2 * zoom - 1)  # the numbers grow by half (30 px)
                assert page.evaluate(READOUT_SIZES, name) == [14 * zoom, value], (query, name)
            assert page.problems == []
        finally:
            page.close()


def test_a_weather_file_over_the_limit_is_refused_in_the_page(browser, url):
    """The page's size check (uploads.js) knows the Site tab's upload: 10 MB, said in the tab;
    a file within it goes to the server by HTTP (app/server/upload_route.py) and becomes the site."""
    page = open_page(browser, url)
    try:
        page.get_by_role("tab", name="Site").click()
        page.wait_for_function(f"() => /%/.test(({DEEP_TEXT})('[data-name=site_lolp]') || '')")
        hours = "".join(f"{3600 * h},{5 + (h % 7) / 3:.2f}\n" for h in range(3 * 24))
        three = {"name": "three.csv", "mimeType": "text/csv", "buffer": ("t,V\n" + hours).encode()}
        # Focused first, as a person's click or Tab focuses it: uploads.js guards a file input
        # drawn later on its focus (or pointerdown, dragenter), or on timers after the tab is
        # chosen; set at once, the file sometimes beat the timers and went over the websocket.
        page.locator(".site-upload input[type=file]").focus()
        page.locator(".site-upload input[type=file]").set_input_files(files=[three])
        page.get_by_text("the uploaded file three").first.wait_for(timeout=60_000)
        assert any("/app/upload?" in post for post in page.posts)
        huge = {"name": "huge.epw", "mimeType": "text/plain", "buffer": b"0,5\n" * 3_000_000}
        page.locator(".site-upload input[type=file]").set_input_files(files=[huge])
        page.get_by_text("This weather file cannot be used: it has 12,000,000 bytes").wait_for(
            timeout=60_000
        )
        assert page.problems == []
    finally:
        page.close()


@pytest.mark.parametrize("width, height", SIZES)
@pytest.mark.parametrize("query", ["", "?presentation=true&theme=dark"])
def test_the_site_tab_fits_every_screen(browser, url, width, height, query):
    """Nothing scrolls sideways and no figure's title or axis label is cut; a screenshot of each."""
    page = open_page(browser, url, width, height, query)
    try:
        page.get_by_role("tab", name="Site").click()
        page.wait_for_function(f"() => /%/.test(({DEEP_TEXT})('[data-name=site_lolp]') || '')")
        # the figures come after the readouts (a busy machine: seconds after); then their
        # layout settles after their data
        page.wait_for_function(FIGURES_DRAWN, arg=list(SITE_FIGURES), timeout=60_000)
        time.sleep(1.0)
        sideways = [(s, extra) for s, extra in page.evaluate(SCROLLS) if extra > 0]
        assert sideways == [], f"sideways scrolling at {width}×{height}{query}: {sideways}"
        cut = {n: page.evaluate(CANVAS_TEXT, f"site_{n}_figure") for n in SITE_FIGURES}
        assert {n: c for n, c in cut.items() if c} == {}
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        theme = "dark" if "dark" in query else "light"
        page.screenshot(path=str(ARTIFACTS / f"site_{theme}_{width}x{height}.png"))
        assert page.problems == []
    finally:
        page.close()


def test_in_us_units_the_site_tab_shows_gallons_its_sliders_as_they_move(browser, url):
    """``?units=us`` on a phone: the readouts, the axes (no "1.5e+5") and the sliders in gallons
    and feet, each slider's US value written by the browser (site_tab.us_format) beside the
    value the link keeps, following a key press; nothing cut or scrolling sideways."""
    import pint

    gal = pint.UnitRegistry().Quantity(1.0, "m**3").to("gallon").magnitude
    page = open_page(browser, url, 390, 844, "?units=us&tab=site")
    try:
        page.wait_for_function(f"() => /%/.test(({DEEP_TEXT})('[data-name=site_lolp]') || '')")
        page.wait_for_function(FIGURES_DRAWN, arg=list(SITE_FIGURES), timeout=60_000)
        time.sleep(1.0)
        assert page.locator(".label", has_text="Pumped · delivered [gal/year]").count() == 1
        assert text(page, "tank_for_5").endswith(" gal")
        titles = page.locator(".bk-slider-title")
        demand = f"Demand: {10.0 * gal:,.0f} gal/day (10.0 m³/day)"
        assert demand in titles.all_text_contents()
        assert f"Tank: {5.0 * gal:,.0f} gal (5.0 m³)" in titles.all_text_contents()
        assert f"Hub height: {10.0 / 0.3048:.1f} ft (10.0 m)" in titles.all_text_contents()
        press(page, "Demand: ", "ArrowRight", 1)  # 10.0 -> 10.1 m³/day
        page.wait_for_function(f"() => ({QUERY})('demand') === '10.1'", timeout=60_000)
        assert f"Demand: {10.1 * gal:,.0f} gal/day (10.1 m³/day)" in titles.all_text_contents()
        sideways = [(s, extra) for s, extra in page.evaluate(SCROLLS) if extra > 0]
        assert sideways == []
        cut = {n: page.evaluate(CANVAS_TEXT, f"site_{n}_figure") for n in SITE_FIGURES}
        assert {n: c for n, c in cut.items() if c} == {}
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "site_us_390x844.png"))
        assert page.problems == []
    finally:
        page.close()


# Boxes [x, y, width, height] of the Site tab's controls and of each figure's slot (its
# placeholder, then the figure), through the shadow roots, by CSS class (site_tab.CONTROLS_CLASS,
# site_tab.SLOT_CLASS); and the fill of each placeholder on the page (viewport.PLACEHOLDER_CSS).
SITE_BOXES = """() => {
  const found = (root, selector, out) => {
    out.push(...root.querySelectorAll(selector));
    for (const el of root.querySelectorAll('*')) if (el.shadowRoot) found(el.shadowRoot, selector, out);
    return out;
  };
  const box = (el) => {
    const b = el.getBoundingClientRect();
    return [b.x, b.y, b.width, b.height].map(Math.round);
  };
  return {
    controls: found(document, '.site-controls', []).map(box),
    slots: found(document, '.site-figure-slot', []).map(box),
    fills: found(document, 'div.placeholder', []).map(el => getComputedStyle(el).backgroundColor),
  };
}"""

# Every stylesheet linked in the page (in the document and in every shadow root) loaded. Panel
# links its widgets' stylesheets in each new view's shadow root, and the browser loads a link
# after the view is drawn: on a busy machine a frame or more later (a CI run at load 6-8 drew
# the tab's controls 16 px lower first, the selects' labels 10 px shorter, their margins not
# yet styled; the same with each stylesheet's response held 0.3 s). That is the stylesheets,
# not the figures, so the first paint measured is the first styled one.
STYLED = """() => {
  const links = (root, out) => {
    out.push(...root.querySelectorAll('link[rel=stylesheet]'));
    for (const el of root.querySelectorAll('*')) if (el.shadowRoot) links(el.shadowRoot, out);
    return out;
  };
  return links(document, []).every(link => link.sheet !== null);
}"""

# Installed before the tab is chosen: the boxes in the first styled frame whose page holds the
# year's readouts (the tab's first paint), before that frame is painted.
BOXES_AT_FIRST_PAINT = (
    """() => {
  window.__siteFirst = null;
  const boxes = """
    + SITE_BOXES
    + """;
  const styled = """
    + STYLED
    + """;
  const readout = () => ("""
    + DEEP_TEXT
    + """)('[data-name=site_lolp]') || '';
  const look = () => {
    if (/%/.test(readout()) && styled()) window.__siteFirst = boxes();
    else requestAnimationFrame(look);
  };
  requestAnimationFrame(look);
}"""
)

FIGURES_DRAWN = """(names) => names.every(name => {
  const model = window.Bokeh.documents[0].get_model_by_name(`site_${name}_figure`);
  const view = model && window.Bokeh.index.find_one(model);
  return view != null && view.el.isConnected && view.el.getBoundingClientRect().height > 0;
})"""


@pytest.mark.parametrize("width, height", SIZES)
@pytest.mark.parametrize("query", ["", "?presentation=true&theme=dark"])
def test_nothing_moves_when_the_site_figures_arrive(browser, url, width, height, query):
    """The figures come after the year's readouts (site_tab.AfterPaint), in the place kept for
    them from the tab's first paint (placeholders, their words readable on no fill): the
    controls and the figures' slots do not move. Before, the controls were laid out across the
    tab, then squeezed into a column beside the water each month (1006 px wide to 382 at
    1366×768, 23 px taller) (issue 37)."""
    page = open_page(browser, url, width, height, query)
    try:
        page.evaluate(BOXES_AT_FIRST_PAINT)
        page.get_by_role("tab", name="Site").click()
        page.wait_for_function("() => window.__siteFirst !== null", timeout=120_000)
        first = page.evaluate("() => window.__siteFirst")
        fills = first.pop("fills")  # the Site tab's placeholders' and the pump's views' below
        assert len(fills) >= len(SITE_FIGURES) and set(fills) == {"rgba(0, 0, 0, 0)"}, fills
        page.wait_for_function(FIGURES_DRAWN, arg=list(SITE_FIGURES), timeout=60_000)
        time.sleep(1.0)  # the figures' layout settles after their data
        after = page.evaluate(SITE_BOXES)
        after.pop("fills")
        assert len(after["controls"]) == 1 and len(after["slots"]) == len(SITE_FIGURES)
        assert first == after, f"the Site tab moved at {width}×{height}{query}: {first} -> {after}"
        assert page.problems == []
    finally:
        page.close()
