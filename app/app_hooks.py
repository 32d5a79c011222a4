"""Server hooks of the directory app: ready before the first student opens the page, and light
enough for a classroom network."""

from __future__ import annotations

import gc
import logging

from bokeh.server.tornado import DEFAULT_UNUSED_LIFETIME_MS, BokehTornado
from tornado.web import GZipContentEncoding

import windpump

log = logging.getLogger("windpump.app")


# A page's session is built when its HTML is served; if its websocket has not connected within
# Bokeh's default 15 s (a class of 30 opening at once on two cores takes minutes), Bokeh drops it
# and builds the page a second time on connection: measured with 12 pages at once, 8 were built
# twice and the burst took 91 s instead of 63 s. A session whose page was closed lingers as long.
UNCONNECTED_SESSION_LIFETIME = 600_000  # [ms]


def on_server_loaded(_server_context) -> None:
    """When ``panel serve app/`` starts: compile (or load from numba's cache) the solver and
    everything a page runs, so the first page opens as fast as the later ones; compress what the
    server sends over HTTP (the page's scripts shrink about four times); and keep a served page's
    session until its browser connects, however busy the server."""
    seed = windpump.Design.seed_example()
    seen = windpump.explore(seed, 600.0)
    windpump.power_budget(seen.run).cycle_means()
    windpump.playback_frames(seen.run)
    servers = bokeh_servers()
    if not servers:
        log.warning("no Bokeh server found: responses uncompressed, Bokeh's session lifetime")
    for server in servers:
        compress_responses(server)
        keep_sessions_until_connected(server)
    log.info("solver compiled and HTTP compression on, before the first page")


def bokeh_servers() -> list[BokehTornado]:
    """The running Bokeh server's Tornado application (``panel serve`` does not hand it to hooks)."""
    # type(), not isinstance(): the heap holds weak proxies, and isinstance() on a dead one raises
    return [o for o in gc.get_objects() if issubclass(type(o), BokehTornado)]


def compress_responses(server: BokehTornado) -> None:
    """Gzip HTTP responses (Tornado's ``compress_response`` setting, which ``panel serve`` does
    not expose)."""
    if GZipContentEncoding not in server.transforms:
        server.transforms.append(GZipContentEncoding)


def keep_sessions_until_connected(server: BokehTornado) -> None:
    """Raise Bokeh's unused-session lifetime to UNCONNECTED_SESSION_LIFETIME, unless it was set
    on the command line (``--unused-session-lifetime``, which then wins)."""
    if server._unused_session_lifetime_milliseconds == DEFAULT_UNUSED_LIFETIME_MS:
        server._unused_session_lifetime_milliseconds = UNCONNECTED_SESSION_LIFETIME
