"""Keyboard and screen readers: tabs that switch with the keys, sliders named by their labels and
saying their values with units, check boxes named by their text, labels for screen readers only.

Bokeh 3.9's tab headers take the focus but ignore Enter and the arrow keys, its slider handles
carry no accessible name and say their value to one decimal without its unit, its check box's
text is not its label, and Panel's template puts the page's roots in a ``<ul>``: ``keyboard.js``
mends each for every widget of its kind, in the browser, once a page (WCAG 2.1 AA, checked by
axe-core in tests/browser/test_accessibility.py).
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


# A control's own <label> (Bokeh's, from the widget's title) for screen readers only, where the
# page shows what the control is in its own words beside it (an upload's heading, the Play
# button's row): named, and laid out as before.
LABEL_FOR_SCREEN_READERS_CSS = (
    "label[for=input] { position: absolute !important; width: 1px; height: 1px; margin: -1px; "
    "padding: 0; border: 0; overflow: hidden; clip-path: inset(50%); white-space: nowrap; }"
)

# A slider's unit (in its label's brackets, "Head h [m]") as a screen reader says its value
# ("3.1 metres"): the word for 1, and for any other value. A unit not here is said as written.
UNIT_WORDS = {
    "m": ("metre", "metres"),
    "mm": ("millimetre", "millimetres"),
    "m/s": ("metre a second", "metres a second"),
    "rad/s": ("radian a second", "radians a second"),
    "rad": ("radian", "radians"),
    "°": ("degree", "degrees"),
    "s": ("second", "seconds"),
    "N·m": ("newton metre", "newton metres"),
    "kg": ("kilogram", "kilograms"),
    "kg·m²": ("kilogram square metre", "kilogram square metres"),
    "m³": ("cubic metre", "cubic metres"),
    "m³/day": ("cubic metre a day", "cubic metres a day"),
    "L/day": ("litre a day", "litres a day"),
    "ft": ("foot", "feet"),
    "in": ("inch", "inches"),
    "mph": ("mile an hour", "miles an hour"),
    "gal/day": ("gallon a day", "gallons a day"),
}


def keyboard_and_screen_readers(document: Document) -> None:
    """Run ``keyboard.js`` in the page once Bokeh has drawn every root of ``document``."""
    words = {unit: list(pair) for unit, pair in UNIT_WORDS.items()}
    document.js_on_event("document_ready", CustomJS(args=dict(unit_words=words), code=KEYBOARD_JS))
