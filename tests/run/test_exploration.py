"""windpump.explore (what the app shows) and fit_torque_curve (students' lab data)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import curve_fit

import windpump
from windpump import Status

from conftest import SEED, SEED_MARGIN


def test_explore_gathers_the_core_figures():
    seen = windpump.explore(SEED, 600.0, math.pi / 2, 3.0, points=50)
    assert seen.status is Status.RUNNING
    assert seen.margin == windpump.stall_margin(SEED)
    assert (seen.alpha_plus, seen.alpha_minus) == windpump.steady_speeds(SEED)
    assert seen.tau == windpump.time_constant(SEED)
    assert seen.operating_point == windpump.operating_point(SEED)
    np.testing.assert_array_equal(seen.spinup_t, np.linspace(0, 600, 50))
    np.testing.assert_array_equal(seen.spinup_speed, windpump.spinup(SEED, seen.spinup_t, 3.0))
    run = windpump.simulate(SEED, 600.0)
    np.testing.assert_array_equal(seen.run.theta_dot, run.theta_dot)
    assert seen.pumped_volume == run.volume[-1]
    assert seen.mean_flow == pytest.approx(run.volume[-1] / 600.0)
    assert seen.intermittency == run.intermittency()


@pytest.mark.parametrize(
    "design, t_end, kick, status",
    [
        (SEED, 600.0, 3.0, Status.RUNNING),
        (SEED, 600.0, 1.0, Status.NEVER_STARTED),  # below alpha- = 1.29 rad/s
        (SEED, 600.0, 0.0, Status.NEVER_STARTED),
        (SEED.replace(h=3.0 * SEED_MARGIN / 0.95), 1500.0, 12.0, Status.STALLED),
        (SEED.replace(h=3.0 * SEED_MARGIN / 0.95), 100.0, 12.0, Status.SLOWING),
    ],
)
def test_status(design, t_end, kick, status):
    seen = windpump.explore(design, t_end, theta_dot0=kick)
    assert seen.status is status
    if status in (Status.STALLED, Status.NEVER_STARTED):
        assert seen.run.stalled
    if design.h > 3.0:
        assert seen.alpha_plus is None and seen.tau is None and seen.operating_point is None


def test_explore_without_a_whole_revolution():
    seen = windpump.explore(SEED, 600.0, theta_dot0=0.0)
    assert seen.intermittency is None and seen.mean_flow == 0.0 and len(seen.cycle_t) == 0


@settings(deadline=None)
@given(st.floats(0.01, 100.0), st.floats(0.5, 500.0), st.integers(3, 40))
def test_fit_recovers_an_exact_curve(T_m, omega_m, count):
    omega = np.linspace(0.05, 2.0, count) * omega_m
    torque = T_m * (omega / omega_m) * (2 - omega / omega_m)
    fit = windpump.fit_torque_curve(omega, torque)
    assert fit.T_m == pytest.approx(T_m, rel=1e-9)
    assert fit.omega_m == pytest.approx(omega_m, rel=1e-9)
    assert fit.rms_residual <= 1e-9 * T_m


def test_fit_of_noisy_data_is_the_least_squares_optimum():
    """Against scipy's nonlinear least squares on Eq. (11) directly."""
    rng = np.random.default_rng(7)
    omega = np.linspace(2, 95, 30)
    torque = 0.6 * (omega / 50) * (2 - omega / 50) + rng.normal(0, 0.02, omega.size)
    fit = windpump.fit_torque_curve(omega, torque)
    (T_m, omega_m), _ = curve_fit(
        lambda w, T, wm: T * (w / wm) * (2 - w / wm), omega, torque, p0=[0.5, 40.0]
    )
    assert fit.T_m == pytest.approx(T_m, rel=1e-6)
    assert fit.omega_m == pytest.approx(omega_m, rel=1e-6)


@pytest.mark.parametrize(
    "omega, torque, name",
    [
        ([1.0, 2.0], [1.0], "torque"),
        ([1.0, math.nan], [1.0, 2.0], "omega"),
        ([-1.0, 2.0], [1.0, 2.0], "omega"),
        ([2.0, 2.0, 0.0], [1.0, 1.0, 0.0], "omega"),
        ([1.0, 2.0, 3.0], [1.0, 2.0, 3.0], "torque"),  # rising: no peak
    ],
)
def test_fit_rejects_data_it_cannot_fit(omega, torque, name):
    with pytest.raises(windpump.ParameterError, match=f"^{name} = "):
        windpump.fit_torque_curve(omega, torque)


def test_why_a_run_never_started():
    """Each reason against what the run shows: no torque at rest and no kick; a load at theta0
    heavier than R+ T_0 (the crank never moves); a kick below alpha- (it turns, then rests)."""
    left = windpump.explore(SEED, 60.0, theta_dot0=0.0)
    assert SEED.T_0 == 0.0 and left.not_started is windpump.NotStarted.NO_KICK
    # At 3 pi / 2 the lever arm is -1 (Eq. 12): the load is rho_w g h A R; give R+ T_0 half that.
    load = SEED.rho_w * SEED.g * SEED.h * math.pi * SEED.bore**2 / 4 * SEED.R
    held_design = SEED.replace(T_0=0.5 * load / SEED.R_dagger)
    held = windpump.explore(held_design, 60.0, 3 * math.pi / 2, 0.0)
    assert np.all(held.run.theta == 3 * math.pi / 2)
    assert held.not_started is windpump.NotStarted.HELD_AT_REST
    gentle = windpump.explore(SEED, 600.0, theta_dot0=1.0)
    assert 1.0 < gentle.alpha_minus and gentle.run.t_stall > 0.0
    assert gentle.not_started is windpump.NotStarted.KICK_TOO_SMALL
    slowing = SEED.replace(h=3.0 * SEED_MARGIN / 0.95)
    for started in (windpump.explore(SEED, 60.0), windpump.explore(slowing, 1500.0, 0.5, 12.0)):
        assert started.status is not Status.NEVER_STARTED and started.not_started is None
