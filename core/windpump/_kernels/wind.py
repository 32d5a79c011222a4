"""The wind the rotor turns in, as the kernels see it: none (the design's own V_ref) or a record.

A run without a wind record passes ``None``; these functions are numba overloads that resolve on
the argument's type when compiled, so the steady run carries no wind code at all (it stays as
fast as before winds existed) and a run in a record compiles its own specialisation.
"""

from __future__ import annotations

import math
import typing

import numpy as np
from numba import types
from numba.extending import overload

from .jit import OPTIONS

JIT_OPTIONS: typing.Any = OPTIONS  # (numba's stubs type the options narrower than it takes)


class Wind(typing.NamedTuple):
    """A wind record: V / V_ref at sample times, linear between them, held past the ends."""

    t: np.ndarray  # sample times [s], increasing
    scale: np.ndarray  # V / V_ref at those times [-], >= 0
    spacing: float  # t[i] = t[0] + i spacing when the samples are evenly spaced, else 0 [s]


def wind_scale(t, wind):
    """V(t) / V_ref [-]: 1 without a record; linear between a record's samples, held past its
    ends."""
    if wind is None:
        return 1.0
    return float(np.interp(t, wind.t, wind.scale))


def has_record(wind):
    """Whether the run has a wind record (else the rotor turns in V_ref throughout)."""
    return wind is not None


def rise_above(t, threshold, wind):
    """The first time >= t [s] at which V / V_ref reaches ``threshold`` (the linear crossing
    inside the interval where it does), or inf: never without a record."""
    if wind is None:
        return math.inf
    return _rise_above(t, threshold, wind)


@overload(wind_scale, jit_options=JIT_OPTIONS)
def _wind_scale_overload(t, wind):
    if isinstance(wind, types.NoneType):
        return lambda t, wind: 1.0
    return _interpolate


@overload(has_record, jit_options=JIT_OPTIONS)
def _has_record_overload(wind):
    if isinstance(wind, types.NoneType):
        return lambda wind: False
    return lambda wind: True


@overload(rise_above, jit_options=JIT_OPTIONS)
def _rise_above_overload(t, threshold, wind):
    if isinstance(wind, types.NoneType):
        return lambda t, threshold, wind: math.inf
    return _rise_above


def _interpolate(t, wind):
    times, scale = wind.t, wind.scale
    last = times.shape[0] - 1
    if t <= times[0]:
        return scale[0]
    if t >= times[last]:
        return scale[last]
    if wind.spacing > 0.0:  # evenly spaced: the interval by division, checked against round-off
        i = min(max(int((t - times[0]) / wind.spacing), 0), last - 1)
        while times[i] > t:
            i -= 1
        while times[i + 1] < t:
            i += 1
    else:
        i = np.searchsorted(times, t, side="right") - 1
    weight = (t - times[i]) / (times[i + 1] - times[i])
    return scale[i] + weight * (scale[i + 1] - scale[i])


def _rise_above(t, threshold, wind):
    times, scale = wind.t, wind.scale
    if wind_scale(t, wind) >= threshold:
        return t
    first = max(np.searchsorted(times, t, side="right") - 1, 0)
    for i in range(first, times.shape[0] - 1):
        if scale[i + 1] >= threshold:
            a = max(t, times[i])
            s_a = wind_scale(a, wind)
            return a + (threshold - s_a) / (scale[i + 1] - s_a) * (times[i + 1] - a)
    return math.inf


def next_kink(t, wind):
    """The record's first sample time after t [s], where V(t) has a kink (steps land on it), or
    inf: none without a record, or past its last sample."""
    if wind is None:
        return math.inf
    return _next_kink(t, wind)


@overload(next_kink, jit_options=JIT_OPTIONS)
def _next_kink_overload(t, wind):
    if isinstance(wind, types.NoneType):
        return lambda t, wind: math.inf
    return _next_kink


def _next_kink(t, wind):
    i = np.searchsorted(wind.t, t, side="right")
    return wind.t[i] if i < wind.t.shape[0] else math.inf
