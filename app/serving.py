"""What a long-running classroom server needs besides the page itself."""

from __future__ import annotations

import ctypes
import ctypes.util
import gc

_LIBC_NAME = ctypes.util.find_library("c")
_LIBC = ctypes.CDLL(_LIBC_NAME) if _LIBC_NAME else None


def release_memory(session_context) -> None:  # Bokeh requires exactly this signature
    """When a session closes, free its arrays and hand the memory back to the operating system
    (glibc otherwise keeps freed arenas, and a server that runs through a lecture only grows).

    Lives in a module of its own: Bokeh clears ``main.py``'s globals once a session has started,
    so a callback defined there cannot reach its imports when the session ends.
    """
    gc.collect()
    if _LIBC is not None and hasattr(_LIBC, "malloc_trim"):
        _LIBC.malloc_trim(0)


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
