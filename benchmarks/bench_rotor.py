"""The averaged theory of a rotor's pump (no closed form: roots, margin and spin-up found
numerically) against the paper's closed forms on the same pump, function by function.

Run: python benchmarks/bench_rotor.py

Each function is timed on fresh designs (a new head each call, so no remembered answer is
reused: what a slider's move pays), as the median of many calls, for the multiblade wheel on the
seed example's pump and for the seed example itself (Eq. 11); the issue asks under 5 ms each.
Its accuracy: alpha+ against scipy's brentq on F(alpha) written here.
"""

from __future__ import annotations

import math
import statistics
import time

import numpy as np
from scipy.interpolate import PchipInterpolator
from scipy.optimize import brentq

import windpump as wp

CALLS = 200


def designs(base: wp.Design, n: int):
    """n designs differing in head only (fresh keys for every remembered answer)."""
    return [base.replace(h=base.h * (1.0 + 1e-6 * k)) for k in range(n)]


FUNCTIONS = {
    "stall_margin": wp.stall_margin,
    "steady_speeds": wp.steady_speeds,
    "time_constant": wp.time_constant,
    "spinup (50 times)": lambda d: wp.spinup(d, np.linspace(0.0, 60.0, 50), 0.0),
    "steady_flow (3 winds)": lambda d: wp.steady_flow(d, [3.0, 5.0, 8.0]),
    "wind_thresholds": wp.wind_thresholds,
    "water_per_day": lambda d: wp.water_per_day(d, 5.0),
    "operating_point": wp.operating_point,
    "max_head (running)": wp.max_head,
    "max_head (starting)": lambda d: wp.max_head(d, start=True),
}


def median_ms(function, base: wp.Design) -> float:
    times = []
    for design in designs(base, CALLS):
        start = time.perf_counter()
        function(design)
        times.append(time.perf_counter() - start)
    return statistics.median(times) * 1e3


def alpha_plus_error(design: wp.Design) -> float:
    """|alpha+ - brentq's root of F written here| / alpha+ (a tight pump, no pipe)."""
    rotor = design.rotor
    curve = PchipInterpolator(rotor.table_tsr, rotor.table_cq)
    r, V, R = rotor.diameter / 2, design.V_ref, design.R_dagger
    scale = 0.5 * rotor.rho_air * math.pi * r**3 * V**2
    M = design.mean_load_torque

    def F(alpha):
        return R * scale * float(curve(R * alpha * r / V)) - M

    runaway = rotor.runaway_tsr * V / (r * R)
    root = brentq(F, 1e-9 * runaway, runaway * (1 - 1e-12), xtol=1e-15)
    return abs(wp.steady_speeds(design)[0] - root) / root


def main() -> None:
    seed = wp.Design.seed_example().replace(T_0=0.2)
    wheel = wp.Design.from_rotor(wp.Rotor.multiblade(1.5), V_ref=5.0, **seed.geometry())
    wheel = wheel.replace(h=30.0)
    for function in FUNCTIONS.values():  # imports, first calls
        function(seed), function(wheel)
    print(f"{'median of ' + str(CALLS) + ' calls':28s}{'rotor ms':>10s}{'Eq. 11 ms':>11s}{'x':>7s}")
    for name, function in FUNCTIONS.items():
        rotor_ms, eq11_ms = median_ms(function, wheel), median_ms(function, seed)
        print(f"{name:28s}{rotor_ms:10.2f}{eq11_ms:11.3f}{rotor_ms / eq11_ms:7.0f}")
    print(f"alpha+ against brentq on F written here: {alpha_plus_error(wheel):.1e} relative")


if __name__ == "__main__":
    main()
