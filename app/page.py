"""The page around the explorer: Panel's Bootstrap template, its header and its narrow layout."""

from __future__ import annotations

import panel as pn

from .keyboard import PAGE_FOCUS_CSS
from .styles import px, zoom_css


def page(
    sidebar, main, dark: bool, presentation: bool, embed: bool = False
) -> pn.template.BootstrapTemplate:
    """The page in Panel's Bootstrap template: ``sidebar`` beside ``main``, in the ``dark`` theme
    or not, its HTML zoomed for ``presentation`` mode (``styles.zoom_css``); ``embed``: for an
    iframe in a course page, without the header (``EMBED_CSS``)."""
    citation = "M. Louge, <i>A simple wind-pump analysis</i> (2010)"
    template = pn.template.BootstrapTemplate(
        title="Wind pump explorer",
        header=[] if embed else [pn.pane.HTML(citation, stylesheets=CITATION_CSS)],
        sidebar=[sidebar],
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
    if embed:
        template.config.raw_css.append(EMBED_CSS)
    return template


# The paper beside the title, left out on a phone (the header keeps one line there).
CITATION_CSS = [
    f":host {{ color: white; font-size: {px(18)}; align-self: center; margin-left: 1em; }}",
    "@media (max-width: 700px) { :host { display: none !important; } }",
]

# Below 700 px (a phone held upright) the screen splits: the tabs, whose readouts answer every
# move, above; the controls below, in a pane of their own that scrolls, in reach of a thumb and
# hidden by the header's toggle. A student who moves a slider sees the readouts change without
# scrolling (the sidebar once stacked ~900 px of controls above the readouts). The controls' pane
# is a fifth of the screen (158 px at 390×844: the preset menu and a slider), so that the first
# screen holds the readouts, the status and the crank speed's whole chart above it, its plot as
# high as elsewhere (at 0.42 the chart's lower half was under the controls; tests/browser/test_layout.py).
CONTROLS_SHARE = 0.2  # of the screen below the header: the controls' pane on a phone
PANE_PADDING = (4, 12)  # [px] the tabs' pane's padding on a phone, above and below its content
HEADER_AT_MOST = 70  # [px] a phone's header, one line (~54 px; tests/browser/test_layout.py)
NARROW_CSS = f"""
#header .title {{ white-space: normal; }}
@media (max-width: 700px) {{
  #header .title {{ font-size: 1.05rem; }}
  #content {{ flex-direction: column; flex-wrap: nowrap; overflow: hidden !important; }}
  #content > #main {{
    order: -1; flex: 1 1 0; min-height: 0; max-height: none !important; width: 100%;
    overflow-y: auto !important; overflow-x: hidden !important;
    padding: {PANE_PADDING[0]}px 6px {PANE_PADDING[1]}px 4px;
  }}
  #content > #sidebar {{  /* outranks the template's width */
    order: 1; flex: 0 0 auto; height: {CONTROLS_SHARE:.0%} !important; max-width: 100% !important;
    width: 100% !important; overflow-y: auto !important; overflow-x: hidden !important;
    padding-top: 4px !important; border-right: none; border-top: 1px solid var(--bs-border-color);
    box-shadow: 0 -4px 8px rgba(0, 0, 0, 0.15);
  }}
  #content > #sidebar.collapsing {{ height: 0 !important; width: 100% !important; }}
}}
"""

# ?embed=true: the page in a course page's iframe (docs/instructors.rst). The template's header
# (its title, the paper, the sidebar's toggle) is not shown, and the sidebar has no toggle to
# fold it: the controls stay beside the tabs, or below them in a pane of their own on a narrow
# frame (NARROW_CSS), always in reach. The course page around it names the explorer.
EMBED_CSS = """
#header { display: none !important; }
#content > #sidebar { box-shadow: none; }
"""


def pane_height_css() -> str:
    """The height of what the tabs' pane shows on a phone (below 700 px), its padding taken off,
    as a CSS length: at least this (the header is ``HEADER_AT_MOST`` at most). A figure this
    high, or lower, fits the pane whole (390×844: ~616 px of the pane's 632)."""
    return f"calc((100vh - {HEADER_AT_MOST}px) * {1 - CONTROLS_SHARE:g} - {sum(PANE_PADDING)}px)"
