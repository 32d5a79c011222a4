"""Wind records for :func:`windpump.simulate`: a gusty day drawn from a site's Weibull wind, or a
measured record read from a CSV file.

A record is a pair of arrays, times [s] from the run's start and wind speeds [m/s]; the run takes
V linear between samples and held past the ends. The rotor's curve follows V(t) by similarity
(``Design.in_wind``).
"""

from __future__ import annotations

import dataclasses
import math
import numbers
import os
import typing

import numpy as np

from ..errors import ParameterError, shown
from ..readers.wind_samples import COLUMNS as COLUMNS
from ..readers.wind_samples import MAX_CSV_BYTES as MAX_CSV_BYTES
from ..readers.wind_samples import MAX_TIME as MAX_TIME
from ..readers.wind_samples import MAX_WIND as MAX_WIND
from ..readers.wind_samples import Samples as Samples
from ..readers.wind_samples import parse_samples as parse_samples
from ..readers.wind_samples import read_samples as read_samples
from ..validation import positive, real, real_array

__all__ = [
    "MAX_CSV_BYTES",
    "MAX_RECORD",
    "MAX_WIND",
    "WindRecord",
    "as_record",
    "gusty",
    "read_csv",
    "weibull_density",
    "weibull_scale",
]


MAX_RECORD = 10_000_000
"""Most samples a wind record may hold (a year at one sample every 3 s)."""


CALLABLE_SAMPLES = 1_000_001
"""Most points a wind given as a function is sampled at (evenly over the run, at most 0.01 s apart
while that fits)."""


MIN_STEP = 1e-6
"""Shortest step between two of a record's times [s] (a microsecond; an anemometer samples at
most ~100 times a second, a windmill's time scales are milliseconds and more), and at least
``MIN_RELATIVE_STEP`` of the times' size: a run lands a step on every sample, and a record
spanning 1e-300 s, or two times a few ulps apart near 1e12 s, gave the wind's slope between
them in round-off (or an overflow) instead of a wind."""

MIN_RELATIVE_STEP = 1e-13
"""Shortest step between two of a record's times, relative to their size (1e-13: about 450
ulps; 0.1 s at ``MAX_TIME``)."""


@dataclasses.dataclass(frozen=True, eq=False)
class WindRecord:
    """Wind speeds ``V`` [m/s] at times ``t`` [s] from the record's start, measured at ``height``
    [m] at the site ``name``; it unpacks as the pair it extends, ``t, V = record``.

    A frozen dataclass rather than a ``typing.NamedTuple``: the site's fields (``height``,
    ``name``, ``month``) have defaults, yet iterating, indexing and ``len`` still see the pair
    (t, V) only, so every caller written for the two-element record (``t, V = record``,
    ``simulate(wind=record)``, :func:`as_record`) works unchanged; a NamedTuple with four fields
    would unpack into four. Records compare by identity (their fields are arrays).

    Attributes
    ----------
    t : ndarray
        Times [s] from the record's start: strictly increasing, from -1e12 to 1e12 (``MAX_TIME``),
        at least one; consecutive ones at least ``MIN_STEP`` (1e-6 s) and ``MIN_RELATIVE_STEP``
        (1e-13) of their size apart.
    V : ndarray
        Wind speeds [m/s], finite, from 0 to ``MAX_WIND``, one a time. The three arrays are
        checked (a ParameterError naming ``t``, ``V`` or ``month``, the first sample at fault
        and the range) and kept read-only, copied unless already read-only floats.
    height : float, default 10.0
        Height of the anemometer above ground [m] (10 m: the meteorological standard).
    name : str, default ""
        The site's name.
    month : ndarray or None, default None
        The calendar month (whole numbers 1 to 12, one a sample) each sample belongs to, when the record has dates (a weather
        file's; for a file that labels each hour at its end, the month the hour lies in); None
        for a record in seconds only (then :func:`windpump.supply` counts its months from 1
        January of a year of 365 days).

    Examples
    --------
    >>> record = WindRecord(np.array([0.0, 3600.0]), np.array([4.0, 6.0]), 10.0, "here")
    >>> t, V = record
    >>> V.tolist(), record.height, len(record)
    ([4.0, 6.0], 10.0, 2)
    >>> record.at_height(40.0).V.round(3).tolist()  # the 1/7 power law
    [4.876, 7.314]
    """

    t: np.ndarray
    V: np.ndarray
    height: float = 10.0
    name: str = ""
    month: np.ndarray | None = None

    def __post_init__(self) -> None:
        t = _field("t", self.t, "s")
        V = _field("V", self.V, "m/s")
        if t.ndim != 1 or t.size == 0:
            raise ParameterError("t", f"an array of shape {t.shape}", "a 1-D array of times", "s")
        if V.shape != t.shape:
            raise ParameterError("V", f"{V.size} speeds", f"one a time ({t.size})", "m/s")
        outside = ~(np.abs(t) <= MAX_TIME)  # (NaN too)
        if outside.any():
            i = int(np.flatnonzero(outside)[0])
            raise ParameterError(
                "t",
                f"t[{i}] = {shown(t[i])}",
                f"increasing times from -{MAX_TIME:g} to {MAX_TIME:g}",
                "s",
            )
        if np.any(np.diff(t) <= 0.0):
            i = int(np.flatnonzero(np.diff(t) <= 0.0)[0]) + 1
            raise ParameterError(
                "t", f"t[{i}] = {shown(t[i])} after t[{i - 1}] = {shown(t[i - 1])}",
                "finite, increasing times", "s",
            )  # fmt: skip
        i = short_step(t)
        if i > 0:
            raise ParameterError(
                "t", f"t[{i}] = {shown(t[i])} after t[{i - 1}] = {shown(t[i - 1])}",
                _STEP_WORDS, "s",
            )  # fmt: skip
        outside = ~((V >= 0.0) & (V <= MAX_WIND))  # (NaN too)
        if outside.any():
            i = int(np.flatnonzero(outside)[0])
            raise ParameterError(
                "V", f"V[{i}] = {shown(V[i])}", f"finite speeds from 0 to {MAX_WIND:g}", "m/s"
            )
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "V", V)
        if self.month is not None:
            object.__setattr__(self, "month", _months(self.month, t.size))
        height = positive("height", self.height, "m")
        if height > MAX_HEIGHT:
            raise ParameterError("height", height, f"a height > 0 and <= {MAX_HEIGHT:g}", "m")
        object.__setattr__(self, "height", height)

    def __iter__(self) -> typing.Iterator[np.ndarray]:
        return iter((self.t, self.V))

    def __len__(self) -> int:
        return 2

    def __getitem__(self, index: int) -> np.ndarray:
        return (self.t, self.V)[index]

    def at_height(self, z: float, shear: float = 1.0 / 7.0) -> WindRecord:
        """The record scaled to the height z [m] by the power law ``V (z / height)^shear``.

        Parameters
        ----------
        z : float
            The height wanted (a rotor's hub) [m], > 0 and at most 500.
        shear : float, default 1/7
            The wind shear exponent [-], from 0 to 1 (0.1 over open water, 1/7 over open land,
            up to about 0.4 over towns and forests).

        Returns
        -------
        WindRecord
            The same times and months, at height z.
        """
        z = real("z", z, "m")
        if not 0.0 < z <= MAX_HEIGHT:  # the whole range, for 0 as for 1e6
            raise ParameterError("z", z, f"a height > 0 and <= {MAX_HEIGHT:g}", "m")
        shear = real("shear", shear)
        if not 0.0 <= shear <= 1.0:
            raise ParameterError("shear", shear, "from 0 to 1", why="a wind shear exponent")
        V = self.V * (z / self.height) ** shear
        if V.size and V.max() > MAX_WIND:
            raise ParameterError("z", z, f"a height where the winds stay <= {MAX_WIND:g} m/s", "m")
        return dataclasses.replace(self, V=_read_only(V), height=z)


MAX_HEIGHT = 500.0
"""Highest hub or anemometer a record may be scaled to or from [m]."""


def _field(name: str, values: object, unit: str) -> np.ndarray:
    """A record's times or speeds as a read-only float array: the caller's own if it already is
    one, else a copy (the record never shares an array its caller may change)."""
    if isinstance(values, np.ndarray) and values.dtype == float and not values.flags.writeable:
        return values

    array = np.array(real_array(name, values, unit), dtype=float)  # a copy
    array.flags.writeable = False
    return array


def _months(values: object, samples: int) -> np.ndarray:
    """A record's months as a read-only int array: whole numbers from 1 to 12, one a sample."""

    allowed = f"whole numbers from 1 to 12, one a sample ({samples})"
    months = real_array("month", values)
    if months.shape != (samples,):
        raise ParameterError("month", f"an array of shape {months.shape}", allowed)
    with np.errstate(invalid="ignore"):
        bad = ~((months >= 1) & (months <= 12) & (months == np.round(months)))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ParameterError("month", f"month[{i}] = {shown(months[i])}", allowed)
    as_int = months.astype(np.int8)
    as_int.flags.writeable = False
    return as_int


def _read_only(values) -> np.ndarray:
    array = np.array(values, dtype=float)
    array.flags.writeable = False
    return array


CALMEST_MEAN = 1e-3
"""Slowest mean wind of a site [m/s] (:func:`weibull_scale`): calm air, far below any site's.
Below it the Weibull scale underflows (at 5e-324 m/s it was 0, and the water a day NaN)."""


def weibull_scale(mean: float, k: float) -> float:
    """Scale c [m/s] of the Weibull distribution of wind speeds with this mean (from 1e-3 to
    150 m/s) and shape k.

    ``c = mean / Gamma(1 + 1/k)``: the distribution's CDF is ``1 - exp(-(V/c)^k)``; k = 2 is the
    Rayleigh wind most sites are close to.

    Examples
    --------
    >>> round(weibull_scale(5.0, 2.0), 4)
    5.6419
    """
    mean = positive("mean_wind", mean, "m/s")
    if not CALMEST_MEAN <= mean <= MAX_WIND:
        raise ParameterError(
            "mean_wind", mean, f"a wind speed from {CALMEST_MEAN:g} to {MAX_WIND:g}", "m/s",
            why="a site's mean wind: below 1 mm/s it is calm",
        )  # fmt: skip
    k = shape(k)
    return mean / math.gamma(1.0 + 1.0 / k)


def weibull_density(V, mean: float, k: float = 2.0):
    """The Weibull density of wind speeds with this mean and shape at speeds V [s/m].

    ``(k/c) (V/c)^(k-1) exp(-(V/c)^k)`` with ``c = weibull_scale(mean, k)``: what
    :func:`windpump.water_per_day` weighs the flow with.

    Examples
    --------
    >>> round(float(weibull_density(5.0, 5.0)), 4)
    0.1432
    """
    c = weibull_scale(mean, k)
    k = shape(k)
    x = np.asarray(V, dtype=float) / c
    return k / c * x ** (k - 1.0) * np.exp(-(x**k))


def shape(k: object) -> float:
    """Return the Weibull shape k as a float if it lies in [0.5, 20] (sites lie in 1.2 ... 4)."""
    value = positive("k", k)
    if not 0.5 <= value <= 20.0:
        raise ParameterError("k", k, "from 0.5 to 20", why="a Weibull shape outside any site's")
    return value


def gusty(
    mean: float,
    duration: float,
    k: float = 2.0,
    time_scale: float = 60.0,
    dt: float = 1.0,
    seed: int | np.random.Generator | None = None,
) -> WindRecord:
    """A reproducible gusty wind whose speeds follow a Weibull distribution exactly.

    A stationary Gaussian Ornstein-Uhlenbeck process z (unit variance, autocorrelation
    ``exp(-lag / time_scale)``: its integral time scale is ``time_scale``), sampled every dt and
    mapped through the Weibull quantile function: ``V = c (-ln(1 - Phi(z)))^(1/k)`` with
    ``c = mean / Gamma(1 + 1/k)``. Every sample is Weibull-distributed; the speeds' own
    correlation is slightly shorter than z's (the map is not linear).

    Parameters
    ----------
    mean : float
        Mean wind speed [m/s], > 0.
    duration : float
        Length of the record [s], > 0; samples at 0, dt, 2 dt, ... up to ``duration``.
    k : float, default 2.0
        Weibull shape [-], 0.5 to 20.
    time_scale : float, default 60.0
        Integral time scale of the gusts [s], > 0.
    dt : float, default 1.0
        Sample spacing [s], > 0; at most ``MAX_RECORD`` samples.
    seed : int, numpy Generator or None
        A whole number >= 0; the same seed gives the same record.

    Returns
    -------
    WindRecord
        ``(t, V)``: pass it as ``simulate(..., wind=record)``.

    Examples
    --------
    >>> record = gusty(5.0, 3600.0, seed=1)
    >>> len(record.t), bool(abs(record.V.mean() - 5.0) < 1.5)
    (3601, True)
    """
    c = weibull_scale(mean, k)
    k = shape(k)
    duration = positive("duration", duration, "s")
    time_scale = positive("time_scale", time_scale, "s")
    dt = positive("dt", dt, "s")
    count = math.floor(duration / dt * (1 + 1e-12)) + 1
    if count > MAX_RECORD:
        raise ParameterError(
            "dt", dt, f">= {duration / (MAX_RECORD - 1):.6g} s for this duration", "s",
            why=f"the record would hold {count:.3g} samples; the bound is {MAX_RECORD}",
        )  # fmt: skip
    rng = _generator(seed)
    from scipy import signal, special

    rho = math.exp(-dt / time_scale)
    z0 = rng.standard_normal()
    shocks = rng.standard_normal(count - 1)
    z = np.empty(count)
    z[0] = z0
    if count > 1:  # z_i = rho z_(i-1) + sqrt(1 - rho^2) e_i, stationary from z_0 ~ N(0, 1)
        z[1:], _ = signal.lfilter([math.sqrt(1.0 - rho * rho)], [1.0, -rho], shocks, zi=[rho * z0])
    V = c * (-special.log_ndtr(-z)) ** (1.0 / k)
    return _frozen(dt * np.arange(count), V)


def _generator(seed: object) -> np.random.Generator:
    """numpy's generator for ``seed``: None, a whole number >= 0, or a Generator itself."""
    if isinstance(seed, np.random.Generator):
        return seed
    allowed = "None, a whole number >= 0 or a numpy Generator"
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, numbers.Integral)):
        raise ParameterError("seed", seed, allowed)
    if seed is not None and seed < 0:
        raise ParameterError("seed", seed, allowed)
    return np.random.default_rng(None if seed is None else int(seed))


def as_record(wind: object, t_end: float) -> WindRecord:
    """A checked, read-only record from what ``simulate(..., wind=...)`` was given.

    A pair (t, V) of equal-length arrays: times finite and strictly increasing, speeds from 0 to
    ``MAX_WIND``. A callable is called with an array of times and sampled evenly over [0, t_end]
    (``CALLABLE_SAMPLES`` points at most, 0.01 s apart while that fits, and 2 ``MIN_STEP`` apart
    at the least, past t_end for a run that short); one that only takes a
    number is called point by point. A bad record raises ParameterError naming ``wind``.
    """
    if callable(wind):
        count = int(min(CALLABLE_SAMPLES, max(1001, math.ceil(t_end / 0.01) + 1)))
        # (a run shorter than 1000 steps of 2 MIN_STEP samples its wind over them, held past
        # t_end: steps of MIN_STEP itself would fall short of it by round-off)
        t = np.linspace(0.0, max(t_end, (count - 1) * 2 * MIN_STEP), count)
        try:
            V = np.asarray(wind(t), dtype=float)
        except Exception:  # a function of one number: call it point by point
            V = None
        if V is None or V.shape != t.shape:
            try:
                V = np.array([float(wind(float(x))) for x in t])
            except Exception as error:
                raise ParameterError(
                    "wind", wind, "a function of time [s] returning wind speeds [m/s]",
                    why=f"calling it failed: {error}",
                ) from None  # fmt: skip
    else:
        try:
            t, V = (np.asarray(a, dtype=float) for a in wind)  # type: ignore[attr-defined]
        except (TypeError, ValueError):
            raise ParameterError(
                "wind", _short(wind), "a pair (t [s], V [m/s]) of arrays, or a function of t"
            ) from None
    return _check(t, V)


def _check(t: np.ndarray, V: np.ndarray) -> WindRecord:
    if t.ndim != 1 or V.shape != t.shape or t.size == 0:
        raise ParameterError(
            "wind",
            f"t of shape {t.shape}, V of shape {V.shape}",
            "two 1-D arrays of one length >= 1",
        )
    if t.size > MAX_RECORD:
        raise ParameterError("wind", f"{t.size} samples", f"at most {MAX_RECORD} samples")
    for name, values, largest in (("times", t, MAX_TIME), ("speeds", V, np.inf)):
        bad = np.flatnonzero(~(np.abs(values) <= largest))  # (NaN too)
        if bad.size:
            allowed = (
                f"finite {name}"
                if largest == np.inf
                else f"times from -{largest:g} to {largest:g} s"
            )
            raise ParameterError("wind", f"{name}[{bad[0]}] = {shown(values[bad[0]])}", allowed)
    outside = (V < 0.0) | (V > MAX_WIND)
    if np.any(outside):
        i = int(np.flatnonzero(outside)[0])
        raise ParameterError(
            "wind", f"V[{i}] = {shown(V[i])} m/s", f"speeds from 0 to {MAX_WIND:g} m/s"
        )
    if np.any(np.diff(t) <= 0.0):
        i = int(np.flatnonzero(np.diff(t) <= 0.0)[0]) + 1
        raise ParameterError(
            "wind",
            f"t[{i}] = {shown(t[i])} s after t[{i - 1}] = {shown(t[i - 1])} s",
            "increasing times",
        )
    i = short_step(t)
    if i > 0:
        raise ParameterError(
            "wind", f"t[{i}] = {shown(t[i])} s after t[{i - 1}] = {shown(t[i - 1])} s",
            _STEP_WORDS,
        )  # fmt: skip
    return _frozen(t, V)


_STEP_WORDS = (
    f"increasing times at least {MIN_STEP:g} s and {MIN_RELATIVE_STEP:g} of their size apart"
)


def short_step(t: np.ndarray) -> int:
    """The index of the first of increasing times ``t`` [s] less than ``MIN_STEP`` (or
    ``MIN_RELATIVE_STEP`` of their size) after the one before it, or 0 when none is.

    Examples
    --------
    >>> short_step(np.array([0.0, 1.0, 2.0])), short_step(np.array([0.0, 1e-300]))
    (0, 1)
    """
    if t.size < 2:
        return 0
    size = np.maximum(np.abs(t[1:]), np.abs(t[:-1]))
    short = np.diff(t) < np.maximum(MIN_STEP, MIN_RELATIVE_STEP * size)
    return int(np.argmax(short)) + 1 if short.any() else 0


def _frozen(t: np.ndarray, V: np.ndarray) -> WindRecord:
    t, V = np.array(t, dtype=float), np.array(V, dtype=float)
    t.flags.writeable = V.flags.writeable = False
    return WindRecord(t, V)


def _short(value: object) -> str:
    return shown(value, 60)


def read_csv(source: bytes | str | os.PathLike, max_bytes: int = MAX_CSV_BYTES) -> WindRecord:
    """Read a measured wind record: time, then wind speed [m/s], one sample per line.

    The time is either seconds (any origin) or an ISO 8601 timestamp (``2026-06-01T12:00:00``,
    ``2026-06-01 12:00``, with or without a zone, one kind throughout); the record's times count
    from its first sample. The rules are the lab torque file's
    (:func:`windpump.read_torque_csv`): ``,``, ``;`` or tab separated, decimal commas with ``;``
    or tab, an optional header row (recognised by its names:
    :func:`windpump.readers.labdata.split_header`), ``#`` comments and blank lines skipped. The file is
    read through the guard every reader goes through (:func:`windpump.readers.files.read_bytes`) and
    parsed a piece at a time (``CHUNK`` characters), so a record near ``MAX_CSV_BYTES`` takes
    memory a few times its size, not a Python object per cell.

    Parameters
    ----------
    source : bytes, str or path
        The file's contents (bytes, or text with a line break) or its path (a ``str`` without a
        line break, or a path object): only a regular file is read.
    max_bytes : int, default MAX_CSV_BYTES
        A longer file is refused before it is parsed [bytes].

    Raises
    ------
    LabDataError
        (a ValueError) saying what is wrong and where: no such file, not a regular file (a pipe,
        a folder, a device), an empty or over-long file, text that is not UTF-8 or holds a NUL
        byte, a line with other than two columns, a time that is neither a number nor a
        timestamp, times that do not increase, a speed that is not a number from 0 to 150 m/s
        (``5x`` in the first row too), fewer than two samples.
    ParameterError
        (a ValueError) for a path that cannot be one: a NUL byte, over ``files.MAX_PATH``
        characters.

    Examples
    --------
    >>> record = read_csv(b"time;speed\\n2026-06-01T12:00:00;4,5\\n2026-06-01T12:00:10;6\\n")
    >>> record.t.tolist(), record.V.tolist()
    ([0.0, 10.0], [4.5, 6.0])
    """
    samples = read_samples(source, max_bytes)
    return _frozen(samples.t, samples.V)
