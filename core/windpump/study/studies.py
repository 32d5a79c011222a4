"""Many full simulations at once: :func:`sweep`, serial or on any ``concurrent.futures`` executor.

A study moves from a laptop to a cluster by the executor it is given: a ``ProcessPoolExecutor``
spreads it over one machine's cores, a dask.distributed ``Client(...).get_executor()`` over a
cluster's workers. Designs go out in chunks, so the overhead per run stays small, and the table
comes back in the designs' order, identical whatever ran it.
"""

from __future__ import annotations

import concurrent.futures
import dataclasses
import math
import warnings
from collections.abc import Iterable

import numpy as np

from ..averaging.averaged import stall_margin, steady_speeds, time_constant
from ..errors import ParameterError
from ..model.design import UNITS, Design
from ..progress import Progress, check_executor, reporter
from ..run.dynamics import simulate
from ..validation import non_negative, positive, real, real_array

FIGURES = {
    "margin": "-",
    "alpha_plus": "rad/s",
    "alpha_minus": "rad/s",
    "tau": "s",
    "stalled": "",
    "t_stall": "s",
    "volume": "m^3",
    "mean_flow": "m^3/s",
    "mean_speed": "rad/s",
    "peak_to_mean": "-",
    "ripple": "-",
    "steps": "",
}
"""The figures of every run in a :class:`Sweep`, with their units."""

INPUTS = {"t_end": "s", "theta0": "rad", "theta_dot0": "rad/s"}

MEASURED_TURNS = 10
"""Mean flow, peak/mean and ripple are measured over a run's last this many revolutions."""

MOST_CHUNKS = 32
"""A sweep is sent in about this many chunks (fewer when it is small): few enough that sending
costs little, enough to keep every worker busy and to report progress."""


@dataclasses.dataclass(frozen=True)
class Sweep:
    """The figures of many full simulations (:func:`sweep`): one entry per design, in order.

    Attributes
    ----------
    designs : tuple of Design
    t_end, theta0, theta_dot0 : ndarray
        Each run's duration [s], start angle [rad] and kick [rad/s].
    margin : ndarray
        Stall margin of Eq. (22) [-].
    alpha_plus, alpha_minus, tau : ndarray
        The averaged theory's steady speeds [rad/s] (Eq. 21) and time constant [s] (Eq. 25);
        NaN when the margin is 1 or less.
    stalled : ndarray of bool
        Whether the run came to rest.
    t_stall : ndarray
        When [s]; NaN when it did not stall.
    volume : ndarray
        Water pumped over the run [m^3].
    mean_flow, mean_speed : ndarray
        Mean flow [m^3/s] and cycle-mean crank speed [rad/s] over the last 10 revolutions; 0 when
        the run stalled, NaN when it turns without completing a revolution.
    peak_to_mean, ripple : ndarray
        Peak over mean flow [-] and the largest speed ripple of a revolution [-] over the same
        revolutions (:class:`windpump.Intermittency`); NaN when the run stalled.
    steps : ndarray of int
        Integration steps each run took.
    failed : dict of int to str
        The runs that failed, by their design's index, with the reason (the error's message):
        their figures are NaN (``stalled`` False, ``steps`` 0). Empty when every run ran; see
        :attr:`ok` and :meth:`without_failures`.
    """

    designs: tuple[Design, ...]
    t_end: np.ndarray
    theta0: np.ndarray
    theta_dot0: np.ndarray
    margin: np.ndarray
    alpha_plus: np.ndarray
    alpha_minus: np.ndarray
    tau: np.ndarray
    stalled: np.ndarray
    t_stall: np.ndarray
    volume: np.ndarray
    mean_flow: np.ndarray
    mean_speed: np.ndarray
    peak_to_mean: np.ndarray
    ripple: np.ndarray
    steps: np.ndarray
    failed: dict[int, str] = dataclasses.field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.designs)

    @property
    def ok(self) -> np.ndarray:
        """Whether each run ran (False where it failed: :attr:`failed` says why) [bool]."""
        ok = np.ones(len(self.designs), dtype=bool)
        ok[list(self.failed)] = False
        return ok

    def without_failures(self) -> Sweep:
        """The table of the runs that ran, in order (the failed rows left out)."""
        keep = self.ok
        columns = {name: getattr(self, name)[keep] for name in (*INPUTS, *FIGURES)}
        designs = tuple(d for d, kept in zip(self.designs, keep, strict=True) if kept)
        return Sweep(designs, **columns)

    def columns(self) -> dict[str, np.ndarray]:
        """Every design field, the run's inputs and its figures, as columns by name."""
        fields = {name: np.array([getattr(d, name) for d in self.designs]) for name in UNITS}
        inputs = {name: getattr(self, name) for name in INPUTS}
        return fields | inputs | {name: getattr(self, name) for name in FIGURES}

    def to_pandas(self):
        """The table as a ``pandas.DataFrame``, a row per design (needs pandas).

        Examples
        --------
        >>> from windpump import Design, sweep
        >>> d = Design.seed_example()
        >>> table = sweep([d, d.replace(h=20.0)], 120.0).to_pandas()
        >>> table[["h", "stalled"]].values.tolist()
        [[3.0, False], [20.0, True]]
        """
        try:
            import pandas
        except ImportError:
            raise ImportError("Sweep.to_pandas needs pandas: pip install pandas") from None
        return pandas.DataFrame(self.columns())

    def to_csv(self) -> str:
        """The table as CSV text, units in the header row."""
        units = UNITS | INPUTS | FIGURES
        columns = self.columns()
        header = ",".join(f"{name} [{units[name]}]".replace(" []", "") for name in columns)
        rows = zip(*columns.values(), strict=True)
        lines = [header] + [",".join(_cell(value) for value in row) for row in rows]
        return "\n".join(lines) + "\n"


def _cell(value) -> str:
    """A CSV cell: booleans and integers as they are, floats in the fewest digits that read back
    exactly (a table read back as designs gives the same designs)."""
    if isinstance(value, (bool, np.bool_, int, np.integer)):
        return str(value.item() if hasattr(value, "item") else value)
    return repr(float(value))


def sweep(
    designs: Iterable[Design],
    t_end,
    theta0=math.pi / 2,
    theta_dot0=3.0,
    *,
    executor: concurrent.futures.Executor | None = None,
    chunksize: int | None = None,
    progress: bool | Progress | None = None,
) -> Sweep:
    """Simulate every design in full (Eq. 12, :func:`windpump.simulate`) and tabulate its figures.

    Parameters
    ----------
    designs : iterable of Design
    t_end : float or array_like
        Duration [s] of every run, or one per design.
    theta0, theta_dot0 : float or array_like
        Start angle [rad] and kick [rad/s], for every run or one per design.
    executor : concurrent.futures.Executor or None, keyword-only
        Where the runs go: None runs them here, one after another; a ``ProcessPoolExecutor``
        over this machine's cores; ``distributed.Client(address).get_executor()`` on a dask
        cluster. The result is the same.
    chunksize : int or None, keyword-only
        Designs per task; None: the sweep is cut in about 32 chunks.
    progress : bool, callable or None, keyword-only
        Progress: a callable taking (done, total), True or False for a tqdm bar or none, None
        for a bar only in a terminal. A callable that raises is warned about once (a
        ``RuntimeWarning``) and called no more; the sweep carries on and returns every row.

    Returns
    -------
    Sweep
        Every run's figures; a run that fails (a ``ValueError``: a design too stiff, a per-design
        t_end too long for its design...) does not stop the others: its row is NaN and
        ``Sweep.failed`` holds its index and the reason, and a ``RuntimeWarning`` says how many
        failed and why.

    Raises
    ------
    ParameterError
        Naming t_end, theta0, theta_dot0 or chunksize when out of range for every run (a value
        given per design is checked with its run, which fails alone); naming executor when it has
        no ``submit`` method, progress when it is neither a flag, None nor a callable.

    Examples
    --------
    >>> from windpump import Design, sweep
    >>> d = Design.seed_example()
    >>> table = sweep([d.replace(h=h) for h in (1.0, 3.0, 9.0)], 600.0)
    >>> from windpump.units import SECONDS_PER_DAY
    >>> per_day = table.mean_flow * SECONDS_PER_DAY  # m^3/day; 9 m stalls from a kick of 3
    >>> [round(float(q), 1) for q in per_day]
    [33.9, 32.6, 0.0]
    """
    executor = check_executor(executor)
    designs = tuple(designs)
    for index, design in enumerate(designs):
        if not isinstance(design, Design):
            raise TypeError(f"designs[{index}] is a {type(design).__name__}, not a Design")
    count = len(designs)
    t_end = _per_design("t_end", t_end, count, "s", positive)
    theta0 = _per_design("theta0", theta0, count, "rad", real)
    theta_dot0 = _per_design("theta_dot0", theta_dot0, count, "rad/s", non_negative)
    if chunksize is None:
        chunksize = max(1, math.ceil(count / MOST_CHUNKS))
    if isinstance(chunksize, bool) or not isinstance(chunksize, int) or chunksize < 1:
        raise ParameterError("chunksize", chunksize, "a whole number >= 1")
    chunks = [slice(start, start + chunksize) for start in range(0, count, chunksize)]
    tasks = [(designs[c], t_end[c], theta0[c], theta_dot0[c], c.start) for c in chunks]
    report = reporter(progress, count, "sweep")
    table = np.empty((count, len(FIGURES)))
    failed: dict[int, str] = {}
    if executor is None:
        for chunk, task in zip(chunks, tasks, strict=True):
            table[chunk], failures = run_chunk(*task)
            failed.update(failures)
            report(min(chunk.stop, count), count)
    else:
        futures = {
            executor.submit(run_chunk, *task): chunk
            for chunk, task in zip(chunks, tasks, strict=True)
        }
        done = 0
        for future in concurrent.futures.as_completed(futures):
            chunk = futures[future]
            table[chunk], failures = future.result()
            failed.update(failures)
            done += len(table[chunk])
            report(done, count)
    figures = dict(zip(FIGURES, table.T, strict=True))
    figures["stalled"] = figures["stalled"] == 1.0  # (NaN where a run failed: False)
    figures["steps"] = np.nan_to_num(figures["steps"]).astype(np.int64)
    failed = dict(sorted(failed.items()))
    if failed:
        warnings.warn(failure_summary(failed, count), RuntimeWarning, stacklevel=2)
    return Sweep(designs, t_end, theta0, theta_dot0, **figures, failed=failed)


def failure_summary(failed: dict[int, str], count: int, shown_runs: int = 3) -> str:
    """One line: how many of ``count`` runs failed, and the first few with their reasons."""
    first = "; ".join(f"designs[{i}]: {why}" for i, why in list(failed.items())[:shown_runs])
    more = f"; and {len(failed) - shown_runs} more" if len(failed) > shown_runs else ""
    return f"{len(failed)} of {count} runs failed (Sweep.failed lists them): {first}{more}"


def _per_design(name, value, count, unit, check) -> np.ndarray:
    """A scalar (``check``-ed: it holds for every run) or one real number per design (each
    checked by its own run), as a float array of ``count`` values."""
    array = real_array(name, value, unit)
    if array.ndim == 0:
        return np.full(count, check(name, float(array), unit))
    if array.shape != (count,):
        raise ParameterError(name, f"shape {array.shape}", f"a number or {count} numbers", unit)
    return array


def run_chunk(designs, t_end, theta0, theta_dot0, first: int) -> tuple[np.ndarray, dict[int, str]]:
    """The figures of a chunk of runs, a row per design (NaN where a run failed), and the runs
    that failed by their index in the sweep (``first`` is the chunk's first) with the reason: a
    task a worker runs."""
    rows = np.full((len(designs), len(FIGURES)), np.nan)
    failed = {}
    for i, design in enumerate(designs):
        try:
            rows[i] = figures_of(design, t_end[i], theta0[i], theta_dot0[i])
        except (ValueError, ArithmeticError) as error:
            failed[first + i] = str(error) or type(error).__name__
    return rows, failed


def figures_of(design: Design, t_end: float, theta0: float, theta_dot0: float) -> list[float]:
    """One run's figures, in the order of FIGURES."""
    run = simulate(design, float(t_end), theta0=float(theta0), theta_dot0=float(theta_dot0))
    margin = stall_margin(design)
    alpha_plus = alpha_minus = tau = math.nan
    if margin > 1.0:
        alpha_plus, unstable = steady_speeds(design)
        alpha_minus = math.nan if unstable is None else unstable
        tau = time_constant(design)
    flow = speed = peak_to_mean = ripple = math.nan
    if run.stalled:  # at rest in the end: it pumps nothing
        flow = speed = 0.0
    elif run.theta[-1] - run.theta[0] >= 2 * math.pi:  # a complete revolution to measure
        figures = run.intermittency(MEASURED_TURNS)
        flow, speed = figures.mean_flow, figures.mean_speed
        peak_to_mean, ripple = figures.peak_to_mean, figures.speed_ripple
    t_stall = run.t_stall if run.t_stall is not None else math.nan
    volume = float(run.volume[-1])
    return [margin, alpha_plus, alpha_minus, tau, float(run.stalled), t_stall, volume, flow,
            speed, peak_to_mean, ripple, float(run.steps)]  # fmt: skip
