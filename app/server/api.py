"""What the page may use of the server: its one front (an import-linter contract in
``pyproject.toml`` keeps the page's modules from the server's other modules).

A page hands its heavy work to the server's threads (``off_the_loop``, ``in_a_process``,
``Newest``), asks for its drawings after the moves (``DRAW_AFTER_MOVES``), knows whether it is
served (``served_document``) and whether the solver is ready (``SOLVER_READY``), marks a step of
its work in the loop's watch (``mark``), settles its memory once built (``TIDY``) and takes a file
the page posted by HTTP (``deliver``). How any of it is done (pools, processes, the route's store,
the framework patches) stays behind this front.
"""

from __future__ import annotations

from .memory import TIDY
from .sessions import SOLVER_READY
from .threads import (
    DRAW_AFTER_MOVES,
    MOVE_RUNS,
    SUPERSEDED,
    Newest,
    in_a_process,
    off_the_loop,
    served_document,
)
from .upload_route import deliver
from .watch import mark

__all__ = [
    "DRAW_AFTER_MOVES",
    "MOVE_RUNS",
    "SOLVER_READY",
    "SUPERSEDED",
    "TIDY",
    "Newest",
    "deliver",
    "in_a_process",
    "mark",
    "off_the_loop",
    "served_document",
]
