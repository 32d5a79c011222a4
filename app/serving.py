"""What a long-running classroom server needs besides the page itself."""

from __future__ import annotations

import asyncio
import ctypes
import ctypes.util
import gc
import math
import threading
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

_LIBC_NAME = ctypes.util.find_library("c")
_LIBC = ctypes.CDLL(_LIBC_NAME) if _LIBC_NAME else None


def session_closed(session_context) -> None:  # Bokeh requires exactly this signature
    """When a session closes, stop counting it as loading (ReadoutsFirst), and have its memory
    handed back to the operating system soon (``TIDY``).

    Lives in a module of its own: Bokeh clears ``main.py``'s globals once a session has started,
    so a callback defined there cannot reach its imports when the session ends.
    """
    READOUTS_FIRST.closed(session_context.id)
    TIDY.closed()


class Tidy:
    """Frees what closed sessions held and hands it back to the operating system (glibc keeps
    freed arenas otherwise, and a server that runs through a lecture only grows), once, after
    the sessions stop closing.

    A full ``gc.collect()`` walks every live object of every open page: with 60 pages open it
    blocks the server's event loop for 1.1-1.4 s (measured). Run for each closing session, a
    class leaving stalled every page still open for minutes; here it runs ``quiet`` seconds after
    the last session closed, at most once every ``every`` seconds.
    """

    def __init__(self, quiet: float = 5.0, every: float = 60.0):
        self.quiet = quiet  # [s]
        self.every = every  # [s]
        self.last = -math.inf  # time.monotonic() of the last run
        self.pending = None  # the IOLoop's handle of the run to come

    def closed(self) -> None:
        from tornado.ioloop import IOLoop

        loop = IOLoop.current()
        if self.pending is not None:
            loop.remove_timeout(self.pending)
        delay = max(self.quiet, self.last + self.every - time.monotonic())
        self.pending = loop.call_later(delay, self.run)

    def run(self) -> None:
        self.pending = None
        self.last = time.monotonic()
        gc.collect()
        if _LIBC is not None and hasattr(_LIBC, "malloc_trim"):
            _LIBC.malloc_trim(0)


TIDY = Tidy()


def without_mathjax() -> None:
    """No page here writes LaTeX, but Panel ships MathJax (1.8 MB, a third of the page) to every
    page that has an HTML pane. Tell Panel's resource bundler this app needs none."""
    from panel.io import resources

    resources._panel_use_mathjax = lambda roots: False


def without_webgl() -> None:
    """No figure here asks for WebGL, but Bokeh's resources list bokeh-gl (190 KB of script a
    browser must parse) for every page. Leave it out of the page Panel's server renders."""
    from panel.io import server

    if getattr(server.bundle_resources, "without_webgl", False):
        return
    bundle_resources = server.bundle_resources

    def bundle_without_webgl(roots, resources, *args, **kwargs):
        bundle = bundle_resources(roots, resources, *args, **kwargs)
        bundle.js_files = [url for url in bundle.js_files if "/bokeh-gl" not in str(url)]
        return bundle

    bundle_without_webgl.without_webgl = True
    server.bundle_resources = bundle_without_webgl


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

    def __init__(self, patience: float = 15.0, forget_after: float = 180.0, poll: float = 0.25):
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
        self._show_when_free(document, show_views, time.monotonic())

    def _show_when_free(self, document, show_views: Callable[[], None], since: float) -> None:
        if not self.others_loading() or time.monotonic() - since >= self.patience:
            show_views()
            return
        document.add_timeout_callback(
            lambda: self._show_when_free(document, show_views, since), int(self.poll * 1e3)
        )


READOUTS_FIRST = ReadoutsFirst()


# Set once the server's solver is compiled or loaded from numba's cache. A first start after an
# install compiles it in the background (app_hooks.py): pages open meanwhile, their browsers load
# while it compiles, and each runs its first design once it is ready (``first_run_when_ready``).
# Set by default: without the hook (a notebook, the tests) nothing waits.
SOLVER_READY = threading.Event()
SOLVER_READY.set()


def first_run_when_ready(session_id: str, document, explorer) -> Callable:
    """The page's onload callback while the solver compiles: wait for it off the event loop,
    then, under the document's lock, run the page's first design and go on as a page does."""

    async def run() -> None:
        if not SOLVER_READY.is_set():
            await asyncio.get_running_loop().run_in_executor(None, SOLVER_READY.wait)

        def first_run() -> None:
            explorer.start()
            READOUTS_FIRST.loaded(session_id, document, explorer.show_views)

        document.add_next_tick_callback(first_run)

    return run


# Heavy work of one page (a wind record read and run, a map, a year) runs here, not on the
# server's event loop, which every page's moves wait for. The compiled kernels release the GIL
# (windpump._kernels.jit), so two threads use the two cores; Python parts share the GIL in 5 ms
# turns, so the loop keeps answering meanwhile.
OFF_THE_LOOP = ThreadPoolExecutor(max_workers=2, thread_name_prefix="heavy work")


def off_the_loop(work: Callable[[], Any], then: Callable[[Any], None]) -> None:
    """Run ``work()`` off the event loop, then ``then(result)`` on it, under the page's lock.

    Served (``pn.state.curdoc`` has a session): ``work`` in ``OFF_THE_LOOP`` and ``then`` as the
    document's next-tick callback (the one Bokeh call that is safe from another thread). Not
    served (a notebook, the tests): both at once, in order. An exception of ``work`` is handed
    to ``then`` as its result.
    """
    import panel as pn

    document = pn.state.curdoc
    if document is None or document.session_context is None:
        then(_outcome(work))
        return

    def done(future) -> None:
        result = future.result()
        document.add_next_tick_callback(lambda: then(result))

    OFF_THE_LOOP.submit(_outcome, work).add_done_callback(done)


def _outcome(work: Callable[[], Any]) -> Any:
    try:
        return work()
    except Exception as error:  # handed to ``then``, which says it on the page
        return error


# When the page's websocket closes (Wi-Fi dropped, the server or its process restarted): say so at
# the top of the page, ask the server for a small static file every 2 s, and once it answers,
# reopen the page at its current address (its link, which holds the design) with ?restored=true,
# which the new page says (link.RESTORED) and drops from its link. Behind the proxy
# (app/proxy.py) the answer comes from a live process, and the page reopens there.
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
