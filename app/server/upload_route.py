"""A wind record or a site's weather file sent by HTTP, not over the page's websocket.

Bokeh sends a FileInput's file whole, as one base64 JSON message on the page's websocket (~13 MB
for a 10 MB file); reading that message and setting the property holds the server's one event loop
~80 ms, and every other page's moves wait for it. The page (``uploads.js``) posts the file's bytes
to ``<app>/upload`` instead (``UploadHandler``): Tornado reads the body in 64 KB pieces between
the other pages' messages. Only a short reference (an id, the name, the size) then goes over the
websocket, through the page's upload channel (``uploads.UploadChannel``); the session takes the
bytes (``UPLOADS.take``) and reads them as it read a FileInput's value (off the loop, in the
file-reading process).

The store is small and bounded (``Uploads``), and shared fairly: bytes only for a session of
this server whose page is connected (its websocket open: a bare GET of the page builds a session
too, and posts nothing), each session's share its newest file of each upload (a later one
replaces one not yet taken, and a post counts from its first byte: ``Uploads.receiving``), gone
once taken, after ``LIFETIME`` s, or when the page's websocket closes. The store's own bounds are a last resort: a file within a connected page's share is
always taken, the oldest file other pages left untaken dropped for it. The session's id, the
post's credential, goes in a header (``SESSION_HEADER``), not in the URL a log would keep.
``serve_uploads`` adds the route when ``panel serve app/`` starts (``hooks.on_server_loaded``);
a server without it (``panel serve app/main.py``, a notebook) leaves the page on Bokeh's
websocket path.
"""

from __future__ import annotations

import dataclasses
import logging
import re
import secrets
import threading
import time
from collections.abc import Callable
from functools import partial

from tornado import web
from tornado.ioloop import IOLoop

from ..inputs import clipped
from ..uploads import KINDS, SESSION_HEADER, WIND_MAX_BYTES, refused_size
from .watch import mark

log = logging.getLogger("windpump.app")

ROUTE = "/upload"  # after the app's own path: <prefix>/app/upload
LIFETIME = 120.0  # [s] bytes not taken by then are dropped (the page's reference comes in ms)
# A session's share: the newest file of each upload (KINDS), each within WIND_MAX_BYTES. The
# store's bounds, for every session of the server, hold at least one share.
MAX_ITEMS = 8  # files held at once
MAX_HELD = 4 * WIND_MAX_BYTES  # [bytes] held at once
# A post still arriving after this long is cut off and its bytes let go (a 10 MB file at ~270
# kbit/s): Tornado waits an hour for a body, so a page that began posts and stalled held their
# bytes (up to one file of each upload a page) that long.
POST_DEADLINE = 300.0  # [s]

# Why a post is refused: (HTTP status, what the page is told).
REFUSALS = {
    "kind": 400,  # not a wind or site upload
    "empty": 400,
    "size": 413,
    "session": 403,  # no session of this server with a connected page has this id
    "busy": 503,  # the store is full (bounds below one share only): choose the file again
    "replaced": 409,  # a later post of the same upload began: it is the page's share now
}


class Refused(Exception):
    """A post the store does not keep: ``reason`` is a key of REFUSALS."""

    def __init__(self, reason: str, message: str):
        super().__init__(message)
        self.reason = reason
        self.status = REFUSALS[reason]


@dataclasses.dataclass(frozen=True)
class Posted:
    """A file posted by a session's page, until the session takes it."""

    session_id: str
    kind: str  # "wind" or "site"
    name: str
    data: bytes
    at: float  # [s] the store's clock when it arrived


def refusal_text(reason: str, kind: str, size: int) -> str:
    """What the page says of a post refused for ``reason`` (REFUSALS): the size's words are the
    page's own refusal (``uploads.refused_size``)."""
    word, what = KINDS.get(kind, ("wind", ""))
    if reason == "size":
        return refused_size(word, size, what) or ""
    if reason == "empty":
        return f"This {word} file cannot be used: the file is empty"
    if reason == "session":
        return (
            f"This {word} file did not reach the page: the server does not hold this page's "
            "session any more. Reload the page (its link keeps the design) and choose it again."
        )
    if reason == "busy":
        return f"The server is receiving other files: choose this {word} file again in a moment."
    if reason == "replaced":
        return f"This {word} file was replaced by a later one chosen in the same page."
    return f"This {word} file could not be sent to the server: choose it again."


class Receiving:
    """A post being received (``Uploads.receiving``), its bytes so far (``chunks``): ``cut``
    once a later post of the same upload began or the page went, and its bytes let go at
    once (not when its client sends more, which it may never do)."""

    def __init__(self, session_id: str, kind: str):
        self.session_id, self.kind = session_id, kind
        self.chunks: list[bytes] = []
        self.cut = ""  # why it was cut: "replaced", "lost"; "" while it is the page's share


class Uploads:
    """The files posted and not yet taken, for the sessions of this server whose page is
    connected: ``connected(session_id)``, served, whether the session's websocket is open
    (``serve_uploads``); until then, every session opened here.

    A session's share is one file of each upload (KINDS), counted from the moment its post
    begins (``receiving``): a later post of the same upload cuts off an earlier one still
    arriving and drops one not yet taken, so a page holds at most one file of each, arrived or
    arriving, however many posts it sends at once."""

    def __init__(
        self,
        max_items: int = MAX_ITEMS,
        max_held: int = MAX_HELD,
        lifetime: float = LIFETIME,
        clock: Callable[[], float] = time.monotonic,
        connected: Callable[[str], bool] = lambda session_id: True,
    ):
        self.max_items, self.max_held, self.lifetime, self.clock = (
            max_items,
            max_held,
            lifetime,
            clock,
        )
        self.connected = connected
        self.url = ""  # the route's path, once served (``serve_uploads``); "": none
        self._lock = threading.Lock()
        self._sessions: set[str] = set()
        self._items: dict[str, Posted] = {}
        self._receiving: dict[tuple[str, str], Receiving] = {}  # (session, kind): in flight
        # ids of files dropped before they were taken, and why ("replaced", "crowded"): the newest
        self._dropped: dict[str, str] = {}

    def opened(self, session_id: str) -> None:
        with self._lock:
            self._sessions.add(session_id)

    def lost(self, session_id: str) -> None:
        """A session's page lost its websocket: what it posted, or is posting, is dropped (it
        posts no more unless it connects again)."""
        with self._lock:
            self._drop(lambda item: item.session_id == session_id, "lost")
            self._cut(session_id, None, "lost")

    def closed(self, session_id: str) -> None:
        """A session closed: it posts no more, and what it posted, or is posting, is
        dropped."""
        with self._lock:
            self._sessions.discard(session_id)
            self._drop(lambda item: item.session_id == session_id, "lost")
            self._cut(session_id, None, "lost")

    def receiving(self, session_id: str, kind: str) -> Receiving:
        """A post of the session's ``kind`` upload begins: it is the session's share of that
        upload from now on. An earlier post of the same upload still arriving is cut off, and
        a file of it not yet taken dropped ("replaced"): their reference, if the page ever
        sends it, is answered as a replaced one's. ``done`` when it ends, however it ends."""
        receipt = Receiving(session_id, kind)
        with self._lock:
            self._cut(session_id, kind, "replaced")
            self._drop(lambda item: item.session_id == session_id and item.kind == kind, "replaced")
            self._receiving[(session_id, kind)] = receipt
        return receipt

    def done(self, receipt: Receiving) -> None:
        """A post has ended (kept, refused or cut off): it no longer holds the share."""
        with self._lock:
            key = (receipt.session_id, receipt.kind)
            if self._receiving.get(key) is receipt:
                del self._receiving[key]

    def in_flight(self) -> int:
        """The posts being received now, as the page's share counts them."""
        with self._lock:
            return len(self._receiving)

    def _cut(self, session_id: str, kind: str | None, why: str) -> None:
        """Cut off the session's posts in flight (of ``kind``, or all). Under the lock."""
        for key in [k for k in self._receiving if k[0] == session_id and kind in (None, k[1])]:
            receipt = self._receiving.pop(key)
            receipt.cut = why
            receipt.chunks.clear()

    def is_open(self, session_id: str) -> bool:
        """Whether the session may post: opened here, and its page connected."""
        with self._lock:
            opened = session_id in self._sessions
        return opened and self.connected(session_id)

    def put(
        self,
        session_id: str,
        kind: str,
        name: str,
        data: bytes,
        receipt: Receiving | None = None,
    ) -> str:
        """Keep ``data`` for the session; its id. Raises ``Refused``. ``receipt``: the post's
        (``receiving``), refused if a later post of the same upload cut it off."""
        if kind not in KINDS:
            raise Refused("kind", f"kind must be one of {sorted(KINDS)}, not {kind!r}")
        if not data:
            raise Refused("empty", refusal_text("empty", kind, 0))
        if len(data) > WIND_MAX_BYTES:
            raise Refused("size", refusal_text("size", kind, len(data)))
        if not self.is_open(session_id):
            raise Refused("session", refusal_text("session", kind, len(data)))
        with self._lock:
            if receipt is not None and receipt.cut:
                reason = "replaced" if receipt.cut == "replaced" else "session"
                raise Refused(reason, refusal_text(reason, kind, len(data)))
            now = self.clock()
            self._drop(lambda item: now - item.at > self.lifetime, "expired")
            self._drop(lambda item: item.session_id == session_id and item.kind == kind, "replaced")
            if not self._room_for(session_id, len(data)):
                raise Refused("busy", refusal_text("busy", kind, len(data)))
            upload_id = secrets.token_urlsafe(12)
            self._items[upload_id] = Posted(session_id, kind, name, data, now)
        return upload_id

    def _room_for(self, session_id: str, size: int) -> bool:
        """Make room for a file of ``size`` bytes of the session, within the store's bounds:
        the oldest files of other sessions are dropped ("crowded"), those their pages did not
        take (a page takes its file within ms of posting it); False if there is no room even
        so (bounds smaller than a share). Under the lock."""

        def full() -> bool:
            held = sum(len(item.data) for item in self._items.values())
            return len(self._items) >= self.max_items or held + size > self.max_held

        others = [k for k, item in self._items.items() if item.session_id != session_id]
        while full() and others:  # the dict keeps the order they came in: oldest first
            key = others.pop(0)
            log.info(
                "the upload store was full: a file not taken after %.0f s dropped",
                self.clock() - self._items[key].at,
            )
            self._forget(key, "crowded")
        return not full()

    def _drop(self, which: Callable[[Posted], bool], why: str = "") -> None:
        """Drop the files ``which`` picks; remember their ids with ``why``, if given. Under
        the lock."""
        for key in [k for k, item in self._items.items() if which(item)]:
            self._forget(key, why)

    def _forget(self, key: str, why: str) -> None:
        del self._items[key]
        if why:
            self._dropped[key] = why
            while len(self._dropped) > 4 * self.max_items:
                del self._dropped[next(iter(self._dropped))]

    def take(self, session_id: str, upload_id: str) -> Posted | str:
        """The file ``upload_id`` of the session, removed from the store; if it is not there,
        why: "replaced" (a later file of the same upload replaced it: that one's reference
        follows), "crowded" (dropped for another page's file in a full store), "expired" (not
        taken within ``lifetime``), "lost" (dropped when its page's websocket closed) or
        "gone" (never held for this session, or dropped too long ago to say why)."""
        with self._lock:
            item = self._items.get(upload_id)
            if item is None or item.session_id != session_id:
                return self._dropped.get(upload_id, "gone")
            del self._items[upload_id]
        return item if self.clock() - item.at <= self.lifetime else "expired"

    def held(self) -> int:
        """The files held now."""
        with self._lock:
            return len(self._items)


UPLOADS = Uploads()


def page_opened(document) -> dict[str, str]:
    """A served page's session may post files while its page is connected (until it is
    destroyed): what its page needs to (``url``, ``session``); both "" when the route is not
    served, or the page not served. What it posted goes when its websocket closes."""
    context = getattr(document, "session_context", None)
    if not UPLOADS.url or context is None:
        return {"url": "", "session": ""}
    UPLOADS.opened(context.id)
    document.on_session_destroyed(session_destroyed)
    document.on_event("connection_lost", partial(connection_lost, context.id))
    return {"url": UPLOADS.url, "session": context.id}


def session_destroyed(session_context) -> None:  # Bokeh requires exactly this signature
    UPLOADS.closed(session_context.id)


def connection_lost(session_id: str, _event) -> None:
    """The page's websocket closed (Bokeh's ``ConnectionLost``, on the server)."""
    UPLOADS.lost(session_id)


@web.stream_request_body
class UploadHandler(web.RequestHandler):
    """``POST <app>/upload?kind=wind|site&name=NAME`` with the file's bytes as the body and the
    page's session id in the ``SESSION_HEADER`` header: 200 ``{"id", "size"}``, or a refusal
    (REFUSALS) ``{"refused", "message"}``.

    Streamed (``stream_request_body``): the body is checked as it comes, and a refused one is
    read and dropped (up to twice the limit; beyond that Tornado closes the connection), so the
    client gets the answer rather than a reset connection."""

    def initialize(self, uploads: Uploads) -> None:
        self.uploads = uploads
        self.size = 0
        self.refusal = ""
        self.receipt: Receiving | None = None  # the page's share and its bytes, as they arrive
        self.deadline: object | None = None  # the IOLoop's handle of ``too_slow``

    def check_xsrf_cookie(self) -> None:
        """The page's session id is the credential (it is what opens the session's websocket),
        and only a connected page's counts."""

    def prepare(self) -> None:
        self.session_id = self.request.headers.get(SESSION_HEADER, "")
        self.kind = self.get_query_argument("kind", "")
        self.name = self.get_query_argument("name", "")[:300]
        self.request.connection.set_max_body_size(2 * WIND_MAX_BYTES)
        length = self.request.headers.get("Content-Length", "")
        self.declared = int(length) if length.isdigit() else None
        if self.kind not in KINDS:
            self.refusal = "kind"
        elif not self.uploads.is_open(self.session_id):
            self.refusal = "session"
        elif self.declared is not None and self.declared > WIND_MAX_BYTES:
            self.refusal = "size"
        else:  # its bytes count against the page's share as they arrive
            self.receipt = self.uploads.receiving(self.session_id, self.kind)
            self.deadline = IOLoop.current().call_later(POST_DEADLINE, self.too_slow)

    def too_slow(self) -> None:
        """POST_DEADLINE has passed and the body is still arriving: cut it off (the page says
        the file could not be sent)."""
        if self.receipt is not None:
            log.info("upload: a post still arriving after %.0f s was cut off", POST_DEADLINE)
            self.release()
            self.request.connection.close()

    def data_received(self, chunk: bytes) -> None:
        if not self.size:
            mark("upload: first piece")
        self.size += len(chunk)
        receipt = self.receipt
        if receipt is not None and receipt.cut and not self.refusal:
            self.refusal = "replaced" if receipt.cut == "replaced" else "session"
        if self.refusal or receipt is None:
            return  # read and dropped
        if self.size > WIND_MAX_BYTES:
            self.refusal = "size"
            receipt.chunks.clear()
            return
        receipt.chunks.append(chunk)

    def on_finish(self) -> None:
        self.release()

    def on_connection_close(self) -> None:
        """The client went before the body had arrived (the page chose another file)."""
        self.release()

    def release(self) -> None:
        """The post has ended: its share and its bytes go."""
        if self.deadline is not None:
            IOLoop.current().remove_timeout(self.deadline)
            self.deadline = None
        if self.receipt is not None:
            self.receipt.chunks.clear()
            self.uploads.done(self.receipt)
            self.receipt = None

    def post(self) -> None:
        mark("upload: body read", size=self.size)
        receipt = self.receipt
        if receipt is not None and receipt.cut and not self.refusal:
            self.refusal = "replaced" if receipt.cut == "replaced" else "session"
        try:
            if self.refusal or receipt is None:
                size = self.size if self.declared is None else self.declared
                reason = self.refusal or "session"
                raise Refused(reason, refusal_text(reason, self.kind, size))
            data = b"".join(receipt.chunks)
            receipt.chunks.clear()
            upload_id = self.uploads.put(self.session_id, self.kind, self.name, data, receipt)
        except Refused as refused:
            self.set_status(refused.status)
            self.write({"refused": refused.reason, "message": str(refused)})
            return
        self.write({"id": upload_id, "size": len(data)})


def serve_uploads(server_context, servers: list) -> str:
    """Add the upload route to each running Bokeh server (``BokehTornado``, a Tornado
    application: ``add_handlers``), after the app's own path (its prefix too); the path, or ""
    when there is no server to add it to."""
    application = getattr(server_context, "application_context", None)
    app_url = getattr(application, "url", None) or "/app"
    if application is not None:
        UPLOADS.connected = partial(page_connected, application)
    for server in servers:
        url = f"{getattr(server, '_prefix', '')}{app_url}{ROUTE}"
        server.add_handlers(r".*", [(re.escape(url), UploadHandler, {"uploads": UPLOADS})])
        UPLOADS.url = url
        log.info("files are uploaded by HTTP at %s", url)
    return UPLOADS.url


def page_connected(application, session_id: str) -> bool:
    """Whether the session ``session_id`` of Bokeh's ``application`` (its ApplicationContext)
    has its page's websocket open: a page's GET builds its session, and only its browser, once
    it has loaded the page, connects it."""
    try:
        session = application.get_session(session_id)
    except Exception:  # Bokeh's ProtocolError: no such session (never built, or destroyed)
        return False
    return not session.destroyed and session.connection_count > 0


def dropped_text(why: str, name: str) -> str:
    """What the page says of its file ``name`` that the store no longer held when the page
    sent its reference, dropped for ``why`` (``Uploads.take``'s answer: "expired", "lost",
    "gone")."""
    file = clipped(name) or "The file"
    if why == "expired":
        return (
            f"{file} did not reach the page in time: the server keeps a file {LIFETIME:.0f} s "
            "for its page, and this one was not taken by then. Choose it again."
        )
    if why == "lost":
        return (
            f"{file} did not reach the page: the page's connection to the server closed "
            "before the page took it, and the server dropped it then. Choose it again."
        )
    return f"{file} did not reach the page: the server no longer holds it. Choose it again."


def deliver(channel, tab, session_id: str) -> bool:
    """What the page's upload channel (``uploads.UploadChannel``) says of a wind or site file,
    done in its tab (the Wind or Site tab: ``refuse_size``, ``sending``, ``load_data``, ``say``):
    a posted file is taken from the store and read as a FileInput's value is. True when a
    refusal was said now (the page scrolls it into view); a reading's outcome scrolls itself."""
    state, detail = channel.state
    size, name = channel.size or 0, channel.filename
    if state == "refused":
        tab.refuse_size(size)
        return True
    if state == "sending":
        tab.sending(name, size)
        return False
    if state == "empty":
        tab.load_data(b"", name)  # the core's words for an empty file
        return False
    if state == "posted":
        posted = UPLOADS.take(session_id, detail)
        mark("upload: reference")
        if isinstance(posted, Posted):
            tab.load_data(posted.data, posted.name or name)
            return False
        if posted == "replaced":
            return False  # a later file's reference follows
        if posted == "crowded":
            tab.say(
                f"The server was receiving many files: {clipped(name) or 'the file'} was dropped "
                "before this page could take it. Choose it again."
            )
            return True
        tab.say(dropped_text(posted, name))
        return True
    tab.say(refusal_text(detail if detail in REFUSALS else "network", channel.kind, size))
    return True
