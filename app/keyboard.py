"""Keyboard and screen readers: tabs that switch with the keys, sliders named by their labels.

Bokeh 3.9's tab headers take the focus but ignore Enter and the arrow keys, and its slider handles
carry no accessible name; ``keyboard.js`` adds both in the browser, once a page.
"""

from __future__ import annotations

from pathlib import Path

from bokeh.document import Document
from bokeh.models import CustomJS

KEYBOARD_JS = (Path(__file__).parent / "keyboard.js").read_text(encoding="utf-8")
# Visible focus: around a control holding it, and on a tab header (Bokeh draws neither).
FOCUS_CSS = (
    ":host(:focus-within) { outline: 3px solid #f0ad4e; outline-offset: 2px; border-radius: 4px; }"
)
TAB_FOCUS_CSS = ".bk-tab:focus-visible { outline: 3px solid #f0ad4e; outline-offset: -3px; }"
# The template's own controls, outside any shadow root; its sidebar toggle, which Bootstrap marks
# with a faint shadow only, by id to outrank Bootstrap's rule.
PAGE_FOCUS_CSS = (
    ":focus-visible, #sidebar-toggle:focus-visible "
    "{ outline: 3px solid #f0ad4e; outline-offset: 2px; }"
)


def keyboard_and_screen_readers(document: Document) -> None:
    """Run ``keyboard.js`` in the page once Bokeh has drawn every root of ``document``."""
    document.js_on_event("document_ready", CustomJS(code=KEYBOARD_JS))
