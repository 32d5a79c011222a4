"""Checks of the linkage's inputs, each failing with one clear :class:`~windpump.ParameterError`,
and the small numeric helpers the modules share."""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterable, Mapping, Sequence

import numpy as np

from ..errors import ParameterError
from ..validation import real

# A linkage is geometry alone, so it takes a wider range than a pump's design (whose model
# overflows past 1e12): the compass construction and Newton-Raphson hold for lengths to 1e+-100.
SMALLEST, LARGEST = 1e-100, 1e100
"""Link lengths [m] lie in [SMALLEST, LARGEST]; angles [rad] and signed lengths within +-LARGEST."""

BOUNDED = f"a finite number from {-LARGEST:g} to {LARGEST:g}"
"""The range of an angle [rad] or a signed length [m]: past it, products of two overflow."""


def link_lengths(**lengths: object) -> tuple[float, ...]:
    """The link lengths, each in [SMALLEST, LARGEST] [m], as floats in the order given."""
    return tuple(link_length(name, value) for name, value in lengths.items())


def link_length(name: str, value: object) -> float:
    """One link length [m] in [SMALLEST, LARGEST]."""
    as_float = real(name, value, "m")
    if not SMALLEST <= as_float <= LARGEST:
        raise ParameterError(
            name, value, f"a finite real number from {SMALLEST:g} to {LARGEST:g}", "m"
        )
    return as_float


def bounded(name: str, value: object, unit: str = "") -> float:
    """``value`` as a float if finite and within +-LARGEST (an angle [rad], a signed length [m])."""
    as_float = real(name, value, unit)
    if abs(as_float) > LARGEST:
        raise ParameterError(name, value, BOUNDED, unit)
    return as_float


def angle(name: str, value: object) -> float:
    """An angle [rad], finite and within +-LARGEST."""
    return bounded(name, value, "rad")


def pair(name: str, value: object, unit: str = "rad") -> tuple[float, float]:
    """Two bounded numbers, e.g. a starting (theta2, theta3) [rad]; ``unit`` may be two, "rad, m"."""
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, (str, bytes)) or not isinstance(value, Sequence) or len(value) != 2:
        raise ParameterError(name, value, f"a pair of numbers [{unit}]")
    first, _, second = unit.partition(", ")
    return bounded(f"{name}[0]", value[0], first), bounded(f"{name}[1]", value[1], second or first)


def named_numbers(name: str, value: object) -> dict[str, float]:
    """A mapping of names to bounded numbers [rad or m], as a dict."""
    if not isinstance(value, Mapping):
        raise ParameterError(name, value, "a mapping of names to numbers")
    for key in value:
        if not isinstance(key, str):
            raise ParameterError(name, dict(value), "names (str) as keys")
    return {key: bounded(f"{name}[{key!r}]", number) for key, number in value.items()}


def branch(name: str, value: object) -> int:
    """An assembly: +1 or -1."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or value not in (1, -1):
        raise ParameterError(name, value, "+1 or -1")
    return 1 if value == 1 else -1


def sign(value: float) -> int:
    """-1, 0 or +1."""
    return int(value > 0) - int(value < 0)


def wrap(angle: float) -> float:
    """The angle in [0, 2 pi) [rad] (a tiny negative angle would round to 2 pi)."""
    wrapped = angle % (2 * math.pi)
    return 0.0 if wrapped == 2 * math.pi else wrapped


def show(names: Sequence[str], values: Iterable[float]) -> str:
    """``"theta2 = 0.5, theta3 = 1.5"``, for messages."""
    return ", ".join(f"{name} = {value:.6g}" for name, value in zip(names, values, strict=True))
