"""Property-based tests: random valid designs keep the invariants; random bad input gets a clear error."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import windpump
from windpump import Design, ParameterError
from windpump.run.dynamics import SMALLEST_KICK


def between(low, high):
    return st.floats(low, high, allow_nan=False, allow_infinity=False)


@st.composite
def designs(draw):
    """Physically plausible wind pumps, from light and fast to heavy and overloaded."""
    R0, R = draw(between(0.01, 0.1)), draw(between(0.01, 0.2))
    bore = draw(between(0.01, 0.15))
    return Design(
        R0=R0,
        R1=R0 * draw(between(1.0, 8.0)),
        R=R,
        L=R * draw(between(1.05, 20.0)),
        A=math.pi / 4 * bore**2,
        I0=draw(between(0.05, 20.0)),
        I1=draw(between(0.001, 2.0)),
        T_m=draw(between(0.05, 20.0)),
        omega_m=draw(between(5.0, 100.0)),
        h=draw(st.one_of(st.just(0.0), between(0.0, 30.0))),
    )


@st.composite
def runs(draw):
    design = draw(designs())
    top = 2 * design.omega_m / design.R_dagger
    return windpump.simulate(
        design,
        t_end=draw(between(0.1, 60.0)),
        theta0=draw(between(-10.0, 10.0)),
        theta_dot0=draw(st.one_of(st.just(0.0), between(SMALLEST_KICK, 1.5 * top))),
    )


@settings(deadline=None)
@given(runs())
def test_invariants_of_a_run(run):
    assert np.all(np.diff(run.t) > 0)
    assert np.all(np.diff(run.volume) >= 0), "volume never decreases"
    assert np.all(run.flow >= 0), "flow is never negative"
    intake = np.mod(run.theta, 2 * math.pi) <= math.pi
    assert np.all(run.flow[intake] == 0), "no flow while the cylinder takes water in"
    speeds = run.theta_dot[:-1] if run.stalled else run.theta_dot
    assert np.all(speeds > 0), "the crank turns forward until it stalls"
    if run.stalled:
        assert run.theta_dot[-1] == 0 and run.t_stall == run.t[-1]
    else:
        assert run.t_stall is None


@settings(deadline=None)
@given(runs())
def test_energy_closes(run):
    d = run.design
    kinetic = 0.5 * d.I_eff * (run.theta_dot**2 - run.theta_dot[0] ** 2)
    lift = d.rho_w * d.g * d.h * run.volume
    # Relative to the energies involved, with a floor: the load's work over a few round-offs of
    # theta (the volume is a function of theta, which cannot resolve a crank that stalls within a
    # few hundred ulps of where it started). The lever arm is at most 2.
    ulp = np.finfo(float).eps * (np.max(np.abs(run.theta)) + 1)
    resolution = d.load_torque * 2 * 8 * ulp + np.finfo(float).tiny  # and energies below floats
    energies = np.max(np.abs(run.shaft_work)) + 0.5 * d.I_eff * run.theta_dot[0] ** 2
    assert np.max(np.abs(run.shaft_work - kinetic - lift)) <= 1e-6 * energies + resolution


@settings(deadline=None)
@given(designs(), between(0.0, 1e3))
def test_averaged_theory_is_consistent(design, t):
    margin = windpump.stall_margin(design)
    assume(margin > 1.0 + 1e-6)
    alpha_plus, alpha_minus = windpump.steady_speeds(design)
    assert 0 <= alpha_minus < alpha_plus <= 2 * design.omega_m / design.R_dagger * (1 + 1e-12)
    assert windpump.time_constant(design) > 0
    between_roots = 0.5 * (alpha_plus + alpha_minus)
    speed = float(windpump.spinup(design, [t], between_roots)[0])
    assert between_roots * (1 - 1e-9) <= speed <= alpha_plus * (1 + 1e-9)
    op = windpump.operating_point(design)
    assert op.omega == pytest.approx(design.R_dagger * alpha_plus, rel=1e-9)


FIELDS = ["R0", "R1", "R", "L", "A", "I0", "I1", "T_m", "omega_m", "rho_w", "g"]
BAD_NUMBERS = st.one_of(
    st.floats(max_value=0.0, allow_nan=False), st.just(math.nan), st.just(math.inf)
)


@given(st.sampled_from(FIELDS), BAD_NUMBERS)
def test_bad_design_values_name_the_parameter(field, value):
    with pytest.raises(ParameterError) as error:
        Design.seed_example().replace(**{field: value})
    assert str(error.value).startswith(f"{field} = ")
    assert "must be" in str(error.value)


@given(
    st.one_of(st.floats(max_value=0.0), st.just(math.inf), st.floats(min_value=1e5)),
    st.one_of(st.just(math.nan), st.just(math.inf), st.floats(max_value=-1e-300)),
)
def test_bad_run_arguments_name_the_parameter(t_end, theta_dot0):
    with pytest.raises(ParameterError, match="^t_end = "):
        windpump.simulate(Design.seed_example(), t_end)
    with pytest.raises(ParameterError, match="^theta_dot0 = "):
        windpump.simulate(Design.seed_example(), 10.0, theta_dot0=theta_dot0)
