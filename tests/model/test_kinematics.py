"""Slider-crank kinematics (Eqs. 1, 16) against geometry, derivatives and quadrature."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

import windpump

R, L = 0.04, 0.15
THETA = np.linspace(-2 * math.pi, 4 * math.pi, 601)


def piston_by_construction(theta, R, L):
    """The crank pin at (R sin theta, R cos theta) from the crank centre, the piston on the axis at
    distance L from the pin: its distance from the centre, subtracted from the TDC distance L + R."""
    pin_x, pin_y = R * np.sin(theta), R * np.cos(theta)
    piston_y = pin_y + np.sqrt(L**2 - pin_x**2)
    return (L + R) - piston_y


@pytest.mark.parametrize("L_over_R", [1.05, 1.5, 3.75, 50.0])
def test_piston_position_is_the_geometric_construction(L_over_R):
    x = windpump.piston_position(THETA, R=R, L=R * L_over_R)
    np.testing.assert_allclose(x, piston_by_construction(THETA, R, R * L_over_R), atol=1e-15)


def test_piston_position_at_the_dead_centres_and_long_rod_limit():
    assert windpump.piston_position(0.0, R, L) == pytest.approx(0.0, abs=1e-16)
    assert windpump.piston_position(math.pi, R, L) == pytest.approx(2 * R)
    x = windpump.piston_position(THETA, R, 1e4 * R)  # x = R(1 - cos) + R sin^2 / (2 L/R) + ...
    np.testing.assert_allclose(x, R * (1 - np.cos(THETA)), atol=0.5e-4 * R * 1.001)
    np.testing.assert_allclose(x, R * (1 - np.cos(THETA) + np.sin(THETA) ** 2 / 2e4), atol=1e-12)


@pytest.mark.parametrize("L_over_R", [1.05, 1.5, 3.75, 50.0])
def test_lever_arm_is_the_derivative_of_eq_1(L_over_R):
    step = 1e-6
    slope = (
        windpump.piston_position(THETA + step, R, R * L_over_R)
        - windpump.piston_position(THETA - step, R, R * L_over_R)
    ) / (2 * step)
    np.testing.assert_allclose(windpump.lever_arm(THETA, L_over_R), slope / R, atol=1e-8)


@pytest.mark.parametrize("L_over_R", [1.05, 3.75])
def test_lever_arm_is_the_rod_force_moment_of_eq_12(L_over_R):
    theta_c = np.arcsin(np.sin(THETA) / L_over_R)
    np.testing.assert_allclose(windpump.rod_angle(THETA, L_over_R), theta_c, atol=1e-15)
    np.testing.assert_allclose(
        windpump.lever_arm(THETA, L_over_R), np.sin(THETA + theta_c) / np.cos(theta_c), atol=1e-14
    )


def test_lever_arm_sign_follows_footnote_6():
    """Positive while taking water in, negative while exhausting (a load on the crank)."""
    intake, exhaust = np.linspace(0.01, math.pi - 0.01, 50), np.linspace(math.pi + 0.01, 6.27, 50)
    assert np.all(windpump.lever_arm(intake, 3.75) > 0)
    assert np.all(windpump.lever_arm(exhaust, 3.75) < 0)


@pytest.mark.parametrize("L_over_R", [1.05, 3.75, 100.0])
def test_f2_sweeps_one_stroke_per_revolution(L_over_R):
    """Eq. (16): the integral of f2 over a revolution is 1 (one stroke volume 2RA)."""
    total, _ = quad(
        lambda th: float(windpump.f2(th, L_over_R)), 0, 2 * math.pi, points=[math.pi], epsabs=1e-13
    )
    assert total == pytest.approx(1.0, abs=1e-11)
    assert np.all(windpump.f2(np.linspace(0, math.pi, 50), L_over_R) == 0.0)
    assert np.all(windpump.f2(THETA, L_over_R) >= 0.0)


@pytest.mark.parametrize("theta", [-5.0, 0.3, 3.5, 4.712, 7.0, 12.0, 100.0])
def test_swept_strokes_is_the_integral_of_f2(theta):
    ratio = 1.5
    value, _ = quad(
        lambda th: float(windpump.f2(th, ratio)),
        0.0,
        theta,
        points=[k * math.pi for k in range(-3, 33) if min(0, theta) < k * math.pi < max(0, theta)],
        limit=400,
        epsabs=1e-12,
    )
    assert float(windpump.swept_strokes(theta, ratio)) == pytest.approx(value, abs=1e-10)


@pytest.mark.parametrize("bad", [1.0, 0.5, -3.0, math.nan, math.inf])
def test_the_rod_must_reach_the_crank(bad):
    with pytest.raises(windpump.ParameterError, match="L_over_R"):
        windpump.lever_arm(1.0, bad)
    with pytest.raises(windpump.ParameterError, match="L_over_R"):
        windpump.mean_lever_arm(bad)
