"""Files chosen in the page: refused in the browser when too large, a wind or site file sent by
HTTP, each reported by the server.

Bokeh sends a chosen file whole over the page's websocket; over ~15 MB the connection closes and
the session (the design on the screen) is lost. ``uploads.js`` checks the file's size before
Bokeh reads it and tells the server through a hidden text input, which ``UploadChannel`` turns
into the size in bytes for the explorer to report in the core's words. A wind record or a site's
weather file (up to 10 MB, ~80 ms of the server's one event loop as a websocket message) the page
posts by HTTP instead (``upload_route``), and the same input carries its reference: its id, name
and size, or why it could not be sent. ``Reveal`` goes the other way: the server names an
upload's outcome and the page scrolls it into view.
"""

from __future__ import annotations

import base64
from pathlib import Path
from typing import Any

import panel as pn
from bokeh.document import Document
from bokeh.models import CustomJS

from windpump.model.wind import MAX_CSV_BYTES
from windpump.readers.labdata import MAX_BYTES

from .inputs import clipped
from .keyboard import LABEL_FOR_SCREEN_READERS_CSS
from .styles import TEXT

# A wind record is sent whole too: its limit stays below the ~15 MB that closes the connection.
WIND_MAX_BYTES = min(MAX_CSV_BYTES, 10_000_000)
WIND_CLASS = "wind-upload"
SITE_CLASS = "site-upload"  # the Site tab's weather file: the wind record's limit
WIND_SIZE = "a day at one sample a second is about 1.5 MB"  # the page's refusal: "(...)"
SITE_SIZE = "a year of hourly weather, a TMY3 or EPW file, is about 1.5 MB"
# The uploads sent by HTTP (upload_route), by the kind the page names: (the file, its refusal's words)
KINDS = {"wind": ("wind", WIND_SIZE), "site": ("weather", SITE_SIZE)}
SESSION_HEADER = "X-Windpump-Session"  # the page's session id: in a header, never in the URL

UPLOADS_JS = (Path(__file__).parent / "uploads.js").read_text(encoding="utf-8")
CHANNEL_CLASS = "upload-refused"

# Scrolls the element carrying the CSS class named in the channel's value into view, through
# Panel's shadow roots, once the server's changes (a message made visible) have been laid out.
REVEAL_JS = """
const target = cb_obj.value.split("\\t")[0]
const find = (root) => {
  const hit = root.querySelector("." + target)
  if (hit != null) return hit
  for (const el of root.querySelectorAll("*")) {
    if (el.shadowRoot) { const found = find(el.shadowRoot); if (found != null) return found }
  }
  return null
}
const reveal = () => {
  const el = target ? find(document) : null
  if (el != null && el.offsetParent !== null) el.scrollIntoView({block: "nearest"})
}
for (const delay of [50, 300, 1000]) setTimeout(reveal, delay)
"""


class UploadChannel(pn.widgets.TextInput):
    """Hidden; the page writes ``"<bytes>\\t<time>\\t<lab|wind|site>\\t<name>[\\t<state>]"``
    into it when it refuses a file (no state, or "refused"), or, for a wind or site file sent by
    HTTP (``upload_route``): "sending" as it starts, "posted <id>" once the server has it,
    "empty" for a file of no bytes (not sent), "failed <reason>" (``upload_route.REFUSALS``, or
    "network")."""

    def __init__(self, **params):
        super().__init__(visible=False, css_classes=[CHANNEL_CLASS], **params)

    @property
    def size(self) -> int | None:
        """The file's size [bytes], or None if the value is not one the page wrote."""
        head = self.value.split("\t", 1)[0]
        return int(head) if head.isdigit() else None

    @property
    def wind(self) -> bool:
        """Whether the file was a wind record (else a lab torque file or a site's weather)."""
        return self.kind == "wind"

    @property
    def kind(self) -> str:
        """Which upload the file was chosen in: "lab", "wind" or "site"."""
        fields = self.value.split("\t")
        return fields[2] if len(fields) > 2 and fields[2] in ("wind", "site") else "lab"

    @property
    def filename(self) -> str:
        """The file's name, as the page wrote it."""
        fields = self.value.split("\t")
        return fields[3] if len(fields) > 3 else ""

    @property
    def state(self) -> tuple[str, str]:
        """(what the page did, its detail): ("refused", ""), ("sending", ""), ("posted", id),
        ("empty", ""), ("failed", reason); a lab file's is always refused."""
        fields = self.value.split("\t")
        if self.kind == "lab" or len(fields) < 5 or not fields[4]:
            return "refused", ""
        state, _, detail = fields[4].partition(" ")
        return state, detail


RefusedUploads = UploadChannel  # its name before it carried more than refusals


def guard_uploads(
    document: Document, max_bytes: int = MAX_BYTES, route: dict[str, str] | None = None
) -> None:
    """Run ``uploads.js`` in the page once Bokeh has drawn it; ``route``: where the page posts
    a wind or site file, and its session's id (``upload_route.page_opened``; without it the file
    goes over the websocket, Bokeh's way)."""
    route = route or {"url": "", "session": ""}
    document.js_on_event(
        "document_ready",
        CustomJS(
            args=dict(
                max_bytes=max_bytes,
                wind_max_bytes=WIND_MAX_BYTES,
                wind_class=WIND_CLASS,
                site_class=SITE_CLASS,
                channel_class=CHANNEL_CLASS,
                upload_url=route["url"],
                session_id=route["session"],
                session_header=SESSION_HEADER,
            ),
            code=UPLOADS_JS,
        ),
    )


class Reveal(pn.widgets.TextInput):
    """Hidden; ``show(css_class)`` scrolls the page's element with that CSS class into view.

    An upload's outcome (the fit applied, a warning, a refusal) appears next to its upload
    control, which at 1280×720 lies below the sidebar's fold: without this nothing in view would
    change. The count in the value makes every outcome a change, the same message twice too.
    """

    def __init__(self, **params):
        super().__init__(visible=False, **params)
        self._count = 0
        self.jscallback(value=REVEAL_JS)

    def show(self, css_class: str) -> None:
        self._count += 1
        self.value = f"{css_class}\t{self._count}"


def refused_size(kind: str, size: int, what: str) -> str | None:
    """What to say when the page stopped a ``kind`` file ("wind", "weather") of ``size`` bytes
    before sending it; None for a size the page does not refuse (a tampered value)."""
    if size <= WIND_MAX_BYTES:
        return None
    return (
        f"This {kind} file cannot be used: it has {size:,} bytes; at most "
        f"{WIND_MAX_BYTES:,} are read ({what})."
    )


def sending_note(name: str, size: int) -> str:
    """What a tab says while the page sends the file ``name`` of ``size`` bytes by HTTP."""
    return f"Sending {clipped(name) or 'the file'} ({size / 1e6:.1f} MB)…"


class Encoded(str):
    """A chosen file's content as the browser sent it, in base64: ``decoded`` off the event loop."""


def decoded(data: bytes | Encoded) -> bytes:
    """An upload's bytes (``chosen``'s), decoded from the browser's base64 if they still are."""
    return base64.b64decode(data) if isinstance(data, Encoded) else data


class FileUpload(pn.widgets.FileInput):
    """Panel's FileInput, whose ``value`` keeps the browser's base64 (``Encoded``): Panel decodes
    it as the message arrives, on the event loop (~0.1-0.15 s of every page's loop for 10 MB,
    found by py-spy on the server); the work reading the file decodes it off the loop.

    ``title`` and ``what`` say what file it takes ("Lab data", "a CSV of ..."): ``heading`` shows
    them above it, and they are its name to a screen reader (its own label, for screen readers
    only: ``keyboard.LABEL_FOR_SCREEN_READERS_CSS``; Bokeh's file input has none)."""

    def __init__(self, title: str, what: str, **params):
        stylesheets = [*params.pop("stylesheets", []), LABEL_FOR_SCREEN_READERS_CSS]
        super().__init__(name=f"{title}: {what}", stylesheets=stylesheets, **params)
        self.heading = pn.pane.Markdown(f"**{title}**: {what}", stylesheets=TEXT)

    def _process_property_change(self, props: dict[str, Any]) -> dict[str, Any]:
        encoded = props.get("value")
        if not isinstance(encoded, str):
            return super()._process_property_change(props)
        params = super()._process_property_change({**props, "value": ""})
        params["value"] = Encoded(encoded) if encoded else None
        return params


def chosen(upload: pn.widgets.FileInput) -> bytes | Encoded | None:
    """The chosen file's content (``decoded`` gives its bytes), or None before one is chosen:
    Panel reports an empty file as None (the value it had), so only its name tells that one was
    chosen."""
    if upload.value is None and upload.filename:
        return b""
    return upload.value
