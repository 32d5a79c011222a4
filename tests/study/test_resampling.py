"""The design map on a fine grid for drawing (windpump.study.resampling, issue 38): against the
map itself, computed in the test."""

from __future__ import annotations

import numpy as np
import pytest

import windpump
from windpump.study.resampling import fine_map

SEED = windpump.Design.seed_example()
LEAKY = SEED.replace(d_leak=0.003, T_0=0.25)


def test_a_tight_pump_s_fine_map_is_the_map_itself():
    ratios, heads = np.linspace(1.0, 6.0, 23), np.linspace(1.0, 20.0, 17)
    mapped = windpump.design_map(SEED, ratios, heads)
    drawn = fine_map(SEED, ratios, heads)
    np.testing.assert_array_equal(drawn.mean_flow, mapped.mean_flow)
    np.testing.assert_array_equal(drawn.edge_gear_ratio, mapped.stall_gear_ratio)
    np.testing.assert_array_equal(drawn.best_gear_ratio, mapped.best_gear_ratio)


def test_on_its_own_coarse_points_a_leaky_map_is_the_coarse_map_and_its_jump():
    """Resampled onto the coarse grid itself, each side keeps its own values and the edge is the
    jump wherever a head has one: nothing is smeared across the jump."""
    ratios, heads = np.linspace(1.0, 6.0, 15), np.linspace(1.0, 20.0, 15)
    mapped = windpump.design_map(LEAKY, ratios, heads)
    drawn = fine_map(LEAKY, ratios, heads, coarse=15)
    known = np.isfinite(mapped.jump_gear_ratio)
    assert known.sum() >= 3
    np.testing.assert_allclose(drawn.mean_flow, np.nan_to_num(mapped.mean_flow), rtol=0, atol=1e-15)
    np.testing.assert_allclose(drawn.edge_gear_ratio[known], mapped.jump_gear_ratio[known])


def test_between_coarse_points_each_side_is_interpolated_from_its_own_side():
    """A fine point left of the edge lies between its coarse neighbours' values on that side (no
    value borrowed from across the jump, where the flow leaps)."""
    coarse = 11
    ratios, heads = np.linspace(1.0, 6.0, 61), np.linspace(1.0, 20.0, 31)
    drawn = fine_map(LEAKY, ratios, heads, coarse=coarse)
    coarse_map = windpump.design_map(
        LEAKY, np.linspace(1.0, 6.0, coarse), np.linspace(1.0, 20.0, coarse)
    )
    flow = np.nan_to_num(coarse_map.mean_flow)
    assert np.all(drawn.mean_flow >= flow.min() - 1e-15)
    assert np.all(drawn.mean_flow <= flow.max() + 1e-15)
    left = ratios[np.newaxis, :] < drawn.edge_gear_ratio[:, np.newaxis]
    assert left.any() and (~left).any()


def test_bad_grids_are_refused_by_name():
    with pytest.raises(windpump.ParameterError, match="gear_ratios"):
        fine_map(SEED, "1,2,3", [1.0, 2.0])
