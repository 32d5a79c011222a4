"""The real machine in the explorer: its inputs, their link, their refusals and their presets."""

from __future__ import annotations

import math
from urllib.parse import parse_qsl

import numpy as np
import pytest
from real_reference import real_reference_run

import windpump
from windpump_app.explorer import Explorer
from windpump_app.inputs import PRESETS, PumpInputs

from panes import shown

SEED = windpump.Design.seed_example()

# slider -> (a value on its grid, the Design field it sets, that value in the core's SI units)
SETTINGS = {
    "m_r": (2.5, "m_r", 2.5),
    "eta_t": (0.85, "eta_t", 0.85),
    "L_main": (30.0, "L_main", 30.0),
    "D_main_mm": (25.0, "D_main", 0.025),
    "f_main": (0.035, "f_main", 0.035),
    "d_leak_mm": (2.5, "d_leak", 0.0025),
    "Cd_leak": (0.7, "Cd_leak", 0.7),
}


@pytest.fixture
def app():
    return Explorer()


def test_the_real_machine_has_its_own_card_closed_on_the_ideal_machine(app):
    card = app.sidebar.real_card
    assert card.collapsed and "Real machine" in card.header.object
    assert list(card.objects) == []  # its sliders are built when it first opens
    assert card.header.object == "<b>Real machine</b>"  # one line, as "More parameters"
    card.collapsed = False  # as the student's click does
    note, *sliders = card.objects  # what it holds, said under its short title
    assert "rod" in note.object and "chain" in note.object and "leak" in note.object
    assert sliders == [app.sidebar.sliders[name] for name in SETTINGS]
    card.collapsed = True  # closed again, it keeps them
    assert list(card.objects)[1:] == [app.sidebar.sliders[name] for name in SETTINGS]
    labels = [app.sidebar.sliders[name].name for name in SETTINGS]
    assert labels[0].endswith("[kg]") and labels[2].endswith("[m]")
    assert labels[3].endswith("[mm]") and labels[5].endswith("[mm]")  # diameters in mm
    assert app.inputs.design() == SEED and app.inputs.design().is_ideal


def test_the_closed_cards_cost_the_page_no_sliders_until_opened():
    app = Explorer()
    bar = app.sidebar
    assert bar.more_card.objects == [] and bar.real_card.objects == []
    built = set(bar.sliders)  # the sliders built so far
    assert built.isdisjoint(SETTINGS) and "t_end" not in built
    bar.more_card.collapsed = False
    assert bar.sliders["t_end"] in bar.more_card.objects and bar.real_card.objects == []


def test_a_link_that_sets_the_real_machine_opens_its_card_with_its_sliders():
    app = Explorer(query={"d_leak_mm": [b"3"]})
    card = app.sidebar.real_card
    assert not card.collapsed and app.inputs.d_leak_mm == 3.0
    assert list(card.objects)[1:] == [app.sidebar.sliders[name] for name in SETTINGS]
    assert app.sidebar.sliders["d_leak_mm"].value == 3.0  # the slider shows the link's value


@pytest.mark.parametrize("name", SETTINGS)
def test_each_slider_sets_its_field_of_the_design_the_core_runs(app, name):
    value, field, si = SETTINGS[name]
    app.sidebar.sliders[name].value = value
    design = SEED.replace(**{field: si})
    assert app.inputs.design() == design and not app.error.visible
    assert app.seen.design == design  # the run on the screen is of this design
    assert app.inputs.design_at_v_ref() == design  # the Wind tab's day too
    assert not app.sidebar.real_card.collapsed  # a value off the ideal machine shows its card


def test_every_tab_gets_the_real_machine(app):
    app.set_values(m_r=4.0, eta_t=0.9, L_main=20.0, D_main_mm=20.0)
    design = SEED.replace(m_r=4.0, eta_t=0.9, L_main=20.0, D_main=0.02)
    app.main().active = 2  # the Wind tab runs its day once opened
    assert app.wind.last_run.design == design
    app.design_map.update(app.seen)  # mapped around this design (all but R1 and h)
    assert app.design_map._mapped_key == design.replace(R1=design.R0, h=0.0)
    downloaded = app._csv().getvalue().splitlines()
    for line in ("# m_r = 4 kg", "# eta_t = 0.9", "# D_main = 0.02 m", "# d_leak = 0 m"):
        assert line in downloaded


def test_a_leak_hole_as_wide_as_the_bore_is_named_and_the_page_keeps_working(app):
    before = dict(app.sources["speed"].data)
    app.sidebar.sliders["d_leak_mm"].value = 40.0  # the seed's bore: sqrt(4 A / pi) = 40 mm
    assert app.error.visible and app.stale
    assert app.error.object.startswith("Leak hole diameter [mm] = 40 cannot be run: ")
    assert "d_leak = 0.04 m is not allowed" in app.error.object
    assert "below the bore = 0.04" in app.error.object
    assert app.sources["speed"].data["upper"] is before["upper"]  # the last good plot stays
    app.sidebar.sliders["d_leak_mm"].value = 3.0
    assert not app.error.visible and not app.stale
    assert app.seen.design == SEED.replace(d_leak=0.003)


# -- the link -------------------------------------------------------------------------------------


def test_the_real_machine_travels_in_the_link_and_its_defaults_stay_out():
    query = {name: [repr(value).encode()] for name, (value, _f, _si) in SETTINGS.items()}
    app = Explorer(query=query)
    assert not app.notices.visible
    expected = SEED.replace(**{field: si for _v, field, si in SETTINGS.values()})
    assert app.inputs.design() == expected and app.seen.design == expected
    assert app.link_query() == (
        "m_r=2.5&eta_t=0.85&L_main=30&D_main_mm=25&f_main=0.035&d_leak_mm=2.5&Cd_leak=0.7"
    )
    again = Explorer(query={k: [v.encode()] for k, v in parse_qsl(app.link_query())})
    assert again.inputs.values() == app.inputs.values() and again.inputs.design() == expected
    app.set_values(**{name: PumpInputs.param[name].default for name in SETTINGS})
    assert app.link_query() == ""


@pytest.mark.parametrize(
    "query, words",
    [
        (
            {"d_leak_mm": [b"40"], "h": [b"5"]},
            "Leak hole diameter [mm] (d_leak_mm) = “40” ignored: d_leak = 0.04 m is not allowed: "
            "d_leak must be from 0 to below the bore",
        ),
        (
            {"eta_t": [b"0"], "h": [b"5"]},
            "(eta_t) = “0” ignored: it must be a number from 0.1 to 1.",
        ),
        ({"m_r": [b"-1"], "h": [b"5"]}, "(m_r) = “-1” ignored: it must be a number from 0 to 50."),
        ({"f_main": [b"0.3"], "h": [b"5"]}, "(f_main) = “0.3” ignored: it must be a number from 0"),
    ],
)
def test_a_bad_real_machine_value_in_the_link_is_named_and_left_out(query, words):
    app = Explorer(query=query)
    assert app.notices.visible and words in shown(app.notices)
    assert not app.error.visible and app.inputs.design() == SEED.replace(h=5.0)


# -- the presets ----------------------------------------------------------------------------------


def lever(phi: float, L_over_R: float) -> float:
    """dx/dphi / R, the derivative of Eq. (1), written here from the paper."""
    s = math.sin(phi)
    return s * (1.0 + math.cos(phi) / math.sqrt(L_over_R**2 - s * s))


def test_the_leak_preset_is_a_tight_pump_that_cannot_start_given_a_hole(app):
    app.sidebar.preset.value = "A leak hole lets it start"
    design = app.inputs.design()
    assert design == SEED.replace(T_0=0.25, d_leak=0.003)
    assert (app.inputs.theta0, app.inputs.theta_dot0) == (4.71, 0.0)
    assert not app.sidebar.real_card.collapsed and not app.error.visible
    assert app.sidebar.sliders["d_leak_mm"] in app.sidebar.real_card.objects  # built as it opened
    tight = design.replace(d_leak=0.0)
    # the tight piston's load at rest at theta0 (mid-upstroke) beats the windmill's R+ T_0 ...
    load_at_rest = design.rho_w * design.g * design.h * design.A * design.R
    load_at_rest *= abs(lever(app.inputs.theta0, design.L_over_R))
    assert design.R_dagger * design.T_0 == pytest.approx(1.0)
    assert load_at_rest == pytest.approx(1.478, abs=1e-3) and load_at_rest > 1.0
    assert not windpump.starts_from_rest(tight)  # ... and so it does from every angle
    assert windpump.starts_from_rest(design)  # with the hole: no load at rest
    # ... while the hole (through the piston) lets the water by: q_L = Cd a_L sqrt(2 g h)
    assert 0.0 < design.d_leak < design.bore
    q_L = 0.6 * math.pi / 4 * 0.003**2 * math.sqrt(2 * 9.81 * 3.0)
    assert design.leak_capacity == pytest.approx(q_L, rel=1e-12)
    values, sentence = PRESETS["A leak hole lets it start"]
    assert "3 mm" in sentence and "R†T₀ = 1 N·m" in sentence and "1.48 N·m" in sentence
    # "at speed the hole costs about 4 % of the water (over this run ... about 6 %)": at alpha+
    # the delivered flow's mean against the swept volume's, and the run's own efficiency
    assert "about 4 %" in sentence and "about 6 %" in sentence
    alpha_plus, _ = windpump.steady_speeds(design)
    swept = design.volume_per_revolution * alpha_plus / (2 * math.pi)
    at_speed = 1 - windpump.steady_flow(design, design.V_ref) / swept
    assert at_speed == pytest.approx(0.04, abs=0.005)
    assert 1 - app.seen.volumetric_efficiency == pytest.approx(0.06, abs=0.01)
    # and the start readout says why it starts, not "peak load 0.00 N·m"
    said = app.readouts.status.object
    assert "starts on its own" in said and "slips back through the leak hole" in said
    assert "peak load 0.00" not in said


def margin_and_kick_force(design: windpump.Design, kick: float) -> tuple[float, float]:
    """The issue's averaged theory, by quadrature written here: the stall margin, the largest
    eta_t R+ T(R+ a) / Lbar(a) over running speeds, with Lbar(a) the revolution mean of the
    upstroke's load rho_w g (h + h_f) A |x'| at constant crank speed a, and the net cycle-mean
    torque at ``kick`` (> 0: the kick is above alpha-)."""
    theta = np.linspace(0.0, 2 * math.pi, 4000, endpoint=False)
    s = np.sin(theta)
    arm = design.R * s * (1 + np.cos(theta) / np.sqrt(design.L_over_R**2 - s * s))
    upstroke = np.where(arm < 0, -arm, 0.0)
    a_main = math.pi / 4 * design.D_main**2
    per_flow2 = design.f_main * design.L_main / design.D_main / (2 * design.g * a_main**2)

    def windmill(a):
        x = design.R_dagger * a / design.omega_m
        return design.eta_t * design.R_dagger * design.T_m * x * (2 - x)

    def mean_load(a):
        head = design.h + per_flow2 * (design.A * upstroke * a) ** 2
        return np.mean(design.rho_w * design.g * head * design.A * upstroke)

    speeds = np.linspace(0.01, 2 * design.omega_m / design.R_dagger, 400)[1:-1]
    margin = max(windmill(a) / mean_load(a) for a in speeds)
    return margin, windmill(kick) - mean_load(kick)


def test_the_deep_well_preset_still_runs(app):
    app.sidebar.preset.value = "A deep well, a heavy rod"
    design = app.inputs.design()
    assert design == SEED.replace(h=25.0, T_m=2.5, m_r=15.0, eta_t=0.8, L_main=30.0, D_main=0.025)
    assert app.inputs.theta_dot0 == 6.0 and not app.sidebar.real_card.collapsed
    assert not app.error.visible
    margin, net_at_kick = margin_and_kick_force(design, app.inputs.theta_dot0)
    ideal, _ = margin_and_kick_force(design.replace(eta_t=1.0, L_main=0.0), 6.0)
    assert ideal == pytest.approx(windpump.stall_margin(SEED.replace(h=25.0, T_m=2.5)), rel=1e-4)
    assert 1.5 < margin < ideal  # the chain and the pipe cost margin, but it still runs
    assert windpump.stall_margin(design) == pytest.approx(margin, rel=1e-4)
    assert net_at_kick > 0  # kicked above alpha-: it spins up


# -- the presets' runs, against the issue's equations integrated by scipy (tests/real_reference.py)


def at(run, t: float, name: str) -> float:
    return float(np.interp(t, run.t, getattr(run, name)))


def test_the_leak_preset_starts_from_rest_and_the_tight_pump_does_not(app):
    app.sidebar.preset.value = "A leak hole lets it start"
    design, theta0 = app.inputs.design(), app.inputs.theta0
    assert "Running" in app.readouts.status.object
    assert "starts on its own" in app.readouts.status.object
    ref = real_reference_run(design, 120.0, theta0, 0.0)
    run = app.seen.run
    assert not ref.stalled and not run.stalled and ref.theta_dot > 1.0
    assert at(run, 120.0, "volume") == pytest.approx(ref.volume, rel=1e-4)
    assert at(run, 120.0, "theta_dot") == pytest.approx(ref.theta_dot, rel=1e-4)
    app.sidebar.sliders["d_leak_mm"].value = 0.0  # the same pump, tight
    assert app.inputs.design() == design.replace(d_leak=0.0)
    tight = real_reference_run(app.inputs.design(), 120.0, theta0, 0.0)
    assert tight.stalled and tight.t == 0.0
    assert app.seen.run.stalled and app.seen.run.t_stall == 0.0
    assert "Never started" in app.readouts.status.object


def test_the_deep_well_preset_runs_as_the_issues_equations_say(app):
    app.sidebar.preset.value = "A deep well, a heavy rod"
    design = app.inputs.design()
    ref = real_reference_run(design, 120.0, app.inputs.theta0, app.inputs.theta_dot0)
    run = app.seen.run
    assert not ref.stalled and not run.stalled and "Running" in app.readouts.status.object
    assert at(run, 120.0, "volume") == pytest.approx(ref.volume, rel=1e-4)
    assert at(run, 120.0, "theta_dot") == pytest.approx(ref.theta_dot, rel=1e-4)
    assert ref.friction_loss > 0.0  # the rising main takes its share
    kicked_lower = real_reference_run(design, 120.0, app.inputs.theta0, 3.0)
    assert kicked_lower.stalled  # the paper's 3 rad/s kick is below this pump's alpha-


@pytest.mark.parametrize("query", [{"d_leak_mm": [b"3"]}, {"h": [b"0"]}])
def test_a_pump_that_never_stalls_reads_so_not_inf(query):
    """A leak hole (no load at rest) or no head gives an endless stall margin (the core's inf,
    Eq. 22): the readout says so in words a class reads, not Python's "inf"."""
    app = Explorer(query=query)
    assert math.isinf(windpump.stall_margin(app.inputs.design()))
    shown = app.readouts["margin"].object
    assert "inf" not in shown and "∞ (never stalls)" in shown
    app.show_views()  # the stall view's title says it too
    assert app.pump.stall.figure.title.text.endswith("margin ∞: it runs")


@pytest.mark.parametrize("name", [n for n in PRESETS if n != "A deep well, a heavy rod"])
def test_a_preset_leaves_the_real_machine_card_as_a_fresh_page_of_it_does(name):
    """Chosen after a preset of a real machine (which opens the card), a preset leaves the card
    as a fresh page opened on its link has it: "A stalled pump" kept it open over the real
    machine's sliders although its machine is the paper's ideal one (issue 37)."""
    app = Explorer()
    app.sidebar.preset.value = "A deep well, a heavy rod"
    assert not app.sidebar.real_card.collapsed
    app.sidebar.preset.value = name
    fresh = Explorer(query={k: [v.encode()] for k, v in parse_qsl(app.inputs.query())})
    assert fresh.inputs.design() == app.inputs.design()  # the same design, opened afresh
    assert app.sidebar.real_card.collapsed == fresh.sidebar.real_card.collapsed
    assert app.sidebar.real_card.collapsed == app.inputs.design().is_ideal
