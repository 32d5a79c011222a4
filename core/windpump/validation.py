"""Checks on user input that fail with one clear message: parameter, value, allowed range."""

from __future__ import annotations

import math
import numbers

import numpy as np

from .errors import ParameterError

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
    as_float = float(value)
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


def finite_array(name: str, value, unit: str = "", minimum: float | None = None):
    """Return ``value`` as a float array if every element is finite (and >= ``minimum``)."""
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(name, value, "finite real numbers", unit) from None
    if not np.all(np.isfinite(array)):
        raise ParameterError(name, "non-finite values", "finite real numbers", unit)
    if minimum is not None and array.size and array.min() < minimum:
        raise ParameterError(name, float(array.min()), f">= {minimum:g} everywhere", unit)
    return array


def whole(name: str, value: object, lowest: int, highest: int) -> int:
    """Return ``value`` as an int if it is a whole number in [lowest, highest]."""
    allowed = f"a whole number from {lowest} to {highest}"
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ParameterError(name, value, allowed)
    as_float = float(value)
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


SMALLEST, LARGEST = 1e-100, 1e100
"""The magnitudes a design's numbers may take [their SI units]: far past any machine, and where the
model's groups (R+^3, L^2, I0 R+^2 ...) stay within double precision."""


def magnitude(name: str, value: object, unit: str = "") -> float:
    """Return ``value`` as a float if it lies in [SMALLEST, LARGEST]."""
    as_float = real(name, value, unit)
    if not SMALLEST <= as_float <= LARGEST:
        allowed = f"a finite number from {SMALLEST:g} to {LARGEST:g}"
        raise ParameterError(name, value, allowed, unit)
    return as_float
