"""The windmill's choice in Debian's chromium: a student chooses the multiblade wheel, sees its
C_Q and C_P against the tip-speed ratio and the wheel's readouts, on a projector and a phone."""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_browser import ARTIFACTS, model_data, open_page, text, wait_for_readout

import windpump
from windpump.catalogue import aermotor_702

from served import show_view

pytestmark = pytest.mark.browser

SEED = windpump.Design.seed_example()
# The page's windmill select, found by its option (Panel's label is not the select's <label>)
WINDMILL = "select:has(option:text-is('A multiblade wheel'))"
# Each of these boxes of the page, in its coordinates, through open shadow roots: where the
# operating view's figure is, and the readouts (nothing overlapping, nothing cut at the right)
BOXES = """() => {
  const found = {readouts: [], figure: null, width: window.innerWidth};
  const walk = (root) => {
    for (const el of root.querySelectorAll('*')) {
      if (el.shadowRoot) walk(el.shadowRoot);
      if (el.classList && el.classList.contains('readout')) {
        const b = el.getBoundingClientRect();
        if (b.width > 0) found.readouts.push([b.left, b.top, b.right, b.bottom]);
      }
    }
  };
  walk(document);
  return found;
}"""


def overlapping(boxes) -> list:
    return [
        (a, b)
        for i, a in enumerate(boxes)
        for b in boxes[i + 1 :]
        if a[0] < b[2] - 1 and b[0] < a[2] - 1 and a[1] < b[3] - 1 and b[1] < a[3] - 1
    ]


@pytest.mark.parametrize("width, height", [(1280, 720), (390, 844)])
def test_choosing_the_wheel_shows_its_coefficients_and_readouts(browser, url, width, height):
    page = open_page(browser, url, width, height)
    try:
        page.locator(WINDMILL).select_option(label="A multiblade wheel")
        # the wheel of 2.4 m on the paper's pump, at 5 m/s: the core's readouts
        design = windpump.Design.from_rotor(
            windpump.Rotor.multiblade(2.4), V_ref=SEED.V_ref, **SEED.geometry()
        )
        seen = windpump.explore(design, 600.0, math.pi / 2, 3.0)
        op = seen.operating_point
        tsr = op.omega * 1.2 / SEED.V_ref
        wait_for_readout(page, "tsr", f"{tsr:.2f}")
        assert text(page, "strokes") == f"{op.crank_speed * 60 / (2 * math.pi):.1f} /min"
        assert text(page, "cp") == f"{tsr * float(design.rotor.cq(tsr)):.3f}"
        assert text(page, "mean_flow") == f"{1e3 * seen.mean_flow:.4f} L/s"
        show_view(page, "operating")
        page.wait_for_function(
            "() => Bokeh.documents[0].get_model_by_name('coefficients').data.tsr.length > 0",
            timeout=60_000,
        )
        drawn = np.asarray(model_data(page, "coefficients", "tsr"))
        np.testing.assert_allclose(
            model_data(page, "coefficients", "cq"), design.rotor.cq(drawn), rtol=1e-12
        )
        assert model_data(page, "running", "tsr") == pytest.approx([tsr], rel=1e-12)
        page.locator("[data-name=tsr]").scroll_into_view_if_needed()
        boxes = page.evaluate(BOXES)
        assert overlapping(boxes["readouts"]) == [], boxes
        assert all(box[2] <= boxes["width"] + 1 for box in boxes["readouts"]), boxes
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(ARTIFACTS / f"wheel-readouts-{width}x{height}.png"))
        show_view(page, "operating")
        page.evaluate(
            "() => Bokeh.index.find_one(Bokeh.documents[0].get_model_by_name("
            "'operating_figure')).el.scrollIntoView({block: 'center'})"
        )
        page.wait_for_timeout(1000)
        page.screenshot(path=str(ARTIFACTS / f"wheel-view-{width}x{height}.png"))
        # the Aermotor: its sizes' selects in the sidebar, its readouts the catalogue mill's
        page.locator(WINDMILL).select_option(label="An Aermotor 702")
        mill = aermotor_702(8, 1.875, lift_ft=0.0, V_ref=SEED.V_ref, L_over_R=SEED.L_over_R)
        op = windpump.explore(mill.replace(h=SEED.h), 600.0, math.pi / 2, 3.0).operating_point
        wait_for_readout(page, "strokes", f"{op.crank_speed * 60 / (2 * math.pi):.1f} /min")
        page.locator("select:has(option:text-is('1 7/8'))").scroll_into_view_if_needed()
        page.screenshot(path=str(ARTIFACTS / f"aermotor-sidebar-{width}x{height}.png"))
        assert page.problems == []
    finally:
        page.close()
