"""Checks on user input that fail with one clear message: parameter, value, allowed range."""

from __future__ import annotations

import math
import numbers

import numpy as np

from .errors import ParameterError, shown

__all__ = [
    "ParameterError",
    "finite_array",
    "flag",
    "non_negative",
    "positive",
    "real",
    "rod_ratio",
    "whole",
]


def real(name: str, value: object, unit: str = "") -> float:
    """Return ``value`` as a finite float, or raise :class:`ParameterError` naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ParameterError(name, value, "a finite real number", unit)
    try:
        as_float = float(value)
    except OverflowError:  # an integer beyond double precision (10**400)
        as_float = math.inf
    if not math.isfinite(as_float):
        raise ParameterError(name, value, "a finite real number", unit)
    return as_float


def positive(name: str, value: object, unit: str = "") -> float:
    """Return ``value`` as a float if it is finite and > 0."""
    as_float = real(name, value, unit)
    if as_float <= 0.0:
        raise ParameterError(name, value, "a finite number > 0", unit)
    return as_float


def non_negative(name: str, value: object, unit: str = "") -> float:
    """Return ``value`` as a float if it is finite and >= 0."""
    as_float = real(name, value, unit)
    if as_float < 0.0:
        raise ParameterError(name, value, "a finite number >= 0", unit)
    return as_float


def rod_ratio(value: object) -> float:
    """Return L/R as a float if the rod can reach the crank (L/R > 1)."""
    as_float = real("L_over_R", value)
    if as_float <= 1.0:
        raise ParameterError("L_over_R", value, "> 1", why="the rod cannot reach the crank")
    return as_float


def finite_array(
    name: str, value, unit: str = "", minimum: float | None = None, maximum: float | None = None
):
    """Return ``value`` as a float array if every element is a finite real number (from
    ``minimum`` to ``maximum``); text, None, booleans and integers beyond double precision are
    refused."""
    array = real_array(name, value, unit)
    bad = np.flatnonzero(~np.isfinite(array))
    if bad.size:
        where = f"{name}[{bad[0]}]" if array.ndim else name
        raise ParameterError(
            name, f"{where} = {shown(array.flat[bad[0]])}", "finite real numbers", unit
        )
    if minimum is not None and array.size and array.min() < minimum:
        raise ParameterError(name, float(array.min()), f">= {minimum:g} everywhere", unit)
    if maximum is not None and array.size and array.max() > maximum:
        raise ParameterError(name, float(array.max()), f"<= {maximum:g} everywhere", unit)
    return array


def real_array(name: str, value, unit: str = "") -> np.ndarray:
    """``value`` as a float array if it holds real numbers only (NaN and inf included; text,
    None and booleans refused; integers beyond double precision become inf)."""
    allowed = "finite real numbers"
    try:
        raw = np.asarray(value)
        if raw.dtype.kind == "O" and all(
            isinstance(x, numbers.Real) and not isinstance(x, bool) for x in raw.flat
        ):
            with np.errstate(over="ignore"):
                return np.array([_float(x) for x in raw.flat]).reshape(raw.shape)
        if raw.dtype.kind not in "iuf":
            raise ParameterError(name, value, allowed, unit)
        return raw.astype(float, copy=False)
    except (TypeError, ValueError, OverflowError) as error:
        if isinstance(error, ParameterError):
            raise
        raise ParameterError(name, value, allowed, unit) from None


def _float(x: numbers.Real) -> float:
    try:
        return float(x)
    except OverflowError:  # an integer beyond double precision
        return math.inf if x > 0 else -math.inf  # type: ignore[operator]


def whole(name: str, value: object, lowest: int, highest: int) -> int:
    """Return ``value`` as an int if it is a whole number in [lowest, highest]."""
    allowed = f"a whole number from {lowest} to {highest}"
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ParameterError(name, value, allowed)
    try:
        as_float = float(value)
    except OverflowError:
        raise ParameterError(name, value, allowed) from None
    if not (
        math.isfinite(as_float) and as_float == int(as_float) and lowest <= as_float <= highest
    ):
        raise ParameterError(name, value, allowed)
    return int(as_float)


def flag(name: str, value: object) -> bool:
    """Return ``value`` as a bool if it is one (Python's or numpy's)."""
    if not isinstance(value, (bool, np.bool_)):
        raise ParameterError(name, value, "True or False")
    return bool(value)


SMALLEST, LARGEST = 1e-12, 1e12
"""The magnitudes a design's numbers may take [their SI units]: far past any machine, and where
every figure of the model stays finite with every field anywhere in the range (the load
rho_w g h A R multiplies five of them; tests/whole_core/test_edges.py probes the corners). At 1e100 the load
overflowed to inf and the wind thresholds divided by zero."""


def fraction(name: str, value: object, unit: str = "") -> float:
    """Return ``value`` as a float if it lies in (0, 1]: an efficiency or a coefficient."""
    allowed = "a real number above 0 and at most 1"
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ParameterError(name, value, allowed, unit)
    as_float = _float(value)
    if not 0.0 < as_float <= 1.0:
        raise ParameterError(name, value, allowed, unit)
    return as_float


def magnitude(
    name: str,
    value: object,
    unit: str = "",
    zero: bool = False,
    highest: float = LARGEST,
    lowest: float | None = None,
) -> float:
    """Return ``value`` as a float if it lies in [SMALLEST, highest], or [0, highest] when
    ``zero``, or [lowest, highest] when ``lowest`` is given."""
    if lowest is None:
        lowest = 0 if zero else SMALLEST
    allowed = f"a finite real number from {lowest:g} to {highest:g}"
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ParameterError(name, value, allowed, unit)
    as_float = _float(value)
    if not lowest <= as_float <= highest:
        raise ParameterError(name, value, allowed, unit)
    return as_float
