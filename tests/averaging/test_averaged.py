"""The averaged theory (Eqs. 18-25) and the operating point (Eq. 5), against independent computations."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import windpump

from conftest import SEED, SEED_MARGIN
from reference import averaged_rhs

NEAR_STALL = SEED.replace(h=3.0 * SEED_MARGIN / 1.05)
OVERLOAD = SEED.replace(h=3.0 * SEED_MARGIN / 0.95)


@pytest.mark.parametrize("ratio", np.geomspace(1.05, 1000.0, 25))
def test_mean_lever_arm_is_minus_one_over_pi(ratio):
    """Eq. (18) for every L/R: the cos theta tan theta_c part integrates to 0 (docs/model.rst)."""
    assert windpump.mean_lever_arm(ratio) == pytest.approx(-1 / math.pi, abs=1e-10)


def test_seed_groups_match_model_notes():
    """docs/model.rst, "The paper's example": the margin is about 5.1 and tau about 79 s."""
    assert windpump.stall_margin(SEED) == pytest.approx(5.1, abs=0.05)
    assert windpump.time_constant(SEED) == pytest.approx(79, abs=1)


def test_margin_compares_peak_windmill_torque_with_mean_load():
    """Eq. (22) restated: R+ T_m against rho_w g h A R / pi."""
    mean_load = SEED.rho_w * SEED.g * SEED.h * SEED.A * SEED.R / math.pi
    assert windpump.stall_margin(SEED) == pytest.approx(
        SEED.R_dagger * SEED.T_m / mean_load, rel=1e-12
    )
    assert windpump.stall_margin(SEED.replace(h=0.0)) == math.inf


@pytest.mark.parametrize("design", [SEED, NEAR_STALL, SEED.replace(h=0.0), SEED.replace(T_m=3.0)])
def test_steady_speeds_are_the_roots_of_the_averaged_equation(design):
    rhs = averaged_rhs(design)
    top = 2 * design.omega_m / design.R_dagger
    vertex = design.omega_m / design.R_dagger  # fastest acceleration, between the roots
    alpha_plus, alpha_minus = windpump.steady_speeds(design)
    assert alpha_plus == pytest.approx(brentq(rhs, vertex, top, xtol=1e-14), rel=1e-10)
    if design.h > 0:
        assert alpha_minus == pytest.approx(brentq(rhs, 0.0, vertex, xtol=1e-14), rel=1e-10)
    else:
        assert alpha_minus == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("design", [SEED, NEAR_STALL, SEED.replace(T_m=3.0)])
def test_time_constant_is_the_relaxation_time_at_alpha_plus(design):
    """tau (Eq. 25) = -1 / (d rhs / d speed) at alpha+, by a central difference of Eq. (19)."""
    rhs = averaged_rhs(design)
    alpha_plus, _ = windpump.steady_speeds(design)
    step = 1e-5 * alpha_plus
    slope = (rhs(alpha_plus + step) - rhs(alpha_plus - step)) / (2 * step)
    assert windpump.time_constant(design) == pytest.approx(-1 / slope, rel=1e-8)


@pytest.mark.parametrize(
    "function", [windpump.steady_speeds, windpump.time_constant, windpump.operating_point]
)
def test_no_steady_state_past_the_stall_criterion(function):
    with pytest.raises(windpump.StallError, match=r"0\.95"):
        function(OVERLOAD)
    assert issubclass(windpump.StallError, ValueError)


SPINUP_CASES = {
    "above alpha+": (SEED, 40.0),
    "between alpha- and alpha+": (SEED, 3.0),
    "below alpha-": (SEED, 1.0),
    "near stall": (NEAR_STALL, 12.0),
    "margin below 1": (OVERLOAD, 12.0),
    "no load": (SEED.replace(h=0.0), 0.5),
}


@pytest.mark.parametrize("name", list(SPINUP_CASES))
def test_spinup_solves_the_averaged_equation(name):
    """Eq. (24) against solve_ivp on Eq. (19), up to the stall if there is one."""
    design, speed0 = SPINUP_CASES[name]
    rhs = averaged_rhs(design)

    def stalls(_t, y):
        return y[0]

    stalls.terminal = True
    sol = solve_ivp(
        lambda _t, y: [rhs(y[0])],
        (0, 1500),
        [speed0],
        method="DOP853",
        rtol=1e-12,
        atol=1e-12,
        events=stalls,
        dense_output=True,
    )
    t = np.linspace(0, sol.t[-1], 400)
    expected = sol.sol(t)[0]
    np.testing.assert_allclose(windpump.spinup(design, t, speed0), expected, rtol=1e-8, atol=1e-9)
    t_stall = windpump.averaged_stall_time(design, speed0)
    if sol.status == 1:
        assert t_stall == pytest.approx(sol.t_events[0][0], rel=1e-8)
        assert windpump.spinup(design, [t_stall * 1.01, 1e4], speed0).tolist() == [0.0, 0.0]
    else:
        assert t_stall is None


def test_spinup_at_the_steady_speeds_stays_there():
    alpha_plus, alpha_minus = windpump.steady_speeds(SEED)
    t = np.linspace(0, 500, 11)
    np.testing.assert_allclose(windpump.spinup(SEED, t, alpha_plus), alpha_plus, rtol=1e-12)
    np.testing.assert_allclose(windpump.spinup(SEED, t, alpha_minus), alpha_minus, rtol=1e-9)


def test_spinup_tracks_the_simulated_cycle_mean_on_the_seed_example():
    """The averaged theory (Eq. 24) against the full integration's cycle mean (its Fig. 3).

    Measured (and recorded in the README): they agree within 0.03 % over all 1,543 revolutions;
    the test allows 0.1 %.
    """
    run = windpump.simulate(SEED, 600.0, theta_dot0=3.0)
    t_mid, mean_speed = run.cycle_mean_speed()
    predicted = windpump.spinup(SEED, t_mid, 3.0)
    assert len(mean_speed) > 1500
    assert np.max(np.abs(mean_speed / predicted - 1)) < 1e-3


def test_stall_criterion_against_the_simulation():
    """Eq. (22): margin 0.95 stalls; margin 1.05, kicked above alpha-, keeps running."""
    _, alpha_minus = windpump.steady_speeds(NEAR_STALL)
    running = windpump.simulate(NEAR_STALL, 1500.0, theta_dot0=1.05 * alpha_minus)
    assert not running.stalled
    assert running.theta_dot[-1] > alpha_minus
    assert windpump.simulate(OVERLOAD, 1500.0, theta_dot0=12.0).stalled


def test_operating_point_is_alpha_plus_and_balances_the_hydraulic_power():
    op = windpump.operating_point(SEED)
    alpha_plus, alpha_minus = windpump.steady_speeds(SEED)
    assert op.omega == pytest.approx(SEED.R_dagger * alpha_plus, rel=1e-12)
    assert op.omega_unstable == pytest.approx(SEED.R_dagger * alpha_minus, rel=1e-9)
    mean_flow = SEED.A * SEED.R * alpha_plus / math.pi  # Eq. (2)
    assert op.flow == pytest.approx(mean_flow, rel=1e-12)
    assert op.power == pytest.approx(SEED.rho_w * SEED.g * SEED.h * mean_flow, rel=1e-10)
    assert op.power == pytest.approx(float(windpump.load_power(SEED, op.omega)), rel=1e-10)
    assert op.power_unstable == pytest.approx(
        float(windpump.load_power(SEED, op.omega_unstable)), rel=1e-9
    )


def test_operating_point_is_where_the_simulation_settles():
    """The full integration's cycle-mean speed at the end of a long run sits at alpha+ (within the
    ripple the averaging neglects)."""
    run = windpump.simulate(SEED, 1500.0)
    _, mean_speed = run.cycle_mean_speed()
    assert mean_speed[-1] == pytest.approx(windpump.operating_point(SEED).crank_speed, rel=1e-3)
