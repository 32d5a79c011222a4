"""A pane's text as a person reads it in the page: its Markdown or HTML rendered as the browser
gets it, tags left out, character references read, blanks collapsed (the app writes text from a
link or a file as references: ``windpump_app.escape``)."""

from __future__ import annotations

import html
import re
from html.parser import HTMLParser

import panel as pn


def rendered(pane) -> str:
    """The HTML the browser puts in the page for a Markdown (Alert too) or HTML pane."""
    if isinstance(pane, pn.pane.Markdown):
        return html.unescape(pane._transform_object(pane.object)["object"])
    return str(pane.object or "")


class Text(HTMLParser):
    """An HTML fragment's text."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.parts: list[str] = []

    def handle_data(self, data):
        self.parts.append(data)


def collapsed(text: str) -> str:
    """``text`` with HTML's blanks collapsed, as a browser shows it."""
    return re.sub(r"[ \t\n\r\f]+", " ", text).strip(" ")


def shown(pane) -> str:
    """``pane``'s text as the page shows it."""
    text = Text()
    text.feed(rendered(pane))
    text.close()
    return collapsed("".join(text.parts))
