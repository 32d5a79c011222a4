"""The explorer's energy view and mechanisms tab in-process: widgets set, sources checked against
windpump and against the closed forms of test_linkage."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from linkage_reference import half_angle

import windpump
from windpump_app.explorer import Explorer
from windpump_app.mechanisms import SIX_BAR

SEED = windpump.Design.seed_example()


@pytest.fixture(scope="module")
def app():
    return Explorer()


def points(source, *columns):
    return np.column_stack([np.asarray(source.data[c], dtype=float) for c in columns])


def bar_lengths(source):
    return [
        math.dist((xs[0], ys[0]), (xs[1], ys[1]))
        for xs, ys in zip(source.data["xs"], source.data["ys"], strict=True)
    ]


# -- the energy view ----------------------------------------------------------------------------


def test_the_energy_view_is_a_waterfall_of_the_windmills_work(app):
    app.reset()
    bars = app.sources["losses"].data
    run = windpump.simulate(SEED, 600.0)
    budget = windpump.power_budget(run)
    W, K, E = (float(a[-1]) for a in (budget.shaft_work, budget.kinetic_energy, budget.lift_work))
    steps = dict(zip(bars["step"], zip(bars["left"], bars["right"], strict=True), strict=True))
    assert steps["windmill's work"] == pytest.approx((0.0, W))
    for loss in ("chain", "rising main", "leak hole"):  # the ideal machine loses nothing
        assert steps[loss][1] - steps[loss][0] == pytest.approx(0.0, abs=1e-9 * W)
    assert steps["spinning up"] == pytest.approx((W - K, W))
    assert steps["lifted water"] == pytest.approx((0.0, E))
    assert W - K == pytest.approx(E, rel=1e-6)  # the water's bar meets what is left
    text = re.sub(r"<[^>]+>", "", app.readouts["energy"].object)  # as the page shows it
    assert f"{budget.shaft_work[-1]:,.0f} J = {budget.kinetic_energy[-1]:,.0f} J + " in text


def test_the_energy_view_follows_the_sliders(app):
    app.reset()
    try:
        before = list(app.sources["losses"].data["right"])
        app.sidebar.sliders["h"].value = 6.0
        run = windpump.simulate(SEED.replace(h=6.0), 600.0)
        lift = windpump.power_budget(run).lift_work[-1]
        assert list(app.sources["losses"].data["right"]) != before
        text = re.sub(r"<[^>]+>", "", app.readouts["energy"].object)  # as the page shows it
        shown = float(re.findall(r"([\d,]+) J", text)[-1].replace(",", ""))  # the water's, last
        assert abs(shown - lift) <= 1.0, (shown, lift)  # each term within a joule: they add up
    finally:
        app.reset()


def test_the_waterfall_and_readouts_name_the_real_machines_losses(app):
    app.reset()
    app.set_values(m_r=1.0, eta_t=0.9, L_main=20.0, d_leak_mm=2.0)
    design = SEED.replace(m_r=1.0, eta_t=0.9, L_main=20.0, d_leak=0.002)
    assert app.seen.design == design
    run = windpump.simulate(design, 600.0)
    totals = windpump.power_budget(run).totals()
    bars = app.sources["losses"].data
    widths = dict(zip(bars["step"], np.subtract(bars["right"], bars["left"]), strict=True))
    assert widths["chain"] == pytest.approx(totals.transmission, rel=1e-6)
    assert widths["rising main"] == pytest.approx(totals.friction, rel=1e-6)
    assert widths["leak hole"] == pytest.approx(totals.leak, rel=1e-6)
    assert widths["lifted water"] == pytest.approx(totals.water, rel=1e-6)
    assert bars["left"][bars["step"].index("spinning up")] == pytest.approx(totals.water, rel=1e-6)
    assert app.readouts["efficiency"].visible  # shown for a real machine, hidden for the ideal
    efficiency = app.readouts["efficiency"].object
    assert f"{100 * run.volumetric_efficiency:.1f} %" in efficiency
    assert f"{100 * run.overall_efficiency:.1f} %" in efficiency
    lost = totals.transmission + totals.friction + totals.leak
    text = re.sub(r"<[^>]+>", "", app.readouts["energy"].object)  # as the page shows it
    right = text.split("=")[-1]  # losses + gained speed + lifted water
    shown = float(re.findall(r"([\d,]+) J", right)[0].replace(",", ""))
    assert abs(shown - lost) <= 3.0, (shown, lost)  # three terms, each within a joule
    app.reset()


def test_the_machine_shows_its_rising_main_and_leak_hole_only_when_it_has_them(app):
    app.reset()
    assert app.sources["machine_main"].data["xs"] == []
    assert app.sources["machine_notes"].data["text"] == []
    app.set_values(L_main=30.0, d_leak_mm=2.5)
    assert len(app.sources["machine_main"].data["xs"]) == 1
    notes = app.sources["machine_notes"].data["text"]
    assert any("30 m × 50 mm" in note for note in notes)
    assert any("2.5 mm" in note for note in notes)
    app.reset()
    assert app.sources["machine_main"].data["xs"] == []


@pytest.mark.parametrize("cylinders", [1.0, 2.0, 4.0])
def test_the_rising_mains_label_ends_inside_the_drawing_right_of_the_cylinders(app, cylinders):
    """The label is anchored at its right end inside the frame, with room for ~130 px of text
    (presentation mode) between the last cylinder and the frame's edge on a phone's ~370 px."""
    app.set_values(L_main=30.0, D_main_mm=25.0, cylinders=cylinders)
    notes = app.sources["machine_notes"].data
    x_range = app.pump.machine.figure.x_range
    width = x_range.end - x_range.start
    walls = app.sources["machine_static"].data["xs"][2 : 2 + 2 * int(cylinders)]
    wall = max(max(xs) for xs in walls)  # the last cylinder's right wall
    assert notes["align"][0] == "right"
    assert wall < notes["x"][0] < x_range.end
    assert notes["x"][0] - wall >= 130 / 370 * width
    app.reset()


# -- the pump's slider-crank --------------------------------------------------------------------


@pytest.mark.parametrize("angle", [0.0, 37.0, 90.0, 200.0, 359.0])
def test_the_slider_crank_is_drawn_where_eq_1_puts_it(app, angle):
    app.reset()
    app.mechanisms.slider_crank.crank_angle.value = angle
    R, L = SEED.R, SEED.L
    x = float(windpump.piston_position(math.radians(angle), R, L))
    (centre,) = points(app.sources["crank_pivots"], "x", "y")
    pin, piston = points(app.sources["crank_joints"], "x", "y")
    np.testing.assert_allclose(centre, [0, 0], atol=1e-15)
    assert piston[0] == pytest.approx(0.0, abs=1e-15)  # on the cylinder's axis
    assert piston[1] == pytest.approx(L + R - x, abs=1e-14)  # x below top dead centre
    assert math.dist(centre, pin) == pytest.approx(R) and math.dist(pin, piston) == pytest.approx(L)
    assert bar_lengths(app.sources["crank_links"]) == pytest.approx([R, L])
    theta_c = math.degrees(float(windpump.rod_angle(math.radians(angle), SEED.L_over_R)))
    note = app.mechanisms.slider_crank.crank_note.object
    assert f"x = {1e3 * x:.2f} mm" in note and f"θc = {theta_c:.1f}°" in note
    assert app.sources["travel_point"].data == {"angle": [angle], "x": [pytest.approx(1e3 * x)]}


def test_the_slider_crank_follows_the_pumps_rod(app):
    app.sidebar.sliders["L_over_R"].value = 2.0
    pin, piston = points(app.sources["crank_joints"], "x", "y")
    assert math.dist(pin, piston) == pytest.approx(2 * SEED.R)
    assert max(app.sources["travel"].data["x"]) == pytest.approx(2e3 * SEED.R)
    app.reset()
    assert math.dist(*points(app.sources["crank_joints"], "x", "y")) == pytest.approx(SEED.L)


# -- the four-bar and double-loop explorer ------------------------------------------------------


def four_bar_state(app):
    m = app.mechanisms
    for name, value in dict(r1=1.0, r2=3.0, r3=2.5, r6=3.0).items():
        m.links[name].value = value
    m.kind.value, m.branch.value = "Four-bar", 1
    return m


@pytest.mark.parametrize("branch", [1, -1])
@pytest.mark.parametrize("angle", [60.0, 200.0, -150.0])
def test_the_four_bar_is_drawn_from_its_closed_loop(app, branch, angle):
    m = four_bar_state(app)
    m.input_angle.value = 0.0
    m.branch.value = branch
    m.input_angle.value = angle  # dragged: followed along the branch
    origin, D = points(app.sources["linkage_pivots"], "x", "y")
    A, B = points(app.sources["linkage_joints"], "x", "y")
    np.testing.assert_allclose([origin, D], [[0, 0], [3.0, 0]], atol=1e-12)
    theta2, theta3 = half_angle(1.0, 3.0, 2.5, 3.0, math.radians(angle))[branch]
    np.testing.assert_allclose(A, [math.cos(math.radians(angle)), math.sin(math.radians(angle))])
    np.testing.assert_allclose(
        B, A + 3.0 * np.array([math.cos(theta2), math.sin(theta2)]), atol=1e-12
    )
    np.testing.assert_allclose(
        B, D + 2.5 * np.array([math.cos(theta3), math.sin(theta3)]), atol=1e-12
    )
    assert f"θ₂ = {math.degrees(theta2):.1f}°" in m.linkage_note.object  # θ₁'s subscripts
    assert f"Branch {branch:+d}" in m.linkage_note.object and not m.linkage_error.visible
    assert len(app.sources["linkage_path"].data["x"]) > 100  # B's whole coupler path


def test_a_branch_that_ends_says_so_and_recovers(app):
    m = app.mechanisms
    m.input_angle.value = 0.0
    for name, value in dict(r1=2.0, r2=2.5, r3=2.0, r6=3.0).items():  # non-Grashof
        m.links[name].value = value
    assert "rocks between limits" in m.linkage_note.object
    m.input_angle.value = 170.0
    limit = math.degrees(math.acos((4 + 9 - 4.5**2) / 12))  # |AD| = r2 + r3
    assert m.linkage_error.visible and "Cannot close at θ₁ = " in m.linkage_error.object
    assert "too short to reach" in m.linkage_error.object
    (A, _) = points(app.sources["linkage_joints"], "x", "y")
    drawn = math.degrees(math.atan2(A[1], A[0]))
    assert limit - 2.0 <= drawn < limit  # drawn at the end of its branch
    assert f"{drawn:.1f}°" in m.linkage_error.object
    m.input_angle.value = 60.0
    assert not m.linkage_error.visible
    A, B = points(app.sources["linkage_joints"], "x", "y")
    assert math.dist(A, B) == pytest.approx(2.5) and math.dist(B, (3.0, 0.0)) == pytest.approx(2.0)
    four_bar_state(app)


def test_lengths_that_cannot_close_keep_the_last_drawing(app):
    m = four_bar_state(app)
    m.input_angle.value = 60.0
    m.links["r6"].value = 5.0
    before = dict(app.sources["linkage_links"].data)
    m.links["r2"].value = 0.5  # r2 + r3 = 3 cannot span |AD| = 4.58
    assert m.linkage_error.visible and "Cannot close at θ₁ = 60.0°" in m.linkage_error.object
    assert "Coupler r₂ = 0.5 and Output link r₃ = 2.5 are too short" in m.linkage_error.object
    assert "theta1" not in m.linkage_error.object and m.linkage_note.object == ""
    assert app.sources["linkage_links"].data == before
    m.links["r2"].value = 3.0
    assert not m.linkage_error.visible
    four_bar_state(app)


def test_the_double_loop_closes_both_loops(app):
    m = four_bar_state(app)
    m.input_angle.value = 60.0
    m.kind.value = SIX_BAR
    assert m.second_loop.visible
    v = {name: widget.value for name, widget in m.links.items()}
    lengths = bar_lengths(app.sources["linkage_links"])
    assert lengths == pytest.approx([v[k] for k in ("r1", "r2", "r3", "r3p", "r4", "r5")])
    _, D, E = points(app.sources["linkage_pivots"], "x", "y")
    np.testing.assert_allclose(E, D + [v["r6p"], 0.0], atol=1e-12)
    assert "θ₄ = " in m.linkage_note.object and "θ₅ = " in m.linkage_note.object
    m.input_angle.value = 120.0
    assert bar_lengths(app.sources["linkage_links"]) == pytest.approx(lengths)
    m.kind.value = "Four-bar"
    assert not m.second_loop.visible and len(app.sources["linkage_links"].data["xs"]) == 3


def test_every_button_and_choice_in_the_tabs_is_14px_or_more():
    """Nothing a student must read below 14 px: each button, button group and select of the tabs
    is given a stylesheet that sizes its text (Bokeh's own is 12.8 px: the Four-bar / Watt
    six-bar and branch buttons were)."""
    import re

    import panel as pn

    explorer = Explorer()
    tabs = explorer.main()
    for index in range(len(tabs)):
        tabs.active = index  # each tab built
    kinds = (pn.widgets.Button, pn.widgets.Toggle, pn.widgets.RadioButtonGroup, pn.widgets.Select)
    widgets = [w for w in tabs.select(pn.widgets.Widget) if isinstance(w, kinds)]
    assert explorer.mechanisms.kind in widgets and explorer.mechanisms.branch in widgets
    for widget in widgets:
        css = " ".join(str(sheet) for sheet in widget.stylesheets)
        rules = re.findall(r"\.bk-btn[^{]*\{[^}]*font-size: calc\((\d+(?:\.\d+)?)px", css)
        rules += re.findall(r"select[^{]*\{[^}]*font-size: calc\((\d+(?:\.\d+)?)px", css)
        assert rules and min(float(size) for size in rules) >= 14, (type(widget).__name__, css)


def test_the_waterfalls_axis_is_plain_numbers_over_the_bars():
    """A deep well's 70,000 J: the axis's ticks in plain numbers with thousands separators (Bokeh's
    default formatter writes 1.500e+5 past 10⁵), the range the bars' (1.02 of the longest; the
    page widens it by what the labels beside the bars need, FIT_BARS_JS), not 2.4 times it."""
    from bokeh.models import CustomJS, NumeralTickFormatter

    explorer = Explorer()
    explorer.show_views()
    explorer.sidebar.preset.value = "A deep well, a heavy rod"
    view = explorer.pump.built["energy"]
    right = view.sources["losses"].data["right"]
    assert max(right) > 5e4  # tens of thousands of joules
    fig = view.figure
    (axis,) = fig.xaxis
    assert isinstance(axis.formatter, NumeralTickFormatter) and axis.formatter.format == "0,0"
    assert fig.x_range.end == pytest.approx(1.02 * max(right))
    fits = view.sources["losses"].js_property_callbacks["change:data"]
    assert any(isinstance(f, CustomJS) and "x_range.end" in f.code for f in fits)


@pytest.mark.parametrize("width, height", [(300, 360), (380, 365), (440, 330)])
def test_the_drawings_keep_equal_scales_whatever_their_frames_shape(app, width, height):
    """A drawing's ranges were equal spans, equal scales only on a square frame: its frame is
    ~320 x 365 px beside the travel plot at 1920 px (and on a phone), and the crank's circle was
    drawn ~14 % taller than wide. Once the page says the frame's pixels, a metre is as many
    pixels across as up, and everything the spans held is still shown."""
    tab = app.mechanisms
    design = app.inputs.design()
    span = design.L + 4 * design.R  # what the slider-crank's drawing holds, across and up
    links = {name: tab.links[name].value for name in ("r1", "r2", "r3")}
    reach = max(links["r1"], links["r2"] + links["r3"])  # the four-bar's, around its pivots
    for fig, needed in ((tab.slider_crank.crank_figure, span), (tab.linkage_figure, 2 * reach)):
        fig.set_from_json("inner_width", width)  # as the page sends them: one, then the other
        fig.set_from_json("inner_height", height)
        across = (fig.x_range.end - fig.x_range.start) / width  # [m/px]
        up = (fig.y_range.end - fig.y_range.start) / height
        assert across == pytest.approx(up, rel=1e-9)
        assert min(fig.x_range.end - fig.x_range.start, fig.y_range.end - fig.y_range.start) == (
            pytest.approx(needed, rel=1e-9)
        )
