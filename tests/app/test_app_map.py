"""The Design map tab in-process: its sources against windpump, the marker, a tap, cached maps."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from bokeh.events import Tap
from bokeh.models import ColorBar

import windpump
from windpump.units import SECONDS_PER_DAY
from windpump_app.explorer import Explorer
from windpump_app.map_tab import GRID, colour_range, contour_levels
from windpump_app.page import CONTROLS_SHARE

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
    np.testing.assert_allclose(image, expected.mean_flow * SECONDS_PER_DAY, rtol=1e-12)
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
    flow = design.volume_per_revolution * alpha_plus / (2 * math.pi) * SECONDS_PER_DAY
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


def test_a_tap_selects_nothing_so_the_labels_and_lines_keep_their_look(app):
    """A tap only moves the design. Bokeh's tap tool also selected what lay under it (a contour
    label, a line), and drew everything else on that renderer at a tenth of its alpha: the other
    labels faded to near invisible. Every renderer the tap tool hit-tests keeps its look."""
    from bokeh.models import GlyphRenderer, TapTool

    figure = app.design_map.figure
    (tap,) = figure.select(type=TapTool)
    hit = tap.renderers
    if hit == "auto":  # Bokeh's default: every renderer of the figure
        hit = [r for r in figure.renderers if isinstance(r, GlyphRenderer)]
    changes_look = [r.glyph.__class__.__name__ for r in hit if r.nonselection_glyph is not None]
    assert changes_look == []


def test_a_head_nothing_can_lift_says_so(app):
    app.set_values(h=30.0, T_m=0.05)
    assert "no sprocket ratio on this map carries the load" in app.design_map.readout.object


def test_contour_levels_are_round_and_within_the_colour_range():
    flow = np.array([[np.nan, 3.0], [47.0, 120.0]])
    assert colour_range(flow) == (3.0, 120.0)
    assert list(contour_levels(flow)) == [5.0, 10.0, 20.0, 50.0, 100.0]
    assert colour_range(np.array([[0.01, 104.0]])) == (1.04, 104.0)  # two decades at most
    assert len(contour_levels(np.full((2, 2), np.nan))) == 0


def test_the_colour_bar_is_labelled_over_its_whole_log_scale(app):
    tab = app.design_map
    bar = tab.figure.select_one(ColorBar)
    low, high = tab.mapper.low, tab.mapper.high
    ticks = np.array(bar.ticker.ticks)
    assert len(ticks) >= 4 and np.all((ticks >= low) & (ticks <= high))
    position = (np.log(ticks) - math.log(low)) / (math.log(high) - math.log(low))
    assert position.min() < 0.25 and position.max() > 0.75  # not bunched at the top
    labels = [bar.formatter.format % tick for tick in ticks]  # the page's printf formatting
    mantissas = {float(label.replace("0", "").replace(".", "") or 0) for label in labels}
    assert mantissas <= {1.0, 2.0, 5.0}  # round values: 0.5, 1, 2, 5, 10, 20, 50, ...
    assert not any("e" in label or "^" in label for label in labels)


def test_the_contours_are_labelled_with_their_values_on_them(app):
    """Each label sits on its level's line; every line but those crowded into a corner (at
    most one in three, their labels left out rather than covering another) has one."""
    tab = app.design_map
    flow = tab.sources["flow"].data["image"][0]  # checked against the core above
    lines = tab.contours.line_renderer.data_source.data
    drawn = [level for level, xs in zip(lines["levels"], lines["xs"], strict=True)
             if np.isfinite(xs).any()]  # fmt: skip
    assert len(drawn) >= 3
    labels = tab.sources["contour_labels"].data
    assert len(labels["text"]) >= 2 * len(drawn) / 3
    assert labels["level"] == sorted(labels["level"]) and set(labels["level"]) <= set(drawn)
    placed = zip(labels["level"], labels["text"], labels["x"], labels["y"], strict=True)
    for level, text, x, y in placed:
        assert text == f"{level:g} m³/day"
        assert on_a_grid_edge(tab, flow, x, y) == pytest.approx(level, rel=1e-6)  # on its line


@pytest.mark.parametrize("values", [{}, {"T_m": 1.2, "h": 5.0}, {"T_0": 0.3}])
def test_contour_labels_keep_off_the_stall_boundary(app, values):
    """Each label's box (at least 14 % of the map's width, 6 % of its height, as aligned) starts
    right of the stall boundary over its whole height."""
    app.set_values(**values)
    tab = app.design_map
    labels = tab.sources["contour_labels"].data
    stall = np.asarray(tab.sources["stall"].data["ratio"], dtype=float)
    (x0, x1), (y0, y1) = (tab.ratios[0], tab.ratios[-1]), (tab.heads[0], tab.heads[-1])
    shift = {"left": 0.0, "center": 0.5, "right": 1.0}
    rise = {"bottom": 1.0, "middle": 0.5, "top": 0.0}
    for x, y, align, baseline in zip(
        labels["x"], labels["y"], labels["align"], labels["baseline"], strict=True
    ):
        left = x - shift[align] * 0.14 * (x1 - x0)
        top = min(y + rise[baseline] * 0.06 * (y1 - y0), y1)
        heads = np.linspace(max(top - 0.06 * (y1 - y0), y0), top, 50)  # the box's height
        assert left > np.interp(heads, tab.heads, stall).max(), (x, y, align, baseline)


@pytest.mark.parametrize("values", [{}, {"d_leak_mm": 2.0}, {"T_m": 1.2, "h": 5.0}])
def test_contour_labels_do_not_cover_each_other(app, values):
    """No two labels' boxes (14 % of the map's width, 6 % of its height, as aligned) overlap: a
    leaky pump's 5 and 10 m³/day lines run side by side along the edge of what runs, and their
    labels sat on each other there."""
    app.set_values(**values)
    tab = app.design_map
    labels = tab.sources["contour_labels"].data
    (x0, x1), (y0, y1) = (tab.ratios[0], tab.ratios[-1]), (tab.heads[0], tab.heads[-1])
    width, height = 0.14 * (x1 - x0), 0.06 * (y1 - y0)
    shift = {"left": 0.0, "center": 0.5, "right": 1.0}
    rise = {"bottom": 1.0, "middle": 0.5, "top": 0.0}
    boxes = [
        (x - shift[align] * width, y + rise[baseline] * height - height)  # left, bottom
        for x, y, align, baseline in zip(
            labels["x"], labels["y"], labels["align"], labels["baseline"], strict=True
        )
    ]
    assert len(boxes) >= 3
    for i, (left, bottom) in enumerate(boxes):
        for other_left, other_bottom in boxes[i + 1 :]:
            apart = abs(left - other_left) >= width or abs(bottom - other_bottom) >= height
            assert apart, (labels["text"], boxes)


def on_a_grid_edge(tab, flow, x, y) -> float:
    """The map's value at a point of a grid cell's edge (where contour lines cross it), linear
    along that edge."""
    column = np.flatnonzero(np.isclose(tab.ratios, x, rtol=0, atol=1e-12))
    if column.size:
        return float(np.interp(y, tab.heads, flow[:, column[0]]))
    row = np.flatnonzero(np.isclose(tab.heads, y, rtol=0, atol=1e-12))
    assert row.size, (x, y)  # a vertex of a contour line lies on the grid's edges
    return float(np.interp(x, tab.ratios, flow[row[0], :]))


def test_a_leaky_pumps_map_is_its_coarse_map_interpolated(app):
    """A hole's averaged theory is a quadrature a point: the tab maps LEAKY_GRID^2 points and
    interpolates them onto its grid; on the coarse grid's own points it is that map."""
    from windpump_app.map_tab import DELIVERY_LABEL, LEAKY_GRID, STALL_LABEL

    app.set_values(d_leak_mm=3.0, T_0=0.25)
    tab = app.design_map
    flow, stall, best = tab.mapped
    ratios = np.linspace(tab.ratios[0], tab.ratios[-1], LEAKY_GRID)
    heads = np.linspace(tab.heads[0], tab.heads[-1], LEAKY_GRID)
    coarse = windpump.design_map(app.seen.design, ratios, heads)
    coarse_flow = np.nan_to_num(coarse.mean_flow)
    # Both grids share their corners, and the first ratio's column is interpolated in h alone.
    assert coarse_flow[0, 0] > 0 and coarse_flow[-1, -1] > 0
    assert flow[0, 0] == pytest.approx(coarse_flow[0, 0])
    assert flow[-1, -1] == pytest.approx(coarse_flow[-1, -1])
    assert flow[7, 0] == pytest.approx(np.interp(tab.heads[7], heads, coarse_flow[:, 0]))
    # The red line: where its speed jumps up, interpolated between the coarse heads that have
    # a jump, and drawn between two coarse heads at least one of which has one.
    edge = coarse.jump_gear_ratio
    known = np.isfinite(edge)
    assert known.sum() > LEAKY_GRID // 2
    drawn = np.isfinite(stall)
    hs, js, step = heads[known], edge[known], heads[1] - heads[0]  # the line, a row past its ends
    hs = np.concatenate([[hs[0] - step], hs, [hs[-1] + step]])
    js = np.concatenate([[2 * js[0] - js[1]], js, [2 * js[-1] - js[-2]]])
    assert np.allclose(np.diff(heads[known])[[0, -1]], step)  # the ends' rows are neighbours
    expected = np.interp(tab.heads[drawn], hs, js)
    assert stall[drawn] == pytest.approx(expected)
    between = np.searchsorted(heads, tab.heads, side="right").clip(1, LEAKY_GRID - 1)
    assert np.array_equal(drawn, known[between - 1] | known[between])
    assert tab.legend[STALL_LABEL].label.value == DELIVERY_LABEL  # a text, not a column


def test_a_leaky_pumps_map_is_joined_at_its_jump_not_interpolated_across_it(app):
    """Where a leaky pump's speed jumps up its flow jumps from (nearly) nothing: the map is
    interpolated on either side and joined there, not across the jump on the coarse grid (which
    drew a staircase along it: cells left of the line coloured as lifting, right of it dark)."""
    app.set_values(d_leak_mm=3.0, T_0=0.25)
    tab = app.design_map
    flow, boundary, _best = tab.mapped
    left = tab.ratios[np.newaxis, :] < boundary[:, np.newaxis]
    # Two columns either side of the line, at every tenth head it crosses, against the scalar
    # averaged theory there: little or nothing left of it, and right of it what the pump lifts.
    design, checked = app.seen.design, 0
    for row in range(0, len(tab.heads), 10):
        first = int(np.argmax(~left[row]))
        if not np.isfinite(boundary[row]) or not 2 <= first < len(tab.ratios) - 2:
            continue
        lifted = []
        for column in (first - 2, first + 2):
            point = design.replace(R1=design.R0 * tab.ratios[column], h=tab.heads[row])
            lifted.append(float(windpump.steady_flow(point, design.V_ref)))
        assert lifted[0] < 0.05 * lifted[1]  # a jump it is
        assert flow[row, first - 2] == pytest.approx(lifted[0], abs=0.02 * lifted[1]), row
        assert flow[row, first + 2] == pytest.approx(lifted[1], rel=0.1), row
        checked += 1
    assert checked >= 5


def test_served_the_map_and_mark_are_worked_out_off_the_loop_the_newest_winning(monkeypatch):
    """A leaky pump's map is ~1.7 s of quadrature: served, the map and the mark are worked out
    in ``off_the_loop``'s work, the readout says it is coming meanwhile (a later map: the one
    drawn dimmed), and a map that comes back after a newer design's is not drawn over it."""
    from windpump_app import map_tab

    held: list = []
    monkeypatch.setattr(map_tab, "off_the_loop", lambda work, then: held.append((work, then)))
    explorer = Explorer()
    explorer.main().active = 3
    tab = explorer.design_map
    assert len(held) == 1 and tab.mapped is None
    design = explorer.inputs.design()  # the readout, laid out with dashes until its numbers come
    assert tab.readout.object == (
        f"At h = {design.h:.1f} m the best sprocket ratio is **R₁/R₀ = –.––**, lifting "
        f"**––.– m³/day** (averaged theory); this design, R₁/R₀ = {design.R_dagger:.2f}: "
        "––.– m³/day."
    )
    explorer.set_values(T_m=0.9)  # a newer design, asked for before the first map came back
    outcomes = [(work(), then) for work, then in held]
    for outcome, then in reversed(outcomes):  # the newer first, the older late
        then(outcome)
    assert tab.image.glyph.global_alpha == 1.0
    explorer.set_values(h=12.0)  # the same map, another mark: the map drawn stands as it is
    assert tab.image.glyph.global_alpha == 1.0
    explorer.set_values(T_m=0.8)  # another map: the one drawn is dimmed until it comes
    assert tab.image.glyph.global_alpha == map_tab.STALE_ALPHA
    work, then = held[-1]
    then(work())
    assert tab.image.glyph.global_alpha == 1.0
    explorer.set_values(T_m=0.9, h=3.0)  # back to the design checked below
    work, then = held[-1]
    then(work())
    design = explorer.inputs.design()
    assert design.T_m == 0.9
    expected = windpump.design_map(
        design, np.linspace(0.5, 10.0, GRID), np.linspace(0.0, 30.0, GRID)
    )
    image = tab.sources["flow"].data["image"][0]
    np.testing.assert_allclose(image, expected.mean_flow * SECONDS_PER_DAY, rtol=1e-12)
    here = float(windpump.steady_flow(design, design.V_ref)) * SECONDS_PER_DAY
    assert tab.sources["here"].data["flow"] == [pytest.approx(here, rel=1e-12)]


def test_a_map_superseded_before_its_turn_in_the_pool_is_not_worked_out(monkeypatch):
    """A leaky pump's map is ~1.7 s of one of the two threads every page shares: a slider
    dragged asks a map a move, and every one worked out for nobody would hold the pool (and the
    newest map, queued behind them) from every page. Only the newest design's is worked out."""
    from windpump_app import map_tab

    held: list = []
    mapped: list[float] = []  # T_m of every map worked out
    real = map_tab.map_of
    monkeypatch.setattr(map_tab, "off_the_loop", lambda work, then: held.append((work, then)))
    monkeypatch.setattr(
        map_tab, "map_of", lambda key, *grid: (mapped.append(key.T_m), real(key, *grid))[1]
    )
    explorer = Explorer()
    explorer.main().active = 3
    tab = explorer.design_map
    for T_m in (0.7, 0.8, 0.9):  # three moves before the pool takes the first map
        explorer.set_values(T_m=T_m)
    assert len(held) == 4
    for work, then in held:  # the pool's turns, in order
        then(work())
    assert mapped == [0.9]
    design = explorer.inputs.design()
    expected = windpump.design_map(
        design, np.linspace(0.5, 10.0, GRID), np.linspace(0.0, 30.0, GRID)
    )
    image = tab.sources["flow"].data["image"][0]
    np.testing.assert_allclose(image, expected.mean_flow * SECONDS_PER_DAY, rtol=1e-12)
    assert tab.sources["here"].data["h"] == [design.h]
    assert "the best sprocket ratio is" in tab.readout.object


def test_served_a_tap_on_a_leaky_pumps_map_marks_the_design_tapped(monkeypatch):
    """Served, with the real threads (``serving.OFF_THE_LOOP``) and the page's next-tick
    callbacks on an event loop (``LoopDocument``): the map of a leaky pump comes, a tap moves
    the design, and its mark and readout follow, the core's numbers for the design tapped."""
    import asyncio

    from test_app_moves import WAIT, LoopDocument, served, until

    explorer = Explorer()

    async def tapped() -> None:
        served(monkeypatch, LoopDocument)
        explorer.main().active = 3
        tab = explorer.design_map
        explorer.set_values(d_leak_mm=0.5)  # a leak hole: its map is quadrature (~1.7 s)
        await until(
            lambda: tab._mapped_key == explorer.seen.design.replace(R1=SEED.R0, h=0.0),
            "the leaky pump's map",
        )
        tab.figure._trigger_event(Tap(tab.figure, x=6.04, y=12.34))
        await until(lambda: tab.sources["here"].data["h"] == [12.3], "the tapped design's mark")

    asyncio.run(asyncio.wait_for(tapped(), 2 * WAIT))
    design = explorer.inputs.design()
    assert (design.R_dagger, design.h) == (pytest.approx(6.0, rel=1e-12), 12.3)
    here = float(windpump.steady_flow(design, design.V_ref)) * SECONDS_PER_DAY
    assert explorer.design_map.sources["here"].data["flow"] == [pytest.approx(here, rel=1e-12)]
    row = windpump.design_map(design, np.linspace(0.5, 10.0, GRID), [12.3])
    assert f"R₁/R₀ = {row.best_gear_ratio[0]:.2f}" in explorer.design_map.readout.object


@pytest.mark.parametrize("width, height", [(210, 270), (600, 330), (1400, 480)])
def test_once_the_page_says_the_maps_size_every_label_lies_inside_it_clear_of_the_others(
    app, width, height
):
    """A phone's map is a third of a projector's width, and its labels two or three times wider
    a share of it: once the browser reports the frame's pixels (``inner_width``, a read-only
    property it sets), the labels are placed for them: inside the map and apart."""
    from windpump_app.map_tab import LABEL_PX, label_box, overlap

    app.set_values(d_leak_mm=2.0)
    tab = app.design_map
    tab.figure.set_from_json("inner_width", width)  # as the page sends them: one, then the other
    tab.figure.set_from_json("inner_height", height)
    size = (LABEL_PX[0] / width, LABEL_PX[1] / height)
    labels = tab.sources["contour_labels"].data
    assert len(labels["x"]) >= 2
    bounds = (tab.ratios[0], tab.ratios[-1]), (tab.heads[0], tab.heads[-1])
    boxes = label_box(labels["x"], labels["y"], labels["align"], labels["baseline"], *bounds, size)
    assert np.all(boxes[:, 0] >= -1e-9) and np.all(boxes[:, 2] <= 1 + 1e-9)
    assert np.all(boxes[:, 1] >= -1e-9) and np.all(boxes[:, 3] <= 1 + 1e-9)
    for i, box in enumerate(boxes):
        assert not np.delete(overlap(boxes, box), i).any()


@pytest.mark.parametrize("width, height", [(1400, 335), (750, 335), (1400, 700)])
def test_every_label_keeps_a_gap_from_the_maps_edges(app, width, height):
    """At 1280×720 and 1920×1080 the paper's example drew "200 m³/day" on the frame's foot and
    "10 m³/day" against its top (their boxes 0 and 1 px from the edge): a newcomer read them as
    cut. Every label's box (LABEL_PX, as placed and drawn: its anchor on its line, shifted by its
    pixel offsets) keeps at least 4 px from each edge of the frame the page reports."""
    from windpump_app.map_tab import LABEL_PX, label_box

    tab = app.design_map
    tab.figure.set_from_json("inner_width", width)
    tab.figure.set_from_json("inner_height", height)
    labels = tab.sources["contour_labels"].data
    assert len(labels["x"]) >= 4
    bounds = (tab.ratios[0], tab.ratios[-1]), (tab.heads[0], tab.heads[-1])
    size = (LABEL_PX[0] / width, LABEL_PX[1] / height)
    boxes = label_box(labels["x"], labels["y"], labels["align"], labels["baseline"], *bounds, size)
    none = [0.0] * len(labels["x"])  # (a label drawn at its anchor)
    dx = np.asarray(labels.get("x_offset", none), dtype=float)  # [px] right
    dy = -np.asarray(labels.get("y_offset", none), dtype=float)  # [px] up
    assert np.all(np.abs(dx) <= 12) and np.all(np.abs(dy) <= 12)  # still on their lines
    left, bottom = boxes[:, 0] * width + dx, boxes[:, 1] * height + dy
    right, top = (1 - boxes[:, 2]) * width - dx, (1 - boxes[:, 3]) * height - dy
    gaps = np.min([left, bottom, right, top], axis=0)
    assert np.all(gaps >= 4.0), dict(zip(labels["text"], np.round(gaps, 1), strict=True))
    drawn = np.column_stack([left, bottom, width - right, height - top])  # [px], as drawn
    for i, box in enumerate(drawn):
        others = np.delete(drawn, i, axis=0)
        apart = (
            (others[:, 2] <= box[0]) | (others[:, 0] >= box[2])
            | (others[:, 3] <= box[1]) | (others[:, 1] >= box[3])
        )  # fmt: skip
        assert apart.all(), (labels["text"][i], drawn)


def test_no_label_lies_under_this_designs_star_wherever_it_moves(app):
    """The star marks the design on the map; a label under it could not be read (a phone
    showed "100 m³/d★"): the labels are placed again clear of it each time it moves."""
    from windpump_app.map_tab import label_box, overlap

    tab = app.design_map
    bounds = (tab.ratios[0], tab.ratios[-1]), (tab.heads[0], tab.heads[-1])
    labels = tab.sources["contour_labels"].data
    moved = 0
    for x, y in list(zip(labels["x"], labels["y"], strict=True)):  # onto each label in turn
        app.set_values(R_dagger=round(x, 1), h=round(y, 1))
        now = tab.sources["contour_labels"].data
        boxes = label_box(now["x"], now["y"], now["align"], now["baseline"], *bounds)
        assert not overlap(boxes, tab.star_box()).any()
        moved += 1
    assert moved >= 3


def test_the_legend_refits_when_its_red_lines_label_changes(app):
    """A leaky pump's map renames the red line's legend item once mapped: the page measures the
    legend's columns again (figures.FIT_TEXT_JS), from the frame's left edge, where a legend
    below the plot starts, not the figure's."""
    from windpump_app.figures import FIT_TEXT_JS
    from windpump_app.map_tab import STALL_LABEL

    fit = app.design_map.figure._fit_text
    for label, item in app.design_map.legend.items():
        assert fit in item.js_property_callbacks.get("change:label", []), label
    assert STALL_LABEL in app.design_map.legend
    assert "frame.left" in FIT_TEXT_JS


def css_px(length: str, screen_height: float) -> float:
    """A CSS length made of px, 100vh, calc() and clamp() [px] on a screen ``screen_height`` px
    high (as the browser computes it)."""
    expression = length.replace("calc", "").replace("100vh", f"{screen_height}").replace("px", "")
    assert re.fullmatch(r"[\d\s.+\-*/(),]*(clamp[\d\s.+\-*/(),]*)*", expression), length
    return eval(
        expression, {"__builtins__": {}, "clamp": lambda low, x, high: max(low, min(x, high))}
    )


def phone_rules(figure) -> dict[str, str]:
    """The properties a figure's own stylesheets set on it below 700 px (a phone held upright)."""
    rules: dict[str, str] = {}
    for sheet in figure.stylesheets:
        found = re.search(r"@media \(max-width: 700px\) \{ :host \{(.*)\} \}", str(sheet))
        for rule in found.group(1).split(";") if found else []:
            if rule.strip():
                name, said = rule.split(":", 1)
                rules[name.strip()] = said.strip()
    return rules


@pytest.mark.parametrize("screen_height", [640, 844, 915])
def test_on_a_phone_the_map_fits_the_tabs_pane_and_keeps_its_height_elsewhere(app, screen_height):
    """On a phone (page.NARROW_CSS) the tabs' pane is what the controls' pane (page.CONTROLS_SHARE) leaves of the screen
    below the header (54 px
    at 390×844), less its padding (4 px above, 12 below): the map's figure, 520 px high, was
    taller than the pane (~442 px at 390×844) and its top went under the header once scrolled
    to its foot. There it fits the pane; elsewhere it stays 520 px high."""
    figure = app.design_map.figure
    assert (figure.height, figure.sizing_mode) == (520, "stretch_width")  # 1280×720 and wider
    rules = phone_rules(figure)
    # Panel lays the figure out in a column, where its flex basis (520 px) rules over its height
    assert {"height", "flex-basis"} <= set(rules), rules
    pane = (screen_height - 54) * (1 - CONTROLS_SHARE) - (4 + 12)
    for name in ("height", "flex-basis"):
        length, important = rules[name].removesuffix("!important").strip(), "!important"
        assert rules[name].endswith(important)  # over the figure's own 520 px
        drawn = css_px(length, screen_height)
        assert drawn <= pane, (name, drawn, pane)
        assert drawn >= min(300.0, pane) and drawn >= min(520.0, pane - 20.0), (name, drawn, pane)


def test_the_hover_says_in_words_where_the_pump_stalls(app):
    """Left of a tight pump's stall line the core's mean flow is NaN (DesignMap: the stall
    margin is 1 or less, Eq. 22): the map's hover said "NaN m³/day" there. Its flow is formatted
    in the page: in words where the core's flow is NaN, in m³/day elsewhere."""
    from bokeh.models import CustomJSHover, HoverTool

    from windpump_app.map_tab import STALLED

    tab = app.design_map
    (hover,) = [tool for tool in tab.figure.tools if isinstance(tool, HoverTool)]
    # Bokeh writes "NaN" for a NaN field (@image) before its formatter: the pixel's index is
    # formatted, the formatter reading the flow source's image there
    assert dict(hover.tooltips)["flow"] == "$image_index{custom}"
    formatter = hover.formatters["$image_index"]
    assert isinstance(formatter, CustomJSHover)
    assert formatter.args == {"source": tab.sources["flow"], "stalled": STALLED}
    assert "Number.isFinite(flow)" in formatter.code and "m³/day" in formatter.code
    assert "NaN" not in STALLED and "stalls" in STALLED
    # the words stand exactly where the core says the pump cannot run
    design = app.inputs.design()
    core = windpump.design_map(design, np.linspace(0.5, 10.0, GRID), np.linspace(0.0, 30.0, GRID))
    image = tab.sources["flow"].data["image"][0]
    stalled = core.margin <= 1.0
    assert stalled.any() and (~stalled).any()
    np.testing.assert_array_equal(~np.isfinite(image), stalled)


def test_before_its_first_map_the_tab_draws_no_image_to_hover():
    """Until the first map comes (a leaky pump's takes ~1.7 s) there is no image: a blank one's
    hover would say the pump stalls everywhere."""
    from windpump_app import map_tab

    held: list = []
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(map_tab, "off_the_loop", lambda work, then: held.append((work, then)))
        explorer = Explorer()
        explorer.main().active = 3
    tab = explorer.design_map
    assert held and tab.mapped is None
    assert list(tab.sources["flow"].data["image"]) == []
    work, then = held[-1]
    then(work())
    assert np.shape(tab.sources["flow"].data["image"][0]) == (GRID, GRID)


def test_a_deep_wells_design_is_on_the_map_whose_heads_follow_it():
    """The map's heads stopped at 30 m: the Aermotor preset (175 ft, 53 m) stood above it. The
    map reaches past the design's head, drawn by the core over the figure's ranges, the star on
    a flow the pump lifts; back at a shallow head the paper's 0-30 m map returns, in the same
    figure."""
    app = Explorer()
    app.main().active = 3
    tab = app.design_map
    figure = tab.figure
    app.sidebar.preset.value = "8-ft Aermotor, 175-ft well"
    design = app.seen.design
    x_range, y_range = figure.x_range, figure.y_range
    assert y_range.start == 0.0 and y_range.end >= 1.5 * design.h > 75.0
    assert x_range.start < design.R_dagger < x_range.end
    glyph = tab.image.glyph
    assert (glyph.x, glyph.x + glyph.dw) == (x_range.start, x_range.end)
    assert (glyph.y, glyph.y + glyph.dh) == (y_range.start, y_range.end)
    ratios = np.linspace(x_range.start, x_range.end, GRID)
    heads = np.linspace(y_range.start, y_range.end, GRID)
    expected = windpump.design_map(design, ratios, heads)
    image = tab.sources["flow"].data["image"][0]
    np.testing.assert_allclose(image, expected.mean_flow * SECONDS_PER_DAY, rtol=1e-12)
    assert tab.sources["here"].data["h"] == [design.h]
    row = np.searchsorted(heads, design.h)  # the map's flow about the star: it lifts water
    column = np.searchsorted(ratios, design.R_dagger)
    assert np.isfinite(image[row - 1 : row + 1, column - 1 : column + 1]).all()
    assert "no sprocket ratio on this map carries the load" not in tab.readout.object
    app.reset()  # the paper's example, 3 m: the paper's map
    assert (y_range.start, y_range.end) == (0.0, 30.0) and tab.figure is figure
    assert tab.sources["here"].data["h"] == [3.0]
