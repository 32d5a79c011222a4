"""A page's session from its opening to its end: kept while its browser loads
(``wait_for_the_browser``), its first run once the solver is ready (``first_run_when_ready``),
readouts first for a class opening at once (``READOUTS_FIRST``), its stylesheets from this server,
reopened once its server is back (``reopen_when_reconnected``), and what its close hands back
(``session_closed``)."""

from __future__ import annotations

import asyncio
import logging
import threading
import time
from collections.abc import Callable
from typing import Any

from ..compiling import COMPILE, FIRST_PAGE
from .memory import TIDY
from .threads import DRAW_AFTER_MOVES

log = logging.getLogger("windpump.app")


def session_closed(session_context) -> None:  # Bokeh requires exactly this signature
    """When a session closes, stop counting it as loading (ReadoutsFirst), and have its memory
    handed back to the operating system soon (``TIDY``).

    Lives in a module of its own: Bokeh clears ``main.py``'s globals once a session has started,
    so a callback defined there cannot reach its imports when the session ends.
    """
    READOUTS_FIRST.closed(session_context.id)
    TIDY.closed()


# A browser that opened the page connects its websocket once it has loaded the page's scripts: on
# a busy server (a class opening at once, a first compile) that took over 30 s, the page's session
# had been dropped as never connected (hooks.UNCONNECTED_SESSION_LIFETIME), and the websocket
# built the page a second time. A browser's navigation says so (``Sec-Fetch-Dest: document``,
# sent by Chromium, Firefox and Safari; not by a script or most link checkers): its session is
# kept this long unconnected; a bare GET's still goes after 30-35 s.
BROWSER_CONNECT_WINDOW = 180.0  # [s]
CONNECTED_POLL = 0.5  # [s] how often a held page's session is asked whether its browser is in
# A script can send that header too: at most this many pages are held at once (a hall of 100
# opening together fits), so forged navigations hold at most as many pages' memory for the
# window; past it a navigation's page goes after the lifetime, as a bare GET's does.
MAX_HELD = 150
HELD: set[str] = set()  # the ids of the sessions held now


def wait_for_the_browser(
    document, window: float = BROWSER_CONNECT_WINDOW, poll: float = CONNECTED_POLL
) -> None:
    """Keep ``document``'s session for up to ``window`` seconds while its browser, whose
    navigation asked for the page, loads it and connects; once it has connected, Bokeh keeps
    it while connected, and once closed it lingers as Bokeh's lifetime says (the hold ends as
    the page connects, not ``window`` seconds after it was served: a class's closed pages are
    dropped, and their memory handed back, within the lifetime). A request that is no browser's
    navigation leaves the session to Bokeh's lifetime alone, and so does a navigation while
    ``MAX_HELD`` pages are held (the header can be forged).

    Examples
    --------
    In ``main.py``, as the page is built: ``wait_for_the_browser(pn.state.curdoc)``.
    """
    from tornado.ioloop import IOLoop

    context = document.session_context
    request = getattr(context, "request", None)
    headers = getattr(request, "headers", None) or {}
    if headers.get("Sec-Fetch-Dest", "").lower() != "document":
        return
    loop = IOLoop.current()

    def release_once_connected(session, held_at: float) -> None:
        if session.destroyed:
            HELD.discard(session.id)
            return
        held_ms = (time.monotonic() - held_at) * 1000.0
        # connected now, or connected and gone between two looks (it left after the hold began)
        connected = session.connection_count > 0 or (
            session.milliseconds_since_last_unsubscribe < held_ms - 1.0
        )
        if connected or held_ms >= window * 1000.0:
            HELD.discard(session.id)
            session.unblock_expiration()
        else:
            loop.call_later(poll, release_once_connected, session, held_at)

    def block() -> None:  # once Bokeh has made the session (just after this document is built)
        session = getattr(context, "_session", None)
        if session is None or session.destroyed or len(HELD) >= MAX_HELD:
            return
        HELD.add(session.id)
        session.block_expiration()
        loop.call_later(poll, release_once_connected, session, time.monotonic())

    loop.add_callback(block)


def stylesheets_from_this_server(document) -> None:
    """Make every stylesheet Panel creates in ``document`` point at this server, not the HoloViz CDN.

    Panel (1.9.4) gives a component the CDN's stylesheet URL until the page's HTML is rendered and
    rewrites them then. A session Bokeh creates when a websocket connects (the page's own session
    expired first, e.g. while a class of 30 loads at once) never has its HTML rendered, so its
    stylesheets stayed on a host a classroom without internet cannot reach. Naming this server's
    address before any component is built fixes both paths.
    """
    from panel.io.resources import LOCAL_DIST
    from panel.io.state import state

    local = f"{state.rel_path}/{LOCAL_DIST}" if state.rel_path else LOCAL_DIST
    document._template_variables.setdefault("dist_url", local)


class ReadoutsFirst:
    """The server's order when a class opens the page at once: readouts for every page, then views.

    A page's views (the plots and the machine, ~450 Bokeh models) cost the server and the browser
    several times what its controls and readouts do. Built as soon as each page has loaded, the
    first pages' views hold up the readouts of the pages still loading; here they wait until no
    other page is still loading, for at most ``patience`` seconds. One instance serves every
    session (this module outlives them); a page alone gets its views at once.
    """

    def __init__(
        self,
        patience: float = 15.0,
        forget_after: float = 180.0,
        poll: float = 0.25,
        settled: Callable[[], None] = lambda: None,
        draw: Callable[[Any, Callable[[], None]], None] = lambda _document, draw: draw(),
    ):
        self.settled = settled  # called once a page is built and sent, and once its views are
        self.draw = draw  # draw(document, show): when a page's views are built
        self.patience = patience  # [s] the longest a loaded page's views wait for the others
        self.forget_after = forget_after  # [s] a page that never loads stops holding others back
        self.poll = poll  # [s]
        self.loading: dict[str, float] = {}  # session id -> when its page was built

    def opened(self, session_id: str) -> None:
        self.loading[session_id] = time.monotonic()

    def closed(self, session_id: str) -> None:
        self.loading.pop(session_id, None)

    def others_loading(self) -> bool:
        now = time.monotonic()
        for session_id, since in list(self.loading.items()):
            if now - since > self.forget_after:
                del self.loading[session_id]
        return bool(self.loading)

    def loaded(self, session_id: str, document, show_views: Callable[[], None]) -> None:
        """The page of ``session_id`` shows its readouts: show its views once the others do."""
        self.closed(session_id)
        self.settled()
        self._show_when_free(document, show_views, time.monotonic())

    def _show_when_free(self, document, show_views: Callable[[], None], since: float) -> None:
        if not self.others_loading() or time.monotonic() - since >= self.patience:

            def show() -> None:
                show_views()
                self.settled()

            self.draw(document, show)
            return
        document.add_timeout_callback(
            lambda: self._show_when_free(document, show_views, since), int(self.poll * 1e3)
        )


READOUTS_FIRST = ReadoutsFirst(settled=TIDY.settle, draw=DRAW_AFTER_MOVES.later)


# Set once the server's solver is compiled or loaded from numba's cache. A first start after an
# install compiles it in the background (hooks.py): pages open meanwhile, their browsers load
# while it compiles, and each runs its first design once it is ready (``first_run_when_ready``).
# Set by default: without the hook (a notebook, the tests) nothing waits.
SOLVER_READY = threading.Event()
SOLVER_READY.set()
COMPILE_PROGRESS_EVERY = 1.0  # [s] how often a waiting page says again how far the compile is


def first_run_when_ready(session_id: str, document, explorer) -> Callable:
    """The page's onload callback while the solver compiles: wait for the part its first run
    needs (``explorer.part_awaited``: the first page's, or a real machine's) off the event loop,
    saying in the page how far the compile is as its parts get ready
    (``explorer.say_compiling``), then, under the document's lock, run the page's first design
    and go on as a page does. A page closed meanwhile (its session destroyed, its document's
    callbacks gone) runs nothing: adding a callback to it raised, a traceback in the log for
    each such page."""
    context = getattr(document, "session_context", None)  # None unless served

    async def run() -> None:
        loop = asyncio.get_running_loop()
        while (part := explorer.part_awaited()) is not None:
            if context is not None and context.destroyed:
                return
            events = (SOLVER_READY, COMPILE.ready[FIRST_PAGE]) if part == FIRST_PAGE else ()
            ready = next((e for e in (*events, COMPILE.ready[part]) if not e.is_set()), None)
            if ready is None:  # ready since part_awaited asked
                continue
            if not await loop.run_in_executor(None, ready.wait, COMPILE_PROGRESS_EVERY):
                if context is None or not context.destroyed:
                    document.add_next_tick_callback(explorer.say_compiling)  # still compiling
        if context is not None and context.destroyed:
            return

        def first_run() -> None:
            explorer.start()
            READOUTS_FIRST.loaded(session_id, document, explorer.show_views)

        document.add_next_tick_callback(first_run)

    return run


# When the page's websocket closes (Wi-Fi dropped, the server or its process restarted): say so at
# the top of the page, ask the server for a small static file every 2 s, and once it answers,
# reopen the page at its current address (its link, which holds the design) with ?restored=true,
# which the new page says (link.RESTORED) and drops from its link. Behind the proxy
# (proxy.py) the answer comes from a live process, and the page reopens there.
RECONNECT_JS = """
if (document.getElementById("windpump-offline") !== null) return
const banner = document.createElement("div")
banner.id = "windpump-offline"
banner.setAttribute("role", "alert")
banner.style.cssText = "position:fixed;top:0;left:0;right:0;z-index:10000;padding:8px 16px;" +
  "background:#f0ad4e;color:#222;font:16px sans-serif;text-align:center"
banner.textContent = "The connection to the server was lost: reconnecting… (this page's " +
  "link holds its design, nothing to retype)"
document.body.appendChild(banner)
const probe = new URL("static/extensions/panel/css/alerts.css", window.location.href)
const again = new URL(window.location.href)
again.searchParams.set("restored", "true")
const attempt = () => {
  fetch(probe, {cache: "no-store"})
    .then((r) => { if (r.ok) window.location.replace(again.href); else setTimeout(attempt, 2000) })
    .catch(() => setTimeout(attempt, 2000))
}
setTimeout(attempt, 1000)
"""


def reopen_when_reconnected(document) -> None:
    """Give ``document``'s page RECONNECT_JS for when its connection is lost."""
    from bokeh.models import CustomJS

    document.js_on_event("connection_lost", CustomJS(code=RECONNECT_JS))
