"""The averaged theory of a rotor's pump (no closed form) against references written here: F's
roots by brentq, tau from F's derivative, the stall margin by dense sampling and a bounded
search, the spin-up by solve_ivp; the ratings against the stall and start criteria."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.interpolate import PchipInterpolator
from scipy.optimize import brentq, minimize_scalar

import windpump as wp
from windpump import Design, Rotor

SEED = Design.seed_example()


def wheel(V_furl=None, **changes):
    rotor = Rotor.multiblade(1.5, V_furl=V_furl)
    return Design.from_rotor(rotor, V_ref=5.0, **SEED.geometry()).replace(**changes)


# A rotor whose C_Q rises from 0.1 at rest to a peak and falls: alpha- exists (below it F < 0)
HUMP = Rotor.from_cq(1.5, [0.0, 0.5, 1.0, 1.5, 2.0, 2.5], [0.1, 0.3, 0.38, 0.3, 0.15, 0.0])


def hump(**changes):
    return Design.from_rotor(HUMP, V_ref=5.0, **SEED.geometry()).replace(**changes)


def torque(design: Design, omega: float, V: float | None = None) -> float:
    """The rotor's law, written here from its table and scipy's PCHIP."""
    rotor = design.rotor
    V = design.V_ref if V is None else V
    V_s = V if rotor.V_furl is None else min(V, rotor.V_furl)
    r = rotor.diameter / 2
    curve = PchipInterpolator(rotor.table_tsr, rotor.table_cq)
    lam = omega * r / V_s
    last = rotor.table_tsr[-1]
    cq = (
        float(curve(lam))
        if lam <= last
        else rotor.table_cq[-1] + float(curve.derivative()(last)) * (lam - last)
    )
    return 0.5 * rotor.rho_air * math.pi * r**3 * V_s**2 * cq


def F(design: Design, alpha: float, V: float | None = None) -> float:
    """eta_t R+ T(R+ alpha) - (M + c alpha^2): the averaged equation's right side (tight pump)."""
    R = design.R_dagger
    M = design.deliveries * design.rho_w * design.g * design.h * design.A * design.R / math.pi
    c = wp.averaging.revolution.friction_load(design)
    return design.eta_t * R * torque(design, R * alpha, V) - (M + c * alpha * alpha)


def I_bar(design: Design) -> float:
    return design.I_eff + wp.averaging.revolution.reciprocating_inertia(design)


CASES = {
    "multiblade": wheel(h=30.0),
    "multiblade, a pipe and a lossy chain": wheel(h=30.0, L_main=80.0, eta_t=0.85, m_r=0.5),
    "hump": hump(h=10.0),
    "hump, furled": Design.from_rotor(
        Rotor.from_cq(1.5, HUMP.table_tsr, HUMP.table_cq, V_furl=4.0), V_ref=5.0, **SEED.geometry()
    ).replace(h=5.0),
}


@pytest.mark.parametrize("name", CASES)
def test_roots_time_constant_and_margin_against_brentq_and_sampling(name):
    d = CASES[name]
    R = d.R_dagger
    runaway = d.rotor.runaway_tsr * min(d.V_ref, d.rotor.V_furl or math.inf) / (d.rotor.radius * R)
    alpha = np.linspace(1e-9, runaway, 4001)
    values = np.array([F(d, a) for a in alpha])
    last_positive = int(np.flatnonzero(values > 0).max())
    alpha_plus = brentq(
        lambda a: F(d, a), alpha[last_positive], alpha[last_positive + 1], xtol=1e-14
    )
    a_plus, a_minus = wp.steady_speeds(d)
    assert a_plus == pytest.approx(alpha_plus, rel=1e-9)
    below = np.flatnonzero(values[:last_positive] <= 0)
    if below.size:  # a rising root below alpha+
        i = int(below.max())
        expected = brentq(lambda a: F(d, a), alpha[i], alpha[i + 1], xtol=1e-14)
        assert a_minus == pytest.approx(expected, rel=1e-9)
    else:
        assert a_minus is None
    step = 1e-5 * alpha_plus
    slope = (F(d, alpha_plus + step) - F(d, alpha_plus - step)) / (2 * step)
    assert wp.time_constant(d) == pytest.approx(I_bar(d) / -slope, rel=1e-6)

    def ratio(a):
        M = d.deliveries * d.rho_w * d.g * d.h * d.A * d.R / math.pi
        c = wp.averaging.revolution.friction_load(d)
        return d.eta_t * R * torque(d, R * a) / (M + c * a * a)

    sampled = np.array([ratio(a) for a in alpha])
    best = int(np.argmax(sampled))
    lo, hi = alpha[max(best - 1, 0)], alpha[min(best + 1, alpha.size - 1)]
    refined = -minimize_scalar(lambda a: -ratio(a), bounds=(lo, hi), method="bounded",
                               options={"xatol": 1e-12}).fun  # fmt: skip
    assert wp.stall_margin(d) == pytest.approx(max(refined, sampled.max()), rel=1e-9)
    flow = d.volume_per_revolution * alpha_plus / (2 * math.pi)
    assert float(wp.steady_flow(d, d.V_ref)) == pytest.approx(flow, rel=1e-9)


@pytest.mark.parametrize("name, kick", [("multiblade", 0.0), ("hump", 2.0), ("hump", 0.5)])
def test_spinup_against_solve_ivp_of_the_averaged_equation(name, kick):
    d = CASES[name]
    t = np.array([0.0, 0.5, 2.0, 5.0, 20.0])
    reference = solve_ivp(
        lambda _t, y: [F(d, max(y[0], 0.0)) / I_bar(d)], (0.0, t[-1]), [kick],
        method="DOP853", rtol=1e-11, atol=1e-12, t_eval=t,
        events=lambda _t, y: y[0] if _t > 0 else 1.0,
    )  # fmt: skip
    speed = np.interp(t, reference.t, reference.y[0], right=0.0)
    if reference.t_events[0].size:  # stalled: at rest after
        stall = reference.t_events[0][0]
        speed = np.where(t >= stall, 0.0, speed)
        assert wp.averaged_stall_time(d, kick) == pytest.approx(stall, rel=1e-6)
    else:
        assert wp.averaged_stall_time(d, kick) is None
    # (PCHIP is C1 only: the quadrature's panels converge more slowly across its knots, ~3e-6)
    np.testing.assert_allclose(wp.spinup(d, t, kick), speed, rtol=2e-5, atol=1e-9)


def test_a_stalled_rotor_pump_has_no_steady_speed():
    d = hump(h=400.0)
    assert wp.stall_margin(d) < 1.0
    with pytest.raises(wp.StallError):
        wp.steady_speeds(d)
    assert float(wp.steady_flow(d, 5.0)) == 0.0


@pytest.mark.parametrize("name", ["multiblade", "multiblade, a pipe and a lossy chain", "hump"])
def test_max_head_running_is_where_the_margin_is_one(name):
    d = CASES[name]
    for V in (None, 3.0, 7.0):
        H = wp.max_head(d, V)
        at = d.replace(h=H) if V is None else d.replace(h=H).in_wind(V)
        assert wp.stall_margin(at) == pytest.approx(1.0, rel=1e-7)


@pytest.mark.parametrize("design", [wheel(h=30.0), wheel(h=30.0, m_r=2.0), SEED.replace(T_0=0.3)])
def test_max_head_starting_is_the_start_criterion(design):
    H = wp.max_head(design, start=True)
    assert wp.starts_from_rest(design.replace(h=0.999 * H))
    assert not wp.starts_from_rest(design.replace(h=1.001 * H))
    assert wp.wind_thresholds(design.replace(h=H))[1] == pytest.approx(design.V_ref, rel=1e-6)


def test_the_paper_s_curve_needs_a_kick_and_a_leak_never_stalls():
    assert wp.max_head(SEED, start=True) == 0.0
    assert wp.max_head(SEED.replace(d_leak=0.004)) == math.inf
    assert wp.max_head(SEED) == pytest.approx(3.0 * wp.stall_margin(SEED), rel=1e-12)


def test_a_furled_wheel_s_thresholds_and_water():
    d = wheel(V_furl=6.0, h=30.0)
    V_stop, V_start = wp.wind_thresholds(d)
    assert wp.stall_margin(d.in_wind(V_stop)) == pytest.approx(1.0, rel=1e-9)
    assert wp.starts_from_rest(d.in_wind(1.0001 * V_start))
    assert not wp.starts_from_rest(d.in_wind(0.9999 * V_start))
    # furled: a wind above V_furl gives what V_furl gives
    assert float(wp.steady_flow(d, 12.0)) == pytest.approx(float(wp.steady_flow(d, 6.0)), rel=1e-12)
    # a head the wheel can start against only above its furl: it never starts
    H = wp.max_head(d, V=6.0, start=True)
    assert wp.wind_thresholds(d.replace(h=1.01 * H))[1] == math.inf
    low, high = wp.water_per_day(d, 5.0)
    assert 0.0 < low <= high
