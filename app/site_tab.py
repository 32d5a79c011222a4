"""The Site tab: the design on the sliders at a site for a year, with a demand and a tank.

A site's hourly wind (a record that ships with pvlib, or a TMY3, EPW or CSV file uploaded) at the
hub height, run through the quasi-steady year of ``windpump.supply``: the water pumped and
demanded month by month, the tank's level over the year, the loss-of-load probability against
tank size (``windpump.supply_map``) with this tank marked, and the year's readouts. Every number
comes from ``windpump``.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable

import numpy as np
import panel as pn
from bokeh.models import ColumnDataSource, CustomJSTickFormatter

import windpump

from .compiling import COMPILE, SITE_TAB
from .escape import as_text
from .figures import palette
from .keyboard import FOCUS_CSS
from .readouts import Readout
from .server.api import Newest, off_the_loop, served_document
from .sidebar import PromptSlider
from .site_figures import (
    level_figure,
    lolp_figure,
    monthly_figure,
    placeholder_year,
    say_water_in,
    show_level,
    show_monthly,
    shown_in,
    water_texts,
)
from .site_inputs import RESTARTS, SITES, UPLOADED, SiteInputs
from .site_record import SiteRecords, read_upload, span, supply_status
from .site_year import Asked, Year, run_year, tank_range
from .styles import CAPTION_CSS, COMPACT, TEXT
from .tab import Tab, later
from .uploads import Encoded, sending_note
from .viewport import PLACEHOLDER_CSS
from .views import refill

log = logging.getLogger("windpump.app")

SITE_READOUTS = {
    "site_water": "Pumped · delivered [{unit} over {span}]",  # "[m³/year]" for a year
    "site_lolp": "Loss of load",
    "dry_days": "Dry days",
    "dry_spell": "Longest dry spell",
    "tank_for_5": "Smallest tank for 5 %",
}
SITE_MESSAGE, SITE_NOTE = "site-message", "site-note"  # an upload's outcome (uploads.Reveal)
CAPTION = (
    "The design on the sliders in the site's hourly wind at the hub, hour by hour "
    "(the quasi-steady year: in each hour's wind the pump runs as the averaged theory "
    "says, stopping below V_stop). The tank takes what is pumped and gives the demand; "
    "the loss-of-load probability is the share of the demand it could not give, and a day "
    "short of water one with any. A month's pumped water cut at the top has its number "
    "written; the tank's water is each day's mean. Dashed: the tank's size, and 5 %."
)


COMPUTING = "**Computing the water at the site…**"
# Asked (1), the page answers (2) once it has painted what it was sent before: a frame's callback
# runs before that frame is painted, a timer set in it after.
AFTER_PAINT_JS = """
if (source.value === 1) {
  requestAnimationFrame(() => setTimeout(() => { source.value = 2 }))
}
"""
FIGURES_AFTER = 5000  # [ms] the figures placed anyway (a page in a hidden browser tab paints none)
CONTROLS_CLASS, SLOT_CLASS = "site-controls", "site-figure-slot"  # for a browser test
SLOT_TITLES = ("the water each month", "the tank over the year", "the loss-of-load curve")
# The sliders' kinds of quantity (``windpump.readers.quantities.KINDS``): in US units each shows
# its value in feet or gallons first, then as it moves (in the core's units, the link's).
SLIDER_FORMAT = "0.0"  # the sliders' values as shown in SI (Panel's numbro format)
SLIDER_KINDS = {"hub": "height", "demand": "daily flow", "tank": "tank"}
US_DECIMALS = {"height": 1, "daily flow": 0, "tank": 0}  # to about a slider's step or finer
US_VALUE_JS = """
const shown = {minimumFractionDigits: digits, maximumFractionDigits: digits}
return `${(tick * factor).toLocaleString("en-US", shown)} ${unit} (${tick.toFixed(1)} ${si_unit})`
"""


class AfterPaint(pn.widgets.IntInput):
    """Hidden; ``ask(then)``: ``then()`` once the page has painted what it was sent before the
    asking (at once in-process), or after FIGURES_AFTER at the latest."""

    def __init__(self, **params):
        super().__init__(value=0, visible=False, **params)
        self._then = None
        self.jscallback(value=AFTER_PAINT_JS)
        self.param.watch(self._painted, "value")

    def ask(self, then) -> None:
        document = served_document()
        if document is None:
            then()
            return
        self._then = then
        self.value = 1
        document.add_timeout_callback(then, FIGURES_AFTER)

    def _painted(self, event) -> None:
        if event.new == 2 and self._then is not None:
            then, self._then = self._then, None
            then()


def number_text(value: float, unit: str = "", digits: int = 1) -> str:
    """A readout's number: "12.5 m³", "none" for inf (no tank on the curve is enough)."""
    if math.isinf(value):
        return "none can"
    return f"{value:,.{digits}f}" + (f" {unit}" if unit else "")


def water_decimals(unit: str) -> int:
    """The decimals a readout gives water in ``unit``: a tenth of a m³, a whole gallon."""
    return 1 if unit.startswith("m³") else 0


def us_format(label: str, kind: str) -> CustomJSTickFormatter:
    """A Site tab slider's shown value in US units: the value in feet, gal/day or gallons, then
    as the slider moves it (in ``label``'s unit, the core's and the link's), "2,642 gal/day (10.0
    m³/day)", the factor pint's (``windpump.readers.quantities``): written by the browser as the
    thumb moves, as its SI value is."""
    factor, unit = shown_in(kind, "us")
    si_unit = label.partition(" [")[2].rstrip("]")
    return CustomJSTickFormatter(
        args=dict(factor=factor, unit=unit, digits=US_DECIMALS[kind], si_unit=si_unit),
        code=US_VALUE_JS,
    )


class SiteTab(Tab):
    """The Site tab: ``inputs`` are the page's (the design), ``site`` the tab's own (in the
    link); ``reveal`` scrolls an upload's outcome into view."""

    title, waiting = "Site", "Computing the water at the site…"

    def __init__(self, inputs, site: SiteInputs, reveal, dark: bool = False):
        super().__init__(dark)
        self.inputs, self.site, self.reveal = inputs, site, reveal
        self.design: windpump.Design | None = None  # at V_ref, of the page's latest run
        self.records = SiteRecords()
        self.system = "si"  # the page's units, "si" or "us" (its units switch: ``show_units``)

    def update(self, seen: windpump.Exploration) -> None:
        self.design = self.inputs.design_at_v_ref()  # the page ran it: valid
        super().update(seen)

    def build(self) -> None:
        self.colors = palette(self.dark)
        self.sources: dict[str, ColumnDataSource] = {}
        self.readouts = {name: Readout(name) for name in SITE_READOUTS}
        self.monthly = monthly_figure(self.sources, self.colors)
        self.level, self.tank_line = level_figure(self.sources, self.colors)
        self.lolp, _target = lolp_figure(self.sources, self.colors)
        for name, source in self.sources.items():
            source.name = f"sitetab_{name}"  # for a browser: get_model_by_name
        for name, fig in zip(("monthly", "level", "lolp"), self.figures(), strict=True):
            fig.name = f"site_{name}_figure"
        self._build_controls()
        self.note = pn.pane.Markdown(
            "", stylesheets=TEXT, sizing_mode="stretch_width", css_classes=[SITE_NOTE]
        )
        self.status = pn.pane.Alert(  # shown with the first year
            "",
            alert_type="success",
            visible=False,
            stylesheets=COMPACT,
            sizing_mode="stretch_width",
        )
        self.error = pn.pane.Alert("", alert_type="danger", visible=False, stylesheets=TEXT)
        self.computing = pn.pane.Alert(
            COMPUTING,
            alert_type="info",
            visible=False,
            stylesheets=TEXT,
        )
        self.supplied: windpump.Supply | None = None  # the year drawn
        self.figures_due = False  # a year came back (or failed): the figures go in the layout
        self._placing: Callable[[], None] | None = None  # the tab's content, held for its year
        self.after_paint = AfterPaint()  # the figures after the readouts are painted
        self._slots: tuple = ()  # the layout's places for the figures, once it is built
        self._curve: tuple = ()  # what the curve drawn is for: design, record, demand, rule, top
        self.tank_5 = math.inf  # [m³] the smallest tank for 5 % (inf: none is enough)
        self._drawn: Asked | None = None  # what the year drawn was asked for
        self.years = Newest()  # the year last asked for
        self.files = Newest()  # the file last chosen: its outcome is shown, not an earlier one's
        self._lolp: dict | None = None  # the loss-of-load curve drawn, in SI (m³, %)
        self._water_texts = water_texts(self.figures())  # their texts naming m³, as built
        self.site.param.watch(lambda *_e: self.redraw(), list(self.site.keys()))
        self.show_units(self.system)

    def _build_controls(self) -> None:
        style = dict(stylesheets=[*TEXT, FOCUS_CSS], sizing_mode="stretch_width")
        self.sliders = {
            name: PromptSlider.from_param(self.site.param[name], format=SLIDER_FORMAT, **style)
            for name in ("hub", "demand", "tank")
        }
        self._us_formats = {
            name: us_format(self.site.param[name].label, kind)
            for name, kind in SLIDER_KINDS.items()
        }
        self.site_select = pn.widgets.Select(
            label="Site", options={label: key for key, label in SITES.items()}, **style
        )
        self.restart = pn.widgets.Select(
            label="Restart after a calm",
            options={label: key for key, label in RESTARTS.items()},
            **style,
        )
        for widget, name in ((self.site_select, "site"), (self.restart, "restart")):
            follow(widget, self.site, name)
        self.upload, self.upload_message = self.records.controls(SITE_MESSAGE)
        self.upload.param.watch(
            lambda *_e: self.load_data(self.records.chosen()), ["value", "filename"]
        )

    # -- units -------------------------------------------------------------------------------

    def show_units(self, system: str) -> None:
        """The tab in ``system``'s units ("si" or "us"): its readouts, the sliders' titles, the
        figures' axes and hovers, and the year drawn, redrawn in place (the same figures, their
        sources refilled), now and from now on."""
        self.system = system
        if not hasattr(self, "sliders"):  # not built: built in these units
            return
        with pn.io.hold():
            say_water_in(self._water_texts, shown_in("tank", system)[1])
            self._slider_units()
            if self.supplied is not None and self._drawn is not None:
                self._paint()

    def _slider_units(self) -> None:
        """The hub's, demand's and tank's sliders in the page's units: in SI as built ("Demand
        [m³/day]: 10.0"), in US units their values in feet or gallons first (``us_format``)."""
        for name in SLIDER_KINDS:
            slider, label = self.sliders[name], self.site.param[name].label
            if self.system == "us":
                slider.param.update(name=label.partition(" [")[0], format=self._us_formats[name])
            else:
                slider.param.update(name=label, format=SLIDER_FORMAT)

    # -- updates -----------------------------------------------------------------------------

    def draw(self, seen: windpump.Exploration) -> None:
        """The year for the design and the site's inputs (~0.4-0.5 s the first, its record read;
        ~1-15 ms a move). Served, it is computed off the event loop (``serving.off_the_loop``),
        so the other pages' moves are answered meanwhile: the tab says it is computing, and a
        year asked for since (a newer design or input) wins: an older one is never drawn over it.
        """
        if self.design is None:
            return
        values = self.site.values()
        uploaded = self.records.uploaded if values["site"] == UPLOADED else None
        largest = self.site.param["tank"].bounds[1]
        asked = Asked(self.design, **values, uploaded=uploaded, largest_tank=largest)
        self.years.wanted = asked  # a year in flight is superseded, by the one drawn too
        if self.supplied is not None and asked == self._drawn:  # the steady wind V moved
            self.computing.visible = self.error.visible = False
            return
        self.computing.object = COMPILE.waiting(SITE_TAB) or COMPUTING
        self.computing.visible = True
        if self.supplied is None:  # a first year: the figures get ranges until it comes
            largest = tank_range(asked.tank, math.inf, asked.largest_tank)
            placeholder_year(self.sources, shown_in("tank", self.system)[0] * largest)
        records, curve, tank_5 = self.records, self._curve, self.tank_5  # as drawn now

        self.years.ask(
            asked,
            lambda: run_year(records, asked, curve, tank_5),
            lambda outcome: self._show(asked, outcome),
            off_the_loop,
        )

    def _show(self, asked: Asked, outcome) -> None:
        """Draw the year ``outcome`` (a ``Year``) of ``asked`` (the newest asked for); a year
        that cannot be run says why, the one drawn stays. The first one places the tab's
        content (held by ``when_ready``) with its readouts, and the figures once the page has
        painted them (``place_figures``, ``AfterPaint``)."""
        with pn.io.hold():  # one message: the computing note gone, the readouts come
            self.computing.visible = False
            try:
                self._outcome(asked, outcome)
            finally:
                if not self.figures_due:
                    placing, self._placing = self._placing, None
                    if placing is not None:
                        placing()
                    self.figures_due = True
                    later(lambda: self.after_paint.ask(self.place_figures))

    def when_ready(self, place: Callable[[], None]) -> None:
        """The tab's content placed once its first year has come (at once if it has): sent
        with its numbers, the browser lays it out once. Before, a first open's content came
        with a "computing" note and empty readouts, and each change after it (the note hidden,
        the readouts, the figures) cost chromium a layout of every built tab: ~0.8 s each
        with the Mechanisms, Wind and Design map tabs built (a 2-core machine). While its part
        of the solver compiles (a first start) it is placed at once, saying how far that is."""
        if self.figures_due or COMPILE.waiting(SITE_TAB):  # compiling: its progress shown
            place()
        else:
            self._placing = place

    def _outcome(self, asked: Asked, outcome) -> None:
        if isinstance(outcome, ValueError):
            self.failed(f"The year cannot be run: {as_text(outcome)}")
            return
        try:
            if isinstance(outcome, Exception):
                raise outcome
            with pn.io.hold():
                self._draw_year(asked, outcome)
        except Exception as error:  # a bug: say so, log it, keep the session alive
            log.exception("Site update failed")
            self.failed(f"Something went wrong ({type(error).__name__}: {as_text(error)}).")

    def place_figures(self) -> None:
        """The figures into the layout, once the first year has come (or failed), in a message
        after its readouts'. A browser builds a tab's views before it reads the next message:
        the tab's three figures, sent with its controls, took chromium ~0.6-0.8 s (~2.9 s with
        three tabs built before it), and the year's readouts, sent meanwhile, waited for that
        and for the figures' second layout with their data (the server's part ~0.35 s). Sent
        after the readouts, the figures come with their data, each in its placeholder's place
        (``_slot``): nothing on the tab moves."""
        if not self._slots or isinstance(self._slots[0][0], pn.pane.Bokeh):
            return  # the layout is not built yet (it places them), or placed already
        with pn.io.hold():
            for slot, fig in zip(self._slots, self.figures(), strict=True):
                slot.objects = [pn.pane.Bokeh(fig, sizing_mode="stretch_width")]

    def _draw_year(self, asked: Asked, year: Year) -> None:
        if year.lolp is not None:
            self._lolp = year.lolp
        self._curve, self.tank_5 = year.curve, year.tank_5
        self.error.visible = False
        self.supplied, self._drawn = year.supplied, asked
        self._paint()

    def _paint(self) -> None:
        """The year drawn (``supplied``, for ``_drawn``) in the figures and readouts, its water
        in the page's units (m³, or gallons: ``shown_in``)."""
        supplied, tank = self.supplied, self._drawn.tank
        water = shown_in("tank", self.system)[0]  # [shown unit / m³]
        if self._lolp is not None:
            tanks = water * np.asarray(self._lolp["tank"])
            refill(self.sources["lolp"], {"tank": tanks, "lolp": self._lolp["lolp"]})
            self.lolp.x_range.end = water * self._curve[-1]
        show_monthly(self.sources["monthly"], self.monthly, supplied.monthly, water)
        show_level(self.sources, self.level, supplied, tank, water)
        self.tank_line.location = water * tank
        here = {"tank": [water * tank], "lolp": [100 * supplied.lolp]}
        refill(self.sources["lolp_here"], here)
        self._readouts(supplied)
        self.note.object = self.records.describe(self._drawn.site, self._drawn.hub, self.system)

    def _readouts(self, supplied) -> None:
        totals = supplied.totals
        water, unit = shown_in("tank", self.system)
        shown = {
            "site_water": f"{water * totals.pumped:,.0f} · {water * totals.delivered:,.0f}",
            "site_lolp": f"{100 * supplied.lolp:.1f} %",
            "dry_days": f"{supplied.dry_days:d}",
            "dry_spell": f"{supplied.longest_dry_spell:d} days",
            "tank_for_5": number_text(water * self.tank_5, unit, water_decimals(unit)),
        }
        over = span(supplied.hours)
        for name, value in shown.items():
            label = SITE_READOUTS[name].format(span=over, unit=unit)
            self.readouts[name].show(label.replace(f"{unit} over the year", f"{unit}/year"), value)
        self.status.object, self.status.alert_type = supply_status(supplied)
        self.status.visible = True

    def failed(self, message: str) -> None:
        self.computing.visible = False
        self.error.object = message
        self.error.visible = True

    # -- an uploaded record ------------------------------------------------------------------

    def load_data(self, data: bytes | Encoded | None, name: str | None = None) -> None:
        """A TMY3, EPW or CSV file chosen (``name``: the file's, else the upload's): the site
        becomes it; a bad file is explained and
        nothing changes. Either outcome is scrolled into view. Served, the file is read off the
        event loop (``serving.off_the_loop``; a TMY3 year, ~40-130 ms), the tab saying so
        meanwhile; a file chosen since wins."""
        if data is None:
            return
        name = (self.upload.filename or "") if name is None else name
        self.records.reading(name)
        self.files.ask(
            object(),
            lambda: read_upload(data, name),
            lambda outcome: self._loaded(name, outcome),
            off_the_loop,
        )

    def _loaded(self, name: str, outcome) -> None:
        if not self.records.accept(outcome, name):
            self.reveal.show(SITE_MESSAGE)
            return
        options = {label: key for key, label in SITES.items()}
        options[f"Uploaded: {self.records.uploaded_name}"] = UPLOADED
        self.site_select.options = options
        if self.site.site == UPLOADED:
            self.redraw()  # a second file: the same choice, a new record
        self.site.site = UPLOADED
        self.reveal.show(SITE_NOTE)

    def refuse_size(self, size: int) -> None:
        """The page stopped a file over the limit before sending it: say so here."""
        self.records.refuse_size(size)

    def say(self, message: str, alert_type: str = "danger") -> None:
        """Say ``message`` under the upload (a file that could not be sent, one on its way)."""
        self.records.say(message, alert_type)

    def sending(self, name: str, size: int) -> None:
        """The page is sending the file ``name`` by HTTP (``upload_route``): say so; an earlier
        file's outcome, still to come, is not shown."""
        self.files.supersede()
        self.say(sending_note(name, size), "info")

    # -- layout ------------------------------------------------------------------------------

    def figures(self) -> list:
        return [self.monthly, self.level, self.lolp]

    def layout(self) -> pn.Column:
        """The readouts, messages and controls, and a placeholder in each figure's place; the
        figures placed once the first year has come (``place_figures``), at once if it has
        (in-process, the year is computed at once)."""
        controls = pn.Column(
            self.site_select,
            self.sliders["hub"],
            self.sliders["demand"],
            self.sliders["tank"],
            self.restart,
            self.upload.heading,
            self.upload,
            self.upload_message,
            sizing_mode="stretch_width",
            styles={"flex": "1 1 300px", "min-width": "280px"},
            css_classes=[CONTROLS_CLASS],
        )
        self._slots = tuple(
            self._slot(fig, title, grow)
            for fig, title, grow in zip(self.figures(), SLOT_TITLES, (2, 1, 1), strict=True)
        )
        upper = pn.FlexBox(controls, self._slots[0], flex_wrap="wrap", sizing_mode="stretch_width")
        lower = pn.FlexBox(*self._slots[1:], flex_wrap="wrap", sizing_mode="stretch_width")
        caption = pn.pane.HTML(f"<p>{CAPTION}</p>", stylesheets=CAPTION_CSS)
        if self.figures_due:
            self.place_figures()
        return pn.Column(
            pn.FlexBox(*self.readouts.values(), sizing_mode="stretch_width"),
            self.computing,
            self.error,
            self.note,
            self.status,
            upper,
            lower,
            caption,
            self.after_paint,
            sizing_mode="stretch_width",
        )

    @staticmethod
    def _slot(fig, title: str, grow: int) -> pn.Column:
        """A figure's place in the layout from the tab's first paint: a placeholder of the
        figure's height, which ``place_figures`` replaces with the figure. Before,
        the figures' boxes came with them: the controls, laid out across the tab, were then
        squeezed into a column beside the first figure (920 px wide to 353 at 1280×720)."""
        held = pn.pane.HTML(
            f'<div class="placeholder" style="height: {fig.height}px">Drawing {title}…</div>',
            sizing_mode="stretch_width",
            margin=0,  # as the figure's: a Bokeh pane's margin is not drawn in its slot
            stylesheets=PLACEHOLDER_CSS,
        )
        return pn.Column(
            held,
            sizing_mode="stretch_width",
            styles={"flex": f"{grow} 1 460px", "min-width": "300px"},
            css_classes=[SLOT_CLASS],
        )


def follow(widget, inputs, name: str) -> None:
    """A choice widget and the input ``name`` of ``inputs`` kept equal, both ways."""
    if getattr(inputs, name) in widget.options.values():
        widget.value = getattr(inputs, name)
    else:
        inputs.param.update(**{name: widget.value})
    widget.param.watch(lambda event: setattr(inputs, name, event.new), "value")
    inputs.param.watch(lambda event: setattr(widget, "value", event.new), name)
