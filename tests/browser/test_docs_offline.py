"""The built documentation in chromium with no network: its equations are typeset by the site's
own MathJax, not left as raw LaTeX (issue 40). Skipped when the site is not built (CI builds it
before the tests: ``python -m sphinx -b html docs docs/_build/html``)."""

from __future__ import annotations

from pathlib import Path

import pytest
from test_browser import ARTIFACTS

pytestmark = pytest.mark.browser

BUILT = Path(__file__).resolve().parents[2] / "docs" / "_build" / "html"

# The page's equations once MathJax has typeset them: how many, and how many are left as LaTeX.
TYPESET = """async () => {
  await MathJax.startup.promise;
  const math = [...document.querySelectorAll('.math')];
  return [math.length, math.filter(e => e.querySelector('mjx-container') === null).length];
}"""


def test_the_model_pages_equations_render_offline(browser):
    page_file = BUILT / "model.html"
    if not page_file.is_file():
        pytest.skip("the site is not built (python -m sphinx -b html docs docs/_build/html)")
    context = browser.new_context(offline=True, viewport={"width": 1280, "height": 900})
    page = context.new_page()
    asked: list[str] = []
    page.on("request", lambda r: asked.append(r.url) if not r.url.startswith("file:") else None)
    failed: list[str] = []
    page.on("requestfailed", lambda r: failed.append(r.url))
    page.goto(page_file.as_uri())
    page.wait_for_function("() => window.MathJax && MathJax.startup", timeout=30_000)
    equations, raw = page.evaluate(TYPESET)
    assert equations >= 3 and raw == 0
    # CommonHTML draws with MathJax's own web fonts: loaded from the copy, none missing
    page.wait_for_function("() => document.fonts.status === 'loaded'", timeout=30_000)
    assert page.evaluate("() => [...document.fonts].some(f => f.family.startsWith('MJXTEX'))")
    assert asked == [] and failed == []
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    page.locator("mjx-container").first.scroll_into_view_if_needed()
    page.screenshot(path=str(ARTIFACTS / "docs_model_offline.png"))
    context.close()
