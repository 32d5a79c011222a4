"""The year in full: the equation of motion (:func:`windpump.simulate`) through a whole wind record,
in chunks of days that run here or on any executor, for ``supply(..., method="full")``.

The wind is the record's hourly means, each at the middle of its hour and linear between them
(held before the first and after the last), times, with ``turbulence`` > 0, gusts inside each hour
from :func:`windpump.model.wind.gusty`: a Weibull factor of mean 1 whose standard deviation is the
turbulence intensity (the shape k that gives that coefficient of variation), integral time scale
``GUST_TIME_SCALE``, one seeded stream per chunk, so a year is the same on any executor.

Each chunk starts where the quasi-steady year (:func:`windpump.supply`) has the pump at the
chunk's start: at rest, or running at alpha+ in the first hour's wind; at rest at the year's start.
Attended (``restart="attended"``, the default) a pump that comes to rest is restarted (at alpha+)
at the start of the next hour whose mean wind reaches V_stop.
"""

from __future__ import annotations

import dataclasses
import math
import typing

import numpy as np

from ..averaging.theory import running_speeds
from ..errors import ParameterError
from ..model.design import Design
from ..model.wind import as_record, gusty
from ..progress import Progress, check_executor, check_progress, reporter
from ..run import dynamics  # dynamics.MAX_STEPS read at each year (a test may lower it)
from ..run.dynamics import estimated_steps, simulate
from ..units import SECONDS_PER_HOUR
from ..validation import real, whole
from .hours import DEFAULT_RESTART, RESTARTS, _choice, _quasi_steady_year, hourly
from .site import wind_thresholds

if typing.TYPE_CHECKING:
    import concurrent.futures

__all__ = [
    "FullYear",
    "full_year",
]


GUST_TIME_SCALE = 60.0
"""Integral time scale of the gusts inside an hour [s]."""

GUST_DT = 1.0
"""Spacing of the gusty wind's samples [s]."""

SAMPLE_DT = 60.0
"""Spacing of a chunk run's samples [s] (a divisor of an hour: the hours' water is read at them)."""

THETA0 = math.pi / 2
"""Crank angle each chunk starts at [rad]."""


@dataclasses.dataclass(frozen=True, eq=False)
class FullYear:
    """The year's hours from the full equation of motion.

    Attributes
    ----------
    running : ndarray of bool
        Whether the crank turned for at least half of the hour.
    pumped : ndarray
        Water pumped in the hour [m^3].
    chunks : int
        How many runs the year was cut into.
    """

    running: np.ndarray
    pumped: np.ndarray
    chunks: int


def turbulence_shape(intensity: float) -> float:
    """The Weibull shape k [-] whose coefficient of variation is ``intensity`` [-].

    ``sqrt(Gamma(1 + 2/k) / Gamma(1 + 1/k)^2 - 1) = intensity``, solved by bisection on log k;
    the gust model's shapes (0.5 to 20) reach intensities from 0.063 to 2.24.

    Examples
    --------
    >>> round(turbulence_shape(0.5227), 3)  # Rayleigh: k = 2
    2.0
    """
    from scipy import optimize

    intensity = real("turbulence", intensity)
    low, high = _variation(20.0), _variation(0.5)
    if not low <= intensity <= high:
        raise ParameterError(
            "turbulence", intensity, f"0 (no gusts) or from {low:.3f} to {high:.3f}",
            why="the gust model's Weibull shapes k from 0.5 to 20",
        )  # fmt: skip
    return float(
        math.exp(
            optimize.brentq(
                lambda x: _variation(math.exp(x)) - intensity,
                math.log(0.5),
                math.log(20.0),
                xtol=1e-12,
            )
        )
    )


def _variation(k: float) -> float:
    """Coefficient of variation of the Weibull distribution of shape k."""
    g1, g2 = math.gamma(1.0 + 1.0 / k), math.gamma(1.0 + 2.0 / k)
    return math.sqrt(g2 / (g1 * g1) - 1.0)


@dataclasses.dataclass(frozen=True)
class _Chunk:
    """What one chunk's run needs (picklable, for an executor)."""

    design: Design
    V: np.ndarray  # hourly means, with one hour either side (repeated at the year's ends)
    first: int  # the chunk's first hour in the year
    hours: int
    theta_dot0: float
    attended: bool
    V_stop: float
    shape: float  # gusts' Weibull k, 0: none
    seed: int | None


def full_year(
    design: Design,
    record,
    *,
    restart: str = DEFAULT_RESTART,
    turbulence: float = 0.0,
    seed: int | None = 0,
    chunk_days: int = 7,
    executor: concurrent.futures.Executor | None = None,
    progress: bool | Progress | None = False,
) -> FullYear:
    """The year's hours (running, water) from the full equation of motion through ``record``.

    Parameters
    ----------
    design : Design
    record : WindRecord or (t, V) pair
        The wind at the rotor (:func:`windpump.supply`'s).
    restart : {"self", "attended"}, default "attended", keyword-only
        Who restarts a resting pump, as :func:`windpump.supply` (``DEFAULT_RESTART``).
    turbulence : float, keyword-only
        Turbulence intensity inside each hour [-]: 0 (the hourly means, linear between them) or
        from 0.063 to 2.24 (:func:`turbulence_shape`).
    seed : int or None, keyword-only
        Seed of the gusts (a whole number >= 0, or None for fresh ones).
    chunk_days : int, keyword-only
        Days per run, 1 to 366.
    executor : concurrent.futures.Executor or None, keyword-only
        Runs the chunks (a ``ProcessPoolExecutor``, dask's ``Client.get_executor()``); None: here.
    progress : bool, callable or None, keyword-only
        As :func:`windpump.sweep`: a callback given (done, total) chunks, a tqdm bar, or none.

    Returns
    -------
    FullYear
    """
    restart = _choice("restart", restart, RESTARTS)
    chunk_days, shape = full_options(turbulence, seed, chunk_days, executor, progress)
    V, month = hourly(record)
    steady = _quasi_steady_year(design, V, month, restart)
    V_stop, _ = wind_thresholds(design)
    padded = np.concatenate(([V[0]], V, [V[-1]]))
    chunks = []
    for index, (first, hours) in enumerate(_spans(design, V, chunk_days * 24, shape > 0.0)):
        ran = first > 0 and bool(steady.running[first - 1])
        theta_dot0 = _running_speed(running_speeds, design, V[first]) if ran else 0.0
        chunk_seed = None if seed is None else int(seed) * 1_000_003 + index
        chunks.append(
            _Chunk(design, padded[first : first + hours + 2], first, hours, theta_dot0,
                   restart == "attended", V_stop, shape, chunk_seed)
        )  # fmt: skip
    results = _run_all(chunks, executor, reporter(progress, len(chunks), "year"))
    running = np.concatenate([r[0] for r in results])
    pumped = np.concatenate([r[1] for r in results])
    return FullYear(running, pumped, len(chunks))


def full_options(
    turbulence: object, seed: object, chunk_days: object, executor: object, progress: object
) -> tuple[int, float]:
    """The full year's options checked (each a ParameterError naming it): ``chunk_days`` as an
    int and the gusts' Weibull shape (0: no gusts) from ``turbulence``."""
    chunk_days = whole("chunk_days", chunk_days, 1, 366)
    intensity = real("turbulence", turbulence)
    shape = 0.0 if intensity == 0.0 else turbulence_shape(intensity)
    if seed is not None:
        whole("seed", seed, 0, 2**63 - 1)
    check_executor(executor)
    check_progress(progress)
    return chunk_days, shape


def _spans(design: Design, V: np.ndarray, hours: int, gusty: bool) -> list[tuple[int, int]]:
    """The chunks (first hour, hours): ``hours`` long, halved until each run's estimated work
    (:func:`windpump.run.dynamics.estimated_steps`, a gust's bend a second added) is at most half
    the integrator's bound ``MAX_STEPS``, so a windy site's week is cut rather than refused."""
    todo = [(first, min(hours, V.size - first)) for first in range(0, V.size, hours)]
    spans = []
    while todo:
        first, length = todo.pop(0)
        t = (np.arange(length) + 0.5) * SECONDS_PER_HOUR
        record = as_record((t, V[first : first + length]), length * SECONDS_PER_HOUR)
        work = estimated_steps(design, length * SECONDS_PER_HOUR, record)
        work *= 2.0 if gusty else 1.0
        work += length * SECONDS_PER_HOUR / GUST_DT if gusty else 0.0
        if work <= dynamics.MAX_STEPS / 2 or length == 1:
            spans.append((first, length))
        else:
            half = length // 2
            todo[:0] = [(first, half), (first + half, length - half)]
    return spans


def _running_speed(running_speeds, design: Design, V: float) -> float:
    """alpha+ [rad/s] in the wind V, 0 where the pump cannot run."""
    alpha = float(running_speeds(design, V=V).alpha_plus)
    return alpha if math.isfinite(alpha) and alpha > 0.0 else 0.0


def _run_all(chunks, executor, report):
    if executor is None:
        results = []
        for done, chunk in enumerate(chunks, 1):
            results.append(run_chunk(chunk))
            report(done, len(chunks))
        return results
    futures = [executor.submit(run_chunk, chunk) for chunk in chunks]
    results = []
    for done, future in enumerate(futures, 1):
        results.append(future.result())
        report(done, len(chunks))
    return results


def chunk_wind(chunk: _Chunk) -> tuple[np.ndarray, np.ndarray]:
    """The chunk's wind (t [s] from its start, V [m/s]): hourly means at mid-hour, linear between,
    times the gust factor."""
    t_mid = (np.arange(-1, chunk.hours + 1) + 0.5) * SECONDS_PER_HOUR
    if chunk.shape == 0.0:
        return t_mid, chunk.V
    duration = chunk.hours * SECONDS_PER_HOUR
    rng = np.random.default_rng(chunk.seed)
    factor = gusty(1.0, duration, chunk.shape, GUST_TIME_SCALE, GUST_DT, seed=rng)
    V = np.interp(factor.t, t_mid, chunk.V) * factor.V
    return factor.t, np.minimum(V, 150.0)


def run_chunk(chunk: _Chunk) -> tuple[np.ndarray, np.ndarray]:
    """One chunk's hours: (running, pumped [m^3]).

    One run to the chunk's end; attended, a run ends where the crank first comes to rest and the
    next starts (at alpha+) at the first hour from then whose mean wind reaches V_stop, as it
    does at the chunk's start when the pump rests there.
    """
    t, V = chunk_wind(chunk)
    end = chunk.hours * SECONDS_PER_HOUR
    boundaries = np.arange(chunk.hours + 1) * SECONDS_PER_HOUR
    volume = np.zeros(chunk.hours + 1)
    turning = np.zeros(chunk.hours)
    start, theta_dot0, base = 0.0, chunk.theta_dot0, 0.0
    while start < end:
        if chunk.attended and theta_dot0 == 0.0:
            start, theta_dot0 = _restart(chunk, boundaries, start)
            if start >= end:
                break
        run = simulate(
            chunk.design, end - start, THETA0, theta_dot0, wind=(t - start, V), sample_dt=SAMPLE_DT
        )
        t_run = run.t + start
        stop = end
        if chunk.attended and len(run.stops):
            stop = max(float(run.stops[0]) + start, start + SAMPLE_DT)
        inside = t_run <= stop
        here = (boundaries >= start) & (boundaries <= stop)
        volume[here] = base + np.interp(boundaries[here], t_run[inside], run.volume[inside])
        _add_turning(turning, t_run[inside], run.theta_dot[inside])
        base = base + float(np.interp(stop, t_run, run.volume))
        volume[boundaries > stop] = base
        start, theta_dot0 = stop, 0.0
    return turning >= 0.5 * SECONDS_PER_HOUR, np.diff(volume)


def _restart(chunk: _Chunk, boundaries: np.ndarray, after: float) -> tuple[float, float]:
    """When someone restarts a resting pump, from ``after`` [s]: the first hour's start whose mean
    wind reaches V_stop, and the crank speed they give it (alpha+ in that wind, or the usual kick
    where the averaged theory has none); the chunk's end when no hour does."""
    later = np.flatnonzero((boundaries[:-1] >= after) & (chunk.V[1:-1] >= chunk.V_stop))
    if not later.size:
        return float(boundaries[-1]), 0.0
    hour = int(later[0])
    alpha = float(running_speeds(chunk.design, V=chunk.V[hour + 1]).alpha_plus)
    return float(boundaries[hour]), alpha if math.isfinite(alpha) and alpha > 0.0 else KICK


KICK = 3.0
"""Crank speed [rad/s] someone gives a resting pump where the averaged theory has no running
speed (as :func:`windpump.run_in_wind`'s kick)."""


def _add_turning(turning: np.ndarray, t: np.ndarray, theta_dot: np.ndarray) -> None:
    """Add to each hour the seconds the crank turned (theta_dot > 0 at a sample: its interval)."""
    if t.size < 2:
        return
    moving = (theta_dot[:-1] > 0.0) | (theta_dot[1:] > 0.0)
    hour = np.minimum((t[:-1] // SECONDS_PER_HOUR).astype(int), turning.size - 1)
    np.add.at(turning, hour, np.where(moving, np.diff(t), 0.0))
