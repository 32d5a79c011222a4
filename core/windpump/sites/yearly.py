"""A year of water at a site: the pump hour by hour through a wind record, a tank between it and
the demand, and the tank a demand needs.

Quasi-steady (the default method), each hour's mean wind V_h sets the hour. Attended
(``restart="attended"``, the default: ``DEFAULT_RESTART``), someone restarts a resting pump and
it runs whenever ``V_h >= V_stop``; on its own (``restart="self"``) it runs when
``V_h >= V_start``, or when it ran the hour before and ``V_h >= V_stop``
(:func:`windpump.wind_thresholds`: a running pump carries on down to V_stop, a resting one needs
V_start). A running hour pumps ``steady_flow(design, V_h) x 3600 s``
(:func:`windpump.steady_flow`). The year starts at rest. In full (``method="full"``) the
equation of motion is integrated through the whole record instead (:func:`windpump.simulate`).

The tank (capacity C [m^3], 0: none) meets the demand hour by hour::

    available = level + pumped;  delivered = min(demand_h, available);
    shortfall = demand_h - delivered;  spilled = max(0, available - delivered - C);
    level = available - delivered - spilled

and starts the year where the year ends (a typical year, repeated): from full, the year is run
again from its end level until that level repeats to ``LEVEL_TOLERANCE`` (at most
``MOST_PASSES`` passes).
"""

from __future__ import annotations

import dataclasses
import math
import typing

import numpy as np

from .._kernels import supply as kernels
from ..errors import ParameterError
from ..model.design import Design
from ..model.wind import WindRecord
from ..progress import Progress
from ..validation import finite_array, non_negative, real, real_array
from .fullyear import full_options, full_year
from .hours import DAYS_IN_MONTH as DAYS_IN_MONTH  # re-exported: the hours moved to hours.py
from .hours import DEFAULT_RESTART as DEFAULT_RESTART
from .hours import HOURS_PER_DAY as HOURS_PER_DAY
from .hours import RESTARTS as RESTARTS
from .hours import _choice, _quasi_steady_year, _Year, hourly

if typing.TYPE_CHECKING:
    import concurrent.futures

METHODS = ("quasi-steady", "full")
"""How the hours are found: the averaged theory in each hour's mean wind, or the full equation
of motion through the record."""

LEVEL_TOLERANCE = 1e-6
"""How close [m^3] the tank's level at the year's end must come to its start."""

MOST_PASSES = 20
"""Most passes through the year looking for the level it repeats at."""

DRY_TOLERANCE = 1e-9
"""Shortfall in a day [m^3] (a microlitre) beyond which the day counts as dry: above the
round-off of the tank's books."""

MONTH_NAMES = ("Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec")


@dataclasses.dataclass(frozen=True, eq=False)
class MonthTable:
    """The year by calendar month (rows: the months the record holds, in calendar order).

    Attributes
    ----------
    month : ndarray of int
        Calendar month, 1 (January) to 12.
    pumped, demand, delivered, shortfall : ndarray
        Water pumped, asked for, delivered and not delivered in the month [m^3].
    running_hours : ndarray of int
        Hours the pump ran [h].
    starts : ndarray of int
        Times a resting pump started [-].
    """

    month: np.ndarray
    pumped: np.ndarray
    demand: np.ndarray
    delivered: np.ndarray
    shortfall: np.ndarray
    running_hours: np.ndarray
    starts: np.ndarray

    COLUMNS: typing.ClassVar[tuple[str, ...]] = (
        "pumped", "demand", "delivered", "shortfall", "running_hours", "starts",
    )  # fmt: skip

    def __len__(self) -> int:
        return len(self.month)

    def to_pandas(self):
        """The table as a pandas DataFrame indexed by month's short name (needs pandas).

        Columns ``pumped, demand, delivered, shortfall`` [m^3], ``running_hours`` [h] and
        ``starts`` [-].
        """
        import pandas

        index = pandas.Index([MONTH_NAMES[m - 1] for m in self.month], name="month")
        return pandas.DataFrame({name: getattr(self, name) for name in self.COLUMNS}, index=index)


@dataclasses.dataclass(frozen=True)
class Totals:
    """The year's totals: water [m^3], hours [h] and starts [-]."""

    pumped: float
    demand: float
    delivered: float
    shortfall: float
    spilled: float
    running_hours: int
    starts: int


@dataclasses.dataclass(frozen=True, eq=False)
class Supply:
    """A pump's year at a site with a tank and a demand (:func:`supply`): hour by hour.

    Attributes
    ----------
    V : ndarray
        Each hour's mean wind at the rotor [m/s].
    running : ndarray of bool
        Whether the pump ran in the hour.
    pumped, delivered, shortfall, spilled : ndarray
        Water pumped, delivered, asked for but not delivered, and spilled by the full tank in
        the hour [m^3].
    level : ndarray
        Water in the tank at the hour's end [m^3].
    demand : ndarray
        Water asked for in the hour [m^3].
    month : ndarray of int
        The hour's calendar month (1 to 12).
    tank : float
        The tank's capacity [m^3] (0: none).
    passes : int
        Passes through the year until the tank's end level repeated (at most ``MOST_PASSES``).
    V_stop : float
        Below it a running pump stops [m/s].
    V_start : float or None
        Above it a resting pump starts on its own [m/s]; None without torque at rest.
    restart : str
        ``"self"`` or ``"attended"`` (the year's; ``DEFAULT_RESTART`` unless asked).
    method : str
        ``"quasi-steady"`` or ``"full"``.
    why : str
        Why the pump never runs, when it does not ("" otherwise), in words (a caller adds how
        its user has someone start it, for ``restart="self"``).
    name : str
        The site's name.
    quasi_steady : Supply or None
        For ``method="full"``: the quasi-steady year, to compare with.
    """

    V: np.ndarray
    running: np.ndarray
    pumped: np.ndarray
    delivered: np.ndarray
    shortfall: np.ndarray
    spilled: np.ndarray
    level: np.ndarray
    demand: np.ndarray
    month: np.ndarray
    tank: float
    passes: int
    V_stop: float
    V_start: float | None
    restart: str = DEFAULT_RESTART
    method: str = "quasi-steady"
    why: str = ""
    name: str = ""
    quasi_steady: Supply | None = None

    @property
    def hours(self) -> int:
        """The year's hours [h]."""
        return len(self.V)

    @property
    def starts(self) -> int:
        """Times a resting pump started over the year [-]."""
        return int(np.count_nonzero(_started(self.running)))

    @property
    def totals(self) -> Totals:
        """The year's pumped, asked, delivered, short and spilled water [m^3], hours run, starts."""
        return Totals(
            pumped=float(self.pumped.sum()),
            demand=float(self.demand.sum()),
            delivered=float(self.delivered.sum()),
            shortfall=float(self.shortfall.sum()),
            spilled=float(self.spilled.sum()),
            running_hours=int(np.count_nonzero(self.running)),
            starts=self.starts,
        )

    @property
    def lolp(self) -> float:
        """Loss-of-load probability [-]: the year's shortfall over its demand (0 without demand)."""
        asked = float(self.demand.sum())
        return float(self.shortfall.sum()) / asked if asked > 0.0 else 0.0

    @property
    def dry(self) -> np.ndarray:
        """Whether each day (24-hour blocks from the record's start, the last maybe shorter) had
        any shortfall [bool]: more than ``DRY_TOLERANCE`` in the day (a tank that holds exactly
        n hours of demand otherwise empties to a round-off of 1e-15 m^3 short)."""
        days = np.arange(self.hours) // HOURS_PER_DAY
        return np.bincount(days, weights=self.shortfall) > DRY_TOLERANCE

    @property
    def dry_days(self) -> int:
        """The number of days with any shortfall [days]."""
        return int(np.count_nonzero(self.dry))

    @property
    def longest_dry_spell(self) -> int:
        """The most dry days in a row within the record [days]."""
        return _longest_run(self.dry)

    @property
    def monthly(self) -> MonthTable:
        """The year by calendar month (:class:`MonthTable`)."""
        months = np.unique(self.month)
        where = np.searchsorted(months, self.month)

        def total(values) -> np.ndarray:
            return np.bincount(where, weights=values, minlength=months.size)

        return MonthTable(
            month=months.astype(int),
            pumped=total(self.pumped),
            demand=total(self.demand),
            delivered=total(self.delivered),
            shortfall=total(self.shortfall),
            running_hours=total(self.running).astype(int),
            starts=total(_started(self.running)).astype(int),
        )

    @property
    def quasi_steady_gap(self) -> float:
        """How far the quasi-steady year's water is from this full one's, relative:
        ``(pumped quasi-steady - pumped full) / pumped full`` [-]; NaN for a quasi-steady year
        (or a full one that pumped nothing)."""
        if self.quasi_steady is None:
            return math.nan
        full = float(self.pumped.sum())
        if full == 0.0:
            return math.nan
        return (float(self.quasi_steady.pumped.sum()) - full) / full


def _started(running: np.ndarray) -> np.ndarray:
    """Hours in which a resting pump started (the year starts at rest)."""
    running = np.asarray(running, dtype=bool)
    before = np.concatenate(([False], running[:-1]))
    return running & ~before


def _longest_run(flags: np.ndarray) -> int:
    """The longest run of True in ``flags``."""
    padded = np.concatenate(([0], np.asarray(flags, dtype=np.int8), [0]))
    edges = np.flatnonzero(np.diff(padded))
    return int((edges[1::2] - edges[::2]).max()) if edges.size else 0


MOST_WATER = 1e12
"""Largest demand [m^3/day] and tank [m^3] :func:`supply` and :func:`tank_for` take: a hundred
times the world's daily water use, far past any pump; a year's sums of it stay exact to a litre's
share. At 1e307 m^3/day the year's demand overflowed (a loss-of-load probability of NaN, a tank
of 0 m^3)."""
WHY_MOST = "past any water supply; larger sums overflow a year's totals"


def hourly_demand(demand: float, profile, hours: int) -> np.ndarray:
    """Water asked for in each hour [m^3]: ``demand`` [m^3/day] spread by the 24 weights of
    ``profile`` (flat by default) over each day from the record's start.

    Examples
    --------
    >>> hourly_demand(2.4, None, 3).round(6).tolist()
    [0.1, 0.1, 0.1]
    """
    demand = non_negative("demand", demand, "m^3/day")
    if not demand <= MOST_WATER:
        raise ParameterError(
            "demand", demand, f"a finite number from 0 to {MOST_WATER:g}", "m^3/day", why=WHY_MOST
        )
    weights = _profile(profile)
    return demand * np.resize(weights / weights.sum(), hours)


def _profile(profile) -> np.ndarray:
    allowed = "24 weights (one an hour from midnight), each finite and >= 0, with a sum > 0"
    if profile is None:
        return np.ones(HOURS_PER_DAY)
    weights = real_array("profile", profile)  # (text, None, ragged lists: a ParameterError)
    if (
        weights.shape != (HOURS_PER_DAY,)
        or not np.all(np.isfinite(weights))  # (10**400 is inf here)
        or np.any(weights < 0.0)
        or not weights.max() > 0.0
    ):
        raise ParameterError("profile", profile, allowed)
    return weights / weights.max()  # proportions: 24 x 1e308 sums to inf, these to <= 24


def _tank(tank: object) -> float:
    value = non_negative("tank", tank, "m^3")
    if not value <= MOST_WATER:
        raise ParameterError("tank", value, f"a finite number from 0 to {MOST_WATER:g}", "m^3",
                             why=WHY_MOST)  # fmt: skip
    return value


def _with_tank(year: _Year, demand: np.ndarray, tank: float, **fields) -> Supply:
    """The tank's books over the periodic year (module docstring)."""
    hours = year.V.size
    delivered, shortfall, spilled, level = (np.empty(hours) for _ in range(4))
    passes = kernels.periodic(
        year.pumped, demand, tank, LEVEL_TOLERANCE, MOST_PASSES,
        delivered, shortfall, spilled, level,
    )  # fmt: skip
    return Supply(
        V=year.V, running=year.running, pumped=year.pumped, delivered=delivered,
        shortfall=shortfall, spilled=spilled, level=level, demand=demand, month=year.month,
        tank=tank, passes=int(passes), V_stop=year.V_stop, V_start=year.V_start, why=year.why,
        **fields,
    )  # fmt: skip


def supply(
    design: Design,
    record,
    demand: float,
    tank: float,
    *,
    restart: str = DEFAULT_RESTART,
    profile=None,
    method: str = "quasi-steady",
    turbulence: float = 0.0,
    seed: int | None = 0,
    chunk_days: int = 7,
    executor: concurrent.futures.Executor | None = None,
    progress: bool | Progress | None = False,
) -> Supply:
    """A pump's year of water at a site, with a tank and a demand (module docstring).

    Parameters
    ----------
    design : Design
        The pump, its rotor at V_ref.
    record : WindRecord or (t, V) pair
        The site's wind at the rotor's height (:meth:`WindRecord.at_height`): hourly or finer
        (averaged to hours), a sample in every hour.
    demand : float
        Water asked for [m^3/day], from 0 to 1e12 (``MOST_WATER``).
    tank : float
        The tank's capacity [m^3], from 0 to 1e12 (0: none, water pumped and not used at once
        spills).
    restart : {"self", "attended"}, default "attended", keyword-only
        Who restarts a resting pump: the wind (above V_start) or someone (above V_stop);
        ``DEFAULT_RESTART`` unless given.
    profile : 24 weights or None, keyword-only
        How the demand spreads over the day's hours from midnight (flat by default).
    method : {"quasi-steady", "full"}, keyword-only
        The averaged theory in each hour's mean wind, or the full equation of motion through the
        record (:func:`full_year`, which the next arguments go to).
    turbulence : float, keyword-only
        ``method="full"``: turbulence intensity of gusts inside each hour [-] (0: none).
    seed : int or None, keyword-only
        ``method="full"``: the gusts' seed.
    chunk_days : int, keyword-only
        ``method="full"``: days per chunk.
    executor : concurrent.futures.Executor or None, keyword-only
        ``method="full"``: where the chunks run: None (here, one after another) or an object with
        a ``submit`` method (a ``ProcessPoolExecutor``, a dask ``Client.get_executor()``).
    progress : bool, callable or None, keyword-only
        ``method="full"``: progress as in :func:`windpump.sweep` (a callable that raises is
        warned about once and called no more; the year carries on).

    Returns
    -------
    Supply

    Raises
    ------
    ParameterError
        Naming the argument: demand or tank < 0, a profile not of 24 finite weights >= 0 with a
        positive sum, an unknown restart or method, a record with a gap or a bad sample; and,
        checked whatever the method, turbulence, seed, chunk_days, an executor without a
        ``submit`` method or a progress that is neither a flag, None nor a callable.

    Examples
    --------
    A day of 6 m/s, a day of calm, for 2 m^3 a day and a 1 m^3 tank:

    >>> from windpump import Design
    >>> wind = (3600.0 * np.arange(48), [6.0] * 24 + [0.0] * 24)
    >>> year = supply(Design.seed_example().replace(T_0=0.3), wind, 2.0, 1.0)
    >>> year.hours, year.totals.running_hours, round(year.lolp, 3), year.dry_days
    (48, 24, 0.25, 1)
    """
    restart = _choice("restart", restart, RESTARTS)
    method = _choice("method", method, METHODS)
    tank = _tank(tank)
    full_options(turbulence, seed, chunk_days, executor, progress)  # whatever the method
    V, month = hourly(record)
    demand_h = hourly_demand(demand, profile, V.size)
    name = record.name if isinstance(record, WindRecord) else ""
    year = _quasi_steady_year(design, V, month, restart)
    steady = _with_tank(year, demand_h, tank, restart=restart, name=name)
    if method == "quasi-steady":
        return steady
    full = full_year(
        design, record, restart=restart, turbulence=turbulence, seed=seed,
        chunk_days=chunk_days, executor=executor, progress=progress,
    )  # fmt: skip
    return _with_tank(
        dataclasses.replace(
            year, running=full.running, pumped=full.pumped, why="" if full.running.any() else year.why
        ),
        demand_h, tank, restart=restart, name=name, method="full", quasi_steady=steady,
    )  # fmt: skip


def tank_for(
    design: Design,
    record,
    demand: float,
    lolp: float = 0.05,
    *,
    restart: str = DEFAULT_RESTART,
    profile=None,
) -> float:
    """The smallest tank [m^3] whose quasi-steady year (:func:`supply`) has a loss-of-load
    probability at most ``lolp``, to 1 L: a whole number of litres, the one below falling short.

    The year's loss-of-load probability falls as the tank grows (a larger tank holds at least as
    much, hour after hour), so the litres are bisected. An endless tank loses
    ``max(0, 1 - pumped / demand)`` of the demand over the year: when that exceeds ``lolp`` no
    tank will do and the answer is inf.

    Parameters
    ----------
    design : Design
    record : WindRecord or (t, V) pair
        The wind at the rotor, as :func:`supply` takes it.
    demand : float
        Water asked for [m^3/day], from 0 to 1e12 (``MOST_WATER``).
    lolp : float, default 0.05
        The loss-of-load probability allowed [-], from 0 to below 1.
    restart : {"self", "attended"}, default "attended", keyword-only
        Who restarts a resting pump, as :func:`supply` (``DEFAULT_RESTART``).
    profile : 24 weights or None, keyword-only
        The demand's spread over the day's hours, as :func:`supply`.

    Returns
    -------
    float
        The capacity [m^3], a multiple of 0.001; 0.0 when no tank is needed; inf when none is
        enough.

    Examples
    --------
    >>> from windpump import Design
    >>> wind = (3600.0 * np.arange(48), [6.0] * 24 + [0.0] * 24)
    >>> tank_for(Design.seed_example().replace(T_0=0.3), wind, 2.0, lolp=0.0)
    2.0
    """
    lolp = _lolp(lolp)
    restart = _choice("restart", restart, RESTARTS)
    V, month = hourly(record)
    asked = hourly_demand(demand, profile, V.size)
    pumped = _quasi_steady_year(design, V, month, restart).pumped
    return _smallest_tank(pumped, asked, lolp)


def _lolp(lolp: object) -> float:
    value = real("lolp", lolp)
    if not 0.0 <= value < 1.0:
        raise ParameterError("lolp", value, "from 0 to below 1")
    return value


def _smallest_tank(pumped: np.ndarray, asked: np.ndarray, lolp: float) -> float:
    """Bisection over whole litres of the periodic year's shortfall."""
    total = float(asked.sum())
    if total == 0.0:
        return 0.0
    allowed = lolp * total

    def short(litres: int) -> float:
        capacity = litres / LITRES
        return kernels.short_total(pumped, asked, capacity, LEVEL_TOLERANCE, MOST_PASSES)

    if short(0) <= allowed:
        return 0.0
    # An endless tank delivers all the year's water (it never spills once it has run dry).
    if max(0.0, total - float(pumped.sum())) > allowed:
        return math.inf
    high = math.ceil(max(total, float(pumped.sum())) * LITRES) + 1
    if short(high) > allowed:  # the endless tank's loss is just at the limit
        return math.inf
    low = 0  # short(low) > allowed >= short(high)
    while high - low > 1:
        middle = (low + high) // 2
        if short(middle) <= allowed:
            high = middle
        else:
            low = middle
    return high / LITRES


LITRES = 1000.0


@dataclasses.dataclass(frozen=True, eq=False)
class SupplyMap:
    """The quasi-steady year's loss-of-load probability over sprocket ratio and tank
    (:func:`supply_map`).

    Attributes
    ----------
    design : Design
        The design the ratios vary (through R1, R0 kept).
    gear_ratios : ndarray
        Sprocket ratios R+ = R1/R0 [-] (columns).
    tanks : ndarray
        Tank capacities [m^3] (rows).
    lolp : ndarray
        Loss-of-load probability [-], shape (tanks, gear ratios).
    pumped : ndarray
        The year's water at each gear ratio [m^3].
    demand : float
        The year's demand [m^3].
    """

    design: Design
    gear_ratios: np.ndarray
    tanks: np.ndarray
    lolp: np.ndarray
    pumped: np.ndarray
    demand: float


MAX_MAP_POINTS = 1_000_000
"""Most ratio x tank points a supply map may hold."""


def supply_map(
    design: Design,
    record,
    demand: float,
    gear_ratios,
    tanks,
    *,
    restart: str = DEFAULT_RESTART,
    profile=None,
) -> SupplyMap:
    """The quasi-steady year's loss-of-load probability over sprocket ratio and tank capacity.

    For each gear ratio (R1 = R0 R+, the design's other fields kept) the hours it runs and pumps
    come from its own thresholds and :func:`windpump.steady_flow`; every tank's periodic books
    then run compiled, in parallel: the same numbers as :func:`supply` design by design.

    Parameters
    ----------
    design : Design
    record : WindRecord or (t, V) pair
        The wind at the rotor, as :func:`supply` takes it.
    demand : float
        Water asked for [m^3/day], >= 0.
    gear_ratios : array_like
        Sprocket ratios R+ [-], each giving a valid design.
    tanks : array_like
        Tank capacities [m^3], finite and >= 0.
    restart : {"self", "attended"}, default "attended", keyword-only
        Who restarts a resting pump, as :func:`supply` (``DEFAULT_RESTART``).
    profile : 24 weights or None, keyword-only
        The demand's spread over the day's hours, as :func:`supply`.

    Returns
    -------
    SupplyMap

    Examples
    --------
    A day of 6 m/s, a day of calm, for 2 m^3 a day. On its own a resting pump needs 6.52 m/s to
    start at R+ = 3, so it never runs in this wind (at R+ = 4, 5.65 m/s: it runs the windy day).

    >>> from windpump import Design
    >>> pump = Design.seed_example().replace(T_0=0.3)
    >>> wind = (3600.0 * np.arange(48), [6.0] * 24 + [0.0] * 24)
    >>> found = supply_map(pump, wind, 2.0, [3.0, 4.0], [0.0, 2.0], restart="self")
    >>> found.lolp.round(3).tolist()  # rows: tanks, columns: gear ratios
    [[1.0, 0.5], [1.0, 0.0]]

    Attended (the default), it runs whenever the wind can carry it (V_stop = 2.56 m/s at
    R+ = 3): the calm day is short without a tank, and a 2 m^3 tank covers it.

    >>> supply_map(pump, wind, 2.0, [3.0, 4.0], [0.0, 2.0]).lolp.round(3).tolist()
    [[0.5, 0.5], [0.0, 0.0]]
    """
    restart = _choice("restart", restart, RESTARTS)
    ratios = np.atleast_1d(finite_array("gear_ratios", gear_ratios, minimum=0.0)).ravel()
    capacities = np.atleast_1d(finite_array("tanks", tanks, "m^3", minimum=0.0)).ravel()
    if ratios.size * capacities.size > MAX_MAP_POINTS:
        raise ParameterError(
            "tanks", f"{capacities.size} x {ratios.size} gear ratios", f"<= {MAX_MAP_POINTS} points"
        )
    V, month = hourly(record)
    asked = hourly_demand(demand, profile, V.size)
    pumped = np.array(
        [
            _quasi_steady_year(design.with_ratios(R_dagger=float(r)), V, month, restart).pumped
            for r in ratios
        ]
    ).reshape(ratios.size, V.size)
    short = kernels.shortfall_map(pumped, asked, capacities, LEVEL_TOLERANCE, MOST_PASSES)
    total = float(asked.sum())
    lolp = short.T / total if total > 0.0 else np.zeros((capacities.size, ratios.size))
    return SupplyMap(design, ratios, capacities, lolp, pumped.sum(axis=1), total)
