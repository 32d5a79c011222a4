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
