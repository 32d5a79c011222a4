"""Server hooks of the directory app: ready before the first student opens the page, and light
enough for a classroom network."""

from __future__ import annotations

import gc
import logging

from bokeh.server.tornado import BokehTornado
from tornado.web import GZipContentEncoding

import windpump

log = logging.getLogger("windpump.app")


def on_server_loaded(_server_context) -> None:
    """When ``panel serve app/`` starts: compile (or load from numba's cache) the solver and
    everything a page runs, so the first page opens as fast as the later ones; and compress what
    the server sends over HTTP (the page's scripts shrink about four times)."""
    seed = windpump.Design.seed_example()
    seen = windpump.explore(seed, 600.0)
    windpump.power_budget(seed, seen.run).cycle_means()
    windpump.playback_frames(seen.run)
    compress_responses()
    log.info("solver compiled and HTTP compression on, before the first page")


def compress_responses() -> None:
    """Gzip HTTP responses (Tornado's ``compress_response`` setting, which ``panel serve`` does
    not expose): added to the running Bokeh server's Tornado application."""
    # type(), not isinstance(): the heap holds weak proxies, and isinstance() on a dead one raises
    servers = [o for o in gc.get_objects() if issubclass(type(o), BokehTornado)]
    for server in servers:
        if GZipContentEncoding not in server.transforms:
            server.transforms.append(GZipContentEncoding)
    if not servers:
        log.warning("no Bokeh server found: responses are sent uncompressed")
