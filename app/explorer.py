"""The live explorer: a ``pn.viewable.Viewer`` that assembles one page from its parts.

The session's state (``session.Session``: inputs → exploration, error, stale) is drawn in the
sidebar (``sidebar.Sidebar``), the readouts (``readouts.Readouts``), the pump's views
(``pump.PumpViews``) and the tabs (``tab.Tab``: ``mechanisms``, ``wind_tab``, ``map_tab``, ``site_tab``); the
link is read and written by ``link``. Every number comes from ``windpump``.
"""

from __future__ import annotations

import contextlib
import io
import logging
from typing import TypeVar

import panel as pn
import param

import windpump

from .compiling import COMPILE, FIRST_PAGE, REAL_MACHINE, WHEEL
from .figures import present
from .inputs import CHOICES, FORMATS, FROM_THE_LINK, PRESETS, SWITCHES, PumpInputs, preset_of
from .link import (
    RESTORED,
    PageLink,
    dark_from,
    embed_from,
    notices_text,
    page_query,
    presentation_from,
    readable,
    restored_from,
    tab_from,
    tab_query,
    units_from,
    units_query,
)
from .map_tab import MapTab
from .mechanisms import Mechanisms
from .page import page
from .pump import ORDER, PumpViews, name_sources
from .readouts import Readouts
from .server.api import DRAW_AFTER_MOVES, SOLVER_READY, TIDY, deliver, served_document
from .session import Session
from .sidebar import PRESET_PROMPT, Sidebar, design_filename, slider
from .site_inputs import SiteInputs
from .site_tab import SITE_MESSAGE, SiteTab
from .styles import NOTICE
from .tab import PageTabs, Tab
from .views import BINS
from .wind_tab import WIND_MESSAGE, WindTab

__all__ = ["BINS", "Explorer", "design_filename"]

log = logging.getLogger("windpump.app")
T = TypeVar("T", bound=Tab)

STALE = {"opacity": "0.35", "filter": "grayscale(1)"}
WORKING = "**Running the new design…**"


def parts_of(design: windpump.Design) -> list[str]:
    """The parts of the solver a run of ``design`` needs beyond the first page's: the real
    machine's (its losses), the wheel's (a rotor's C_Q table)."""
    return [part for part, needs in ((REAL_MACHINE, not design.is_ideal), (WHEEL, design.rotor))
            if needs]  # fmt: skip


class Explorer(pn.viewable.Viewer):
    """One session's explorer. ``template()`` is the page; ``query`` a URL query to start from;
    ``start=False`` waits for ``start()`` to run it (while the server compiles the solver);
    ``defer_views`` waits for ``show_views()`` to put the views on the page, and ``lazy_views``
    builds each view only once the page says it shows it (``see_views``).

    Its ``session`` (``session.Session``) holds the inputs, the run on the screen and whether it
    is current, and takes a move from its inputs to its run drawn here (``_draw``, ``_mark_stale``,
    ``_followed``, ``_working``: the page as the session's screen)."""

    presentation = param.Boolean(False, doc="Larger text and thicker lines for a projector.")
    dark = param.Boolean(False, doc="Dark theme (the page's ?theme=dark).")
    embed = param.Boolean(False, doc="In a course page's iframe: no header (?embed=true).")
    units = param.Selector(
        objects=["si", "us"], default="si", doc="The readouts' units: SI or US (?units=us)."
    )

    def __init__(
        self,
        bins: int | None = BINS,
        query: dict | None = None,
        defer_views: bool = False,
        lazy_views: bool = False,
        start: bool = True,
        **params,
    ):
        super().__init__(**params)
        self.session = Session(screen=self)  # inputs -> run -> this page
        query, notices = readable(query or {})
        # First: the theme button's label and every figure's colours follow it.
        self.dark = dark_from(query, notices)
        self.units = units_from(query, notices)
        self.embed = embed_from(query, notices)  # for an iframe: no header (page.page)
        self.bins = bins  # None: every sample of every trace (the benchmark's baseline)
        self._to_plot: windpump.Exploration | None = None  # the run the next plot callback draws
        self.pump = PumpViews(self.dark, bins)
        self.sources = self.pump.sources
        self.lazy_views = lazy_views  # each view built once the page says it is seen
        self._views_shown = False
        self.sidebar = Sidebar(self.inputs, self.dark, self._csv, self._show_lab_points)
        self.readouts = Readouts(system=self.units)
        self._build_messages(restored_from(query))
        self._build_tabs()
        self._wire()
        if not defer_views:
            self.show_views()
        site_values, notices_site = self.site_inputs.parse_query(query)
        pump_query = {key: raw for key, raw in query.items() if key not in SiteInputs.keys()}
        values, read = self.inputs.parse_query(pump_query)
        notices += read + notices_site
        self.site_inputs.param.update(**site_values)
        self._tab = tab_from(query, notices)  # the tab the link opens on (main())
        presentation = presentation_from(query, notices)
        if presentation is not None:
            self.presentation = presentation
        self.inputs.param.update(**values)
        self._location: PageLink | None = None  # the page's address, once followed
        self._noted = ""  # the inputs' query when the presets' note was written (``_say``)
        # what start() runs first, and whether the link names the design (taken or refused)
        designs = any(key in (*FORMATS, *SWITCHES, *CHOICES) for key in pump_query)
        self._link = (values, notices, designs)
        if start:
            self.start()
        else:
            self.say_compiling()

    # -- the session's state, as the page shows it -------------------------------------------

    @property
    def inputs(self) -> PumpInputs:
        """The pump's inputs (the session's)."""
        return self.session.inputs

    @property
    def seen(self) -> windpump.Exploration | None:
        """The run on the screen (the session's)."""
        return self.session.seen

    @property
    def stale(self) -> bool:
        """Whether the screen shows an earlier design: the last input was refused."""
        return self.session.stale

    @property
    def error(self) -> pn.pane.Alert:
        """The session's message of a refused input, above the plots."""
        return self.session.error

    def say_compiling(self) -> None:
        """The status, while the part of the solver this page's first run needs compiles (a
        first start after an install): how far it is, "Compiling the solver (once after an
        install): 1 of 6 parts ready" (``serving.first_run_when_ready`` says it again as parts
        get ready), and meanwhile the averaged theory's τ, stall margin and α₊, which need no
        compiled code (``Readouts.show_averaged``)."""
        part = self.part_awaited()
        if self.seen is None and part is not None:
            status = self.readouts.status
            try:  # the averaged theory needs no compiled code: its numbers now
                averaged = self.readouts.show_averaged(self.inputs.design())
            except windpump.ParameterError:  # refused: its first run says why
                averaged = ""
            numbers = "The full run's numbers" if averaged else "These numbers"
            status.object = f"{COMPILE.saying(part, numbers)} {averaged}".strip()
            status.alert_type = "info"

    def part_awaited(self) -> str | None:
        """The part of the solver this page's first run waits for while a first start compiles
        it, or None once it is ready: the first page's; then, for a page whose link opens a real
        machine (a deep well), the real machine's, or a wheel, the wheel's, compiled in a worker
        (waited for off the event loop: on it every page stood still)."""
        if not (SOLVER_READY.is_set() and COMPILE.ready[FIRST_PAGE].is_set()):
            return FIRST_PAGE
        try:
            design = self.inputs.design()
        except Exception:  # refused: its first run says why, and compiles nothing
            return None
        return next((p for p in parts_of(design) if not COMPILE.ready[p].is_set()), None)

    def _build_messages(self, restored: bool) -> None:
        self.notices = pn.pane.Alert(
            "", alert_type="warning", visible=False, stylesheets=NOTICE, sizing_mode="stretch_width"
        )
        self.restored = pn.pane.Alert(
            RESTORED,
            alert_type="info",
            visible=restored,
            stylesheets=NOTICE,
            sizing_mode="stretch_width",
        )

    def _build_tabs(self) -> None:
        """The tabs beside the pump's, in their order on the page; each built when first viewed."""
        reveal = self.sidebar.reveal
        self.mechanisms_tab = Mechanisms(slider, self.dark)
        self.wind_tab = WindTab(self.inputs, self.sidebar.sliders, self.bins, reveal, self.dark)
        self.wind_tab.system = self.units
        self.map_tab = MapTab(self.inputs, self.dark)
        self.site_inputs = SiteInputs()  # the Site tab's own inputs, in the link
        self.site_tab = SiteTab(self.inputs, self.site_inputs, reveal, self.dark)
        self.site_tab.system = self.units
        self.page_tabs = PageTabs(
            [self.mechanisms_tab, self.wind_tab, self.map_tab, self.site_tab], self._open
        )

    def _wire(self) -> None:
        """The sidebar's actions, presentation mode and a refused upload."""
        bar = self.sidebar
        bar.reset_button.on_click(lambda _e: self.reset())
        bar.preset.param.watch(self._on_preset, "value")
        bar.pin_button.on_click(lambda _e: self.pin())
        bar.clear_button.on_click(lambda _e: self.clear_pinned())
        bar.present_toggle.link(self, value="presentation", bidirectional=True)
        bar.units_switch.value = self.units
        bar.units_switch.link(self, value="units", bidirectional=True)
        self.param.watch(self._units_chosen, "units")
        bar.refused_upload.param.watch(self._on_refused_upload, "value")
        self.pump.channel.param.watch(self._on_views_seen, "value")
        self.param.watch(self._restyle, "presentation")

    def start(self) -> None:
        """The first run: the link's design (a value the core refuses is named and left out),
        then every change of an input runs again."""
        if self._link is None:
            return
        values, notices, designs = self._link
        self._link = None
        seen = self.session.run_link(values, notices)
        # A reopened link that names the design says what it shows, as a chosen preset does,
        # whatever of it was refused (?h=-5 shows the paper's example, and says so).
        if designs:
            self._say_what_the_link_shows()
        self.notices.object = notices_text(notices)
        self.notices.visible = bool(notices)
        self.inputs.param.watch(self._on_inputs, self.inputs.names())
        self.inputs.param.watch(self._leave_preset, self.inputs.names())
        self.session.update(seen)

    # -- the tabs, each built when first viewed ------------------------------------------------

    @property
    def mechanisms(self) -> Mechanisms:
        """The Mechanisms tab, built on first use."""
        return self._open(self.mechanisms_tab)

    @property
    def wind(self) -> WindTab:
        """The Wind tab, built on first use (it runs its day then)."""
        return self._open(self.wind_tab)

    @property
    def design_map(self) -> MapTab:
        """The Design map tab, built on first use."""
        return self._open(self.map_tab)

    @property
    def site(self) -> SiteTab:
        """The Site tab, built on first use (it runs its year then)."""
        return self._open(self.site_tab)

    def _open(self, tab: T) -> T:
        """``tab``, built and drawn (the latest run, if hidden it was left behind it); the
        Mechanisms tab's data sources join the page's."""
        tab.catch_up()
        if not tab.built:
            tab.open()
            if tab is self.mechanisms_tab:
                self.sources.update(self.mechanisms_tab.sources)
                name_sources(self.sources)
            if self.presentation:
                self._restyle_views(True)
        return tab

    def show_views(self) -> None:
        """Build the plots and the machine, draw the current run in them and put them on the page:
        every view, or with ``lazy_views`` those the page has said it shows (``see_views``).

        A served page calls this once it has loaded (``pn.state.onload``): the page a student
        opens carries the controls, the readouts and the views' placeholders and is quick to
        build, which matters when a class of 30 opens it at once; the views it shows follow in
        one message (~65 models each), the others when it scrolls to them.
        """
        self._views_shown = True
        self._build_views(self.pump.channel.names(ORDER) if self.lazy_views else ORDER)

    def see_views(self, names: list[str]) -> None:
        """The page shows (or is about to show) the views ``names``: build those not built yet
        (once ``show_views()`` has run)."""
        self.pump.channel.value = " ".join(
            sorted(set(self.pump.channel.value.split()) | set(names))
        )

    def _on_views_seen(self, _event) -> None:
        if self._views_shown and self._build_views(self.pump.channel.names(ORDER)):
            document = pn.state.curdoc
            if document is not None and document.session_context is not None:
                TIDY.settle()  # built on a scroll: frozen out of later collections as its page

    def _build_views(self, names) -> bool:
        """Build the views ``names`` not built yet; whether any was."""
        if all(name in self.pump.built for name in names):
            return False
        document = pn.state.curdoc
        frozen = document.models.freeze() if document is not None else contextlib.nullcontext()
        with pn.io.hold(), frozen:  # one message, one walk of the page's models
            if self.seen is not None and self.pump.drawn is None:
                self._plot(self.seen)  # the latest run, which a view built now draws
            self.pump.build(names)
        return True

    # -- the one path from inputs to screen --------------------------------------------------

    def _on_inputs(self, *_events) -> None:
        # The run off the event loop, one at a time, the latest move winning (Session.move): a
        # dragged slider redraws as fast as the machine can and always ends on its final value.
        self.session.move()

    def _working(self, working: bool) -> None:
        """A move's run is taking long: the status says so and the views and readouts are marked
        as not current (as for a refused input), until its run (or its refusal) is drawn."""
        status = self.readouts.status
        if working:
            self._status_before = (status.object, status.alert_type)
            parts = parts_of(self.inputs.design())
            compiling = next((said for said in map(COMPILE.waiting, parts) if said), "")
            status.object, status.alert_type = compiling or WORKING, "info"
            self._mark_stale(True)
            return
        status.object, status.alert_type = self._status_before
        self._mark_stale(self.stale)

    def _mark_stale(self, stale: bool) -> None:
        styles = STALE if stale else {"opacity": "1", "filter": "none"}
        self.pump.mark_stale(styles)
        self.readouts.mark_stale(styles)

    def _draw(self, seen: windpump.Exploration) -> None:
        """Readouts and status first, in a message of their own, then the plots and the machine:
        the numbers a class reads arrive without waiting for ~100 KB of traces to be drawn."""
        self.readouts.show(seen)
        self._to_plot = seen
        document = pn.state.curdoc
        if document is not None and document.session_context is not None:
            DRAW_AFTER_MOVES.later(document, self._plot_latest)  # after others' readouts
        else:  # in-process (a notebook, the tests): at once
            self._plot(seen)

    def _plot_latest(self) -> None:
        seen, self._to_plot = self._to_plot, None
        if seen is None:  # a later move's callback has drawn it already
            return
        try:
            with pn.io.hold():
                self._plot(seen)
        except Exception as error:
            log.exception("drawing failed")
            self.session.show_error(
                f"Something went wrong ({type(error).__name__}: {error}); it has been logged."
            )

    def _plot(self, seen: windpump.Exploration) -> None:
        """The plots, the machine and the download's file name (after the readouts, as they)."""
        self.sidebar.show_design(seen.design)
        self.pump.plot(seen, self.inputs.t_end)

    def _followed(self, seen: windpump.Exploration) -> None:
        self.page_tabs.update(seen)

    # -- actions -----------------------------------------------------------------------------

    def set_values(self, **values: float | bool) -> None:
        """Set several inputs and update once."""
        self.inputs.param.update(**values)

    def reset(self) -> None:
        """Everything back to the paper's example: inputs, pinned run, lab data, Mechanisms tab."""
        self.clear_pinned()
        self.pump.show_lab_data([], [])
        self.sidebar.lab.hide()
        self.sidebar.preset_note.visible = False
        self.sidebar.preset.value = PRESET_PROMPT
        if self.mechanisms_tab.built:
            self.mechanisms_tab.reset()
        self.site_inputs.param.update(**self.site_inputs.defaults())
        self.set_values(**self.inputs.defaults())

    def _say_what_the_link_shows(self) -> None:
        """The preset the link's design is (chosen, with its sentence), or that it is the link's."""
        name = preset_of(self.inputs)
        if name is not None:
            self.sidebar.preset.value = name  # _on_preset: the same values, and its sentence
        else:
            self._say(FROM_THE_LINK)

    def _on_preset(self, event) -> None:
        if event.new not in PRESETS:
            return
        values, sentence = PRESETS[event.new]
        self.clear_pinned()
        self.sidebar.preset_note.visible = False  # its values are not yet the inputs'
        self.set_values(**{**self.inputs.defaults(), **values})
        self.sidebar.cards_as_fresh(self.inputs)
        self._say(f"**{event.new}.** {sentence}")

    def _say(self, note: str) -> None:
        """Show ``note`` under the presets menu, about the design the inputs hold now."""
        self._noted = self.inputs.query()
        self.sidebar.preset_note.object = note
        self.sidebar.preset_note.visible = True

    def _leave_preset(self, *_events) -> None:
        """An input left the design the preset's (or the link's) sentence is about: the sentence
        goes and the menu asks again, so no "spins up over τ ≈ 79 s" sits beside a stall."""
        if self.sidebar.preset_note.visible and self.inputs.query() != self._noted:
            self.sidebar.preset_note.visible = False
            self.sidebar.preset.value = PRESET_PROMPT

    def pin(self) -> None:
        """Keep the current traces as a faint ghost to compare the next change with."""
        self.show_views()
        self.pump.pin()
        self.sidebar.clear_button.disabled = False

    def clear_pinned(self) -> None:
        self.pump.clear()
        self.sidebar.clear_button.disabled = True

    def load_lab_data(self, data: bytes | None) -> None:
        """A CSV of windmill speed [rad/s] and torque [N m] (``lab.LabData.load``)."""
        self.sidebar.lab.load(data)

    def load_wind_data(self, data: bytes | None) -> None:
        """A measured wind CSV for the Wind tab's day (``WindTab.load_data``)."""
        self.wind.load_data(data)

    def forget_wind_data(self) -> None:
        self.wind.forget_data()

    def _show_lab_points(self, omega, power) -> None:
        self.show_views()
        self.pump.show_lab_data(omega, power)

    def _on_refused_upload(self, _event) -> None:
        """The page stopped a file over the size limit before sending it: say so where it was
        chosen; a value that is not a size over the limit (tampered) is ignored. A wind or site
        file the page sent by HTTP: read it there (``upload_route.deliver``)."""
        note = self.sidebar.refused_upload
        if note.size is None:
            return
        if note.kind == "lab":
            self.sidebar.lab.refuse_size(note.size)
            return
        tab, message = (
            (self.site, SITE_MESSAGE) if note.kind == "site" else (self.wind, WIND_MESSAGE)
        )
        document = served_document()
        if deliver(note, tab, document.session_context.id if document is not None else ""):
            self.sidebar.reveal.show(message)

    def _csv(self) -> io.StringIO:
        return io.StringIO(self.seen.run.to_csv(litres=True) if self.seen else "")

    def _units_chosen(self, event) -> None:
        """The readouts in the units chosen, the pump's, the Wind tab's and the Site tab's (its
        figures too; a mode of the page, as presentation mode: Reset and the presets keep it)."""
        self.readouts.system = event.new
        if self.seen is not None:
            self.readouts.show(self.seen)
        self.wind_tab.show_units(event.new)
        self.site_tab.show_units(event.new)

    def _restyle(self, event) -> None:
        self._restyle_views(event.new)  # the readouts follow the page's zoom (styles.px)

    def _restyle_views(self, large: bool) -> None:
        """Presentation mode on (``large``) or back off, in every figure built so far: the text
        they draw on their canvas and their lines (the page's HTML follows ``styles.ZOOM_JS``)."""
        for fig in self.page_tabs.figures():
            present(fig, large)
        self.pump.restyle(large)  # and the views built later

    def figures(self) -> list:
        """Every figure on the page so far: the views' and those of the tabs opened."""
        figures = [view.figure for view in self.pump.views]
        figures.extend(self.page_tabs.figures())
        return figures

    # -- the link ----------------------------------------------------------------------------

    def link_query(self) -> str:
        """The page's query as its link carries it (``link.page_query``)."""
        shown = self.tabs.active if hasattr(self, "tabs") else self._tab
        return page_query(
            self.inputs,
            self.presentation,
            self.dark,
            self.bins is None,
            self.site_inputs.query(),
            tab_query(shown),
            units_query(self.units),
            embed=self.embed,
        )

    def follow_in_link(self, location) -> None:
        """Keep ``location`` (a served page's ``pn.state.location``) on ``link_query()``."""
        self._location = PageLink(location, self.link_query)
        self.inputs.param.watch(self._location.write_later, self.inputs.names())  # after a move's
        self.site_inputs.param.watch(self._location.write, list(self.site_inputs.keys()))
        self.param.watch(self._location.write, ["presentation", "units"])
        if hasattr(self, "tabs"):
            self.tabs.param.watch(self._location.write, "active")

    # -- layout ------------------------------------------------------------------------------

    def pump_tab(self) -> pn.Column:
        return pn.Column(
            self.pump.channel,
            self.restored,
            self.notices,
            self.error,
            self.readouts.row,
            self.readouts.status,
            self.pump.results,
            sizing_mode="stretch_width",
        )

    def main(self) -> pn.Tabs:
        """The tabs: the pump's, then each of ``page_tabs`` once it is chosen."""
        self.tabs = self.page_tabs.strip(self.pump_tab())
        self.tabs.active = self._tab  # the link's tab, opened as a click opens it
        if self._location is not None:
            self.tabs.param.watch(self._location.write, "active")
        return self.tabs

    def __panel__(self) -> pn.Row:
        return pn.Row(pn.Column(self.sidebar, width=340), self.main(), sizing_mode="stretch_width")

    def template(self) -> pn.template.BootstrapTemplate:
        """The page: the sidebar beside the tabs, under the title (none when embedded)."""
        return page(
            self.sidebar.__panel__(), self.main(), self.dark, self.presentation, embed=self.embed
        )
