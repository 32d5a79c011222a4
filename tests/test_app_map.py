"""The Design map tab in-process: its sources against windpump, the marker, a tap, cached maps."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest
from bokeh.events import Tap

import windpump

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "app"))
from explorer import Explorer  # noqa: E402
from map_tab import GRID, PER_DAY, colour_range, contour_levels  # noqa: E402

SEED = windpump.Design.seed_example()


@pytest.fixture
def app():
    explorer = Explorer()
    explorer.main().active = 3  # open the Design map tab
    return explorer


def test_the_map_is_the_cores_over_the_sliders_ranges(app):
    app.set_values(cylinders=2, T_0=0.2, V=6.0)
    design = app.inputs.design()
    ratios, heads = np.linspace(0.5, 10.0, GRID), np.linspace(0.0, 30.0, GRID)
    expected = windpump.design_map(design, ratios, heads)
    tab = app.design_map
    image = tab.sources["flow"].data["image"][0]
    np.testing.assert_array_equal(np.isnan(image), np.isnan(expected.mean_flow))
    np.testing.assert_allclose(image, expected.mean_flow * PER_DAY, rtol=1e-12)
    np.testing.assert_allclose(tab.sources["best"].data["ratio"], expected.best_gear_ratio)
    np.testing.assert_allclose(tab.sources["stall"].data["ratio"], expected.stall_gear_ratio)
    assert image.shape == (GRID, GRID)  # no more cells than the figure has pixels


def test_the_marker_and_readout_follow_the_sliders_without_remapping(app):
    tab = app.design_map
    first = tab.mapped
    app.set_values(R_dagger=6.0, h=5.0)
    assert tab.mapped is first  # R1/R0 and h only move the marker
    here = tab.sources["here"].data
    design = SEED.with_ratios(R_dagger=6.0, h=5.0)
    assert (here["ratio"], here["h"]) == ([6.0], [5.0])
    alpha_plus, _ = windpump.steady_speeds(design)
    flow = design.volume_per_revolution * alpha_plus / (2 * math.pi) * PER_DAY
    assert here["flow"][0] == pytest.approx(flow, rel=1e-12)
    best = windpump.design_map(design, np.linspace(0.5, 10.0, GRID), [5.0])
    assert f"R₁/R₀ = {best.best_gear_ratio[0]:.2f}" in tab.readout.object
    assert f"{flow:.1f} m³/day" in tab.readout.object
    app.set_values(T_m=0.9)
    assert tab.mapped is not first  # the windmill changed: a new map


def test_a_tap_moves_the_design_onto_the_sliders_steps(app):
    figure = app.design_map.figure
    figure._trigger_event(Tap(figure, x=2.345, y=7.77))
    assert (app.inputs.R_dagger, app.inputs.h) == (2.3, 7.8)
    assert app.seen.run.design.R_dagger == pytest.approx(2.3)  # the run followed
    figure._trigger_event(Tap(figure, x=50.0, y=-3.0))  # off the map: clipped to the ranges
    assert (app.inputs.R_dagger, app.inputs.h) == (10.0, 0.0)


def test_a_head_nothing_can_lift_says_so(app):
    app.set_values(h=30.0, T_m=0.05)
    assert "no sprocket ratio on this map carries the load" in app.design_map.readout.object


def test_contour_levels_are_round_and_within_the_colour_range():
    flow = np.array([[np.nan, 3.0], [47.0, 120.0]])
    assert colour_range(flow) == (3.0, 120.0)
    assert list(contour_levels(flow)) == [5.0, 10.0, 20.0, 50.0, 100.0]
    assert colour_range(np.array([[0.01, 104.0]])) == (1.04, 104.0)  # two decades at most
    assert len(contour_levels(np.full((2, 2), np.nan))) == 0
