"""The design map against the scalar averaged theory, a scalar optimiser and full simulations."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.optimize import minimize_scalar

import windpump
from windpump import Design, ParameterError, design_map

SEED = Design.seed_example()
DESIGNS = {
    "seed": SEED,
    "three double-acting cylinders": SEED.replace(cylinders=3, double_acting=True),
    "torque at rest": SEED.replace(T_0=0.3),
    "two cylinders, T_0, strong wind": SEED.replace(cylinders=2, T_0=0.2).in_wind(8.0),
}
RATIOS = np.linspace(0.3, 12.0, 37)
HEADS = np.array([0.0, 0.5, 2.0, 3.0, 7.5, 20.0])


def averaged_flow(design: Design) -> float:
    """Mean flow by Eq. (21) through the scalar API [m^3/s]; 0 where it cannot run."""
    if windpump.stall_margin(design) <= 1.0:
        return 0.0
    return design.volume_per_revolution * windpump.steady_speeds(design)[0] / (2 * math.pi)


@pytest.mark.parametrize("name", DESIGNS)
def test_every_point_matches_the_scalar_averaged_theory(name):
    design = DESIGNS[name]
    result = design_map(design, RATIOS, HEADS)
    assert result.margin.shape == (len(HEADS), len(RATIOS))
    for row, h in enumerate(HEADS):
        for column, ratio in enumerate(RATIOS):
            point = design.replace(R1=design.R0 * ratio, h=h)
            assert point == result.design_at(row, column)
            margin = windpump.stall_margin(point)
            assert result.margin[row, column] == pytest.approx(margin, rel=1e-12)
            if margin <= 1.0:
                assert np.isnan(result.alpha_plus[row, column])
                assert np.isnan(result.tau[row, column])
                assert np.isnan(result.mean_flow[row, column])
                continue
            alpha_plus, _ = windpump.steady_speeds(point)
            assert result.alpha_plus[row, column] == pytest.approx(alpha_plus, rel=1e-12)
            tau = windpump.time_constant(point)
            assert result.tau[row, column] == pytest.approx(tau, rel=1e-12)
            assert result.mean_flow[row, column] == pytest.approx(averaged_flow(point), rel=1e-12)


@pytest.mark.parametrize("name", DESIGNS)
def test_the_best_gear_ratio_is_a_scalar_optimisers_to_1e_6(name):
    design = DESIGNS[name]
    heads = HEADS[HEADS > 0]
    result = design_map(design, RATIOS, heads)
    for row, h in enumerate(heads):

        def flow(ratio, h=h):
            return -averaged_flow(design.replace(R1=design.R0 * ratio, h=h))

        found = minimize_scalar(
            flow, bounds=(RATIOS[0], RATIOS[-1]), method="bounded", options={"xatol": 1e-12}
        )
        if found.fun == 0.0:  # nothing in the range runs
            assert np.isnan(result.best_gear_ratio[row])
            continue
        assert result.best_gear_ratio[row] == pytest.approx(found.x, rel=1e-6)
        assert result.best_flow[row] == pytest.approx(-found.fun, rel=1e-6)
        assert result.best_flow[row] >= -found.fun * (1 - 1e-12)  # no worse than the optimiser
        # and nothing on the grid does better
        assert np.nanmax(result.mean_flow[row]) <= result.best_flow[row] * (1 + 1e-12)


def test_without_torque_at_rest_the_best_gear_puts_the_margin_at_nine_eighths():
    result = design_map(SEED, np.geomspace(0.01, 100, 5), [1.0, 3.0, 30.0])
    for ratio, h in zip(result.best_gear_ratio, result.heads, strict=True):
        margin = windpump.stall_margin(SEED.replace(R1=SEED.R0 * ratio, h=h))
        assert margin == pytest.approx(9 / 8, rel=1e-12)


def test_the_best_gear_stays_in_the_range_and_is_nan_where_nothing_runs():
    # The unconstrained best at h = 3 is R+ = 0.883 and the stall boundary 0.785.
    above = design_map(SEED, [2.0, 3.0, 4.0], [3.0])
    assert above.best_gear_ratio[0] == 2.0
    below = design_map(SEED, [0.5, 0.6, 0.7], [3.0])
    assert np.isnan(below.best_gear_ratio[0]) and np.isnan(below.best_flow[0])
    assert np.all(np.isnan(below.mean_flow))
    no_load = design_map(SEED, [1.0, 2.0], [0.0])  # no head: the smallest ratio spins fastest
    assert no_load.best_gear_ratio[0] == 1.0 and np.isinf(no_load.margin).all()


def test_the_stall_boundary_is_where_the_margin_is_one():
    result = design_map(SEED, RATIOS, HEADS)
    for ratio, h in zip(result.stall_gear_ratio, HEADS, strict=True):
        if h > 0:
            point = SEED.replace(R1=SEED.R0 * ratio, h=h)
            assert windpump.stall_margin(point) == pytest.approx(1.0, rel=1e-12)


def test_a_tight_pumps_speed_jumps_up_at_its_stall_boundary():
    result = design_map(SEED, RATIOS, HEADS)
    np.testing.assert_array_equal(result.jump_gear_ratio, result.stall_gear_ratio)


@pytest.mark.parametrize("d_leak, T_0", [(0.004, 0.0), (0.003, 0.25)])
def test_a_leaky_pumps_speed_jumps_up_at_its_jump_ratio_and_only_there(d_leak, T_0):
    """A leak hole never stalls; at the jump ratio its steady speed (steady_speeds, the scalar
    averaged theory) goes from a slow one lifting little or nothing to a delivering one many
    times faster, within 1/1024 of the grid's step, and rises smoothly either side of it."""
    leaky = SEED.replace(d_leak=d_leak, T_0=T_0)
    ratios, heads = np.linspace(0.5, 10.0, 31), np.array([2.0, 9.0, 15.5, 22.0, 27.0])
    result = design_map(leaky, ratios, heads)
    assert np.all(result.stall_gear_ratio == 0.0)
    step = ratios[1] - ratios[0]
    for edge, h in zip(result.jump_gear_ratio, heads, strict=True):
        assert ratios[0] < edge < ratios[-1]
        at = [edge - 0.5 * step, edge - step / 1024, edge, edge + 0.5 * step]
        speeds = [windpump.steady_speeds(leaky.replace(R1=leaky.R0 * r, h=h))[0] for r in at]
        flows = [windpump.steady_flow(leaky.replace(R1=leaky.R0 * r, h=h), SEED.V_ref) for r in at]
        # over 1/1024 of a step, more than over half a step either side: a jump
        jump, before, after = speeds[2] - speeds[1], speeds[1] - speeds[0], speeds[3] - speeds[2]
        assert jump > max(abs(before), abs(after)) and speeds[2] > 1.5 * speeds[1]
        assert flows[2] > 10 * flows[1] and flows[2] > 0.0


def test_a_leaky_maps_jump_ratio_is_nan_where_the_grid_holds_no_jump():
    leaky = SEED.replace(d_leak=0.004)
    result = design_map(leaky, [0.5, 0.6, 0.7], [1.0, 30.0])
    assert np.isnan(result.jump_gear_ratio).all()  # running at 1 m; slow (lifting none) at 30


def test_a_map_writes_csv_with_units():
    result = design_map(SEED, [2.0, 4.0], [3.0, 50.0])
    lines = result.to_csv().splitlines()
    assert len(lines) == 1 + 4
    h, ratio, margin, alpha_plus, tau, flow = (float(x) for x in lines[2].split(","))
    assert (h, ratio) == (3.0, 4.0)
    assert alpha_plus == pytest.approx(windpump.steady_speeds(SEED)[0], rel=1e-11)
    assert lines[-1].split(",")[3] == "nan"  # 50 m: stalled


# The numeric map: full simulations from theta = 0 at alpha+.


def simulated_speed(design: Design, kick: float, revolutions: int) -> float:
    """Cycle-mean crank speed over the last 10 of ``revolutions`` revolutions of a long run."""
    run = windpump.simulate(design, revolutions * 2 * math.pi / kick, 0.0, kick)
    if run.stalled:
        return math.nan
    return run.intermittency(10).mean_speed


def test_the_numeric_map_agrees_with_long_runs_of_simulate_at_sample_points():
    ratios, heads = np.array([1.0, 2.5, 4.0, 8.0]), np.array([1.0, 3.0, 9.0])
    result = design_map(SEED, ratios, heads, numeric=True, progress=False)
    averaged = design_map(SEED, ratios, heads)
    assert np.array_equal(np.isnan(result.alpha_plus), np.isnan(averaged.alpha_plus))
    for row, column in [(0, 0), (1, 3), (2, 2), (1, 1)]:
        kick = averaged.alpha_plus[row, column]
        tau = averaged.tau[row, column]
        long_run = int(16 * tau * kick / (2 * math.pi))  # 16 tau: settled far past the map's 8
        speed = simulated_speed(result.design_at(row, column), kick, long_run)
        assert result.alpha_plus[row, column] == pytest.approx(speed, rel=2e-6)
        flow = result.design.volume_per_revolution * speed / (2 * math.pi)
        assert result.mean_flow[row, column] == pytest.approx(flow, rel=2e-6)
        # a heavy rotor ripples little: the averaged theory is close
        assert result.alpha_plus[row, column] == pytest.approx(kick, rel=1e-3)


@pytest.mark.parametrize(
    "name", ["three double-acting cylinders", "two cylinders, T_0, strong wind"]
)
def test_the_numeric_map_of_several_cylinders_and_torque_at_rest_matches_simulate(name):
    design = DESIGNS[name]
    ratios, heads = np.array([2.0, 6.0]), np.array([0.5, 2.0])
    result = design_map(design, ratios, heads, numeric=True, progress=False)
    averaged = design_map(design, ratios, heads)
    running = np.argwhere(~np.isnan(averaged.alpha_plus))
    assert len(running) >= 3
    for row, column in running:
        kick, tau = averaged.alpha_plus[row, column], averaged.tau[row, column]
        long_run = max(200, int(16 * tau * kick / (2 * math.pi)))
        speed = simulated_speed(result.design_at(row, column), kick, long_run)
        assert result.alpha_plus[row, column] == pytest.approx(speed, rel=2e-6)


def test_a_light_rotor_stalls_in_full_where_the_averaged_theory_runs():
    light = SEED.replace(I0=SEED.I0 / 1000, I1=SEED.I1 / 1000)
    ratios, heads = np.linspace(0.5, 8, 16), np.linspace(0.5, 10, 12)
    calls = []
    result = design_map(light, ratios, heads, numeric=True, progress=lambda *a: calls.append(a))
    averaged = design_map(light, ratios, heads)
    parted = np.isnan(result.alpha_plus) & ~np.isnan(averaged.alpha_plus)
    assert parted.any()  # the ripple's share
    assert not (~np.isnan(result.alpha_plus) & np.isnan(averaged.alpha_plus)).any()
    row, column = np.argwhere(parted)[0]
    kick = averaged.alpha_plus[row, column]
    assert math.isnan(simulated_speed(result.design_at(row, column), kick, 3000))
    assert calls[-1] == (ratios.size * heads.size, ratios.size * heads.size)
    # the best gear, refined between grid points, lies within a grid step of the grid's best
    best = np.nanargmax(result.mean_flow, axis=1)
    step = ratios[1] - ratios[0]
    assert np.all(np.abs(result.best_gear_ratio - ratios[best]) <= step)
    assert np.all(result.best_flow >= np.nanmax(result.mean_flow, axis=1) * (1 - 1e-12))


# Bad input


@pytest.mark.parametrize(
    "ratios, heads, name",
    [
        ([], [1.0], "gear_ratios"),
        ([0.0, 1.0], [1.0], "gear_ratios"),
        ([1.0, float("nan")], [1.0], "gear_ratios"),
        ([2.0, 1.0], [1.0], "gear_ratios"),
        ([[1.0, 2.0]], [1.0], "gear_ratios"),
        (["a"], [1.0], "gear_ratios"),
        ([1.0], [-1.0], "heads"),
        ([1.0], [1.0, 1.0], "heads"),
        ([1.0], [float("inf")], "heads"),
        ([1e-99], [1.0], "gear_ratios"),  # R1 = R0 x 1e-99 is below the smallest length
    ],
)
def test_bad_grids_are_refused_by_name(ratios, heads, name):
    with pytest.raises(ParameterError) as caught:
        design_map(SEED, ratios, heads)
    assert caught.value.name == name


@given(
    st.lists(st.floats(allow_nan=True, allow_infinity=True), min_size=1, max_size=6),
    st.lists(st.floats(allow_nan=True, allow_infinity=True), min_size=1, max_size=6),
)
def test_any_grid_maps_or_is_refused_with_a_parameter_error(ratios, heads):
    try:
        result = design_map(SEED, ratios, heads)
    except ParameterError as error:
        assert error.name in ("gear_ratios", "heads")
        return
    assert result.margin.shape == (len(heads), len(ratios))
    runs = result.margin > 1.0
    assert np.all(np.isnan(result.mean_flow[~runs]))
    assert np.all(result.mean_flow[runs] > 0.0)
