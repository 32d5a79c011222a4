"""The server's start and stop (Bokeh's ``on_server_loaded``, ``on_server_unloaded``, handed to
Bokeh by ``app/app_hooks.py``, which Bokeh finds by that name): ready before the first student
opens the page, and light enough for a classroom network."""

from __future__ import annotations

import dataclasses
import gc
import logging
import threading
import time
from collections.abc import Callable

from bokeh.server.tornado import DEFAULT_CHECK_UNUSED_MS, DEFAULT_UNUSED_LIFETIME_MS, BokehTornado
from tornado import httputil
from tornado.httpserver import HTTPServer
from tornado.web import GZipContentEncoding

import windpump
from windpump.run.dynamics import solver_is_cached

from ..compiling import (
    COMPILE,
    COMPILING,
    FIRST_PAGE,
    PARTS,
    Workers,
    compiled_parts,
)
from . import patches
from .memory import TIDY, large_blocks_mapped
from .policy import protect_pages
from .sessions import SOLVER_READY
from .threads import FILE_READERS, MOVE_RUNS, OFF_THE_LOOP, every_thread_started
from .upload_route import serve_uploads
from .watch import hide_session_ids, log_request, quiet_closed_pages, watch_the_loop

log = logging.getLogger("windpump.app")
log.setLevel(logging.INFO)  # `panel serve` shows its own INFO lines only: show these too

# A first start after an install compiles the solver: its first page's full readouts this long
# after the launch (11 s on a quiet 2-core machine, 20-23 s at load 2-4; the averaged theory's
# within ~4 s), measured with benchmarks/bench_app.py first-start (docs/measured.rst); the other
# parts compile in worker processes meanwhile (app/compiling.py), each said when ready.
FIRST_COMPILE_SECONDS = "11-23"

# The parts after the first page's, compiled (or, a later start, loaded) in worker processes
WORKERS = Workers(SOLVER_READY)


# A page's session is built when its HTML is served and lives while its websocket is open. One
# whose page never connects (a bare GET: a link checker, or a script) held a page's memory for as
# long as this: 600 s, and 100 bare GETs held +480 MB for those 10 minutes. Dropped too soon, a
# page whose browser connects late is built a second time when it does (Bokeh's 15 s: 12 pages
# opened at once by 12 browsers on the server's own two cores, 8 were built twice and the burst
# took 91 s instead of 63 s): twice Bokeh's default, checked every CHECK_UNUSED_SESSIONS. A
# session whose page was closed lingers as long; its uploads go at once (upload_route).
# A browser's navigation keeps its page longer while it loads (sessions.wait_for_the_browser).
UNCONNECTED_SESSION_LIFETIME = 30_000  # [ms]
CHECK_UNUSED_SESSIONS = 5_000  # [ms] so a bare session lives 30-35 s

# Tornado closes a connection whose request line and headers pass 64 KB, with no answer at all (the
# browser shows ERR_EMPTY_RESPONSE), and answers 400 to a query of more than 1000 fields; a page's
# link comes back in its session token, in the websocket's request header. Chromium sends URLs up
# to 2 MB: the page opens, and says when it ignored a link too long to read (explorer.MAX_QUERY).
REQUEST_HEADERS_LIMIT = 4 * 1024 * 1024  # [bytes]
# Fields are counted before they are parsed; parsing 20,000 costs the server ~50 ms.
QUERY_FIELDS_LIMIT = 20_000


def on_server_loaded(_server_context) -> None:
    """When ``panel serve app/`` starts: compress what the server sends over HTTP (the page's
    scripts shrink about four times); drop a served page's session its browser never connects
    within 30 s; log requests without their query (a page's link, an upload's name), and no
    line with a session's id (``watch.HideSessionIds``); accept long
    links; and load the solver from numba's cache before the server answers, or, on a first
    start after an install, compile it in the background while pages open (they run their first
    design once it is ready), and then read the Site tab's record (``warm_the_site_tab``) and
    run a first Wind tab's day in the background (``warm_the_wind_tab``); read uploads in a process of their own (``threads.FILE_READERS``);
    map each large block on its own (``large_blocks_mapped``); and start now what a class would
    start for good among its pages (``ready_for_a_class``)."""
    framework_patches()  # Panel's, Bokeh's and param's internals (patches/), said in the log
    watch_the_loop()  # only with WINDPUMP_LOOP_WATCH=<file> (what holds up the loop)
    hide_session_ids()  # no session's id in the server's log, at any level (watch.py)
    quiet_closed_pages()  # a page closed mid-write: one debug line, not a traceback (watch.py)
    large_blocks_mapped()  # a freed upload leaves no heap of freed blocks behind (memory.py)
    servers = bokeh_servers()
    if not servers:
        log.warning("no Bokeh server found: responses uncompressed, Bokeh's session lifetime")
    for server in servers:
        protect_pages(server)  # a Content-Security-Policy with a nonce for the page's scripts
        compress_responses(server)
        drop_unconnected_sessions(server)
        server.settings["log_function"] = log_request  # no query in the access log (watch.py)
    accept_long_links(http_servers())
    serve_uploads(_server_context, servers)  # a wind or site file posted by HTTP (upload_route)
    FILE_READERS.start()  # an upload is read in a process of its own
    ready_for_a_class()
    if solver_is_cached(windpump.Design.seed_example()):
        prepare_solver()  # loaded from numba's cache in under a second: before answering
        TIDY.settle()  # the solver, Panel and Bokeh frozen: no collection walks them again
        # a server stopped before its first start's parts were all compiled left them to this one
        # (each part done is in the cache, and a worker loads it in a second or two)
        threading.Thread(target=compile_the_rest, name="compile the rest", daemon=True).start()
        return
    # A first start: compile while the server answers, so a page's browser loads meanwhile
    # (sessions.first_run_when_ready runs its design once the solver is ready), the first page's
    # part here and the others in worker processes meanwhile (app/compiling.py).
    SOLVER_READY.clear()
    COMPILE.begin()
    threading.Thread(target=compile_the_rest, name="compile the rest", daemon=True).start()
    threading.Thread(target=compile_in_background, name="compile the solver", daemon=True).start()


def framework_patches() -> dict[str, bool]:
    """Apply the framework patches (``patches.apply_all``, as each page does again) and log
    which are in place: a warning naming each one left out (a Panel, Bokeh or param other than
    the ones ``pyproject.toml`` allows, installed anyway)."""
    import bokeh
    import panel
    import param

    patches.apply_all()
    applied = patches.applied()
    missing = [name for name, done in applied.items() if not done]
    versions = f"panel {panel.__version__}, bokeh {bokeh.__version__}, param {param.__version__}"
    if missing:
        log.warning("framework patches not applied on %s: %s", versions, ", ".join(missing))
    else:
        log.info("framework patches: all %d applied (%s)", len(applied), versions)
    return applied


def on_server_unloaded(_server_context) -> None:
    """When the server stops: no file reader or compiling worker left behind."""
    FILE_READERS.stop()
    WORKERS.stop()


# What the server's first upload imports to start its reading process (threads.FileReaders)
READERS_IMPORT = (
    "concurrent.futures.process",
    "multiprocessing.popen_spawn_posix",
    "multiprocessing.queues",
    "multiprocessing.resource_tracker",
    "multiprocessing.spawn",
    "multiprocessing.synchronize",
)


def ready_for_a_class() -> None:
    """Start the threads of the moves' runs and of the heavy work, and import what reading an
    upload imports, before the first page: what a server starts or imports once is kept for
    good, and made in the middle of a class, among its pages' objects, it kept their memory
    after they closed (Python's allocator hands a 1 MiB arena back to the system only once
    every object in it is freed; docs/known-issues.rst)."""
    import importlib

    every_thread_started(MOVE_RUNS.pool)
    every_thread_started(OFF_THE_LOOP)
    for name in READERS_IMPORT:
        importlib.import_module(name)


def compile_in_background() -> None:
    try:
        prepare_solver()
    except Exception:  # never leave the pages waiting: they will compile what they need
        log.exception("compiling the solver failed")
    finally:
        SOLVER_READY.set()
        COMPILE.done(FIRST_PAGE)


def compile_the_rest() -> None:
    """Every part after the first page's, in worker processes (``compiling.Workers``), each
    marked ready as its worker ends; and the Wind tab's first day once its part is ready.

    A later start's pages wait for none of them: each part is most likely in the cache already
    (the workers then only load it), and a page loads it sooner than a worker that gives way to
    the server; one a server stopped before it was done is compiled in a worker meanwhile.
    The parts a worker compiled for this very source (``compiling.compiled_parts``) run in no
    worker again: loading them cost every start seconds of CPU (every test's server, every
    process behind the proxy)."""
    done = compiled_parts() - {FIRST_PAGE}
    for name in done:
        COMPILE.ready[name].set()  # in numba's cache: a page loads it in a second or two
    rest = [part.name for part in PARTS if part.name not in done | {FIRST_PAGE}]
    # the Wind tab's day once its part is ready: at once on a later start, not after every
    # worker (a server's memory then grew for a minute after its start, the test of bare visits'
    # included)
    threading.Thread(target=warm_when_ready, name="warm the Wind tab", daemon=True).start()
    try:
        WORKERS.run(rest)
    except Exception:  # no workers (a checkout not installed): the pages compile what they need
        log.exception("compiling the solver's parts in worker processes failed")
        for name in rest:
            COMPILE.ready[name].set()


# What the page has the server run once its part is ready (``app/app_hooks.py`` registers them:
# the server imports none of the page's tabs): (the part it waits for or None, the warm-up)
WARM_UPS: list[tuple[str | None, Callable[[], None]]] = []


def warm_when_ready() -> None:
    """Run each of ``WARM_UPS`` once its part is ready, in order, off the event loop."""
    for part, warm_up in WARM_UPS:
        if part is not None:
            COMPILE.wait(part)
        warm_up()


def prepare_solver() -> None:
    """Run what a first page runs, saying in the terminal when that means compiling the solver
    (an empty numba cache: the first start after an install) and how long it took."""
    seed = windpump.Design.seed_example()
    cached = solver_is_cached(seed)
    if not cached:
        log.info(
            "%s: the first page's numbers take about %s s (the averaged theory's in a few), then "
            "%d more parts follow in worker processes (pages open meanwhile and show their "
            "numbers once their part is ready); "
            "later starts load it from numba's cache (`python -m windpump_app.compiling` "
            "compiles every part before a start: the README's serve command)",
            COMPILING,
            FIRST_COMPILE_SECONDS,
            len(PARTS) - 1,
        )
    started = time.perf_counter()
    seen = windpump.explore(seed, 600.0)
    windpump.power_budget(seen.run).cycle_means()
    windpump.playback_frames(seen.run)
    done = "loaded from numba's cache" if cached else "compiled"
    log.info("solver %s in %.1f s: serving pages", done, time.perf_counter() - started)


def bokeh_servers() -> list[BokehTornado]:
    """The running Bokeh server's Tornado application (``panel serve`` does not hand it to hooks)."""
    # type(), not isinstance(): the heap holds weak proxies, and isinstance() on a dead one raises
    return [o for o in gc.get_objects() if issubclass(type(o), BokehTornado)]


def http_servers() -> list[HTTPServer]:
    """The running server's Tornado HTTP servers (made before the hooks run)."""
    return [o for o in gc.get_objects() if issubclass(type(o), HTTPServer)]


def accept_long_links(servers: list[HTTPServer]) -> None:
    """Raise the request headers Tornado reads to REQUEST_HEADERS_LIMIT (each new connection
    takes its limit from the server's ``conn_params``) and the fields of a query it parses to
    QUERY_FIELDS_LIMIT (a global of Tornado's, from 6.5.5)."""
    for server in servers:
        params = server.conn_params
        params.max_header_size = max(params.max_header_size or 0, REQUEST_HEADERS_LIMIT)
    config = getattr(httputil, "_DEFAULT_PARSE_BODY_CONFIG", None)
    if config is not None and config.urlencoded.max_arguments < QUERY_FIELDS_LIMIT:
        urlencoded = dataclasses.replace(config.urlencoded, max_arguments=QUERY_FIELDS_LIMIT)
        httputil.set_parse_body_config(dataclasses.replace(config, urlencoded=urlencoded))


def compress_responses(server: BokehTornado) -> None:
    """Gzip HTTP responses (Tornado's ``compress_response`` setting, which ``panel serve`` does
    not expose)."""
    if GZipContentEncoding not in server.transforms:
        server.transforms.append(GZipContentEncoding)


def drop_unconnected_sessions(server: BokehTornado) -> None:
    """Set Bokeh's unused-session lifetime to UNCONNECTED_SESSION_LIFETIME and its check to
    every CHECK_UNUSED_SESSIONS, each unless set on the command line
    (``--unused-session-lifetime``, ``--check-unused-sessions``, which then win). The check is
    already scheduled: restarted at the new period."""
    if server._unused_session_lifetime_milliseconds == DEFAULT_UNUSED_LIFETIME_MS:
        server._unused_session_lifetime_milliseconds = UNCONNECTED_SESSION_LIFETIME
    check = server._cleanup_job
    if check.callback_time == DEFAULT_CHECK_UNUSED_MS:
        running = check.is_running()
        check.stop()
        check.callback_time = CHECK_UNUSED_SESSIONS
        if running:
            check.start()
