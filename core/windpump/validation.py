"""Checks on user input that fail with one clear message: parameter, value, allowed range."""

from __future__ import annotations

import math
import numbers

import numpy as np


class ParameterError(ValueError):
    """A parameter is outside its allowed range.

    Attributes
    ----------
    name : str
        The parameter's name, as the caller spelled it (``"L"``, ``"t_end"``).
    value : object
        The value that was rejected.
    allowed : str
        The allowed range, in words (``"> 0"``, ``"> R = 0.04 m"``).
    """

    def __init__(self, name: str, value: object, allowed: str, unit: str = "", why: str = ""):
        self.name, self.value, self.allowed = name, value, allowed
        shown = f"{value!r} {unit}".rstrip()
        message = f"{name} = {shown} is not allowed: {name} must be {allowed}"
        super().__init__(f"{message} ({why})" if why else message)


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
