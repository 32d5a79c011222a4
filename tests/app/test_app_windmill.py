"""The windmill's choice in-process: the paper's curve, a multiblade wheel of a diameter, an
Aermotor 702 of the catalogue; its link, its readouts and the coefficients' view against the core
(and hand references written here), its preset, and the Wind, Design map and Site tabs with a
wheel."""

from __future__ import annotations

import math
import re
from urllib.parse import parse_qsl

import numpy as np
import pytest
from scipy import optimize

import windpump
from windpump.catalogue import aermotor_702
from windpump.units import M3_PER_US_GALLON, METRES_PER_FOOT, SECONDS_PER_DAY
from windpump_app.explorer import Explorer
from windpump_app.inputs import PRESETS
from windpump_app.map_tab import GRID
from windpump_app.views import BINS

SEED = windpump.Design.seed_example()
AERMOTOR = "8-ft Aermotor, 175-ft well"


def readouts(app) -> dict[str, str]:
    """Every readout's value shown, as the page shows it."""
    return {name: value(r, name) for name, r in app.readouts.readouts.items() if r.visible}


def reopened(app) -> Explorer:
    """A page opened from ``app``'s link."""
    query = app.link_query()
    return Explorer(query={key: [value.encode()] for key, value in parse_qsl(query)})


def test_a_multiblade_wheel_is_the_rotor_of_the_diameter_on_the_sliders_pump():
    app = Explorer()
    app.set_values(windmill="multiblade", diameter=3.0, h=4.0, V=6.0)
    design = app.seen.design
    wheel = windpump.Rotor.multiblade(3.0)
    expected = windpump.Design.from_rotor(wheel, V_ref=6.0, **{**SEED.geometry(), "h": 4.0})
    assert design.rotor == wheel and design.V_ref == 6.0
    for name, value in expected.as_dict().items():
        assert getattr(design, name) == pytest.approx(value, rel=1e-12), name
    # the wheel sets T_m, omega_m and T_0: their sliders are hidden, the diameter shown
    sliders = app.sidebar.sliders
    assert not sliders["T_m"].visible and not sliders["T_0"].visible
    assert sliders["diameter"].visible and sliders["R_dagger"].visible
    assert app.sidebar.windmill.note.visible and "sets Tₘ, ωₘ" in app.sidebar.windmill.note.object
    app.sidebar.windmill.select.value = "eq11"  # the widget drives the input
    assert app.seen.design.rotor is None and sliders["T_m"].visible
    assert not sliders["diameter"].visible and not app.sidebar.windmill.note.visible


def test_an_aermotor_is_the_catalogues_mill_lifting_by_the_head():
    app = Explorer()
    app.set_values(windmill="aermotor", wheel_ft=10, cylinder_in=2.5, stroke="short", h=30.0)
    expected = aermotor_702(
        10, "2 1/2", stroke="short", lift_ft=30.0 / METRES_PER_FOOT, V_ref=SEED.V_ref,
        L_over_R=SEED.L_over_R,
    )  # fmt: skip
    design = app.seen.design
    assert design.rotor == expected.rotor
    for name, value in expected.as_dict().items():
        assert getattr(design, name) == pytest.approx(value, rel=1e-12), name
    sliders = app.sidebar.sliders
    assert not any(sliders[name].visible for name in ("R_dagger", "T_m", "diameter"))
    assert app.sidebar.windmill.aermotor.visible
    assert app.sidebar.windmill.wheel.value == 10 and app.sidebar.windmill.stroke.value == "short"


def test_the_head_slider_reaches_a_catalogue_mills_lift_and_the_papers_stays_fine():
    app = Explorer()
    assert app.sidebar.sliders["h"].end == 30.0  # the paper's pump stalls at 21 m
    app.set_values(windmill="aermotor")
    assert app.sidebar.sliders["h"].end == 300.0  # 920 ft: the 16-ft mill's lift
    app.set_values(windmill="eq11", h=40.0)  # a head beyond: the slider shows it
    assert app.sidebar.sliders["h"].end == 300.0


@pytest.mark.parametrize(
    "query",
    [
        {"windmill": "multiblade", "diameter": "3.7", "h": "6", "V": "7.5"},
        {"windmill": "aermotor", "wheel_ft": "12", "cylinder_in": "2.75", "stroke": "short",
         "h": "60", "theta_dot0": "0"},
    ],
)  # fmt: skip
def test_a_link_keeps_the_windmill_and_reopens_the_same_readouts(query):
    app = Explorer(query={key: [value.encode()] for key, value in query.items()})
    assert not app.notices.visible and not app.error.visible
    assert dict(parse_qsl(app.inputs.query())) == {**query}
    again = reopened(app)
    assert again.inputs.values() == app.inputs.values()
    assert again.seen.design == app.seen.design
    assert readouts(again) == readouts(app)
    assert {"tsr", "strokes", "cp", "max_head"} <= set(readouts(app))


@pytest.mark.parametrize(
    "query, notice",
    [
        ({"windmill": "banana"}, "Windmill (windmill) = “banana” ignored: one of eq11, multiblade, "
         "aermotor."),
        ({"windmill": "multiblade", "diameter": "9"}, "(diameter) = “9” ignored: it must be a "
         "number from 1.5 to 6."),
        ({"windmill": "aermotor", "stroke": "medium"}, "Stroke (stroke) = “medium” ignored: one "
         "of long, short."),
        ({"windmill": "aermotor", "wheel_ft": "7"}, "Wheel [ft] (wheel_ft) = “7” ignored: one of "
         "6, 8, 10, 12, 14, 16."),
        # a cylinder the table has, but not on this wheel: the core refuses it with the others
        ({"windmill": "aermotor", "cylinder_in": "3.75"}, "Cylinder bore [in] (cylinder_in) = “3.75” "
         "ignored: "),
    ],
)  # fmt: skip
def test_a_bad_windmill_value_in_the_link_gets_the_notice_others_get(query, notice):
    app = Explorer(query={key: [value.encode()] for key, value in query.items()})
    assert app.notices.visible and notice in app.notices.object, app.notices.object
    assert not app.error.visible and app.seen is not None


def hand_tsr(design: windpump.Design) -> float:
    """λ where it runs, by hand, for an ideal single-acting pump: α₊ the root of the averaged
    balance R† T(R† α) = ρ_w g h (2 R A) / 2π (the lifted water's work a revolution over 2π) on
    the falling side of the wheel's torque (brentq), ω = R† α₊, λ = ω (D/2) / V."""
    assert design.is_ideal and design.cylinders == 1 and not design.double_acting
    load = design.rho_w * design.g * design.h * 2 * design.R * design.A / (2 * math.pi)

    def balance(alpha):
        return design.R_dagger * windpump.windmill_torque(design, design.R_dagger * alpha) - load

    runaway = design.runaway_speed / design.R_dagger  # the multiblade's torque falls from rest
    alpha = optimize.brentq(balance, 0.0, runaway, xtol=1e-14, rtol=1e-15)
    return design.R_dagger * alpha * (design.rotor.diameter / 2) / design.V_ref


def test_a_wheels_readouts_are_the_cores_where_it_runs():
    app = Explorer()
    app.set_values(windmill="multiblade", diameter=2.0, h=12.0, R_dagger=2.0)
    design, op = app.seen.design, app.seen.operating_point
    tsr = hand_tsr(design)
    assert op.omega * 1.0 / design.V_ref == pytest.approx(tsr, rel=1e-9)
    shown_now = readouts(app)
    assert shown_now["tsr"] == f"{tsr:.2f}"
    assert shown_now["strokes"] == f"{op.crank_speed * 60 / (2 * math.pi):.1f} /min"
    cq = float(design.rotor.cq(tsr))
    assert shown_now["cp"] == f"{tsr * cq:.3f}"  # C_P = λ C_Q
    running, start = windpump.max_head(design), windpump.max_head(design, start=True)
    assert shown_now["max_head"] == f"{running:.4g} m, {start:.4g} m"
    # running: the stall margin falls to 1 there; starting: the torque at rest meets the peak load
    assert windpump.stall_margin(design.replace(h=running)) == pytest.approx(1.0, rel=1e-9)
    at_start = design.replace(h=start)
    assert design.eta_t * design.R_dagger * design.T_0 == pytest.approx(
        windpump.peak_load_torque(at_start), rel=1e-9
    )
    app.set_values(windmill="eq11")  # the paper's curve: no wheel's readouts
    assert not {"tsr", "strokes", "cp", "max_head"} & set(readouts(app))


def test_the_view_draws_the_wheels_coefficients_and_where_it_runs_then_the_papers_curve():
    app = Explorer()
    view = app.pump.built["operating"]
    app.set_values(windmill="multiblade", diameter=4.0, h=8.0)
    design = app.seen.design
    rotor = design.rotor
    data = view.sources["coefficients"].data
    tsr = np.asarray(data["tsr"])
    assert len(tsr) <= BINS and tsr[0] == 0.0 and tsr[-1] > rotor.runaway_tsr
    np.testing.assert_allclose(data["cq"], rotor.cq(tsr), rtol=1e-12)
    np.testing.assert_allclose(data["cp"], tsr * rotor.cq(tsr), rtol=1e-12)
    running = view.sources["running"].data
    assert running["tsr"][0] == pytest.approx(hand_tsr(design), rel=1e-9)
    assert running["cp"][0] == pytest.approx(running["tsr"][0] * running["cq"][0], rel=1e-12)
    assert view.figure.xaxis.axis_label.startswith("tip-speed ratio λ")
    assert view.sources["curve"].data["omega"] == []  # nothing of Eq. 11 drawn
    visible = {label for label, item in view.items.items() if item.visible}
    assert visible == {"torque coefficient C_Q", "power coefficient C_P", "where it runs"}
    app.set_values(windmill="eq11")
    assert view.figure.xaxis.axis_label == "windmill speed ω [rad/s]"
    assert view.sources["coefficients"].data["tsr"] == []
    assert len(view.sources["curve"].data["omega"]) > 0
    assert "windmill, Eq. (11)" in {label for label, item in view.items.items() if item.visible}


def test_the_aermotor_preset_does_what_its_sentence_says():
    app = Explorer()
    app.sidebar.preset.value = AERMOTOR
    values, sentence = PRESETS[AERMOTOR]
    assert sentence in app.sidebar.preset_note.object and not app.error.visible
    design, seen = app.seen.design, app.seen
    assert design.h == pytest.approx(175 * METRES_PER_FOOT, rel=1e-12)
    assert design.rotor.diameter == pytest.approx(8 * METRES_PER_FOOT, rel=1e-12)
    assert seen.starts_from_rest and "starts on its own" in app.readouts.status.object
    assert seen.status is windpump.Status.RUNNING and values["theta_dot0"] == 0.0
    assert seen.tau < 10.0  # "within seconds"
    strokes = seen.operating_point.crank_speed * 60 / (2 * math.pi)
    assert round(strokes) == 28  # "some 28 strokes a minute"
    gallons = seen.mean_flow * 3600 / M3_PER_US_GALLON
    assert 150 < gallons < 170  # "about 160 gal/h"
    tsr = hand_tsr(design)
    assert round(tsr, 1) == 1.8  # "λ ≈ 1.8"
    lam = np.linspace(0.0, design.rotor.runaway_tsr, 2001)
    assert abs(lam[np.argmax(design.rotor.cp(lam))] - 1.0) < 0.1  # "the C_P peak near λ = 1"
    again = reopened(app)  # its link says which preset it is
    assert again.sidebar.preset.value == AERMOTOR and readouts(again) == readouts(app)


def wheel_page(tab: int) -> Explorer:
    app = Explorer()
    app.set_values(windmill="multiblade")
    app.main().active = tab
    return app


def value(readout, name) -> str:
    html = readout.object
    value = html.split(f'data-name="{name}">')[1].rsplit("</div></div>", 1)[0]
    return re.sub(r"<[^>]+>", "", value)


def test_the_wind_tab_with_a_wheel_is_the_cores():
    app = wheel_page(2)
    design = app.inputs.design_at_v_ref()
    assert design.rotor is not None
    wind = app.wind
    V_stop, V_start = windpump.wind_thresholds(design)
    assert math.isfinite(V_stop) and math.isfinite(V_start)
    assert value(wind.readouts["thresholds"], "thresholds") == f"{V_stop:.1f} · {V_start:.1f}"
    curve = wind.sources["curve"].data
    flow = np.asarray(curve["flow"])
    assert np.isfinite(flow).all() and flow.max() > 0
    np.testing.assert_allclose(flow, 1e3 * windpump.steady_flow(design, curve["V"]), rtol=1e-12)
    litres = np.asarray(wind.sources["litres"].data["litres"])
    assert len(litres) <= BINS and np.isfinite(litres).all() and litres[-1] > 0


def test_the_design_map_with_a_wheel_is_the_cores():
    app = wheel_page(3)
    design = app.inputs.design()
    ratios, heads = np.linspace(0.5, 10.0, GRID), np.linspace(0.0, 30.0, GRID)
    expected = windpump.design_map(design, ratios, heads)
    image = app.design_map.sources["flow"].data["image"][0]
    assert np.isfinite(image).any()
    np.testing.assert_array_equal(np.isnan(image), np.isnan(expected.mean_flow))
    np.testing.assert_allclose(image, expected.mean_flow * SECONDS_PER_DAY, rtol=1e-12)
    here = app.design_map.sources["here"].data
    flow = float(windpump.steady_flow(design, design.V_ref)) * SECONDS_PER_DAY
    assert here["flow"][0] == pytest.approx(flow, rel=1e-12) and flow > 0


def test_the_site_tab_with_a_wheel_is_the_cores():
    app = wheel_page(4)
    site = app.site
    design = app.inputs.design_at_v_ref()
    inputs = app.site_inputs
    record = windpump.sample_site(inputs.site).at_height(inputs.hub)
    supplied = windpump.supply(design, record, inputs.demand, inputs.tank, restart=inputs.restart)
    monthly = site.sources["monthly"].data
    assert np.isfinite(monthly["pumped"]).all() and sum(monthly["pumped"]) > 0
    np.testing.assert_array_equal(monthly["pumped"], np.asarray(supplied.monthly.pumped))
    assert value(site.readouts["site_lolp"], "site_lolp") == f"{100 * supplied.lolp:.1f} %"


def test_the_units_switch_shows_the_readouts_in_us_units_and_is_kept_in_the_link():
    app = Explorer(query={"windmill": [b"multiblade"], "units": [b"us"]})
    assert app.sidebar.units_switch.value == "us" and not app.notices.visible
    seen = app.seen
    gallons_an_hour = seen.mean_flow * 3600 / M3_PER_US_GALLON
    shown_now = readouts(app)
    assert shown_now["mean_flow"].endswith(f" · {gallons_an_hour:.3g} gal/h")
    assert shown_now["volume"] == f"{seen.pumped_volume / M3_PER_US_GALLON:.4g} gal"
    feet = [
        windpump.max_head(seen.design, start=start) / METRES_PER_FOOT for start in (False, True)
    ]
    assert shown_now["max_head"] == f"{feet[0]:.4g} ft, {feet[1]:.4g} ft"
    # the heads are for the design's wind, and the label says which (a new user read "456 m")
    mph = seen.design.V_ref / 0.44704
    assert (
        f"Max head in {mph:.3g} mph: running, starting" in app.readouts.readouts["max_head"].object
    )
    assert "units=us" in app.link_query()
    assert readouts(reopened(app)) == shown_now
    app.sidebar.units_switch.value = "si"  # back: the link drops it, the readouts in SI
    assert "units" not in app.link_query()
    assert readouts(app)["mean_flow"] == f"{1e3 * seen.mean_flow:.4f} L/s"
    label = f"Max head in {seen.design.V_ref:.3g} m/s: running, starting"
    assert label in app.readouts.readouts["max_head"].object
    app.sidebar.units_switch.value = "us"
    app.reset()  # a mode of the page: Reset keeps it
    assert app.units == "us" and readouts(app)["mean_flow"].endswith(" gal/h")
    bad = Explorer(query={"units": [b"metric"]})
    assert "Units (units) = “metric” ignored: si or us." in bad.notices.object


def test_in_us_units_the_mean_flow_is_in_gallons_a_minute_and_an_hour_by_pint():
    """A builder reads a pump's flow in gallons a minute, a windmill catalogue in gallons an
    hour: both, each pint's conversion of the core's mean flow."""
    import pint

    app = Explorer(query={"units": [b"us"]})
    app.sidebar.preset.value = AERMOTOR
    flow = pint.UnitRegistry().Quantity(app.seen.mean_flow, "m**3/s")
    per_minute, per_hour = (flow.to(unit).magnitude for unit in ("gallon/minute", "gallon/hour"))
    assert readouts(app)["mean_flow"] == f"{per_minute:.3g} gpm · {per_hour:.3g} gal/h"
    assert 2.5 < per_minute < 2.85  # the preset's "about 160 gal/h"


def test_the_coefficients_caption_says_which_curve_is_which_and_where_it_runs():
    """One caption served both the paper's curve and a wheel's coefficients: it says what the
    view draws now, which curve is C_Q and which C_P, and where it runs."""
    app = Explorer()
    view = app.pump.built["operating"]
    caption = view.caption_panel()
    assert caption in app.pump.slots["operating"].objects  # the one under the figure

    def said() -> str:
        return re.sub(r"<[^>]+>", "", caption.object)

    assert "Eq. 11, solid" in said() and "C_Q" not in said()
    app.set_values(windmill="multiblade", diameter=4.0, h=8.0)
    design = app.seen.design
    tsr = hand_tsr(design)
    cq = float(design.rotor.cq(tsr))
    assert "solid, its torque coefficient C_Q(λ)" in said()
    assert "dashed, its power coefficient C_P(λ) = λ C_Q" in said()
    assert f"λ = {tsr:.2f}, C_Q = {cq:.3f}, C_P = {tsr * cq:.3f}." in said()
    (cq_line,) = view.items["torque coefficient C_Q"].renderers  # drawn as the caption says
    (cp_line,) = view.items["power coefficient C_P"].renderers
    assert cq_line.glyph.line_dash == [] and cp_line.glyph.line_dash == [6]  # solid, dashed
    app.set_values(diameter=1.5, V=1.0, h=100.0)  # a small wheel, a calm, a deep well
    assert app.seen.operating_point is None
    assert "does not run in this wind" in said() and "C_P(λ) = λ C_Q" in said()
    app.set_values(windmill="eq11", h=3.0)
    assert "Eq. 11, solid" in said() and "C_Q" not in said()


def test_the_wind_tab_says_its_winds_in_mph_and_its_water_in_gallons_in_us_units():
    app = wheel_page(2)
    wind = app.wind
    design = app.inputs.design_at_v_ref()
    V_stop, V_start = windpump.wind_thresholds(design)
    mph = 3600 / 1609.344  # [mph per m/s]: a mile is 1609.344 m
    app.sidebar.units_switch.value = "us"
    thresholds = wind.readouts["thresholds"]
    assert "[mph]" in thresholds.object
    assert value(thresholds, "thresholds") == f"{V_stop * mph:.1f} · {V_start * mph:.1f}"
    low, high = windpump.water_per_day(design, app.inputs.mean_wind, app.inputs.k)
    gallons = [
        f"{float(f'{g:.3g}'):,.0f}" for g in (low / M3_PER_US_GALLON, high / M3_PER_US_GALLON)
    ]
    assert value(wind.readouts["site_bounds"], "site_bounds") == " · ".join(gallons)
    assert "[gal/day]" in wind.readouts["day_litres"].object
    app.sidebar.units_switch.value = "si"
    assert value(thresholds, "thresholds") == f"{V_stop:.1f} · {V_start:.1f}"
    assert "[m/s]" in thresholds.object


def test_a_lab_fit_applied_on_a_wheels_page_is_the_papers_curve_it_fits():
    """A lab file's fit is of Eq. (11): applied, the page's windmill is the paper's curve with
    the fitted Tₘ and ωₘ, and the measurements are drawn over its power curve."""
    app = Explorer()
    app.set_values(windmill="multiblade")
    omega = np.linspace(5, 75, 15)
    torque = 0.8 * (omega / 40) * (2 - omega / 40)  # Eq. 11, T_m = 0.8 N m, omega_m = 40 rad/s
    app.load_lab_data("".join(f"{w},{q}\n" for w, q in zip(omega, torque, strict=True)).encode())
    assert app.inputs.windmill == "eq11" and app.seen.design.rotor is None
    assert app.seen.design.T_m == pytest.approx(0.8, rel=1e-6)
    assert app.seen.design.omega_m == pytest.approx(40.0 * app.inputs.V / SEED.V_ref, rel=1e-6)
    view = app.pump.built["operating"]
    assert view.items["lab data"].visible and view.items["lab data"].renderers[0].visible


def test_a_link_naming_only_the_windmill_says_it_is_the_links_design():
    app = Explorer(query={"windmill": [b"multiblade"]})
    assert app.sidebar.preset_note.visible
    assert app.sidebar.preset_note.object == "Your design, from the link."
