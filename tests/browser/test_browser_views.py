"""The pump's views built when the page first shows them, in Debian's chromium: a page nobody
scrolls builds its first screen's views only; scrolled, the others come with their data; a
phone, whose first screen is the sidebar, builds none before it scrolls. And the notice of a
restored connection at the top of what each screen shows."""

from __future__ import annotations

import time

import pytest
from playwright.sync_api import expect
from test_browser import ARTIFACTS, open_page

from served import FIND_VIEW, POLL_MS, show_view

pytestmark = pytest.mark.browser

ORDER = ("speed", "machine", "flow", "closeup", "energy", "stall", "operating")
BUILT = (
    "() => [...Bokeh.documents[0].all_models].map(m => m.name)"
    ".filter(n => n && n.endsWith('_figure')).map(n => n.slice(0, -'_figure'.length))"
)
# Each view's main data source, filled: what it draws has arrived.
FILLED = {
    "speed": ("speed", "upper"),
    "machine": ("frames", "t"),
    "flow": ("flow", "upper"),
    "closeup": ("closeup", "flow"),
    "energy": ("losses", "right"),
    "stall": ("stall", "value"),
    "operating": ("curve", "power"),
}
HAS_DATA = """([source, column]) => {
  const s = window.Bokeh.documents[0].get_model_by_name(source);
  return s !== null && s.data[column] !== undefined && s.data[column].length > 0;
}"""
SCROLLER = "(document.querySelector('#content').scrollHeight > document.querySelector('#content').clientHeight + 2 && getComputedStyle(document.querySelector('#content')).overflowY !== 'visible' ? document.querySelector('#content') : document.querySelector('#main'))"  # noqa: E501


def built(page) -> set[str]:
    return set(page.evaluate(BUILT))


def scroll_down_by_screens(page, height: int) -> None:
    """Scroll the page down a screen at a time to its end, pausing as a reader would."""
    for _ in range(20):
        at_end = page.evaluate(
            f"(h) => {{ const s = {SCROLLER}; s.scrollTop += 0.8 * h;"
            " return s.scrollTop + s.clientHeight >= s.scrollHeight - 1 }",
            height,
        )
        time.sleep(0.5)
        if at_end:
            return


def test_a_projector_page_builds_its_first_screen_and_the_rest_when_scrolled(browser, url):
    page = open_page(browser, url, 1280, 720)
    try:
        time.sleep(3.0)  # anything the page would ask for unscrolled has been asked for
        assert built(page) == {"speed", "machine"}
        # a jump to the lower half: the views there come, and the page stays where it was put
        at = page.evaluate(
            f"() => {{ const s = {SCROLLER}; s.scrollTop = 0.6 * s.scrollHeight;"
            " return s.scrollTop }"
        )
        for name in ("energy", "stall", "operating"):
            page.wait_for_function(HAS_DATA, arg=FILLED[name], timeout=60_000, polling=POLL_MS)
        time.sleep(1.0)  # laid out
        assert abs(page.evaluate(f"() => {SCROLLER}.scrollTop") - at) <= 2
        page.evaluate(f"() => {{ {SCROLLER}.scrollTop = 0 }}")  # then from the top to the end
        scroll_down_by_screens(page, 720)
        for name in ORDER:
            page.wait_for_function(HAS_DATA, arg=FILLED[name], timeout=60_000, polling=POLL_MS)
        assert built(page) == set(ORDER)
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "views-scrolled-1280x720.png"))
        assert page.problems == []
    finally:
        page.close()


def test_a_phone_builds_only_the_view_under_its_readouts_before_it_scrolls(browser, url):
    """At 390×844 the tabs' pane shows the readouts, then at most the top of the crank speed; the
    controls' pane below them: no other view is built until the student scrolls down to it, then
    it comes with its data, and the views further down are not built."""
    page = open_page(browser, url, 390, 844)
    try:
        time.sleep(3.0)
        assert built(page) <= {"speed"}
        show_view(page, "flow")
        page.wait_for_function(HAS_DATA, arg=FILLED["flow"], timeout=60_000, polling=POLL_MS)
        time.sleep(1.0)
        assert "operating" not in built(page)
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "views-phone-390x844.png"))
        assert page.problems == []
    finally:
        page.close()


@pytest.mark.parametrize("width, height", [(390, 844), (1280, 720)])
def test_a_restored_connection_is_said_at_the_top_of_the_screen(browser, url, width, height):
    """The page reopened after its connection was lost says so where each screen starts: above
    the readouts (on a phone the tabs' pane comes first, the controls' pane under it)."""
    page = open_page(browser, url, width, height, query="?restored=true")
    try:
        notice = page.get_by_text("The connection to the server was lost and is back")
        shown = notice.filter(visible=True)
        expect(shown).to_have_count(1)
        expect(shown).to_be_in_viewport(ratio=1.0)
        header = page.locator("#header").bounding_box()
        assert shown.bounding_box()["y"] >= header["y"] + header["height"] - 1  # not under it
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / f"restored-{width}x{height}.png"))
        assert page.problems == []
    finally:
        page.close()


# Each axis of a figure: (major ticks inside its range, their spacing [px], the extent of a tick
# label along the axis [px]: its font size across y, its widest label across x).
TICK_ROOM = """(name) => {
  const fig = Bokeh.documents[0].get_model_by_name(name + '_figure');
  const ctx = document.createElement('canvas').getContext('2d');
  const out = [];
  const axes = [[fig.below, fig.x_range, fig.inner_width, true], [fig.left, fig.y_range, fig.inner_height, false]];
  for (const [panels, range, room, across] of axes) {
    const axis = panels.find(p => p.ticker !== undefined);
    const low = Math.min(range.start, range.end), high = Math.max(range.start, range.end);
    const major = axis.ticker.get_ticks(low, high, range, NaN).major.filter(v => v >= low && v <= high);
    const step = major.length > 1 ? (major[1] - major[0]) / (high - low) * room : room;
    const px = parseFloat(axis.major_label_text_font_size);
    ctx.font = `${px}px helvetica`;
    const size = across ? Math.max(...major.map(v => ctx.measureText(String(v)).width)) : px;
    out.push([major.length, step, size]);
  }
  return out;
}"""  # noqa: E501


def test_a_phone_in_presentation_mode_draws_fewer_ticks_than_would_crowd(browser, url):
    """At 390×844 in presentation mode the crank speed's tick labels (18 px) stand apart: at least
    half a label between two labels, on both axes, and still two ticks or more."""
    page = open_page(browser, url, 390, 844, query="?presentation=true")
    try:
        show_view(page, "speed")
        page.wait_for_function(HAS_DATA, arg=FILLED["speed"], timeout=60_000, polling=POLL_MS)
        time.sleep(1.0)
        for count, step, size in page.evaluate(TICK_ROOM, "speed"):
            assert count >= 2 and step >= 1.5 * size, (count, step, size)
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "ticks-phone-presentation-390x844.png"))
        assert page.problems == []
    finally:
        page.close()


def test_a_phone_shows_a_notice_the_readouts_and_the_whole_status_above_the_controls(browser, url):
    """At 390×844 a link's notice (two values ignored), the readouts and the status under them
    all fit the tabs' pane, above the controls' pane; the Wind tab's four readouts take two rows."""
    page = open_page(browser, url, 390, 844, query="?h=banana&T_m=x")
    try:
        status = page.locator("p", has_text="It settles at").first
        status.wait_for(timeout=60_000)
        notice = page.get_by_text("Some values in the link were ignored").first
        tabs_pane = page.locator("#main").bounding_box()
        controls = page.locator("#sidebar").bounding_box()
        seen = status.bounding_box()
        assert notice.bounding_box()["y"] >= tabs_pane["y"]
        assert seen["y"] + seen["height"] <= controls["y"], (seen, controls)
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "notice-phone-390x844.png"))
        page.get_by_role("tab", name="Wind", exact=True).click()
        names = ("day_litres", "record_bounds", "site_bounds", "thresholds")
        for name in names:
            expect(page.locator(f"[data-name={name}]")).not_to_have_text("", timeout=60_000)
        for _ in range(80):  # a readout Bokeh re-renders meanwhile has no box for a moment (top 0)
            tops = [
                page.locator(f"[data-name={name}]").evaluate(
                    "el => el.parentElement.getBoundingClientRect().top"
                )
                for name in names
            ]
            rows = {round(top / 20) for top in tops}  # its box's top; a row: within ~20 px
            if min(tops) > 0 and len(rows) == 2:
                break
            page.wait_for_timeout(250)
        assert len(rows) == 2, tops
        page.screenshot(path=str(ARTIFACTS / "wind-readouts-phone-390x844.png"))
        assert page.problems == []
    finally:
        page.close()


PLACED = (
    "(name) => {" + FIND_VIEW + "\n  return el === null ? null : el.getBoundingClientRect().top;\n}"
)


def test_a_view_behind_a_phones_controls_is_not_seen(browser, url):
    """At 390×844 the machine's placeholder starts on the screen, but behind the controls' pane
    (under the crank speed): it is not built until the tabs' pane is scrolled to it."""
    page = open_page(browser, url, 390, 844)
    try:
        time.sleep(3.0)
        assert "machine" not in built(page)
        controls = page.locator("#sidebar").bounding_box()
        top = page.evaluate(PLACED, "machine")
        assert top is not None and controls["y"] < top < 844  # on the screen, behind the pane
        show_view(page, "machine")
        page.wait_for_function(HAS_DATA, arg=FILLED["machine"], timeout=60_000, polling=POLL_MS)
        assert page.problems == []
    finally:
        page.close()


# A figure's canvas text sizes as drawn (its title, axes' labels and ticks, legends' labels) and
# its frame's height [px].
CANVAS_SIZES = """(name) => {
  const model = window.Bokeh.documents[0].get_model_by_name(name + '_figure');
  const view = window.Bokeh.index.find_one(model);
  const sizes = [model.title.text_font_size];
  for (const panel of [...model.below, ...model.left]) {
    if (panel.axis_label !== undefined) sizes.push(panel.axis_label_text_font_size, panel.major_label_text_font_size);
    if (panel.items !== undefined) sizes.push(panel.label_text_font_size);
  }
  return {sizes: [...new Set(sizes)].map(parseFloat).sort(), frame: view.frame.bbox.height};
}"""


WATERFALL_LABELS = """() => {
  const figure = window.Bokeh.documents[0].get_model_by_name('energy_figure');
  const text = figure.renderers.find(r => r.glyph.type === 'Text' || r.glyph.constructor.name === 'Text');
  return text.glyph.text_font_size.value;
}"""


@pytest.mark.parametrize("width, height", [(390, 844), (1280, 720)])
def test_presentation_mode_keeps_a_phones_figure_text_and_plot(browser, url, width, height):
    """The docs: presentation mode makes every text a quarter larger, and on a phone the page's
    text keeps its size. The figures' canvas text grew on a phone all the same: the crank speed's
    legend took four rows of 18 px and left its plot ~76 px high. On a phone a figure's text is
    as without presentation mode (14 to 16 px) and its plot keeps its height; a projector's text
    grows (18 to 22 px)."""
    page = open_page(browser, url, width, height, query="?presentation=true")
    try:
        show_view(page, "speed")
        page.wait_for_function(HAS_DATA, arg=FILLED["speed"], timeout=60_000, polling=POLL_MS)
        time.sleep(1.0)
        drawn = page.evaluate(CANVAS_SIZES, "speed")
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / f"presentation-text-{width}x{height}.png"))
        show_view(page, "energy")  # the waterfall's labels: a text glyph's
        page.wait_for_function(HAS_DATA, arg=FILLED["energy"], timeout=60_000, polling=POLL_MS)
        time.sleep(1.0)
        labels = page.evaluate(WATERFALL_LABELS)
        if width < 700:
            assert drawn["sizes"] and max(drawn["sizes"]) <= 16, drawn
            assert drawn["frame"] >= 150, drawn  # as without presentation mode: ~169 px
            assert labels == "15px"
            toggle = page.get_by_role("button", name="Presentation mode")
            toggle.click()  # off, and on again: the server sends the larger sizes anew
            in_link = "() => location.search.includes('presentation=true')"
            page.wait_for_function(f"() => !({in_link})()", timeout=30_000)
            toggle.click()
            page.wait_for_function(in_link, timeout=30_000)
            time.sleep(2.0)  # the server's sizes come, and the page keeps a phone's
            assert page.evaluate(WATERFALL_LABELS) == "15px"
            again = page.evaluate(CANVAS_SIZES, "speed")
            assert max(again["sizes"]) <= 16 and again["frame"] >= 150, again
        else:
            assert min(drawn["sizes"]) >= 18, drawn
            assert labels == "19px"
        assert page.problems == []
    finally:
        page.close()
