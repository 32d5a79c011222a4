"""The explorer as a student meets it: `panel serve app/` in Debian's chromium, driven by playwright."""

from __future__ import annotations

import math
import os
from pathlib import Path

import pytest

import windpump

from served import CHROMIUM, CHROMIUM_FLAGS, DEEP_TEXT, require_chromium, served_app

pytestmark = pytest.mark.browser

ARTIFACTS = Path(
    os.environ.get("WINDPUMP_ARTIFACTS", Path(__file__).resolve().parents[1] / "artifacts")
)
MAIN_SLIDERS = [
    "L/R, rod / crank",
    "R₁/R₀, sprocket ratio",
    "Head h [m]",
    "Windmill torque Tₘ [N·m]",
]
SPEED_DATA = "() => Array.from(window.Bokeh.documents[0].get_model_by_name('speed').data.upper)"


@pytest.fixture(scope="module")
def url():
    require_chromium()
    with served_app() as (address, _process):
        yield address


@pytest.fixture(scope="module")
def browser():
    require_chromium()
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        chromium = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_FLAGS)
        yield chromium
        chromium.close()


@pytest.fixture
def page(browser, url):
    page = browser.new_page(viewport={"width": 1400, "height": 1000})
    problems = []
    page.on("console", lambda m: problems.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda error: problems.append(str(error)))
    page.goto(url)
    page.wait_for_function(f"() => ({DEEP_TEXT})('[data-name=mean_flow]') !== null", timeout=60_000)
    page.problems = problems
    yield page
    page.close()


def handle(page, label):
    title = page.locator(".bk-slider-title", has_text=label)
    return page.locator(".bk-input-group", has=title).locator(".noUi-handle")


def text(page, name):
    return page.evaluate(DEEP_TEXT, f"[data-name={name}]")


def wait_for_change(page, name, before):
    page.wait_for_function(
        f"(b) => ({DEEP_TEXT})('[data-name={name}]') !== b", arg=before, timeout=30_000
    )
    return text(page, name)


def test_a_keyboard_move_redraws_what_the_core_computes(page):
    assert page.problems == []
    for label in MAIN_SLIDERS:
        assert page.locator(".bk-slider-title", has_text=label).count() == 1, label
    assert "Running" in page.get_by_text("Running.").first.inner_text()
    flow_before, speed_before = text(page, "mean_flow"), page.evaluate(SPEED_DATA)

    head = handle(page, "Head h [m]")
    head.focus()
    for _ in range(5):
        page.keyboard.press("ArrowRight")
    page.locator(".bk-slider-title", has_text="Head h [m]: 3.5").wait_for(timeout=30_000)
    seen = windpump.explore(windpump.Design.seed_example().replace(h=3.5), 600.0, math.pi / 2, 3.0)
    expected = f"{1e3 * seen.mean_flow:.4f} L/s"
    page.wait_for_function(
        f"(e) => ({DEEP_TEXT})('[data-name=mean_flow]') === e", arg=expected, timeout=30_000
    )
    assert text(page, "mean_flow") != flow_before
    speed_after = page.evaluate(SPEED_DATA)
    assert speed_after != speed_before
    assert max(speed_after) == pytest.approx(seen.run.theta_dot.max(), rel=1e-9)

    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(ARTIFACTS / "explorer.png"))
    assert page.problems == []


def test_a_rejected_value_is_shown_and_the_next_move_recovers(page):
    rod = handle(page, "L/R, rod / crank")
    rod.focus()
    page.keyboard.press("Home")  # L/R = 1: the rod cannot reach the crank
    page.get_by_text("the rod cannot reach the crank").first.wait_for(timeout=30_000)
    assert page.get_by_text("L/R, rod / crank = 1 cannot be run").first.is_visible()
    page.keyboard.press("ArrowRight")  # L/R = 1.05: a valid, very short rod
    page.get_by_text("the rod cannot reach the crank").first.wait_for(
        state="hidden", timeout=30_000
    )
    assert "Running" in page.get_by_text("Running.").first.inner_text()
    assert page.problems == []


def model_data(page, name, column):
    return page.evaluate(
        f"() => Array.from(window.Bokeh.documents[0].get_model_by_name('{name}').data.{column})"
    )


def press(page, label, key, times):
    handle(page, label).focus()
    for _ in range(times):
        page.keyboard.press(key)


def test_the_energy_view_is_on_the_main_page(page):
    run = windpump.simulate(windpump.Design.seed_example(), 600.0)
    work = windpump.power_budget(run.design, run).shaft_work[-1]
    assert f"{work:,.0f} J = " in text(page, "energy")
    shaft = model_data(page, "power_split", "shaft")
    assert 0 < len(shaft) and max(shaft) > 0
    assert page.problems == []


def test_the_mechanisms_tab_draws_what_the_loops_close_to(page):
    page.get_by_text("Mechanisms", exact=True).first.click()
    page.locator(".bk-slider-title", has_text="Crank angle θ [°]").wait_for(timeout=30_000)
    assert text(page, "slider_crank").startswith("x = 45.43 mm from TDC")
    crank_before = model_data(page, "crank_links", "xs")

    press(page, "Crank angle θ [°]", "ArrowRight", 5)  # 90° -> 95°
    theta = math.radians(95.0)
    design = windpump.Design.seed_example()
    x = float(windpump.piston_position(theta, design.R, design.L))
    theta_c = math.degrees(float(windpump.rod_angle(theta, design.L_over_R)))
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
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(ARTIFACTS / "mechanisms.png"))
    assert page.problems == []
