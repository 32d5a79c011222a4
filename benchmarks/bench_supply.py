"""A year of water at a site: quasi-steady, mapped, sized, and in full on both cores.

Run: python benchmarks/bench_supply.py [--full] [--site greensboro|sand_point]

1. The quasi-steady year (windpump.supply) at Greensboro, 15 m hub, the seed design with
   T_0 = 0.3 N m restarting on its own (restart="self", the rule the plain loop writes), 2 m^3/day
   into a 5 m^3 tank: the best of several calls (the first, which
   compiles or loads the kernels, shown apart), against a plain Python loop over the hours doing
   the same rule and books in this process.
2. tank_for at that site (loss-of-load probability 0.05).
3. supply_map over 100 sprocket ratios x 100 tanks, against a loop of supply calls over the
   same ratios and tanks (timed on a 10 x 10 corner and scaled: the loop's own cost per point).
4. With --full: the year in full (method="full", weekly chunks) on a ProcessPoolExecutor of two
   workers, with the quasi-steady year's distance from it.
"""

from __future__ import annotations

import argparse
import concurrent.futures
import os
import time

import numpy as np

import windpump
from windpump.units import SECONDS_PER_HOUR

DESIGN = windpump.Design.seed_example().replace(T_0=0.3)
DEMAND, TANK, HUB = 2.0, 5.0, 15.0
RESTART = "self"  # the hysteresis rule plain_year writes (not the default, "attended")


def best(call, repeats: int = 7) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return min(times)


def plain_year(design, record, demand, tank):
    """The quasi-steady year written as a plain loop over the hours (same rule, same books)."""
    V = np.asarray(record.V, dtype=float)
    V_stop, V_start = windpump.wind_thresholds(design)
    flow = windpump.steady_flow(design, V) * SECONDS_PER_HOUR
    asked = demand / 24.0
    start, shortfall = tank, 0.0
    for _ in range(20):
        level, was, shortfall = start, False, 0.0
        for h in range(V.size):
            now = V[h] >= V_start or (was and V[h] >= V_stop)
            was = now
            available = level + (flow[h] if now else 0.0)
            given = min(asked, available)
            shortfall += asked - given
            level = available - given - max(0.0, available - given - tank)
        if abs(level - start) <= 1e-6:
            break
        start = level
    return shortfall / (asked * V.size)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--full", action="store_true", help="also the year in full (minutes)")
    parser.add_argument("--site", default="greensboro")
    args = parser.parse_args()
    record = windpump.sample_site(args.site).at_height(HUB)
    print(f"site {record.name}, hub {HUB:g} m, mean {record.V.mean():.2f} m/s, {record.V.size} h")
    print(f"load: {os.getloadavg()}")

    start = time.perf_counter()
    year = windpump.supply(DESIGN, record, DEMAND, TANK, restart=RESTART)
    first = time.perf_counter() - start
    quick = best(lambda: windpump.supply(DESIGN, record, DEMAND, TANK, restart=RESTART))
    plain = best(lambda: plain_year(DESIGN, record, DEMAND, TANK), 3)
    assert abs(plain_year(DESIGN, record, DEMAND, TANK) - year.lolp) < 1e-9
    print(
        f"1. quasi-steady year: {quick * 1e3:.2f} ms (first call {first * 1e3:.0f} ms), "
        f"plain Python loop {plain * 1e3:.0f} ms: x{plain / quick:.0f}; lolp {year.lolp:.4f}, "
        f"{year.totals.pumped:.0f} m^3 pumped, {year.passes} passes"
    )

    sizing = best(lambda: windpump.tank_for(DESIGN, record, DEMAND, 0.05, restart=RESTART), 3)
    size = windpump.tank_for(DESIGN, record, DEMAND, 0.05, restart=RESTART)
    print(f"2. tank_for(lolp=0.05): {size:.3f} m^3 in {sizing * 1e3:.1f} ms")

    ratios, tanks = np.linspace(2.5, 7.0, 100), np.linspace(0.0, 40.0, 100)
    windpump.supply_map(DESIGN, record, DEMAND, ratios[:2], tanks[:2], restart=RESTART)  # compile
    mapped = best(
        lambda: windpump.supply_map(DESIGN, record, DEMAND, ratios, tanks, restart=RESTART), 3
    )

    def loop():
        for r in ratios[::10]:
            design = DESIGN.with_ratios(R_dagger=float(r))
            for c in tanks[::10]:
                windpump.supply(design, record, DEMAND, float(c), restart=RESTART)

    looped = best(loop, 1) * 100  # 10 x 10 points timed, 100 x 100 wanted
    print(
        f"3. supply_map 100 x 100: {mapped:.3f} s; a loop of supply calls ~{looped:.1f} s "
        f"(10 x 10 timed, x100): x{looped / mapped:.0f}"
    )

    if args.full:
        start = time.perf_counter()
        with concurrent.futures.ProcessPoolExecutor(2) as pool:
            full = windpump.supply(
                DESIGN,
                record,
                DEMAND,
                TANK,
                method="full",
                chunk_days=7,
                executor=pool,
                restart=RESTART,
            )
        took = time.perf_counter() - start
        print(
            f"4. the year in full on 2 workers: {took:.0f} s; pumped {full.totals.pumped:.1f} m^3 "
            f"(quasi-steady {full.quasi_steady.totals.pumped:.1f} m^3, gap "
            f"{full.quasi_steady_gap:+.2%}); lolp {full.lolp:.4f} (quasi-steady "
            f"{full.quasi_steady.lolp:.4f}); running hours {full.totals.running_hours} "
            f"({full.quasi_steady.totals.running_hours})"
        )
        print(f"load after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
