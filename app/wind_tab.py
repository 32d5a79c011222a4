"""The Wind tab: the pump at a site, from its steady-wind curve to a gusty day run in full.

Two views and a day: water against steady wind (``windpump.steady_flow``) with V_stop, V_start
and the site's Weibull density; and a day of wind (a gusty record drawn from the site's Weibull
wind, or a measured CSV) integrated in full by ``windpump.simulate``: its V(t), crank speed and
cumulative litres with stops and starts marked, and its litres a day beside the averaged bounds.
Every number comes from ``windpump``.
"""

from __future__ import annotations

import functools
import logging
import math

import numpy as np
import panel as pn
from bokeh.models import ColumnDataSource

import windpump
from windpump.model.wind import gusty, read_csv
from windpump.readers.labdata import LabDataError, check_file_size
from windpump.readers.quantities import display_unit
from windpump.sites.site import kick_in_wind
from windpump.units import LITRES_PER_M3, SECONDS_PER_DAY

from .buttons import ActionButton
from .compiling import COMPILE, REAL_IN_WIND, WIND_TAB
from .envelope import band
from .escape import as_text
from .figures import palette
from .inputs import clipped
from .readouts import PAIR, Readout
from .server.api import Newest, in_a_process, mark, off_the_loop
from .styles import CAPTION_CSS, TEXT
from .tab import Tab
from .uploads import (
    WIND_CLASS,
    WIND_MAX_BYTES,
    WIND_SIZE,
    Encoded,
    FileUpload,
    Reveal,
    chosen,
    decoded,
    refused_size,
    sending_note,
)
from .views import refill
from .wind_figures import a_day, curve_figure, day_figures, label_day, time_unit
from .wind_steady import steady_wind

log = logging.getLogger("windpump.app")

# The averaged theory's two bounds (windpump.record_water, water_per_day) are two answers to one
# question, said as such: the water if the pump must start from rest in each wind, and once
# running ("0 … 30,098" read as a range of unknown meaning).
BOUNDS = "from rest · once running"
WIND_READOUTS = {
    "day_litres": "This day, in full [L/day]",
    "record_bounds": f"Averaged over this day's wind [L/day], {BOUNDS}",
    "site_bounds": f"Averaged over the site's Weibull wind [L/day], {BOUNDS}",
    "thresholds": "V_stop · V_start [m/s]",
}
BOUNDS_TIP = (
    "The averaged theory's water a day. From rest: counting only the winds above V_start, in "
    "which the pump starts on its own (0 without torque at rest, T₀ = 0). Once running: counting "
    "every wind above V_stop, in which a turning pump keeps turning. Three significant figures: "
    "the averaged theory is no closer than that."
)


def three_figures(value: float) -> str:
    """A number to three significant figures, with the page's thousands separator.

    >>> three_figures(30_098.4), three_figures(1_234_567.0), three_figures(45.67), three_figures(0.0)
    ('30,100', '1,230,000', '45.7', '0')
    >>> three_figures(0.012345)
    '0.0123'
    """
    if value == 0.0 or not math.isfinite(value):
        return f"{value:g}"
    decimals = 2 - math.floor(math.log10(abs(value)))
    rounded = round(value, decimals)
    return f"{rounded:,.{max(decimals, 0)}f}"


def bounds_text(low: float, high: float) -> str:
    """The averaged theory's (from rest, once running) water a day [L/day], as the readout says it.

    >>> bounds_text(0.0, 30_098.4)
    '0 · 30,100'
    """
    return f"{three_figures(low)} · {three_figures(high)}"


# An upload's outcome, by the CSS class that scrolls it into view (uploads.Reveal)
WIND_MESSAGE, WIND_DAY_NOTE = "wind-message", "wind-day-note"


@functools.lru_cache(maxsize=8)
def gusty_day(mean_wind: float, k: float, time_scale: float, seed: int):
    """A day of gusty wind at one sample a second (kept: a pump slider move reuses it)."""
    return gusty(mean_wind, SECONDS_PER_DAY, k=k, time_scale=time_scale, seed=seed)


def duration_text(seconds: float) -> str:
    """A record's length as a person says it: "3 h 0 min", "45 min", "12.5 days"."""
    minutes = round(seconds / 60.0)
    if minutes >= 2 * 24 * 60:
        return f"{seconds / SECONDS_PER_DAY:.1f} days"
    hours, minutes = divmod(minutes, 60)
    return f"{hours} h {minutes} min" if hours else f"{minutes} min"


def times(count: int) -> str:
    """A count of events in words: "once", "twice", "3 times"."""
    return {1: "once", 2: "twice"}.get(count, f"{count} times")


def stops_and_starts(stops: int, starts: int) -> str:
    """How often a day's pump stops and starts again, in words.

    >>> stops_and_starts(0, 0), stops_and_starts(1, 0), stops_and_starts(3, 2)
    ('never stops', 'stops once and never starts again', 'stops 3 times and starts again twice')
    """
    if stops == 0 and starts == 0:
        return "never stops"
    again = f"starts again {times(starts)}" if starts else "never starts again"
    return f"stops {times(stops)} and {again}" if stops else again


def is_a_day(duration: float) -> bool:
    """Whether a record [s] is a day long (to the minute): its litres are then a day's."""
    return a_day(duration)


def record_water_text(
    litres: float, per_day: float, duration: float, system: str = "si"
) -> tuple[str, str]:
    """The day_litres readout's (label, value): a day's litres for a record of a day; for a
    shorter or longer record its own litres, over its length, and the rate a day that makes (so
    three hours' water is not read as a day's). In US units (``system``), gallons: ``litres``
    and ``per_day`` are then gallons and gallons a day."""
    water = "gal" if system == "us" else "L"
    if is_a_day(duration):
        return in_units(WIND_READOUTS["day_litres"], system), f"{litres:,.0f}"
    return (
        f"This record ({duration_text(duration)}), in full",
        f"{litres:,.0f} {water} ({per_day:,.0f} {water}/day at this rate)",
    )


def in_units(label: str, system: str) -> str:
    """A readout's label in the units of ``system``: the SI labels' L/day and m/s, or gal/day
    and mph."""
    if system != "us":
        return label
    return label.replace("[L/day]", "[gal/day]").replace("[m/s]", "[mph]")


def water_factor(system: str) -> float:
    """[shown unit / m^3] litres, or in US units gallons (``windpump.readers.quantities``)."""
    return display_unit("volume", system)[0] if system == "us" else LITRES_PER_M3


def wind_factor(system: str) -> float:
    """[shown unit / (m/s)] 1, or in US units mph."""
    return display_unit("wind speed", system)[0]


def read_record(data: bytes | Encoded) -> windpump.model.wind.WindRecord | str:
    """A wind CSV read (served, in the file-reading process: ``serving.in_a_process``), or the
    sentence that refuses it (its size, its content, its length)."""
    try:
        data = decoded(data)
        check_file_size(len(data), WIND_MAX_BYTES, what="a year of wind at one sample a minute")
        record = in_a_process(read_csv, data)
    except LabDataError as error:
        return f"This wind file cannot be used: {as_text(error)}"
    if record.t[-1] > 400 * SECONDS_PER_DAY:
        return "This wind file is longer than 400 days; cut it shorter."
    return record


def _same_day(a: tuple, b: tuple) -> bool:
    """Whether two (design, wind, theta0, kick) describe the same run: the wind a measured
    record (by identity: it is kept) or a gusty day's key (by value: ``wind_of``)."""
    return (
        len(a) == len(b) == 4
        and a[0] == b[0]
        and (a[1] is b[1] or (isinstance(a[1], tuple) and a[1] == b[1]))
        and a[2:] == b[2:]
    )


def wind_of(wind: windpump.model.wind.WindRecord | tuple) -> windpump.model.wind.WindRecord:
    """The record a day runs in: the measured one, or the gusty day of a key (mean wind, k,
    time scale, seed), made off the event loop (~0.4 s) and kept."""
    return wind if isinstance(wind, windpump.model.wind.WindRecord) else gusty_day(*wind)


def run_day(design, record, theta0: float, kick: float) -> tuple:
    """The day in ``record`` and the water its wind gives by the averaged theory: (day, low,
    high), all of it the core's, off the event loop."""
    # a first start compiles it in a worker: not a second time here
    COMPILE.wait(WIND_TAB if design.is_ideal else REAL_IN_WIND)
    return (
        windpump.run_in_wind(design, record, theta0, kick),
        *windpump.record_water(design, record),
    )


def warm_up(inputs) -> None:
    """What the first Wind tab a server shows runs, for ``inputs`` (a page's, ``PumpInputs``):
    its steady-wind curve and its gusty day, run once when the server starts
    (``app_hooks.on_server_loaded``). The modules they import (scipy's special functions,
    integration and signal processing) and the kernels of a run in a wind record, loaded from
    numba's cache, are then the server's from its start: the first student who opens the tab
    waits for none of them, and none is made in the middle of a class, among its pages' objects,
    whose memory a module kept for ever would pin once they are freed. The day is kept
    (``gusty_day``): the first page asks for the same one."""
    design = inputs.design_at_v_ref()
    steady_wind(design, inputs.mean_wind, inputs.k, inputs.V)
    day = (inputs.mean_wind, inputs.k, inputs.time_scale, int(round(inputs.seed)))
    run_day(design, wind_of(day), inputs.theta0, kick_in_wind(design, inputs.theta_dot0))


class WindTab(Tab):
    """The Wind tab: the design at V_ref (its sliders' curve) under the wind inputs; the design
    in the steady wind is ``design.in_wind(inputs.V)``."""

    title, waiting = "Wind", "Running a day of wind…"

    def __init__(self, inputs, sliders: dict, bins: int | None, reveal: Reveal, dark=False):
        super().__init__(dark)
        self.inputs = inputs
        self.sliders = sliders
        self.bins = bins
        self.reveal = reveal  # scrolls an upload's outcome into view
        self.system = "si"  # the readouts' units (the page's units switch)
        self._said: dict[str, tuple] = {}  # what the readouts say, in SI, to say again in US units

    def build(self) -> None:
        self.colors = palette(self.dark)
        self.measured: windpump.model.wind.WindRecord | None = None
        self.measured_name = ""
        self.sources: dict[str, ColumnDataSource] = {}
        self.readouts = {name: Readout(name, css_classes=PAIR) for name in WIND_READOUTS}
        for name, label in WIND_READOUTS.items():  # laid out as they will be: their numbers come
            self.readouts[name].show(label, "…")  # from threads, and would shift the tab on a phone
        self.upload = FileUpload(
            "Measured wind",
            "a CSV of time [s] or ISO timestamp, wind speed [m/s]",
            accept=".csv,.txt,.tsv",
            css_classes=[WIND_CLASS],  # the page's size check knows it by this
            stylesheets=TEXT,
            sizing_mode="stretch_width",
        )
        self.upload_message = pn.pane.Alert(
            "", alert_type="danger", visible=False, stylesheets=TEXT, css_classes=[WIND_MESSAGE]
        )
        self.use_gusty = ActionButton(
            label="Back to the gusty day",
            visible=False,
            stylesheets=TEXT,
            sizing_mode="stretch_width",
        )
        self.day_note = pn.pane.Markdown(
            "", stylesheets=TEXT, sizing_mode="stretch_width", css_classes=[WIND_DAY_NOTE]
        )
        self.error = pn.pane.Alert("", alert_type="danger", visible=False, stylesheets=TEXT)
        self.curve, self.stop_span, self.start_span = curve_figure(self.sources, self.colors)
        self.day_wind, self.day_speed, self.day_litres, self.marker_items = day_figures(
            self.sources, self.colors
        )
        for name, source in self.sources.items():
            source.name = f"windtab_{name}"  # for a browser: get_model_by_name
        self.last_run: windpump.SimulationResult | None = None
        self._drawn_day: tuple = ()  # (design, record, theta0, kick) of last_run
        self._ready_day: tuple | None = None  # (run_of, (day, low, high)), run ahead with a file
        self._drawn_curve: tuple = ()  # (design, mean wind, k, V) of the curve drawn
        self.curves = Newest()  # and the one last asked for
        self.days = Newest(_same_day)  # (design, record, theta0, kick) of the day last asked for
        self.files = Newest()  # the file last chosen: its outcome is shown, not an earlier one's
        self.upload.param.watch(
            lambda *_e: self.load_data(chosen(self.upload)), ["value", "filename"]
        )
        self.use_gusty.on_click(lambda _e: self.forget_data())

    # -- updates -----------------------------------------------------------------------------

    def draw(self, seen: windpump.Exploration) -> None:
        """Redraw the curve and the day, run in full (about a second), for the wind inputs."""
        try:
            design = self.inputs.design_at_v_ref()
            self._update_curve(design, self.inputs)
            self._update_day(design, self.inputs)
        except ValueError as error:
            self.failed(f"The wind cannot be run: {as_text(error)}")

    def failed(self, message: str) -> None:
        self.error.object = message
        self.error.visible = True

    def _update_curve(self, design, inputs) -> None:
        """The steady wind's numbers (``wind_steady``), off the event loop when served; a newer
        request wins, and one the drawn curve already answers is not asked again."""
        asked = (design, inputs.mean_wind, inputs.k, inputs.V)
        self.curves.wanted = asked  # a curve in flight is superseded, by the one drawn too
        if asked == self._drawn_curve:
            return
        if not self._drawn_curve:  # a first curve: the figure gets ranges until it comes
            refill(self.sources["curve"], {"V": [0.0, 20.0], "flow": [0.0, 0.0]})

        self.curves.ask(
            asked,
            lambda: steady_wind(*asked),
            lambda outcome: self._draw_curve(asked, outcome),
            off_the_loop,
        )

    def _draw_curve(self, asked: tuple, outcome) -> None:
        if isinstance(outcome, Exception):
            said = str(outcome)
            if not isinstance(outcome, ValueError):  # a bug: say so, log it, keep the page alive
                log.error("the steady wind failed", exc_info=outcome)
                said = f"{type(outcome).__name__}: {outcome}"
            self.failed(f"The wind cannot be run: {as_text(said)}")
            return
        self._drawn_curve = asked
        steady, V = outcome, asked[3]
        refill(self.sources["curve"], {"V": steady.V, "flow": steady.flow})
        refill(self.sources["density"], {"V": steady.V, "density": steady.density})
        self.curve.extra_y_ranges["density"].end = 1.1 * float(np.max(steady.density))
        refill(self.sources["here"], {"V": [V], "flow": [steady.here]})
        self.stop_span.location = steady.V_stop
        self.start_span.location = steady.V_start if steady.V_start is not None else -1.0
        self.start_span.visible = steady.V_start is not None
        self._said["curve"] = (steady.V_stop, steady.V_start, steady.low, steady.high)
        self._say_curve()

    def _say_curve(self) -> None:
        """The steady winds' readouts (the stopping and starting winds [m/s], the site's water a
        day [L/day]) in the page's units."""
        V_stop, V_start, low, high = self._said["curve"]
        system, wind = self.system, wind_factor(self.system)
        water = water_factor(self.system) / LITRES_PER_M3
        start = f"{wind * V_start:.1f}" if V_start is not None else "never (T₀ = 0)"
        self.readouts["thresholds"].show(
            in_units(WIND_READOUTS["thresholds"], system), f"{wind * V_stop:.1f} · {start}"
        )
        self.readouts["site_bounds"].show(
            in_units(WIND_READOUTS["site_bounds"], system),
            bounds_text(water * low, water * high),
            BOUNDS_TIP,
        )

    def show_units(self, system: str) -> None:
        """The readouts in ``system``'s units ("si" or "us"), now and from now on."""
        self.system = system
        if self.built and "curve" in self._said:
            self._say_curve()
        if self.built and "day" in self._said:
            self._say_day()

    def wind(self, inputs) -> windpump.model.wind.WindRecord | tuple:
        """The day's wind: the measured record if one was loaded, else the gusty day's key
        (``wind_of`` makes it)."""
        if self.measured is not None:
            return self.measured
        return (inputs.mean_wind, inputs.k, inputs.time_scale, int(round(inputs.seed)))

    def _update_day(self, design, inputs) -> None:
        """Run the day (about a second; a week of measured wind, seconds) and draw it.

        Served, the run goes off the event loop (``serving.off_the_loop``, as an upload's), so
        the other pages' moves are answered meanwhile; the tab says it is working, and a run
        asked for since (a newer design or wind) wins (``serving.Newest``): an older day is never
        drawn over it, nor worked out once superseded."""
        wind = self.wind(inputs)
        # keyed by the kick the day gets: a windmill that starts on its own ignores the slider's
        run_of = (design, wind, inputs.theta0, kick_in_wind(design, inputs.theta_dot0))
        self.days.wanted = run_of  # a day in flight is superseded, by the one drawn too
        if self.last_run is not None and _same_day(run_of, self._drawn_day):
            return  # the steady wind V moved: the day, run at V_ref in its record, is as drawn
        source = (
            f"the measured record *{as_text(self.measured_name)}*"
            if self.measured is not None
            else f"a gusty day (seed {int(round(inputs.seed))})"
        )
        ready, self._ready_day = self._ready_day, None
        if ready is not None and _same_day(run_of, ready[0]):  # run off the loop with its record
            self._draw_day(run_of, source, ready[1])
            return
        part = WIND_TAB if design.is_ideal else REAL_IN_WIND
        self.day_note.object = COMPILE.waiting(part) or self.waiting
        if self.last_run is None:  # a first day: the figures get ranges until it comes
            duration = SECONDS_PER_DAY if self.measured is None else self.measured.t[-1]
            self._placeholder_day(float(duration))

        theta0, kick = inputs.theta0, inputs.theta_dot0  # as asked: the inputs move on

        self.days.ask(  # a day (~1 s) run for nobody would hold the pool from every page
            run_of,
            lambda: run_day(design, wind_of(wind), theta0, kick),
            lambda outcome: self._draw_day(run_of, source, outcome),
            off_the_loop,
        )

    def _placeholder_day(self, duration: float) -> None:
        """Flat, empty bands over the day, so that its figures have ranges before it is run
        (Bokeh cannot set the ranges of figures with no data)."""
        x = [0.0, duration / time_unit(duration)[0]]
        for name in ("wind", "speed"):
            refill(self.sources[name], {"t": x, "lower": [0.0, 0.0], "upper": [0.0, 0.0]})
        refill(self.sources["litres"], {"t": x, "litres": [0.0, 0.0]})

    def _draw_day(self, run_of: tuple, source: str, outcome) -> None:
        """Draw the day ``outcome`` = (day, low, high) of ``run_of`` (the newest asked for); a
        refused day says why."""
        if isinstance(outcome, ValueError):
            self.error.object = f"The day cannot be run: {as_text(outcome)}"
            self.error.visible = True
            return
        if isinstance(outcome, Exception):  # a bug: say so, log it, keep the session alive
            log.error("running a day of wind failed", exc_info=outcome)
            self.failed(f"The day cannot be run: {type(outcome).__name__}: {as_text(outcome)}")
            return
        day, low, high = outcome
        self.error.visible = False
        run, duration = day.run, day.duration
        self.last_run, self._drawn_day = run, run_of
        unit = time_unit(duration)[0]  # [s] hours, or days for a record of days
        t = run.t / unit
        self.day_wind.x_range.end = self.day_wind.x_range.start + duration / unit
        label_day(self.day_wind, self.day_speed, self.day_litres, duration)
        bins = self.bins
        for name, values in (("wind", run.wind_speed), ("speed", run.theta_dot)):
            x, lower, upper = band(t, values, bins)
            refill(self.sources[name], {"t": x, "lower": lower, "upper": upper})
        x, _, lifted = band(t, LITRES_PER_M3 * run.volume, bins)
        refill(self.sources["litres"], {"t": x, "litres": lifted})
        for kind, events in (("stops", day.stops), ("starts", day.starts)):
            refill(self.sources[f"{kind}_wind"], {"t": events.t / unit, "y": events.V})
            refill(
                self.sources[f"{kind}_litres"],
                {"t": events.t / unit, "y": LITRES_PER_M3 * events.volume},
            )
            self.marker_items[kind].visible = len(events) > 0
        self._said["day"] = (day.volume, day.per_day, low, high, duration)
        self._say_day()
        if self.measured is not None:
            source += f" ({duration_text(duration)})"
        start = "starts on its own" if day.kick == 0.0 else f"is kicked at {day.kick:g} rad/s"
        self.day_note.object = (
            f"Integrated in full over {source}: the pump {start}, "
            f"{stops_and_starts(len(day.stops), len(day.starts))}; "
            f"mean wind {day.mean_wind:.2f} m/s."
        )

    def _say_day(self) -> None:
        """The day's readouts (its water in full, the averaged bounds) in the page's units."""
        volume, per_day, low, high, duration = self._said["day"]
        water = water_factor(self.system)
        self.readouts["day_litres"].show(
            *record_water_text(water * volume, water * per_day, duration, self.system)
        )
        label = (
            WIND_READOUTS["record_bounds"]
            if is_a_day(duration)
            else f"Averaged over this record's wind [L/day], {BOUNDS}"
        )
        self.readouts["record_bounds"].show(
            in_units(label, self.system), bounds_text(water * low, water * high), BOUNDS_TIP
        )

    # -- a measured record -------------------------------------------------------------------

    def accept(self, record: windpump.model.wind.WindRecord | str, name: str) -> bool:
        """``record`` (read by ``read_record``) becomes the day's wind; a refusal is said."""
        self.upload_message.alert_type = "danger"
        if isinstance(record, str):
            self.upload_message.object = record
            self.upload_message.visible = True
            return False
        self.measured, self.measured_name = record, name or "uploaded"
        self.upload_message.visible = False
        self.use_gusty.visible = True
        return True

    def refuse_size(self, size: int) -> None:
        """The page stopped a wind file over the limit before sending it: say so here."""
        message = refused_size("wind", size, WIND_SIZE)
        if message is not None:
            self.say(message)

    def say(self, message: str, alert_type: str = "danger") -> None:
        """Say ``message`` under the upload (a refusal, a file on its way)."""
        self.upload_message.object, self.upload_message.alert_type = message, alert_type
        self.upload_message.visible = True

    def sending(self, name: str, size: int) -> None:
        """The page is sending the file ``name`` by HTTP (``upload_route``): say so; an earlier
        file's outcome, still to come, is not shown."""
        self.files.supersede()
        self.say(sending_note(name, size), "info")

    def forget(self) -> None:
        self.measured, self.measured_name = None, ""
        self.use_gusty.visible = False

    def load_data(self, data: bytes | Encoded | None, name: str | None = None) -> None:
        """A measured wind CSV for the day (``name``: the file's, else the upload's); a bad file
        is refused and the day stays as it was. Either outcome is scrolled into view; a file
        chosen since wins.

        Reading it and running the pump through it (seconds for a week of wind) happen off the
        server's event loop (``serving.off_the_loop``), so the other pages' moves are answered
        meanwhile; the tab says it is working until the day is drawn."""
        if data is None:
            return
        name = (self.upload.filename or "") if name is None else name
        # (its span is not known before it is read: "the day" was said over a week's record)
        self.say(f"Reading {clipped(name) or 'the file'} and running the pump through it…", "info")
        design, theta0, kick = (
            self.inputs.design_at_v_ref(),
            self.inputs.theta0,
            self.inputs.theta_dot0,
        )

        def work() -> tuple:
            record = read_record(data)
            if isinstance(record, str):
                return record, None
            try:
                run_of = (design, record, theta0, kick_in_wind(design, kick))
                mark("day: starting")
                day = run_day(design, record, theta0, kick)
                mark("day: run")
                return record, (run_of, day)
            except ValueError:  # the day's redraw says why
                return record, None

        self.files.ask(object(), work, lambda outcome: self._loaded(outcome, name), off_the_loop)

    def _loaded(self, outcome, name: str) -> None:
        if isinstance(outcome, Exception):  # a bug: say so, log it, keep the session alive
            log.error("reading a wind file failed", exc_info=outcome)
            outcome = (f"This wind file cannot be used: {type(outcome).__name__}: {outcome}", None)
        record, self._ready_day = outcome
        if self.accept(record, name):
            self.redraw()
            self.reveal.show(WIND_DAY_NOTE)
        else:
            self.reveal.show(WIND_MESSAGE)

    def forget_data(self) -> None:
        """Back to the gusty day."""
        self.forget()
        self.redraw()

    # -- layout ------------------------------------------------------------------------------

    def figures(self) -> list:
        return [self.curve, self.day_wind, self.day_speed, self.day_litres]

    def layout(self) -> pn.Column:
        def caption(text: str):
            return pn.pane.HTML(f"<p>{text}</p>", stylesheets=CAPTION_CSS)

        flex = {"flex": "1 1 460px", "min-width": "300px"}
        site = pn.Column(
            self.sliders["V"],
            pn.pane.Bokeh(self.curve, sizing_mode="stretch_width"),
            caption(
                "Mean flow m A R α₊(V)/π of the averaged theory in a steady wind (the rotor by "
                "similarity: torque ∝ V², speed ∝ V). Below V_stop (red) a running pump stops; "
                "above V_start (green, dashed) a resting one starts. Grey: the site's Weibull "
                "wind."
            ),
            sizing_mode="stretch_width",
            styles=flex,
        )
        day_controls = pn.Column(
            self.sliders["mean_wind"],
            self.sliders["k"],
            self.sliders["time_scale"],
            self.sliders["seed"],
            self.upload.heading,
            self.upload,
            self.upload_message,
            self.use_gusty,
            sizing_mode="stretch_width",
            styles=flex,
        )
        readouts = pn.FlexBox(*self.readouts.values(), sizing_mode="stretch_width")
        day = [
            pn.Column(
                pn.pane.Bokeh(fig, sizing_mode="stretch_width"),
                sizing_mode="stretch_width",
                styles=flex,
            )  # fmt: skip
            for fig in (self.day_wind, self.day_speed, self.day_litres)
        ]
        return pn.Column(
            readouts,
            self.error,
            pn.FlexBox(site, day_controls, flex_wrap="wrap", sizing_mode="stretch_width"),
            self.day_note,
            pn.FlexBox(*day, flex_wrap="wrap", sizing_mode="stretch_width"),
            caption(
                "The wind's run integrated in full (Eq. 12 with the curve following V(t)), a day's "
                "or a record's: a pump at rest waits until the windmill's torque at rest on the crank, "
                "R†T₀(V/V_ref)², beats the load at its "
                "angle. Red: stops; green: starts."
            ),
            sizing_mode="stretch_width",
        )
