"""The decorator every kernel is compiled with."""

from __future__ import annotations

from numba import njit

# NumPy's error model drops the zero-division checks. fastmath allows fused multiply-adds and
# reciprocals only: no-NaN/no-inf assumptions would break step rejection, approximate library
# functions would cost accuracy, and reassociation made a freshly compiled kernel and the same
# kernel loaded from numba's cache differ in the last bit (a sweep on dask workers then differed
# from the serial one); without it they agree, at ~5 % of the seed example's time.
OPTIONS = {"error_model": "numpy", "fastmath": {"contract", "arcp", "nsz"}}


def kernel(function, **options):
    """Compile ``function`` lazily (on its first call) and cache it on disk when it can.

    An install without a writable ``__pycache__`` (read-only site-packages, no
    ``NUMBA_CACHE_DIR``) has no cache locator: numba refuses ``cache=True`` there, so compile
    without caching rather than fail the import.
    """
    try:
        return njit(cache=True, **OPTIONS, **options)(function)
    except RuntimeError:  # "cannot cache function ...: no locator available"
        return njit(cache=False, **OPTIONS, **options)(function)


def parallel_kernel(function):
    """A :func:`kernel` whose ``numba.prange`` loops run on every core."""
    return kernel(function, parallel=True)
