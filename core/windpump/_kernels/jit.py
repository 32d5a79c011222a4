"""The decorator every kernel is compiled with."""

from __future__ import annotations

import os
from pathlib import Path

from numba import njit, types
from numba.core import caching
from numba.core.registry import CPUDispatcher

KERNELS = Path(__file__).resolve().parent
# The pointwise equations the kernels compile (the model's, windpump.model.equations)
EQUATIONS = KERNELS.parent / "model" / "equations.py"


class KernelsStamp:
    """A cache locator's source stamp for a kernel of this folder: every kernel module's size and
    modification time, and the model's pointwise equations', not its own file's only.

    numba stamps a cached kernel with its own source file, yet the code it caches holds its
    callees' from other modules: a change to ``stepping.py`` alone left ``driver.integrate``
    loaded from the cache with the old steps (numba's known limit). Any change to a kernel
    module now recompiles every kernel, as a fresh install does.
    """

    @classmethod
    def from_function(cls, py_func, py_file):
        if Path(py_file).resolve().parent != KERNELS and Path(py_file).resolve() != EQUATIONS:
            return None  # another folder's function: numba's own locators
        return super().from_function(py_func, py_file)

    def get_source_stamp(self):
        stamps = []
        for path in [*sorted(KERNELS.glob("*.py")), EQUATIONS]:
            status = os.stat(path)
            stamps.append((path.name, status.st_mtime, status.st_size))
        return tuple(stamps)


def stamp_every_kernel_module() -> None:
    """Put :class:`KernelsStamp` locators first in numba's list (its own for the cache in
    ``NUMBA_CACHE_DIR`` and beside the source), once; numba's private names have moved between
    versions (``_CacheImpl`` became ``CacheImpl``), so a numba without them keeps its own."""
    implementation = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl", None)
    if implementation is None or any(
        issubclass(locator, KernelsStamp) for locator in implementation._locator_classes
    ):
        return
    stamped = []
    for name in ("UserProvidedCacheLocator", "InTreeCacheLocator"):
        locator = getattr(caching, name, None) or getattr(caching, f"_{name}", None)
        if locator is not None:
            stamped.append(type(f"Kernels{name.lstrip('_')}", (KernelsStamp, locator), {}))
    implementation._locator_classes[:0] = stamped


stamp_every_kernel_module()

# NumPy's error model drops the zero-division checks. fastmath allows fused multiply-adds and
# reciprocals only: no-NaN/no-inf assumptions would break step rejection, approximate library
# functions would cost accuracy, and reassociation made a freshly compiled kernel and the same
# kernel loaded from numba's cache differ in the last bit (a sweep on dask workers then differed
# from the serial one); without it they agree, at ~5 % of the seed example's time.
OPTIONS = {"error_model": "numpy", "fastmath": {"contract", "arcp", "nsz"}}


class OneSpecialisation(CPUDispatcher):
    """A dispatcher that compiles one specialisation per argument *type*.

    numba types a constant argument of a call between kernels as a literal of its value
    (``record(out, 0, ...)``, ``final=True``) and compiles the callee once per value: a first
    start compiled 20 such copies of small kernels, each one again in every kernel that links it
    (1.2 s of 9 s). The literal folded into a copy is folded just as well once the callee is
    inlined into its caller, so the numbers are the same.
    """

    def get_call_template(self, args, kws):
        args = tuple(types.unliteral(a) for a in args)
        kws = {name: types.unliteral(a) for name, a in kws.items()}
        return super().get_call_template(args, kws)


def kernel(function, *, by_value=False, **options):
    """Compile ``function`` lazily (on its first call) and cache it on disk when it can.

    Compiled once per argument type (:class:`OneSpecialisation`), or with ``by_value`` once per
    value of each constant argument, for the kernels whose branches those values select.

    An install without a writable ``__pycache__`` (read-only site-packages, no
    ``NUMBA_CACHE_DIR``) has no cache locator: numba refuses ``cache=True`` there, so compile
    without caching rather than fail the import.

    Every kernel releases the GIL while it runs (``nogil``): a server that runs a long one (a
    week of wind) in a thread keeps answering its other pages meanwhile.
    """
    try:
        dispatcher = njit(cache=True, nogil=True, **OPTIONS, **options)(function)
    except RuntimeError:  # "cannot cache function ...: no locator available"
        dispatcher = njit(cache=False, nogil=True, **OPTIONS, **options)(function)
    if not by_value:
        dispatcher.__class__ = OneSpecialisation  # the same dispatcher, typing calls by type
    return dispatcher


def by_value_kernel(function):
    """A :func:`kernel` compiled once per value of each constant argument: ``rates`` and
    ``dp5_step`` once per domain (ANGLE, TIME), each without the other domain's branch, as
    they always were (the steps' code, and so their numbers and speed, stay as measured)."""
    return kernel(function, by_value=True)


def parallel_kernel(function):
    """A :func:`kernel` whose ``numba.prange`` loops run on every core."""
    return kernel(function, parallel=True)


def inline_kernel(function):
    """A :func:`kernel` spliced into its caller's code (numba's ``inline="always"``) before
    either is compiled: a piece of one long kernel given a name, with no compiled copy of its own.

    Free when it takes and returns numbers (the caller compiles as if it were written in place).
    Each array it takes is one more reference to it, counted atomically on every call unless
    numba can prune the pair: the driver's helpers called per sub-step or per segment take
    numbers only (four arrays passed per sub-step cost six cylinders 12 %).
    """
    return kernel(function, inline="always")
