"""Progress of long studies (design maps, sweeps): a tqdm bar in a terminal, a callback, or none."""

from __future__ import annotations

import sys
from collections.abc import Callable

Progress = Callable[[int, int], None]
"""A progress callback: called with (done, total) as work completes."""


def reporter(progress: bool | Progress | None, total: int, what: str) -> Progress:
    """The callback to report (done, total) to.

    ``progress`` is a callable (used as is), True (a tqdm bar on stderr), False (silence), or
    None: a tqdm bar when stderr is a terminal and tqdm is installed, else silence.
    """
    if callable(progress):
        return progress
    if progress is None:
        progress = sys.stderr.isatty()
    if not progress:
        return _silent
    try:
        from tqdm.auto import tqdm
    except ImportError:  # tqdm is optional: no bar without it
        return _silent
    bar = tqdm(total=total, desc=what, unit="run", leave=False)

    def update(done: int, total: int) -> None:
        bar.update(done - bar.n)
        if done >= total:
            bar.close()

    return update


def _silent(done: int, total: int) -> None:
    """Report nothing."""
