"""Wind records for :func:`windpump.simulate`: a gusty day drawn from a site's Weibull wind, or a
measured record read from a CSV file.

A record is a pair of arrays, times [s] from the run's start and wind speeds [m/s]; the run takes
V linear between samples and held past the ends. The rotor's curve follows V(t) by similarity
(``Design.in_wind``).
"""

from __future__ import annotations

import dataclasses
import datetime
import math
import numbers
import operator
import os
import typing
from collections.abc import Iterator

import numpy as np

from .errors import LabDataError, ParameterError, cut, shown
from .labdata import _cells, _is_number, check_columns, contents, decoded, split_header
from .validation import positive, real, real_array

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

MAX_CSV_BYTES = 50_000_000
"""Largest wind file read [bytes] (a day at one sample a second takes about 1.5 MB)."""

CALLABLE_SAMPLES = 1_000_001
"""Most points a wind given as a function is sampled at (evenly over the run, at most 0.01 s apart
while that fits)."""

MAX_WIND = 150.0
"""Fastest wind speed a record may hold [m/s] (the strongest gusts measured are about 113 m/s)."""

MAX_TIME = 1e12
"""Largest time a record may hold, either side of zero [s] (about 31,700 years): the core's
largest number (``validation.LARGEST``); two such times are still apart by a finite number."""

MIN_STEP = 1e-6
"""Shortest step between two of a record's times [s] (a microsecond; an anemometer samples at
most ~100 times a second, a windmill's time scales are milliseconds and more), and at least
``MIN_RELATIVE_STEP`` of the times' size: a run lands a step on every sample, and a record
spanning 1e-300 s, or two times a few ulps apart near 1e12 s, gave the wind's slope between
them in round-off (or an overflow) instead of a wind."""

MIN_RELATIVE_STEP = 1e-13
"""Shortest step between two of a record's times, relative to their size (1e-13: about 450
ulps; 0.1 s at ``MAX_TIME``)."""

COLUMNS = "two columns: time [s] or an ISO timestamp, then wind speed [m/s]"


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
    :func:`windpump.labdata.split_header`), ``#`` comments and blank lines skipped. The file is
    read through the guard every reader goes through (:func:`windpump.files.read_bytes`) and
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


CHUNK = 1 << 20
"""Characters of a wind CSV's text parsed at a time (a piece ends at a line's end)."""


@dataclasses.dataclass(frozen=True)
class Samples:
    """A wind CSV's samples (:func:`read_samples`): times from the first [s], speeds [m/s], each
    one's line in the file (None unless asked for) and, for timestamps, its calendar month (None
    for seconds)."""

    t: np.ndarray
    V: np.ndarray
    line: np.ndarray | None
    month: np.ndarray | None


def read_samples(
    source: bytes | str | os.PathLike, max_bytes: int = MAX_CSV_BYTES, lines: bool = False
) -> Samples:
    """What :func:`read_csv` reads, with each sample's month and (if ``lines``) line in the file:
    a site's year needs them (:func:`windpump.read_weather`). Its rules, its errors.

    The whole-file checks come first, as the lab reader makes them (UTF-8, no NUL byte, not
    empty, the separator any line uses, a header); then the lines, a piece of ``CHUNK``
    characters at a time. A piece of plain samples is converted in bulk; one that is not (a
    quoted cell, a trailing separator, a bad line...) is read line by line, which says which
    line is at fault, in the same words.

    Examples
    --------
    >>> data = b"t,V\\n# calm\\n2026-01-31T23:00,4\\n2026-02-01T00:00,5\\n"
    >>> samples = read_samples(data, lines=True)
    >>> samples.t.tolist(), samples.line.tolist(), samples.month.tolist()
    ([0.0, 3600.0], [3, 4], [1, 2])
    """
    return parse_samples(decoded(contents(source, max_bytes, what=None)), lines)


def parse_samples(text: str, lines: bool = False) -> Samples:
    """:func:`read_samples` of a file's text, once read and decoded (``labdata.decoded``)."""
    first = next((row for piece in _pieces(text) for row in zip(*_kept(*piece), strict=True)), None)
    if first is None:
        raise LabDataError(f"the file is empty; it needs {COLUMNS}")
    separator = _separator(text)
    header, _rows = split_header(
        [(int(first[0]), _cells(first[1], separator))],
        lambda cell: _is_number(cell) or _time(cell) is not None,
        COLUMNS,
    )
    reader = _Reader(separator, lines)
    for piece in _pieces(text):
        numbers, rows = _kept(*piece)
        if header is not None and len(numbers) and numbers[0] == first[0]:
            numbers, rows = numbers[1:], rows[1:]
        reader.read(numbers, rows)
    return reader.samples()


def _pieces(text: str) -> Iterator[tuple[int, str, list[str]]]:
    """``text`` in pieces of about ``CHUNK`` characters, each ending at a line's end: the number
    of its first line, the piece and its lines (``str.splitlines``'s)."""
    start, number = 0, 1
    while start < len(text):
        end = _piece_end(text, start, CHUNK)
        piece = text[start:end]
        lines = piece.splitlines()
        yield number, piece, lines
        number += len(lines)
        start = end


def _piece_end(text: str, start: int, size: int) -> int:
    """Where a piece from ``start`` ends: after the last ``\\n`` or ``\\r`` (of a ``\\r\\n``,
    after both) within ``size`` characters, or the first beyond them; or the text's end."""
    end = start + size
    if end >= len(text):
        return len(text)
    cut = max(text.rfind("\n", start, end), text.rfind("\r", start, end))
    if cut < 0:  # a line longer than a piece
        found = [i for i in (text.find("\n", end), text.find("\r", end)) if i >= 0]
        if not found:
            return len(text)
        cut = min(found)
    if text.startswith("\r\n", cut):
        cut += 1
    return cut + 1


def _kept(start: int, piece: str, lines: list[str]) -> tuple[np.ndarray, list[str]]:
    """The numbers of a piece's lines that are neither blank nor a ``#`` comment, and those
    lines, stripped."""
    stripped = [line.strip() for line in lines]
    if "#" not in piece and "" not in stripped:  # (most pieces: every line kept)
        return np.arange(start, start + len(stripped)), stripped
    kept = [i for i, line in enumerate(stripped) if line and line[0] != "#"]
    return start + np.array(kept, dtype=np.int64), [stripped[i] for i in kept]


def _separator(text: str) -> str:
    """Tab, then ``;``, then ``,``: the first one a line of data (or the header) uses."""
    if "\t" not in text and ";" not in text:
        return ","
    semicolon = False
    for start, piece, lines in _pieces(text):
        if "\t" in piece or ";" in piece:
            kept = "\n".join(_kept(start, piece, lines)[1])
            if "\t" in kept:
                return "\t"
            semicolon = semicolon or ";" in kept
    return ";" if semicolon else ","


class _Reader:
    """The samples of a wind CSV's rows, read a piece at a time; the kind of time, the first
    sample's (the origin) and the last one's seconds carried from piece to piece. Each sample's
    line is kept when ``lines`` asks for it."""

    def __init__(self, separator: str, lines: bool):
        self.separator, self.lines = separator, lines
        self.kind: str | None = None
        self.origin: float | datetime.datetime | None = None
        self.last: float | None = None
        self.pieces: dict[str, list[np.ndarray]] = {"t": [], "V": [], "line": [], "month": []}

    def read(self, numbers: np.ndarray, rows: list[str]) -> None:
        """Read a piece's rows (stripped lines) and keep their samples."""
        if not rows:
            return
        t, V, month = self._in_bulk(rows) or self._line_by_line(numbers, rows)
        self.pieces["t"].append(t)
        self.pieces["V"].append(V)
        if month is not None and self.kind != "seconds":
            self.pieces["month"].append(month)
        if self.lines:  # (in 4 bytes a line while they fit)
            small = numbers[-1] < np.iinfo(np.int32).max
            self.pieces["line"].append(numbers.astype(np.int32) if small else numbers)

    def samples(self) -> Samples:
        """The samples of every piece read, each array joined once (its pieces then let go)."""
        count = sum(map(len, self.pieces["t"]))
        if count < 2:
            raise LabDataError(
                f"the file has {count} sample(s); a wind record needs at least 2 lines of {COLUMNS}"
            )
        joined = {}
        for name, pieces in self.pieces.items():
            joined[name] = np.concatenate(pieces) if pieces else None
            pieces.clear()
        t, V = joined["t"], joined["V"]
        assert t is not None and V is not None
        return Samples(t, V, joined["line"], joined["month"])

    def _in_bulk(self, rows: list[str]) -> tuple[np.ndarray, np.ndarray, np.ndarray | None] | None:
        """The piece's times, speeds and months if every row is two plain cells (no quotes, no
        space around the separator) of a time of the record's kind and a speed in range, in
        order; else None (then :meth:`_line_by_line` reads it)."""
        separators = list(map(operator.methodcaller("count", self.separator), rows))
        if separators.count(1) != len(separators):
            return None
        text = self.separator.join(rows)
        if self.separator != ",":
            text = text.replace(",", ".")  # decimal commas
        cells = text.split(self.separator)
        times, speeds = cells[0::2], cells[1::2]
        try:
            V = np.array(list(map(float, speeds)))
        except ValueError:
            return None
        if not np.all((V >= 0.0) & (V <= MAX_WIND)):  # (NaN fails too)
            return None
        month = None
        try:
            seconds = np.array(list(map(float, times)))
        except ValueError:
            moments = _timestamps(times)
            if moments is None:
                return None
            kinds = {_kind(moment) for moment in moments}
            kind = kinds.pop()
            if kinds or self.kind not in (None, kind):
                return None
            start = self.origin if isinstance(self.origin, datetime.datetime) else moments[0]
            seconds = np.array([(moment - start).total_seconds() for moment in moments])
            month = np.array([moment.month for moment in moments], dtype=np.int8)
            origin: float | datetime.datetime = start
        else:
            kind = "seconds"
            if not np.all(np.abs(seconds) <= MAX_TIME) or self.kind not in (None, kind):
                return None
            origin = self.origin if isinstance(self.origin, float) else float(seconds[0])
            seconds -= origin
        steps = np.diff(seconds, prepend=-np.inf if self.last is None else self.last)
        if not np.all(steps > 0.0):
            return None
        self.kind, self.origin, self.last = kind, origin, float(seconds[-1])
        return seconds, V, month

    def _line_by_line(
        self, numbers: np.ndarray, rows: list[str]
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The piece's times, speeds and months, a row at a time: the first row at fault raises
        its error."""
        t: list[float] = []
        V: list[float] = []
        months: list[int] = []
        for number, line in zip(numbers.tolist(), rows, strict=True):
            cells = _cells(line, self.separator)
            check_columns(number, cells, COLUMNS)
            moment = _time(cells[0])
            if moment is None:
                raise LabDataError(
                    f"'{_cut(cells[0])}' is neither seconds nor an ISO timestamp", number, 1
                )
            if isinstance(moment, float) and not abs(moment) <= MAX_TIME:
                raise LabDataError(
                    f"the time '{_cut(cells[0])}' is past {MAX_TIME:g} s either side of 0",
                    number,
                    1,
                )
            if self.kind is None:
                self.kind, self.origin = _kind(moment), moment
            elif _kind(moment) != self.kind:
                raise LabDataError(
                    f"'{_cut(cells[0])}' mixes {_kind(moment)} with {self.kind}", number, 1
                )
            speed = _speed(cells[1], number)
            seconds = _seconds(moment, self.origin)
            if self.last is not None and seconds <= self.last:
                raise LabDataError(
                    f"the time '{_cut(cells[0])}' does not come after the line before", number, 1
                )
            self.last = seconds
            t.append(seconds)
            V.append(speed)
            months.append(moment.month if isinstance(moment, datetime.datetime) else 0)
        return np.array(t), np.array(V), np.array(months, dtype=np.int8)


def _timestamps(cells: list[str]) -> list[datetime.datetime] | None:
    """The cells as timestamps, if every one is one and none is a number (``20260601`` is
    seconds, as :func:`_time` reads it); else None."""
    if any(map(str.isdigit, cells)):
        return None
    try:
        return [datetime.datetime.fromisoformat(cell.replace(" ", "T", 1)) for cell in cells]
    except ValueError:
        return None


def _time(cell: str) -> float | datetime.datetime | None:
    """Seconds (a finite number) or a timestamp, or None."""
    if _is_number(cell):
        value = float(cell)
        return value if math.isfinite(value) else None
    try:
        return datetime.datetime.fromisoformat(cell.replace(" ", "T", 1))
    except ValueError:
        return None


def _kind(moment: float | datetime.datetime) -> str:
    if isinstance(moment, numbers.Real):
        return "seconds"
    assert isinstance(moment, datetime.datetime)
    return "timestamps without a zone" if moment.tzinfo is None else "timestamps with a zone"


def _seconds(moment, origin) -> float:
    if isinstance(moment, datetime.datetime):
        return (moment - origin).total_seconds()
    return float(moment - origin)


def _speed(cell: str, line: int) -> float:
    try:
        value = float(cell)
    except ValueError:
        raise LabDataError(f"'{_cut(cell)}' is not a number", line, 2) from None
    if not 0.0 <= value <= MAX_WIND:  # (NaN fails too)
        raise LabDataError(
            f"the wind speed '{_cut(cell)}' is not a number from 0 to {MAX_WIND:g} m/s", line, 2
        )
    return value


def _cut(cell: str) -> str:
    return cut(cell, 20)
