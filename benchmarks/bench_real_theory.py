"""The averaged theory of the real machine with a leak hole (quadrature and root finding).

Run: python benchmarks/bench_real_theory.py

Issue 22 asks each averaged function of a pump with a leak hole to run in under 5 ms. Each is
timed here (best of 30 calls, after one warm call that loads scipy) on the seed design with a
4 mm hole, then with every effect on (hole, rising main, reciprocating mass, chain losses), and
the ideal machine's closed forms for comparison. Nothing is asserted: the times are printed.
"""

from __future__ import annotations

import time

import numpy as np

import windpump

SEED = windpump.Design.seed_example()
HOLED = SEED.replace(d_leak=0.004, T_0=0.2)
EVERYTHING = HOLED.replace(m_r=5.0, eta_t=0.9, L_main=30.0, D_main=0.02)
TIMES = np.linspace(0.0, 600.0, 601)

CALLS = {
    "stall_margin": lambda d: windpump.stall_margin(d),
    "steady_speeds": lambda d: windpump.steady_speeds(d),
    "time_constant": lambda d: windpump.time_constant(d),
    "spinup (601 times)": lambda d: windpump.spinup(d, TIMES, 3.0),
    "averaged_stall_time": lambda d: windpump.averaged_stall_time(d, 3.0),
    "steady_flow (one wind)": lambda d: windpump.steady_flow(d, 6.0),
    "water_per_day": lambda d: windpump.water_per_day(d, 5.0),
    "wind_thresholds": lambda d: windpump.wind_thresholds(d),
    "starts_from_rest": lambda d: windpump.starts_from_rest(d),
}


def best_of(function, design, repeats: int = 30) -> float:
    function(design)  # warm: scipy's modules load on the first call
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function(design)
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    designs = {"ideal": SEED, "leak hole": HOLED, "every effect": EVERYTHING}
    print(f"{'function':26s}" + "".join(f"{name:>16s}" for name in designs))
    for label, function in CALLS.items():
        times = [best_of(function, design) for design in designs.values()]
        print(f"{label:26s}" + "".join(f"{t * 1e3:13.2f} ms" for t in times))
    print("(issue 22: each averaged function with a leak hole under 5 ms)")


if __name__ == "__main__":
    main()
