"""The page around the explorer: Panel's Bootstrap template, its header and its narrow layout."""

from __future__ import annotations

import panel as pn

from .keyboard import PAGE_FOCUS_CSS
from .styles import px, zoom_css


def page(
    sidebar, main, dark: bool, presentation: bool, above_sidebar=None
) -> pn.template.BootstrapTemplate:
    """The page in Panel's Bootstrap template: ``sidebar`` beside ``main``, in the ``dark`` theme
    or not, its HTML zoomed for ``presentation`` mode (``styles.zoom_css``); ``above_sidebar``
    (a notice for a phone, ``PHONE_ONLY``) at the sidebar's top."""
    template = pn.template.BootstrapTemplate(
        title="Wind pump explorer",
        header=[
            pn.pane.HTML(
                "M. Louge, <i>A simple wind-pump analysis</i> (2010)", stylesheets=CITATION_CSS
            )
        ],
        sidebar=[sidebar] if above_sidebar is None else [above_sidebar, sidebar],
        main=[main],
        sidebar_width=330,
        header_background="#0b4f8a",
        theme="dark" if dark else "default",
        meta_viewport="width=device-width, initial-scale=1",
        # Panel's busy spinner follows the whole server's activity, so every other student's
        # move made it spin on this page and sent it a message: a class of 30 loading at once
        # kept 30 spinners turning and the server messaging every page for everyone's work.
        busy_indicator=None,
    )
    template.config.raw_css.extend([NARROW_CSS, PAGE_FOCUS_CSS, zoom_css(presentation)])
    return template


# The paper beside the title, left out on a phone (the header keeps one line there).
CITATION_CSS = [
    f":host {{ color: white; font-size: {px(18)}; align-self: center; margin-left: 1em; }}",
    "@media (max-width: 700px) { :host { display: none !important; } }",
]

# A component's stylesheet: shown on a phone only (where the sidebar comes first), or beside it only.
PHONE_ONLY = "@media (min-width: 701px) { :host { display: none !important; } }"
WIDE_ONLY = "@media (max-width: 700px) { :host { display: none !important; } }"

# Below 700 px the sidebar stacks above the views and the page scrolls as one column.
NARROW_CSS = """
#header .title { white-space: normal; }
@media (max-width: 700px) {
  #header .title { font-size: 1.05rem; }
  #content { flex-direction: column; flex-wrap: nowrap; overflow-y: auto !important; }
  #content > #sidebar { max-width: 100% !important; width: 100% !important; }  /* outranks the template's */
  #sidebar, #sidebar > * { max-height: none !important; height: auto !important; overflow: visible !important; }  /* no scroll of its own */
  #main { max-height: none !important; overflow: visible !important; width: 100%; }
}
"""
