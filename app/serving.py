"""What a long-running classroom server needs besides the page itself."""

from __future__ import annotations

import asyncio
import ctypes
import ctypes.util
import dataclasses
import functools
import gc
import json
import logging
import math
import multiprocessing
import os
import re
import threading
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from typing import Any

import numpy as np

from .compiling import COMPILE, FIRST_PAGE

log = logging.getLogger("windpump.app")

_LIBC_NAME = ctypes.util.find_library("c")
_LIBC = ctypes.CDLL(_LIBC_NAME) if _LIBC_NAME else None
_NICE = hasattr(os, "setpriority")  # Unix: a file-reading process runs below the server's priority


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
# had been dropped as never connected (app_hooks.UNCONNECTED_SESSION_LIFETIME), and the websocket
# built the page a second time. A browser's navigation says so (``Sec-Fetch-Dest: document``,
# sent by Chromium, Firefox and Safari; not by a script or most link checkers): its session is
# kept this long unconnected; a bare GET's still goes after 30-35 s.
BROWSER_CONNECT_WINDOW = 180.0  # [s]


def wait_for_the_browser(document, window: float = BROWSER_CONNECT_WINDOW) -> None:
    """Keep ``document``'s session for ``window`` seconds while its browser, whose navigation
    asked for the page, loads it and connects (a session connected is kept while connected,
    and lingers as Bokeh's lifetime says once closed). A request that is no browser's
    navigation leaves the session to Bokeh's lifetime alone.

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

    def block() -> None:  # once Bokeh has made the session (just after this document is built)
        session = getattr(context, "_session", None)
        if session is None or session.destroyed:
            return
        session.block_expiration()
        IOLoop.current().call_later(window, session.unblock_expiration)

    IOLoop.current().add_callback(block)


def log_request(handler) -> None:
    """Tornado's line in its access log for a request answered (``log_function``), with the
    request's path and not its query: a page's query is its link (up to megabytes), and an
    upload's names its file; no session's id goes in a URL (``upload_route.SESSION_HEADER``)."""
    from tornado.log import access_log

    status, request = handler.get_status(), handler.request
    say = access_log.info  # Tornado's levels: refusals are warnings, failures errors
    if status >= 400:
        say = access_log.warning if status < 500 else access_log.error
    elapsed = 1000.0 * request.request_time()
    say("%d %s %s (%s) %.2fms", status, request.method, request.path, request.remote_ip, elapsed)


# A Bokeh session's id (44 letters and digits: no word or name in a log line is that long), or
# a token carrying one (base64url JSON, which opens with "eyJ", and its signature).
SESSION_ID = re.compile(r"\beyJ[A-Za-z0-9_-]+(?:\.[A-Za-z0-9_-]*)*|[A-Za-z0-9]{40,}")
HIDDEN = "[a session]"


class HideSessionIds(logging.Filter):
    """Writes every session id or token in a log line as HIDDEN (a session's id is the credential
    of its page's uploads). Bokeh's own lines name sessions: at WARNING "Session '<id>' was
    scheduled to discard but came back to life", at ERROR a token or id of a bad signature, at
    DEBUG each page's "Sending pull-doc-reply from session '<id>'" and its discarding."""

    def filter(self, record: logging.LogRecord) -> bool:
        try:
            message = record.getMessage()
        except Exception:  # a line whose arguments do not fit: the handler says so, as before
            return True
        if SESSION_ID.search(message):
            record.msg, record.args = SESSION_ID.sub(HIDDEN, message), None
        if record.exc_info and not record.exc_text:
            record.exc_text = logging.Formatter().formatException(record.exc_info)
        if record.exc_text and SESSION_ID.search(record.exc_text):
            record.exc_text = SESSION_ID.sub(HIDDEN, record.exc_text)
        return True


def hide_session_ids(logger: logging.Logger | None = None) -> None:
    """Add ``HideSessionIds`` to every handler of ``logger`` (the root's: where ``panel serve``
    writes Bokeh's, Tornado's and these lines, to the terminal or its ``--log-file``), once."""
    for handler in (logger or logging.getLogger()).handlers:
        if not any(isinstance(f, HideSessionIds) for f in handler.filters):
            handler.addFilter(HideSessionIds())


class Tidy:
    """When the server collects its garbage: never a walk of every open page on the event loop
    while students move, and what closed sessions held handed back to the operating system.

    Python's automatic full collection (generation 2) walks every live object. With 100 pages
    open (3.5 million objects) one took 1.8-2.6 s of the event loop, and the heap growing while a
    hall opens triggers one at every 25 % of growth: nineteen in the first 70 s of a hall of 100,
    ~10 s in all, and later ones while the students moved (measured with ``LoopWatch``). Here a
    page's objects, once it is built and sent (``settle``), are frozen (``gc.freeze()``: moved
    to a permanent generation no collection walks), after a collection of what is not frozen
    yet: one page's worth, ~35k objects. Later collections walk only what the moves made since.
    What a page's build leaves in reference cycles and lets go of later is frozen with it
    (~0.4 MB a page) until the next ``run``.

    Frozen objects are not freed when their session closes: ``closed`` unfreezes and collects
    everything (``run``; with 60 pages open 1.1-1.4 s of the loop), ``quiet`` seconds after the
    last session closed, at most once every ``every`` seconds, and only once the sessions closed
    since the last run are at least ``share`` of those still open (or none is): at most that
    share of dead pages is kept, as Python's own rule for full collections keeps it.
    """

    def __init__(self, quiet: float = 5.0, every: float = 60.0, share: float = 0.25):
        self.quiet = quiet  # [s]
        self.every = every  # [s]
        self.share = share
        self.last = -math.inf  # time.monotonic() of the last run
        self.pending = None  # the IOLoop's handle of the run to come
        self.open = 0  # sessions open
        self.dead = 0  # sessions closed since the last run

    def opened(self) -> None:
        self.open += 1

    def closed(self) -> None:
        from tornado.ioloop import IOLoop

        self.open = max(0, self.open - 1)
        self.dead += 1
        if self.dead < self.share * self.open:
            return
        loop = IOLoop.current()
        if self.pending is not None:
            loop.remove_timeout(self.pending)
        delay = max(self.quiet, self.last + self.every - time.monotonic())
        self.pending = loop.call_later(delay, self.run)

    def settle(self) -> None:
        """A page is built (or its views): collect what is not frozen yet (that page, what the
        moves since left), then freeze what lives, which no collection walks again. Called at
        once, not later: a hall's pages are built in one turn of the loop, one after another."""
        gc.collect()
        gc.freeze()

    def run(self) -> None:
        """Free what the closed sessions held: every object walked once, then frozen again."""
        self.pending = None
        self.last = time.monotonic()
        self.dead = 0
        if self.open == 0:
            forget_the_class()
        gc.unfreeze()
        gc.collect()
        gc.freeze()
        if _LIBC is not None and hasattr(_LIBC, "malloc_trim"):
            _LIBC.malloc_trim(0)


TIDY = Tidy()


def forget_the_class() -> None:
    """Every page has closed: forget the designs the class moved to (``dynamics.ideal_of``
    remembers the last 64, ~10 small objects each). Made during the class, among its pages'
    objects, they kept those pages' memory after the class: Python's allocator hands a 1 MiB
    arena back to the system only once every object in it is freed, and after a hall of 30
    they were in nearly every arena it had added (docs/known-issues.rst). The next class
    fills it again (35 us a design)."""
    from windpump.dynamics import ideal_of

    ideal_of.cache_clear()


# glibc's mallopt parameters (malloc.h)
M_TRIM_THRESHOLD, M_MMAP_THRESHOLD = -1, -3
LARGE_BLOCK = 4 * 1024 * 1024  # [bytes] a block this large or larger is mapped on its own
TRIM_ABOVE = 2 * LARGE_BLOCK  # [bytes] free memory at a heap's top handed back (glibc's ratio)


def large_blocks_mapped() -> bool:
    """Have glibc map every block of LARGE_BLOCK or more on its own, handed back to the system
    when freed, whatever blocks were freed before; True if it was done (glibc's ``mallopt``).

    By default glibc maps a block of 128 KiB or more, but each mapped block freed raises that
    threshold to its size (up to 32 MiB): a 10 MB upload's blocks (its 13 MB of base64, its
    bytes, its record's arrays) raised it past 10 MB, and from then on every block below that
    came from malloc's heaps, one for each thread of the moves' runs and the heavy work, whose
    freed memory stays resident. A hall of 30 with an upload (``benchmarks/bench_hall.py``):
    the heaps held 383 MB, 62 MB of it in use, and the server 425 MB after the hall against
    266 MB before; with the threshold fixed, 70 MB of heaps and 330 MB after. At 128 KiB a run
    of the paper's example took three times its CPU (its integrator's buffers mapped and
    zeroed anew each run); at 4 MiB, with the heaps' tops handed back above 8 MiB, ~5 % more.
    """
    if _LIBC is None or not hasattr(_LIBC, "mallopt"):
        return False
    return bool(_LIBC.mallopt(M_MMAP_THRESHOLD, LARGE_BLOCK)) and bool(
        _LIBC.mallopt(M_TRIM_THRESHOLD, TRIM_ABOVE)
    )


class LoopWatch:
    """What holds up the server's event loop, written to a file as JSON lines: every garbage
    collection of generation 2 (or longer than ``slow`` seconds), and every time the loop ran a
    timer ``slow`` seconds or more late. Off unless the server is started with
    ``WINDPUMP_LOOP_WATCH=<file>`` (``benchmarks/bench_hall.py --watch`` does that); each line
    holds ``t`` (``time.time()`` [s] at its end), ``kind`` ("gc" or "lag"), ``seconds``, and for
    a collection its ``generation``, ``collected`` and the objects ``tracked`` after it.
    """

    def __init__(self, path: str, slow: float = 0.05, every: float = 0.05):
        self.path = path
        self.slow = slow  # [s]
        self.every = every  # [s] the lag timer's period
        self.started: float | None = None  # perf_counter() of the collection under way

    def on_gc(self, phase: str, info: dict) -> None:
        """A ``gc.callbacks`` entry."""
        if phase == "start":
            self.started = time.perf_counter()
            return
        if self.started is None:
            return
        seconds, self.started = time.perf_counter() - self.started, None
        if info["generation"] == 2 or seconds >= self.slow:
            tracked = len(gc.get_objects(2)) if info["generation"] == 2 else None
            self.write(
                "gc",
                seconds,
                generation=info["generation"],
                collected=info["collected"],
                tracked=tracked,
            )

    def late(self, expected: float) -> float:
        """The timer due at ``expected`` [perf_counter] ran now: write it if ``slow`` late."""
        lag = time.perf_counter() - expected
        if lag >= self.slow:
            self.write("lag", lag)
        return lag

    def write(self, kind: str, seconds: float, **more) -> None:
        line = {"t": time.time(), "kind": kind, "seconds": round(seconds, 4), **more}
        with open(self.path, "a") as out:
            out.write(json.dumps(line) + "\n")

    def start(self, loop: asyncio.AbstractEventLoop) -> None:
        """Watch the collections and ``loop`` (a timer every ``every`` seconds) until ``stop``."""
        gc.callbacks.append(self.on_gc)
        self.ticking = True

        def tick(expected: float) -> None:
            self.late(expected)
            if self.ticking:
                loop.call_later(self.every, tick, time.perf_counter() + self.every)

        loop.call_later(self.every, tick, time.perf_counter() + self.every)

    def stop(self) -> None:
        self.ticking = False
        if self.on_gc in gc.callbacks:
            gc.callbacks.remove(self.on_gc)


WATCHED: list[LoopWatch] = []  # the server's LoopWatch, once started (``watch_the_loop``)


def watch_the_loop() -> LoopWatch | None:
    """A LoopWatch on the running loop if ``WINDPUMP_LOOP_WATCH`` names a file, else nothing;
    ``WINDPUMP_LOOP_WATCH_SLOW`` [s]: how late the loop is written down (0.05 s unless said)."""
    path = os.environ.get("WINDPUMP_LOOP_WATCH")
    if not path:
        return None
    from tornado.ioloop import IOLoop

    slow = float(os.environ.get("WINDPUMP_LOOP_WATCH_SLOW") or 0.05)
    watch = LoopWatch(path, slow=slow, every=min(0.05, slow))
    watch.start(IOLoop.current().asyncio_loop)  # type: ignore[attr-defined]
    WATCHED[:] = [watch]
    return watch


def mark(step: str, **more: Any) -> None:
    """Write a step of the server's work (an upload's: its first byte, its body read, its
    reading started, ...) beside the loop's stalls, when the loop is watched (``LoopWatch``);
    nothing otherwise. Any thread."""
    for watch in WATCHED:
        watch.write("mark", 0.0, step=step, thread=threading.current_thread().name, **more)


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


def lighter_patches() -> None:
    """Bokeh (3.9) starts every PATCH-DOC message by listing every model of its document and
    making each one's reference (``Serializer(references=doc.models.synced_references)``): ~600
    models a page here, for a message that changes one readout. Measured with py-spy while 30
    students moved at once, it was a fifth of the server's event loop. Here a model's reference
    is made when the message meets it (``SyncedSerializer``); the message is the same."""
    import bokeh
    from bokeh.document.json import PatchJson
    from bokeh.protocol.messages.patch_doc import patch_doc

    # It reaches into Bokeh's document internals: only on the Bokeh it was checked against.
    if getattr(patch_doc.create, "lighter", False) or not bokeh.__version__.startswith("3.9."):
        return

    def create(cls, events, **metadata):
        if not events:
            raise ValueError("PATCH-DOC message requires at least one event")
        docs = {event.document for event in events}
        if len(docs) != 1:
            raise ValueError("PATCH-DOC message configured with events for more than one document")
        [doc] = docs
        serializer = SyncedSerializer(doc.models)
        patch_json = PatchJson(events=serializer.encode(events))
        doc.models.flush_synced(lambda model: not serializer.has_ref(model))
        message = cls(cls.create_header(), metadata, patch_json)
        message.add_buffers(*serializer.buffers)
        return message

    create.lighter = True  # type: ignore[attr-defined]
    create.bokeh = patch_doc.create  # type: ignore[attr-defined]
    patch_doc.create = classmethod(create)  # type: ignore[method-assign,assignment]


def lighter_updates() -> None:
    """Panel (1.9) works out a component's design, its theme's stylesheets read through
    ``param.Path`` parameters that look up the file system, on every change of every component
    (``Reactive._update_properties``), and uses it only when the change is of its stylesheets:
    ~10 % of the event loop while 30 students moved at once (py-spy). Here it is worked out
    only then; what the change sends is the same."""
    import panel
    from panel.reactive import Reactive

    if getattr(Reactive._update_properties, "lighter", False) or not panel.__version__.startswith(
        "1.9."
    ):
        return

    def _update_properties(self, *events, doc):
        changes = {event.name: event.new for event in events}
        if "stylesheets" in changes and self._design:
            params, _ = self._design.params(self, doc)
            if "stylesheets" in params:
                changes["stylesheets"] = params["stylesheets"] + changes["stylesheets"]
        return self._process_param_change(changes)

    _update_properties.lighter = True  # type: ignore[attr-defined]
    _update_properties.panel = Reactive._update_properties  # type: ignore[attr-defined]
    Reactive._update_properties = _update_properties  # type: ignore[method-assign]


def writes_not_stranded() -> None:
    """Panel (1.9) sends a page's changes made while its socket is busy a little later, from a
    task (``panel.io.document._dispatch_msgs``), the page's writes blocked meanwhile. A task
    that finishes sending unblocks the page even when more changes were queued while it sent;
    the task queued for those then finds the page unblocked and returns, and they wait for the
    page's next change. A thread's answer drawn on a page just after a move's (the Design
    map's mark and readout, its work back while the move's patch was being written) did not
    reach the browser (a browser test's tap, 1 run in 4 to 10). Here a task that leaves
    changes queued and the page unblocked sends them."""
    import panel
    from panel.io import document as documents

    dispatch = documents._dispatch_msgs
    if getattr(dispatch, "not_stranded", False) or not panel.__version__.startswith("1.9."):
        return

    async def _dispatch_msgs(doc) -> None:
        await dispatch(doc)
        if doc in documents._WRITE_MSGS and doc not in documents._WRITE_BLOCK:
            documents._WRITE_BLOCK[doc] = True  # queued while it sent: sent now
            documents._dispatch_write_task(doc, _dispatch_msgs, doc)

    _dispatch_msgs.not_stranded = True  # type: ignore[attr-defined]
    _dispatch_msgs.panel = dispatch  # type: ignore[attr-defined]
    documents._dispatch_msgs = _dispatch_msgs


def fake_roots_forgotten() -> None:
    """Panel (1.9) lists the reference of every page's template root in ``state._fake_roots``
    (``BaseTemplate._init_doc``) and means to drop it when the page's session is destroyed
    (``BaseTemplate._server_destroy`` pops it from the template's ``_refs``), but never records
    it in ``_refs``: each page served left its string there for good (30 after a hall of 30),
    each one made among that page's objects and keeping its memory once the page was gone
    (docs/known-issues.rst), and every change of every component scans the list. Here the
    references a template's page adds are recorded in its ``_refs``, which Panel then drops."""
    import panel
    from panel.io.state import state
    from panel.template.base import BaseTemplate

    init_doc = BaseTemplate._init_doc
    if getattr(init_doc, "forgets", False) or not panel.__version__.startswith("1.9."):
        return

    def _init_doc(self, doc=None, *args, **kwargs):
        before = set(state._fake_roots)
        document = init_doc(self, doc, *args, **kwargs)
        added = [ref for ref in state._fake_roots if ref not in before]
        if len(added) == 1 and document not in self._refs:
            self._refs[document] = added[0]
        return document

    _init_doc.forgets = True  # type: ignore[attr-defined]
    _init_doc.panel = init_doc  # type: ignore[attr-defined]
    BaseTemplate._init_doc = _init_doc  # type: ignore[method-assign]


def _serializer_class():
    from bokeh.core.serialization import Serializer
    from bokeh.model import Model

    class SyncedSerializer(Serializer):
        """Bokeh's serializer, knowing the synced models of a document (those the browser has)
        as it meets them rather than all of them beforehand."""

        def __init__(self, models) -> None:
            super().__init__()
            self._models = models  # the document's DocumentModelManager

        def _synced(self, obj: Any) -> bool:
            if id(obj) in self._references:
                return True
            models = self._models
            if (
                isinstance(obj, Model)
                and models._models.get(obj.id) is obj
                and obj not in models._new_models
            ):
                self._references[id(obj)] = obj.ref
                return True
            return False

        def has_ref(self, obj: Any) -> bool:
            return self._synced(obj)

        def get_ref(self, obj: Any):
            return self._references[id(obj)] if self._synced(obj) else None

    return SyncedSerializer


SyncedSerializer = _serializer_class()


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


class DrawAfterMoves:
    """The server's order of drawing: every pending move's readouts first, then plots and views,
    one page's at a time.

    A move's readouts go out as soon as its run is done; its page's plots (~10-40 ms) and a
    page's views once it has loaded (~0.3 s) are drawn afterwards. Drawn on each page's next
    tick, 30 moves arriving at once interleaved the plots of the first with the readouts of the
    last, and the views of a hall's pages were built in one turn of the loop (59 s for 100,
    every move meanwhile waiting). Here a page asks for a drawing (``later``); the drawings run
    one per turn of the event loop, each after the messages read meanwhile, and not while a
    change Panel has read is still to be applied (a move waiting for its run), for at most
    ``patience`` seconds (a hall that never stops moving still gets its plots). The same drawing
    asked for again before it ran (a page's ``_plot_latest``: it draws the latest run) runs once.
    """

    def __init__(self, retry: float = 0.005, patience: float = 0.5):
        self.retry = retry  # [s] how soon to look again while moves are pending
        self.patience = patience  # [s] the longest the next drawing waits for moves
        self.queue: dict[Callable[[], None], Any] = {}  # drawing -> its document, in order
        self.waiting_since: float | None = None  # time.monotonic() the next drawing first waited
        self.scheduled = False

    def later(self, document, draw: Callable[[], None]) -> None:
        """Run ``draw`` under ``document``'s lock once no move is waiting."""
        self.queue.setdefault(draw, document)
        self._schedule(0.0)

    def _schedule(self, delay: float) -> None:
        if self.scheduled or not self.queue:
            return
        from tornado.ioloop import IOLoop

        self.scheduled = True
        IOLoop.current().call_later(delay, self._next)  # a timer: after the I/O of its turn

    def _next(self) -> None:
        self.scheduled = False
        now = time.monotonic()
        if self.waiting_since is None:
            self.waiting_since = now
        if moves_pending() and now - self.waiting_since < self.patience:
            self._schedule(self.retry)
            return
        self.waiting_since = None
        draw = next(iter(self.queue))
        # Under the document's lock, as its curdoc, at the head of the loop's next turn; the
        # next drawing is looked at after that turn's messages (a timer runs after the I/O)
        try:
            self.queue.pop(draw).add_next_tick_callback(draw)
        except Exception:  # its page closed meanwhile: the drawings queued behind it still run
            log.debug("a drawing's page is gone", exc_info=True)
        finally:
            self._schedule(0.0)


def moves_pending() -> bool:
    """Whether some page's move is still to be answered: a change Panel has read and not applied
    yet (its callbacks wait in ``state._change_callbacks``; a private part of Panel, read
    defensively), or a move's run under way off the loop (``MOVE_RUNS``)."""
    from panel.io.state import state

    return MOVE_RUNS.under_way > 0 or any(getattr(state, "_change_callbacks", {}).values())


DRAW_AFTER_MOVES = DrawAfterMoves()
READOUTS_FIRST = ReadoutsFirst(settled=TIDY.settle, draw=DRAW_AFTER_MOVES.later)


# Set once the server's solver is compiled or loaded from numba's cache. A first start after an
# install compiles it in the background (app_hooks.py): pages open meanwhile, their browsers load
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


# Heavy work of one page (a wind record read and run, a map, a year) runs here, not on the
# server's event loop, which every page's moves wait for. The compiled kernels release the GIL
# (windpump._kernels.jit), so two threads use the two cores; Python parts share the GIL in 5 ms
# turns, so the loop keeps answering meanwhile.
OFF_THE_LOOP = ThreadPoolExecutor(max_workers=2, thread_name_prefix="heavy work")


class Runs:
    """A pool of threads for the runs of the pages' moves (``session.Session.move``), counting
    those under way (``DrawAfterMoves`` draws no plots while a move's readouts are to come).

    A pool of its own, not ``OFF_THE_LOOP``: a move is answered while two wind records load.
    Only the run goes here, not Panel's handling of the change: Panel's own thread pool
    (``panel serve --num-threads N``, ``pn.config.nthreads``; Panel's docs, "Enable Automatic
    Threading", https://panel.holoviz.org/how_to/concurrency/threading.html) runs every
    callback of every page in a thread, and a page's two quick moves in two threads at once;
    measured in the hall of 100 against this pool in docs/measured.rst.
    """

    def __init__(self, threads: int = 2):
        self.pool = ThreadPoolExecutor(max_workers=threads, thread_name_prefix="a move's run")
        self.under_way = 0  # runs submitted and not done
        self.lock = threading.Lock()

    def submit(self, document, work: Callable[[], Any], then: Callable[[Any], None]) -> None:
        """``work()`` in a thread, then ``then(result)`` as ``document``'s next-tick callback
        (``in_thread``). Counted until that callback is queued, ahead of any drawing asked for
        later, not until it runs: a page closed meanwhile never runs it."""
        with self.lock:
            self.under_way += 1
        in_thread(self.pool, document, work, then, queued=self._done)

    def _done(self) -> None:
        with self.lock:
            self.under_way -= 1


MOVE_RUNS = Runs()


def every_thread_started(pool: ThreadPoolExecutor, within: float = 10.0) -> int:
    """Start every thread of ``pool`` now, not when a class's work first needs it; the threads
    started (``within`` seconds at most).

    A pool starts a thread when work arrives and none is idle: served, in the middle of a
    class. A thread's objects (its ``Thread``, locks, conditions, the pool's weak references:
    ~40 small objects) live as long as the server, and made among the pages' objects they keep
    the pages' memory once the pages are gone: Python's allocator hands a 1 MiB arena back to
    the system only when every object in it is freed (docs/known-issues.rst). Here each thread
    is given a task that waits for all the others, so none is idle until all have started.
    """
    threads = pool._max_workers  # type: ignore[attr-defined]  # the pool's size, as given
    everyone = threading.Barrier(threads + 1, timeout=within)

    def wait() -> None:
        try:
            everyone.wait()
        except threading.BrokenBarrierError:
            pass

    for _ in range(threads):
        pool.submit(wait)
    try:
        everyone.wait()
    except threading.BrokenBarrierError:
        log.warning("a pool's threads did not start within %.0f s", within)
    return len(pool._threads)  # type: ignore[attr-defined]


def served_document():
    """The document of the page being served (``pn.state.curdoc`` with a session), else None
    (a notebook, the tests: nothing runs off the loop)."""
    import panel as pn

    document = pn.state.curdoc
    if document is None or document.session_context is None:
        return None
    return document


def in_thread(
    pool: ThreadPoolExecutor,
    document,
    work: Callable[[], Any],
    then: Callable[[Any], None],
    queued: Callable[[], None] = lambda: None,
) -> None:
    """``work()`` in ``pool``, then ``then(result)`` as ``document``'s next-tick callback: on the
    event loop, under the document's lock, its curdoc set (Panel's docs, "Modify Bokeh Models",
    https://panel.holoviz.org/how_to/callbacks/server.html, schedule a change of the models from
    a thread on the loop likewise, ``pn.state.execute``). An exception of ``work`` is handed to
    ``then`` as its result; ``queued()`` runs on the loop once ``then`` is queued (or its page
    is gone). Called on the event loop's thread.

    The next-tick callback is added on the loop's thread, not the work's: Bokeh calls
    ``add_next_tick_callback`` thread-safe, but while the loop holds the document
    (``pn.io.hold``, a page drawing) the callback's event is appended to the held events, and
    an ``unhold`` on the loop at that moment can copy and clear that list first: the callback
    was lost, and a page's move never answered (its plots stayed on the earlier design, and the
    page ran no later move).
    """
    from tornado.ioloop import IOLoop

    loop = IOLoop.current()

    def done(future) -> None:  # in the work's thread
        result = future.result()
        loop.add_callback(_next_tick, document, lambda: then(result), queued)

    pool.submit(_outcome, work).add_done_callback(done)


def _next_tick(document, callback: Callable[[], None], queued: Callable[[], None]) -> None:
    try:
        document.add_next_tick_callback(callback)
    except Exception:  # its page closed meanwhile (Bokeh: "already-destroyed Document")
        log.debug("a page closed before its work was done", exc_info=True)
    finally:
        queued()


class FileReaders:
    """A process of its own for reading each uploaded file (``in_a_process``), once the server
    has started them (``start``, app_hooks.py); before that (a notebook, the tests) a file is
    read where it is asked for.

    Reading a file is pure Python: a 10 MB wind CSV is ~1.8 s of it. In a thread it held the GIL
    half of that time, and every other page's move took twice as long meanwhile; in a process
    it costs the server's loop nothing. The process is spawned for the file and ends with it
    (~0.2 s to start: it imports ``windpump``, not numba, Panel or Bokeh), so the ~100 MB a big
    file's Python objects take go back to the system at once, and a reader that dies takes only
    its file with it. One pool per file, not one long-lived pool whose process ends after each
    task (``max_tasks_per_child``): on Python 3.11 to 3.13 such a pool can stop replacing its
    process while tasks are queued, and every later read would wait for ever (CPython
    gh-115634), and with it the threads of ``OFF_THE_LOOP`` waiting for the reads.

    The reader runs ``NICENESS`` steps below the server's CPU priority: on a laptop's two cores
    the server, a reader and the browsers share the CPU, and a reader at the same priority took
    a core from the pages' moves for the ~2 s of a big file. It is lowered as soon as it is
    started, not by the pool's initializer only: that runs once its interpreter has started
    (~0.04 s of a core at the server's priority, just as the file arrives).
    """

    NICENESS = 10  # added to the reader's nice value (Unix): the server's moves come first

    def __init__(self):
        self.started = False

    def start(self) -> None:
        self.started = True

    def stop(self) -> None:
        self.started = False

    def read(self, function: Callable[..., Any], *args: Any) -> Any:
        """``function(*args)`` in a process of its own, waited for (call it off the event loop);
        what it raises is raised here. ``function`` is the core's (``windpump``), imported by
        name in the spawned process: served, this module is a package of Bokeh's making, which
        another process cannot import."""
        if not self.started:
            return function(*args)
        spawn = multiprocessing.get_context("spawn")
        niceness = min(19, os.getpriority(os.PRIO_PROCESS, 0) + self.NICENESS) if _NICE else 0
        # os.setpriority, not a function of this module: the reader could not import it
        lower = (
            {"initializer": os.setpriority, "initargs": (os.PRIO_PROCESS, 0, niceness)}
            if _NICE
            else {}
        )
        mark("reader: starting")
        with ProcessPoolExecutor(max_workers=1, mp_context=spawn, **lower) as pool:
            try:
                future = pool.submit(function, *args)  # starts the process
                for process in getattr(pool, "_processes", {}).values() if _NICE else ():
                    _niced(niceness, process.pid)  # from its interpreter's start, not its task
                mark("reader: submitted")
                value = future.result()
                mark("reader: answered")
                return _read_only(value)
            except BrokenProcessPool:  # the reader died (killed, out of memory)
                raise RuntimeError("the process reading the file stopped") from None


def _niced(niceness: int, pid: int = 0) -> None:
    """Process ``pid`` (0: this one) at ``niceness``, if it still runs."""
    try:
        os.setpriority(os.PRIO_PROCESS, pid, niceness)
    except (ProcessLookupError, PermissionError):
        pass


def _read_only(value: Any) -> Any:
    """The arrays of a frozen dataclass read-only again, as the core made them (pickling does
    not keep the flag)."""
    if dataclasses.is_dataclass(value):
        for field in dataclasses.fields(value):
            item = getattr(value, field.name)
            if isinstance(item, np.ndarray):
                item.flags.writeable = False
    return value


FILE_READERS = FileReaders()


def in_a_process(function: Callable[..., Any], *args: Any) -> Any:
    """``function(*args)`` in the server's file-reading process (``FileReaders.read``)."""
    return FILE_READERS.read(function, *args)


def off_the_loop(work: Callable[[], Any], then: Callable[[Any], None]) -> None:
    """Run ``work()`` off the event loop, then ``then(result)`` on it, under the page's lock.

    Served (``pn.state.curdoc`` has a session): ``work`` in ``OFF_THE_LOOP`` and ``then`` as the
    document's next-tick callback (``in_thread``). Not served (a notebook, the tests): both at
    once, in order. An exception of ``work`` is handed to ``then`` as its result.
    """
    document = served_document()
    if document is None:
        then(_outcome(work))
        return
    in_thread(OFF_THE_LOOP, document, work, then)


SUPERSEDED = object()  # what ``Newest``'s work gives when it was superseded before its turn


class Newest:
    """A tab's newest request for work off the event loop: a request superseded before its turn
    in the pool is not worked out (a leaky pump's map, a day of wind: ~1-2 s of one of the two
    threads every page shares, and a dragged slider asks one a move), and an outcome that comes
    back superseded is not drawn over the newer one's.

    ``same(a, b)``: whether two requests ask for the same work (``==`` by default).

    Examples
    --------
    >>> drawn = []
    >>> maps = Newest()
    >>> maps.ask(1, lambda: "map 1", drawn.append, lambda work, then: None)  # held in the pool
    >>> maps.ask(2, lambda: "map 2", drawn.append, lambda work, then: then(work()))
    >>> drawn
    ['map 2']
    """

    def __init__(self, same: Callable[[Any, Any], bool] = lambda a, b: bool(a == b)):
        self.same = same
        self.wanted: Any = None  # the request last asked for (None: none yet)

    def wants(self, asked: Any) -> bool:
        """Whether ``asked`` is still the request last asked for."""
        return self.wanted is not None and self.same(asked, self.wanted)

    def ask(
        self,
        asked: Any,
        work: Callable[[], Any],
        then: Callable[[Any], None],
        run: Callable[[Callable[[], Any], Callable[[Any], None]], None] | None = None,
    ) -> None:
        """Ask for ``work()`` as request ``asked``, run by ``run`` (``off_the_loop``); ``then``
        draws its outcome (or the exception it raised) on the loop, unless superseded."""
        self.wanted = asked

        @functools.wraps(work)
        def unless_superseded() -> Any:
            return work() if self.wants(asked) else SUPERSEDED

        @functools.wraps(then)
        def drawn(outcome: Any) -> None:
            if outcome is not SUPERSEDED and self.wants(asked):
                then(outcome)

        (run or off_the_loop)(unless_superseded, drawn)

    def supersede(self) -> None:
        """Supersede whatever was asked before without asking for new work here (a file on its
        way by HTTP, worked out once it has come): nothing asked earlier is drawn."""
        self.wanted = object()


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
