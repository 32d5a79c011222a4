"""docs/validation.rst's numbers held to the functions, and the functions to references by hand.

For the 702's ideal pump (one single-acting cylinder, no rod mass, friction, main or leak) the
averaged model's answers have closed forms written here from the geometry and the rotor's law
T(omega, V) = 1/2 rho_air pi r^3 V^2 C_Q(omega r / V): the steady crank speed balances the gear's
torque against the mean load rho_w g h A R / pi (the load works 2 R A rho_w g h a revolution), the
flow is A 2R per revolution, a running pump keeps running while the torque near rest (the wheel's
largest) exceeds that mean load, and a pump at rest starts while it exceeds the load's peak, the
mean's pi times the slider-crank's largest lever arm (here by finite differences of the piston's
position, R cos(theta) + sqrt(L^2 - R^2 sin^2(theta))). The page's claims are then checked over
every row of the table.
"""

from __future__ import annotations

import math
import statistics

import numpy as np
import pytest
from scipy.optimize import brentq

import windpump
from windpump.catalogue import aermotor_702, aermotor_702_table
from windpump.units import M3_PER_US_GALLON, M_S_PER_MPH, METRES_PER_FOOT

MPH = M_S_PER_MPH
GPH = 3600 / M3_PER_US_GALLON
MAKER = [row for row in aermotor_702_table() if row.source == "aermotor"]
MILLS = [(row, aermotor_702(row.wheel_ft, row.cylinder, lift_ft=row.lift_ft)) for row in MAKER]


def rotor_torque(design, omega, V):
    wheel = design.rotor
    r = wheel.radius
    return 0.5 * wheel.rho_air * math.pi * r**3 * V**2 * float(wheel.cq(omega * r / V))


def mean_load(design):
    """rho_w g h A 2R over a revolution's 2 pi of crank angle [N m]."""
    return design.rho_w * design.g * design.h * design.A * design.R / math.pi


def largest_lever(L_over_R):
    """max of |dx/dtheta| / R over the exhaust half, by central differences of x(theta)/R (the
    same on either half: theta -> -theta mirrors one onto the other)."""
    theta = np.linspace(math.pi, 2 * math.pi, 200_001)
    step = 1e-6

    def x(t):
        return np.cos(t) + np.sqrt(L_over_R**2 - np.sin(t) ** 2)

    return float(np.max(np.abs(x(theta + step) - x(theta - step)) / (2 * step)))


def hand_flow(design, V):
    """The crank speed where R+ T(R+ alpha, V) = mean load, and A 2R alpha / 2 pi [m^3/s]."""
    gear, wheel = design.R_dagger, design.rotor
    runaway = wheel.runaway_tsr * V / wheel.radius / gear
    alpha = brentq(
        lambda a: gear * rotor_torque(design, gear * a, V) - mean_load(design),
        1e-9 * runaway,
        runaway * (1 - 1e-12),
        xtol=1e-15,
        rtol=1e-14,
    )
    return design.A * 2 * design.R * alpha / (2 * math.pi)


SAMPLE = [0, 7, 20, 33]  # 6 ft 1 7/8; 8 ft 2 1/4; 8 ft 2 3/4; 16 ft 3 3/4


@pytest.mark.parametrize("index", SAMPLE)
@pytest.mark.parametrize("mph", [15.0, 17.5, 20.0])
def test_steady_flow_is_the_torque_balance_by_hand(index, mph):
    row, design = MILLS[index]
    V = mph * MPH
    assert float(windpump.steady_flow(design, V)) == pytest.approx(hand_flow(design, V), rel=1e-9)


@pytest.mark.parametrize("index", SAMPLE)
@pytest.mark.parametrize("mph", [15.0, 20.0])
def test_the_ratings_are_the_torque_at_rest_against_the_mean_and_the_peak_load(index, mph):
    row, design = MILLS[index]
    V = mph * MPH
    at_rest = design.R_dagger * rotor_torque(design, 0.0, V)  # the wheel's largest torque
    per_head = design.rho_w * design.g * design.A * design.R  # [N m / m]
    running = math.pi * at_rest / per_head
    starting = at_rest / (per_head * largest_lever(design.L / design.R))
    assert windpump.max_head(design, V) == pytest.approx(running, rel=1e-6)
    assert windpump.max_head(design, V, start=True) == pytest.approx(starting, rel=1e-6)


@pytest.mark.parametrize("index", SAMPLE)
def test_the_starting_wind_at_the_table_s_lift_by_hand(index):
    """T(0, V) ~ V^2: the pump starts where R+ T(0, V) reaches the peak load."""
    row, design = MILLS[index]
    peak = (
        design.rho_w
        * design.g
        * design.h
        * design.A
        * design.R
        * largest_lever(design.L / design.R)
    )
    V = design.V_ref * math.sqrt(peak / (design.R_dagger * rotor_torque(design, 0.0, design.V_ref)))
    assert windpump.wind_thresholds(design)[1] == pytest.approx(V, rel=1e-6)


# -- the page's claims, over every row


def test_the_capacity_claims():
    """8- to 16-ft: 4 to 10 % above the table at 17.5 mph, bracketed by 15 and 20 mph; the 6-ft
    mill 1.5 times; the flagged cell 1.09 times the 260 its row's law predicts."""
    ratios = {}
    for row, design in MILLS:
        ratios[row.wheel_ft, row.cylinder] = [
            float(windpump.steady_flow(design, v * MPH)) * GPH / row.capacity_gph
            for v in (15.0, 17.5, 20.0)
        ]
    large = [
        ratios[r.wheel_ft, r.cylinder] for r in MAKER if r.wheel_ft >= 8 and "out of" not in r.note
    ]
    assert len(large) == 24
    assert all(low < 1 < high for low, _, high in large)
    assert all(1.035 <= mid < 1.105 for _, mid, _ in large)  # the page: 1.04-1.10
    assert statistics.median(mid for _, mid, _ in large) == pytest.approx(1.07, abs=0.005)
    six = [ratios[r.wheel_ft, r.cylinder][1] for r in MAKER if r.wheel_ft == 6]
    assert all(1.5 <= x <= 1.6 for x in six)
    flagged = ratios[8, "2 1/4"][1] * 360
    assert flagged / 260 == pytest.approx(1.09, abs=0.005)


def test_the_lift_claims():
    """The running stall 6.5 to 17 times the table's lift in 15 to 20 mph, the start at 15 mph 2
    to 3 times, and at the table's lift a start from rest in 8.7 to 10.5 mph, every row."""
    running15 = [windpump.max_head(d, 15 * MPH) / d.h for _, d in MILLS]
    running20 = [windpump.max_head(d, 20 * MPH) / d.h for _, d in MILLS]
    starting = [windpump.max_head(d, 15 * MPH, start=True) / d.h for _, d in MILLS]
    start_winds = [windpump.wind_thresholds(d)[1] / MPH for _, d in MILLS]
    assert 6.4 < min(running15) and max(running20) < 17.0
    assert 2.0 < min(starting) and max(starting) < 3.0
    assert 8.6 < min(start_winds) and max(start_winds) < 10.6
    assert statistics.median(start_winds) == pytest.approx(9.17, abs=0.005)
    assert all(d.h == pytest.approx(r.lift_ft * METRES_PER_FOOT, rel=1e-12) for r, d in MILLS)
