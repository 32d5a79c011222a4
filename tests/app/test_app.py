"""The explorer in-process: set inputs and widgets, check the data sources and readouts against windpump."""

from __future__ import annotations

import logging
import math
import re
from decimal import Decimal
from pathlib import Path

import numpy as np
import param
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import windpump
from windpump_app.envelope import band
from windpump_app.explorer import Explorer, design_filename
from windpump_app.figures import WIDTH
from windpump_app.inputs import FORMATS, FROM_THE_LINK, PRESETS, PumpInputs
from windpump_app.page import EMBED_CSS
from windpump_app.sidebar import PRESET_PROMPT
from windpump_app.views import BINS

from panes import shown

SEED = windpump.Design.seed_example()


@pytest.fixture
def app():
    return Explorer()


def expected(design=SEED, t_end=600.0, theta0=math.pi / 2, theta_dot0=3.0):
    return windpump.explore(design, t_end, theta0, theta_dot0)


def readout_text(app, name):
    """A readout's text as the page shows it: its HTML's tags left out."""
    return re.sub(r"<[^>]+>", "", app.readouts[name].object)


def test_the_default_is_the_papers_example(app):
    seen = expected()
    assert app.inputs.design() == SEED
    speed = app.sources["speed"].data
    assert max(speed["upper"]) == pytest.approx(seen.run.theta_dot.max(), rel=1e-12)
    assert min(speed["lower"]) == pytest.approx(seen.run.theta_dot.min(), rel=1e-12)
    np.testing.assert_allclose(app.sources["spinup"].data["speed"], seen.spinup_speed)
    assert app.sources["alpha_plus"].data["speed"] == [seen.alpha_plus] * 2
    assert f"{1e3 * seen.mean_flow:.4f} L/s" in readout_text(app, "mean_flow")
    assert f"{1e3 * seen.pumped_volume:.1f} L" in readout_text(app, "volume")
    assert f"{seen.tau:.1f} s" in readout_text(app, "tau")
    assert f"{seen.margin:.3f}" in readout_text(app, "margin")
    assert (
        "Running" in app.readouts.status.object
        and f"{seen.alpha_plus:.2f}" in app.readouts.status.object
    )
    assert not app.error.visible and not app.stale


def test_a_slider_move_recomputes_everything(app):
    app.sidebar.sliders["h"].value = 6.0
    seen = expected(SEED.replace(h=6.0))
    assert max(app.sources["flow"].data["upper"]) == pytest.approx(
        1e3 * seen.run.flow.max(), rel=1e-12
    )
    np.testing.assert_allclose(app.sources["spinup"].data["speed"], seen.spinup_speed)
    op = seen.operating_point
    assert app.sources["stable"].data == {"omega": [op.omega], "power": [op.power]}
    assert f"{seen.margin:.3f}" in readout_text(app, "margin")
    values = np.array(app.sources["stall"].data["value"])
    assert values[0] / values[1] == pytest.approx(seen.margin, rel=1e-12)


def test_only_what_changed_is_sent(app):
    """The windmill's curve does not depend on h: a head move must not re-send it, nor the
    Mechanisms tab (R, L, A unchanged)."""
    curve = app.sources["curve"].data
    crank = app.mechanisms.sources["crank_links"].data  # (the tab is built when first opened)
    travel = app.sources["piston_table"].data
    app.inputs.h = 4.0
    assert app.sources["curve"].data is curve
    assert app.sources["crank_links"].data is crank
    assert app.sources["piston_table"].data is travel
    app.inputs.L_over_R = 3.0
    assert app.sources["crank_links"].data is not crank


def test_the_closeup_holds_every_sample_of_the_last_revolutions(app):
    run = expected().run
    start, _ = run.revolutions()
    window = run.t >= start[-3]
    np.testing.assert_array_equal(app.sources["closeup"].data["t"], run.t[window])
    np.testing.assert_allclose(app.sources["closeup"].data["flow"], 1e3 * run.flow[window])


def test_a_stalled_run_shares_its_time_axis_and_shows_its_last_turns(app):
    app.inputs.h = 21.0
    run = expected(SEED.replace(h=21.0)).run
    assert run.stalled and app.pump.time_range.end == pytest.approx(run.t_stall)
    for name in ("speed", "flow"):
        assert max(app.sources[name].data["t"]) <= run.t_stall
    closeup = app.sources["closeup"].data["t"]
    start, _ = run.revolutions()
    assert closeup[0] == pytest.approx(run.t[run.t >= start[-3]][0])
    assert closeup[-1] == run.t_stall


def test_no_more_points_than_pixels(app):
    for name in ("speed", "flow", "cycle_mean"):
        assert len(app.sources[name].data["t"]) <= BINS <= WIDTH // 2


@pytest.mark.parametrize(
    "changes, status",
    [
        ({"h": 20.0}, "Stalled"),
        ({"theta_dot0": 0.0}, "Never started"),
        ({"theta_dot0": 1.0}, "Never started"),
    ],
)
def test_status_reads_at_a_glance(app, changes, status):
    app.set_values(**changes)
    assert app.readouts.status.object.startswith(f"**{status}")
    if (
        "h" in changes
    ):  # no steady state past the stall criterion: no alpha lines, no operating point
        assert (
            app.sources["alpha_plus"].data["t"] == [] and app.sources["stable"].data["omega"] == []
        )
        assert not app.pump.speed.items["α₊, Eq. (21)"].visible
        assert not app.pump.operating.items["operating point"].visible
    if status == "Never started":
        assert "–" in readout_text(app, "tau")  # no time constant for a run that never started


@pytest.mark.parametrize("preset", ["A deep well, a heavy rod", "A leak hole lets it start"])
def test_the_operating_points_dots_lie_where_its_drawn_lines_meet(app, preset):
    """The Operating point view: the windmill's curve runs to where its torque is 0 (with a
    torque at rest beyond 2 omega_m: the curve stopped short of the dot), and the dot lies on
    both lines (the load line was the ideal machine's: no chain, pipe or hole)."""
    app.sidebar.preset.value = preset
    s, op = app.sources, app.seen.operating_point
    omega = np.asarray(s["curve"].data["omega"])
    assert omega[-1] >= app.seen.design.runaway_speed > op.omega
    assert s["curve"].data["power"][-1] <= 0.0  # past the runaway: a brake
    for name in ("curve", "load_line"):
        drawn = np.interp(op.omega, omega, s[name].data["power"])
        assert drawn == pytest.approx(op.power, rel=2e-3), name  # on a 211-point line


def test_no_kick_draws_a_time_axis_from_zero(app):
    app.inputs.theta_dot0 = 0.0
    assert (app.pump.time_range.start, app.pump.time_range.end) == (0.0, 600.0)
    assert "no kick" in app.readouts.status.object


def test_a_rejected_value_marks_the_plots_stale_and_the_next_move_redraws(app):
    before = dict(app.sources["speed"].data)
    app.inputs.L_over_R = 1.0
    assert app.error.visible and app.stale
    assert app.error.object.startswith("L/R, rod / crank = 1 cannot be run: ")
    assert "L_over_R = 1.0 is not allowed" in app.error.object and "> 1" in app.error.object
    assert (
        app.pump.results.styles["opacity"] == "0.35"
        and app.readouts.row.styles["opacity"] == "0.35"
    )
    assert app.sources["speed"].data["upper"] is before["upper"]  # the last good plot stays
    app.inputs.L_over_R = 2.0
    assert not app.error.visible and not app.stale and app.pump.results.styles["opacity"] == "1"
    seen = expected(SEED.replace(L=2 * SEED.R))
    assert max(app.sources["speed"].data["upper"]) == pytest.approx(
        seen.run.theta_dot.max(), rel=1e-12
    )


def test_a_run_too_long_for_the_sample_bound_is_refused(app):
    app.set_values(R_dagger=0.5, omega_m=150.0, t_end=3000.0)
    assert app.error.visible and "t_end" in app.error.object and "<=" in app.error.object
    app.set_values(t_end=100.0)
    assert not app.error.visible


def test_an_unexpected_exception_is_shown_logged_and_survived(app, monkeypatch, caplog):
    def broken(*_args, **_kwargs):
        raise RuntimeError("boom")

    monkeypatch.setattr(windpump, "explore", broken)
    with caplog.at_level(logging.ERROR, logger="windpump.app"):
        app.inputs.h = 4.0
    assert app.error.visible and "RuntimeError: boom" in app.error.object
    assert any("update failed" in record.message for record in caplog.records)
    monkeypatch.undo()
    app.inputs.h = 5.0
    assert not app.error.visible and "Running" in app.readouts.status.object


def test_reset_brings_back_everything(app):
    app.set_values(h=12.0, T_m=2.0, t_end=100.0, I0=5.0)
    app.pin()
    app.mechanisms.slider_crank.crank_angle.value = 200.0
    app.mechanisms.links["r2"].value = 4.0
    app.mechanisms.kind.value = app.mechanisms.kind.options[1]
    app.sidebar.reset_button.clicks += 1
    assert app.inputs.design() == SEED and app.inputs.t_end == 600.0
    assert max(app.sources["speed"].data["upper"]) == pytest.approx(expected().run.theta_dot.max())
    assert app.sources["speed_ghost"].data["t"] == []
    assert (
        app.mechanisms.slider_crank.crank_angle.value == 90.0
        and app.mechanisms.links["r2"].value == 3.0
    )
    assert app.mechanisms.kind.value == app.mechanisms.kind.options[0]


# -- the energy readout keeps its sign -----------------------------------------------------------


def test_a_slowing_rotor_gives_power_back_below_zero(app):
    """Kicked at 30 rad/s, above alpha+ = 23.7: the rotor slows and gives energy back."""
    app.set_values(theta_dot0=30.0)
    seen = expected(theta_dot0=30.0)
    budget = windpump.power_budget(seen.run)
    kinetic = float(budget.kinetic_energy[-1])
    assert kinetic < 0
    bars = app.sources["losses"].data
    spin = bars["step"].index("spinning up")
    # The spin-up bar goes up from what is left of W to the water: the rotor gave energy back.
    assert bars["left"][spin] == pytest.approx(float(budget.shaft_work[-1]))
    assert bars["right"][spin] == pytest.approx(float(budget.lift_work[-1]))
    assert "given back" in bars["label"][spin]
    # each bar's share is of the energy that came in, W and what the rotor gave back: the water
    # took all of it, never more (of W alone it was "456 %" for a stalling pump)
    came_in = float(budget.shaft_work[-1]) - kinetic
    shares = [int(re.search(r"(\d+) %", label).group(1)) for label in bars["label"]]
    assert all(0 <= share <= 100 for share in shares), bars["label"]
    assert shares[-1] == round(100 * float(budget.lift_work[-1]) / came_in)  # the water, last
    text = readout_text(app, "energy")
    assert "gained speed" not in text and "given back" in text
    work, back, lift = (int(v.replace(",", "")) for v in re.findall(r"([\d,]+) J", text))
    assert work == pytest.approx(budget.shaft_work[-1], abs=1)  # each within a joule
    assert back == pytest.approx(-kinetic, abs=1) and lift == pytest.approx(
        budget.lift_work[-1], abs=1
    )
    assert work + back == lift  # and the shown terms add up


def shown_balance(text: str) -> tuple[list[int], list[int]]:
    """The shown energy balance's two sides, in whole joules."""
    left, right = text.split(" = ")
    return [
        [int(term.strip().removesuffix(" J").replace(",", "")) for term in side.split(" + ")]
        for side in (left, right)
    ]


def test_the_shown_energy_terms_add_up_to_the_shown_sum_over_random_designs(app):
    """Each term rounded on its own read "22 J + 122 J = 143 J": over random designs, ideal and
    real, running, slowing and stalled, the shown terms add up exactly, and each is the core's
    term within a joule (issue 37)."""
    rng = np.random.default_rng(37)
    for _ in range(40):
        values = dict(
            h=round(rng.uniform(0.5, 25.0), 1),
            T_m=round(rng.uniform(0.2, 3.0), 2),
            theta_dot0=round(rng.uniform(0.0, 30.0), 1),
            t_end=float(rng.choice([10.0, 60.0, 200.0])),
        )
        if rng.random() < 0.5:  # a real machine: its losses are a term of their own
            values.update(eta_t=round(rng.uniform(0.5, 1.0), 2), m_r=round(rng.uniform(0, 20), 1))
            values.update(L_main=float(rng.integers(0, 40)), d_leak_mm=round(rng.uniform(0, 3), 1))
        app.set_values(**{**app.inputs.defaults(), **values})
        value = app.readouts["energy"].object.split('class="value"', 1)[1]
        text = re.sub(r"<[^>]+>", "", value.split(">", 1)[1])
        left, right = shown_balance(text)
        assert sum(left) == sum(right), (values, text)
        totals = app.seen.energy_totals
        kinetic = totals.kinetic + totals.potential
        lost = totals.transmission + totals.friction + totals.leak
        terms = [totals.shaft] + ([-kinetic] if kinetic < 0 else [])
        terms += ([] if app.seen.design.is_ideal else [lost]) + ([kinetic] if kinetic >= 0 else [])
        terms += [totals.water]
        assert len(terms) == len(left) + len(right), (values, text)
        for shown_term, term in zip(left + right, terms, strict=True):
            assert abs(shown_term - term) <= 1.0, (values, text, terms)
        # the Losses view's bars say the same joules, its losses adding up to the readout's
        bars = [
            int(label.split(" J")[0].replace(",", ""))
            for label in app.sources["losses"].data["label"]
        ]
        assert bars[0] == left[0] and bars[-1] == right[-1], (values, text, bars)
        if not app.seen.design.is_ideal:
            assert sum(bars[1:4]) == right[0], (values, text, bars)


# -- presets and pinning -----------------------------------------------------------------------------


@pytest.mark.parametrize("name", list(PRESETS))
def test_every_preset_runs_and_says_what_to_look_at(app, name):
    values, sentence = PRESETS[name]
    app.sidebar.preset.value = name
    assert app.inputs.values() == {**PumpInputs().defaults(), **values}
    assert sentence in app.sidebar.preset_note.object and app.sidebar.preset_note.visible
    assert not app.error.visible


def test_presets_show_what_they_promise(app):
    app.sidebar.preset.value = "A stalled pump"
    assert app.readouts.status.object.startswith("**Stalled")
    app.sidebar.preset.value = "Kicked below α₋"
    assert app.readouts.status.object.startswith("**Never started")
    app.sidebar.preset.value = "Near the stall boundary"
    assert 1.0 < expected(app.inputs.design()).margin < 1.1


def test_a_pinned_run_stays_as_a_ghost_until_cleared(app):
    speed = dict(app.sources["speed"].data)
    app.pin()
    app.inputs.h = 6.0
    np.testing.assert_array_equal(app.sources["speed_ghost"].data["upper"], speed["upper"])
    assert app.pump.speed.items["pinned run"].visible and not app.sidebar.clear_button.disabled
    app.clear_pinned()
    assert app.sources["speed_ghost"].data["t"] == [] and app.sources["flow_ghost"].data["t"] == []
    assert not app.pump.speed.items["pinned run"].visible


# -- state in the link ----------------------------------------------------------------------------


def test_a_link_reproduces_the_design_and_the_run():
    app = Explorer(query={"h": [b"5"], "T_m": [b"0.8"], "theta_dot0": [b"4.5"]})
    assert app.inputs.design() == SEED.replace(h=5.0, T_m=0.8)
    seen = expected(SEED.replace(h=5.0, T_m=0.8), theta_dot0=4.5)
    assert f"{1e3 * seen.mean_flow:.4f} L/s" in readout_text(app, "mean_flow")
    assert not app.notices.visible
    again = Explorer(query={k: [v.encode()] for k, v in _query_pairs(app.inputs.query())})
    assert again.inputs.values() == app.inputs.values()


@pytest.mark.parametrize("name", list(PRESETS))
def test_a_link_to_a_presets_design_says_which_preset_it_is(name):
    from urllib.parse import parse_qs

    chosen = Explorer()
    chosen.sidebar.preset.value = name
    query = chosen.inputs.query() or "h=3"  # the paper's example: its one value, given as is
    app = Explorer(query={k: [v.encode() for v in vs] for k, vs in parse_qs(query).items()})
    assert app.sidebar.preset.value == name
    assert PRESETS[name][1] in app.sidebar.preset_note.object and app.sidebar.preset_note.visible
    assert app.inputs.values() == chosen.inputs.values()


def test_a_link_to_a_design_of_its_own_says_it_is_the_links():
    app = Explorer(query={"h": [b"5"], "T_m": [b"0.8"]})
    assert app.sidebar.preset.value == PRESET_PROMPT
    assert app.sidebar.preset_note.object == "Your design, from the link."
    assert app.sidebar.preset_note.visible
    plain = Explorer(query={"tab": [b"wind"], "foo": [b"1"]})  # no design: the prompt alone
    assert plain.sidebar.preset.value == PRESET_PROMPT and not plain.sidebar.preset_note.visible


def _query_pairs(query: str):
    from urllib.parse import parse_qsl

    return parse_qsl(query)


@pytest.mark.parametrize(
    "key, raw, words",
    [
        ("h", b"banana", "Head h [m] (h) = “banana” ignored: it must be a number from 0 to 300."),
        ("h", b"1e9", "from 0 to 300"),
        ("L_over_R", b"nan", "L/R, rod / crank (L_over_R) = “nan” ignored"),
        ("T_m", b"-1", "from 0.05 to 5"),
        ("bogus", b"1", "“bogus” is not a parameter of this page"),
    ],
)
def test_a_tampered_link_is_ignored_with_a_notice(key, raw, words):
    app = Explorer(query={key: [raw], "h": [b"4"]} if key != "h" else {key: [raw]})
    assert app.notices.visible and words in shown(app.notices)
    assert not app.error.visible and "Running" in app.readouts.status.object
    if key != "h":
        assert app.inputs.h == 4.0  # the valid values in the same link still apply


# -- files ----------------------------------------------------------------------------------------


def test_lab_data_sets_the_windmill_curve(app):
    omega = np.linspace(5, 95, 10)
    torque = 0.8 * (omega / 45) * (2 - omega / 45)
    app.sidebar.lab.upload.value = "".join(
        f"{w},{q}\n" for w, q in zip(omega, torque, strict=True)
    ).encode()
    assert app.inputs.T_m == pytest.approx(0.8) and app.inputs.omega_m == pytest.approx(45.0)
    np.testing.assert_allclose(app.sources["data"].data["power"], omega * torque)
    assert "Tₘ = 0.800 N·m" in app.sidebar.lab.note.object
    assert app.pump.operating.items["lab data"].visible


def test_served_a_lab_file_is_read_and_fitted_off_the_loop_and_the_newest_wins(app, monkeypatch):
    """Served, the file is read and fitted in a thread (``off_the_loop``): nothing changes until
    its fit comes back, and a fit that comes back after a newer file's is not applied."""
    from windpump_app import lab

    held: list = []  # (work, then) as the thread pool would run them
    monkeypatch.setattr(lab, "off_the_loop", lambda work, then: held.append((work, then)))

    def curve(T_m: float, omega_m: float) -> bytes:
        omega = np.linspace(5, 95, 10)
        torque = T_m * (omega / omega_m) * (2 - omega / omega_m)
        return "".join(f"{w},{q}\n" for w, q in zip(omega, torque, strict=True)).encode()

    before = (app.inputs.T_m, app.inputs.omega_m)
    app.sidebar.lab.upload.value = curve(0.8, 45.0)
    app.sidebar.lab.upload.value = curve(0.7, 50.0)
    assert len(held) == 2 and (app.inputs.T_m, app.inputs.omega_m) == before
    for work, then in reversed(held):  # the newer file's fit first, the older one's late
        then(work())
    assert app.inputs.T_m == pytest.approx(0.7) and app.inputs.omega_m == pytest.approx(50.0)
    assert "Tₘ = 0.700 N·m" in app.sidebar.lab.note.object


def test_lab_data_in_a_european_spreadsheet_is_read(app):
    text = "Drehzahl;Moment\n" + "".join(
        f"{w:.1f};{0.5 * (w / 40) * (2 - w / 40):.6f}\n".replace(".", ",") for w in range(5, 80, 5)
    )
    app.load_lab_data(text.encode())
    assert app.inputs.T_m == pytest.approx(0.5, rel=1e-4) and app.inputs.omega_m == pytest.approx(
        40.0, rel=1e-4
    )


@pytest.mark.parametrize(
    "content, words",
    [
        (b"", "The file is empty"),
        (b"1,2\n2,3\nabc,4\n", "Line 3, column 1: 'abc' is not a number"),
        (b"1,2,3\n2,3,4\n", "Line 1, column 3: 3 columns where the file needs two columns"),
        (b"x" * 1_000_001, "at most 1,000,000 are read"),
        (b"torque,speed\n0.2,10\n0.6,50\n0.2,90\n", "the header names torque first"),
        (b"speed,torque\n1,1\n2,2\n3,3\n", "Could not use that file"),
    ],
)
def test_lab_data_that_cannot_be_used_is_explained_and_changes_nothing(app, content, words):
    before = app.inputs.values()
    app.load_lab_data(content)
    assert app.sidebar.lab.message.visible and words in app.sidebar.lab.message.object
    assert "Nothing was changed" in app.sidebar.lab.message.object
    assert app.inputs.values() == before


def test_a_file_the_page_refused_for_its_size_is_explained_and_changes_nothing(app):
    """The page stops a file over the limit before sending it and reports its size."""
    before = app.inputs.values()
    app.sidebar.refused_upload.value = "52428800\t1700000000000\tbig.csv"
    assert (
        app.sidebar.lab.message.visible and "Nothing was changed" in app.sidebar.lab.message.object
    )
    assert (
        "The file has 52,428,800 bytes; at most 1,000,000 are read"
        in app.sidebar.lab.message.object
    )
    assert app.inputs.values() == before
    app.sidebar.lab.message.visible = False
    for tampered in ("abc", "999\t1\tsmall.csv", ""):  # not a refusal the page would send
        app.sidebar.refused_upload.value = tampered
        assert not app.sidebar.lab.message.visible


def test_a_poor_fit_outside_the_sliders_is_explained_and_not_offered(app):
    """Swapped columns: the fit (Tₘ ≈ 59 N·m, ωₘ ≈ 0.4 rad/s) lies outside the sliders' ranges."""
    omega = np.linspace(5, 95, 10)
    torque = 0.6 * (omega / 50) * (2 - omega / 50)
    swapped = "".join(f"{q},{w}\n" for w, q in zip(omega, torque, strict=True)).encode()
    fit = windpump.fit_torque_curve(torque, omega)
    assert fit.poor and not 0.05 <= fit.T_m <= 5.0 and not 5.0 <= fit.omega_m <= 150.0
    app.load_lab_data(swapped)
    message = app.sidebar.lab.message.object
    assert app.sidebar.lab.message.visible and "A poor fit" in message
    assert f"Peak torque Tₘ [N·m] = {fit.T_m:.3g} is outside 0.05–5" in message
    assert f"Windmill peak speed ωₘ [rad/s] = {fit.omega_m:.3g} is outside 5–150" in message
    assert "cannot be applied" in message and "Nothing was changed" in message
    assert not app.sidebar.lab.apply_fit.visible  # only what can be applied is offered
    assert app.inputs.T_m == SEED.T_m and app.inputs.omega_m == SEED.omega_m


def test_a_poor_fit_inside_the_sliders_is_applied_only_on_request(app):
    omega = np.linspace(5, 95, 10)
    torque = 0.6 * (omega / 50) * (2 - omega / 50) + 0.15 * np.array([1, -1] * 5)  # ±25 % of Tₘ
    fit = windpump.fit_torque_curve(omega, torque)
    assert fit.poor and 0.05 <= fit.T_m <= 5.0 and 5.0 <= fit.omega_m <= 150.0
    app.load_lab_data("".join(f"{w},{q}\n" for w, q in zip(omega, torque, strict=True)).encode())
    assert app.sidebar.lab.message.visible and "A poor fit" in app.sidebar.lab.message.object
    assert "cannot be applied" not in app.sidebar.lab.message.object
    assert app.sidebar.lab.apply_fit.visible and app.inputs.T_m == SEED.T_m
    app.sidebar.lab.apply_fit.clicks += 1
    assert app.inputs.T_m == pytest.approx(fit.T_m) and app.inputs.omega_m == pytest.approx(
        fit.omega_m
    )
    assert app.sidebar.lab.note.visible and not app.sidebar.lab.apply_fit.visible


def test_an_empty_lab_file_is_explained(app):
    """Panel reports a chosen 0-byte file as its name with no content (value stays None)."""
    before = app.inputs.values()
    app.sidebar.lab.upload.filename = "empty.csv"
    assert app.sidebar.lab.message.visible and "The file is empty" in app.sidebar.lab.message.object
    assert app.inputs.values() == before


def revealed(app) -> str:
    """The CSS class of what the page was last told to scroll into view."""
    return app.sidebar.reveal.value.split("\t")[0]


def test_every_lab_upload_outcome_is_scrolled_into_view(app):
    """At 1280×720 the messages under the upload lie below the sidebar's fold."""
    omega = np.linspace(5, 95, 10)
    good = 0.8 * (omega / 45) * (2 - omega / 45)
    rows = "".join(f"{w},{q}\n" for w, q in zip(omega, good, strict=True))
    outcomes = []
    for content in (rows.encode(), b"10,0.216x\n", (rows + "5,9\n").encode(), rows.encode()):
        app.sidebar.lab.upload.param.update(
            value=content, filename="lab.csv"
        )  # as the page sends it
        shown = [pane for pane in (app.sidebar.lab.message, app.sidebar.lab.note) if pane.visible]
        assert revealed(app) in shown[0].css_classes
        outcomes.append(app.sidebar.reveal.value)
    assert len(set(outcomes)) == 4  # the same outcome twice is scrolled to twice
    app.sidebar.refused_upload.value = "52428800\t1700000000000\tlab\tbig.csv"
    assert revealed(app) in app.sidebar.lab.message.css_classes and app.sidebar.lab.message.visible


def test_download_is_the_run_in_litres_with_its_design(app):
    text = app._csv().getvalue()
    assert text == expected().run.to_csv(litres=True)
    assert "# h = 3 m" in text and "flow [L/s]" in text
    assert (
        app.sidebar.download.filename
        == design_filename(SEED)
        == ("windpump_h3m_LR3.75_Rdagger4_Tm0.6_omegam50.csv")
    )


# -- the machine's frames -------------------------------------------------------------------------


def test_the_machine_gets_the_runs_frames_once_per_run(app):
    run = expected().run
    frames = app.sources["frames"].data
    assert frames["t"][0] == 0 and frames["t"][-1] == pytest.approx(600.0)
    np.testing.assert_allclose(frames["theta"], np.interp(frames["t"], run.t, run.theta), rtol=1e-6)
    litres = 1e3 * np.interp(frames["t"], run.t, run.volume)  # the label's, in L
    np.testing.assert_allclose(frames["litres"], litres, rtol=1e-6, atol=1e-3)
    table = app.sources["piston_table"].data
    np.testing.assert_allclose(table["x"], windpump.piston_position(table["theta"], SEED.R, SEED.L))
    assert app.pump.machine.scrubber.end == pytest.approx(600.0)
    app.inputs.t_end = 100.0
    assert app.sources["frames"].data["t"][-1] == pytest.approx(100.0)


def test_the_machine_redraws_when_the_cylinders_change(app):
    """The fixed drawing (one cylinder head each) and the crank table follow a new count."""
    app.show_views()
    app.set_values(cylinders=3)
    assert app.sources["machine_geometry"].data["cylinders"] == [3.0]
    assert {f"pin_x{k}" for k in range(3)} <= set(app.sources["piston_table"].data)


def test_band_keeps_each_bins_extremes():
    rng = np.random.default_rng(3)
    x = np.sort(rng.uniform(0, 100, 20_000))
    y = rng.normal(size=x.size)
    mid, lower, upper = band(x, y, 50)
    assert len(mid) <= 50
    assert lower.min() == y.min() and upper.max() == y.max()
    edges = np.linspace(x[0], x[-1], 51)
    for k in range(50):
        inside = (x >= edges[k]) & (x < edges[k + 1])
        assert lower[k] == y[inside].min() and upper[k] == y[inside].max()
        assert edges[k] <= mid[k] <= edges[k + 1]


# -- presentation and theme ---------------------------------------------------------------------


def test_presentation_mode_enlarges_text_and_lines(app):
    title = app.pump.speed.figure.title.text_font_size
    widths = [
        r.glyph.line_width
        for r in app.pump.speed.figure.renderers
        if hasattr(r.glyph, "line_width")
    ]
    app.sidebar.present_toggle.value = True
    assert app.presentation
    assert float(app.pump.speed.figure.title.text_font_size[:-2]) > float(title[:-2])
    larger = [
        r.glyph.line_width
        for r in app.pump.speed.figure.renderers
        if hasattr(r.glyph, "line_width")
    ]
    assert all(b > a for a, b in zip(widths, larger, strict=True))
    app.sidebar.present_toggle.value = False
    assert app.pump.speed.figure.title.text_font_size == title


@pytest.mark.parametrize("cylinders", [1, 6])
def test_the_machine_drawing_lies_inside_its_figure_at_equal_scales(cylinders):
    """Every fixed part (the tank's top included) inside the ranges, whose aspect is the figure's."""
    from windpump_app.machine import ASPECT

    app = Explorer(query={"cylinders": [str(cylinders).encode()]})
    app.show_views()
    fig, data = app.pump.machine.figure, app.sources["machine_static"].data
    xs, ys = np.concatenate(data["xs"]), np.concatenate(data["ys"])
    assert fig.x_range.start < xs.min() and xs.max() < fig.x_range.end
    assert fig.y_range.start < ys.min() and ys.max() < fig.y_range.end
    width, height = fig.x_range.end - fig.x_range.start, fig.y_range.end - fig.y_range.start
    assert (
        width / height == pytest.approx(ASPECT) == pytest.approx(fig.width / fig.height, rel=0.01)
    )
    assert fig.min_border == 0 and not fig.axis[0].visible  # the frame is the whole figure


def test_a_page_built_while_the_solver_compiles_runs_its_link_on_start():
    """start=False (a first start's pages): controls and a word on the compile, no run; start()
    runs the link's design and names what it ignored, as a page built ready does."""
    from windpump_app.server import sessions as serving

    query = {"h": [b"5"], "foo": [b"1"]}
    serving.SOLVER_READY.clear()  # a first start's compile under way
    try:
        waiting = Explorer(query=query, start=False)
    finally:
        serving.SOLVER_READY.set()
    assert waiting.seen is None
    assert "Compiling the solver (once after an install)" in waiting.readouts.status.object
    assert readout_text(waiting, "mean_flow") == ""
    waiting.inputs.T_m = 0.8  # a move before the first run is in it
    waiting.start()
    seen = expected(SEED.replace(h=5.0, T_m=0.8))
    assert f"{1e3 * seen.mean_flow:.4f} L/s" in readout_text(waiting, "mean_flow")
    assert "foo" in waiting.notices.object and waiting.notices.visible
    waiting.inputs.h = 6.0  # and every move after it runs again
    assert f"{1e3 * expected(SEED.replace(h=6.0, T_m=0.8)).mean_flow:.4f} L/s" in readout_text(
        waiting, "mean_flow"
    )


def canvas_text_sizes(app) -> list[float]:
    """Every text size [px] the page's figures draw on their canvas, the tabs' included."""
    from bokeh.models import Legend, Text

    sizes = []
    for fig in app.figures():
        if fig.title.text:
            sizes.append(fig.title.text_font_size)
        for axis in (*fig.xaxis, *fig.yaxis):
            if axis.visible:
                sizes += [axis.axis_label_text_font_size, axis.major_label_text_font_size]
        sizes += [legend.label_text_font_size for legend in fig.select(type=Legend)]
        sizes += [r.glyph.text_font_size for r in fig.renderers if isinstance(r.glyph, Text)]
    return [float(size[:-2]) for size in sizes]


def test_presentation_mode_enlarges_every_canvas_text_and_back(app):
    """Titles, axes, legends and the machine's label, in every tab opened, not only titles."""
    assert app.mechanisms.figures()  # the Mechanisms tab, as if opened
    before = canvas_text_sizes(app)
    app.sidebar.present_toggle.value = True
    after = canvas_text_sizes(app)
    assert len(after) == len(before) > 20
    assert all(b >= 1.2 * a for a, b in zip(before, after, strict=True)), (before, after)
    app.sidebar.present_toggle.value = False
    assert canvas_text_sizes(app) == before


def test_presentation_mode_gives_the_views_below_the_first_screen_more_height(app):
    """Their text grows, so their plots would shrink; the crank speed and the machine keep the
    first screen's layout."""
    heights = {view: view.figure.height for view in app.pump.views}
    app.sidebar.present_toggle.value = True
    grown = {view for view in app.pump.views if view.figure.height > 1.2 * heights[view]}
    assert grown == set(app.pump.views) - {app.pump.speed, app.pump.machine}
    app.sidebar.present_toggle.value = False
    assert {view: view.figure.height for view in app.pump.views} == heights


def test_the_dark_theme_comes_from_the_link():
    assert Explorer(query={"theme": [b"dark"]}).template().theme.__name__.startswith("Dark")
    assert not Explorer().template().theme.__name__.startswith("Dark")


@pytest.mark.parametrize(
    "query, words, runs",
    [
        (
            {"T_0": [b"0.9"]},  # above the default T_m = 0.6
            "Torque at rest T₀ [N·m] (T_0) = “0.9” ignored: T₀ = 0.9 N·m is not allowed: "
            "T₀ must be < Tₘ = 0.6 N·m",  # the page's symbols, as in its labels
            SEED,
        ),
        (
            {"L_over_R": [b"1"], "h": [b"5"]},
            "L/R, rod / crank (L_over_R) = “1” ignored: L_over_R = 1.0 is not allowed",
            SEED.replace(h=5.0),
        ),
        (
            {"T_0": [b"0.5"], "T_m": [b"0.4"]},
            "(T_0) = “0.5” ignored: T₀ = 0.5 N·m is not allowed: T₀ must be < Tₘ = 0.4 N·m",
            SEED.replace(T_m=0.4),
        ),
    ],
)
def test_a_link_value_the_core_refuses_is_named_and_the_page_runs_without_it(query, words, runs):
    app = Explorer(query=query)
    assert app.notices.visible and words in shown(app.notices)
    assert not app.error.visible and not app.stale and app.pump.results.styles["opacity"] == "1"
    assert app.inputs.design() == runs
    assert max(app.sources["speed"].data["upper"]) == pytest.approx(
        expected(runs).run.theta_dot.max(), rel=1e-12
    )
    assert "T_0" not in app.link_query() and "L_over_R" not in app.link_query()


def test_a_session_built_without_its_html_page_asks_no_cdn_for_stylesheets():
    """Bokeh builds a second session when a page connects after its own expired (a class loading
    at once); Panel rewrites CDN stylesheet URLs only while rendering the HTML, which that session
    never gets. The app names this server's address before building anything."""
    from bokeh.document import Document
    from bokeh.models import ImportedStyleSheet
    from panel.io.state import set_curdoc

    from windpump_app.server.sessions import stylesheets_from_this_server

    document = Document()
    with set_curdoc(document):
        stylesheets_from_this_server(document)
        Explorer().template().server_doc(document)
    urls = [m.url for m in document.models if isinstance(m, ImportedStyleSheet)]
    assert urls and all(url.startswith("static/extensions/panel/") for url in urls), urls


def test_a_served_page_gets_its_readouts_first_and_its_views_when_loaded():
    """What `panel serve` builds for a page: controls and readouts (quick, for a class opening it at
    once), then on load the views, drawn from the latest run, in presentation mode if it is on."""
    app = Explorer(defer_views=True, query={"h": [b"5"]})
    seen = expected(SEED.replace(h=5.0))
    assert f"{1e3 * seen.mean_flow:.4f} L/s" in readout_text(app, "mean_flow")
    assert app.pump.views == [] and "speed" not in app.sources
    app.inputs.T_m = 0.8  # moves before the views exist still reach them
    app.sidebar.present_toggle.value = True
    app.show_views()
    seen = expected(SEED.replace(h=5.0, T_m=0.8))
    assert max(app.sources["speed"].data["upper"]) == pytest.approx(seen.run.theta_dot.max())
    assert float(app.pump.speed.figure.title.text_font_size[:-2]) > 16
    assert (
        len(app.pump.results.objects) == len(app.pump.views) + 1
    )  # and the card about the machine
    app.show_views()  # once only
    assert len(app.pump.results.objects) == len(app.pump.views) + 1
    about = app.pump.results.objects[-1]  # its text is made when it first opens
    assert about.collapsed and about.objects == []
    about.collapsed = False
    assert "stall criterion" in about.objects[0].object


def test_pinning_before_the_views_exist_builds_them():
    app = Explorer(defer_views=True)
    app.pin()
    assert app.pump.views and not app.sidebar.clear_button.disabled
    app.clear_pinned()
    assert app.sidebar.clear_button.disabled


@pytest.mark.parametrize(
    "raw, presentation, notice",
    [(b"true", True, False), (b"false", False, False), (b"maybe", False, True)],
)
def test_presentation_mode_comes_from_the_link(raw, presentation, notice):
    app = Explorer(query={"presentation": [raw]})
    assert app.presentation is presentation and app.sidebar.present_toggle.value is presentation
    assert (float(app.pump.speed.figure.title.text_font_size[:-2]) > 16) is presentation
    assert app.notices.visible is notice
    if notice:
        assert "Presentation mode (presentation) = “maybe” ignored" in app.notices.object


@pytest.mark.parametrize(
    "raw, embed, notice", [(b"true", True, False), (b"false", False, False), (b"1", False, True)]
)
def test_an_embedded_page_comes_from_the_link_and_stays_in_it(raw, embed, notice):
    """``?embed=true``: the page for a course page's iframe, without the template's header; kept
    in the link through a move and Reset, as presentation mode is; any other value than true or
    false is ignored with the notice the other flags get (issue 40)."""
    app = Explorer(query={"embed": [raw], "h": [b"5"]})
    assert app.embed is embed and app.link_query() == ("h=5&embed=true" if embed else "h=5")
    assert app.notices.visible is notice
    if notice:
        assert "Embedded page (embed) = “1” ignored: true or false." in app.notices.object
    template = app.template()
    assert (EMBED_CSS in template.config.raw_css) is embed
    assert (len(template.header) == 0) is embed  # the paper's citation: the header's, not built
    app.set_values(T_m=0.8)
    app.reset()
    assert app.link_query() == ("embed=true" if embed else "")


# -- several cylinders, double-acting, torque at rest ---------------------------------------------


def test_cylinders_double_acting_and_torque_at_rest_reach_every_view(app):
    app.show_views()
    app.set_values(cylinders=2.0, double_acting=True, T_0=0.3, h=1.0)
    design = SEED.replace(cylinders=2, double_acting=True, T_0=0.3, h=1.0)
    assert app.inputs.design() == design
    seen = expected(design)
    assert f"{1e3 * seen.mean_flow:.4f} L/s" in readout_text(app, "mean_flow")
    assert f"{seen.margin:.3f}" in readout_text(app, "margin")
    faces = app.sources["closeup_faces"].data
    assert len(faces["ys"]) == 4  # both faces of both cylinders deliver
    total = np.sum(faces["ys"], axis=0)
    flow = np.asarray(app.sources["closeup"].data["flow"])
    np.testing.assert_allclose(total, flow, rtol=1e-9, atol=1e-9 * flow.max())
    peak = windpump.peak_load_torque(design)
    assert f"peak load {peak:.2f} N·m" in re.sub(r"<[^>]+>", "", app.readouts.status.object)


def test_a_start_from_rest_needs_torque_at_rest(app):
    app.set_values(theta_dot0=0.0)
    assert (
        "Never started" in app.readouts.status.object
        and "needs a kick" in app.readouts.status.object
    )
    app.set_values(cylinders=2.0, T_0=0.4)
    assert (
        "Running" in app.readouts.status.object
        and "starts on its own" in app.readouts.status.object
    )
    seen = expected(SEED.replace(cylinders=2, T_0=0.4), theta_dot0=0.0)
    assert f"{1e3 * seen.pumped_volume:.1f} L" in readout_text(app, "volume")


def test_torque_at_rest_above_the_peak_is_refused_and_named(app):
    app.set_values(T_0=0.8)  # above T_m = 0.6
    assert app.error.visible and "T₀ = 0.8 N·m" in app.error.object and "< Tₘ" in app.error.object
    assert "T_0" not in app.error.object and " N m" not in app.error.object  # the page's symbols
    app.set_values(T_0=0.2)
    assert not app.error.visible


def test_the_new_inputs_travel_in_the_link():
    app = Explorer(query={"cylinders": [b"3"], "double_acting": [b"true"], "T_0": [b"0.25"]})
    assert app.inputs.design() == SEED.replace(cylinders=3, double_acting=True, T_0=0.25)
    query = dict(_query_pairs(app.inputs.query()))
    assert query["double_acting"] == "true" and query["cylinders"] == "3"
    again = Explorer(query={k: [v.encode()] for k, v in query.items()})
    assert again.inputs.values() == app.inputs.values()
    bad = Explorer(query={"double_acting": [b"maybe"], "cylinders": [b"9"]})
    assert "it must be true or false" in bad.notices.object
    assert "from 1 to 6" in bad.notices.object and bad.inputs.design() == SEED


def test_no_figure_asks_for_webgl(app):
    """app/server/patches/panel_bundle_resources.py leaves Bokeh's WebGL bundle out of the page: safe while no figure, on any
    tab, asks for WebGL."""
    from bokeh.models import Plot

    root = app.__panel__().get_root()
    for tab in (1, 2, 3):
        app.tabs.active = tab  # each tab builds its figures when first opened
    plots = list(root.select({"type": Plot}))
    assert len(plots) > 10
    assert [p for p in plots if p.output_backend == "webgl"] == []


# -- the link as it is written --------------------------------------------------------------------

SLIDERS = [name for name in PumpInputs().names() if name in FORMATS]  # not switches, choices


def _grid(name: str, index: int) -> float:
    """The ``index``-th value of a slider's grid, in decimal arithmetic (no float steps added)."""
    parameter = PumpInputs.param[name]
    low, high = (Decimal(repr(b)) for b in parameter.bounds)
    step = Decimal(repr(parameter.step))
    return float(min(low + index * step, high))


@settings(deadline=None, max_examples=200, suppress_health_check=[HealthCheck.too_slow])
@given(
    st.dictionaries(
        st.sampled_from(SLIDERS), st.integers(min_value=0, max_value=10_000), max_size=6
    ),
    st.booleans(),
)
def test_any_value_on_a_sliders_grid_travels_through_the_link_exactly(indices, double):
    values = {name: _grid(name, index) for name, index in indices.items()}
    inputs = PumpInputs(**values, double_acting=double)
    query = inputs.query()
    pairs = dict(_query_pairs(query))
    for name, text in pairs.items():
        if name == "double_acting":
            assert text == "true"
            continue
        step_decimals = -Decimal(repr(PumpInputs.param[name].step)).normalize().as_tuple().exponent
        assert len(text.partition(".")[2]) <= max(step_decimals, 0), (name, text)
        assert getattr(inputs, name) != PumpInputs.param[name].default  # defaults never written
    written = {n for n, v in inputs.values().items() if v != PumpInputs.param[n].default}
    assert set(pairs) == written
    read, notices = PumpInputs().parse_query({k: [v.encode()] for k, v in pairs.items()})
    assert notices == []
    assert {**PumpInputs().values(), **read} == inputs.values()


def test_the_defaults_make_an_empty_link_and_reset_clears_it(app):
    assert app.inputs.query() == "" and app.link_query() == ""
    app.set_values(h=6.0, cylinders=2.0, T_0=0.25, double_acting=True)
    assert app.link_query() == "h=6&cylinders=2&T_0=0.25&double_acting=true"
    app.sidebar.present_toggle.value = True
    app.sidebar.reset_button.clicks += 1
    assert app.link_query() == "presentation=true"  # a mode, not an input: Reset keeps it
    assert Explorer(query={"theme": [b"dark"]}).link_query() == "theme=dark"


def test_a_slider_moved_in_the_browser_is_linked_as_it_shows(app):
    """The browser adds a slider's step in floating point; the page keeps the value it sent (a
    value sent back would move a slider still being moved) and links what the slider shows."""
    app.sidebar.sliders["h"]._process_events({"value": 3.0999999999999996})  # an ArrowRight press
    assert app.link_query() == "h=3.1"
    assert readout_text(app, "mean_flow") == readout_text(
        Explorer(query={"h": [b"3.1"]}), "mean_flow"
    )
    app.sidebar.sliders["T_m"]._process_events({"value": 0.7000000000000001})
    assert app.link_query() == "h=3.1&T_m=0.7"
    app.sidebar.sliders["h"]._process_events({"value": 3.0000000000000004})  # and back
    app.sidebar.sliders["T_m"]._process_events({"value": 0.6000000000000001})
    assert app.link_query() == ""


class FakeLocation(param.Parameterized):
    """What the explorer uses of pn.state.location."""

    search = param.String("")


def test_the_page_writes_its_link_and_drops_what_it_ignored():
    query = {"foo": [b"1"], "h": [b"3.0999999999999996"], "T_m": [b"0.8"]}
    app, location = Explorer(query=query), FakeLocation(search="?foo=1&h=3.0999999999999996")
    assert app.inputs.h == 3.1 and "“foo” is not a parameter" in app.notices.object
    app.follow_in_link(location)
    assert location.search == "?h=3.1&T_m=0.8"
    location.search = "?foo=1&h=3.0999999999999996"  # the browser reports the address it opened
    assert location.search == "?h=3.1&T_m=0.8"
    app.inputs.h = 4.0
    assert location.search == "?h=4&T_m=0.8"
    app.sidebar.present_toggle.value = True
    assert location.search == "?h=4&T_m=0.8&presentation=true"
    app.sidebar.present_toggle.value = False
    app.reset()
    assert location.search == ""
    assert "“foo” is not a parameter" in app.notices.object  # the notice stays


@pytest.mark.parametrize("raw", [b"2.5", b"4.5", b"2.0000001"])
def test_a_count_that_is_not_whole_is_refused_and_the_run_follows_the_slider(raw):
    app = Explorer(query={"cylinders": [raw], "h": [b"2"]})
    text = raw.decode()
    assert (
        f"Cylinders n (phase lag 2π/n) (cylinders) = “{text}” ignored: it must be a whole "
        "number from 1 to 6." in app.notices.object
    )
    assert app.sidebar.sliders["cylinders"].value == app.inputs.cylinders == 1
    assert app.inputs.design() == SEED.replace(h=2.0)  # the slider's count is the run's
    again = Explorer(query={"cylinders": [b"3"]})
    assert again.sidebar.sliders["cylinders"].value == 3 and again.inputs.design().cylinders == 3


def test_a_key_given_twice_says_which_value_is_used():
    app = Explorer(query={"h": [b"5", b"7"]})
    assert app.inputs.h == 7.0
    assert "“h” is given 2 times (5, 7): the last, “7”, is used." in app.notices.object


def test_a_value_off_its_sliders_step_is_taken_exactly_and_float_noise_is_dropped():
    """A hand-typed value off the slider's grid is the value asked for (the link keeps it as
    typed); float noise on the grid is the slider's value, with no word."""
    app = Explorer(query={"h": [b"3.14159"], "T_m": [b"0.7000000000000001"]})
    assert app.inputs.h == 3.14159 and app.inputs.T_m == 0.7
    assert not app.notices.visible
    assert app.link_query() == "h=3.14159&T_m=0.7"
    old = Explorer(query={"theta0": [repr(math.pi / 2).encode()], "I0": [b"%r" % SEED.I0]})
    assert not old.notices.visible and old.inputs.values() == PumpInputs().values()


TORQUE_CSV = Path(__file__).parents[2] / "docs" / "examples" / "torque.csv"


def test_a_fitted_design_travels_through_the_link_to_the_bit():
    """A lab fit's Tₘ and ωₘ are off their sliders' grids: the link carries them in full, and
    the page it opens holds the same design and shows the same readouts."""
    app = Explorer()
    app.load_lab_data(TORQUE_CSV.read_bytes())
    assert (round(app.inputs.T_m, 5), round(app.inputs.omega_m, 2)) == (0.58199, 50.14)
    pairs = dict(_query_pairs(app.link_query()))
    assert float(pairs["T_m"]) == app.inputs.T_m and float(pairs["omega_m"]) == app.inputs.omega_m
    again = Explorer(query={key: [value.encode()] for key, value in pairs.items()})
    assert again.inputs.design() == app.inputs.design()
    assert not again.notices.visible
    for name in app.readouts.readouts:
        assert readout_text(again, name) == readout_text(app, name), name
    assert again.link_query() == app.link_query()


def test_the_preset_sentence_goes_when_a_slider_leaves_the_preset():
    app = Explorer()
    app.sidebar.preset.value = "The paper's example"
    assert "spins up over τ ≈ 79 s" in shown(app.sidebar.preset_note)
    app.inputs.h = 30.0
    assert "Stalled" in shown(app.readouts.status)
    assert not app.sidebar.preset_note.visible
    assert app.sidebar.preset.value == PRESET_PROMPT
    app.sidebar.preset.value = "A stalled pump"  # a preset chosen again says its sentence
    assert app.sidebar.preset_note.visible and "At h = 21 m" in shown(app.sidebar.preset_note)
    linked = Explorer(query={"h": [b"7"]})
    assert shown(linked.sidebar.preset_note) == FROM_THE_LINK
    linked.inputs.T_m = 0.8  # no longer the link's design
    assert not linked.sidebar.preset_note.visible


def test_an_unknown_theme_is_named_in_a_notice():
    app = Explorer(query={"theme": [b"purple"], "h": [b"5"]})
    assert not app.dark and app.notices.visible
    assert "Theme (theme) = “purple” ignored: light or dark." in shown(app.notices)
    assert app.link_query() == "h=5"
    marked = Explorer(query={"theme": [b"<b>x</b>"]})
    assert "Theme (theme) = “<b>x</b>” ignored" in shown(marked.notices)  # shown as typed
    for fine in (b"dark", b"light"):
        assert not Explorer(query={"theme": [fine]}).notices.visible


def test_notices_are_bounded_however_long_the_link():
    name = "x" * 30_000
    app = Explorer(query={name: [b"1"], "h": [b"y" * 30_000]})
    assert len(app.notices.object) < 600
    assert "“" + "x" * 39 + "…” is not a parameter" in app.notices.object
    many = Explorer(query={f"k{i}": [b"1"] for i in range(1000)})
    assert many.notices.object.count("\n- ") == 6 and "… and 995 more ignored." in (
        many.notices.object
    )
    assert len(many.notices.object) < 600
    huge = Explorer(query={"h": [b"5"], "pad": [b"z" * 100_000]})
    assert "The link was too long (98 KB; at most 64 KB): its parameters were ignored." in (
        huge.notices.object
    )
    assert (
        huge.inputs.values() == PumpInputs().values() and "Running" in huge.readouts.status.object
    )


def test_ragged_columns_are_compared_column_by_column():
    """Lines of several lengths, the same xs and new ys (the machine's tank lifted by a rising
    main): not the same data, so a refill sends it (the first ragged column alone once decided)."""
    from windpump_app.views import same

    old = {"xs": [[0.0, 1.0], [2.0, 3.0, 4.0]], "ys": [[0.0, 1.0], [2.0, 3.0, 4.0]]}
    new = {"xs": [[0.0, 1.0], [2.0, 3.0, 4.0]], "ys": [[0.0, 1.0], [2.0, 3.0, 5.0]]}
    assert not same(old, new) and same(old, {key: list(v) for key, v in old.items()})


def test_no_number_is_parted_from_its_unit():
    """On a phone a readout's value or the status wraps: never between a number and its unit
    ("3,925" and a lone "J" on the next line), each such pair in a span that does not wrap."""
    app = Explorer()
    app.sidebar.preset.value = "A leak hole lets it start"  # losses: four terms of energy
    texts = [readout.object for readout in app.readouts.readouts.values()]
    texts.append(app.readouts.status.object)
    kept = re.compile(r'<span style="white-space: nowrap">([^<]*)</span>')
    units = r"\d (?:J|N·m|rad/s|L/s|s|%|L)(?!\w)"
    for text in texts:
        assert re.search(units, text) is None or kept.search(text), text
        assert re.search(units, kept.sub("", text)) is None, text  # none left outside a span
    energy = kept.findall(app.readouts["energy"].object)
    assert len(energy) == 4 and all(term.endswith(" J") for term in energy)
    app.sidebar.preset.value = "The paper's example"  # no torque at rest: "T₀" and "= 0" once
    assert "T₀ = 0" in kept.findall(app.readouts.status.object)  # parted on a phone


@pytest.mark.parametrize(
    "query",
    [
        {"h": [b"-5"]},
        {"h": [b"-5"], "T_m": [b"abc"], "foo": [b"1"], "cylinders": [b"2.5"], "T_0": [b"0.9"]},
    ],
    ids=["h", "several"],
)
def test_a_link_whose_values_are_all_refused_says_it_shows_the_papers_example(query):
    """Every value of these links is refused (out of range, not a number, not whole, beyond
    Tₘ): each opens on the paper's example and says so, as a link to it does, under its notices."""
    app = Explorer(query=query)
    assert app.inputs.design() == SEED
    assert app.sidebar.preset.value == "The paper's example"
    assert app.sidebar.preset_note.visible and PRESETS["The paper's example"][1] in (
        app.sidebar.preset_note.object
    )
    assert app.notices.visible and "(h) = “-5” ignored" in app.notices.object


def test_a_phones_link_notices_say_that_they_scroll():
    """On a phone the notices' list scrolls within two whole lines (the status under the
    readouts stays in view), once a line and a half with nothing saying it scrolled: its title
    says how many notices to scroll through, on a phone only, and the scroll bar is drawn."""
    from windpump_app.styles import NOTICE

    app = Explorer(query={"h": [b"-5"], "T_m": [b"abc"], "foo": [b"1"]})
    assert '<span class="scroll-hint">(3: scroll the list)</span>' in app.notices.object
    assert "scroll-hint" not in Explorer(query={"h": [b"-5"]}).notices.object  # one: all shown
    phone = " ".join(NOTICE).split("@media (max-width: 700px)")[-1]
    assert "max-height: 3em" in phone and "line-height: 1.5;" in phone  # two whole lines
    assert "overflow-y: scroll" in phone and "::-webkit-scrollbar-thumb" in phone
    assert ".scroll-hint { display: inline; white-space: nowrap; }" in phone
    assert ".scroll-hint { display: none; }" in NOTICE  # elsewhere the list is whole
