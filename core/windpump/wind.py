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
import os
import typing

import numpy as np

from .errors import ParameterError, cut, shown
from .labdata import LabDataError, _is_number, check_columns, read_rows, split_header
from .validation import positive, real

MAX_RECORD = 10_000_000
"""Most samples a wind record may hold (a year at one sample every 3 s)."""

MAX_CSV_BYTES = 50_000_000
"""Largest wind file read [bytes] (a day at one sample a second takes about 1.5 MB)."""

CALLABLE_SAMPLES = 1_000_001
"""Most points a wind given as a function is sampled at (evenly over the run, at most 0.01 s apart
while that fits)."""

MAX_WIND = 150.0
"""Fastest wind speed a record may hold [m/s] (the strongest gusts measured are about 113 m/s)."""

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
        Times [s] from the record's start: finite and strictly increasing, at least one.
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
        if not np.all(np.isfinite(t)):
            i = int(np.flatnonzero(~np.isfinite(t))[0])
            raise ParameterError("t", f"t[{i}] = {float(t[i])!r}", "finite, increasing times", "s")
        if np.any(np.diff(t) <= 0.0):
            i = int(np.flatnonzero(np.diff(t) <= 0.0)[0]) + 1
            raise ParameterError(
                "t", f"t[{i}] = {float(t[i])!r} after t[{i - 1}] = {float(t[i - 1])!r}",
                "finite, increasing times", "s",
            )  # fmt: skip
        outside = ~((V >= 0.0) & (V <= MAX_WIND))  # (NaN too)
        if outside.any():
            i = int(np.flatnonzero(outside)[0])
            raise ParameterError(
                "V", f"V[{i}] = {float(V[i])!r}", f"finite speeds from 0 to {MAX_WIND:g}", "m/s"
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
    from .validation import real_array

    array = np.array(real_array(name, values, unit), dtype=float)  # a copy
    array.flags.writeable = False
    return array


def _months(values: object, samples: int) -> np.ndarray:
    """A record's months as a read-only int array: whole numbers from 1 to 12, one a sample."""
    from .validation import real_array

    allowed = f"whole numbers from 1 to 12, one a sample ({samples})"
    months = real_array("month", values)
    if months.shape != (samples,):
        raise ParameterError("month", f"an array of shape {months.shape}", allowed)
    with np.errstate(invalid="ignore"):
        bad = ~((months >= 1) & (months <= 12) & (months == np.round(months)))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ParameterError("month", f"month[{i}] = {float(months[i])!r}", allowed)
    as_int = months.astype(np.int8)
    as_int.flags.writeable = False
    return as_int


def _read_only(values) -> np.ndarray:
    array = np.array(values, dtype=float)
    array.flags.writeable = False
    return array


def weibull_scale(mean: float, k: float) -> float:
    """Scale c [m/s] of the Weibull distribution of wind speeds with this mean and shape k.

    ``c = mean / Gamma(1 + 1/k)``: the distribution's CDF is ``1 - exp(-(V/c)^k)``; k = 2 is the
    Rayleigh wind most sites are close to.

    Examples
    --------
    >>> round(weibull_scale(5.0, 2.0), 4)
    5.6419
    """
    mean = positive("mean_wind", mean, "m/s")
    if mean > MAX_WIND:
        raise ParameterError("mean_wind", mean, f"a wind speed > 0 and <= {MAX_WIND:g}", "m/s")
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
    (``CALLABLE_SAMPLES`` points at most, 0.01 s apart while that fits); one that only takes a
    number is called point by point. A bad record raises ParameterError naming ``wind``.
    """
    if callable(wind):
        count = int(min(CALLABLE_SAMPLES, max(1001, math.ceil(t_end / 0.01) + 1)))
        t = np.linspace(0.0, t_end, count)
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
    for name, values in (("times", t), ("speeds", V)):
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise ParameterError(
                "wind", f"{name}[{bad[0]}] = {float(values[bad[0]])!r}", f"finite {name}"
            )
    outside = (V < 0.0) | (V > MAX_WIND)
    if np.any(outside):
        i = int(np.flatnonzero(outside)[0])
        raise ParameterError(
            "wind", f"V[{i}] = {float(V[i])!r} m/s", f"speeds from 0 to {MAX_WIND:g} m/s"
        )
    if np.any(np.diff(t) <= 0.0):
        i = int(np.flatnonzero(np.diff(t) <= 0.0)[0]) + 1
        raise ParameterError(
            "wind",
            f"t[{i}] = {float(t[i])!r} s after t[{i - 1}] = {float(t[i - 1])!r} s",
            "increasing times",
        )
    return _frozen(t, V)


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
    :func:`windpump.labdata.split_header`), ``#`` comments and blank lines skipped.

    Raises
    ------
    LabDataError
        (a ValueError) saying what is wrong and where: an empty or over-long file, text that is
        not UTF-8 or holds a NUL byte, a line with other than two columns, a time that is neither
        a number nor a timestamp, times that do not increase, a speed that is not a number from 0
        to 150 m/s (``5x`` in the first row too), fewer than two samples.

    Examples
    --------
    >>> record = read_csv(b"time;speed\\n2026-06-01T12:00:00;4,5\\n2026-06-01T12:00:10;6\\n")
    >>> record.t.tolist(), record.V.tolist()
    ([0.0, 10.0], [4.5, 6.0])
    """
    rows = read_rows(source, max_bytes, COLUMNS)
    _header, rows = split_header(
        rows, lambda cell: _is_number(cell) or _time(cell) is not None, COLUMNS
    )
    times: list[float | datetime.datetime] = []
    speeds: list[float] = []
    kind = None
    for number, cells in rows:
        check_columns(number, cells, COLUMNS)
        moment = _time(cells[0])
        if moment is None:
            raise LabDataError(
                f"'{_cut(cells[0])}' is neither seconds nor an ISO timestamp", number, 1
            )
        if kind is None:
            kind = _kind(moment)
        elif _kind(moment) != kind:
            raise LabDataError(f"'{_cut(cells[0])}' mixes {_kind(moment)} with {kind}", number, 1)
        speed = _speed(cells[1], number)
        if times and _seconds(moment, times[0]) <= _seconds(times[-1], times[0]):
            raise LabDataError(
                f"the time '{_cut(cells[0])}' does not come after the line before", number, 1
            )
        times.append(moment)
        speeds.append(speed)
    if len(times) < 2:
        raise LabDataError(
            f"the file has {len(times)} sample(s); a wind record needs at least 2 lines of {COLUMNS}"
        )
    t = np.array([_seconds(moment, times[0]) for moment in times])
    return _frozen(t, np.array(speeds))


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
