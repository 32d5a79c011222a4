"""The design map: the averaged 200 x 200 grid and the numeric 100 x 100 grid.

Run: python benchmarks/bench_map.py

1. The averaged map of the seed design over 200 gear ratios x 200 heads (windpump.design_map,
   vectorised) against the same map point by point through the scalar API (stall_margin,
   steady_speeds, time_constant on a Design per point), both timed here; the largest relative
   difference between them.
2. The best gear ratio of 200 heads in closed form against scipy's bounded scalar optimiser run
   on the scalar API per head: time and agreement.
3. The numeric 100 x 100 map (full simulations, numba prange) on every core and on one thread,
   against windpump.simulate called per point on a sample of 1 point in 25 (the cost per run);
   its largest departure from the averaged map, and from long simulate runs at the sample points.
"""

from __future__ import annotations

import math
import time

import numba
import numpy as np
from scipy.optimize import minimize_scalar

import windpump

DESIGN = windpump.Design.seed_example()
RATIOS, HEADS = np.linspace(0.5, 16.0, 200), np.linspace(0.0, 20.0, 200)


def timed(function, repeats=5):
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return min(times), result


def scalar_map(ratios, heads):
    """margin, alpha+ and tau point by point through the scalar API."""
    out = np.full((3, len(heads), len(ratios)), np.nan)
    for i, h in enumerate(heads):
        for j, ratio in enumerate(ratios):
            point = DESIGN.replace(R1=DESIGN.R0 * ratio, h=h)
            out[0, i, j] = windpump.stall_margin(point)
            if out[0, i, j] > 1.0:
                out[1, i, j] = windpump.steady_speeds(point)[0]
                out[2, i, j] = windpump.time_constant(point)
    return out


def flow_at(ratio, h):
    point = DESIGN.replace(R1=DESIGN.R0 * ratio, h=h)
    if windpump.stall_margin(point) <= 1.0:
        return 0.0
    return point.volume_per_revolution * windpump.steady_speeds(point)[0] / (2 * math.pi)


def optimised_best(heads):
    best = []
    for h in heads[heads > 0]:
        found = minimize_scalar(
            lambda r, h=h: -flow_at(r, h), bounds=(RATIOS[0], RATIOS[-1]), method="bounded",
            options={"xatol": 1e-10},
        )  # fmt: skip
        best.append(found.x if found.fun < 0 else math.nan)
    return np.array(best)


def relative(a, b):
    both = np.isfinite(a) & np.isfinite(b)
    return float(np.max(np.abs(a[both] / b[both] - 1.0)))


def averaged():
    fast, result = timed(lambda: windpump.design_map(DESIGN, RATIOS, HEADS))
    slow, reference = timed(lambda: scalar_map(RATIOS, HEADS), repeats=1)
    assert np.array_equal(np.isnan(result.alpha_plus), np.isnan(reference[1]))
    print(f"averaged 200 x 200 map: {fast * 1e3:.1f} ms; point by point {slow * 1e3:.0f} ms "
          f"({slow / fast:.0f}x); largest relative difference: margin "
          f"{relative(result.margin, reference[0]):.1e}, alpha+ "
          f"{relative(result.alpha_plus, reference[1]):.1e}, tau {relative(result.tau, reference[2]):.1e}")  # fmt: skip
    slow, best = timed(lambda: optimised_best(HEADS), repeats=1)
    found = result.best_gear_ratio[HEADS > 0]
    print(
        f"best gear of 200 heads: in closed form with the map; scipy's bounded optimiser "
        f"{slow * 1e3:.0f} ms; largest relative difference {relative(found, best):.1e}"
    )


def numeric():
    ratios, heads = RATIOS[::2], HEADS[::2]
    windpump.design_map(DESIGN, ratios[:3], heads[:3], numeric=True, progress=False)  # compile
    both, result = timed(
        lambda: windpump.design_map(DESIGN, ratios, heads, numeric=True, progress=False), 2
    )
    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    one, _ = timed(
        lambda: windpump.design_map(DESIGN, ratios, heads, numeric=True, progress=False), 1
    )
    numba.set_num_threads(threads)
    theory = windpump.design_map(DESIGN, ratios, heads)
    sample = [(i, j) for i in range(0, 100, 5) for j in range(0, 100, 5)]
    start, speeds = time.perf_counter(), []
    for i, j in sample:
        kick, tau = theory.alpha_plus[i, j], theory.tau[i, j]
        if math.isnan(kick):
            continue
        turns = min(4000, max(60, 8 * tau * kick / (2 * math.pi)))
        run = windpump.simulate(theory.design_at(i, j), turns * 2 * math.pi / kick, 0.0, kick)
        speeds.append((result.alpha_plus[i, j], run.intermittency(10).mean_speed))
    per_run = (time.perf_counter() - start) / len(speeds)
    running = int(np.count_nonzero(~np.isnan(theory.alpha_plus)))
    mapped, simulated = np.array(speeds).T
    print(
        f"numeric 100 x 100 map ({running} running designs simulated): {both:.2f} s on "
        f"{threads} threads, {one:.2f} s on 1 ({one / both:.2f}x); simulate per point "
        f"{per_run * 1e3:.2f} ms a run, {per_run * running:.1f} s for the map "
        f"({per_run * running / both:.1f}x)"
    )
    print(f"  largest departure from the averaged map {relative(result.alpha_plus, theory.alpha_plus):.1e}"
          f"; from the same runs of simulate at {len(speeds)} points {relative(mapped, simulated):.1e}")  # fmt: skip


if __name__ == "__main__":
    averaged()
    numeric()
