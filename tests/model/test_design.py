"""Design: the paper's example, the groups of Eqs. (14-15), and bad input."""

from __future__ import annotations

import dataclasses
import math

import pytest

import windpump
from windpump import Design, ParameterError

SEED = Design.seed_example()


def test_seed_example_reads_the_papers_call():
    """docs/model.rst: inpI = [.03; .12; .04; .15; pi/4 .04^2; I0; I1; 50; .6; 1000 9.81], h = 3 m."""
    assert (SEED.R0, SEED.R1, SEED.R, SEED.L) == (0.03, 0.12, 0.04, 0.15)
    assert SEED.A == pytest.approx(math.pi / 4 * 0.04**2)
    assert SEED.I0 == pytest.approx(
        8000 * math.pi / 2 * 0.04**4 * 0.01 + 2000 * 0.1 * 0.02 * 0.75**3
    )
    assert SEED.I1 == pytest.approx(8000 * math.pi / 2 * 0.15**4 * 0.01)
    assert (SEED.omega_m, SEED.T_m, SEED.h) == (50.0, 0.6, 3.0)
    assert SEED.rho_w * SEED.g == pytest.approx(9810.0)


def test_groups_follow_eqs_14_and_15():
    I_eff = SEED.I1 + SEED.I0 * (SEED.R1 / SEED.R0) ** 2
    assert SEED.R_dagger == 4.0
    assert SEED.I_eff == pytest.approx(I_eff)
    assert SEED.Tm_dagger == pytest.approx(16 * 0.6 / (50**2 * I_eff))
    assert SEED.L_dagger == pytest.approx(9810 * 3 * SEED.A * 0.04 / (50**2 * I_eff))


def test_design_is_frozen_and_replace_validates():
    with pytest.raises(dataclasses.FrozenInstanceError):
        SEED.h = 4.0
    assert SEED.replace(h=5).h == 5.0 and SEED.h == 3.0
    with pytest.raises(ParameterError, match="h = -1"):
        SEED.replace(h=-1)
    with pytest.raises(TypeError, match="head"):
        SEED.replace(head=2)


POSITIVE = ["R0", "R1", "R", "L", "A", "I0", "I1", "T_m", "omega_m", "rho_w", "g"]


@pytest.mark.parametrize("field", POSITIVE)
@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf, -math.inf])
def test_positive_fields_reject_bad_values(field, bad):
    with pytest.raises(ParameterError) as error:
        SEED.replace(**{field: bad})
    message = str(error.value)
    assert message.startswith(f"{field} = {bad!r}")
    assert "> 0" in message or "finite" in message
    assert error.value.name == field and isinstance(error.value, ValueError)


@pytest.mark.parametrize("bad", [-0.1, math.nan, math.inf])
def test_head_rejects_bad_values_but_allows_zero(bad):
    assert SEED.replace(h=0).h == 0.0
    with pytest.raises(ParameterError, match=r"^h = .*must be"):
        SEED.replace(h=bad)


@pytest.mark.parametrize("bad", ["3", None, True, [1.0]])
def test_non_numbers_are_rejected(bad):
    with pytest.raises(ParameterError, match="finite real number"):
        SEED.replace(T_m=bad)


@pytest.mark.parametrize("L", [0.04, 0.03])
def test_rod_must_be_longer_than_the_crank(L):
    with pytest.raises(ParameterError, match=r"L = .* must be > R = 0\.04 m .*cannot reach"):
        SEED.replace(L=L)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"t_end": 0.0}, "t_end"),
        ({"t_end": -5.0}, "t_end"),
        ({"t_end": math.nan}, "t_end"),
        ({"t_end": math.inf}, "t_end"),
        ({"t_end": 1e9}, "t_end"),
        ({"t_end": 10.0, "theta0": math.nan}, "theta0"),
        ({"t_end": 10.0, "theta0": math.inf}, "theta0"),
        ({"t_end": 10.0, "theta_dot0": -1.0}, "theta_dot0"),
        ({"t_end": 10.0, "theta_dot0": math.nan}, "theta_dot0"),
        ({"t_end": 10.0, "theta_dot0": math.inf}, "theta_dot0"),
    ],
)
def test_simulate_rejects_bad_arguments(kwargs, name):
    with pytest.raises(ParameterError) as error:
        windpump.simulate(SEED, **kwargs)
    assert error.value.name == name
    assert str(error.value).startswith(f"{name} = ")


def test_the_sample_bound_names_the_longest_allowed_run():
    with pytest.raises(ParameterError, match=r"t_end = 1000000000.0 s .* <= [0-9.e+]+ s") as error:
        windpump.simulate(SEED, 1e9)
    longest = float(str(error.value).split("<= ")[1].split(" s")[0])
    assert windpump.simulate(SEED, longest * 0.999, theta_dot0=3.0).t[-1] > 0


def test_simulate_wants_a_design():
    with pytest.raises(TypeError, match="Design"):
        windpump.simulate({"h": 3.0}, 10.0)


@pytest.mark.parametrize("bad", [-1.0, math.nan])
def test_spinup_rejects_bad_input(bad):
    with pytest.raises(ParameterError, match="theta_dot0"):
        windpump.spinup(SEED, [0.0, 1.0], bad)
    with pytest.raises(ValueError, match="t must"):
        windpump.spinup(SEED, [0.0, bad], 3.0)


@pytest.mark.parametrize(
    "call",
    [
        lambda: windpump.windmill_torque(SEED, [10.0, math.nan]),
        lambda: windpump.windmill_power(SEED, -1.0),
        lambda: windpump.load_power(SEED, math.inf),
        lambda: windpump.lever_arm([0.0, math.inf], 3.75),
        lambda: windpump.f2(math.nan, 3.75),
        lambda: windpump.piston_position("far", SEED.R, SEED.L),
    ],
)
def test_curves_and_kinematics_reject_bad_arrays(call):
    with pytest.raises(ParameterError, match=r"^(omega|theta) = "):
        call()
