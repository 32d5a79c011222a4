"""Progress of long studies (design maps, sweeps, a full year): a tqdm bar in a terminal, a
callback, or none; and the executors a study may run on.

A callback that raises does not lose the study: :func:`reporter` catches its error, warns once
(a ``RuntimeWarning`` naming the error) and calls it no more; the study carries on and returns
every row.
"""

from __future__ import annotations

import sys
import warnings
from collections.abc import Callable

import numpy as np

from .errors import ParameterError

Progress = Callable[[int, int], None]
"""A progress callback: called with (done, total) as work completes."""

PROGRESS = "True, False, None or a callable taking (done, total)"
EXECUTORS = (
    "None (run here) or a concurrent.futures.Executor: an object with a submit method "
    "(a ProcessPoolExecutor, a dask Client's get_executor())"
)


def reporter(progress: bool | Progress | None, total: int, what: str) -> Progress:
    """The callback to report (done, total) to.

    Parameters
    ----------
    progress : bool, callable or None
        A callable (called with (done, total) [runs]), True (a tqdm bar on stderr), False
        (silence), or None: a tqdm bar when stderr is a terminal and tqdm is installed, else
        silence.
    total : int
        How many runs the study makes [-].
    what : str
        The bar's label.

    Returns
    -------
    callable
        Takes (done, total). Should the given callback raise (an ``Exception``), the error is
        caught, a ``RuntimeWarning`` says so once, and the callback is called no more: a failing
        progress bar never loses the study.

    Raises
    ------
    ParameterError
        Naming ``progress`` when it is none of these.

    Examples
    --------
    >>> import warnings
    >>> def broken(done, total):
    ...     raise RuntimeError("the window was closed")
    >>> report = reporter(broken, 2, "sweep")
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     report(1, 2), report(2, 2)
    (None, None)
    >>> len(caught), "the window was closed" in str(caught[0].message)
    (1, True)
    """
    check_progress(progress)
    if callable(progress):
        return _guarded(progress, what)
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

    return _guarded(update, what)


def check_progress(progress: object) -> None:
    """Refuse a ``progress`` that is neither True, False, None nor a callable (ParameterError)."""
    if not (progress is None or isinstance(progress, bool | np.bool_) or callable(progress)):
        raise ParameterError("progress", progress, PROGRESS)


def _guarded(callback: Progress, what: str) -> Progress:
    """``callback``, which warns once and is called no more after it raises."""
    failed = False

    def report(done: int, total: int) -> None:
        nonlocal failed
        if failed:
            return
        try:
            callback(done, total)
        except Exception as error:
            failed = True
            warnings.warn(
                f"the {what}'s progress callback raised {type(error).__name__}: "
                f"{str(error)[:200]}; it is called no more, the {what} carries on",
                RuntimeWarning,
                stacklevel=2,
            )

    return report


def check_executor(executor: object):
    """``executor`` if it is None or can run tasks (has a callable ``submit``), else a
    ParameterError naming ``executor`` and what is allowed.

    Examples
    --------
    >>> check_executor(None) is None
    True
    >>> check_executor("x")
    Traceback (most recent call last):
    ...
    windpump.errors.ParameterError: executor = 'x' is not allowed: executor must be None (run here) or a concurrent.futures.Executor: an object with a submit method (a ProcessPoolExecutor, a dask Client's get_executor())
    """
    if executor is not None and not callable(getattr(executor, "submit", None)):
        raise ParameterError("executor", executor, EXECUTORS)
    return executor


def _silent(done: int, total: int) -> None:
    """Report nothing."""
