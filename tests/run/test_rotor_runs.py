"""Full runs of a rotor's pump: against scipy's DOP853 of Eq. (12) with the rotor's law written in
the test (tests/reference.py), a dense table of the paper's parabola against Eq. (11)'s runs,
furling in a wind record, the energy balance, and a start from rest."""

from __future__ import annotations

import math

import numpy as np
import pytest

import windpump as wp
from windpump import Design, Rotor

from reference import reference_run
from reference import rotor_law as law

SEED = Design.seed_example()


def relative(a, b):
    return abs(a - b) / abs(b)


HUMP = Rotor.from_cq(1.5, [0.0, 0.5, 1.0, 1.5, 2.0, 2.5], [0.1, 0.3, 0.38, 0.3, 0.15, 0.0])
CASES = {
    "multiblade, kicked": (Design.from_rotor(Rotor.multiblade(1.5), V_ref=5.0, **SEED.geometry()),
                           60.0, math.pi / 2, 2.0),
    "multiblade from rest": (Design.from_rotor(Rotor.multiblade(1.5), V_ref=5.0, **SEED.geometry()),
                             30.0, 1.5 * math.pi, 0.0),
    "hump, deep well: stalls": (
        Design.from_rotor(HUMP, V_ref=5.0, **SEED.geometry()).replace(h=60.0), 60.0, math.pi / 2, 1.0),
    "hump, short rod": (Design.from_rotor(HUMP, V_ref=6.0, **SEED.geometry()).replace(L=0.06, h=8.0),
                        60.0, math.pi / 2, 3.0),
}  # fmt: skip


@pytest.mark.parametrize("name", CASES)
def test_a_rotor_s_run_matches_dop853_of_its_law(name):
    design, t_end, theta0, theta_dot0 = CASES[name]
    run = wp.simulate(design, t_end, theta0=theta0, theta_dot0=theta_dot0)
    if theta_dot0 == 0.0:  # the reference starts moving: the torque at rest beats the load
        assert design.eta_t * design.R_dagger * design.T_0 > wp.peak_load_torque(design)
        theta_dot0 = 1e-12  # (the reference's state from rest, a hair above it)
    ref = reference_run(design, t_end, theta0, theta_dot0, windmill=law(design.rotor, design.V_ref))
    assert run.stalled == ref.stalled
    assert relative(run.volume[-1], ref.volume) < 1e-4
    assert relative(run.theta[-1], ref.theta) < 1e-4
    if ref.stalled:
        assert relative(run.t_stall, ref.t_stall) < 1e-3
    else:
        assert relative(run.theta_dot[-1], ref.theta_dot) < 1e-4
        assert relative(run.shaft_work[-1], ref.shaft_work) < 1e-4


@pytest.mark.parametrize("T_0", [0.0, 0.2])
def test_a_dense_table_of_the_paper_s_parabola_runs_as_eq_11(T_0):
    """C_Q(lambda) = T(omega)/(1/2 rho pi r^3 V^2) of Eq. (11) with T_0 on 401 points: PCHIP of
    a parabola differs from it by ~(spacing)^3, and the run with it."""
    eq11 = SEED.replace(T_0=T_0)
    r, V = 0.75, eq11.V_ref
    scale = 0.5 * 1.225 * math.pi * r**3 * V**2
    lam = np.linspace(0.0, 2.5 * eq11.runaway_speed * r / V, 401)
    x = lam * V / (r * eq11.omega_m)
    cq = (T_0 + (eq11.T_m - T_0) * x * (2 - x)) / scale
    rotor = Design.from_rotor(Rotor.from_cq(1.5, lam, cq), V_ref=V, **eq11.geometry())
    assert rotor.T_0 == pytest.approx(T_0, abs=1e-12)
    runs = [wp.simulate(d, 300.0, theta0=math.pi / 2, theta_dot0=3.0) for d in (eq11, rotor)]
    assert relative(runs[1].theta_dot[-1], runs[0].theta_dot[-1]) < 1e-6
    assert relative(runs[1].volume[-1], runs[0].volume[-1]) < 1e-6
    assert wp.steady_speeds(rotor)[0] == pytest.approx(wp.steady_speeds(eq11)[0], rel=1e-7)
    # tau is F's slope at alpha+: PCHIP's derivative is off by ~(spacing)^2, 2e-5 here
    assert wp.time_constant(rotor) == pytest.approx(wp.time_constant(eq11), rel=1e-4)


def test_a_furled_wheel_runs_in_a_gale_as_at_its_furling_wind():
    rotor = Rotor.multiblade(1.5, V_furl=7.0)
    design = Design.from_rotor(rotor, V_ref=5.0, **SEED.geometry()).replace(h=10.0)
    gale = wp.simulate(design, 40.0, theta_dot0=2.0, wind=([0.0, 40.0], [12.0, 12.0]))
    furled = wp.simulate(design, 40.0, theta_dot0=2.0, wind=([0.0, 40.0], [7.0, 7.0]))
    np.testing.assert_array_equal(gale.theta_dot, furled.theta_dot)
    ref = reference_run(design, 40.0, math.pi / 2, 2.0, windmill=law(rotor, 12.0))
    assert relative(gale.theta_dot[-1], ref.theta_dot) < 1e-4


def test_a_rotor_s_run_closes_its_energy_balance():
    design = Design.from_rotor(Rotor.multiblade(1.5), V_ref=5.0, **SEED.geometry()).replace(
        eta_t=0.9, m_r=0.3, L_main=30.0
    )
    run = wp.simulate(design, 60.0, theta_dot0=1.0, wind=([0.0, 30.0, 60.0], [4.0, 8.0, 5.0]))
    budget = wp.power_budget(run)
    assert budget.closure < budget.tolerance and budget.imbalance < 1e-6
