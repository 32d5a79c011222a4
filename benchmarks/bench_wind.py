"""A day of gusty wind in full, and a year of days on both cores.

Run: python benchmarks/bench_wind.py [days]

1. An hour of gusty wind on the seed design with torque at rest (T_0 = 0.3 N m), stops and
   restarts included: windpump.simulate against a straightforward scipy port (solve_ivp RK45 in
   time, one call per stretch between the record's samples and the stops, ODE45's tolerances),
   both timed in this process; each side's error against the tight reference of
   tests/reference.py (DOP853 at rtol 1e-11, stroke by stroke, with events).
2. A full day (86,400 s) of gusty wind at one sample a second: the time, the samples and the
   water it lifts beside the averaged bounds of ``water_per_day``.
3. A year of such days (a record per day, seeds 0 ... 364) through a ProcessPoolExecutor on both
   cores, against the same days run one after the other here.
"""

from __future__ import annotations

import concurrent.futures
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

import windpump
from windpump.model.wind import gusty
from windpump.units import SECONDS_PER_DAY

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from reference import summed_load, wind_reference_run, wind_rhs  # noqa: E402

DESIGN = windpump.Design.seed_example().replace(T_0=0.3)
MEAN_WIND, DAY = 5.0, SECONDS_PER_DAY


def scipy_port(design, t_end, theta0, theta_dot0, wind_t, wind_V):
    """Eq. (12) in time with solve_ivp's RK45 at its default tolerances, the load switching
    inside the right-hand side: one call per stretch between wind samples, a stop found by an
    event, a rest waited out to the next wind sample."""
    width = math.pi / design.cylinders

    def load(theta):
        return summed_load(design, (math.floor(theta / width) + 0.5) * width)(theta)

    def stops(_t, state):
        return state[1]

    stops.terminal, stops.direction = True, -1
    rhs = wind_rhs(design, load, wind_t, wind_V)
    t, y = 0.0, np.array([theta0, theta_dot0, 0.0, 0.0])
    for t_next in [*wind_t[1:][wind_t[1:] < t_end], t_end]:
        while t < t_next:
            if y[1] == 0.0:
                ratio = np.interp(t, wind_t, wind_V) / design.V_ref
                if design.R_dagger * design.T_0 * ratio**2 + load(y[0]) <= 0.0:
                    break  # rests until the next wind sample
            sol = solve_ivp(rhs, (t, t_next), y, method="RK45", events=stops)
            t, y = sol.t[-1], sol.y[:, -1].copy()
            if sol.t_events[0].size:
                y[1] = 0.0
        t = t_next
    return y[0], y[1], y[2]


def timed(function, repeats):
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return statistics.median(times), result


def one_day(seed: int) -> tuple[float, int, int]:
    """Water lifted [m^3] on a gusty day, its stops and its starts."""
    record = gusty(MEAN_WIND, DAY, seed=seed)
    run = windpump.simulate(DESIGN, DAY, theta_dot0=0.0, wind=record, sample_dt=1.0)
    return float(run.volume[-1]), len(run.stops), len(run.starts)


def hour_against_scipy():
    record = gusty(3.0, 3600.0, time_scale=30.0, seed=1)
    args = (DESIGN, 3600.0, math.pi / 2, 0.0)
    ref, stops, _ = wind_reference_run(*args, *record)
    truth = np.array([ref.theta, ref.theta_dot, ref.volume])

    def ours():
        run = windpump.simulate(*args[:2], args[2], args[3], wind=record, sample_dt=1.0)
        return run.theta[-1], run.theta_dot[-1], run.volume[-1]

    ours()
    fast, fast_result = timed(ours, 21)
    slow, slow_result = timed(lambda: scipy_port(*args, record.t, record.V), 3)
    print(f"an hour of gusty wind (mean 3 m/s, {len(stops)} stops in the reference)")
    print(f"{'':28s}{'median time':>14s}{'theta':>11s}{'theta_dot':>11s}{'volume':>11s}")
    for name, seconds, result in [
        ("windpump.simulate", fast, fast_result),
        ("scipy port (RK45)", slow, slow_result),
    ]:
        errors = np.abs(np.array(result) - truth) / np.maximum(np.abs(truth), 1e-300)
        print(f"{name:28s}{seconds * 1e3:11.2f} ms" + "".join(f"{e:11.1e}" for e in errors))
    print(f"speed-up: {slow / fast:.0f}x\n")


def a_day():
    record = gusty(MEAN_WIND, DAY, seed=0)
    windpump.simulate(DESIGN, 60.0, theta_dot0=0.0, wind=record, sample_dt=1.0)  # compiled
    seconds, run = timed(
        lambda: windpump.simulate(DESIGN, DAY, theta_dot0=0.0, wind=record, sample_dt=1.0), 5
    )
    low, high = windpump.water_per_day(DESIGN, MEAN_WIND)
    print(
        f"a day of gusty wind (mean {MEAN_WIND} m/s, k = 2, time scale 60 s), T_0 = {DESIGN.T_0} N m:"
        f"\n  {seconds:.3f} s median of 5, {run.steps} steps, {len(run.t)} samples,"
        f" {len(run.stops)} stops, {len(run.starts)} starts"
        f"\n  lifted {run.volume[-1]:.2f} m^3; averaged bounds {low:.2f} ... {high:.2f} m^3/day\n"
    )
    return seconds


def a_year(days: int):
    start = time.perf_counter()
    with concurrent.futures.ProcessPoolExecutor(max_workers=2) as pool:
        year = list(pool.map(one_day, range(days)))
    both = time.perf_counter() - start
    start = time.perf_counter()
    serial = [one_day(seed) for seed in range(min(days, 20))]
    one = (time.perf_counter() - start) / len(serial)
    assert year[: len(serial)] == serial, "a day's water must not depend on where it ran"
    water = np.array([day[0] for day in year])
    print(
        f"{days} days on 2 processes: {both:.1f} s ({both / days:.3f} s a day; one core"
        f" {one:.3f} s a day, {one * days / both:.2f}x in parallel)"
        f"\n  water {water.sum():.0f} m^3, {water.mean():.2f} m^3/day"
        f" (min {water.min():.2f}, max {water.max():.2f}),"
        f" {sum(day[1] for day in year)} stops"
    )


def main():
    days = int(sys.argv[1]) if len(sys.argv) > 1 else 365
    hour_against_scipy()
    a_day()
    a_year(days)


if __name__ == "__main__":
    main()
