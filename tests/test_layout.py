"""The page as a class sees it on a projector, a laptop and a phone, measured from element boxes in
Debian's chromium: what is in the first screen, what scrolls, what presentation mode enlarges, and
that no text a figure draws on its canvas is cut."""

from __future__ import annotations

import time

import pytest
from test_browser import ARTIFACTS, SIZES, open_page

from served import show_view

pytestmark = pytest.mark.browser

FIGURES = ("speed", "machine", "flow", "closeup", "energy", "stall", "operating")

# The box of a named Bokeh model's view (a figure), in the page's coordinates.
VIEW_BOX = """(name) => {
  const model = window.Bokeh.documents[0].get_model_by_name(name);
  const view = model && window.Bokeh.index.find_one(model);
  if (!view) return null;
  const b = view.el.getBoundingClientRect();
  return {x: b.x, y: b.y, width: b.width, height: b.height};
}"""

# Every text a figure draws on its canvas that could be cut: its title (from the frame's left
# edge, as Bokeh aligns it, to the canvas's right edge) and its axis labels (along the frame).
# Widths are measured with the canvas's own font, so this is what the page draws.
CANVAS_TEXT = """(name) => {
  const model = window.Bokeh.documents[0].get_model_by_name(name);
  const view = window.Bokeh.index.find_one(model);
  const ctx = document.createElement('canvas').getContext('2d');
  const width = (text, size, style) => {
    ctx.font = `${style} ${size} helvetica`;
    return Math.max(...String(text).split('\\n').map(line => ctx.measureText(line).width));
  };
  const frame = view.frame.bbox, canvas = view.el.getBoundingClientRect().width, cut = [];
  const title = model.title;
  const small = (size) => parseFloat(size) < 14;
  if (title && small(title.text_font_size)) cut.push(['title below 14 px', title.text_font_size]);
  if (title && title.text) {
    const w = width(title.text, title.text_font_size, 'bold');
    if (frame.left + w > canvas + 1) cut.push(['title', title.text, w, canvas - frame.left]);
  }
  for (const [axes, room] of [[model.below, frame.width], [model.left, frame.height]]) {
    for (const axis of axes) {
      if (!axis.axis_label || !axis.visible) continue;
      if (small(axis.axis_label_text_font_size)) cut.push(['label below 14 px', axis.axis_label]);
      const w = width(axis.axis_label, axis.axis_label_text_font_size, 'italic');
      if (w > room + 1) cut.push(['axis', axis.axis_label, w, room]);
    }
  }
  return cut;
}"""

SCROLLS = """() => ['#content', '#main'].map(s => {
  const el = document.querySelector(s);
  return [s, el.scrollWidth - el.clientWidth];
})"""

# The computed font size [px] of the first element with this text, through shadow roots.
FONT_SIZE = """(text) => {
  const walk = (root) => {
    for (const el of root.querySelectorAll('*')) {
      const own = Array.from(el.childNodes).some(n => n.nodeType === 3 && n.textContent.includes(text));
      if (own) return el;
      if (el.shadowRoot) { const hit = walk(el.shadowRoot); if (hit) return hit; }
    }
    return null;
  };
  const el = walk(document);
  return el ? parseFloat(getComputedStyle(el).fontSize) : null;
}"""


def settled(page) -> None:
    """Bokeh lays figures out after their data arrive: give the layout a moment to settle."""
    show_view(page, "machine")  # on a phone, below the sidebar: scrolled to
    time.sleep(1.0)


def bottom(b) -> float:
    return b["y"] + b["height"]


@pytest.mark.parametrize("query", ["", "?presentation=true"])
def test_a_projector_shows_readouts_status_machine_and_crank_speed_in_the_first_screen(
    browser, url, query
):
    """At 1280×720 the lecture's picture is on the first screen: the readouts, the status, the
    machine with its Play button and scrubber, and the crank speed it is playing."""
    page = open_page(browser, url, 1280, 720, query)
    try:
        settled(page)
        boxes = {
            name: page.locator(f"[data-name={name}]").bounding_box()
            for name in ("mean_flow", "volume", "tau", "margin", "peak_to_mean", "energy")
        }
        boxes["status"] = page.get_by_text("Running.").first.bounding_box()
        boxes["play"] = page.get_by_role("button", name="▶ Play").bounding_box()
        scrubber = page.locator(
            ".bk-input-group", has=page.locator(".bk-slider-title", has_text="time t [s]")
        )
        boxes["scrubber"] = scrubber.bounding_box()
        for figure in ("speed", "machine"):
            boxes[figure] = page.evaluate(VIEW_BOX, f"{figure}_figure")
        below = {name: bottom(b) for name, b in boxes.items() if bottom(b) > 720 or b["y"] < 0}
        assert below == {}, f"not in the first screen at 1280×720 ({query}): {below}"
        # the scrubber takes the machine's width: under 1 s a pixel for the 600 s run
        assert boxes["scrubber"]["width"] >= 0.9 * boxes["machine"]["width"] >= 400
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / f"projector-1280x720{query.replace('?', '-')}.png"))
        assert page.problems == []
    finally:
        page.close()


def test_a_wide_screen_leaves_no_blank_band_between_rows_of_views(browser, url):
    """At 1920×1080 the views stand in three columns; the second row follows the first closely
    (a card beside the machine once left ~150 px of blank space under its neighbours)."""
    page = open_page(browser, url, 1920, 1080)
    try:
        settled(page)
        speed, machine = (page.evaluate(VIEW_BOX, f"{n}_figure") for n in ("speed", "machine"))
        closeup = page.evaluate(VIEW_BOX, "closeup_figure")
        assert abs(speed["y"] - machine["y"]) < 2 and machine["x"] > speed["x"]  # one row
        caption = page.get_by_text("Crank speed θ̇: the full").first.bounding_box()
        gap = closeup["y"] - bottom(caption)
        assert 0 <= gap <= 100, f"{gap:.0f} px between the rows"
    finally:
        page.close()


@pytest.mark.parametrize("width, height", SIZES)
@pytest.mark.parametrize("query", ["", "?presentation=true"])
def test_nothing_scrolls_sideways_and_no_canvas_text_is_cut(browser, url, width, height, query):
    """The element that scrolls (the page's #content on a phone, #main beside the sidebar) never
    scrolls sideways, and every figure's title and axis labels fit inside it."""
    page = open_page(browser, url, width, height, query)
    try:
        settled(page)
        sideways = [(s, extra) for s, extra in page.evaluate(SCROLLS) if extra > 0]
        assert sideways == [], f"sideways scrolling at {width}×{height}{query}: {sideways}"
        for name in FIGURES:  # each built once scrolled to
            show_view(page, name)
        cut = {n: page.evaluate(CANVAS_TEXT, f"{n}_figure") for n in FIGURES if n != "machine"}
        assert {n: c for n, c in cut.items() if c} == {}
        header = page.locator("#header").bounding_box()
        assert header["height"] <= 70, "the header keeps to one line"
        if width < 700:  # the page scrolls as one column: nothing in a scroll of its own
            inner = page.evaluate(
                "() => { const s = document.querySelector('#sidebar');"
                " return s.scrollHeight - s.clientHeight }"
            )
            assert inner <= 1, f"the sidebar hides {inner} px in a scroll of its own"
            scrubber = page.locator(
                ".bk-input-group", has=page.locator(".bk-slider-title", has_text="time t [s]")
            )
            assert scrubber.bounding_box()["width"] >= 300
        assert page.problems == []
    finally:
        page.close()


def test_presentation_mode_enlarges_the_sidebar_captions_status_and_notes(browser, url):
    page = open_page(browser, url, 1280, 720)
    try:
        texts = (
            "Head h [m]",  # a slider's label
            "More parameters",  # a card's title
            "Pin this run",  # a button
            "Running.",  # the status
            "Crank speed θ̇: the full Eq. (12)",  # a caption
            "The machine playing the computed run",  # the machine's caption
        )
        before = {text: page.evaluate(FONT_SIZE, text) for text in texts}
        page.get_by_role("button", name="Presentation mode").click()
        page.wait_for_function(
            "(args) => (" + FONT_SIZE + ")(args[0]) > args[1]", arg=[texts[0], before[texts[0]]]
        )
        after = {text: page.evaluate(FONT_SIZE, text) for text in texts}
        small = {t: (before[t], after[t]) for t in texts if not after[t] >= 1.2 * before[t]}
        assert small == {}, f"not enlarged: {small}"
        page.get_by_role("button", name="Presentation mode").click()  # and back
        page.wait_for_function(
            "(args) => (" + FONT_SIZE + ")(args[0]) === args[1]", arg=[texts[0], before[texts[0]]]
        )
        assert page.problems == []
    finally:
        page.close()


@pytest.mark.parametrize("tab", ["Mechanisms", "Design map"])
def test_a_short_tab_does_not_scroll_into_blank_space(browser, url, tab):
    """Panel keeps hidden tabs laid out; the page must be as long as the tab shown, not the
    longest tab: scrolled to its end, the tab's own content is still in view."""
    page = open_page(browser, url, 1280, 720)
    try:
        page.get_by_text(tab, exact=True).first.click()
        last = {"Mechanisms": "linkage_figure", "Design map": "map_figure"}[tab]
        page.wait_for_function(f"(n) => ({VIEW_BOX})(n) !== null", arg=last, timeout=60_000)
        time.sleep(1.0)
        page.evaluate(
            "() => { const m = document.querySelector('#main'); m.scrollTop = m.scrollHeight }"
        )
        time.sleep(0.5)
        box = page.evaluate(VIEW_BOX, last)
        assert box["y"] + box["height"] >= 360, f"scrolled past {tab}'s content into blank: {box}"
        page.get_by_text("Wind pump", exact=True).first.click()  # the first tab is whole again
        page.wait_for_function(f"(n) => ({VIEW_BOX})(n).height > 100", arg="speed_figure")
        assert page.problems == []
    finally:
        page.close()


# A glyph the page's fonts cannot draw comes out as the same empty box as an unassigned code point.
MISSING_GLYPHS = """(text) => {
  const draw = (s) => {
    const canvas = document.createElement('canvas'); canvas.width = 48; canvas.height = 48;
    const ctx = canvas.getContext('2d'); ctx.font = '36px sans-serif'; ctx.fillText(s, 4, 40);
    return ctx.getImageData(0, 0, 48, 48).data.join(',');
  };
  const tofu = draw('\\u{10FFFD}');
  return [...text].filter(ch => ch.trim() && draw(ch) === tofu);
}"""


def test_the_play_and_pause_labels_are_drawn_by_the_page_fonts(browser, url):
    page = open_page(browser, url, 1280, 720)
    try:
        assert page.evaluate(MISSING_GLYPHS, "\u23f8") == ["\u23f8"]  # the check sees a tofu
        page.get_by_role("button", name="▶ Play").click()
        pause = page.get_by_role("button", name="Pause")
        pause.wait_for(timeout=30_000)
        assert page.evaluate(MISSING_GLYPHS, pause.inner_text() + "▶ Play") == []
    finally:
        page.close()
