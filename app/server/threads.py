"""The server's threads and worker processes: a move's run and a page's heavy work off the
event loop (``MOVE_RUNS``, ``off_the_loop``, ``Newest``), an upload read in a process of its own
(``FILE_READERS``), the answers drawn back under the document's lock (``in_thread``), and the
order of drawing once the moves are answered (``DRAW_AFTER_MOVES``)."""

from __future__ import annotations

import dataclasses
import functools
import logging
import multiprocessing
import os
import threading
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from typing import Any

import numpy as np

from .watch import mark

log = logging.getLogger("windpump.app")

_NICE = hasattr(os, "setpriority")  # Unix: a file-reading process runs below the server's priority


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
    has started them (``start``, hooks.py); before that (a notebook, the tests) a file is
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
