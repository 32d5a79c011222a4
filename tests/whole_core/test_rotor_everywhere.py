"""Every function that takes a design takes a rotor design: the paper's parabola (with a torque at
rest) given as a dense C_Q table must give what Eq. (11) gives, function by function. Eq. (11)'s
answers are held to their own references elsewhere (closed forms, quadrature, DOP853); the rotor
design reaches them by another road (PCHIP, the numeric averaged theory, the table in the
kernels), so the two agree only if both are right, to the table's interpolation error."""

from __future__ import annotations

import math

import numpy as np
import pytest

import windpump as wp

EQ11 = wp.Design.seed_example().replace(T_0=0.2, h=4.0)
RECORD = ([0.0, 300.0, 600.0, 900.0], [3.0, 7.0, 4.0, 6.0])


def parabola_rotor(design: wp.Design, points: int = 401) -> wp.Design:
    """The design's Eq. (11) curve with T_0 as a C_Q table of a 1.5 m wheel (PCHIP between)."""
    r, V = 0.75, design.V_ref
    scale = 0.5 * 1.225 * math.pi * r**3 * V**2
    lam = np.linspace(0.0, 2.5 * design.runaway_speed * r / V, points)
    x = lam * V / (r * design.omega_m)
    cq = (design.T_0 + (design.T_m - design.T_0) * x * (2 - x)) / scale
    return wp.Design.from_rotor(wp.Rotor.from_cq(2 * r, lam, cq), V_ref=V, **design.geometry())


ROTOR = parabola_rotor(EQ11)
REAL = {"eta_t": 0.9, "m_r": 0.4, "L_main": 40.0}


def close(a, b, rel=1e-5):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    np.testing.assert_allclose(a, b, rtol=rel, atol=rel * max(1e-12, float(np.max(np.abs(b)))))


def both(function):
    return function(EQ11), function(ROTOR)


def test_the_curve_s_fields_come_out_as_eq_11_s():
    assert ROTOR.T_0 == pytest.approx(EQ11.T_0, rel=1e-12)
    assert ROTOR.runaway_speed == pytest.approx(EQ11.runaway_speed, rel=1e-9)
    close(wp.windmill_torque(ROTOR, [0.0, 20.0, 50.0, 90.0]),
          wp.windmill_torque(EQ11, [0.0, 20.0, 50.0, 90.0]), rel=1e-5)  # fmt: skip


@pytest.mark.parametrize(
    "name",
    ["stall_margin", "steady_speeds", "time_constant", "spinup", "averaged_stall_time",
     "steady_flow", "wind_thresholds", "water_per_day", "operating_point", "peak_load_torque",
     "starts_from_rest", "max_head", "stall_sides", "load_power"],
)  # fmt: skip
def test_the_averaged_functions(name):
    calls = {
        "stall_margin": wp.stall_margin,
        "steady_speeds": lambda d: wp.steady_speeds(d)[0],
        "time_constant": wp.time_constant,
        "spinup": lambda d: wp.spinup(d, [0.0, 30.0, 120.0, 600.0], 3.0),
        "averaged_stall_time": lambda d: wp.averaged_stall_time(d.replace(h=18.0), 0.5),
        "steady_flow": lambda d: wp.steady_flow(d, [1.0, 3.0, 5.0, 8.0, 12.0]),
        "wind_thresholds": wp.wind_thresholds,
        "water_per_day": lambda d: wp.water_per_day(d, 4.5),
        "operating_point": lambda d: [wp.operating_point(d).omega, wp.operating_point(d).power],
        "peak_load_torque": wp.peak_load_torque,
        "starts_from_rest": lambda d: [
            float(wp.starts_from_rest(d)),
            float(wp.starts_from_rest(d.replace(h=1.0))),
        ],
        "max_head": lambda d: [wp.max_head(d), wp.max_head(d, 3.0), wp.max_head(d, start=True)],
        "stall_sides": lambda d: wp.stall_sides(d)[1] / wp.stall_sides(d)[0],
        "load_power": lambda d: wp.load_power(d, [10.0, 40.0]),
    }
    eq11, rotor = both(calls[name])
    # the margin and the ratings are the curve's peak: PCHIP's ~1e-6 off it between points
    close(rotor, eq11, rel=2e-5)


@pytest.mark.parametrize("real", [False, True])
def test_the_full_runs_alone_in_wind_and_in_a_study(real):
    eq11, rotor = (d.replace(**REAL) if real else d for d in (EQ11, ROTOR))
    runs = [wp.simulate(d, 300.0, theta_dot0=3.0) for d in (eq11, rotor)]
    close(runs[1].theta_dot[-1], runs[0].theta_dot[-1], rel=1e-5)
    close(runs[1].volume[-1], runs[0].volume[-1], rel=1e-5)
    windy = [wp.simulate(d, 900.0, theta_dot0=3.0, wind=RECORD) for d in (eq11, rotor)]
    close(windy[1].volume[-1], windy[0].volume[-1], rel=1e-5)
    budgets = [wp.power_budget(run) for run in windy]
    close(budgets[1].totals().shaft, budgets[0].totals().shaft, rel=1e-5)
    assert budgets[1].closure < budgets[1].tolerance
    if not real:
        explored = [wp.explore(d, 120.0) for d in (eq11, rotor)]
        close(explored[1].run.volume[-1], explored[0].run.volume[-1], rel=1e-5)
        in_wind = [wp.run_in_wind(d, RECORD) for d in (eq11, rotor)]
        close(in_wind[1].run.volume[-1], in_wind[0].run.volume[-1], rel=1e-5)
        swept = wp.sweep([eq11, rotor, rotor.replace(h=6.0)], 60.0)
        close(swept.volume[1], swept.volume[0], rel=1e-5)
        close(swept.alpha_plus[1], swept.alpha_plus[0], rel=1e-5)


def test_the_map_and_a_site_s_year():
    ratios, heads = np.linspace(2.0, 8.0, 7), np.linspace(1.0, 12.0, 5)
    maps = [wp.design_map(d, ratios, heads) for d in (EQ11, ROTOR)]
    close(np.nan_to_num(maps[1].mean_flow), np.nan_to_num(maps[0].mean_flow), rel=1e-5)
    close(maps[1].stall_gear_ratio, maps[0].stall_gear_ratio, rel=2e-5)
    record = wp.sample_site("greensboro")
    supplies = [wp.supply(d, record, demand=0.5, tank=3.0).totals for d in (EQ11, ROTOR)]
    close(supplies[1].pumped, supplies[0].pumped, rel=1e-4)
    tanks = [wp.tank_for(d, record, demand=0.5) for d in (EQ11, ROTOR)]
    close(tanks[1], tanks[0], rel=1e-3)
    grids = [wp.supply_map(d, record, 0.5, [3.0, 4.0], [1.0, 5.0]) for d in (EQ11, ROTOR)]
    close(grids[1].pumped, grids[0].pumped, rel=1e-4)
