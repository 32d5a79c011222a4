"""Start-up power (the ski lift) and the wind pump's power budget, against independent references."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.integrate import quad, simpson

import windpump
from windpump.run.energy import power_budget, startup_power

from conftest import SEED
from reference import equation_12

# -- the seed's ski lift ----------------------------------------------------------------------


def test_the_ski_lift_needs_43_7_kilowatts():
    chairs = 1000 / 20  # 1 km one way, a chair every 20 m
    power = startup_power(chairs * 250.0, 10 / 3.6, 5.0, 200 / 1000)
    assert round(power.accelerate / 1e3, 1) == 9.6
    assert round(power.lift / 1e3, 1) == 34.1
    assert round(power.total / 1e3, 1) == 43.7
    accelerate, lift, total = power  # unpacks as (accelerate, lift, total)
    assert total == pytest.approx(accelerate + lift, rel=1e-15)


@given(
    mass=st.floats(1.0, 1e5),
    speed=st.floats(0.0, 50.0),
    duration=st.floats(0.1, 100.0),
    grade=st.floats(-1.0, 1.0),
)
def test_startup_power_is_the_mean_of_force_times_speed(mass, speed, duration, grade):
    # Constant acceleration a: at time t the drive pushes m (a + g grade) at speed a t.
    a, g = speed / duration, 9.81
    accelerate = quad(lambda t: mass * a * (a * t), 0.0, duration)[0] / duration
    lift = quad(lambda t: mass * g * grade * (a * t), 0.0, duration)[0] / duration
    power = startup_power(mass, speed, duration, grade)
    scale = max(abs(accelerate) + abs(lift), 1e-300)
    assert power.accelerate == pytest.approx(accelerate, abs=1e-12 * scale)
    assert power.lift == pytest.approx(lift, abs=1e-12 * scale)


@pytest.mark.parametrize(
    "arguments, name",
    [
        ((0.0, 1.0, 1.0, 0.1), "mass"),
        ((1.0, -1.0, 1.0, 0.1), "speed"),
        ((1.0, 1.0, 0.0, 0.1), "duration"),
        ((1.0, 1.0, 1.0, 1.5), "grade"),
        ((1.0, 1.0, 1.0, math.nan), "grade"),
    ],
)
def test_startup_power_names_a_bad_argument(arguments, name):
    with pytest.raises(windpump.ParameterError) as caught:
        startup_power(*arguments)
    assert caught.value.name == name


@pytest.mark.parametrize(
    "arguments, name",
    [((1e300, 1e300, 1e-300, 1.0, 1e300), "mass"), ((1.0, 1e300, 1.0, 0.1), "speed"),
     ((1.0, 1.0, 1e-300, 0.1), "duration"), ((1.0, 1.0, 1.0, 0.1, 1e300), "g"),
     ((1e-300, 1.0, 1.0, 0.1), "mass")],
)  # fmt: skip
def test_startup_power_refuses_what_overflows_by_name_and_range(arguments, name):
    # issue 36's re-probe: (1e300, 1e300, 1e-300, 1, g=1e300) raised a bare OverflowError
    with pytest.raises(windpump.ParameterError) as caught:
        startup_power(*arguments)
    lowest = "0" if name == "speed" else "1e-12"
    assert caught.value.name == name and f"from {lowest} to 1e+12" in str(caught.value)


def test_startup_power_is_finite_and_right_at_the_ends_of_its_ranges():
    # the closed forms m v^2 / (2 T) and m g grade v / 2 at the largest and smallest values
    power = startup_power(1e12, 1e12, 1e-12, -1.0, g=1e12)
    assert power.accelerate == pytest.approx(0.5 * 1e12 * 1e24 / 1e-12, rel=1e-15)
    assert power.lift == pytest.approx(-0.5 * 1e12 * 1e12 * 1e12, rel=1e-15)
    tiny = startup_power(1e-12, 0.0, 1e12, 1.0, g=1e-12)
    assert tiny == (0.0, 0.0, 0.0)


# -- the wind pump's budget -------------------------------------------------------------------


@pytest.fixture(scope="module")
def seed_budget(runs):
    (design, t_end, theta0, theta_dot0), run, reference = runs["seed example"]
    return design, run, power_budget(run), reference


def test_the_seed_examples_budget_closes(seed_budget):
    design, run, budget, reference = seed_budget
    assert budget.imbalance < 1e-6
    # ... and each integral agrees with the DOP853 reference, which integrates the shaft power
    # and the flow as states of its own
    kinetic = 0.5 * design.I_eff * (reference.theta_dot**2 - run.theta_dot[0] ** 2)
    lift = design.rho_w * design.g * design.h * reference.volume
    assert budget.shaft_work[-1] == pytest.approx(reference.shaft_work, rel=1e-6)
    assert budget.kinetic_energy[-1] == pytest.approx(kinetic, rel=1e-6)
    assert budget.lift_work[-1] == pytest.approx(lift, rel=1e-6)
    assert budget.shaft_work[-1] == pytest.approx(kinetic + lift, rel=1e-6)


def test_each_power_is_the_papers_at_every_sample(seed_budget):
    design, run, budget, _ = seed_budget
    exhaust = np.remainder(run.theta, 2 * math.pi) > math.pi
    rates = np.array(
        [
            equation_12(design, bool(e))(0.0, [theta, speed, 0.0, 0.0])
            for theta, speed, e in zip(run.theta, run.theta_dot, exhaust, strict=True)
        ]
    )
    peak = budget.shaft_power.max()
    np.testing.assert_allclose(budget.shaft_power, rates[:, 3], rtol=0, atol=1e-12 * peak)
    hydraulic = design.rho_w * design.g * design.h * rates[:, 2]
    np.testing.assert_allclose(budget.hydraulic_power, hydraulic, rtol=0, atol=1e-9 * peak)
    kinetic = design.I_eff * run.theta_dot * rates[:, 1]  # d(I theta_dot^2 / 2)/dt
    np.testing.assert_allclose(budget.kinetic_power, kinetic, rtol=0, atol=1e-9 * peak)
    assert budget.hydraulic_power.min() == 0.0 and budget.hydraulic_power.max() > 0.0


def test_the_powers_integrate_to_the_energies(seed_budget):
    _, _, budget, _ = seed_budget
    # Simpson's rule on the uneven samples: its pairs of intervals never straddle a dead centre
    # (16 samples a stroke, the run starts half a stroke before one), so it keeps its 4th order
    for power, energy in (
        (budget.shaft_power, budget.shaft_work),
        (budget.kinetic_power, budget.kinetic_energy),
        (budget.hydraulic_power, budget.lift_work),
    ):
        integral = simpson(power, x=budget.t)
        assert integral == pytest.approx(energy[-1] - energy[0], rel=1e-5)


def test_cycle_means_show_spin_up_giving_way_to_lifting(seed_budget):
    design, run, budget, _ = seed_budget
    means = budget.cycle_means()
    np.testing.assert_allclose(means.shaft, means.kinetic + means.hydraulic, rtol=1e-9)
    # Most of the power goes into speed early on, mostly into water at the end (tau = 79 s)
    share = means.kinetic / means.shaft
    assert share[0] > 0.5 and share.max() > 0.75 and 0 < share[-1] < 0.1
    assert np.all(np.diff(share[len(share) // 2 :]) < 0)  # and it keeps falling
    # At the end it lifts rho g h times the mean flow
    last = run.intermittency(revolutions=1)
    assert means.hydraulic[-1] == pytest.approx(
        design.rho_w * design.g * design.h * last.mean_flow, rel=1e-9
    )


@pytest.mark.parametrize("case", ["overload, margin 0.95", "kick below alpha-"])
def test_a_slowing_rotor_gives_its_energy_back(runs, case):
    (design, *_), run, _ = runs[case]
    budget = power_budget(run)
    assert budget.imbalance < 1e-6
    assert budget.kinetic_energy[-1] < 0  # it ends slower than it was kicked
    assert budget.cycle_means().kinetic.min() < 0


def test_the_budget_takes_the_runs_own_design():
    run = windpump.simulate(SEED.replace(cylinders=2, double_acting=True, h=1.0), 30.0)
    budget = power_budget(run)
    assert budget.imbalance < 1e-8
    expected = 1000 * 9.81 * 1.0 * run.flow  # rho_w g h Q with both faces of both cylinders
    np.testing.assert_allclose(budget.hydraulic_power, expected, rtol=1e-12)
    with pytest.raises(TypeError, match="SimulationResult"):
        power_budget("a run")


# -- the overall efficiency: what the water was given, never more than the work ------------------


@given(
    h=st.floats(0.5, 30.0),
    eta_t=st.floats(0.5, 1.0),
    theta_dot0=st.sampled_from([0.0, 1.0, 3.0, 12.0, 40.0]),
    m_r=st.sampled_from([0.0, 2.0]),
    L_main=st.sampled_from([0.0, 20.0]),
    d_leak=st.sampled_from([0.0, 0.002]),
    t_end=st.floats(5.0, 300.0),
)
def test_the_overall_efficiency_is_the_waters_share_of_what_it_was_given(
    h, eta_t, theta_dot0, m_r, L_main, d_leak, t_end
):
    """At most 1 on every run, stalled or spinning up (rho_w g h V / W was 456 % on a stalled
    run: its kick's kinetic energy lifted water); and, by the power budget's balance, the water's
    share of the work less the kinetic and potential energy gained."""
    design = SEED.replace(h=h, eta_t=eta_t, m_r=m_r, L_main=L_main, d_leak=d_leak)
    run = windpump.simulate(design, t_end, theta_dot0=theta_dot0)
    overall = run.overall_efficiency
    totals = power_budget(run).totals()
    given_to_water = totals.shaft - totals.kinetic - totals.potential
    if totals.water == 0.0 and given_to_water <= 1e-9 * max(totals.shaft, 1.0):
        return  # nothing lifted nor lost: NaN, or 0 once a loss is counted
    assert 0.0 <= overall <= 1.0
    if totals.transmission >= 0.0:  # the windmill drove the crank (kicked past its runaway it
        # brakes, and the chain's loss is counted as a loss all the same)
        assert overall == pytest.approx(max(totals.water, 0.0) / given_to_water, rel=1e-5, abs=1e-8)
    if eta_t == 1.0 and L_main == 0.0 and d_leak == 0.0:
        assert overall == pytest.approx(1.0, abs=1e-12) or totals.water == 0.0
