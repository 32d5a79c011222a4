"""The Wind tab in-process: its readouts and sources against windpump, the link, measured files."""

from __future__ import annotations

import math
import re

import numpy as np
import panel as pn
import pytest
from scipy import special, stats

import windpump
from windpump.model.wind import gusty, read_csv
from windpump.units import SECONDS_PER_DAY as DAY
from windpump_app.explorer import Explorer
from windpump_app.views import BINS

from panes import rendered, shown

SEED = windpump.Design.seed_example()


@pytest.fixture
def app():
    explorer = Explorer()
    explorer.main().active = 2  # open the Wind tab
    return explorer


def value(app, name):
    html = app.wind.readouts[name].object
    value = html.split(f'data-name="{name}">')[1].rsplit("</div></div>", 1)[0]
    return re.sub(r"<[^>]+>", "", value)  # as the page shows it


def litres(number: float) -> str:
    return f"{number:,.0f}"


def bounds(low: float, high: float) -> str:
    """The averaged theory's (from rest, once running) litres a day to three significant figures
    (each at least 100 L here, or 0), as the readout writes them."""
    return " · ".join(f"{float(f'{b:.3g}'):,.0f}" for b in (low, high))


def test_opening_the_tab_runs_a_gusty_day_in_full(app):
    design = SEED.replace(T_0=0.3)
    app.set_values(T_0=0.3, mean_wind=4.0)
    record = gusty(4.0, DAY, k=2.0, time_scale=60.0, seed=1)
    run = windpump.simulate(design, DAY, math.pi / 2, 3.0, wind=record, sample_dt=1.0)
    assert value(app, "day_litres") == litres(1e3 * run.volume[-1])
    low, high = windpump.record_water(design, record)
    assert value(app, "record_bounds") == bounds(1e3 * low, 1e3 * high)
    low, high = windpump.water_per_day(design, 4.0, 2.0)
    assert value(app, "site_bounds") == bounds(1e3 * low, 1e3 * high)
    V_stop, V_start = windpump.wind_thresholds(design)
    assert value(app, "thresholds") == f"{V_stop:.1f} · {V_start:.1f}"
    stops = app.wind.sources["stops_wind"].data
    np.testing.assert_allclose(stops["t"], np.asarray(run.stops) / 3600.0)
    for name in ("wind", "speed", "litres"):
        assert len(app.wind.sources[name].data["t"]) <= BINS
    assert app.wind.sources["litres"].data["litres"][-1] == pytest.approx(1e3 * run.volume[-1])
    density = app.wind.sources["density"].data
    expected = stats.weibull_min(2.0, scale=4.0 / special.gamma(1.5)).pdf(density["V"])
    np.testing.assert_allclose(density["density"], expected, rtol=1e-12)


def test_the_steady_wind_moves_every_view(app):
    app.set_values(V=8.0)
    moved = SEED.in_wind(8.0)
    assert app.seen.design == moved
    assert app.seen.mean_flow == windpump.explore(moved, 600.0).mean_flow
    here = app.wind.sources["here"].data
    assert here["V"] == [8.0]
    assert here["flow"][0] == pytest.approx(1e3 * windpump.steady_flow(SEED, 8.0))
    curve = app.wind.sources["curve"].data
    np.testing.assert_allclose(curve["flow"], 1e3 * windpump.steady_flow(SEED, curve["V"]))


def test_a_self_starting_pump_needs_no_kick_and_stops_and_starts_with_the_wind(app):
    app.set_values(cylinders=2.0, T_0=0.4, mean_wind=3.0, time_scale=600.0, I0=0.2)
    run = app.wind.last_run
    assert run.theta_dot[0] == 0.0  # no kick: at rest until the wind first can turn it
    assert np.all(run.theta_dot[run.t < run.starts[0]] == 0.0)
    assert len(run.stops) >= 1 and len(run.starts) >= 2
    assert "starts on its own" in app.wind.day_note.object
    note = app.wind.day_note.object  # the counts in words, not "stops 0 time(s)"
    said = {1: "once", 2: "twice"}.get(len(run.starts), f"{len(run.starts)} times")
    assert "time(s)" not in note and f"starts again {said}" in note
    assert len(app.wind.sources["starts_litres"].data["t"]) == len(run.starts)


def test_a_link_sets_the_wind_and_a_tampered_one_is_ignored_with_a_notice():
    query = {"V": [b"6.5"], "mean_wind": [b"4"], "k": [b"2.5"], "time_scale": [b"95"],
             "seed": [b"7"], "T_0": [b"0.2"]}  # fmt: skip
    app = Explorer(query=query)
    assert (app.inputs.V, app.inputs.mean_wind, app.inputs.k) == (6.5, 4.0, 2.5)
    assert (app.inputs.time_scale, app.inputs.seed) == (95.0, 7)
    assert "V=6.5" in app.inputs.query() and "seed=7" in app.inputs.query()
    off_step = Explorer(query={"time_scale": [b"99"]})  # its slider's step is 5: taken as written
    assert off_step.inputs.time_scale == 99.0 and off_step.link_query() == "time_scale=99"
    tampered = Explorer(query={"k": [b"99"], "mean_wind": [b"gale"]})
    assert tampered.notices.visible
    assert "Weibull shape k (2: Rayleigh) (k)" in tampered.notices.object
    assert "(mean_wind)" in tampered.notices.object
    assert (tampered.inputs.k, tampered.inputs.mean_wind) == (2.0, 5.0)


def test_a_measured_wind_file_replaces_the_day_and_a_bad_one_is_refused(app):
    rows = "\n".join(f"{60 * i},{5 + 2 * math.sin(i / 5):.3f}" for i in range(121))
    app.wind.upload.filename = "mast.csv"
    app.load_wind_data(("t [s],V [m/s]\n" + rows + "\n").encode())
    run = app.wind.last_run
    assert run.t[-1] == 7200.0 and "mast.csv" in shown(app.wind.day_note)
    day = value(app, "day_litres")
    lifted = 1e3 * run.volume[-1]
    assert day == f"{litres(lifted)} L ({litres(lifted * DAY / 7200.0)} L/day at this rate)"
    app.load_wind_data(b"t,V\n0,5\n10,-3\n")
    assert app.wind.upload_message.visible and "line 3" in app.wind.upload_message.object
    assert value(app, "day_litres") == day  # nothing lost
    app.forget_wind_data()
    assert app.wind.last_run.t[-1] == DAY


def test_an_empty_wind_file_is_explained_and_the_day_stays(app):
    """Panel reports a chosen 0-byte file as its name with no content (value stays None)."""
    day = value(app, "day_litres")
    app.wind.upload.filename = "empty.csv"
    assert app.wind.upload_message.visible and "the file is empty" in app.wind.upload_message.object
    assert value(app, "day_litres") == day


def test_every_wind_upload_outcome_is_scrolled_into_view(app):
    rows = "\n".join(f"{60 * i},{5 + 2 * math.sin(i / 5):.3f}" for i in range(121))
    app.wind.upload.param.update(value=rows.encode(), filename="mast.csv")
    assert "mast.csv" in shown(app.wind.day_note)
    assert app.sidebar.reveal.value.split("\t")[0] in app.wind.day_note.css_classes
    app.wind.upload.param.update(value=b"0,5x\n10,6\n", filename="typo.csv")
    assert "line 1, column 2" in app.wind.upload_message.object
    assert app.sidebar.reveal.value.split("\t")[0] in app.wind.upload_message.css_classes
    app.sidebar.refused_upload.value = f"{12_000_000}\t1\twind\tyear.csv"
    assert app.sidebar.reveal.value.split("\t")[0] in app.wind.upload_message.css_classes


def test_a_design_the_day_cannot_run_is_said_and_the_tab_lives(app):
    app.set_values(h=30.0, T_m=0.05)  # the pump never carries its load: the day rests
    assert not app.wind.error.visible
    assert value(app, "day_litres") == "0"
    app.set_values(h=3.0, T_m=0.6)
    assert value(app, "day_litres") != "0"


def test_a_wind_file_the_page_refused_is_reported_in_the_wind_tab(app):
    app.sidebar.refused_upload.value = f"{12_000_000}\t1\twind\tyear.csv"
    assert app.wind.upload_message.visible and "12,000,000 bytes" in app.wind.upload_message.object
    assert not app.sidebar.lab.message.visible
    app.wind.upload_message.visible = False
    app.sidebar.refused_upload.value = f"{5_000}\t2\twind\tsmall.csv"  # not a size the page refuses
    assert not app.wind.upload_message.visible


def test_a_steady_wind_move_leaves_the_day_as_it_was(app):
    day = app.wind.last_run
    app.set_values(V=7.0)
    assert app.wind.last_run is day  # the day runs in its own record: V does not enter it
    app.set_values(seed=2.0)
    assert app.wind.last_run is not day


def steady_record(hours: float, speed: float) -> bytes:
    rows = "".join(f"{60 * i},{speed}\n" for i in range(int(hours * 60) + 1))
    return ("t [s],V [m/s]\n" + rows).encode()


def test_a_record_shorter_than_a_day_says_its_water_and_its_rate_a_day(app):
    """Three hours' water is not a day's: the readout gives the record's litres over its length,
    then the rate a day that makes."""
    app.load_wind_data(steady_record(3.0, 6.0))
    duration = 3 * 3600.0
    record = read_csv(steady_record(3.0, 6.0))
    run = windpump.simulate(SEED, duration, math.pi / 2, 3.0, wind=record, sample_dt=1.0)
    lifted = 1e3 * run.volume[-1]
    html = app.wind.readouts["day_litres"].object
    assert "This record (3 h 0 min), in full" in html
    assert (
        "Averaged over this record's wind [L/day], from rest · once running"
        in app.wind.readouts["record_bounds"].object
    )
    assert value(app, "day_litres") == (
        f"{litres(lifted)} L ({litres(lifted * 86_400 / duration)} L/day at this rate)"
    )
    app.forget_wind_data()  # a whole day: its litres are the day's
    assert "This day, in full [L/day]" in app.wind.readouts["day_litres"].object
    assert (
        "Averaged over this day's wind [L/day], from rest · once running"
        in app.wind.readouts["record_bounds"].object
    )
    assert value(app, "day_litres") == litres(1e3 * app.wind.last_run.volume[-1])


def legend_labels(fig) -> list[str]:
    return [item.label.value for item in fig.legend[0].items if item.visible]


def test_the_stops_and_starts_legend_lists_only_what_the_day_has(app):
    app.load_wind_data(steady_record(3.0, 6.0))  # a steady wind: it never stops
    run = app.wind.last_run
    assert len(run.stops) == len(run.starts) == 0
    assert legend_labels(app.wind.day_wind) == []
    assert "never stops;" in app.wind.day_note.object  # not "stops 0 time(s)"
    app.forget_wind_data()
    app.set_values(cylinders=2.0, T_0=0.4, mean_wind=3.0, time_scale=600.0, I0=0.2)
    run = app.wind.last_run
    assert len(run.stops) >= 1 and len(run.starts) >= 1
    assert legend_labels(app.wind.day_wind) == ["stops", "starts"]


def test_the_kick_slider_does_not_rerun_the_day_of_a_windmill_that_starts_on_its_own(app):
    """Such a windmill is let go from rest (windpump.sites.site.kick_in_wind): the day is the same run."""
    app.set_values(T_0=0.4)
    assert windpump.starts_from_rest(app.inputs.design())
    day = app.wind.last_run
    assert day.theta_dot[0] == 0.0
    app.set_values(theta_dot0=5.0)
    assert app.wind.last_run is day
    app.set_values(T_0=0.0)  # now it needs the kick: a new day, kicked at 5 rad/s
    assert app.wind.last_run.theta_dot[0] == 5.0


def test_presentation_mode_gives_the_steady_wind_plot_room_for_its_larger_legend(app):
    """Its legend's three items take three rows in presentation mode: the figure grows by the
    rows' height, and shrinks back when presentation mode is turned off."""
    curve = app.wind.curve
    usual = curve.height
    app.presentation = True
    grown = curve.height
    app.presentation = False
    assert grown >= usual + 3 * 25  # three rows of 18-px labels and 28-px swatches, about
    assert curve.height == usual
    app.presentation = True
    assert curve.height == grown  # as often as it is turned on


def test_served_a_day_runs_off_the_loop_says_so_and_the_newest_wins(monkeypatch):
    """Served, the day runs off the event loop (``off_the_loop``): the tab says it is working,
    and when two moves' days come back in the wrong order only the newer one is drawn; a day
    superseded before its turn in the pool is not run at all (~1 s of a shared thread)."""
    from windpump_app import wind_tab

    held: list = []  # the days' (work, then) as the thread pool would run them
    ran: list = []  # the designs whose day was run
    run_day = wind_tab.run_day
    monkeypatch.setattr(wind_tab, "run_day", lambda d, *a: ran.append(d) or run_day(d, *a))

    def days_held(work, then) -> None:  # the steady wind's curve at once
        if "_update_curve" in then.__qualname__:
            then(work())
        else:
            held.append((work, then))

    monkeypatch.setattr(wind_tab, "off_the_loop", days_held)
    explorer = Explorer()
    explorer.main().active = 2  # the Wind tab: its day is asked for
    assert explorer.wind.day_note.object == wind_tab.WindTab.waiting
    explorer.set_values(T_0=0.3)  # a newer design's day, asked for before the first came back
    assert len(held) == 2
    newer_work, newer_then = held[1]
    newer_then(newer_work())
    newer = value(explorer, "day_litres")
    older_work, older_then = held[0]
    older_then(older_work())  # the older day, late: not drawn over the newer
    assert value(explorer, "day_litres") == newer
    assert [d.T_0 for d in ran] == [0.3]  # the older, superseded, was never run
    design, record = SEED.replace(T_0=0.3), gusty(5.0, DAY, k=2.0, time_scale=60.0, seed=1)
    run = windpump.simulate(design, DAY, math.pi / 2, 3.0, wind=record, sample_dt=1.0)
    assert newer == litres(1e3 * run.volume[-1])
    assert "Integrated in full" in explorer.wind.day_note.object


def test_served_nothing_of_a_day_is_computed_on_the_loop_neither_the_gusty_wind_nor_a_files_water(
    monkeypatch,
):
    """Served, the gusty day itself (~0.4 s to make) and the water an uploaded record gives by
    the averaged theory (~0.15 s for a week) are computed in ``off_the_loop``'s work, not on the
    event loop before or after it."""
    from windpump_app import wind_tab

    held: list = []  # (work, then) as the thread pool would run them
    monkeypatch.setattr(wind_tab, "off_the_loop", lambda work, then: held.append((work, then)))
    in_work, calls = [False], []  # whether each core call below ran inside a work

    def counted(function):
        def call(*args, **kwargs):
            calls.append((function.__name__, in_work[0]))
            return function(*args, **kwargs)

        return call

    monkeypatch.setattr(wind_tab, "gusty_day", counted(wind_tab.gusty_day))
    monkeypatch.setattr(windpump, "record_water", counted(windpump.record_water))

    def run_held() -> None:
        while held:  # in order, each outcome's drawing after its work
            work, then = held.pop(0)
            in_work[0] = True
            outcome = work()
            in_work[0] = False
            then(outcome)

    explorer = Explorer()
    explorer.main().active = 2  # the Wind tab: its day is asked for
    run_held()
    assert ("gusty_day", True) in calls and ("record_water", True) in calls
    rows = "\n".join(f"{60 * i},{5 + 2 * math.sin(i / 5):.3f}" for i in range(121))
    explorer.wind.upload.filename = "mast.csv"
    explorer.load_wind_data(("t [s],V [m/s]\n" + rows + "\n").encode())
    run_held()
    assert explorer.wind.last_run.t[-1] == 7200.0 and "mast.csv" in shown(explorer.wind.day_note)
    assert calls and all(inside for _name, inside in calls)


def test_a_files_content_stays_as_the_browser_sent_it_until_the_work_reads_it(monkeypatch):
    """The browser sends a file in base64; the upload keeps it so (``uploads.Encoded``) and the
    work off the loop decodes it (Panel's FileInput decoded 10 MB on the event loop)."""
    import base64

    from windpump_app import wind_tab
    from windpump_app.uploads import Encoded

    held: list = []
    monkeypatch.setattr(wind_tab, "off_the_loop", lambda work, then: held.append((work, then)))
    explorer = Explorer()
    explorer.main().active = 2
    rows = "\n".join(f"{60 * i},{5 + 2 * math.sin(i / 5):.3f}" for i in range(121))
    content = ("t [s],V [m/s]\n" + rows + "\n").encode()
    sent = base64.b64encode(content).decode()
    explorer.wind.upload._process_events({"filename": "mast.csv", "value": sent})
    assert isinstance(explorer.wind.upload.value, Encoded) and explorer.wind.upload.value == sent
    for work, then in held:
        then(work())
    assert explorer.wind.last_run.t[-1] == 7200.0 and "mast.csv" in shown(explorer.wind.day_note)
    assert explorer.wind.measured.V.tolist() == read_csv(content).V.tolist()


def test_served_the_steady_winds_numbers_are_worked_out_off_the_loop_the_newest_winning(
    monkeypatch,
):
    """A real machine's averaged theory takes ~0.15 s for the curve's 400 winds: served, the
    curve, the thresholds and the water a day are worked out in ``off_the_loop``'s work, and a
    curve that comes back after a newer one was asked for is not drawn over it."""
    from windpump_app import wind_tab

    held: list = []
    monkeypatch.setattr(wind_tab, "off_the_loop", lambda work, then: held.append((work, then)))
    explorer = Explorer()
    explorer.set_values(m_r=1.0, L_main=10.0, d_leak_mm=1.5)
    explorer.main().active = 2
    explorer.set_values(h=4.0)  # a newer curve, asked for before the first came back
    curves = [(w, t) for w, t in held if "_update_curve" in t.__qualname__]
    assert len(curves) == 2 and list(explorer.wind.sources["curve"].data["flow"]) == [0.0, 0.0]
    for name, label in wind_tab.WIND_READOUTS.items():  # laid out before their numbers come
        assert f">{label}<" in explorer.wind.readouts[name].object and value(explorer, name) == "…"
    worked: list = []
    steady_wind = wind_tab.steady_wind
    monkeypatch.setattr(
        wind_tab, "steady_wind", lambda d, *a: worked.append(d) or steady_wind(d, *a)
    )
    for work, then in reversed(curves):  # the newer first, the older late
        then(work())
    assert [d.h for d in worked] == [4.0]  # the older, superseded before its turn: not worked out
    design = explorer.inputs.design_at_v_ref()
    assert design.h == 4.0 and design.d_leak == 0.0015
    V = explorer.wind.sources["curve"].data["V"]
    np.testing.assert_allclose(
        explorer.wind.sources["curve"].data["flow"], 1e3 * windpump.steady_flow(design, V)
    )
    V_stop, _ = windpump.wind_thresholds(design)
    assert value(explorer, "thresholds").startswith(f"{V_stop:.1f} · ")
    low, high = windpump.water_per_day(design, explorer.inputs.mean_wind, explorer.inputs.k)
    assert value(explorer, "site_bounds") == bounds(1e3 * low, 1e3 * high)


def test_served_a_day_and_curve_in_flight_are_not_drawn_once_the_inputs_are_back_to_those_drawn(
    monkeypatch,
):
    """A move and its undo before the move's day and curve come back: the inputs are the ones
    drawn, so nothing new is asked, and the day and curve in flight, for inputs the page no
    longer has, are not drawn over them (nor worked out if not yet started)."""
    from windpump_app import wind_tab

    held: list = []
    monkeypatch.setattr(wind_tab, "off_the_loop", lambda work, then: held.append((work, then)))
    explorer = Explorer()
    explorer.main().active = 2
    for work, then in held:  # the first day and curve, drawn
        then(work())
    curve = list(explorer.wind.sources["curve"].data["flow"])
    litres = value(explorer, "day_litres")
    held.clear()
    explorer.set_values(h=6.0)  # a day and a curve in flight
    explorer.set_values(h=3.0)  # back: the day and curve drawn are this design's
    assert len(held) == 2
    for work, then in held:
        then(work())
    assert list(explorer.wind.sources["curve"].data["flow"]) == curve
    assert value(explorer, "day_litres") == litres


def test_a_record_of_days_is_titled_and_timed_as_its_span(app):
    """71 hours of wind is not "the day's wind" nor water "since dawn": the figures say the
    record's, time runs in days, and the litres' axis is written in plain numbers."""
    from bokeh.models import HoverTool, NumeralTickFormatter

    said = []
    say = app.wind.say
    app.wind.say = lambda text, *args: said.append(text) or say(text, *args)
    app.load_wind_data(steady_record(71.0, 6.0))
    app.wind.say = say
    words = [text for text in said] + [
        rendered(pane) for pane in app.wind.layout().select(pn.pane.Markdown)
    ]
    assert words and not [text for text in words if "the day" in text.lower()], words
    wind, speed, lifted = app.wind.day_wind, app.wind.day_speed, app.wind.day_litres
    assert wind.title.text == "The record's wind"
    assert lifted.yaxis[0].axis_label == "water since the record's start [L]"
    assert isinstance(lifted.yaxis[0].formatter, NumeralTickFormatter)  # 100,000, not 1.000e+5
    assert lifted.yaxis[0].formatter.format == "0,0.[00]"  # 0.5 L, not a second "1"
    for fig in (wind, speed, lifted):
        assert fig.xaxis[0].axis_label == "time [days]"
        assert ("t", "@t{0.00} days") in fig.select_one(HoverTool).tooltips
    assert wind.x_range.end == pytest.approx(71 / 24)
    assert max(app.wind.sources["litres"].data["t"]) == pytest.approx(71 / 24, rel=0.01)
    assert "This record (3.0 days), in full" in app.wind.readouts["day_litres"].object
    assert "(3.0 days)" in app.wind.day_note.object
    app.forget_wind_data()  # the gusty day: a day's words again, in hours
    assert wind.title.text == "The day's wind"
    assert lifted.yaxis[0].axis_label == "water since dawn [L]"
    assert fig.xaxis[0].axis_label == "time [h]" and wind.x_range.end == pytest.approx(24)
    assert ("t", "@t{0.00} h") in lifted.select_one(HoverTool).tooltips


def test_a_tab_hidden_behind_another_runs_nothing_until_it_is_shown_again(monkeypatch):
    """A preset chosen on the pump's tab with the Wind and Site tabs built: neither runs its day
    or year (hidden, a browser still lays them out: every tab built made a preset cost seconds),
    and each shows the preset's own when chosen again (the day against the core's, run here)."""
    import windpump_app.site_tab as site_tab
    import windpump_app.wind_tab as wind_tab

    app = Explorer()
    tabs = app.main()
    tabs.active = 2  # the Wind tab, then the Site tab, built
    tabs.active = 4
    tabs.active = 0  # back on the pump's
    days, years = [], []
    run_day, run_year = wind_tab.run_day, site_tab.run_year
    monkeypatch.setattr(wind_tab, "run_day", lambda *a: days.append(a) or run_day(*a))
    monkeypatch.setattr(site_tab, "run_year", lambda *a: years.append(a) or run_year(*a))
    app.sidebar.preset.value = "A double-acting pump"
    design = SEED.replace(double_acting=True, h=1.5)
    assert app.seen.design == design  # the pump's tab follows
    assert days == [] and years == []  # hidden: nothing run for them
    tabs.active = 2
    assert len(days) == 1 and years == []
    record = gusty(5.0, DAY, k=2.0, time_scale=60.0, seed=1)
    run = windpump.simulate(design, DAY, math.pi / 2, 3.0, wind=record, sample_dt=1.0)
    assert value(app, "day_litres") == litres(1e3 * run.volume[-1])
    tabs.active = 4
    assert len(years) == 1 and years[0][1].design == design
