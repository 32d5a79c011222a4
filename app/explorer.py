"""The live explorer: a ``pn.viewable.Viewer`` wiring inputs, views, readouts and files together.

Every number comes from ``windpump``; this module only decides what to show and where.
"""

from __future__ import annotations

import contextlib
import io
import logging
from urllib.parse import urlencode

import panel as pn
import param
from bokeh.models import ColumnDataSource, Range1d

import windpump
from windpump import Status

from .buttons import ActionButton
from .figures import present
from .inputs import FORMATS, PRESETS, SEED, SWITCHES, PumpInputs, clipped, link_text, on_grid
from .keyboard import FOCUS_CSS, PAGE_FOCUS_CSS, TAB_FOCUS_CSS
from .machine import MachineView
from .map_tab import MapTab
from .mechanisms import Mechanisms
from .readouts import Readout, StatusAlert
from .styles import COMPACT, TEXT, ZOOM_JS, px, zoom_css
from .uploads import RefusedUploads, Reveal
from .views import (
    BINS,
    CloseupView,
    EnergyView,
    FlowView,
    OperatingView,
    SpeedView,
    StallView,
)
from .wind_tab import WIND_DAY_NOTE, WIND_MESSAGE, WindTab

log = logging.getLogger("windpump.app")

STATUS_STYLE = {
    Status.RUNNING: "success",
    Status.SLOWING: "warning",
    Status.STALLED: "danger",
    Status.NEVER_STARTED: "warning",
}
VIEW_FLEX = {"flex": "1 1 460px", "min-width": "300px"}  # two or more columns from ~1600 px
VIEW_FLEX_ROW = {"gap": "8px"}
# Two buttons share a row of the sidebar: in presentation mode a label wraps inside its button.
BUTTON_CSS = ".bk-btn { white-space: normal; padding-left: 4px; padding-right: 4px; }"
STALE = {"opacity": "0.35", "filter": "grayscale(1)"}
READOUTS = ("mean_flow", "volume", "tau", "margin", "peak_to_mean", "ripple", "energy")
PRESET_PROMPT = "Choose a preset…"
PRESENTATION_GROWTH = 1.3  # the height of a view below the first screen in presentation mode
COMPILING = (
    "**Compiling the solver.** The first start after an install compiles it (about 8 s); this "
    "page's numbers follow as soon as it is done."
)
MAX_NOTICES = 5  # the link's ignored values listed; the rest counted
MAX_QUERY = 64 * 1024  # [characters] a longer link's parameters are ignored (app_hooks.py)
# An upload's outcome, by the CSS class that scrolls it into view (uploads.Reveal)
LAB_MESSAGE, LAB_NOTE = "lab-message", "lab-note"
# A tab's content arrives after its header is chosen (the Wind tab's after its day has run): its
# file input gets the page's size check (uploads.js) as soon as it is drawn.
GUARD_NEW_UPLOADS_JS = """
for (const delay of [300, 1000, 2500, 5000, 10000, 20000]) {
  setTimeout(() => window.__windpumpGuardAll && window.__windpumpGuardAll(), delay)
}
"""


class PromptSlider(pn.widgets.FloatSlider):
    """Panel's float slider without its 50 ms wait for further moves before the server reacts
    (``Syncable._debounce``): a key press or a drag's first move starts the run at once, a third
    of the way to a readout within 100 ms. Moves that arrive while a run is under way are still
    gathered by Panel and the latest applied, so a drag never queues runs."""

    _debounce = 0


def design_filename(design: windpump.Design) -> str:
    return (
        f"windpump_h{design.h:g}m_LR{design.L_over_R:.3g}_Rdagger{design.R_dagger:.3g}"
        f"_Tm{design.T_m:g}_omegam{design.omega_m:g}.csv"
    )


class Explorer(pn.viewable.Viewer):
    """One session's explorer. ``template()`` is the page; ``query`` a URL query to start from;
    ``start=False`` waits for ``start()`` to run it (while the server compiles the solver)."""

    inputs = param.ClassSelector(class_=PumpInputs)
    presentation = param.Boolean(False, doc="Larger text and thicker lines for a projector.")
    stale = param.Boolean(
        False, doc="The plots show an earlier design: the last input was rejected."
    )
    dark = param.Boolean(False, doc="Dark theme (the page's ?theme=dark).")

    def __init__(
        self,
        bins: int | None = BINS,
        query: dict | None = None,
        defer_views: bool = False,
        start: bool = True,
        **params,
    ):
        super().__init__(inputs=PumpInputs(), **params)
        query, notices = _readable(query or {})
        # First: the theme button's label and every figure's colours follow it.
        self.dark = _text(query.get("theme", [b""])) == "dark"
        self.bins = bins  # None: every sample of every trace (the benchmark's baseline)
        self.seen: windpump.Exploration | None = None
        self._to_plot: windpump.Exploration | None = None  # the run the next plot callback draws
        self.views: list = []  # built by show_views()
        self.sources: dict[str, ColumnDataSource] = {}
        self._mechanisms: Mechanisms | None = None  # built when first opened: most pages never do
        self._drawn_linkage: tuple | None = None
        self._build_widgets()
        self._wind: WindTab | None = None  # built when first opened: most pages never do
        self.wind_open = False  # the Wind tab runs its day only once it has been opened
        self._map: MapTab | None = None  # the Design map tab, also built when first opened
        self.map_open = False
        self._build_results()
        if not defer_views:
            self.show_views()
        self.param.watch(self._restyle, "presentation")
        values, read = self.inputs.parse_query(query)
        notices += read
        self._presentation_from(query, notices)
        self.inputs.param.update(**values)
        self._location = None  # the page's address, once follow_in_link() is called
        self._link = (values, notices)  # what start() runs first
        if start:
            self.start()
        else:
            self.status.object, self.status.alert_type = COMPILING, "info"

    def start(self) -> None:
        """The first run: the link's design (a value the core refuses is named and left out),
        then every change of an input runs again."""
        if self._link is None:
            return
        values, notices = self._link
        self._link = None
        seen = self._run_link(values, notices)
        self._show_notices(notices)
        self.inputs.param.watch(self._on_inputs, self.inputs.names())
        self.update(seen)

    # -- building ----------------------------------------------------------------------------

    def show_views(self) -> None:
        """Build the plots and the machine, draw the current run in them and put them on the page.

        A served page calls this once it has loaded (``pn.state.onload``): the page a student
        opens carries the controls and readouts alone and is quick to build, which matters when
        a class of 30 opens it at once; the ~450 models of the views follow in one message.
        """
        if self.views:
            return
        document = pn.state.curdoc
        frozen = document.models.freeze() if document is not None else contextlib.nullcontext()
        with pn.io.hold(), frozen:  # one message, one walk of the page's models
            self._build_views()
            self.results.objects = self._view_panels()
            if self.presentation:
                self._restyle_views(True)
            if self.seen is not None:
                self._plot(self.seen)

    def _build_views(self) -> None:
        self.time_range = Range1d(0.0, 600.0, name="speed_range")
        self.cursor = ColumnDataSource({"t": [0.0]}, name="cursor")
        dark = self.dark  # each view draws in its theme's colours
        self.speed = SpeedView(self.time_range, self.cursor, dark)
        self.flow = FlowView(self.time_range, self.cursor, dark)
        self.energy = EnergyView(self.time_range, self.cursor, dark)
        self.closeup = CloseupView(dark)
        self.stall = StallView(dark)
        self.operating = OperatingView(dark)
        self.machine = MachineView(self.cursor, dark)
        # The crank speed and the machine playing it first: side by side in a projector's first screen.
        self.views = [
            self.speed,
            self.machine,
            self.flow,
            self.closeup,
            self.energy,
            self.stall,
            self.operating,
        ]
        self.sources.update(cursor=self.cursor)
        self.base_heights = {view: view.figure.height for view in self.views}
        for view in self.views:
            self.sources.update(view.sources)
        self._name_sources()

    def _name_sources(self) -> None:
        for name, source in self.sources.items():
            source.name = name  # so a browser can find it: Bokeh.documents[0].get_model_by_name
        if self.views:
            for name in ("speed", "flow", "energy", "closeup", "stall", "operating", "machine"):
                getattr(self, name).figure.name = f"{name}_figure"

    @property
    def wind(self) -> WindTab:
        """The Wind tab's content, built on first use (its four figures cost every page that
        never opens it)."""
        if self._wind is None:
            self._wind = WindTab(self.sliders, self.bins, self.dark)
            upload = self._wind.upload
            upload.param.watch(
                lambda *_e: self.load_wind_data(_chosen(upload)), ["value", "filename"]
            )
            self._wind.use_gusty.on_click(lambda _e: self.forget_wind_data())
        return self._wind

    @property
    def design_map(self) -> MapTab:
        """The Design map tab, built on first use."""
        if self._map is None:
            bounds = self.inputs.param
            self._map = MapTab(
                bounds["R_dagger"].bounds, bounds["h"].bounds, self.move_to, self.dark
            )
        return self._map

    def move_to(self, ratio: float, h: float) -> None:
        """A tap on the design map: the sprocket ratio and head there, on the sliders' steps."""
        values = {}
        for name, value in (("R_dagger", ratio), ("h", h)):
            low, high = self.inputs.param[name].bounds
            step = self.inputs.param[name].step
            values[name] = min(max(on_grid(value, step), low), high)
        self.set_values(**values)

    @property
    def mechanisms(self) -> Mechanisms:
        """The Mechanisms tab's content, built on first use and following the pump's design."""
        if self._mechanisms is None:
            self._mechanisms = Mechanisms(self._slider, self.dark)
            self.sources.update(self._mechanisms.sources)
            self._name_sources()
            if self.seen is not None:
                self._mechanisms.set_design(self.seen.design)
        return self._mechanisms

    def _slider(self, label, start, end, step, value, fmt):
        return PromptSlider(
            label=label,
            start=start,
            end=end,
            step=step,
            value=value,
            format=fmt,
            stylesheets=[*TEXT, FOCUS_CSS],
            sizing_mode="stretch_width",
        )

    def _build_widgets(self) -> None:
        self.sliders = {
            name: PromptSlider.from_param(
                self.inputs.param[name],
                format=fmt,
                stylesheets=[*TEXT, FOCUS_CSS],
                sizing_mode="stretch_width",
            )
            for name, (fmt, _main) in FORMATS.items()
        }
        self.switches = {
            name: pn.widgets.Checkbox.from_param(
                self.inputs.param[name],
                stylesheets=[*TEXT, FOCUS_CSS],
                sizing_mode="stretch_width",
            )
            for name in SWITCHES
        }
        button = dict(stylesheets=[*TEXT, BUTTON_CSS, FOCUS_CSS], sizing_mode="stretch_width")
        self.reset_button = ActionButton(
            label="Reset to the paper's example", color="primary", **button
        )
        self.preset = pn.widgets.Select(
            label="Presets", options=[PRESET_PROMPT, *PRESETS], **button
        )
        self.preset_note = pn.pane.Markdown("", visible=False, stylesheets=TEXT)
        self.pin_button = ActionButton(label="Pin this run", **button)
        self.clear_button = ActionButton(label="Clear pinned", disabled=True, **button)
        self.present_toggle = pn.widgets.Toggle(label="Presentation mode", **button)
        self.copy_link = pn.widgets.Button(label="Copy link to this state", **button)
        self.copy_link.js_on_click(code=COPY_LINK_JS)
        self.dark_toggle = pn.widgets.Button(
            label="Light theme" if self.dark else "Dark theme", **button
        )
        self.dark_toggle.js_on_click(code=DARK_JS)
        self.lab_data = pn.widgets.FileInput(
            accept=".csv,.txt,.tsv", stylesheets=[*TEXT, FOCUS_CSS], sizing_mode="stretch_width"
        )
        self.refused_upload = RefusedUploads()  # the page's word that it refused a large file
        self.lab_message = pn.pane.Alert(
            "", alert_type="danger", visible=False, stylesheets=TEXT, css_classes=[LAB_MESSAGE]
        )
        self.lab_note = pn.pane.Markdown(
            "", visible=False, stylesheets=TEXT, css_classes=[LAB_NOTE]
        )
        self.reveal = Reveal()  # scrolls an upload's outcome into view
        self.apply_fit = ActionButton(
            label="Apply this fit anyway", color="warning", visible=False, **button
        )
        self.download = pn.widgets.FileDownload(
            callback=self._csv,
            filename="windpump_run.csv",
            label="Download this run (CSV)",
            color="light",
            **button,
        )
        self.readouts = {name: Readout(name) for name in READOUTS}
        self.status = StatusAlert(
            "", alert_type="success", stylesheets=COMPACT, sizing_mode="stretch_width"
        )
        self.error = pn.pane.Alert(
            "", alert_type="danger", visible=False, stylesheets=TEXT, sizing_mode="stretch_width"
        )
        self.notices = pn.pane.Alert(
            "", alert_type="warning", visible=False, stylesheets=TEXT, sizing_mode="stretch_width"
        )
        self._pending_fit: windpump.TorqueFit | None = None

        self.reset_button.on_click(lambda _e: self.reset())
        self.preset.param.watch(self._on_preset, "value")
        self.pin_button.on_click(lambda _e: self.pin())
        self.clear_button.on_click(lambda _e: self.clear_pinned())
        self.present_toggle.link(self, value="presentation", bidirectional=True)
        self.present_toggle.jscallback(value=ZOOM_JS)
        self.lab_data.param.watch(
            lambda *_e: self.load_lab_data(_chosen(self.lab_data)), ["value", "filename"]
        )
        self.refused_upload.param.watch(self._on_refused_upload, "value")
        self.apply_fit.on_click(lambda _e: self._apply_fit(self._pending_fit))

    # -- the one path from inputs to screen --------------------------------------------------

    def _on_inputs(self, *_events) -> None:
        # Panel gathers the changes that arrive while an update runs and applies the latest, so a
        # dragged slider redraws as fast as the machine can and always ends on its final value.
        self.update()

    def _explore(self) -> windpump.Exploration:
        i = self.inputs
        return windpump.explore(i.design(), i.t_end, i.theta0, i.theta_dot0)

    def _run_link(self, values: dict, notices: list[str]) -> windpump.Exploration | None:
        """The run of the link's values. A value the core refuses with the others (``T_0=0.9``
        with the default T_m = 0.6) is ignored with the core's reason, as a value refused on
        reading is, and the page opens on the rest. None: nothing ran (update() says why)."""
        values = dict(values)
        while True:
            try:
                return self._explore()
            except ValueError as error:
                name = _input_name(error)
                if name not in values:
                    return None
                label = self.inputs.param[name].label
                notices.append(
                    f"{label} ({name}) = “{link_text(name, values.pop(name))}” ignored: "
                    f"{_sentence(error)}"
                )
                setattr(self.inputs, name, self.inputs.param[name].default)
            except Exception:  # a bug: update() shows and logs it
                return None

    def update(self, seen: windpump.Exploration | None = None) -> None:
        """Run the core on the current inputs (``seen``: that run, done already) and redraw; a
        rejected input shows its message."""
        try:
            seen = self._explore() if seen is None else seen
            with pn.io.hold():
                self._draw(seen)
        except ValueError as error:  # the core's verdict on an input: say so, mark the plots stale
            self._show_error(f"{self._culprit(error)}cannot be run: {error}")
        except Exception as error:  # a bug: say so, log it, keep the session alive
            log.exception("update failed")
            self._show_error(
                f"Something went wrong ({type(error).__name__}: {error}); it has been logged."
            )
        else:
            self.seen = seen
            self.error.visible = False
            self.stale = False
            self._mark_stale(False)
            if self.wind_open:
                self.update_wind()
            if self.map_open:
                self.update_map()

    def update_map(self) -> None:
        """Redraw the Design map (when the map itself changed) and move its marker."""
        try:
            with pn.io.hold():
                self.design_map.update(self.inputs.design())
        except Exception as error:  # a bug: say so, log it, keep the session alive
            log.exception("design map update failed")
            self.design_map.readout.object = (
                f"Something went wrong ({type(error).__name__}: {error})."
            )

    def open_map(self) -> None:
        self.map_open = True
        self.update_map()

    def update_wind(self) -> None:
        """Redraw the Wind tab: its curve and its day, run in full (about a second)."""
        try:
            with pn.io.hold():
                self.wind.update(self.inputs.design_at_v_ref(), self.inputs)
        except ValueError as error:
            self.wind.error.object = f"The wind cannot be run: {error}"
            self.wind.error.visible = True
        except Exception as error:  # a bug: say so, log it, keep the session alive
            log.exception("wind update failed")
            self.wind.error.object = f"Something went wrong ({type(error).__name__}: {error})."
            self.wind.error.visible = True

    def open_wind(self) -> None:
        self.wind_open = True
        self.update_wind()

    def load_wind_data(self, data: bytes | None) -> None:
        """A measured wind CSV for the day; a bad file is refused and the day stays as it was.
        Either outcome is scrolled into view."""
        if data is None:
            return
        if self.wind.load(data, self.wind.upload.filename or ""):
            self.update_wind()
            self.reveal.show(WIND_DAY_NOTE)
        else:
            self.reveal.show(WIND_MESSAGE)

    def forget_wind_data(self) -> None:
        self.wind.forget()
        self.update_wind()

    def _culprit(self, error: ValueError) -> str:
        """The control behind a rejected parameter, as the student sees it: "L/R, rod / crank = 1 "."""
        name = _input_name(error)
        if name in FORMATS:
            return f"{self.inputs.param[name].label} = {getattr(self.inputs, name):g} "
        return "This design "

    def _show_error(self, message: str) -> None:
        self.error.object = message
        self.error.visible = True
        if self.seen is None:  # nothing drawn yet (a link's design was rejected): show the paper's
            self.seen = windpump.explore(SEED, 600.0)  # example behind it, marked not current
            with pn.io.hold():
                self._draw(self.seen)
        self.stale = True
        self._mark_stale(True)

    def _mark_stale(self, stale: bool) -> None:
        styles = STALE if stale else {"opacity": "1", "filter": "none"}
        self.results.styles = {**VIEW_FLEX_ROW, **styles}
        self.readout_row.styles = styles
        self.status.styles = styles

    def _draw(self, seen: windpump.Exploration) -> None:
        """Readouts and status first, in a message of their own, then the plots and the machine:
        the numbers a class reads arrive without waiting for ~100 KB of traces to be drawn."""
        self._readouts(seen)
        self.status.object, self.status.alert_type = (
            f"{self._status_text(seen)} {self._start_text(seen)}",
            STATUS_STYLE[seen.status],
        )
        self.download.filename = design_filename(seen.design)
        self._to_plot = seen
        document = pn.state.curdoc
        if document is not None and document.session_context is not None:
            document.add_next_tick_callback(self._plot_latest)
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
            self._show_error(
                f"Something went wrong ({type(error).__name__}: {error}); it has been logged."
            )

    def _plot(self, seen: windpump.Exploration) -> None:
        if not self.views:  # not on the page yet: show_views() draws the latest run
            return
        run = seen.run
        span = float(run.t[-1]) if run.t[-1] > 0 else float(self.inputs.t_end)
        self.time_range.update(start=0.0, end=span)
        if self._drawn_linkage != _linkage_of(seen.design):  # R, L, A or the sprockets moved
            self._drawn_linkage = _linkage_of(seen.design)
            self.machine.set_design(seen.design)
            if self._mechanisms is not None:
                self._mechanisms.set_design(seen.design)
        for view in self.views:
            view.update(seen, self.bins)

    def _readouts(self, seen: windpump.Exploration) -> None:
        figures = seen.intermittency
        started = seen.status is not Status.NEVER_STARTED
        values = {
            "mean_flow": ("Mean flow", f"{1e3 * seen.mean_flow:.4f} L/s"),
            "volume": ("Volume pumped", f"{1e3 * seen.pumped_volume:.1f} L"),
            "tau": (
                "Spin-up time τ, Eq. (25)",
                f"{seen.tau:.1f} s" if seen.tau and started else "–",
            ),
            "margin": ("Stall margin, Eq. (22)", f"{seen.margin:.3f}"),
            "peak_to_mean": ("Peak / mean flow", f"{figures.peak_to_mean:.2f}" if figures else "–"),
            "ripple": ("Speed ripple", f"{100 * figures.speed_ripple:.3f} %" if figures else "–"),
            "energy": self._energy_readout(seen),
        }
        for name, (label, value) in values.items():
            self.readouts[name].show(label, value)

    @staticmethod
    def _energy_readout(seen: windpump.Exploration) -> tuple[str, str]:
        """The run's energy balance in words that keep the sign: a slowing rotor gives energy back."""
        budget = windpump.power_budget(seen.run)
        work, kinetic, lift = (
            float(e[-1]) for e in (budget.shaft_work, budget.kinetic_energy, budget.lift_work)
        )
        if kinetic >= 0:
            return (
                "Windmill's work = gained speed + lifted water",
                f"{work:,.0f} J = {kinetic:,.0f} J + {lift:,.0f} J",
            )
        return (
            "Windmill's work + speed given back = lifted water",
            f"{work:,.0f} J + {-kinetic:,.0f} J = {lift:,.0f} J",
        )

    @staticmethod
    def _start_text(seen: windpump.Exploration) -> str:
        """Whether the rotor starts on its own: R+ T_0 against the largest load on the crank."""
        d = seen.design
        if d.T_0 == 0.0:
            return "From rest it needs a kick (no torque at rest, T₀ = 0)."
        at_rest = d.R_dagger * d.T_0
        peak = windpump.peak_load_torque(d)
        if seen.starts_from_rest:
            return f"It starts on its own from any angle (R†T₀ = {at_rest:.2f} N·m > peak load {peak:.2f} N·m)."
        return f"It does not start on its own from every angle (R†T₀ = {at_rest:.2f} N·m ≤ peak load {peak:.2f} N·m)."

    @staticmethod
    def _status_text(seen: windpump.Exploration) -> str:
        run = seen.run
        if seen.status is Status.RUNNING:
            return (
                f"**Running.** It settles at α₊ = {seen.alpha_plus:.2f} rad/s on the crank "
                f"(windmill {seen.operating_point.omega:.1f} rad/s) with τ = {seen.tau:.1f} s."
            )
        if seen.status is Status.SLOWING:
            when = seen.averaged_t_stall
            return (
                f"**Slowing to a stall.** Margin {seen.margin:.3f} ≤ 1: the windmill cannot carry the "
                f"load; the averaged theory stalls at {when:.0f} s."
                if when
                else "**Slowing to a stall.**"
            )
        if seen.status is Status.STALLED:
            return f"**Stalled** at t = {run.t_stall:.2f} s (stall margin {seen.margin:.3f})."
        if seen.theta_dot0 == 0.0 and seen.design.T_0 == 0.0:
            return "**Never started.** With no kick (θ̇₀ = 0) this windmill has no torque at rest: give it a kick."
        if run.t_stall == 0.0:
            return "**Never started.** From rest, the torque at rest cannot beat the load at θ₀: give it a kick or raise T₀."
        need = (
            f"α₋ = {seen.alpha_minus:.2f} rad/s"
            if seen.alpha_minus is not None
            else "a running margin"
        )
        return (
            f"**Never started.** The kick θ̇₀ = {seen.theta_dot0:.2f} rad/s is below {need}: "
            f"it came to rest at t = {run.t_stall:.2f} s."
        )

    # -- actions -----------------------------------------------------------------------------

    def set_values(self, **values: float | bool) -> None:
        """Set several inputs and update once."""
        self.inputs.param.update(**values)

    def reset(self) -> None:
        """Everything back to the paper's example: inputs, pinned run, lab data, Mechanisms tab."""
        self.clear_pinned()
        if self.views:
            self.operating.show_lab_data([], [])
        for pane in (self.lab_note, self.lab_message, self.apply_fit, self.preset_note):
            pane.visible = False
        self.preset.value = PRESET_PROMPT
        if self._mechanisms is not None:
            self._mechanisms.reset()
        self.set_values(**self.inputs.defaults())

    def _on_preset(self, event) -> None:
        if event.new not in PRESETS:
            return
        values, sentence = PRESETS[event.new]
        self.clear_pinned()
        self.set_values(**{**self.inputs.defaults(), **values})
        self.preset_note.object = f"**{event.new}.** {sentence}"
        self.preset_note.visible = True

    def pin(self) -> None:
        """Keep the current traces as a faint ghost to compare the next change with."""
        self.show_views()
        self.speed.pin()
        self.flow.pin()
        self.clear_button.disabled = False

    def clear_pinned(self) -> None:
        if self.views:
            self.speed.clear()
            self.flow.clear()
        self.clear_button.disabled = True

    def _restyle(self, event) -> None:
        for readout in self.readouts.values():
            readout.present(event.new)
        self._restyle_views(event.new)

    def _restyle_views(self, large: bool) -> None:
        """Presentation mode on (``large``) or back off, in every figure built so far: the text
        they draw on their canvas and their lines (the page's HTML follows ``styles.ZOOM_JS``)."""
        for fig in self.figures():
            present(fig, large)
        # Larger text leaves a plot less room: the views below the first screen grow with it
        # (the crank speed and the machine keep a projector's first screen).
        for view in self.views:
            if view not in (self.speed, self.machine):
                growth = PRESENTATION_GROWTH if large else 1
                view.figure.height = round(self.base_heights[view] * growth)

    def figures(self) -> list:
        """Every figure on the page so far: the views' and those of the tabs opened."""
        figures = [view.figure for view in self.views]
        for tab in (self._wind, self._map, self._mechanisms):
            figures.extend(tab.figures() if tab is not None else [])
        return figures

    def _presentation_from(self, query: dict, notices: list[str]) -> None:
        """``?presentation=true`` opens the page in presentation mode (kept in the link, so the
        theme switch, which reloads the page, keeps it too)."""
        raw = _text(query.get("presentation", [b""]))
        if raw in ("true", "false"):
            self.presentation = raw == "true"
        elif raw:
            notices.append(
                f"Presentation mode (presentation) = “{clipped(raw)}” ignored: true or false."
            )

    def _show_notices(self, notices: list[str]) -> None:
        """The link's ignored values, MAX_NOTICES at most (a link may carry thousands)."""
        listed = [f"- {notice}" for notice in notices[:MAX_NOTICES]]
        if len(notices) > MAX_NOTICES:
            listed.append(f"- … and {len(notices) - MAX_NOTICES} more ignored.")
        self.notices.object = "**Some values in the link were ignored:**\n\n" + "\n".join(listed)
        self.notices.visible = bool(notices)

    # -- the link ----------------------------------------------------------------------------

    def link_query(self) -> str:
        """The page's query as its link carries it: the inputs that differ from the defaults,
        each as its slider shows it, then presentation mode, the dark theme and full resolution
        if on. Nothing else: a key the page ignored is not carried on."""
        page = {"presentation": "true"} if self.presentation else {}
        if self.dark:
            page["theme"] = "dark"
        if self.bins is None:
            page["resolution"] = "full"
        return "&".join(part for part in (self.inputs.query(), urlencode(page)) if part)

    def follow_in_link(self, location) -> None:
        """Keep ``location`` (a served page's ``pn.state.location``) on ``link_query()``: written
        on every change, and written again when the browser reports the address it opened."""
        self._location = location
        self.inputs.param.watch(self._write_link, self.inputs.names())
        self.param.watch(self._write_link, "presentation")
        location.param.watch(self._write_link, "search")
        self._write_link()

    def _write_link(self, *_events) -> None:
        query = self.link_query()
        search = f"?{query}" if query else ""
        if self._location is not None and self._location.search != search:
            self._location.search = search

    # -- files -------------------------------------------------------------------------------

    def _csv(self) -> io.StringIO:
        return io.StringIO(self.seen.run.to_csv(litres=True) if self.seen else "")

    def load_lab_data(self, data: bytes | None) -> None:
        """A CSV of windmill speed [rad/s] and torque [N m]: fit Eq. (11); apply T_m and omega_m
        if the fit is good, else show it with a warning and apply it only on request."""
        self.apply_fit.visible = False
        self._pending_fit = None
        if data is None:
            return
        try:
            table = windpump.read_torque_csv(data)
            fit = windpump.fit_torque_curve(table.omega, table.torque)
        except ValueError as error:
            self._refuse_lab_file(error)
            return
        self.show_views()
        self.operating.show_lab_data(table.omega, table.torque)
        summary = (
            f"Fitted Eq. (11) to {len(table.omega)} points: Tₘ = {fit.T_m:.3f} N·m, "
            f"ωₘ = {fit.omega_m:.1f} rad/s (rms residual {fit.rms_residual:.3g} N·m, "
            f"{100 * fit.relative_residual:.0f} % of Tₘ)."
        )
        if fit.poor:
            outside = self._outside_sliders(fit)
            self.lab_message.object = (
                f"**A poor fit.** {summary} Eq. (11) misses these data by more than "
                f"{100 * fit.POOR:.0f} % of Tₘ: are the columns speed, then torque? "
                + (
                    f"It cannot be applied: {'; '.join(outside)}. Nothing was changed."
                    if outside
                    else "Not applied."
                )
            )
            self.lab_message.alert_type = "warning"
            self.lab_message.visible = True
            self._pending_fit = None if outside else fit
            self.apply_fit.visible = not outside  # offer only what can be applied
            self.reveal.show(LAB_MESSAGE)
            return
        self.lab_message.visible = False
        self._apply_fit(fit, summary)

    def _on_refused_upload(self, _event) -> None:
        """The page stopped a file over the size limit before sending it: say so, in the core's
        words; a value that is not a size over the limit (tampered) is ignored."""
        size = self.refused_upload.size
        if size is None:
            return
        if self.refused_upload.wind:
            self.wind.refuse_size(size)
            self.reveal.show(WIND_MESSAGE)
            return
        try:
            windpump.labdata.check_file_size(size)
        except ValueError as error:
            self._refuse_lab_file(error)

    def _refuse_lab_file(self, error: ValueError) -> None:
        self.apply_fit.visible = False
        self._pending_fit = None
        self.lab_message.object = (
            f"**Could not use that file.** {_sentence(error)} Nothing was changed."
        )
        self.lab_message.alert_type = "danger"
        self.lab_message.visible = True
        self.reveal.show(LAB_MESSAGE)

    def _outside_sliders(self, fit: windpump.TorqueFit) -> list[str]:
        """Why the fit cannot be set on the sliders: each value outside its slider's range."""
        return [
            f"{self.inputs.param[name].label} = {value:.3g} is outside {low:g}–{high:g}"
            for name, value in (("T_m", fit.T_m), ("omega_m", fit.omega_m))
            for low, high in [self.inputs.param[name].bounds]
            if not low <= value <= high
        ]

    def _apply_fit(self, fit: windpump.TorqueFit | None, summary: str = "") -> None:
        if fit is None:
            return
        outside = self._outside_sliders(fit)
        if outside:
            self.apply_fit.visible = False
            self.lab_message.object = (
                f"**The fit cannot be applied:** {'; '.join(outside)}. Nothing was changed."
            )
            self.lab_message.alert_type = "danger"
            self.lab_message.visible = True
            self.reveal.show(LAB_MESSAGE)
            return
        self.apply_fit.visible = False
        self.lab_note.object = (
            summary or f"Applied the fit: Tₘ = {fit.T_m:.3f} N·m, ωₘ = {fit.omega_m:.1f} rad/s."
        )
        self.lab_note.visible = True
        self.set_values(T_m=fit.T_m, omega_m=fit.omega_m)
        self.reveal.show(LAB_NOTE)

    # -- layout ------------------------------------------------------------------------------

    def controls(self) -> pn.Column:
        main = [self.sliders[name] for name, (_f, place) in FORMATS.items() if place == "main"]
        more = pn.Card(
            *(self.sliders[name] for name, (_f, place) in FORMATS.items() if place == "more"),
            header=card_header("More parameters"),
            collapsed=True,
            sizing_mode="stretch_width",
            stylesheets=TEXT,
        )
        return pn.Column(
            self.preset,
            self.preset_note,
            *main,
            *self.switches.values(),
            more,
            pn.Row(self.pin_button, self.clear_button, sizing_mode="stretch_width"),
            self.reset_button,
            self.copy_link,
            pn.Row(self.present_toggle, self.dark_toggle, sizing_mode="stretch_width"),
            pn.pane.Markdown(
                "**Lab data**: a CSV of windmill speed [rad/s], torque [N·m]", stylesheets=TEXT
            ),
            self.lab_data,
            self.refused_upload,
            self.reveal,
            self.lab_message,
            self.apply_fit,
            self.lab_note,
            self.download,
            sizing_mode="stretch_width",
        )

    def _build_results(self) -> None:
        self.readout_row = pn.FlexBox(
            *(self.readouts[name] for name in READOUTS), sizing_mode="stretch_width"
        )
        self.results = pn.FlexBox(
            pn.pane.Markdown("Drawing the plots and the machine…", stylesheets=TEXT),
            flex_wrap="wrap",
            sizing_mode="stretch_width",
            styles=VIEW_FLEX_ROW,
        )

    def _view_panels(self) -> list:
        panels = [view.panel(styles=VIEW_FLEX) for view in self.views]
        # After the views, across the page: beside the machine it made the first row of views
        # taller than its neighbours, and a band of blank space under them.
        about = pn.Card(
            pn.pane.Markdown(ABOUT, stylesheets=TEXT, sizing_mode="stretch_width"),
            header=card_header("What is this machine?"),
            collapsed=True,
            sizing_mode="stretch_width",
            stylesheets=TEXT,
        )
        return [*panels, about]

    def pump(self) -> pn.Column:
        return pn.Column(
            self.notices,
            self.error,
            self.readout_row,
            self.status,
            self.results,
            sizing_mode="stretch_width",
        )

    def main(self) -> pn.Tabs:
        tabs = pn.Tabs(
            ("Wind pump", self.pump()),
            ("Mechanisms", pn.pane.Markdown("Loading the mechanisms…", stylesheets=TEXT)),
            ("Wind", pn.pane.Markdown("Running a day of wind…", stylesheets=TEXT)),
            ("Design map", pn.pane.Markdown("Mapping the design…", stylesheets=TEXT)),
            dynamic=False,
            sizing_mode="stretch_width",
            stylesheets=[
                f":host {{ font-size: {px(16)}; }}",
                f".bk-tab {{ font-size: {px(16)}; }}",
                # four headers fit a phone's width
                "@media (max-width: 500px) { .bk-tab { font-size: 14px; padding: 8px 6px !important; } }",
                TAB_FOCUS_CSS,
                # Panel keeps a hidden tab's content laid out (visibility: hidden), so the page
                # was as tall as the longest tab: a short tab scrolled into blank space.
                ':host > [aria-hidden="true"] { max-height: 0; overflow: hidden; }',
            ],
        )

        def open_mechanisms(event) -> None:
            if event.new == 1 and not isinstance(tabs[1], pn.Column):
                tabs[1] = ("Mechanisms", self.mechanisms.layout())
            if event.new == 2 and not self.wind_open:
                self.open_wind()  # data first: a figure sent empty warns in the browser
                tabs[2] = ("Wind", self.wind.layout())
            if event.new == 3 and not self.map_open:
                self.open_map()
                tabs[3] = ("Design map", self.design_map.layout())
            if self.presentation:
                self._restyle_views(True)

        tabs.param.watch(open_mechanisms, "active")
        tabs.jscallback(active=GUARD_NEW_UPLOADS_JS)
        self.tabs = tabs
        return tabs

    def __panel__(self) -> pn.Row:
        return pn.Row(
            pn.Column(self.controls(), width=340), self.main(), sizing_mode="stretch_width"
        )

    def template(self) -> pn.template.BootstrapTemplate:
        page = pn.template.BootstrapTemplate(
            title="Wind pump explorer",
            header=[
                pn.pane.HTML(
                    "M. Louge, <i>A simple wind-pump analysis</i> (2010)", stylesheets=CITATION_CSS
                )
            ],
            sidebar=[self.controls()],
            main=[self.main()],
            sidebar_width=330,
            header_background="#0b4f8a",
            theme="dark" if self.dark else "default",
            meta_viewport="width=device-width, initial-scale=1",
            # Panel's busy spinner follows the whole server's activity, so every other student's
            # move made it spin on this page and sent it a message: a class of 30 loading at once
            # kept 30 spinners turning and the server messaging every page for everyone's work.
            busy_indicator=None,
        )
        page.config.raw_css.extend([NARROW_CSS, PAGE_FOCUS_CSS, zoom_css(self.presentation)])
        return page


def card_header(title: str) -> pn.pane.HTML:
    """A card's title at the page's text size (Panel's own title keeps a fixed size)."""
    return pn.pane.HTML(f"<b>{title}</b>", stylesheets=[*TEXT, ":host { margin: 2px 6px; }"])


def _readable(query: dict) -> tuple[dict, list[str]]:
    """``query``, or nothing and a notice if it is longer than MAX_QUERY characters (a link of
    this page is a few hundred)."""
    size = sum(len(key) + sum(len(v) + 2 for v in _listed(raw)) for key, raw in query.items())
    if size <= MAX_QUERY:
        return query, []
    return {}, [
        f"The link was too long ({size / 1024:.0f} KB; at most {MAX_QUERY // 1024} KB): "
        "its parameters were ignored."
    ]


def _listed(raw) -> list:
    return list(raw) if isinstance(raw, list | tuple) else [raw]


def _input_name(error: Exception) -> str | None:
    """The input behind a parameter the core refused (the core names R1 and L, the page R† and
    L/R)."""
    name = getattr(error, "name", None)
    return {"L": "L_over_R", "R1": "R_dagger"}.get(name, name)


def _linkage_of(design: windpump.Design) -> tuple[float, ...]:
    """What the Mechanisms tab and the machine's fixed drawing depend on."""
    return (design.R, design.L, design.A, design.R0, design.R1)


def _text(raw) -> str:
    raw = raw[-1] if isinstance(raw, list | tuple) and raw else raw
    return raw.decode("utf-8", "replace") if isinstance(raw, bytes) else str(raw or "")


def _chosen(upload: pn.widgets.FileInput) -> bytes | None:
    """The chosen file's content, or None before one is chosen: Panel reports an empty file as
    None (the value it had), so only its name tells that one was chosen."""
    if upload.value is None and upload.filename:
        return b""
    return upload.value


def _sentence(error: Exception) -> str:
    text = str(error)
    return text[0].upper() + text[1:] + ("" if text.endswith(".") else ".")


COPY_LINK_JS = """
const url = window.location.href
const done = () => { cb_obj.label = 'Link copied' ; setTimeout(() => { cb_obj.label = 'Copy link to this state' }, 2500) }
if (navigator.clipboard && window.isSecureContext) {
  navigator.clipboard.writeText(url).then(done, () => window.prompt('Copy this link:', url))
} else {
  const area = document.createElement('textarea'); area.value = url; document.body.appendChild(area)
  area.select(); const ok = document.execCommand('copy'); area.remove()
  if (ok) done(); else window.prompt('Copy this link:', url)
}
"""

# The paper beside the title, left out on a phone (the header keeps one line there).
CITATION_CSS = [
    f":host {{ color: white; font-size: {px(18)}; align-self: center; margin-left: 1em; }}",
    "@media (max-width: 700px) { :host { display: none !important; } }",
]

# Below 700 px the sidebar stacks above the views and the page scrolls as one column.
NARROW_CSS = """
#header .title { white-space: normal; }
@media (max-width: 700px) {
  #header .title { font-size: 1.05rem; }
  #content { flex-direction: column; flex-wrap: nowrap; overflow-y: auto !important; }
  #content > #sidebar { max-width: 100% !important; width: 100% !important; }  /* outranks the template's */
  #sidebar, #sidebar > * { max-height: none !important; height: auto !important; overflow: visible !important; }  /* no scroll of its own */
  #main { max-height: none !important; overflow: visible !important; width: 100%; }
}
"""

# The template's theme is set when the page is built: switch it through the link, keeping the state.
DARK_JS = """
const url = new URL(window.location.href)
if (url.searchParams.get('theme') === 'dark') url.searchParams.delete('theme')
else url.searchParams.set('theme', 'dark')
window.location.href = url.toString()
"""

ABOUT = """
A windmill turns a small sprocket of radius R₀; a chain drives a large sprocket of radius R₁ on the
crankshaft, so the windmill turns R† = R₁/R₀ times faster than the crank (Eq. 4). A crank of radius R
and a rod of length L drive a single-acting piston of cross-section A: while it moves up it lifts the
water above it by a head h (the *exhaust* half of a revolution); while it moves down it takes water in.

The windmill's torque T = Tₘ x(2 − x), x = ω/ωₘ (Eq. 11), is zero at rest and at 2ωₘ: the pump must
be *kicked* into motion. It then spins up over a time constant τ (Eq. 25) to a steady speed α₊
(Eq. 21), pulsing once per revolution, unless the load is more than the windmill can carry: the
stall criterion, Eq. (22). Press ▶ Play to watch the computed run; the time cursor on the plots
follows it, and the scrubber moves through it. The model is M. Louge, *A simple wind-pump analysis*, Cornell University (2010).
"""
