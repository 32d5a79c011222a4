"""The server's memory: when it collects its garbage (``TIDY``), what a class leaves
behind forgotten once every page has closed, and how glibc maps large blocks."""

from __future__ import annotations

import ctypes
import ctypes.util
import gc
import logging
import math
import time

log = logging.getLogger("windpump.app")

_LIBC_NAME = ctypes.util.find_library("c")
_LIBC = ctypes.CDLL(_LIBC_NAME) if _LIBC_NAME else None


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
    from windpump.run.dynamics import ideal_of

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
