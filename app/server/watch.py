"""What the server writes down: its access log without queries, no session's id in any log
(``hide_session_ids``), no traceback for a page that closed mid-write (``quiet_closed_pages``),
and what holds up its event loop (``LoopWatch``, ``mark``)."""

from __future__ import annotations

import asyncio
import gc
import json
import logging
import os
import re
import threading
import time
from typing import Any

log = logging.getLogger("windpump.app")


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


def quiet_closed_pages(loop: asyncio.AbstractEventLoop | None = None) -> None:
    """A page closed while the server wrote to it: tornado's write task ends in its
    ``WebSocketClosedError``, which nothing awaits, and asyncio printed a traceback ("Task
    exception was never retrieved") in the server's terminal, as if something had failed. Such
    a task is logged as one debug line; every other exception goes to the handler there was
    (asyncio's own by default). ``loop``: the server's (tornado's current loop's by default)."""
    from tornado.ioloop import IOLoop
    from tornado.websocket import WebSocketClosedError

    loop = loop or IOLoop.current().asyncio_loop
    before = loop.get_exception_handler()

    def handle(loop: asyncio.AbstractEventLoop, context: dict[str, Any]) -> None:
        if isinstance(context.get("exception"), WebSocketClosedError):
            log.debug("a page closed while the server wrote to it")
        elif before is not None:
            before(loop, context)
        else:
            loop.default_exception_handler(context)

    loop.set_exception_handler(handle)


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
