"""The page as a class sees it on a projector, a laptop and a phone, measured from element boxes in
Debian's chromium: what is in the first screen, what scrolls, what presentation mode enlarges, and
that no text a figure draws on its canvas is cut."""

from __future__ import annotations

import time

import pytest
from playwright.sync_api import expect
from test_browser import ARTIFACTS, MAP_MARKER, SIZES, handle, map_settled, open_page, text

from served import DEEP_TEXT, VIEW_DRAWN, show_view

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


PHONE = (390, 844)


def in_first_screen(page, locator) -> None:
    """Wholly on the screen, below the header (not under it) and not clipped by a pane's edge."""
    expect(locator).to_be_in_viewport(ratio=1.0)
    for _ in range(40):  # an element Bokeh re-renders meanwhile has no box for a moment (0, 0)
        box = locator.evaluate(
            "(el) => { const b = el.getBoundingClientRect();"
            " return {y: b.y, bottom: b.bottom, screen: window.innerHeight} }"
        )
        if box["bottom"] > 0:
            break
        page.wait_for_timeout(250)
    header = page.locator("#header").bounding_box()
    assert bottom(header) - 1 <= box["y"] and box["bottom"] <= box["screen"], box


@pytest.mark.parametrize("query", ["", "?theme=dark", "?presentation=true"])
def test_a_phone_shows_the_readouts_while_a_slider_is_moved(browser, url, query):
    """At 390×844 a student drags a slider with a finger and sees, on the same screen and without
    scrolling, the readouts and the status answer it: the tabs above, the controls below (the
    sidebar once stood ~900 px of controls above the readouts, 1.5 screens of scrolling)."""
    page = open_page(browser, url, *PHONE, query)
    try:
        page.get_by_text("Running.").first.wait_for()
        status = page.locator(".alert").filter(visible=True)  # the status, whatever it says
        expect(status).to_have_count(1)
        readouts = [page.locator(f"[data-name={n}]") for n in ("mean_flow", "margin", "energy")]
        head = handle(page, "Head h [m]")
        head.scroll_into_view_if_needed()  # scrolls the controls' pane, not the tabs'
        for shown in [*readouts, status, head]:
            in_first_screen(page, shown)
        before = text(page, "mean_flow")
        box = head.bounding_box()
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        page.mouse.move(x, y)
        page.mouse.down()
        page.mouse.move(x + 60, y, steps=6)
        page.mouse.up()
        page.wait_for_function(
            f"(b) => ({DEEP_TEXT})('[data-name=mean_flow]') !== b", arg=before, timeout=60_000
        )
        for shown in [*readouts, status, head]:  # nothing scrolled away meanwhile
            in_first_screen(page, shown)
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / f"phone-moved{query.replace('?', '-')}.png"))
        assert page.problems == []
    finally:
        page.close()


def test_a_phone_shows_the_readouts_and_the_whole_crank_speed_in_its_first_screen(browser, url):
    """A phone's first screen: the readouts, the status and one whole chart, the crank speed,
    below the header and above the controls' pane (cut at the fold in a new user's trial), its
    plot as high as elsewhere; the controls' pane shows the preset menu and a slider whole."""
    page = open_page(browser, url, *PHONE)
    try:
        page.get_by_text("Running.").first.wait_for()
        page.wait_for_function(VIEW_DRAWN, arg="speed", timeout=60_000)
        time.sleep(1.0)
        box = page.evaluate(VIEW_BOX, "speed_figure")
        pane = page.locator("#main").bounding_box()
        top = bottom(page.locator("#header").bounding_box())
        assert box is not None and top - 1 <= box["y"], box
        assert bottom(box) <= bottom(pane) + 1, (box, pane)
        frame = page.evaluate(FRAME_HEIGHT, "Crank speed")
        assert frame >= 150, frame  # not squashed to fit (~169 px, as in presentation mode)
        status = page.locator(".alert").filter(visible=True)
        readouts = [page.locator(f"[data-name={n}]") for n in ("mean_flow", "margin", "energy")]
        presets = page.locator("#sidebar select").first
        for shown in [*readouts, status, presets, handle(page, "L/R, rod / crank")]:
            in_first_screen(page, shown)
    finally:
        page.close()


# The legend below a figure: its box (in the canvas's coordinates), its visible items, and the
# canvas's height.
LEGEND_BELOW = """(name) => {
  const model = window.Bokeh.documents[0].get_model_by_name(name);
  const view = window.Bokeh.index.find_one(model);
  const legend = model.below.find(panel => panel.items !== undefined);
  const shown = legend.items.filter(item => item.visible !== false).length;
  const box = view.views.find_one(legend).bbox;
  return {shown, top: box.top, bottom: box.bottom, canvas: view.el.getBoundingClientRect().height};
}"""


def test_a_phone_shows_a_deep_wells_whole_crank_speed_and_a_slider_under_its_preset(browser, url):
    """The preset "A deep well, a heavy rod" on a phone: its crank speed's legend holds five
    items in three rows, and the first screen cut its last rows (the chart ~55 px past the
    controls' pane); its sentence, six lines, filled the controls' pane. Now the whole chart,
    legend and a plot as high as the paper's example's, is above the controls, and the controls
    show the sentence's start (two lines; a tap shows it all) and, scrolled to it, no more."""
    page = open_page(browser, url, *PHONE)
    try:
        page.get_by_text("Running.").first.wait_for()
        page.locator("#sidebar select").first.select_option(label="A deep well, a heavy rod")
        page.get_by_text("It settles at α₊ = 20.74 rad/s").first.wait_for(timeout=120_000)
        page.wait_for_function(
            f"() => ({LEGEND_BELOW})('speed_figure').shown === 5", timeout=60_000
        )
        time.sleep(1.0)  # laid out
        box = page.evaluate(VIEW_BOX, "speed_figure")
        pane = page.locator("#main").bounding_box()
        top = bottom(page.locator("#header").bounding_box())
        assert top - 1 <= box["y"] and bottom(box) <= bottom(pane) + 1, (box, pane)
        legend = page.evaluate(LEGEND_BELOW, "speed_figure")
        assert 0 < legend["top"] and legend["bottom"] <= legend["canvas"] + 1, legend
        assert page.evaluate(FRAME_HEIGHT, "Crank speed") >= 150  # not squashed to fit
        note = page.locator("#sidebar p", has_text="A deep well, a heavy rod.")
        line = float(note.evaluate("(el) => parseFloat(getComputedStyle(el).lineHeight)"))
        folded = note.bounding_box()["height"]
        assert folded <= 2 * line + 2, (folded, line)
        sidebar = page.locator("#sidebar").bounding_box()
        assert bottom(note.bounding_box()) <= bottom(sidebar) - 20  # room for what follows
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "phone-deep-well.png"))
        note.click()  # a tap shows the whole sentence
        page.wait_for_function(
            "([el, h]) => el.getBoundingClientRect().height > h + 1",
            arg=[note.element_handle(), folded],
        )
        assert page.problems == []
    finally:
        page.close()


def test_a_phone_hides_and_shows_its_controls_with_the_header_toggle(browser, url):
    """The header's toggle hides the controls' pane (the views take the whole screen) and brings
    it back; the sidebar's own scroll holds the controls below its first screen."""
    page = open_page(browser, url, *PHONE)
    try:
        main, sidebar = page.locator("#main"), page.locator("#sidebar")
        with_controls = main.bounding_box()
        assert bottom(with_controls) <= sidebar.bounding_box()["y"] + 1  # above, not beside
        assert page.evaluate("() => document.querySelector('#content').scrollHeight") <= PHONE[1]
        download = page.get_by_role("button", name="Download this run (CSV)")
        download.scroll_into_view_if_needed()  # scrolls the controls' pane, not the page
        in_first_screen(page, download)
        in_first_screen(page, page.locator("[data-name=mean_flow]"))
        page.locator("#sidebar-toggle").click()
        expect(sidebar).to_be_hidden()
        page.wait_for_function(
            f"() => document.querySelector('#main').clientHeight > {PHONE[1] - 80}"
        )
        page.locator("#sidebar-toggle").click()
        expect(sidebar).to_be_visible()
        page.wait_for_function(
            "(h) => Math.abs(document.querySelector('#main').clientHeight - h) < 2",
            arg=with_controls["height"],
        )
        assert page.problems == []
    finally:
        page.close()


@pytest.mark.parametrize("query", ["?restored=true", "?h=-3"])
def test_a_phone_says_a_restored_connection_or_a_refused_value_first(browser, url, query):
    """The notices stand above the readouts, at the top of a phone's screen."""
    page = open_page(browser, url, *PHONE, query)
    try:
        said = "connection to the server was lost" if "restored" in query else "were ignored"
        notice = page.locator(".alert", has_text=said).filter(visible=True).first
        in_first_screen(page, notice)
        assert page.problems == []
    finally:
        page.close()


@pytest.mark.parametrize("width, height", SIZES)
@pytest.mark.parametrize("query", ["", "?presentation=true"])
def test_nothing_scrolls_sideways_and_no_canvas_text_is_cut(browser, url, width, height, query):
    """The element that scrolls (#main, above the controls on a phone, beside them elsewhere)
    never scrolls sideways, and every figure's title and axis labels fit inside it."""
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
        if width < 700:  # two panes, each scrolling on its own: the page itself does not
            outer = page.evaluate(
                "() => { const c = document.querySelector('#content');"
                " return c.scrollHeight - c.clientHeight }"
            )
            assert outer <= 1, f"the page scrolls {outer} px around its two panes"
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


# Every collapsed card's chevron, as drawn: Panel 1.9's listpanel.css strokes it with a variable the
# page's theme does not define, which leaves it unpainted (stroke "none"); and every slider title
# wider than its box (Bokeh keeps a title on one line: a long one loses its value past the edge).
CHEVRONS = """() => { const out = []; const walk = (r) => {
  for (const svg of r.querySelectorAll('.card-button > svg')) out.push(getComputedStyle(svg).stroke);
  for (const el of r.querySelectorAll('*')) if (el.shadowRoot) walk(el.shadowRoot); };
  walk(document); return out; }"""
CUT_TITLES = """() => { const out = []; const walk = (r) => {
  for (const el of r.querySelectorAll('.bk-slider-title'))
    if (el.scrollWidth > el.clientWidth + 1) out.push(el.textContent);
  for (const el of r.querySelectorAll('*')) if (el.shadowRoot) walk(el.shadowRoot); };
  walk(document); return out; }"""


@pytest.mark.parametrize("query", ["?presentation=true", "?presentation=true&theme=dark"])
def test_the_cards_show_their_chevron_and_every_slider_its_value(browser, url, query):
    """A newcomer sees that "More parameters" and "Real machine" open (a chevron, painted in
    the text's colour), and, with both open in presentation mode at 1280×720, every slider's
    title and value in full ("Leak discharge coefficient: 0.60" wraps, not cut)."""
    page = open_page(browser, url, 1280, 720, query)
    try:
        strokes = page.evaluate(CHEVRONS)
        assert len(strokes) >= 2 and "none" not in strokes, strokes
        for title in ("More parameters", "Real machine"):
            page.get_by_text(title).first.click()
        page.locator(".bk-slider-title", has_text="Leak discharge coefficient").wait_for()
        time.sleep(1.0)
        assert page.evaluate(CUT_TITLES) == []
        assert page.problems == []
    finally:
        page.close()


# The text glyphs a figure draws that end past its frame's right edge, measured with the canvas's
# font: the waterfall's "11,967 J, 100 %" lost its "%" in presentation mode and on a phone.
CUT_GLYPH_TEXT = """(name) => {
  const model = window.Bokeh.documents[0].get_model_by_name(name);
  const view = window.Bokeh.index.find_one(model);
  const frame = view.frame.bbox, scale = view.frame.x_scale, cut = [];
  const ctx = document.createElement('canvas').getContext('2d');
  const v = (p) => (p !== null && typeof p === 'object' && 'value' in p) ? p.value : p;
  for (const r of model.renderers) {
    const g = r.glyph;
    if (!g || !('text' in g) || !('x_offset' in g)) continue;
    const data = r.data_source.data, text = data[g.text.field], x = data[g.x.field];
    ctx.font = `${v(g.text_font_size)} helvetica`;
    for (let i = 0; i < text.length; i++) {
      const end = scale.compute(x[i]) + v(g.x_offset) + ctx.measureText(text[i]).width;
      if (end > frame.right + 1) cut.push([text[i], end, frame.right]);
    }
  }
  return cut;
}"""


@pytest.mark.parametrize(
    "width, height, query", [(1280, 720, "?presentation=true"), (390, 844, "")]
)
def test_the_waterfall_labels_end_inside_their_figure(browser, url, width, height, query):
    page = open_page(browser, url, width, height, query)
    try:
        settled(page)
        show_view(page, "energy")  # built when scrolled to, as a student sees it
        assert page.evaluate(CUT_GLYPH_TEXT, "energy_figure") == []
        assert page.problems == []
    finally:
        page.close()


# The smallest distance [px] between neighbouring tick labels of each vertical axis of a figure
# titled so, with the labels' font size [px]: the Wind tab's second axis once stacked nine labels
# (0 to 0.16 by 0.02) 14-17 px apart in 18 px type.
TICK_GAPS = """(title) => {
  const out = [];
  for (const model of window.Bokeh.documents[0].all_models) {
    if (model.type !== 'LinearAxis' && model.constructor.__name__ !== 'LinearAxis') continue;
    const view = window.Bokeh.index.find_one(model);
    if (!view || !view.tick_coords || view.dimension !== 1) continue;
    const plot = view.parent;
    if (!plot.model.title || plot.model.title.text !== title) continue;
    const frame = plot.frame, range = model.y_range_name;
    const scale = range === 'default' ? frame.y_scale : frame.y_scales.get(range);
    const ys = view.tick_coords.major[1].map(y => scale.compute(y));
    const gap = Math.min(...ys.slice(1).map((y, i) => Math.abs(y - ys[i])));
    out.push([model.axis_label, gap, parseFloat(model.major_label_text_font_size)]);
  }
  return out;
}"""


FRAME_HEIGHT = """(title) => {
  for (const model of window.Bokeh.documents[0].all_models)
    if (model.title && model.title.text === title) return window.Bokeh.index.find_one(model).frame.bbox.height;
}"""


@pytest.mark.parametrize(
    "width, height, query", [(1280, 720, "&presentation=true"), (390, 844, "")]
)
def test_the_wind_curves_tick_labels_do_not_overlap(browser, url, width, height, query):
    page = open_page(browser, url, width, height, "?tab=wind" + query)
    try:
        title = "Water against steady wind"
        page.wait_for_function(f"(t) => ({TICK_GAPS})(t).length === 2", arg=title, timeout=60_000)
        time.sleep(1.0)
        gaps = page.evaluate(TICK_GAPS, title)
        assert [label for label, _, _ in gaps] == ["mean flow [L/s]", "Weibull density [s/m]"]
        crowded = [(label, gap, font) for label, gap, font in gaps if gap < 1.5 * font]
        assert crowded == []
        if "presentation" in query:  # its legend in three rows once left the plot 90-140 px
            assert page.evaluate(FRAME_HEIGHT, title) >= 200
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


@pytest.mark.parametrize("width, height", SIZES)
def test_the_design_map_fits_the_tabs_pane_whole(browser, url, width, height):
    """Scrolled to its top, the Design map's figure (title, colour bar, legend) is wholly in the
    tabs' pane: on a phone it was 520 px high in a pane of ~458 and its top went under the
    header once scrolled to its foot. Laptops keep its 520 px; at 1920×1080 it took 520 px too
    and drew a frame ~4 times wider than high over the screen's upper half, the rest blank: it
    takes the screen's height there (ending within 10 % of its foot)."""
    page = open_page(browser, url, width, height)
    try:
        page.get_by_text("Design map", exact=True).first.click()
        page.wait_for_function(f"() => ({MAP_MARKER})() !== null", timeout=120_000)
        map_settled(page)
        page.evaluate(
            "() => window.Bokeh.index.find_one(window.Bokeh.documents[0]"
            ".get_model_by_name('map_figure')).el.scrollIntoView({block: 'start'})"
        )
        time.sleep(0.5)
        box = page.evaluate(VIEW_BOX, "map_figure")
        header = page.locator("#header").bounding_box()
        pane = page.locator("#main").bounding_box()
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / f"design_map_top_{width}x{height}.png"))
        assert box["y"] >= bottom(header) - 1, (box, header)
        assert bottom(box) <= min(bottom(pane), height) + 1, (box, pane)
        if width >= 1920:
            assert 0.9 * height <= bottom(box) <= height, (box, height)
        elif width > 700:
            assert abs(box["height"] - 520) <= 1, box
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


# Every select box shown, through shadow roots: each option's text wider than the room its box
# leaves it (its inner width less its padding, where the arrow is drawn), measured in its own font.
CUT_OPTIONS = """() => {
  const cut = [], ctx = document.createElement('canvas').getContext('2d');
  let boxes = 0;
  const walk = (root) => {
    for (const el of root.querySelectorAll('*')) {
      if (el.shadowRoot) walk(el.shadowRoot);
      if (el.tagName !== 'SELECT' || el.getBoundingClientRect().width === 0) continue;
      boxes += 1;
      const style = getComputedStyle(el);
      ctx.font = `${style.fontWeight} ${style.fontSize} ${style.fontFamily}`;
      const room = el.clientWidth - parseFloat(style.paddingLeft) - parseFloat(style.paddingRight);
      for (const option of el.options) {
        const width = ctx.measureText(option.text).width;
        if (width > room) cut.push([option.text, Math.round(width), Math.round(room)]);
      }
    }
  };
  walk(document);
  return {boxes, cut};
}"""


@pytest.mark.parametrize("width, height", SIZES)
def test_every_select_shows_each_option_whole(browser, url, width, height):
    """A select box shows its choice on one line and cut it at its edge ("A deep well with a
    heavy pump roc"): every option of every select (the presets, the machine's playback speed,
    the Site tab's site and restart) fits its box, in presentation mode's larger text (a phone
    keeps its usual sizes), whose boxes are as wide as without it."""
    page = open_page(browser, url, width, height, "?tab=site&presentation=true")
    try:
        page.get_by_text("Restart after a calm").wait_for(timeout=120_000)  # the Site tab built
        page.get_by_text("Wind pump", exact=True).first.click()
        show_view(page, "machine")  # its playback speed
        page.get_by_text("Site", exact=True).first.click()  # shown again: its selects measured
        page.get_by_text("Restart after a calm").wait_for(timeout=60_000)
        shown = page.evaluate(CUT_OPTIONS)
        assert shown["boxes"] == 5, shown  # the presets, windmill, playback speed, site, restart
        assert shown["cut"] == [], f"options cut at {width}×{height}: {shown['cut']}"
        assert page.problems == []
    finally:
        page.close()


# The boxes of the Mechanisms tab's three figures (the slider-crank's drawing and travel, the
# linkage), in the page's coordinates, and the tabs' pane's.
MECHANISM_BOXES = """() => {
  const boxes = [];
  for (const model of window.Bokeh.documents[0].all_models) {
    const title = model.title?.text ?? '';
    if (!/slider-crank \\(Newton|Piston position|Four-bar \\/ double loop/.test(title)) continue;
    const view = window.Bokeh.index.find_one(model);
    if (!view) continue;
    const b = view.el.getBoundingClientRect();
    boxes.push({title, x: b.x, y: b.y, right: b.right, bottom: b.bottom, width: b.width});
  }
  const pane = document.querySelector('#main').getBoundingClientRect();
  return {boxes, pane: {x: pane.x, right: pane.right, width: pane.width, bottom: pane.bottom}};
}"""


@pytest.mark.parametrize("width, height", SIZES)
def test_the_mechanisms_tab_uses_the_screens_width(browser, url, width, height):
    """At 1920×1080 the tab drew its figures in the left ~60 % of the pane, the rest blank: its
    two parts, the slider-crank and the linkage, go side by side where both fit, so the tab fills
    the width and its three figures are in the first screen. Narrower screens keep them one
    above the other, each figure at least 300 px wide, nothing wider than the pane."""
    page = open_page(browser, url, width, height, "?tab=mechanisms")
    try:
        page.wait_for_function(f"(n) => ({VIEW_BOX})(n) !== null", arg="linkage_figure")
        time.sleep(1.0)  # laid out
        shown = page.evaluate(MECHANISM_BOXES)
        boxes, pane = shown["boxes"], shown["pane"]
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / f"mechanisms_{width}x{height}.png"))
        assert len(boxes) == 3, boxes
        for box in boxes:
            assert box["width"] >= 300 - 1, box
            assert box["x"] >= pane["x"] - 1 and box["right"] <= pane["right"] + 1, (box, pane)
        if width >= 1920:
            used = max(box["right"] for box in boxes) - pane["x"]
            assert used >= 0.9 * pane["width"], f"{used:.0f} px of the pane's {pane['width']:.0f}"
            assert all(box["bottom"] <= height for box in boxes), boxes  # the first screen
        assert page.problems == []
    finally:
        page.close()


@pytest.mark.parametrize("width, height", SIZES)
def test_the_mechanisms_tab_uses_a_wide_screens_height(browser, url, width, height):
    """At 1920×1080 the figures stood 440 px high and left ~30 % of the screen blank below them:
    where the two parts stand side by side the figures take the screen's height (the lowest
    ending within 10 % of the screen's foot, none past it), their drawings still at equal
    scales. Where the parts stand one above the other (1366 px and narrower) the figures keep
    their 440 px."""
    page = open_page(browser, url, width, height, "?tab=mechanisms")
    try:
        page.wait_for_function(f"(n) => ({VIEW_BOX})(n) !== null", arg="linkage_figure")
        time.sleep(2.0)  # laid out
        boxes = page.evaluate(MECHANISM_BOXES)["boxes"]
        assert len(boxes) == 3, boxes
        if width >= 1920:
            lowest = max(box["bottom"] for box in boxes)
            assert 0.9 * height <= lowest <= height, f"figures end at {lowest:.0f} of {height}"
        else:
            heights = [box["bottom"] - box["y"] for box in boxes]
            assert all(abs(h - 440) <= 2 for h in heights), heights
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / f"mechanisms-height_{width}x{height}.png"))
        assert page.problems == []
    finally:
        page.close()


@pytest.mark.parametrize("width, height", SIZES)
def test_the_linkages_controls_leave_no_blank_block_beside_its_drawing(browser, url, width, height):
    """At 1920×1080 the four-bar's sliders stood in a column beside its drawing, which takes the
    screen's height there: a block ~270 × 420 px blank under them. The controls stand above the
    drawing (in columns side by side where they fit) and the drawing spans their width: at
    every size no control ends below the drawing's top, and the drawing is at least as wide as
    the controls' row, within its 920 px."""
    page = open_page(browser, url, width, height, "?tab=mechanisms")
    try:
        page.wait_for_function(f"(n) => ({VIEW_BOX})(n) !== null", arg="linkage_figure")
        time.sleep(2.0)  # laid out, the heights filled
        drawing = page.evaluate(VIEW_BOX, "linkage_figure")
        controls = [
            page.get_by_text(label).first.bounding_box()
            for label in ("Input angle θ₁", "Ground r₆", "+1: B left of A→D")
        ]
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / f"linkage_controls_{width}x{height}.png"))
        for box in controls:
            assert bottom(box) <= drawing["y"] + 1, (box, drawing)
        span = max(b["x"] + b["width"] for b in controls) - min(b["x"] for b in controls)
        assert drawing["width"] >= min(span, 920) - 40, (drawing, span)
        assert page.problems == []
    finally:
        page.close()
