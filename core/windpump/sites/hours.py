"""A site's hours, shared by :mod:`windpump.sites.yearly` (quasi-steady years, the tank) and
:mod:`windpump.sites.fullyear` (the full equation through a year): a record's hourly winds and months
(:func:`hourly`), who restarts a resting pump (``RESTARTS``), and the quasi-steady hour-by-hour rule
(:mod:`windpump.sites.yearly`'s docstring) that both start from. :mod:`windpump.sites.yearly` re-exports the
public names.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .._kernels import supply as kernels
from ..errors import ParameterError, shown
from ..model.design import Design
from ..model.wind import WindRecord, as_record
from ..units import SECONDS_PER_HOUR
from .site import steady_flow, wind_thresholds

RESTARTS = ("self", "attended")
"""Who restarts a pump at rest: ``"self"`` (the windmill's torque at rest, above V_start) or
``"attended"`` (someone, whenever the wind could carry it: above V_stop)."""

DEFAULT_RESTART = "attended"
"""The restart a year takes when none is given: the one default of :func:`windpump.supply`,
:func:`windpump.tank_for`, :func:`windpump.supply_map`, :func:`windpump.sites.fullyear.full_year`,
``windpump supply`` and ``windpump tank`` (``--restart``) and the explorer's Site tab: someone
restarts a pump a calm stopped. A windmill without torque at rest (T_0 = 0, the paper's) never
starts on its own: with ``"self"`` it never runs."""

HOURS_PER_DAY = 24

DAYS_IN_MONTH = (31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31)
"""A year of 365 days: the months of a record without dates, counted from 1 January."""


def hourly(record) -> tuple[np.ndarray, np.ndarray]:
    """A record's hourly mean winds [m/s] and the hours' calendar months.

    Hour h holds the samples with ``h <= (t - t[0]) / 3600 < h + 1``; a record finer than an
    hour is averaged (the mean of the hour's samples), an hourly one kept as it is. The months
    are the record's (its first sample's in each hour) or, without dates, counted from 1 January
    of a year of 365 days.

    Parameters
    ----------
    record : WindRecord or (t, V) pair
        Times [s] and speeds [m/s]: finite, speeds >= 0, times increasing, a sample in every
        hour from the first to the last.

    Raises
    ------
    ParameterError
        Naming ``record`` and the sample at fault.

    Examples
    --------
    >>> V, month = hourly(([0.0, 1800.0, 3600.0, 5400.0], [4.0, 6.0, 3.0, 3.0]))
    >>> V.tolist(), month.tolist()
    ([5.0, 3.0], [1, 1])
    """
    checked = _record(record)
    hour = ((checked.t - checked.t[0]) // SECONDS_PER_HOUR).astype(np.int64)
    counts = np.bincount(hour)
    empty = np.flatnonzero(counts == 0)
    if empty.size:
        h = int(empty[0])
        i = int(np.searchsorted(hour, h)) - 1  # the last sample before the gap
        raise ParameterError(
            "record",
            f"a gap after t[{i}] = {shown(checked.t[i])} s (no sample in hour {h})",
            "a sample in every hour",
        )
    V = np.bincount(hour, weights=checked.V) / counts
    if checked.month is not None:
        first = np.searchsorted(hour, np.arange(counts.size))
        month = np.asarray(checked.month, dtype=int)[first]
    else:
        month = _calendar_months(counts.size)
    return V, month


def _record(record) -> WindRecord:
    """``record`` checked, as :func:`windpump.model.wind.as_record` checks ``simulate``'s, named."""
    try:
        checked = as_record(record, 1.0)
    except ParameterError as error:
        raise ParameterError("record", error.value, error.allowed, error.unit, error.why) from None
    if isinstance(record, WindRecord):
        month = record.month
        if month is not None and len(month) != len(checked.t):
            raise ParameterError(
                "record", f"{len(month)} months", f"{len(checked.t)}, one a sample"
            )
        return dataclasses.replace(checked, height=record.height, name=record.name, month=month)
    return checked


def _calendar_months(hours: int) -> np.ndarray:
    """The months of ``hours`` hours from 1 January 00:00, years of 365 days."""
    ends = np.cumsum(DAYS_IN_MONTH) * HOURS_PER_DAY
    return np.searchsorted(ends, np.arange(hours) % ends[-1], side="right") + 1


def _choice(name: str, value: object, allowed: tuple[str, ...]) -> str:
    if not isinstance(value, str) or value not in allowed:
        raise ParameterError(name, value, "one of " + ", ".join(map(repr, allowed)))
    return value


@dataclasses.dataclass(frozen=True)
class _Year:
    """The pump's year before the tank: hourly winds, months, running hours and water."""

    V: np.ndarray
    month: np.ndarray
    running: np.ndarray
    pumped: np.ndarray
    V_stop: float
    V_start: float | None
    why: str


def _quasi_steady_year(design: Design, V: np.ndarray, month: np.ndarray, restart: str) -> _Year:
    """The hour-by-hour rule (module docstring) and each running hour's water [m^3]."""
    V_stop, V_start = wind_thresholds(design)
    attended = restart == "attended"
    running = np.zeros(V.size, dtype=np.bool_)
    why = ""
    if not attended and (V_start is None or math.isinf(V_start)):
        why = _never_starts(V_start)
    else:
        kernels.hysteresis(V, math.inf if V_start is None else V_start, V_stop, attended, running)
        if not running.any():
            need = V_stop if attended or V_start is None else V_start  # (V_start: not None)
            why = _never_reached(need, attended)
    pumped = np.where(running, steady_flow(design, V) * SECONDS_PER_HOUR, 0.0)
    return _Year(V, month, running, pumped, V_stop, V_start, why)


def _never_starts(V_start: float | None) -> str:
    """Why a pump that restarts on its own never does, in words a user acts on (a caller adds
    how its user has someone start it)."""
    if V_start is None:
        return (
            "the windmill has no torque at rest (T_0 = 0), so no wind starts it on its own: "
            "someone must start it"
        )
    return (
        "the windmill's torque at rest is too small to start the pump in any wind: "
        "someone must start it"
    )


def _never_reached(need: float, attended: bool) -> str:
    """Why a pump never runs in this record: the wind it needs never blows."""
    if attended:
        return (
            f"the wind never reaches {need:.3g} m/s (V_stop), the least in which the windmill "
            "can carry the pump"
        )
    return (
        f"the wind never reaches {need:.3g} m/s (V_start), the least in which the pump starts "
        "on its own"
    )
