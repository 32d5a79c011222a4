"""The real machine in the integrator: reciprocating mass, transmission, rising main, leak hole.

Every run is checked against tests/real_reference.py, a tight DOP853 integration of the issue's
equations written independently of the kernels, and the energy balance against its named terms.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st
from real_reference import real_reference_run

import windpump
from windpump import _kernels, reciprocating
from windpump.run.dynamics import kernel_machine

SEED = windpump.Design.seed_example()

DESIGNS = {
    "heavy rod": SEED.replace(m_r=1.5),
    "lossy chain": SEED.replace(eta_t=0.85),
    "thin main": SEED.replace(L_main=20.0, D_main=0.02),
    "leak hole": SEED.replace(d_leak=0.003),
    "every effect": SEED.replace(m_r=1.0, eta_t=0.9, L_main=20.0, d_leak=0.002),
    "two double-acting": SEED.replace(
        m_r=1.0, eta_t=0.9, L_main=20.0, d_leak=0.002, cylinders=2, double_acting=True, h=1.0
    ),
    "three cylinders": SEED.replace(m_r=0.5, L_main=30.0, D_main=0.03, d_leak=0.001, cylinders=3),
}


@pytest.mark.parametrize("name", DESIGNS)
def test_a_run_follows_the_reference(name):
    design = DESIGNS[name]
    run = windpump.simulate(design, 20.0)
    ref = real_reference_run(design, 20.0, math.pi / 2, 3.0)
    assert not run.stalled and not ref.stalled
    assert run.t[-1] == pytest.approx(ref.t, abs=1e-12)
    assert run.theta[-1] == pytest.approx(ref.theta, rel=1e-5)  # with a hole: ~2e-6 (measured)
    assert run.theta_dot[-1] == pytest.approx(ref.theta_dot, rel=1e-5)
    assert run.volume[-1] == pytest.approx(ref.volume, rel=1e-5)
    assert run.shaft_work[-1] == pytest.approx(ref.shaft_work, rel=1e-5)
    W = ref.shaft_work
    assert run.friction_loss[-1] == pytest.approx(ref.friction_loss, abs=5e-5 * W)
    lift = design.rho_w * design.g * design.h
    leak = ref.faces_work - lift * ref.volume - ref.friction_loss
    assert run.leak_loss[-1] == pytest.approx(leak, abs=5e-5 * W)


@pytest.mark.parametrize("name", DESIGNS)
def test_the_energy_closes_with_each_loss_named(name):
    design = DESIGNS[name]
    budget = windpump.power_budget(windpump.simulate(design, 600.0))
    assert budget.imbalance < 1e-9
    totals = budget.totals()
    assert totals.imbalance < 1e-9
    assert totals.transmission == pytest.approx((1 - design.eta_t) * totals.shaft, rel=1e-12)
    assert totals.friction >= 0.0 and totals.leak >= -1e-9 * totals.shaft
    if design.friction_coefficient == 0.0:
        assert totals.friction == 0.0
    if design.leak_capacity == 0.0:
        assert abs(totals.leak) < 1e-9 * totals.shaft


def test_the_ideal_machine_keeps_its_own_kernel():
    assert SEED.is_ideal and kernel_machine(SEED).real is None
    neutral = SEED.replace(m_r=0.0, eta_t=1.0, L_main=0.0, d_leak=0.0, f_main=0.05)
    assert neutral.is_ideal
    assert not SEED.replace(eta_t=0.99).is_ideal
    assert SEED.replace(L_main=10.0, f_main=0.0).is_ideal  # a frictionless main adds nothing


def test_the_real_kernel_with_vanishing_effects_tends_to_the_ideal_run():
    ideal = windpump.simulate(SEED, 60.0)
    almost = windpump.simulate(SEED.replace(m_r=1e-9, d_leak=1e-9, L_main=1e-9), 60.0)
    assert almost.theta_dot[-1] == pytest.approx(ideal.theta_dot[-1], rel=1e-7)
    assert almost.volume[-1] == pytest.approx(ideal.volume[-1], rel=1e-7)


def test_a_leak_hole_lets_a_pump_start_that_the_tight_one_cannot():
    weak = SEED.replace(T_0=0.1)  # R+ T_0 = 0.4 N m, below the static load's peak (1.22 N m)
    assert not windpump.starts_from_rest(weak)
    tight = windpump.simulate(weak, 200.0, theta0=1.5 * math.pi, theta_dot0=0.0)
    assert tight.stalled and tight.t_stall == 0.0
    holed = weak.replace(d_leak=0.004)  # it crawls (sweeping less than the hole passes), then runs
    run = windpump.simulate(holed, 200.0, theta0=1.5 * math.pi, theta_dot0=0.0)
    ref = real_reference_run(holed, 200.0, 1.5 * math.pi, 0.0)
    assert not run.stalled and not ref.stalled
    assert run.theta_dot[-1] == pytest.approx(ref.theta_dot, rel=1e-5)
    assert run.volume[-1] == pytest.approx(ref.volume, rel=1e-4)
    assert 0.0 < run.volumetric_efficiency < 1.0


def test_the_efficiencies_are_the_volumes_and_works_over_the_run():
    run = windpump.simulate(DESIGNS["every effect"], 600.0)
    assert run.volumetric_efficiency == pytest.approx(run.volume[-1] / run.swept_volume[-1])
    # the water's share of what it was given: W less the kinetic and potential energy gained
    totals = windpump.power_budget(run).totals()
    given = totals.shaft - totals.kinetic - totals.potential
    assert run.overall_efficiency == pytest.approx(totals.water / given, rel=1e-6)
    assert 0.0 < run.overall_efficiency < 1.0
    tight = windpump.simulate(SEED, 60.0)
    assert tight.volumetric_efficiency == 1.0


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    theta=st.floats(-20.0, 20.0),
    m_r=st.floats(0.0, 50.0),
    cylinders=st.integers(1, 6),
    ratio=st.floats(1.05, 20.0),
)
def test_the_kernels_masses_are_the_numpy_sides(theta, m_r, cylinders, ratio):
    design = SEED.replace(m_r=m_r, cylinders=cylinders, L=SEED.R * ratio)
    machine = kernel_machine(design)
    if machine.real is None:  # m_r = 0: the ideal machine
        machine = machine._replace(real=kernel_machine(design.replace(eta_t=0.5)).real)
    from windpump._kernels import real

    j = real._inertia_ratio(theta, machine) * design.I_eff
    assert j == pytest.approx(float(reciprocating.crank_inertia(design, theta)), rel=1e-12)
    torque = real._weight_torque(theta, machine)
    expected = float(windpump.model.loads.weight_torque(design, theta))
    assert torque == pytest.approx(expected, rel=1e-12, abs=1e-12 * m_r * design.g * design.R)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    m_r=st.floats(0.0, 3.0),
    eta_t=st.floats(0.5, 1.0),
    L_main=st.floats(0.0, 40.0),
    leak=st.floats(0.0, 0.5),
    cylinders=st.integers(1, 3),
    double_acting=st.booleans(),
)
def test_any_real_machine_closes_its_energy_and_delivers_at_most_what_it_sweeps(
    m_r, eta_t, L_main, leak, cylinders, double_acting
):
    design = SEED.replace(
        m_r=m_r, eta_t=eta_t, L_main=L_main, d_leak=leak * SEED.bore, cylinders=cylinders,
        double_acting=double_acting, h=1.0,
    )  # fmt: skip
    run = windpump.simulate(design, 30.0)
    budget = windpump.power_budget(run)
    assert budget.imbalance < 1e-9
    assert np.all(run.volume <= run.swept_volume * (1 + 1e-9) + 1e-15)
    assert np.all(run.volume >= -2e-6 * run.swept_volume[-1])  # swept less leaked, each to ~1e-6
    assert np.all(np.diff(run.volume) >= -2e-6 * run.swept_volume[-1])  # to its accuracy


@pytest.mark.parametrize("name", ["leak hole", "every effect", "two double-acting"])
@pytest.mark.parametrize("sample_dt", [None, 0.37])
def test_a_leaky_runs_flow_is_what_its_faces_deliver(name, sample_dt):
    # The kernel computes the delivered flow (the lever arms tabulated on the output grid);
    # numpy's face_flows computes it again from the samples' angles and speeds.
    run = windpump.simulate(DESIGNS[name], 30.0, sample_dt=sample_dt)
    faces = windpump.face_flows(run.theta, run.theta_dot, run.design).sum(axis=0)
    assert np.any(faces == 0.0) and np.any(faces > 0.0)  # the hole takes some samples' flow
    np.testing.assert_allclose(run.flow, faces, rtol=1e-12, atol=1e-12 * faces.max())


def test_the_kernel_returns_no_real_rows_for_the_ideal_machine():
    run = _kernels.run(kernel_machine(SEED), math.pi / 2, 3.0, 1.0, 16, None, 1e-8, 10**6, 64)
    assert run.leaked is None and run.friction_loss is None


def test_in_a_lull_a_leaky_pump_rests_and_starts_again_by_its_torque_at_rest():
    from real_reference import torque_at_rest

    design = SEED.replace(T_0=0.1, d_leak=0.004, m_r=0.5, cylinders=2)
    lull = ([0.0, 600.0, 610.0, 2400.0, 2410.0], [5.0, 5.0, 0.0, 0.0, 6.0])  # calm air
    run = windpump.simulate(design, 3600.0, theta_dot0=0.0, wind=lull, sample_dt=1.0)
    assert len(run.stops) >= 1 and len(run.starts) >= 2 and not run.stalled
    width = math.pi / design.cylinders
    for times, moving in ((run.stops, False), (run.starts, True)):
        for t in times:
            theta = float(np.interp(t, run.t, run.theta))
            V = float(np.interp(t, *lull))
            mid = (math.floor(theta / width) + 0.5) * width
            net = torque_at_rest(design.in_wind(max(V, 1e-3)), theta, mid)
            assert (net > 0.0) == moving or abs(net) < 1e-9
    assert windpump.power_budget(run).imbalance < 1e-9


def test_a_design_maps_simulated_points_run_the_real_machine():
    from windpump._kernels.grid import steady_runs
    from windpump.run.dynamics import MAX_STEPS, PACE_STEPS, RTOL, kernel_real_base
    from windpump.run.machine import kernel_rotor

    design = DESIGNS["every effect"]
    base = np.array([design.T_m, design.T_0, design.omega_m, design.L_over_R])
    # Every argument given, as design_map gives them: an omitted ``rotor`` is a type of its own
    # to numba, and its parallel kernel took 1.5-5 minutes to compile for this test alone.
    speed, _, _ = steady_runs(
        np.array([design.R_dagger]), np.array([1 / design.I_eff]),
        np.array([design.load_torque]), np.array([23.0]), np.array([300.0]), base, 1, False, 5,
        RTOL, MAX_STEPS, PACE_STEPS, kernel_real_base(design), kernel_rotor(design),
    )  # fmt: skip
    run = windpump.simulate(design, 300.0, theta_dot0=23.0)
    marks, times = windpump.revolution_marks(run.t, run.theta)
    expected = 5 * 2 * math.pi / (times[-1] - times[-6])
    assert speed[0] == pytest.approx(expected, rel=1e-3)


def test_a_numeric_design_map_of_a_real_machine_measures_its_real_runs():
    design = SEED.replace(eta_t=0.8, L_main=20.0, D_main=0.02)  # a lossy chain, a thin main
    ratios, heads = [3.0, 4.0], [2.0, 3.0]
    averaged = windpump.design_map(design, ratios, heads)
    numeric = windpump.design_map(design, ratios, heads, numeric=True)
    ideal = windpump.design_map(SEED, ratios, heads, numeric=True)
    # The runs' steady speeds are the real averaged theory's to its ripple, well off the ideal's.
    assert np.allclose(numeric.alpha_plus, averaged.alpha_plus, rtol=2e-3)
    assert np.all(numeric.alpha_plus < 0.97 * ideal.alpha_plus)


def test_each_power_of_the_budget_integrates_to_its_work():
    from scipy.integrate import cumulative_trapezoid

    run = windpump.simulate(DESIGNS["every effect"], 20.0, samples_per_stroke=512)
    budget = windpump.power_budget(run)
    W = budget.shaft_work[-1]
    pairs = [
        (budget.shaft_power, budget.shaft_work),
        (budget.transmission_power, budget.transmission_loss),
        (budget.friction_power, budget.friction_loss),
        (budget.leak_power, budget.leak_loss),
        (budget.weight_power, budget.potential_energy),
        (budget.kinetic_power, budget.kinetic_energy),
        (budget.hydraulic_power, budget.lift_work),
    ]
    for power, work in pairs:
        integrated = cumulative_trapezoid(power, run.t, initial=0.0)
        assert np.max(np.abs(integrated - work)) < 1e-5 * W  # the trapezoid rule: ~6e-7


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    levers=st.lists(st.floats(0.0, 1.5), min_size=1, max_size=6),
    theta_dot=st.floats(0.0, 60.0),
    leak=st.floats(0.0, 0.9),
    L_main=st.floats(0.0, 60.0),
    D_main=st.floats(0.01, 0.1),
)
def test_the_kernels_face_loads_are_the_numpy_sides(levers, theta_dot, leak, L_main, D_main):
    """The compiled twin of windpump.model.loads.faces_load (kept for speed) gives its numbers."""
    from windpump._kernels import real

    design = SEED.replace(
        cylinders=len(levers), d_leak=leak * SEED.bore, L_main=L_main, D_main=D_main,
        eta_t=0.9,  # a real machine whatever the rest
    )  # fmt: skip
    machine = kernel_machine(design)
    row = np.zeros(real.ROW)
    row[1 : 1 + len(levers)] = levers
    load, Q, _, arms = real._face_loads(theta_dot, row, machine)
    expected_load, expected_Q = windpump.model.loads.faces_load(
        np.array(levers)[:, None], theta_dot, design
    )
    scale = design.load_torque * max(sum(levers), 1.0)
    assert load == pytest.approx(float(expected_load[0]), rel=1e-12, abs=1e-12 * scale)
    assert Q == pytest.approx(float(expected_Q[0]), rel=1e-12, abs=1e-18)
    assert arms == pytest.approx(sum(levers), rel=1e-15, abs=0.0)


def _numpy_frozen_friction(design, theta, e):
    """The rising main's friction torque [N m] at theta when the energy J theta_dot^2 / (2 I_eff)
    is e, from the numpy side: faces_load's load less the static head's (no hole)."""
    J = float(reciprocating.crank_inertia(design, theta))
    theta_dot = math.sqrt(2.0 * e * design.I_eff / J)
    levers = windpump.model.kinematics.face_levers(np.array([theta]), design)
    load, _ = windpump.model.loads.faces_load(levers, theta_dot, design)
    static = design.load_torque * levers.sum()
    return float(load[0]) - static


@st.composite
def _mains(draw):
    """Real machines with a rising main and no hole, any cylinders and masses."""
    return SEED.replace(
        m_r=draw(st.floats(0.0, 5.0)), L_main=draw(st.floats(0.1, 60.0)),
        D_main=draw(st.floats(0.01, 0.1)), cylinders=draw(st.integers(1, 6)),
        double_acting=draw(st.booleans()), L=SEED.R * draw(st.floats(1.05, 20.0)),
    )  # fmt: skip


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(design=_mains(), theta=st.floats(-20.0, 20.0), e=st.floats(1e-3, 1e4))
def test_the_kernels_frozen_friction_is_the_numpy_sides(design, theta, e):
    """The kernels' friction split at a frozen energy (c(theta) . (e_ref, sqrt(e_ref), 1) I_eff:
    its own copy of the main's friction, kept for speed) is faces_load's friction at that
    energy's speed."""
    from windpump._kernels import model, real

    machine = kernel_machine(design)
    segment = model.segment_at(theta, machine)
    first, second, third = real.friction_density(theta, segment, machine)
    compiled = (first * e + second * math.sqrt(e) + third) * design.I_eff
    expected = _numpy_frozen_friction(design, theta, e)
    assert second == third == 0.0  # (a tight piston's friction is the first part alone)
    scale = design.load_torque * 1e-12 * design.cylinders
    assert compiled == pytest.approx(expected, rel=1e-11, abs=scale)


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    design=_mains(), hole=st.floats(0.001, 0.5), theta=st.floats(-20.0, 20.0),
    e=st.floats(1e-3, 1e4),
)  # fmt: skip
def test_with_a_hole_the_frozen_friction_is_the_continued_loads_friction(design, hole, theta, e):
    """With a leak hole the frozen friction's three parts, at the weights (e, sqrt(e), 1), are
    the main's friction of the loads continued past the hole's windows (each delivering face
    delivers what it sweeps less q_L) at that energy's speed: rho_w g K q (q theta_dot -
    faces q_L)^2, q = A R sum |dx/dtheta| / R, written here from the issue's conventions."""
    from windpump._kernels import model, real

    design = design.replace(d_leak=hole * design.bore)
    angles = np.mod(
        windpump.model.kinematics.cylinder_angles(np.array([theta]), design.cylinders), np.pi
    )
    assume(np.all(np.minimum(angles, np.pi - angles) > 1e-9))  # no face at a dead centre
    machine = kernel_machine(design)
    segment = model.segment_at(theta, machine)
    first, second, third = real.friction_density(theta, segment, machine)
    compiled = (first * e + second * math.sqrt(e) + third) * design.I_eff
    levers = windpump.model.kinematics.face_levers(np.array([theta]), design)[:, 0]
    J = float(reciprocating.crank_inertia(design, theta))
    theta_dot = math.sqrt(2.0 * e * design.I_eff / J)
    q = design.A * design.R * float(levers.sum())
    held = float((levers > 0.0).sum()) * design.leak_capacity
    expected = (
        design.rho_w * design.g * design.friction_coefficient * q * (q * theta_dot - held) ** 2
    )
    scale = design.load_torque * 1e-12 * design.cylinders
    assert compiled == pytest.approx(expected, rel=1e-10, abs=scale)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    design=_mains(), segment=st.integers(-6, 6), ends=st.tuples(st.floats(0, 1), st.floats(0, 1))
)
@example(  # a short main: the reference's round-off is 1.7e-10 of the friction's integral
    design=SEED.replace(R=0.04, L=0.08, double_acting=True, L_main=0.25, D_main=0.09375),
    segment=0,
    ends=(0.0, 0.5),
)
def test_the_frozen_frictions_integral_is_a_quadrature_of_the_numpy_friction(design, segment, ends):
    """C between two angles of a segment (Gauss-Legendre on pieces, in the kernels) against
    scipy's quad of the numpy side's friction per unit energy over I_eff."""
    from scipy.integrate import quad

    from windpump._kernels import model, real

    machine = kernel_machine(design)
    width = math.pi / design.cylinders
    start = model.segment_start(segment, machine)
    a, b = (start + width * f for f in sorted(ends))
    compiled, second, third = real.friction_between(a, b, segment, machine)
    assert second == third == 0.0  # (a tight piston)

    def density(theta):
        return _numpy_frozen_friction(design, theta, 1.0) / design.I_eff

    def static_density(theta):
        levers = windpump.model.kinematics.face_levers(np.array([theta]), design)
        return design.load_torque * float(levers.sum()) / design.I_eff

    expected, _ = quad(density, a, b, epsabs=0.0, epsrel=1e-13, limit=200)
    whole, _ = quad(density, start, start + width, epsabs=0.0, epsrel=1e-13, limit=200)
    # The numpy side's friction is a load less the static head's: a short main's is lost in that
    # difference's round-off (~1e-16 of the static load; 6e-6 of the friction near a dead centre
    # of a 0.25 m main), which the reference then carries: ~100 ulps of the static work allowed.
    static, _ = quad(static_density, a, b, limit=200)
    bound = 1e-10 * whole + 1e-14 * static + 1e-300
    assert compiled == pytest.approx(expected, rel=0.0, abs=bound)


# -- A leak hole's windows, jumped (docs/model.rst, "The real machine"). --------------------


def continued_rhs(design, segment_mid):
    """real_reference's machine_rhs on the loads continued through a hole's windows (u - q_L at
    rho_w g (h + h_f)), the loads a windowed segment is stepped on; and I_eff."""
    from real_reference import machine_rhs

    I_eff = design.I1 + design.I0 * (design.R1 / design.R0) ** 2
    return machine_rhs(design, segment_mid, continued=True), I_eff


def across(rhs, theta_from, theta_dot, theta_to):
    """(t, theta_dot, V, W, F, P) where a tight DOP853 run from theta_from (t = 0) reaches
    theta_to."""
    from scipy.integrate import solve_ivp

    def reaches(_t, y):
        return y[0] - theta_to

    reaches.terminal = True
    sol = solve_ivp(
        rhs, (0.0, 10.0), [theta_from, theta_dot, 0, 0, 0, 0], method="DOP853", rtol=1e-13,
        atol=1e-16, events=reaches,
    )  # fmt: skip
    t = sol.t_events[0][0]
    return np.concatenate([[t], sol.y_events[0][0][1:]])


def inertia(design, theta, I_eff):
    """J and dJ/dtheta [kg m^2, kg m^2/rad] at theta."""
    from real_reference import piston

    J, J_slope = I_eff, 0.0
    for k in range(design.cylinders):
        _, dx, ddx = piston(design, theta - 2 * math.pi * k / design.cylinders)
        J += design.m_r * dx * dx
        J_slope += 2 * design.m_r * dx * ddx
    return J, J_slope


WINDOWED = {  # design, a segment with a window after its start, one with one before its end, speed
    "seed, 1.5 mm": (SEED.replace(d_leak=0.0015), 1, 1, 16.0),
    "every effect": (
        SEED.replace(m_r=1.0, eta_t=0.9, L_main=10, D_main=0.025, d_leak=0.0015),
        1,
        1,
        14.0,
    ),
    "two double-acting": (DESIGNS["two double-acting"], 2, 1, 12.0),  # two windows at pi
    "three cylinders": (DESIGNS["three cylinders"], 3, 3, 15.0),
    "a slow seed, 3 mm": (SEED.replace(d_leak=0.003), 1, 1, 6.0),  # windows 0.09 rad wide
}


@pytest.mark.parametrize("name", WINDOWED)
@pytest.mark.parametrize("side", [1.0, -1.0])
def test_a_windows_jump_is_the_true_run_less_the_continued_one(name, side):
    # Across a window, from the same state on one side: the true loads (real_reference) by
    # DOP853, against the continued loads by DOP853 with the jump where the driver takes it
    # (after the jump at a segment's start; before it at its end), agree past the window to
    # second order in the jump.
    from real_reference import machine_rhs

    design, after_start, before_end, speed = WINDOWED[name]
    segment = after_start if side > 0 else before_end
    width = math.pi / design.cylinders
    dead_centre = (segment if side > 0 else segment + 1) * width
    far = dead_centre + side * 0.2
    rhs, I_eff = continued_rhs(design, (segment + 0.5) * width)
    start, stop = (dead_centre, far) if side > 0 else (far, dead_centre)
    true = across(machine_rhs(design, (segment + 0.5) * width), start, speed, stop)
    cont = across(rhs, start, speed, stop)
    J, J_slope = inertia(design, dead_centre, I_eff)
    at = speed if side > 0 else cont[1]  # the jump from the state at the dead centre
    e = 0.5 * J * at**2 / I_eff
    slope = (J * rhs(0.0, [dead_centre, at])[1] + 0.5 * J_slope * at**2) / I_eff  # de/dtheta
    machine = kernel_machine(design)
    delivers = _kernels.model.delivering_face
    faces = sum(1.0 for k in range(design.cylinders) if delivers(segment, k, machine))
    rows = np.empty((7, _kernels.real.ROW))
    jump, dt, works = _kernels.real._window_jump(
        dead_centre, e, slope, side, segment, faces, J / I_eff, rows, machine
    )
    assert jump > 0.0 and works[1] < 0.0  # a relief, and less leaks back than q_L would
    if side > 0:  # continued from e + jump
        cont = across(rhs, start, math.sqrt(2 * (e + jump) * I_eff / J), stop)
        gained = 0.0
    else:
        gained = jump
    J_far = inertia(design, stop, I_eff)[0]
    e_true, e_cont = (0.5 * J_far * run[1] ** 2 / I_eff for run in (true, cont))
    assert e_true - e_cont == pytest.approx(gained, abs=1e-4 * jump)
    assert true[0] - cont[0] == pytest.approx(dt, rel=1e-3)
    assert cont[2] - true[2] == pytest.approx(works[1], rel=1e-4)  # delivered
    assert true[4] - cont[4] == pytest.approx(works[2], rel=1e-4, abs=1e-12)  # friction
    assert true[5] - cont[5] == pytest.approx(works[3], rel=1e-4)  # the faces' work


@settings(max_examples=80, deadline=None)
@given(
    levers=st.lists(st.floats(0.0, 1.5), min_size=1, max_size=6),
    theta_dot=st.floats(0.5, 60.0),
    leak=st.floats(0.0, 0.9),
    L_main=st.floats(0.0, 60.0),
)
def test_the_continued_loads_are_the_face_loads_where_every_face_delivers(
    levers, theta_dot, leak, L_main
):
    """Where every delivering face sweeps more than its hole passes, the continued loads (what a
    windowed segment is stepped on) are faces_load's; inside a window they differ."""
    from windpump._kernels import real

    design = SEED.replace(
        cylinders=len(levers), d_leak=leak * SEED.bore, L_main=L_main, eta_t=0.9
    )  # (eta_t: a real machine whatever the rest)
    machine = kernel_machine(design)
    row = np.zeros(real.ROW + 2)
    row[1 : 1 + len(levers)] = levers
    swept = design.A * design.R * np.array(levers) * theta_dot
    q_L = machine.real.q_L
    load, Q, h_f, arms = real._continued_loads(theta_dot, row, float(len(levers)), machine)
    expected_load, expected_Q = windpump.model.loads.faces_load(
        np.array(levers)[:, None], theta_dot, design
    )
    assert Q == pytest.approx(float(np.sum(swept - q_L)), rel=1e-12, abs=1e-18)
    if np.all(swept > q_L):
        scale = design.load_torque * max(sum(levers), 1.0)
        assert load == pytest.approx(float(expected_load[0]), rel=1e-12, abs=1e-12 * scale)
        assert Q == pytest.approx(float(expected_Q[0]), rel=1e-9, abs=1e-18)


@settings(max_examples=200, deadline=None)
@given(s=st.floats(-0.3, 0.3))
def test_a_windows_sine_and_cosine_are_the_librarys(s):
    """A window's sin s and cos s (Taylor's up to SMALL_ANGLE) to round-off."""
    from windpump._kernels import real

    sin, cos = real._sin_cos(s)
    assert sin == pytest.approx(math.sin(s), rel=3e-16, abs=1e-300)
    assert cos == pytest.approx(math.cos(s), rel=3e-16)


@settings(max_examples=200, deadline=None)
@given(phi=st.floats(-7.0, 7.0), ratio=st.floats(1.05, 10.0))
def test_a_windows_lever_arm_is_eq_1s(phi, ratio):
    """The windows' lever arm and its slope from sin and cos are equations.lever_arm's and
    lever_arm_slope's."""
    from windpump._kernels import equations, real

    arm, slope = real._arm_of(math.sin(phi), math.cos(phi), ratio)
    assert arm == pytest.approx(float(equations.lever_arm(phi, ratio)), rel=1e-13, abs=1e-15)
    expected = float(equations.lever_arm_slope(phi, ratio))
    assert slope == pytest.approx(expected, rel=1e-13, abs=1e-13)


@settings(max_examples=100, deadline=None)
@given(target=st.floats(1e-6, 0.05), ratio=st.floats(1.1, 10.0), top=st.booleans())
def test_a_windows_kink_is_where_the_arm_reaches_its_target(target, ratio, top):
    """s past a dead centre where |lever arm| = target: against a 30-digit root of Eq. (1)'s
    derivative (mpmath, the dead centre pi exact)."""
    import mpmath

    from windpump._kernels import real

    s = real._window_kink(target, top, ratio, real.WINDOW_NEWTON)
    with mpmath.workdps(30):
        k, L = (1 if top else -1), mpmath.mpf(ratio)

        def arm(x):  # |x'/R| at s past the top (phi = s) or bottom (phi = pi + s) dead centre
            return mpmath.sin(x) * (1 + k * mpmath.cos(x) / mpmath.sqrt(L**2 - mpmath.sin(x) ** 2))

        exact = mpmath.findroot(lambda x: arm(x) - mpmath.mpf(target), mpmath.mpf(s))
        assert s == pytest.approx(float(exact), rel=1e-14)


@settings(max_examples=100, deadline=None)
@given(
    levers=st.lists(st.floats(0.0, 1.5), min_size=1, max_size=6),
    theta_dot=st.floats(0.5, 60.0),
    leak=st.floats(0.01, 0.9),
    L_main=st.floats(0.0, 60.0),
)
def test_a_windows_loads_are_the_face_loads_less_the_continued(levers, theta_dot, leak, L_main):
    """The windows' twin of faces' loads less the continued loads (their load, delivered flow
    and friction) is the two kernels' difference."""
    from windpump._kernels import real

    design = SEED.replace(cylinders=len(levers), d_leak=leak * SEED.bore, L_main=L_main)
    machine = kernel_machine(design)
    row = np.zeros(real.ROW + 2)
    row[1 : 1 + len(levers)] = levers
    faces = float(len(levers))
    load, Q, h_f, _ = real._face_loads(theta_dot, row, machine)
    load_c, Q_c, h_f_c, _ = real._continued_loads(theta_dot, row, faces, machine)
    d_load, d_Q, d_friction = real._window_loads(theta_dot, row, faces, machine)
    scale = design.load_torque * max(sum(levers), 1.0)  # a load, a flow and their friction's
    flow = design.A * design.R * max(sum(levers), 1.0) * theta_dot + faces * machine.real.q_L
    assert d_load == pytest.approx(load - load_c, rel=1e-12, abs=1e-12 * scale)
    assert d_Q == pytest.approx(Q_c - Q, rel=1e-12, abs=1e-15 * flow)
    friction = machine.real.friction * flow**3
    assert d_friction == pytest.approx(h_f * Q - h_f_c * Q_c, rel=1e-12, abs=1e-12 * friction)


LEAKY_RUNS = {  # (design, samples per stroke, rtol): windows jumped, and where they are not
    "seed, 1 mm": (SEED.replace(d_leak=0.001), 16, 1e-6),
    "seed, 1.5 mm": (SEED.replace(d_leak=0.0015), 16, 1e-6),
    "seed, 3 mm (wide windows: kinks)": (SEED.replace(d_leak=0.003), 16, 3e-6),
    "seed, 1.5 mm, 400 samples a stroke (in the windows)": (SEED.replace(d_leak=0.0015), 400, 1e-6),
    "seed, 1.5 mm, a weak wind (slow)": (SEED.replace(d_leak=0.0015, T_m=0.35), 16, 3e-6),
    "every effect, 1.5 mm": (
        SEED.replace(m_r=1.0, eta_t=0.9, L_main=10.0, D_main=0.025, d_leak=0.0015),
        16,
        1e-6,
    ),
    "two double-acting": (DESIGNS["two double-acting"], 16, 1e-6),
}


@pytest.mark.parametrize("name", LEAKY_RUNS)
def test_a_leaky_run_at_speed_follows_the_reference(name):
    # From the kick to 4.7-7.5 rad/s (the seed's): segments past ~3.3 rad/s jump their windows
    # unless these are wide (3 mm) or hold a grid angle (400 samples a stroke); a weak wind keeps
    # the crank slow. Each run ends inside a segment (in time, on the kinks). At 60 and 120 s.
    design, per_stroke, rtol = LEAKY_RUNS[name]
    for t_end in (60.0, 120.0):
        run = windpump.simulate(design, t_end, samples_per_stroke=per_stroke)
        ref = real_reference_run(design, t_end, math.pi / 2, 3.0)
        assert run.theta_dot[-1] == pytest.approx(ref.theta_dot, rel=rtol)
        assert run.volume[-1] == pytest.approx(ref.volume, rel=rtol)
        assert run.theta[-1] == pytest.approx(ref.theta, rel=rtol)
        assert windpump.power_budget(run).imbalance < 1e-9


@settings(max_examples=100, deadline=None)
@given(phi=st.floats(-20.0, 20.0), ratio=st.floats(1.05, 30.0))
def test_the_arm_squareds_closed_form_integral_is_a_quadrature(phi, ratio):
    """int_0^phi (lever arm)^2 (the masses' frozen ripple in the time) against scipy's quad."""
    from scipy.integrate import quad

    from windpump.model.equations import lever_arm, lever_arm_squared_integral

    # on quarter turns (near L/R = 1 the arm peaks sharply at pi/2 + k pi)
    edges = np.append(np.arange(0.0, abs(phi), 0.5 * math.pi), abs(phi)) * math.copysign(1, phi)
    expected = sum(
        quad(lambda p: lever_arm(p, ratio) ** 2, a, b, epsabs=1e-15, epsrel=1e-14, limit=400)[0]
        for a, b in zip(edges[:-1], edges[1:], strict=True)
    )
    scale = max(1.0, abs(phi)) * ratio * ratio  # its terms' size: they cancel to ~1e-16 of it
    assert float(lever_arm_squared_integral(phi, ratio)) == pytest.approx(
        expected, rel=1e-12, abs=1e-14 * scale
    )


HEAVY_RUNS = {  # the time's ripple taken out of its steps (docs/model.rst, "The real machine")
    "seed, m_r = 1 kg": SEED.replace(m_r=1.0),
    "two cylinders, m_r = 3 kg": SEED.replace(m_r=3.0, cylinders=2),
    "eta_t = 0.9": SEED.replace(eta_t=0.9),
    "a main": SEED.replace(L_main=10.0, D_main=0.025),
}


@pytest.mark.parametrize("name", HEAVY_RUNS)
def test_a_real_run_with_its_times_ripple_frozen_follows_the_reference(name):
    design = HEAVY_RUNS[name]
    for t_end in (60.0, 120.0):
        run = windpump.simulate(design, t_end)
        ref = real_reference_run(design, t_end, math.pi / 2, 3.0)
        assert run.theta_dot[-1] == pytest.approx(ref.theta_dot, rel=1e-6)
        assert run.volume[-1] == pytest.approx(ref.volume, rel=1e-6)
        assert run.theta[-1] == pytest.approx(ref.theta, rel=1e-6)
        assert windpump.power_budget(run).imbalance < 1e-9
