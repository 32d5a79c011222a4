"""Text sizes of the page's HTML, in one place, scaled by presentation mode.

Every Panel and Bokeh component draws in its own shadow root, so a page-wide stylesheet cannot
reach its text; a CSS custom property can (it inherits through shadow roots). Each component's
sizes are ``calc(N px * var(--windpump-zoom))``, and presentation mode sets that one property on
the page: the sidebar, captions, notes, status and notices grow together, in one change made in the
browser. (The figures draw their text on a canvas: ``figures.present`` sizes it on the server.)
"""

from __future__ import annotations

import re

PRESENTATION_ZOOM = 1.25
ZOOM_VARIABLE = "--windpump-zoom"


def px(size: float) -> str:
    """A CSS length of ``size`` pixels, scaled in presentation mode."""
    return f"calc({size:g}px * var({ZOOM_VARIABLE}, 1))"


TEXT = [
    f":host {{ font-size: {px(16)}; }}",
    # a long title wraps (Bokeh keeps it on one line, and its value went past the sidebar's edge)
    f".bk-slider-title {{ font-size: {px(15)}; white-space: normal; }}",
    f".bk-btn, .bk-input, select, input {{ font-size: {px(15)}; }}",
]
# An alert on a phone: smaller and tighter, so that a notice, the readouts and the status under
# them fit the tabs' pane together (page.NARROW_CSS).
PHONE_ALERT = (  # the alert is the host (Bootstrap's padding on it outranks a :host rule)
    "@media (max-width: 700px) { :host { font-size: 14px; line-height: 1.3; padding: 4px 10px !important; "
    "margin: 2px 4px !important; } }"
)
COMPACT = [
    f":host {{ font-size: {px(16)}; }}",
    ".alert { padding: 6px 14px; margin: 4px 0; }",
    "p { margin: 0; }",
    PHONE_ALERT,
]
# The link's notices above the readouts: on a phone their list scrolls within two whole lines,
# so that the status under the readouts stays in view, and says so: the title says how many
# notices to scroll through (link.notices_text's "scroll-hint", shown on a phone only), and the
# scroll bar is styled where the browser draws one (a phone's overlay bar shows only in a scroll).
NOTICE = [
    *TEXT,
    PHONE_ALERT,
    ".scroll-hint { display: none; }",
    "@media (max-width: 700px) { p { margin: 0 0 2px; } "
    ".scroll-hint { display: inline; white-space: nowrap; } "
    "ul { margin: 0; padding-left: 1.2em; line-height: 1.5; max-height: 3em; overflow-y: scroll; } "
    "ul::-webkit-scrollbar { width: 6px; } "
    "ul::-webkit-scrollbar-thumb { background: currentColor; border-radius: 3px; } }",
]
CAPTION_CSS = [f":host {{ font-size: {px(15)}; margin: 0 8px; }} p {{ margin: 2px 0; }}"]


def zoom_css(presentation: bool) -> str:
    """The page's starting zoom (a page opened with ?presentation=true starts enlarged); a phone
    keeps its usual sizes (presentation mode is for a projector, and a phone has no room)."""
    return (
        f":root {{ {ZOOM_VARIABLE}: {PRESENTATION_ZOOM if presentation else 1}; }}\n"
        f"@media (max-width: 700px) {{ :root {{ {ZOOM_VARIABLE}: 1 !important; }} }}"
    )


# The presentation toggle's value, in the browser, sets the zoom: it runs for a click and for a
# change sent by the server alike (the model's ``active`` property changes either way).
ZOOM_JS = f"""
document.documentElement.style.setProperty(
  '{ZOOM_VARIABLE}', cb_obj.active ? '{PRESENTATION_ZOOM}' : '1')
"""


# A number and its unit, on one line: a span that does not wrap (the text a reader or a test sees
# keeps its ordinary space). Units the page writes after a number; the longest first.
UNITS = "m³/day|L/day|rad/s|L/s|m/s|N·m|N m|kg|mm|J|W|s|L|m|%|°"
NUMBER_AND_UNIT = re.compile(rf"(?<![\w.,])([−-]?\d[\d,]*(?:\.\d+)?) ({UNITS})(?![\w/³²·])")
NOWRAP = '<span style="white-space: nowrap">'
# A short symbol equal to a bare number ("T₀ = 0"), on one line too ("T₀" and "= 0)" once parted)
SYMBOL_IS_NUMBER = re.compile(r"(?<![^\s(])([^\s(<>]{1,4}) = ([−-]?\d[\d,]*(?:\.\d+)?)(?![\d<])")


def keep_units(text: str) -> str:
    """``text`` (Markdown or HTML) with each number and its unit kept on one line, and each
    short symbol equal to a bare number.

    >>> keep_units("at 1.00 N·m, 5 %")
    'at <span style="white-space: nowrap">1.00 N·m</span>, <span style="white-space: nowrap">5 %</span>'
    >>> keep_units("(no torque at rest, T₀ = 0).")
    '(no torque at rest, <span style="white-space: nowrap">T₀ = 0</span>).'
    """
    text = NUMBER_AND_UNIT.sub(rf"{NOWRAP}\1 \2</span>", text)
    return SYMBOL_IS_NUMBER.sub(rf"{NOWRAP}\1 = \2</span>", text)


def keep_terms(value: str) -> str:
    """A readout's ``value`` with each of its terms on one line, the lines breaking only between
    them: at " = ", " + ", " · " or ", " outside parentheses ("13,526 J = 265 J + 3,925 J",
    "2.2 · never (T₀ = 0)").

    >>> keep_terms("2.2 · never (T₀ = 0)")
    '<span style="white-space: nowrap">2.2</span> · <span style="white-space: nowrap">never (T₀ = 0)</span>'
    """
    parts, depth, start, i = [], 0, 0, 0
    while i < len(value):
        char = value[i]
        depth += (char == "(") - (char == ")")
        separator = re.match(r" [=+·] |, ", value[i:]) if depth == 0 else None
        if separator:
            parts += [value[start:i], separator.group()]
            i = start = i + len(separator.group())
            continue
        i += 1
    parts.append(value[start:])
    return "".join(
        part if k % 2 else f"{NOWRAP}{part}</span>" for k, part in enumerate(parts) if part or k % 2
    )
