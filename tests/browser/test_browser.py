"""The explorer as a student meets it: `panel serve app/` in Debian's chromium, driven by playwright."""

from __future__ import annotations

import math
import os
import re
import time
from pathlib import Path
from urllib.parse import parse_qs, urlparse

import numpy as np
import pytest

import windpump
from windpump.model.wind import gusty

from served import (
    DEEP_TEXT,
    OPENED_PAGES,
    VIEWS_DRAWN,
    server_log,
    show_view,
)

pytestmark = pytest.mark.browser

ARTIFACTS = Path(
    os.environ.get("WINDPUMP_ARTIFACTS", Path(__file__).resolve().parents[2] / "artifacts")
)
SEED = windpump.Design.seed_example()
MAIN_SLIDERS = [
    "L/R, rod / crank",
    "R₁/R₀, sprocket ratio",
    "Head h [m]",
    "Peak torque Tₘ [N·m]",
]
SIZES = [(1280, 720), (1366, 768), (1920, 1080), (390, 844)]
SPEED_DATA = "() => Array.from(window.Bokeh.documents[0].get_model_by_name('speed').data.upper)"
PLAYER = "() => window.Bokeh.documents[0].get_model_by_name('frames')._player || null"

# Every element that shows text of its own, through open shadow roots, with its font size and
# whether it is visible: nothing a student must read may be below 14 px.
TEXT_SIZES = """() => {
  const found = [];
  const walk = (root) => {
    for (const el of root.querySelectorAll('*')) {
      if (el.shadowRoot) walk(el.shadowRoot);
      const own = Array.from(el.childNodes).some(n => n.nodeType === 3 && n.textContent.trim());
      if (!own) continue;
      const box = el.getBoundingClientRect(), style = getComputedStyle(el);
      if (box.width === 0 || box.height === 0 || style.visibility === 'hidden') continue;
      found.push([el.textContent.trim().slice(0, 40), parseFloat(style.fontSize)]);
    }
  };
  walk(document);
  return found;
}"""


# The addresses in chromium's console line for a load the page's policy blocked before it was
# requested ("Loading the stylesheet 'https://…' violates the following Content Security Policy").
ADDRESS = re.compile(r"(?:https?|wss?)://[^\s'\"]+")


def record_elsewhere(page, url: str, opened: str) -> list[str]:
    """Record in ``page.elsewhere`` (returned) every request ``page`` makes to another host than
    ``url``'s, its frames' included, and every such load its policy refused (app/server/policy.py:
    refused, it is never requested, but it is what the page asked for); checked after each test
    (tests/conftest.py)."""
    host, elsewhere = urlparse(url).netloc, []

    def other(address: str) -> bool:
        parts = urlparse(address)
        return parts.scheme in ("http", "https", "ws", "wss") and parts.netloc != host

    page.on("request", lambda r: elsewhere.append(r.url) if other(r.url) else None)
    page.on(
        "console",
        lambda m: (
            elsewhere.extend(a.rstrip(".") for a in ADDRESS.findall(m.text) if other(a))
            if "Content Security Policy" in m.text
            else None
        ),
    )
    page.elsewhere, page.opened = elsewhere, opened
    OPENED_PAGES.append(page)
    return elsewhere


def open_page(browser, url, width=1400, height=1000, query=""):
    page = browser.new_page(viewport={"width": width, "height": height})
    page.set_default_timeout(60_000)  # clicks and locators on a busy machine (playwright's: 30 s)
    problems: list[str] = []
    page.on(
        "console", lambda m: problems.append(m.text) if m.type in ("error", "warning") else None
    )
    page.on("pageerror", lambda error: problems.append(str(error)))
    record_elsewhere(page, url, url + query)
    scripts, received = [], []
    page.on("request", lambda r: scripts.append(r.url) if r.resource_type == "script" else None)
    page.on("websocket", lambda ws: ws.on("framereceived", lambda frame: received.append(frame)))
    sent, posts = [], []  # the sizes of the page's websocket frames [chars]; its POSTs' URLs
    page.on("websocket", lambda ws: ws.on("framesent", lambda frame: sent.append(len(frame))))
    page.on("request", lambda r: posts.append(r.url) if r.method == "POST" else None)
    page.goto(url + query, timeout=120_000)
    page.wait_for_function(
        f"() => ({DEEP_TEXT})('[data-name=mean_flow]') !== null", timeout=120_000
    )
    if width > 700:  # a phone shows the sidebar first: its views come when it scrolls to them
        page.wait_for_function(VIEWS_DRAWN, timeout=120_000)  # the views follow the readouts
    page.problems, page.scripts = problems, scripts
    page.received = received  # the server's messages over the page's websocket
    page.sent, page.posts = sent, posts
    return page


@pytest.fixture
def page(browser, url):
    page = open_page(browser, url)
    yield page
    assert page.elsewhere == []  # every resource from the app's own server
    page.close()


def handle(page, label):
    title = page.locator(".bk-slider-title", has_text=label)
    return page.locator(".bk-input-group", has=title).locator(".noUi-handle")


def text(page, name):
    return page.evaluate(DEEP_TEXT, f"[data-name={name}]")


def model_data(page, name, column):
    return page.evaluate(
        f"() => Array.from(window.Bokeh.documents[0].get_model_by_name('{name}').data.{column})"
    )


def press(page, label, key, times):
    handle(page, label).focus()
    for _ in range(times):
        page.keyboard.press(key)


def wait_for_readout(page, name, expected):
    page.wait_for_function(
        f"(e) => ({DEEP_TEXT})('[data-name={name}]') === e", arg=expected, timeout=60_000
    )


def flow_readout(design, t_end=600.0, theta0=math.pi / 2, theta_dot0=3.0) -> str:
    return f"{1e3 * windpump.explore(design, t_end, theta0, theta_dot0).mean_flow:.4f} L/s"


def test_a_keyboard_move_redraws_what_the_core_computes(page):
    assert page.problems == []
    for label in MAIN_SLIDERS:
        assert page.locator(".bk-slider-title", has_text=label).count() == 1, label
    assert "Running" in page.get_by_text("Running.").first.inner_text()
    flow_before, speed_before = text(page, "mean_flow"), page.evaluate(SPEED_DATA)

    press(page, "Head h [m]", "ArrowRight", 5)
    page.locator(".bk-slider-title", has_text="Head h [m]: 3.5").wait_for(timeout=30_000)
    seen = windpump.explore(SEED.replace(h=3.5), 600.0, math.pi / 2, 3.0)
    wait_for_readout(page, "mean_flow", f"{1e3 * seen.mean_flow:.4f} L/s")
    assert text(page, "mean_flow") != flow_before
    # the readouts come first, the views' data after them (serving.ReadoutsFirst): on a busy
    # machine the crank speed's patch may still be on its way when the readout has changed
    top = float(seen.run.theta_dot.max())
    page.wait_for_function(
        f"(top) => Math.abs(Math.max(...({SPEED_DATA})()) - top) <= 1e-6 * top",
        arg=top,
        timeout=60_000,
    )
    speed_after = page.evaluate(SPEED_DATA)
    assert speed_after != speed_before
    assert max(speed_after) == pytest.approx(top, rel=1e-6)
    # ... and the link follows the slider
    page.wait_for_function(
        "() => new URLSearchParams(location.search).get('h') === '3.5'", timeout=30_000
    )
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(ARTIFACTS / "explorer.png"))
    assert page.problems == []


def test_one_students_moves_send_nothing_to_another_students_page(browser, url):
    mine, theirs = open_page(browser, url), open_page(browser, url)
    try:
        time.sleep(2.0)  # both pages settled
        before = len(theirs.received)
        press(mine, "Head h [m]", "ArrowRight", 3)
        wait_for_readout(mine, "mean_flow", flow_readout(SEED.replace(h=3.3)))
        time.sleep(2.0)  # anything the server sent the other page has arrived
        # (the other page's own layout reports may still get their "OK" replies)
        changes = [f for f in theirs.received[before:] if '"msgtype": "PATCH-DOC"' in str(f)]
        assert changes == []
        assert mine.problems == [] and theirs.problems == []
    finally:
        mine.close()
        theirs.close()


def test_a_rejected_value_is_shown_marked_stale_and_the_next_move_recovers(page):
    press(page, "L/R, rod / crank", "Home", 1)  # L/R = 1: the rod cannot reach the crank
    page.get_by_text("the rod cannot reach the crank").first.wait_for(timeout=30_000)
    assert page.get_by_text("L/R, rod / crank = 1 cannot be run").first.is_visible()
    page.keyboard.press("ArrowRight")  # L/R = 1.05: a valid, very short rod
    page.get_by_text("the rod cannot reach the crank").first.wait_for(
        state="hidden", timeout=30_000
    )
    assert "Running" in page.get_by_text("Running.").first.inner_text()
    assert page.problems == []


def test_the_energy_view_is_on_the_main_page(page):
    run = windpump.simulate(SEED, 600.0)
    work = windpump.power_budget(run).shaft_work[-1]
    assert f"{work:,.0f} J = " in text(page, "energy")
    show_view(page, "energy")  # below the first screen: built once scrolled to
    right = model_data(page, "losses", "right")
    assert len(right) == 6 and right[0] == pytest.approx(work, rel=1e-9)
    assert page.problems == []


def test_the_page_loads_no_webgl_and_draws_without_it(page):
    names = [urlparse(u).path.rsplit("/", 1)[-1] for u in page.scripts]
    assert "bokeh.min.js" in names and "panel.min.js" in names
    assert not any(name.startswith("bokeh-gl") for name in names)
    assert page.problems == []  # every view drawn (open_page waited) and nothing missing


def test_the_mechanisms_tab_draws_what_the_loops_close_to(page):
    page.get_by_text("Mechanisms", exact=True).first.click()
    page.locator(".bk-slider-title", has_text="Crank angle θ [°]").wait_for(timeout=30_000)
    assert text(page, "slider_crank").startswith("x = 45.43 mm from TDC")
    crank_before = model_data(page, "crank_links", "xs")

    press(page, "Crank angle θ [°]", "ArrowRight", 5)  # 90° -> 95°
    theta = math.radians(95.0)
    x = float(windpump.piston_position(theta, SEED.R, SEED.L))
    theta_c = math.degrees(float(windpump.rod_angle(theta, SEED.L_over_R)))
    expected = f"x = {1e3 * x:.2f} mm from TDC, θc = {theta_c:.1f}°"
    page.wait_for_function(
        f"(e) => ({DEEP_TEXT})('[data-name=slider_crank]') === e", arg=expected, timeout=30_000
    )
    assert model_data(page, "crank_links", "xs") != crank_before

    linkage_before, note_before = model_data(page, "linkage_links", "xs"), text(page, "linkage")
    press(page, "Input angle θ₁ [°]", "ArrowRight", 10)  # 60° -> 70°
    page.wait_for_function(
        f"(b) => ({DEEP_TEXT})('[data-name=linkage]').startsWith('θ₁ = 70.0°')",
        arg=note_before,
        timeout=30_000,
    )
    assert model_data(page, "linkage_links", "xs") != linkage_before

    press(page, "Coupler r₂ [m]", "Home", 1)  # r2 = 0.2: r2 + r3 cannot span |AD| = 2.82
    page.get_by_text("Cannot close at θ₁ = 70.0°").first.wait_for(timeout=30_000)
    assert page.get_by_text("Coupler r₂ = 0.2 and Output link r₃ = 2.5").first.is_visible()
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(ARTIFACTS / "mechanisms.png"))
    assert page.problems == []


FOCUSED = """() => {
  let el = document.activeElement;
  while (el && el.shadowRoot && el.shadowRoot.activeElement) el = el.shadowRoot.activeElement;
  return el ? [el.className, el.textContent.trim().slice(0, 40), getComputedStyle(el).outlineStyle] : null;
}"""


def test_the_keyboard_switches_tabs_and_screen_readers_hear_every_slider(page):
    for label in MAIN_SLIDERS:
        assert page.get_by_role("slider", name=label, exact=True).count() == 1
    page.get_by_role("tab", name="Wind pump").focus()
    page.keyboard.press("ArrowRight")  # builds the Mechanisms tab on the server: headers redrawn
    page.get_by_role("tab", name="Mechanisms", selected=True).wait_for(timeout=60_000)
    page.get_by_role("slider", name="Crank angle θ [°]", exact=True).wait_for(timeout=60_000)
    page.wait_for_function(f"() => ({FOCUSED})()[1] === 'Mechanisms'", timeout=30_000)
    classes, _, outline = page.evaluate(FOCUSED)
    assert "bk-tab" in classes and outline == "solid"  # focus visible on the header
    page.keyboard.press("Home")
    page.get_by_role("tab", name="Wind pump", selected=True).wait_for(timeout=30_000)
    page.keyboard.press("End")
    page.keyboard.press("Enter")  # the last tab: the Site, its year run when first opened
    page.get_by_role("tab", name="Site", selected=True).wait_for(timeout=60_000)
    assert page.problems == []


# The focused control, through shadow roots, and whether it or a host around it (Panel's
# :host(:focus-within) rule) draws an outline.
FOCUS_SHOWN = """() => {
  let el = document.activeElement;
  while (el && el.shadowRoot && el.shadowRoot.activeElement) el = el.shadowRoot.activeElement;
  if (!el || el === document.body) return [null, true];  // past the last control: not a control
  const name = el ? (el.getAttribute('aria-label') || el.textContent.trim().slice(0, 30) || el.tagName) : null;
  for (let node = el; node; node = node.parentNode || node.host) {
    if (node.nodeType === 1 && getComputedStyle(node).outlineStyle !== 'none') return [name, true];
  }
  return [name, false];
}"""


def test_every_control_shows_its_focus(page):
    page.locator(".bk-slider-title", has_text="L/R, rod / crank").click()  # start in the controls
    seen = {}
    for _ in range(30):
        page.keyboard.press("Tab")
        name, shown = page.evaluate(FOCUS_SHOWN)
        seen[name] = shown
    seen.pop(None, None)
    hidden = [name for name, shown in seen.items() if not shown]
    assert len(seen) > 10 and hidden == [], hidden


def test_a_lab_file_over_the_limit_is_refused_in_the_page_and_the_session_lives(page):
    """Bokeh would send a 20 MB file whole and the page's connection would close (over ~15 MB)."""
    big = {"name": "big.csv", "mimeType": "text/csv", "buffer": b"1,2\n" * 5_000_000}
    page.locator("input[type=file]").set_input_files(files=[big])
    page.get_by_text("The file has 20,000,000 bytes").wait_for(timeout=60_000)
    press(page, "Head h [m]", "ArrowRight", 1)  # the session is alive and keeps its design
    wait_for_readout(page, "mean_flow", flow_readout(SEED.replace(h=3.1)))
    assert page.problems == []


TO_THE_TOP = "() => document.querySelectorAll('*').forEach((el) => { el.scrollTop = 0 })"


def in_view(page, shown):
    """Whether the first element with this text lies wholly inside the window."""
    box = page.get_by_text(shown).first.bounding_box()
    height, width = page.evaluate("() => [window.innerHeight, window.innerWidth]")
    return (
        box is not None
        and 0 <= box["y"]
        and box["y"] + box["height"] <= height
        and (0 <= box["x"] and box["x"] + box["width"] <= width)
    )


def test_every_lab_uploads_outcome_is_shown_in_view_at_1280x720(browser, url):
    """The messages under the upload lie below the sidebar's fold: each outcome is scrolled to."""
    from playwright.sync_api import expect

    omega = np.linspace(5, 95, 10)
    torque = 0.6 * (omega / 50) * (2 - omega / 50)
    swapped = "".join(f"{q},{w}\n" for w, q in zip(omega, torque, strict=True)).encode()
    page = open_page(browser, url, width=1280, height=720)
    try:
        upload = page.locator("input[type=file]").first
        for name, content, shown in [
            ("typo.csv", b"10,0.216x\n50,0.6\n90,0.2\n", "Line 1, column 2: '0.216x' is not"),
            ("empty.csv", b"", "The file is empty"),
            ("swapped.csv", swapped, "It cannot be applied: Peak torque"),
        ]:
            page.evaluate(TO_THE_TOP)  # the sidebar scrolled back: the upload's messages below
            upload.set_input_files(
                files=[{"name": name, "mimeType": "text/csv", "buffer": content}]
            )
            message = page.get_by_text(shown).first
            expect(message).to_be_in_viewport(ratio=1.0, timeout=60_000)
            assert in_view(page, shown), name
        assert page.get_by_role("button", name="Apply this fit anyway").is_hidden()
        assert page.problems == []
    finally:
        page.close()


# -- the page a class sees ------------------------------------------------------------------------


def box(page, selector_text):
    """The bounding box of the first visible element with this text."""
    return page.get_by_text(selector_text).first.bounding_box()


@pytest.mark.parametrize("width, height", SIZES)
def test_the_page_fits_the_screen(browser, url, width, height):
    page = open_page(browser, url, width, height)
    try:
        time.sleep(1.0)  # let the layout settle
        scroll, client = page.evaluate(
            "() => [document.documentElement.scrollWidth, document.documentElement.clientWidth]"
        )
        assert scroll <= client, f"{scroll - client} px of horizontal scrolling at {width}×{height}"
        viewport = page.evaluate(
            "() => document.querySelector('meta[name=viewport]')?.getAttribute('content')"
        )
        assert viewport and "width=device-width" in viewport
        small = [(t, size) for t, size in page.evaluate(TEXT_SIZES) if size < 14]
        assert small == [], f"text below 14 px: {small[:8]}"
        speed, flow = box(page, "Crank speed θ̇: the full"), box(page, "Flow Q = A ẋ")
        if width >= 1600:
            assert abs(speed["y"] - flow["y"]) < 2 and flow["x"] > speed["x"]  # side by side
        if width < 700:
            assert flow["y"] > speed["y"] + speed["height"] - 1  # one column
        if (width, height) == (1280, 720):
            for shown in ("Mean flow", "Stall margin, Eq. (22)", "Running."):
                assert box(page, shown)["y"] + box(page, shown)["height"] <= height, shown
            # under its plot: the crank speed and the machine playing it, side by side
            for caption in ("Crank speed θ̇: the full", "The machine playing the computed run"):
                assert box(page, caption)["y"] <= height, caption
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / f"explorer-{width}x{height}.png"))
        assert page.problems == [] and page.elsewhere == []
    finally:
        page.close()


# -- state in the link ----------------------------------------------------------------------------


def test_a_link_reproduces_the_design(browser, url):
    page = open_page(browser, url, query="?h=5&T_m=0.8&theta_dot0=4.5")
    try:
        expected = flow_readout(SEED.replace(h=5.0, T_m=0.8), theta_dot0=4.5)
        wait_for_readout(page, "mean_flow", expected)
        assert page.locator(".bk-slider-title", has_text="Head h [m]: 5.0").count() == 1
        query = parse_qs(urlparse(page.url).query)
        assert float(query["h"][0]) == 5.0 and float(query["T_m"][0]) == 0.8
        assert page.problems == []
    finally:
        page.close()


def test_presentation_mode_is_in_the_link_and_survives_the_theme_switch(browser, url):
    page = open_page(browser, url, query="?presentation=true")
    value = page.locator("[data-name=mean_flow]")
    try:
        assert value.evaluate("e => getComputedStyle(e).fontSize") == "30px"  # 20 px without
        page.get_by_role("button", name="Dark theme").click()  # reloads the page with theme=dark
        page.wait_for_url("**theme=dark**", timeout=120_000)
        value.wait_for(timeout=120_000)
        assert "presentation=true" in page.url
        assert value.evaluate("e => getComputedStyle(e).fontSize") == "30px"
    finally:
        page.close()


def test_a_tampered_link_is_ignored_with_a_notice(browser, url):
    page = open_page(browser, url, query="?h=banana&T_m=0.8&L_over_R=1e9")
    try:
        page.get_by_text("Some values in the link were ignored").first.wait_for(timeout=30_000)
        assert page.get_by_text("Head h [m] (h) = “banana” ignored").first.is_visible()
        assert page.get_by_text("L/R, rod / crank (L_over_R) = “1e9” ignored").first.is_visible()
        wait_for_readout(page, "mean_flow", flow_readout(SEED.replace(T_m=0.8)))
        assert page.problems == []
    finally:
        page.close()


TORQUE_CSV = Path(__file__).parents[2] / "docs" / "examples" / "torque.csv"


def readouts_text(page) -> dict[str, str]:
    from windpump_app.readouts import READOUTS

    return {name: text(page, name) for name in READOUTS}


def test_a_fitted_design_reopens_from_its_link_with_the_same_readouts(browser, url):
    """A lab fit puts Tₘ and ωₘ off their sliders' grids: the page's link carries them in full
    and the page it opens shows the same readouts (it once showed Tₘ = 0.6's)."""
    table = windpump.read_torque_csv(TORQUE_CSV.read_bytes())
    fit = windpump.fit_torque_curve(table.omega, table.torque)
    fitted = SEED.replace(T_m=fit.T_m, omega_m=fit.omega_m)
    page = open_page(browser, url)
    again = None
    try:
        page.locator("input[type=file]").first.set_input_files(files=[TORQUE_CSV])
        wait_for_readout(page, "mean_flow", flow_readout(fitted))
        wait_for_link(page, f"?T_m={fit.T_m!r}&omega_m={fit.omega_m!r}")
        shown = readouts_text(page)
        again = open_page(browser, url, query="?" + urlparse(page.url).query)
        wait_for_readout(again, "mean_flow", shown["mean_flow"])
        assert readouts_text(again) == shown
        assert again.evaluate(LINK) == page.evaluate(LINK)
        assert again.get_by_text("Some values in the link").first.is_hidden()  # no notice
        assert page.problems == [] and again.problems == []
    finally:
        page.close()
        if again is not None:
            again.close()


LINK = "() => location.search"
# The opacity an element is seen with: its own times its ancestors', through shadow roots.
SEEN_OPACITY = """e => {
  let seen = 1
  for (let n = e; n; n = n.parentElement || n.getRootNode().host)
    seen *= parseFloat(getComputedStyle(n).opacity)
  return seen
}"""
NOTICES_HTML = """() => Array.from(window.Bokeh.documents[0].all_models)
  .map(m => m.text).find(t => typeof t === 'string' && t.includes('Some values in the link'))"""
COPIED_LINK = """() => {
  window.__copied = null
  navigator.clipboard.writeText = (text) => { window.__copied = text; return Promise.resolve() }
}"""


def wait_for_link(page, search):
    page.wait_for_function(f"(s) => ({LINK})() === s", arg=search, timeout=60_000)


def test_the_link_reads_as_the_sliders_and_reset_leaves_it_bare(page):
    press(page, "Head h [m]", "ArrowRight", 1)
    press(page, "Peak torque Tₘ [N·m]", "ArrowRight", 2)
    wait_for_link(page, "?h=3.1&T_m=0.7")  # not h=3.0999999999999996, T_m=0.7000000000000001
    wait_for_readout(page, "mean_flow", flow_readout(SEED.replace(h=3.1, T_m=0.7)))
    press(page, "Head h [m]", "ArrowRight", 9)
    wait_for_link(page, "?h=4&T_m=0.7")
    page.evaluate(COPIED_LINK)
    page.get_by_role("button", name="Copy link to this state").click()
    page.wait_for_function("() => window.__copied !== null", timeout=30_000)
    assert urlparse(page.evaluate("() => window.__copied")).query == "h=4&T_m=0.7"
    page.get_by_role("button", name="Link copied").wait_for(timeout=10_000)  # it says so
    page.get_by_role("button", name="Copy link to this state").wait_for(timeout=10_000)  # then back
    page.get_by_role("button", name="Reset to the paper's example").click()
    wait_for_link(page, "")  # the defaults are not written
    assert page.problems == []


LINK_BEFORE_TAB = """() => {
  window.__tabInLink = null  // at the link's first tab=wind: were the Wind tab's models there?
  const built = () => [...window.Bokeh.documents[0].all_models].some(
    (m) => typeof m.name === "string" && m.name.startsWith("windtab_"))
  const every = setInterval(() => {
    if (window.location.search.includes("tab=wind")) {
      window.__tabInLink = built()
      clearInterval(every)
    }
  }, 5)
}"""


def test_a_tab_chosen_is_in_the_link_before_it_is_built(page):
    """The Wind tab runs a day when first chosen (seconds): its tab= is in the link at once, so a
    link copied meanwhile opens on it."""
    page.evaluate(LINK_BEFORE_TAB)
    page.get_by_role("tab", name="Wind", exact=True).click()
    page.wait_for_function("() => window.__tabInLink !== null", timeout=60_000)
    assert page.evaluate("() => window.__tabInLink") is False
    page.wait_for_function(
        "() => window.Bokeh.documents[0].get_model_by_name('windtab_litres') !== null",
        timeout=120_000,
    )
    assert page.problems == []


def test_a_link_opens_cleaned_with_a_word_for_what_it_ignored(browser, url):
    query = "?foo=1&h=5&h=3.0999999999999996&cylinders=2.5&T_m=0.8"
    page = open_page(browser, url, query=query)
    try:
        wait_for_link(page, "?h=3.1&T_m=0.8")  # unknown keys and refused values dropped
        notices = page.locator("text=Some values in the link were ignored").first
        assert notices.is_visible()
        for words in (
            "“foo” is not a parameter of this page; ignored.",
            "“h” is given 2 times (5, 3.0999999999999996): the last",
            "(cylinders) = “2.5” ignored: it must be a whole number from 1 to 6.",
        ):
            assert page.get_by_text(words).first.is_visible(), words
        # the slider, the run and the link agree: one cylinder, h = 3.1
        assert page.locator(".bk-slider-title", has_text="Cylinders n (phase lag 2π/n): 1").count()
        wait_for_readout(page, "mean_flow", flow_readout(SEED.replace(h=3.1, T_m=0.8)))
        assert page.problems == []
    finally:
        page.close()


def test_a_link_value_the_core_refuses_is_named_and_the_page_runs_without_it(browser, url):
    page = open_page(browser, url, query="?T_0=0.9&h=5")
    try:
        page.get_by_text(
            "Torque at rest T₀ [N·m] (T_0) = “0.9” ignored: T₀ = 0.9 N·m is not allowed"
        ).first.wait_for(timeout=30_000)
        wait_for_readout(page, "mean_flow", flow_readout(SEED.replace(h=5.0)))
        assert "Running" in page.get_by_text("Running.").first.inner_text()
        assert page.locator("[data-name=mean_flow]").evaluate(SEEN_OPACITY) == 1  # not greyed
        assert page.get_by_text("cannot be run").count() == 0
        wait_for_link(page, "?h=5")
        assert page.problems == []
    finally:
        page.close()


@pytest.mark.parametrize(
    "query, words",
    [
        (
            "?" + "&".join(f"k{i}=1" for i in range(1000)) + "&" + "x" * 30_000 + "=1",
            "996 more ignored",
        ),
        ("?h=5&pad=" + "z" * 100_000, "The link was too long"),
    ],
    ids=["1001 keys, 37 KB", "100 KB"],
)
def test_a_very_long_link_opens_the_page_with_a_short_notice(browser, url, query, words):
    page = open_page(browser, url, query=query)
    try:
        page.get_by_text(words).first.wait_for(timeout=30_000)
        assert len(page.evaluate(NOTICES_HTML)) < 1000
        wait_for_link(page, "")
        wait_for_readout(page, "mean_flow", flow_readout(SEED))
        assert page.problems == []
    finally:
        page.close()


def test_pin_and_reset_at_once_after_arrow_keys_always_reset(browser, server):
    """A class's quick hands: three arrow keys, then Pin and Reset at once, twelve times."""
    url, process = server
    page = open_page(browser, url)
    logged = len(server_log(process))
    reset_state = """() => location.search === ''
      && window.Bokeh.documents[0].get_model_by_name('speed_ghost').data.t.length === 0"""
    try:
        for _attempt in range(12):
            press(page, "Head h [m]", "ArrowRight", 3)
            page.locator(".bk-slider-title", has_text="Head h [m]: 3.3").wait_for(timeout=30_000)
            page.get_by_role("button", name="Pin this run").click()
            page.get_by_role("button", name="Reset to the paper's example").click()
            # back to h = 3.0 only once the server has reset it: the page showed 3.3 until then
            page.locator(".bk-slider-title", has_text="Head h [m]: 3.0").wait_for(timeout=60_000)
            page.wait_for_function(reset_state, timeout=60_000)  # no ghost left pinned
            wait_for_readout(page, "mean_flow", flow_readout(SEED))
        new_lines = server_log(process)[logged:]
        assert "Traceback" not in new_lines and "RuntimeError" not in new_lines, new_lines
        assert page.problems == []
    finally:
        page.close()


# -- the machine in motion ------------------------------------------------------------------------


def drawn_crank(page):
    """The drawn crank pin's angle from TDC [rad] and the drawn piston pin's height [m]."""
    xs, ys = model_data(page, "machine_links", "xs"), model_data(page, "machine_links", "ys")
    pin = (xs[4][1], ys[4][1])  # the crank: centre -> pin
    piston = ys[5][1]  # the rod: pin -> piston pin
    return math.atan2(-pin[0], pin[1]) % (2 * math.pi), piston


def test_the_machine_plays_the_run_in_the_browser(page):
    run = windpump.simulate(SEED, 600.0)
    page.get_by_role("button", name="▶ Play").click()
    page.wait_for_function(f"() => ({PLAYER})() && ({PLAYER})().t > 1.0", timeout=30_000)
    first = page.evaluate(PLAYER)
    page.wait_for_function(  # frames advance (however slowly the machine draws them)
        f"(first) => ({PLAYER})().drawn > first.drawn && ({PLAYER})().t > first.t",
        arg=first,
        timeout=30_000,
    )
    page.get_by_role("button", name="▮▮ Pause").click()
    paused = page.evaluate(PLAYER)["t"]
    time.sleep(0.5)
    assert page.evaluate(PLAYER)["t"] == paused and not page.evaluate(PLAYER)["playing"]

    for t in (100.0, 377.7):
        page.evaluate(
            f"() => {{ window.Bokeh.documents[0].get_model_by_name('scrubber').value = {t} }}"
        )
        page.wait_for_function(f"() => Math.abs(({PLAYER})().t - {t}) < 1e-9", timeout=30_000)
        theta, piston = drawn_crank(page)
        run_theta = float(np.interp(t, run.t, run.theta)) % (2 * math.pi)
        assert abs(math.remainder(theta - run_theta, 2 * math.pi)) < 0.01
        x = float(windpump.piston_position(theta, SEED.R, SEED.L))
        assert piston == pytest.approx(SEED.L + SEED.R - x, abs=2e-6)  # where Eq. (1) puts it
        assert model_data(page, "cursor", "t") == [t]  # the time plots' cursor follows

    press(page, "Head h [m]", "ArrowRight", 1)  # a new run: the player stops and starts over
    page.wait_for_function(f"() => ({PLAYER})().t === 0", timeout=30_000)
    assert not page.evaluate(PLAYER)["playing"]
    assert page.problems == []


def test_a_preset_sets_the_design_and_says_what_to_look_at(page):
    page.locator("select").filter(has_text="Choose a preset").select_option("A stalled pump")
    page.get_by_text("At h = 21 m the stall margin is below 1").first.wait_for(timeout=30_000)
    page.get_by_text("Stalled at t =").first.wait_for(timeout=30_000)
    wait_for_readout(page, "mean_flow", flow_readout(SEED.replace(h=21.0)))
    assert page.problems == []


# Every legend the page draws, with its visible labels, its box and its figure's width [px]
# (Bokeh draws legends on the canvas: a label past the figure's edge is cut, "cycle mea").
LEGEND_BOXES = """() => {
  const found = []
  for (const model of Bokeh.documents[0].all_models) {
    if (model.type !== 'Legend' && model.constructor.__name__ !== 'Legend') continue
    const view = Bokeh.index.find_one(model)
    if (!view || !view.bbox) continue
    const labels = model.items.filter(item => item.visible).map(item => item.label.value)
    found.push({labels, x0: view.bbox.x0, x1: view.bbox.x1, width: view.parent.bbox.width})
  }
  return found
}"""


def test_with_a_pinned_run_every_legend_label_shows_in_full(browser, url):
    """A kick just above α₋ draws all six of the crank-speed view's items once a run is pinned:
    every legend lies within its figure at 1280 x 720."""
    page = open_page(browser, url, width=1280, height=720, query="?theta_dot0=1.5")
    try:
        page.get_by_role("button", name="Pin this run").click()
        page.wait_for_function(
            "() => Bokeh.documents[0].get_model_by_name('speed_ghost').data.t.length > 0",
            timeout=60_000,
        )
        for name in ("flow", "operating"):  # below the first screen
            show_view(page, name)
        page.wait_for_function(
            "() => Bokeh.documents[0].get_model_by_name('flow_ghost').data.t.length > 0",
            timeout=60_000,
        )  # the ghost of a run pinned before the view was built
        page.wait_for_timeout(500)  # the legend is laid out on the next frame
        legends = page.evaluate(LEGEND_BOXES)
        speed = [
            box
            for box in legends
            if "pinned run" in box["labels"] and "α₋, Eq. (21)" in box["labels"]
        ]
        assert len(speed) == 1 and len(speed[0]["labels"]) == 6
        assert len(legends) >= 3  # speed, flow, operating point (the waterfall needs none)
        for box in legends:
            assert box["x0"] >= 0 and box["x1"] <= box["width"], box
        assert page.problems == []
    finally:
        page.close()


@pytest.mark.parametrize(
    "query, shown",
    [
        ("?theta_dot0=0", "Never started."),  # no kick: an axis from 0, no range warnings
        ("?h=21", "Stalled at t ="),
        ("?L_over_R=1", "the rod cannot reach the crank"),
    ],
)
def test_corner_cases_open_cleanly(browser, url, query, shown):
    page = open_page(browser, url, query=query)
    try:
        page.get_by_text(shown).first.wait_for(timeout=30_000)
        start, end = page.evaluate(
            "() => { const r = window.Bokeh.documents[0].get_model_by_name('speed_range'); return [r.start, r.end] }"
        )
        assert start == 0.0 and end > 0
        assert page.problems == [] and page.elsewhere == []
    finally:
        page.close()


def test_cylinders_and_torque_at_rest_from_the_link_and_the_double_acting_box(browser, url):
    design = SEED.replace(cylinders=2, T_0=0.4)
    page = open_page(browser, url, query="?cylinders=2&T_0=0.4&theta_dot0=0")
    try:
        wait_for_readout(page, "mean_flow", flow_readout(design, theta_dot0=0.0))
        page.get_by_text("It starts on its own from any angle").first.wait_for(timeout=30_000)
        faces = "() => window.Bokeh.documents[0].get_model_by_name('closeup_faces').data.ys.length"
        show_view(page, "closeup")
        page.wait_for_function(f"{faces} === 2", timeout=60_000)  # each cylinder's pulses
        box = page.get_by_role("checkbox")  # the page's one check box
        assert box.count() == 1 and page.get_by_text("Double-acting pistons").count() == 1
        box.check(timeout=30_000)
        double = design.replace(double_acting=True)  # 4 faces: too heavy to start from rest
        page.get_by_text("cannot beat the load at θ₀").first.wait_for(timeout=60_000)
        wait_for_readout(page, "mean_flow", flow_readout(double, theta_dot0=0.0))
        page.wait_for_function(
            "() => new URLSearchParams(location.search).get('double_acting') === 'true'",
            timeout=30_000,
        )
        assert page.problems == []
    finally:
        page.close()


def test_the_machine_draws_every_cylinder_on_its_own_throw(browser, url):
    design = SEED.replace(cylinders=3, h=2.0)
    run = windpump.simulate(design, 600.0)
    page = open_page(browser, url, query="?cylinders=3&h=2")
    try:
        t = 123.4
        page.evaluate(
            f"() => {{ window.Bokeh.documents[0].get_model_by_name('scrubber').value = {t} }}"
        )
        page.wait_for_function(f"() => Math.abs(({PLAYER})().t - {t}) < 1e-9", timeout=30_000)
        xs, ys = model_data(page, "machine_links", "xs"), model_data(page, "machine_links", "ys")
        assert len(xs) == 4 + 2 * 3  # blades and mark, then a crank and a rod per cylinder
        theta = float(np.interp(t, run.t, run.theta))
        for k in range(3):
            (cx, pin_x), (cy, pin_y) = xs[4 + 2 * k], ys[4 + 2 * k]
            drawn = math.atan2(-(pin_x - cx), pin_y - cy)
            lag = theta - 2 * math.pi * k / 3  # cylinder k sees theta - 2 pi k / n
            assert abs(math.remainder(drawn - lag, 2 * math.pi)) < 0.01, k
            x = float(windpump.piston_position(drawn, design.R, design.L))
            assert ys[5 + 2 * k][1] == pytest.approx(design.L + design.R - x, abs=2e-6)
        assert page.problems == []
    finally:
        page.close()


def wind_day_litres(design, mean_wind, kick=3.0) -> str:
    record = gusty(mean_wind, 86_400.0, seed=1)
    run = windpump.simulate(design, 86_400.0, math.pi / 2, kick, wind=record, sample_dt=1.0)
    return f"{1e3 * run.volume[-1]:,.0f}"


def test_the_wind_tab_runs_the_linked_day_and_follows_its_sliders(browser, url):
    design = SEED.replace(T_0=0.3)
    page = open_page(browser, url, width=1280, height=720, query="?T_0=0.3&mean_wind=4")
    try:
        page.get_by_text("Wind", exact=True).first.click()
        wait_for_readout(page, "day_litres", wind_day_litres(design, 4.0))
        low, high = windpump.water_per_day(design, 4.0)
        shown = " · ".join(f"{float(f'{1e3 * b:.3g}'):,.0f}" for b in (low, high))
        assert text(page, "site_bounds") == shown  # 3 significant figures, each 100 L or more
        bands = "(n) => window.Bokeh.documents[0].get_model_by_name(n).data.t.length"
        assert 0 < page.evaluate(bands, "windtab_wind") <= 450
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "wind_1280x720.png"), full_page=True)

        press(page, "Site's mean wind [m/s]", "ArrowRight", 5)  # 4.0 -> 4.5
        page.wait_for_function(
            "() => new URLSearchParams(location.search).get('mean_wind') === '4.5'",
            timeout=60_000,
        )
        wait_for_readout(page, "day_litres", wind_day_litres(design, 4.5))
        assert page.problems == []
    finally:
        page.close()


def test_the_wind_tab_on_a_phone(browser, url):
    page = open_page(browser, url, width=390, height=844, query="?T_0=0.3")
    try:
        page.get_by_text("Wind", exact=True).first.click()
        page.wait_for_function(
            f"() => /^[0-9,]+$/.test(({DEEP_TEXT})('[data-name=day_litres]') || '')",
            timeout=120_000,
        )
        width = page.evaluate("() => document.documentElement.scrollWidth")
        assert width <= 390 + 1, "no sideways scrolling on a phone"
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "wind_390x844.png"), full_page=True)
        assert page.problems == []
    finally:
        page.close()


def open_wind_tab(page):
    page.get_by_text("Wind", exact=True).first.click()
    page.wait_for_function(
        f"() => /^[0-9,]+$/.test(({DEEP_TEXT})('[data-name=day_litres]') || '')",
        timeout=120_000,
    )
    upload = page.locator("input[type=file]").nth(1)
    # Focused, as a person's click or Tab focuses it: uploads.js guards a file input drawn
    # later on its focus (or on timers after the tab is chosen, which a file set at once can beat)
    upload.focus()
    return upload


def a_day_of_wind(name: str, step: float = 1.0) -> dict:
    rows = "".join(f"{t:.1f},{5 + math.sin(t / 900):.3f}\n" for t in np.arange(0, 86_401, step))
    return {"name": name, "mimeType": "text/csv", "buffer": ("t,V\n" + rows).encode()}


def test_a_measured_day_of_wind_is_uploaded_and_a_huge_file_refused(browser, url):
    """The file goes to the server by HTTP (app/server/upload_route.py), not over the websocket; of two
    chosen one after the other the later one is the day; an empty file and one over the limit
    are said, and the page keeps working."""
    page = open_page(browser, url)
    try:
        upload = open_wind_tab(page)
        day = a_day_of_wind("mast.csv")
        assert len(day["buffer"]) > 1_000_000  # over the lab file's limit, within the wind's
        upload.set_input_files(files=[day])
        page.get_by_text("the measured record mast.csv").first.wait_for(timeout=120_000)
        assert any("/app/upload?" in post for post in page.posts)
        assert max(page.sent) < 100_000  # its reference went over the websocket, not the file
        early, late = a_day_of_wind("early.csv"), a_day_of_wind("late.csv", step=2.0)
        upload.set_input_files(files=[early])
        upload.set_input_files(files=[late])  # while the early one is sent or read
        page.get_by_text("the measured record late.csv").first.wait_for(timeout=120_000)
        time.sleep(3.0)  # the early file's outcome, had it come later, would show by now
        assert page.get_by_text("the measured record early.csv").count() == 0
        empty = {"name": "empty.csv", "mimeType": "text/csv", "buffer": b""}
        upload.set_input_files(files=[empty])
        page.get_by_text("This wind file cannot be used: the file is empty").wait_for(
            timeout=60_000
        )
        huge = {"name": "huge.csv", "mimeType": "text/csv", "buffer": b"0,5\n" * 3_000_000}
        upload.set_input_files(files=[huge])
        page.get_by_text("it has 12,000,000 bytes").first.wait_for(timeout=60_000)
        press(page, "Head h [m]", "ArrowRight", 1)  # the session is alive and keeps its design
        wait_for_readout(page, "mean_flow", flow_readout(SEED.replace(h=3.1)))
        assert page.problems == []
    finally:
        page.close()


def test_without_the_upload_route_a_wind_file_goes_over_the_websocket(browser, url):
    """A server without the route (404: one older than it) still gets the file, Bokeh's way."""
    page = open_page(browser, url)
    try:
        page.route("**/app/upload?*", lambda route: route.fulfill(status=404, body="Not Found"))
        upload = open_wind_tab(page)
        upload.set_input_files(files=[a_day_of_wind("mast.csv", step=10.0)])
        page.get_by_text("the measured record mast.csv").first.wait_for(timeout=120_000)
        assert any("/app/upload?" in post for post in page.posts)  # tried first
        assert max(page.sent) > 100_000  # then sent whole over the websocket
        assert page.problems == [] or all("404" in p for p in page.problems), page.problems
    finally:
        page.close()


MAP_MARKER = """() => {
  const source = window.Bokeh.documents[0].get_model_by_name('maptab_here');
  return source && source.data.ratio.length ? [source.data.ratio[0], source.data.h[0]] : null;
}"""
# Where a sprocket ratio and head lie on the map's canvas [px], from its frame and ranges as
# drawn now (the frame narrows when the map's colour bar gets its labels)
MAP_POINT = """([ratio, h]) => {
  const figure = window.Bokeh.documents[0].get_model_by_name('map_figure');
  const frame = window.Bokeh.index.find_one(figure).frame.bbox;
  const x = figure.x_range, y = figure.y_range;
  return [frame.left + (ratio - x.start) / (x.end - x.start) * frame.width,
          frame.top + (y.end - h) / (y.end - y.start) * frame.height];
}"""
QUERY = "(name) => new URLSearchParams(location.search).get(name)"


def test_the_design_map_marks_the_linked_design_and_a_tap_moves_it(browser, url):
    page = open_page(browser, url, width=1280, height=720, query="?h=5")
    try:
        page.get_by_text("Design map", exact=True).first.click()
        page.wait_for_function(f"() => ({MAP_MARKER})() !== null", timeout=120_000)
        assert page.evaluate(MAP_MARKER) == [4.0, 5.0]
        # the map is worked out off the server's loop: its readout replaces "Mapping the
        # design…" with it, and the figure settles below the longer text before a tap
        page.get_by_text("the best sprocket ratio is").wait_for(timeout=60_000)
        image = page.evaluate(
            "() => window.Bokeh.documents[0].get_model_by_name('maptab_flow').data.image[0].length"
        )
        assert 0 < image <= 160 * 160  # no more cells than the figure has pixels
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / "design_map_1280x720.png"))
        canvases = [c for c in page.locator("canvas").all() if c.is_visible()]
        map_canvas = max(canvases, key=lambda c: c.bounding_box()["height"])
        box, deadline = None, time.monotonic() + 30
        while box != (box := map_canvas.bounding_box()) and time.monotonic() < deadline:
            page.wait_for_timeout(250)  # until the figure stops moving (the readout laid out)
        # R₁/R₀ = 6.0, the middle of its step (~8 px wide), and h = 19 m: a tap at a share of
        # the canvas fell ~1 px from the step of 5.1, whose design's R₁/R₀ is 5.1000000000000005
        x, y = page.evaluate(MAP_POINT, [6.0, 19.0])
        page.mouse.click(box["x"] + x, box["y"] + y)
        moved = (  # both in the link once moved (R_dagger may be absent while it is the default)
            f"() => ![null, '4.0'].includes(({QUERY})('R_dagger'))"
            f" && parseFloat(({QUERY})('h')) !== 5"
        )
        page.wait_for_function(moved, timeout=60_000)
        ratio, head = float(page.evaluate(QUERY, "R_dagger")), float(page.evaluate(QUERY, "h"))
        assert ratio == 6.0 and abs(head - 19.0) < 0.5  # a head step is ~1 px of the map
        # the mark is the core's design: its R₁/R₀ is R₁ / R₀, the slider's value to a few ulps
        page.wait_for_function(
            f"() => Math.abs(({MAP_MARKER})()[0] - {ratio}) < 1e-9", timeout=60_000
        )
        assert page.evaluate(MAP_MARKER) == [pytest.approx(ratio, rel=1e-12), head]
        # the sliders and the run followed: the main readout is this design's margin
        design = SEED.with_ratios(R_dagger=ratio, h=head)
        wait_for_readout(page, "margin", f"{windpump.stall_margin(design):.3f}")
        assert page.problems == []
    finally:
        page.close()


# The map's sources with anything selected in them (a tap's selection: see the test below)
MAP_SELECTED = """() => ['maptab_flow', 'maptab_contour_labels', 'maptab_stall', 'maptab_best',
  'maptab_here'].filter(name => {
  const s = window.Bokeh.documents[0].get_model_by_name(name).selected;
  return s.indices.length + s.line_indices.length + s.image_indices.length > 0;
})"""
MAP_BOX = """() => {
  const figure = window.Bokeh.documents[0].get_model_by_name('map_figure');
  const b = window.Bokeh.index.find_one(figure).el.getBoundingClientRect();
  return {x: b.x, y: b.y, width: b.width, height: b.height};
}"""


def test_a_tap_on_a_contour_label_leaves_every_label_as_it_was(browser, url):
    """Bokeh's tap tool selected the label tapped, and drew the others at a tenth of their
    alpha (near invisible) until the next selection: a tap moves the design and selects
    nothing on the map."""
    page = open_page(browser, url, width=1280, height=720, query="?tab=map&h=5")
    try:
        page.wait_for_function(f"() => ({MAP_MARKER})() !== null", timeout=120_000)
        map_settled(page)
        labels = page.evaluate(
            "() => { const d = window.Bokeh.documents[0].get_model_by_name("
            "'maptab_contour_labels').data; return [Array.from(d.x), Array.from(d.y)] }"
        )
        assert len(labels[0]) >= 3
        box = page.evaluate(MAP_BOX)
        x, y = page.evaluate(MAP_POINT, [labels[0][1], labels[1][1]])  # on a label's anchor
        page.mouse.click(box["x"] + x, box["y"] + y)
        moved = f"() => parseFloat(({QUERY})('h')) !== 5"
        page.wait_for_function(moved, timeout=60_000)
        assert page.evaluate(MAP_SELECTED) == []
        assert page.problems == []
    finally:
        page.close()


def map_settled(page) -> dict:
    """The Design map's canvas box once mapped and still (its readout laid out above it)."""
    page.get_by_text("the best sprocket ratio is").wait_for(timeout=60_000)
    canvases = [c for c in page.locator("canvas").all() if c.is_visible()]
    map_canvas = max(canvases, key=lambda c: c.bounding_box()["height"])
    box, deadline = None, time.monotonic() + 30
    while box != (box := map_canvas.bounding_box()) and time.monotonic() < deadline:
        page.wait_for_timeout(250)
    return box


def test_the_design_maps_hover_says_where_the_pump_stalls(browser, url):
    """Left of the red line the core's flow is NaN (the pump cannot run): the hover said
    "NaN m³/day" there; it says so in words, and the flow in m³/day right of the line."""
    from windpump_app.map_tab import STALLED

    page = open_page(browser, url, width=1280, height=720, query="?tab=map")
    try:
        page.wait_for_function(f"() => ({MAP_MARKER})() !== null", timeout=120_000)
        box = map_settled(page)
        for point, said in (([2.0, 20.0], STALLED), ([8.0, 5.0], None)):  # left, right of it
            x, y = page.evaluate(MAP_POINT, point)
            page.mouse.move(box["x"] + x, box["y"] + y)
            row = page.locator(".bk-tooltip-content").filter(visible=True).first
            row.wait_for(timeout=30_000)
            shown = row.inner_text()
            assert "NaN" not in shown, shown
            if said is not None:
                assert said in shown, shown
            else:
                assert re.search(r"flow:\s*\d+\.\d m³/day", shown) and STALLED not in shown, shown
            page.mouse.move(0, 0)  # off the map: the tooltip goes
        assert page.problems == []
    finally:
        page.close()
