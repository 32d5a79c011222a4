"""The Site tab in-process: its sources and readouts against windpump.supply for the same inputs,
the link, uploads good and bad."""

from __future__ import annotations

import csv
import datetime
import inspect
import io
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import panel as pn
import param
import pytest
from bokeh.models import HoverTool

import windpump
from windpump.readers.labdata import LabDataError
from windpump_app.explorer import Explorer
from windpump_app.server.threads import SUPERSEDED
from windpump_app.site_inputs import RESTARTS, SiteInputs
from windpump_app.site_record import read_upload

from panes import shown

SEED = windpump.Design.seed_example()
SITE_TAB = 4  # Wind pump, Mechanisms, Wind, Design map, Site


@pytest.fixture
def app():
    explorer = Explorer()
    explorer.main().active = SITE_TAB
    return explorer


def value(app, name):
    html = app.site.readouts[name].object
    value = html.split(f'data-name="{name}">')[1].rsplit("</div></div>", 1)[0]
    return re.sub(r"<[^>]+>", "", value)  # as the page shows it


def year(design=SEED, site="greensboro", hub=10.0, demand=10.0, tank=5.0, restart="attended"):
    record = windpump.sample_site(site).at_height(hub)
    return record, windpump.supply(design, record, demand, tank, restart=restart)


def data(app, name):
    return app.site.sources[name].data


def check_drawn(app, supplied, tank: float) -> None:
    """The tab's sources and readouts hold ``supplied``'s numbers (the year the core runs)."""
    monthly = data(app, "monthly")
    np.testing.assert_array_equal(monthly["pumped"], np.asarray(supplied.monthly.pumped))
    np.testing.assert_array_equal(monthly["demand"], np.asarray(supplied.monthly.demand))
    np.testing.assert_array_equal(monthly["delivered"], np.asarray(supplied.monthly.delivered))
    np.testing.assert_array_equal(monthly["shortfall"], np.asarray(supplied.monthly.shortfall))
    # each day's lowest, highest and mean level: the year's 8760 hours as 365 rows of 24
    days = np.asarray(supplied.level).reshape(365, 24)
    level = data(app, "level")
    np.testing.assert_array_equal(level["lower"], days.min(axis=1))
    np.testing.assert_array_equal(level["upper"], days.max(axis=1))
    np.testing.assert_allclose(level["mean"], days.mean(axis=1), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(level["t"], np.arange(365) + 0.5)
    # the days short of water, a rug along the bottom
    np.testing.assert_allclose(data(app, "dry")["t"], np.flatnonzero(supplied.dry) + 0.5)
    here = data(app, "lolp_here")
    assert here["tank"] == [tank] and here["lolp"] == [100 * supplied.lolp]
    assert app.site.tank_line.location == tank
    assert value(app, "site_lolp") == f"{100 * supplied.lolp:.1f} %"
    assert value(app, "dry_days") == f"{supplied.dry_days:d}"
    assert value(app, "dry_spell") == f"{supplied.longest_dry_spell:d} days"


def test_opening_the_tab_runs_the_year_at_greensboro(app):
    record, supplied = year()
    check_drawn(app, supplied, 5.0)
    totals = supplied.totals
    assert value(app, "site_water") == f"{totals.pumped:,.0f} · {totals.delivered:,.0f}"
    tanks = np.asarray(data(app, "lolp")["tank"])
    np.testing.assert_allclose(tanks, np.linspace(0.0, tanks[-1], tanks.size))
    mapped = windpump.supply_map(SEED, record, 10.0, [SEED.R_dagger], tanks, restart="attended")
    np.testing.assert_allclose(data(app, "lolp")["lolp"], 100 * mapped.lolp[:, 0], rtol=1e-12)
    smallest = windpump.tank_for(SEED, record, 10.0, 0.05, restart="attended")
    assert value(app, "tank_for_5") == f"{smallest:,.1f} m³"
    assert tanks[-1] >= 1.5 * smallest  # the curve reaches past the 5 % tank
    assert "Greensboro" in app.site.note.object


def test_one_default_restart_in_the_core_the_command_and_the_tab():
    """Issue 37: the command line restarted "self" and the Site tab "attended". Now one constant
    is the default of the core's functions, of --restart and of the tab's control."""
    from windpump.command.cli import build_parser
    from windpump.sites.fullyear import full_year
    from windpump.sites.yearly import DEFAULT_RESTART
    from windpump.sites.yearly import RESTARTS as CORE_RESTARTS

    assert DEFAULT_RESTART == "attended" and set(RESTARTS) == set(CORE_RESTARTS)
    for function in (windpump.supply, windpump.tank_for, windpump.supply_map, full_year):
        assert inspect.signature(function).parameters["restart"].default is DEFAULT_RESTART
    assert windpump.Supply.__dataclass_fields__["restart"].default is DEFAULT_RESTART
    parser = build_parser()
    for command in ("supply", "tank"):
        args = parser.parse_args([command, "--site", "sand_point", "--demand", "1"])
        assert args.restart is DEFAULT_RESTART
    assert SiteInputs.param["restart"].default is DEFAULT_RESTART
    assert SiteInputs().restart is DEFAULT_RESTART


def test_the_command_without_restart_is_the_site_tabs_year_at_sand_point(app, tmp_path):
    """``windpump supply`` at Sand Point with the tab's other inputs and no --restart: the year
    the tab draws there (the paper's pump, no torque at rest: on its own it would never run, and
    the command says so), hour by hour from its --csv."""
    app.site_inputs.site = "sand_point"
    drawn = app.site.supplied
    inputs = app.site_inputs
    hours = tmp_path / "hours.csv"
    done = subprocess.run(
        [
            sys.executable, "-m", "windpump", "supply", "--site", "sand_point",
            "--hub-height", f"{inputs.hub:g}", "--demand", f"{inputs.demand:g}",
            "--tank", f"{inputs.tank:g}", "--csv", str(hours),
        ],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert any(line.startswith("restart              attended") for line in lines)
    assert "never runs" not in done.stdout.replace("would never run", "")
    assert any("On its own (--restart self) the pump would never run" in line for line in lines)
    rows = list(csv.reader(io.StringIO(hours.read_text())))[1:]
    columns = np.array([[float(x) for x in row[2:]] for row in rows]).T
    V, running, pumped, delivered, shortfall, _, level = columns
    np.testing.assert_allclose(V, drawn.V, rtol=1e-5)
    np.testing.assert_array_equal(running.astype(bool), drawn.running)
    np.testing.assert_allclose(pumped, drawn.pumped, rtol=1e-8)
    np.testing.assert_allclose(delivered, drawn.delivered, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(shortfall, drawn.shortfall, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(level, drawn.level, rtol=1e-8, atol=1e-12)
    # attended, the rule as written: every hour the wind can carry the pump, it runs
    V_stop, V_start = windpump.wind_thresholds(SEED)
    assert V_start is None  # on its own it never would
    np.testing.assert_array_equal(drawn.running, drawn.V >= V_stop)
    assert drawn.running.any() and drawn.why == ""


def test_every_control_moves_the_year(app):
    app.site_inputs.param.update(site="sand_point", hub=20.0, demand=8.0, tank=25.0)
    _, supplied = year(site="sand_point", hub=20.0, demand=8.0, tank=25.0)
    check_drawn(app, supplied, 25.0)
    app.site.sliders["demand"].value = 3.0  # the widgets are the inputs
    assert app.site_inputs.demand == 3.0
    app.site.site_select.value = "greensboro"
    app.site.restart.value = "self"
    _, supplied = year(hub=20.0, demand=3.0, tank=25.0, restart="self")
    check_drawn(app, supplied, 25.0)


def test_the_design_on_the_sliders_is_the_sites(app):
    app.set_values(h=2.0, T_0=0.3)
    _, supplied = year(design=SEED.with_ratios(h=2.0, T_0=0.3))
    check_drawn(app, supplied, 5.0)
    app.set_values(V=8.0)  # the steady wind: the same rotor, the same year
    check_drawn(app, supplied, 5.0)


@pytest.mark.parametrize(
    "demand, head, box",
    [(0.5, 3.0, "success"), (10.0, 3.0, "warning"), (10.0, 100.0, "danger")],
)
def test_a_years_box_is_green_only_when_it_meets_its_demand(demand, head, box):
    """Within 5 % of the demand short (the tank readout's target) green; short of more, yellow
    with the share short; half or more short, red. A pump that ran 1 h of the year at h = 100 m,
    99.9 % of its demand short, once said so in a green box."""
    from windpump_app.site_record import LOLP_TARGET, MOSTLY_SHORT, supply_status

    record = windpump.sample_site("greensboro").at_height(10.0)
    supplied = windpump.supply(SEED.with_ratios(h=head), record, demand, 5.0)
    text, alert = supply_status(supplied)
    expected = (
        "success" if supplied.lolp <= LOLP_TARGET
        else "warning" if supplied.lolp < MOSTLY_SHORT
        else "danger"
    )  # fmt: skip
    assert alert == expected == box
    assert f"{supplied.totals.running_hours:,d} h of the year" in text
    assert (f"{100 * supplied.lolp:.1f} % of the demand goes undelivered" in text) == (
        box != "success"
    )


def test_a_pump_that_never_starts_says_why_in_a_warning_box(app):
    assert "starting" in app.site.status.object
    app.site_inputs.restart = "self"  # T_0 = 0: no torque at rest
    supplied = windpump.supply(SEED, windpump.sample_site("greensboro"), 10.0, 5.0, restart="self")
    assert supplied.why
    status = app.site.status
    assert status.alert_type == "warning" and "never starts" in status.object
    assert supplied.why[1:] in status.object  # the core's words, capitalised
    assert "“Attended”" in status.object and "restart=" not in status.object
    assert RESTARTS["attended"].startswith("Attended")  # the option it points to


def test_the_monthly_chart_shows_the_shortfall_on_the_demands_scale(app):
    """A small tank at Greensboro: ~700 m³ pumped in March against ~60 m³ asked for. The
    figure's top stays near the demand (its bars readable), the months cut there name their
    water, and the shortfall is a bar of its own colour on the delivered one."""
    app.set_values(T_0=0.3)
    app.site_inputs.param.update(hub=15.0, demand=2.0, tank=5.0, restart="self")
    _, supplied = year(design=SEED.with_ratios(T_0=0.3), hub=15.0, demand=2.0, restart="self")
    table = supplied.monthly
    assert table.pumped.max() > 5 * table.demand.max() and supplied.lolp > 0.1  # the case
    top = app.site.monthly.y_range.end
    assert table.demand.max() < top <= 3 * table.demand.max()
    cut = data(app, "monthly")["cut"]
    for pumped, label in zip(table.pumped, cut, strict=True):
        assert label == (f"{pumped:,.0f} " if pumped > top else "")
    short = [
        r for r in app.site.monthly.renderers if getattr(r.glyph, "bottom", None) == "delivered"
    ]
    assert len(short) == 1 and short[0].glyph.top == "short_top"
    drawn = data(app, "monthly")
    short_months = table.shortfall > 0
    np.testing.assert_allclose(drawn["short_top"][short_months], table.demand[short_months])
    app.site_inputs.param.update(demand=20.0)  # pumped no longer dwarfs the demand: all in view
    _, supplied = year(design=SEED.with_ratios(T_0=0.3), hub=15.0, demand=20.0, restart="self")
    assert app.site.monthly.y_range.end >= supplied.monthly.pumped.max()
    assert set(data(app, "monthly")["cut"]) == {""}


def test_a_short_record_is_labelled_by_its_span_not_a_year(app):
    app.set_values(T_0=0.3)
    app.site_inputs.restart = "self"
    app.site.upload.param.update(value=hourly_csv(3), filename="three.csv")
    assert app.site_inputs.site == "uploaded", app.site.upload_message.object
    html = app.site.readouts["site_water"].object
    assert "[m³ over 3 days]" in html and "year" not in html
    assert "of 3 days" in app.site.status.object and "year" not in app.site.status.object
    assert app.site.level.title.text == "The tank over 3 days"
    rug = [i for i in app.site.level.legend[0].items if i.label.value == "days short of water"]
    assert rug[0].visible is False  # none short: no blank swatch
    assert "year" not in app.site.level.xaxis.axis_label
    seventy = b"".join(hourly_csv(3).splitlines(keepends=True)[:71])  # a header, 70 hours
    app.site.upload.param.update(value=seventy, filename="short.csv")
    assert "[m³ over 70 h]" in app.site.readouts["site_water"].object
    app.site_inputs.site = "greensboro"
    assert "[m³/year]" in app.site.readouts["site_water"].object
    assert app.site.level.title.text == "The tank over the year"
    assert rug[0].visible is True


def test_the_link_carries_every_control_and_a_tampered_value_is_ignored():
    query = {"site": [b"sand_point"], "hub": [b"15"], "demand": [b"7.5"], "tank": [b"30"],
             "restart": [b"self"], "T_0": [b"0.3"]}  # fmt: skip
    app = Explorer(query=query)
    assert app.site_inputs.values() == {
        "site": "sand_point", "restart": "self", "hub": 15.0, "demand": 7.5, "tank": 30.0,
    }  # fmt: skip
    assert not app.notices.visible
    linked = app.link_query()
    for part in ("site=sand_point", "hub=15", "demand=7.5", "tank=30", "restart=self", "T_0=0.3"):
        assert part in linked.split("&")
    assert Explorer(query={"demand": [b"10"]}).link_query() == ""  # defaults left out
    tampered = Explorer(query={"site": [b"atlantis"], "tank": [b"-1"], "demand": [b"2.04"]})
    assert tampered.notices.visible
    assert "Site (site) = “atlantis” ignored" in tampered.notices.object
    assert "Tank [m³] (tank) = “-1” ignored" in tampered.notices.object
    assert "demand" not in tampered.notices.object  # off its slider's step, taken as written
    assert tampered.site_inputs.site == "greensboro" and tampered.site_inputs.demand == 2.04
    assert tampered.link_query() == "demand=2.04"
    uploaded = Explorer(query={"site": [b"uploaded"]})
    assert "upload it again" in uploaded.notices.object
    reset = Explorer(query=query)
    reset.reset()
    assert reset.link_query() == ""


class Location(param.Parameterized):
    """What a served page's ``pn.state.location`` offers its link."""

    search = param.String("")


def test_the_page_link_follows_a_site_control():
    app = Explorer()
    location = Location()
    app.follow_in_link(location)
    app.site_inputs.tank = 20.0
    assert location.search == "?tank=20"


def hourly_csv(days: int, speed=lambda h: 5.0 + 2.0 * math.sin(h / 7.0)) -> bytes:
    start = datetime.datetime(2026, 1, 1)
    rows = "".join(
        f"{start + datetime.timedelta(hours=h):%Y-%m-%dT%H:%M},{speed(h):.3f}\n"
        for h in range(24 * days)
    )
    return ("time,V [m/s]\n" + rows).encode()


def test_an_uploaded_file_is_the_site_and_a_bad_one_changes_nothing(app):
    import pvlib  # the shipped Greensboro year, uploaded as a file

    tmy3 = (Path(pvlib.__file__).parent / "data" / "723170TYA.CSV").read_bytes()
    app.site.upload.param.update(value=tmy3, filename="greensboro.csv")
    assert app.site_inputs.site == "uploaded" and not app.site.upload_message.visible
    _, supplied = year()
    check_drawn(app, supplied, 5.0)
    assert "Uploaded" in " ".join(app.site.site_select.options)
    drawn = value(app, "site_lolp"), np.array(data(app, "monthly")["pumped"])
    for bad, said in (
        (b"t,V\n0,5\n3600,-3\n", "line 3"),
        (b"", "empty"),
    ):
        app.site.upload.param.update(value=bad, filename="bad.csv")
        assert app.site.upload_message.visible and said in app.site.upload_message.object
        assert app.site_inputs.site == "uploaded"
        assert value(app, "site_lolp") == drawn[0]
        np.testing.assert_array_equal(data(app, "monthly")["pumped"], drawn[1])
    assert app.sidebar.reveal.value.split("\t")[0] in app.site.upload_message.css_classes


def test_an_empty_weather_file_is_refused_with_what_it_needs(app):
    """The core's sentence, shown as it is: the formats and the CSV's two columns."""
    app.site.upload.param.update(value=b"", filename="empty.csv")
    message = app.site.upload_message
    assert message.visible and message.object.startswith("This weather file cannot be used: ")
    assert "TMY3 or EPW" in shown(message) and "wind speed [m/s]" in shown(message)
    assert "time [s] or an ISO timestamp" in shown(message)


def test_a_csv_of_timestamps_is_a_site_too(app):
    app.site.upload.param.update(value=hourly_csv(60), filename="mast.csv")
    assert app.site_inputs.site == "uploaded", app.site.upload_message.object
    assert "mast" in app.site.note.object
    assert len(data(app, "level")["t"]) == 60
    assert data(app, "monthly")["month"] == ["Jan", "Feb", "Mar"]  # the months it holds


def test_a_file_the_page_refused_is_reported_in_the_site_tab(app):
    app.sidebar.refused_upload.value = f"{12_000_000}\t1\tsite\tyear.epw"
    message = app.site.upload_message
    assert message.visible and "12,000,000 bytes" in message.object
    # one pair of brackets: "(a year of hourly weather (a TMY3 or EPW file is about 1.5 MB))" read
    # as a slip; and the core's own refusal says what the file holds in one clause too
    assert message.object.endswith(
        "(a year of hourly weather, a TMY3 or EPW file, is about 1.5 MB)."
    )
    with pytest.raises(LabDataError, match=r"\(a year of hourly weather needs far fewer\)$"):
        read_upload(b"0" * 10_000_001, "year.csv")
    assert not app.wind_tab.built and not app.sidebar.lab.message.visible
    assert app.sidebar.reveal.value.split("\t")[0] in message.css_classes


def test_served_a_new_sites_year_is_said_and_computed_off_the_event_loop(app, monkeypatch):
    """Served, a year asked for is said first ("Computing the water…") and computed in a thread
    of ``serving``'s pool while the event loop goes on; it is drawn back on the loop, in the
    document's next tick (the real ``off_the_loop``, not a stand-in)."""
    import asyncio
    import threading

    from bokeh.document import Document

    document = Document()
    document._session_context = lambda: object()  # as a served session's document
    ticks = []
    monkeypatch.setattr(document, "add_next_tick_callback", ticks.append)
    monkeypatch.setattr(pn.state, "_curdoc", pn.state._curdoc)
    threads = []  # where the core's year runs
    supply = windpump.supply

    def recorded(*args, **kwargs):
        threads.append(threading.current_thread().name)
        return supply(*args, **kwargs)

    monkeypatch.setattr(windpump, "supply", recorded)
    lolp = value(app, "site_lolp")

    async def served() -> None:
        app.site_inputs.site = "sand_point"
        assert app.site.computing.visible and value(app, "site_lolp") == lolp  # said, not done
        for _ in range(6000):  # the loop turns while the year is computed (a minute at most)
            if ticks:
                return
            await asyncio.sleep(0.01)

    pn.state.curdoc = document
    try:
        asyncio.run(served())
        assert threads and all(name.startswith("heavy work") for name in threads), threads
        assert len(ticks) == 1 and app.site.computing.visible
        ticks.pop()()  # on the loop, under the document's lock
    finally:
        pn.state.curdoc = None
    assert not app.site.computing.visible and not app.site.error.visible
    _, supplied = year(site="sand_point")
    check_drawn(app, supplied, 5.0)
    assert value(app, "site_lolp") != lolp


@pytest.fixture
def held(monkeypatch):
    """The Site tab's work held as (work, then) pairs, as the thread pool would run them."""
    from windpump_app import site_tab

    pairs: list = []
    monkeypatch.setattr(site_tab, "off_the_loop", lambda work, then: pairs.append((work, then)))
    return pairs


def finish(pair) -> None:
    """A held (work, then) run as ``serving.off_the_loop`` does: an exception is the outcome."""
    work, then = pair
    try:
        outcome = work()
    except Exception as error:
        outcome = error
    then(outcome)


def test_served_a_year_runs_off_the_loop_says_so_and_the_newest_wins(held):
    """Served, the year runs off the event loop: the tab says it is computing, its figures have
    ranges meanwhile, and when two years come back in the wrong order only the newer is drawn.
    A year that cannot run says why and keeps the one drawn; back to it, nothing is run again."""
    app = Explorer()
    app.main().active = SITE_TAB
    assert (
        len(held) == 1
        and app.site.computing.visible
        and app.site.readouts["site_lolp"].object == ""
    )
    for name, x in (("level", "t"), ("lolp", "tank")):  # flat placeholders: ranges, no water
        assert len(data(app, name)[x]) == 2 and data(app, name)[x][0] < data(app, name)[x][1]
    assert not np.any(data(app, "monthly")["pumped"]) and len(data(app, "monthly")["month"]) == 12
    assert not app.site.status.visible  # no empty box
    app.site_inputs.param.update(site="sand_point", demand=8.0)  # before the first came back
    assert len(held) == 2 and app.site.computing.visible
    finish(held[1])
    assert not app.site.computing.visible and app.site.status.visible
    finish(held[0])  # Greensboro's year, late: not drawn over Sand Point's
    record, supplied = year(site="sand_point", demand=8.0)
    check_drawn(app, supplied, 5.0)
    smallest = windpump.tank_for(SEED, record, 8.0, 0.05, restart="attended")
    assert value(app, "tank_for_5") == f"{smallest:,.1f} m³"
    assert "Sand Point" in app.site.note.object
    app.site_inputs.site = "uploaded"  # no file yet: the year cannot run
    assert len(held) == 3 and app.site.computing.visible
    finish(held[2])
    assert app.site.error.visible and not app.site.computing.visible
    assert app.site.error.object.startswith("The year cannot be run: no file has been uploaded")
    check_drawn(app, supplied, 5.0)  # the year drawn stays
    app.site_inputs.site = "sand_point"  # the year drawn: nothing to run, the error gone
    assert len(held) == 3 and not app.site.error.visible and not app.site.computing.visible
    app.site_inputs.demand = 9.0
    app.site_inputs.demand = 7.0
    skipped = held[3][0]()  # 9's year, started after 7's was asked for: not run
    assert skipped is SUPERSEDED
    app.site_inputs.demand = 9.0  # asked for again before that came back: its own run draws
    held[3][1](skipped)
    assert app.site.computing.visible and not app.site.error.visible
    finish(held[5])
    finish(held[4])  # 7's year, late
    check_drawn(app, year(site="sand_point", demand=9.0)[1], 5.0)


def test_served_the_first_year_places_the_tab_with_its_readouts_then_its_figures(held, monkeypatch):
    """Served, a first open's content is held until its year has come and is then placed with
    its readouts (no "computing" note or empty readouts first), and the figures a tick later,
    with that year's data. A browser builds a tab's views before it reads the next message, and
    lays out every built tab at each change: the readouts waited for the three figures' views
    and for a layout per change, 1.3-2.1 s alone and 7-12 s with three tabs built (issue 37)."""
    from windpump_app import site_tab

    ticks: list = []
    monkeypatch.setattr(site_tab, "later", ticks.append, raising=False)
    app = Explorer()
    strip = app.main()
    strip.active = SITE_TAB

    def placed() -> list:
        return [pane.object for pane in strip.objects[SITE_TAB].select(pn.pane.Bokeh)]

    assert len(held) == 1 and app.site.computing.visible
    waiting = strip.objects[SITE_TAB]  # the content held for its year
    assert isinstance(waiting, pn.pane.Markdown) and waiting.object == app.site.waiting
    finish(held.pop())
    _, supplied = year()
    content = strip.objects[SITE_TAB]
    assert app.site.readouts["site_lolp"] in content.objects[0].objects  # placed, with numbers
    assert value(app, "site_lolp") == f"{100 * supplied.lolp:.1f} %"
    assert not app.site.computing.visible
    assert placed() == [] and len(ticks) == 1  # the figures on the next tick
    ticks.pop()()
    assert placed() == app.site.figures()
    check_drawn(app, supplied, 5.0)
    app.site_inputs.demand = 8.0  # later years: drawn in the figures placed
    finish(held.pop())
    assert not ticks and placed() == app.site.figures()
    check_drawn(app, year(demand=8.0)[1], 5.0)


def test_while_its_part_compiles_the_tab_is_placed_at_once_saying_so(held):
    """On a first start the year waits for its part of the solver: the tab is placed at once
    (not held for its year), its note saying that the solver is compiling."""
    from windpump_app.compiling import COMPILE
    from windpump_app.compiling import SITE_TAB as PART

    COMPILE.begin([PART])
    try:
        app = Explorer()
        strip = app.main()
        strip.active = SITE_TAB
        assert app.site.computing in strip.objects[SITE_TAB].objects
        assert app.site.computing.visible and "ompiling the solver" in app.site.computing.object
    finally:
        COMPILE.done(PART)
    finish(held.pop())
    assert not app.site.computing.visible
    assert value(app, "site_lolp") == f"{100 * year()[1].lolp:.1f} %"


def test_served_the_figures_wait_for_the_page_to_paint_the_readouts(monkeypatch):
    """Served, ``AfterPaint`` asks the page (value 1) and runs what waits once the page answers
    (2, set by its script after the next paint), once, or after FIGURES_AFTER at the latest (a
    timeout callback): a message sent behind the readouts kept chromium from painting them
    until it had built the figures (~2.7 s with three tabs built before, issue 37)."""
    from windpump_app import site_tab

    timeouts = []

    class Document:
        def add_timeout_callback(self, callback, ms):
            timeouts.append((callback, ms))

    monkeypatch.setattr(site_tab, "served_document", Document)
    ran = []
    after = site_tab.AfterPaint()
    assert not after.visible and "requestAnimationFrame" in site_tab.AFTER_PAINT_JS
    after.ask(lambda: ran.append(1))
    assert after.value == 1 and ran == [] and timeouts[0][1] == site_tab.FIGURES_AFTER
    after.value = 2  # the page painted
    assert ran == [1]
    after.value = 1
    after.value = 2  # asked by nobody: nothing runs again
    assert ran == [1]


def test_a_first_year_that_cannot_run_still_places_the_tab_and_its_figures(held, monkeypatch):
    """A first year that cannot run places the tab all the same, saying why, and its figures
    (in-process ``later`` runs at once), with their placeholder ranges."""
    from windpump_app import site_tab

    def refused(*_args):
        raise ValueError("hub must be at most 60 m, got 99")

    monkeypatch.setattr(site_tab, "run_year", refused)
    app = Explorer()
    strip = app.main()
    strip.active = SITE_TAB
    finish(held.pop())
    assert app.site.error.visible and "hub must be at most 60 m" in app.site.error.object
    assert app.site.error in strip.objects[SITE_TAB].objects
    figures = [pane.object for pane in strip.objects[SITE_TAB].select(pn.pane.Bokeh)]
    assert figures == app.site.figures()


def test_served_an_upload_is_read_off_the_loop_and_the_newest_file_wins(held):
    """Served, a weather file is read off the event loop, the tab saying so; of two files chosen
    one after the other, the later one's is the site even when the earlier is read last, and a
    refused file is said and changes nothing."""
    app = Explorer()
    app.main().active = SITE_TAB
    finish(held.pop())  # Greensboro's year
    app.site.upload.param.update(value=hourly_csv(3), filename="three.csv")
    message = app.site.upload_message
    assert message.visible and message.alert_type == "info" and "three.csv" in shown(message)
    app.site.upload.param.update(value=hourly_csv(5), filename="five.csv")
    assert len(held) == 2 and app.site_inputs.site == "greensboro"  # nothing read yet
    finish(held[1])  # five days
    assert app.site_inputs.site == "uploaded" and not message.visible
    assert len(held) == 3  # the five days' year, asked for
    finish(held[0])  # three days, the earlier file, late: not the site
    assert "Uploaded: five" in app.site.site_select.options
    assert "Uploaded: three" not in app.site.site_select.options
    finish(held[2])
    record = windpump.read_weather(hourly_csv(5)).at_height(10.0)
    supplied = windpump.supply(SEED, record, 10.0, 5.0, restart="attended")
    np.testing.assert_array_equal(data(app, "monthly")["pumped"], supplied.monthly.pumped)
    assert len(data(app, "level")["t"]) == 5 and supplied.hours == 5 * 24
    assert value(app, "site_lolp") == f"{100 * supplied.lolp:.1f} %"
    assert "five" in app.site.note.object
    app.site.upload.param.update(value=b"t,V\n0,5\n3600,-3\n", filename="bad.csv")
    assert message.alert_type == "info"
    finish(held[3])
    assert message.visible and message.alert_type == "danger" and "line 3" in message.object
    assert app.site_inputs.site == "uploaded" and len(held) == 4  # no year asked: none changed
    assert value(app, "site_lolp") == f"{100 * supplied.lolp:.1f} %"


def test_the_link_remembers_the_tab_both_ways():
    """``tab=site`` (etc.) opens the page on that tab, the pump's tab (the default) left out; a
    click on a tab is written into a served page's link."""
    from windpump_app.link import TABS

    app = Explorer(query={"tab": [b"site"], "site": [b"sand_point"]})
    location = Location()
    app.follow_in_link(location)  # as main.py: before the page (and its tabs) is built
    tabs = app.main()
    assert tabs.active == SITE_TAB and app.site_tab.built and not app.notices.visible
    assert app.link_query().split("&") == ["site=sand_point", "tab=site"]
    tabs.active = 2
    assert location.search == "?site=sand_point&tab=wind"
    tabs.active = 0
    assert location.search == "?site=sand_point"
    for index, name in enumerate(TABS, start=1):
        opened = Explorer(query={"tab": [name.encode()]})
        assert opened.main().active == index and opened.link_query() == f"tab={name}"
    wrong = Explorer(query={"tab": [b"nowhere"]})
    assert wrong.main().active == 0 and wrong.link_query() == ""
    assert "Tab (tab) = “nowhere” ignored" in wrong.notices.object


def test_every_tabs_readouts_grow_with_presentation_mode(app):
    """Presentation mode sets the page's zoom in the browser (styles.ZOOM_JS): a readout's label
    and value are sized by it, the Site and Wind tabs' as the pump's (their sizes were fixed)."""
    import re

    from windpump_app.styles import ZOOM_VARIABLE

    readouts = [*app.readouts.readouts.values(), *app.site.readouts.values()]
    readouts += app.wind.readouts.values()
    for readout in readouts:
        css = "".join(readout.stylesheets)
        for part in ("label", "value"):
            size = re.search(rf"\.readout \.{part} \{{font-size: ([^;]*);", css).group(1)
            assert ZOOM_VARIABLE in size, (readout.readout_name, part, size)


def test_a_month_without_a_shortfall_draws_no_short_bar(app):
    """A month whose demand is all delivered has no short bar: not a bar of no height, whose
    outline was a line across the month's delivered bar."""
    app.set_values(T_0=0.3)
    app.site_inputs.param.update(hub=15.0, demand=1.0, tank=10.0, restart="self")
    _, supplied = year(
        design=SEED.with_ratios(T_0=0.3), hub=15.0, demand=1.0, tank=10.0, restart="self"
    )
    table = supplied.monthly
    met = table.shortfall == 0.0
    assert met.any() and (~met).any()  # the case: months with and without a shortfall
    drawn = data(app, "monthly")
    assert np.isnan(np.asarray(drawn["short_top"], float)[met]).all()  # nothing to draw
    (short,) = [
        r for r in app.site.monthly.renderers if getattr(r.glyph, "bottom", None) == "delivered"
    ]
    (delivered,) = [
        r for r in app.site.monthly.renderers if getattr(r.glyph, "top", None) == "delivered"
    ]
    for bar in (short, delivered):  # filled, never outlined: no height draws nothing
        assert bar.glyph.line_color is None and bar.glyph.fill_color is not None


def test_the_server_reads_the_first_site_tabs_record_as_it_starts(monkeypatch):
    """``app_hooks.warm_the_site_tab`` (run as the server starts) reads the default site's record
    at the default hub, pvlib and pandas imported then: the first page to open the Site tab reads
    no file (it waited seconds for their import on a busy server) and shows the core's year."""
    from windpump_app import app_hooks, site_record

    _record, expected = year()  # read here, before the file is taken away
    site_record.sample_at.cache_clear()
    site_record.sample.cache_clear()
    app_hooks.warm_the_site_tab()

    def no_file(name):
        raise AssertionError(f"the record of {name} was read again")

    monkeypatch.setattr(windpump, "sample_site", no_file)
    app = Explorer()
    app.main().active = SITE_TAB
    assert value(app, "site_lolp") == f"{100 * expected.lolp:.1f} %"


def gallons_per_m3() -> float:
    """[gal/m³] by pint's own registry (the US liquid gallon, 231 in³), not the package's."""
    import pint

    return float(pint.UnitRegistry().Quantity(1.0, "m**3").to("gallon").magnitude)


def test_in_us_units_the_site_tab_says_gallons_and_redraws_in_place(app):
    """The units switch on US: the year's readouts, the sliders' titles, the figures' axes and
    hovers and their data in gallons; back on SI, the same figures and sources hold the core's
    m³ again (nothing is built anew)."""
    site = app.site
    figures, sources = site.figures(), dict(site.sources)
    record, supplied = year()
    gal = gallons_per_m3()
    app.sidebar.units_switch.value = "us"
    totals = supplied.totals
    assert "[gal/year]" in site.readouts["site_water"].object
    assert value(app, "site_water") == f"{gal * totals.pumped:,.0f} · {gal * totals.delivered:,.0f}"
    smallest = windpump.tank_for(SEED, record, 10.0, 0.05, restart="attended")
    assert value(app, "tank_for_5") == f"{gal * smallest:,.0f} gal"
    monthly = data(app, "monthly")
    for column in ("pumped", "demand", "delivered", "shortfall"):
        expected = gal * np.asarray(getattr(supplied.monthly, column))
        np.testing.assert_allclose(monthly[column], expected, rtol=1e-12)
    days = np.asarray(supplied.level).reshape(365, 24)
    np.testing.assert_allclose(data(app, "level")["mean"], gal * days.mean(axis=1), rtol=1e-12)
    assert data(app, "lolp_here")["tank"] == [pytest.approx(5.0 * gal, rel=1e-12)]
    assert site.tank_line.location == pytest.approx(5.0 * gal, rel=1e-12)
    labels = [site.monthly.yaxis[0].axis_label, site.level.yaxis[0].axis_label]
    labels.append(site.lolp.xaxis[0].axis_label)
    assert labels == ["water [gal]", "water in the tank [gal]", "tank [gal]"]
    tips = [
        text for fig in figures for hover in fig.select(HoverTool) for _, text in hover.tooltips
    ]
    assert any(text.endswith(" gal") for text in tips) and not any("m³" in t for t in tips)
    # the sliders show the US value first, then their own (the link's): the browser writes it
    # as the thumb moves (test_browser_site), by pint's factor
    demand, tank, hub = (site.sliders[name] for name in ("demand", "tank", "hub"))
    assert (demand.name, tank.name, hub.name) == ("Demand", "Tank", "Hub height")
    shown = {name: site.sliders[name].format.args for name in ("demand", "tank", "hub")}
    assert shown["demand"]["factor"] == pytest.approx(gal, rel=1e-12)  # [gal/day per m³/day]
    assert (shown["demand"]["unit"], shown["demand"]["si_unit"]) == ("gal/day", "m³/day")
    assert shown["tank"]["factor"] == pytest.approx(gal, rel=1e-12)
    assert (shown["tank"]["unit"], shown["tank"]["si_unit"]) == ("gal", "m³")
    assert shown["hub"]["factor"] == pytest.approx(1 / 0.3048, rel=1e-12)  # [ft/m]
    assert (shown["hub"]["unit"], shown["hub"]["si_unit"]) == ("ft", "m")
    assert f"the hub at {10.0 / 0.3048:.1f} ft." in site.note.object
    app.site_inputs.tank = 7.5  # a move: the year is drawn in gallons
    assert site.tank_line.location == pytest.approx(7.5 * gal, rel=1e-12)
    app.sidebar.units_switch.value = "si"
    check_drawn(app, year(tank=7.5)[1], 7.5)
    assert value(app, "tank_for_5") == f"{smallest:,.1f} m³"
    assert site.lolp.xaxis[0].axis_label == "tank [m³]" and tank.format == "0.0"
    assert tank.name == "Tank [m³]" and demand.name == "Demand [m³/day]"
    assert "the hub at 10 m." in site.note.object
    assert all(a is b for a, b in zip(site.figures(), figures, strict=True))
    assert all(site.sources[name] is source for name, source in sources.items())


def test_a_page_opened_in_us_units_draws_its_first_year_in_gallons():
    app = Explorer(query={"units": [b"us"]})
    app.main().active = SITE_TAB
    _, supplied = year()
    gal = gallons_per_m3()
    np.testing.assert_allclose(
        data(app, "monthly")["pumped"], gal * np.asarray(supplied.monthly.pumped), rtol=1e-12
    )
    assert app.site.level.yaxis[0].axis_label == "water in the tank [gal]"
    assert app.site.sliders["demand"].format.args["unit"] == "gal/day"
