"""The pump's views built when the page first shows them: placeholders and the page's report.

A page's seven views are ~450 Bokeh models, most of the server's work for a page; the first screen
holds two of them (the crank speed and the machine at 1280×720, none on a phone until it
scrolls past the sidebar). Each view stands on the page as a placeholder of its own height
until ``viewport.js``, in the page, sees it come within ``MARGIN`` of a screen of the browser's
viewport and writes the names of the views seen so far into a hidden text input
(``ViewsSeen``); the server then builds those views (``Explorer.see_views``).
"""

from __future__ import annotations

from pathlib import Path

import panel as pn
from bokeh.document import Document
from bokeh.models import CustomJS

from .styles import px

VIEWPORT_JS = (Path(__file__).parent / "viewport.js").read_text(encoding="utf-8")
CHANNEL_CLASS = "views-seen"
PLACEHOLDER_CLASS = "view-placeholder"  # and view-<name>, which names the view it stands for
MARGIN = 0.0  # [screens] a view this close below (or above) the viewport is built already

# The placeholder's box, then the view's caption as its own pane (styles.CAPTION_CSS) sets it.
# Without a fill: Bootstrap's own ".placeholder" (a block of the text's colour, a "wait" cursor)
# reaches a pane the page adds later (the Site tab's), which showed a dark block, its words hidden.
PLACEHOLDER_CSS = [
    f""":host {{ font-size: {px(16)}; }}
.placeholder {{ box-sizing: border-box; display: flex; align-items: center;
  justify-content: center; border: 1px dashed rgba(128, 128, 128, 0.5); border-radius: 4px;
  color: inherit; opacity: 0.7; background-color: transparent; cursor: auto; }}
.caption {{ font-size: {px(15)}; margin: 0 8px; }}
.caption p {{ margin: 2px 0; }}"""
]


class ViewsSeen(pn.widgets.TextInput):
    """Hidden; the page writes the names of the views it has seen, space-separated, here."""

    def __init__(self, **params):
        super().__init__(visible=False, css_classes=[CHANNEL_CLASS], **params)

    def names(self, known: tuple[str, ...]) -> list[str]:
        """The views named in the value, in ``known``'s order; anything else (tampered) left out."""
        said = set(self.value.split())
        return [name for name in known if name in said]


def placeholder_html(title: str, caption: str, height: int, aspect: float | None = None) -> str:
    """A placeholder's box saying what comes (``height`` [px] high, or of width / height
    ``aspect`` with ``height`` [px] of controls under it), and the view's caption under it."""
    box = (
        f"height: {height}px;"
        if aspect is None
        else f"aspect-ratio: {aspect}; max-width: 900px; margin-bottom: {height}px;"
    )
    return (
        f'<div class="placeholder" style="{box}">Drawing {title}…</div>'
        f'<div class="caption"><p>{caption}</p></div>'
    )


def placeholder(name: str, html: str, **options) -> pn.pane.HTML:
    """What stands for view ``name`` until it is built (``placeholder_html``): one pane, the
    page's layout as it will be once the view is drawn."""
    return pn.pane.HTML(
        html,
        sizing_mode="stretch_width",
        margin=0,
        css_classes=[PLACEHOLDER_CLASS, f"view-{name}"],
        stylesheets=PLACEHOLDER_CSS,
        **options,
    )


def report_views_seen(document: Document, names: tuple[str, ...]) -> None:
    """Run ``viewport.js`` in the page once Bokeh has drawn it."""
    document.js_on_event(
        "document_ready",
        CustomJS(
            args=dict(
                channel_class=CHANNEL_CLASS,
                placeholder_class=PLACEHOLDER_CLASS,
                margin=MARGIN,
                names=list(names),
            ),
            code=VIEWPORT_JS,
        ),
    )
