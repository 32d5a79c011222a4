"""The frames the explorer plays, and the design helpers the app relies on, against the run and
against geometry."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import windpump
from windpump import Design, ParameterError

SEED = Design.seed_example()


@pytest.fixture(scope="module")
def run():
    return windpump.simulate(SEED, 600.0)


def test_frames_are_the_run_on_a_uniform_grid(run):
    frames = windpump.playback_frames(run, max_frames=3000)
    assert len(frames.t) == 3000 and frames.t[0] == 0 and frames.t[-1] == run.t[-1]
    np.testing.assert_allclose(np.diff(frames.t), frames.t[1] - frames.t[0], rtol=1e-9)
    # A frame's angle is the run's: compare with a cubic Hermite of the run's own samples.
    from scipy.interpolate import CubicHermiteSpline

    exact = CubicHermiteSpline(run.t, run.theta, run.theta_dot)(frames.t)
    np.testing.assert_allclose(frames.theta, exact, atol=1e-4)
    np.testing.assert_allclose(frames.volume, np.interp(frames.t, run.t, run.volume))


def test_hermite_between_frames_stays_on_the_run(run):
    """What player.js does between frames, done here in numpy: within a hundredth of a radian."""
    frames = windpump.playback_frames(run, max_frames=3000)
    t = np.linspace(0, 600, 10_007)
    k = np.clip(np.searchsorted(frames.t, t) - 1, 0, len(frames.t) - 2)
    h = frames.t[k + 1] - frames.t[k]
    s = (t - frames.t[k]) / h
    between = (
        (2 * s**3 - 3 * s**2 + 1) * frames.theta[k]
        + (s**3 - 2 * s**2 + s) * h * frames.theta_dot[k]
        + (-2 * s**3 + 3 * s**2) * frames.theta[k + 1]
        + (s**3 - s**2) * h * frames.theta_dot[k + 1]
    )
    assert np.max(np.abs(between - np.interp(t, run.t, run.theta))) < 0.01


def test_a_short_run_gets_frames_a_quarter_turn_apart():
    short = windpump.simulate(SEED, 10.0)
    frames = windpump.playback_frames(short)
    assert np.max(np.diff(frames.theta)) <= math.pi / 2 + 1e-9
    stalled_at_once = windpump.simulate(SEED, 10.0, theta_dot0=0.0)
    assert len(windpump.playback_frames(stalled_at_once).t) == 2


def test_the_piston_table_is_eq_1(run):
    theta, x = windpump.piston_table(SEED, 361)
    geometric = (
        SEED.L
        + SEED.R
        - (np.sqrt(SEED.L**2 - (SEED.R * np.sin(theta)) ** 2) + SEED.R * np.cos(theta))
    )
    np.testing.assert_allclose(x, geometric, atol=1e-15)
    with pytest.raises(ParameterError, match="max_frames"):
        windpump.playback_frames(run, max_frames=0)


@given(st.floats(1.0001, 50.0), st.floats(0.01, 50.0))
def test_ratios_set_the_rod_and_sprocket(L_over_R, R_dagger):
    d = SEED.with_ratios(L_over_R=L_over_R, R_dagger=R_dagger)
    assert d.L_over_R == pytest.approx(L_over_R, rel=1e-14)
    assert d.R_dagger == pytest.approx(R_dagger, rel=1e-14)
    assert (d.R, d.R0) == (SEED.R, SEED.R0)


@pytest.mark.parametrize(
    "name, value", [("L_over_R", 1.0), ("L_over_R", 0.5), ("R_dagger", 0.0), ("L_over_R", math.nan)]
)
def test_bad_ratios_name_the_ratio(name, value):
    with pytest.raises(ParameterError, match=name):
        SEED.with_ratios(**{name: value})


def test_the_stall_sides_are_eq_22():
    for h in (0.5, 3.0, 21.0):
        d = SEED.replace(h=h)
        windmill, load = windpump.stall_sides(d)
        assert windmill == pytest.approx(d.R_dagger**2 * d.T_m / (d.omega_m**2 * d.I_eff))
        assert load == pytest.approx(
            d.R_dagger * d.rho_w * d.g * h * d.A * d.R / (d.omega_m**2 * d.I_eff * math.pi)
        )
        assert windmill / load == pytest.approx(windpump.stall_margin(d), rel=1e-12)


def test_the_bore_gives_back_the_area():
    assert math.pi * SEED.bore**2 / 4 == pytest.approx(SEED.A, rel=1e-15)


def test_the_slider_crank_pose_is_closed_once_and_matches_eq_1():
    for theta in np.linspace(0, 2 * math.pi, 25):
        pose = windpump.linkage.slider_crank_pose(theta, SEED.R, SEED.L)
        assert pose.x == pytest.approx(
            float(windpump.piston_position(theta, SEED.R, SEED.L)), abs=1e-12
        )
        centre, pin, piston = pose.joints
        assert math.dist(centre, pin) == pytest.approx(SEED.R) and math.dist(
            pin, piston
        ) == pytest.approx(SEED.L)
        assert piston[1] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("cylinders", [1, 2, 3, 5])
def test_the_crank_table_is_each_cylinder_s_slider_crank_at_its_own_lag(cylinders):
    d = SEED.replace(cylinders=cylinders)
    table = windpump.crank_table(d, 361)
    assert table.piston.shape == table.pin_x.shape == (cylinders, 361)
    for k in range(cylinders):
        # Geometry, not Eq. (1): the pin on the crank circle at the cylinder's own angle, the
        # piston pin on the axis one rod length from it.
        pin_x, pin_y, top = table.pin_x[k], table.pin_y[k], table.piston_y[k]
        np.testing.assert_allclose(np.hypot(pin_x, pin_y), d.R, rtol=1e-14)
        own = np.arctan2(-pin_x, pin_y)
        lag = table.theta - 2 * math.pi * k / cylinders
        np.testing.assert_allclose(np.remainder(own - lag + math.pi, 2 * math.pi), math.pi)
        np.testing.assert_allclose(np.hypot(pin_x, top - pin_y), d.L, rtol=1e-14)
        assert np.all(top > pin_y)  # the piston above its crank
        np.testing.assert_allclose(table.piston[k], d.L + d.R - top, atol=1e-15)
    with pytest.raises(ParameterError, match="points"):
        windpump.crank_table(d, 1)


def test_frames_carry_what_the_machine_draws():
    d = SEED.replace(cylinders=3, h=2.0)
    run = windpump.simulate(d, 120.0)
    frames = windpump.playback_frames(run, max_frames=500)
    np.testing.assert_allclose(frames.rotor_angle, d.R_dagger * frames.theta, rtol=1e-15)
    np.testing.assert_allclose(frames.rotor_speed, np.interp(frames.t, run.t, run.omega))
    np.testing.assert_allclose(frames.tank_level, frames.volume / run.volume[-1], rtol=1e-15)
    assert frames.tank_level[0] == 0.0 and frames.tank_level[-1] == 1.0
    for k in range(3):
        phi = frames.theta - 2 * math.pi * k / 3
        eq1 = d.L + d.R - (np.sqrt(d.L**2 - (d.R * np.sin(phi)) ** 2) + d.R * np.cos(phi))
        np.testing.assert_allclose(frames.pistons[k], eq1, atol=1e-15)
    for name in ("theta", "piston", "pin_x", "pin_y", "piston_y"):
        np.testing.assert_array_equal(
            getattr(frames.table, name), getattr(windpump.crank_table(d), name)
        )
    dry = windpump.playback_frames(windpump.simulate(SEED, 10.0, theta_dot0=0.0))
    assert np.all(dry.tank_level == 0.0)  # nothing pumped: an empty tank, not 0/0


def test_between_frames_the_table_puts_each_part_where_the_run_has_it(run):
    """What player.js does at a time between frames, in numpy: the crank angle by Hermite, then
    each part linearly in the table; against the run's own angle through Eq. (1)."""
    frames = windpump.playback_frames(run, max_frames=3000)
    table = frames.table
    t = np.linspace(1.0, 599.0, 2001)
    k = np.clip(np.searchsorted(frames.t, t) - 1, 0, len(frames.t) - 2)
    h = frames.t[k + 1] - frames.t[k]
    s = (t - frames.t[k]) / h
    theta = (
        (2 * s**3 - 3 * s**2 + 1) * frames.theta[k]
        + (s**3 - 2 * s**2 + s) * h * frames.theta_dot[k]
        + (-2 * s**3 + 3 * s**2) * frames.theta[k + 1]
        + (s**3 - s**2) * h * frames.theta_dot[k + 1]
    )
    drawn = np.interp(np.mod(theta, 2 * math.pi), table.theta, table.piston_y[0])
    exact = (
        SEED.L + SEED.R - windpump.piston_position(np.interp(t, run.t, run.theta), SEED.R, SEED.L)
    )
    assert np.max(np.abs(drawn - exact)) < 1e-3 * SEED.R  # well under a pixel, as drawn
