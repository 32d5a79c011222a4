"""The live explorer: widgets, layout and drawing. Every number comes from ``windpump``."""

from __future__ import annotations

import io
import logging
import math

import numpy as np
import panel as pn
from envelope import band, bin_means
from figures import WIDTH, energy_view, flow_views, operating_view, speed_view, stall_view
from mechanisms import Mechanisms

import windpump
from windpump import Status

log = logging.getLogger("windpump.app")

SEED = windpump.Design.seed_example()
BINS = WIDTH // 2  # min/max bands of 2-pixel bins: fewer points than pixels across
CLOSEUP_REVOLUTIONS = 3

# name: (label with unit, start, end, step, the paper's example, display format)
MAIN_SLIDERS = {
    "L_over_R": ("L/R, rod / crank", 1.0, 10.0, 0.05, SEED.L_over_R, "0.00"),
    "R_dagger": ("R₁/R₀, sprocket ratio", 0.5, 10.0, 0.1, SEED.R_dagger, "0.0"),
    "h": ("Head h [m]", 0.0, 30.0, 0.1, SEED.h, "0.0"),
    "T_m": ("Windmill torque Tₘ [N·m]", 0.05, 5.0, 0.05, SEED.T_m, "0.00"),
}
MORE_SLIDERS = {
    "omega_m": ("Windmill peak speed ωₘ [rad/s]", 5.0, 150.0, 1.0, SEED.omega_m, "0"),
    "t_end": ("Duration t_end [s]", 10.0, 3000.0, 10.0, 600.0, "0"),
    "theta_dot0": ("Kick θ̇₀ [rad/s]", 0.0, 30.0, 0.1, 3.0, "0.0"),
    "theta0": ("Start angle θ₀ [rad]", 0.0, round(2 * math.pi, 2), 0.01, math.pi / 2, "0.00"),
    "I0": ("Rotor inertia I₀ [kg·m²]", 0.05, 10.0, 0.05, SEED.I0, "0.00"),
    "I1": ("Crank inertia I₁ [kg·m²]", 0.005, 1.0, 0.005, SEED.I1, "0.000"),
}
# Parameters the core may reject -> the slider that sets them.
SLIDER_OF_PARAMETER = {
    "L": "L_over_R",
    "R1": "R_dagger",
    **{n: n for n in (*MAIN_SLIDERS, *MORE_SLIDERS)},
}
STATUS_STYLE = {
    Status.RUNNING: "success",
    Status.SLOWING: "warning",
    Status.STALLED: "danger",
    Status.NEVER_STARTED: "warning",
}
LARGE_TEXT = [":host { font-size: 15pt; }", ".bk-slider-title { font-size: 14pt; }"]
READOUT_CSS = """
.readout {border: 1px solid #ccc; border-radius: 6px; padding: 6px 12px; min-width: 170px}
.readout .label {font-size: 13pt; color: #555}
.readout .value {font-size: 22pt; font-weight: bold}
"""


def slider(label, start, end, step, value, fmt):
    return pn.widgets.FloatSlider(
        label=label,
        start=start,
        end=end,
        step=step,
        value=value,
        format=fmt,
        stylesheets=LARGE_TEXT,
    )


def readout(label: str, value: str, name: str) -> str:
    return f'<div class="readout"><div class="label">{label}</div><div class="value" data-name="{name}">{value}</div></div>'


class Explorer:
    """One session's explorer: build it, then ``template()`` or ``layout()`` it."""

    def __init__(self, bins: int | None = BINS):
        self.bins = bins  # None: every sample of every trace (the benchmark's baseline)
        self.sliders = {
            name: slider(*spec) for name, spec in {**MAIN_SLIDERS, **MORE_SLIDERS}.items()
        }
        self.reset_button = pn.widgets.Button(label="Reset to the paper's example", color="primary")
        self.lab_data = pn.widgets.FileInput(accept=".csv,.txt", label="Lab torque curve")
        self.download = pn.widgets.FileDownload(
            callback=self._csv,
            filename="windpump_run.csv",
            label="Download this run (CSV)",
            color="light",
        )
        self.speed_figure, speed_sources = speed_view()
        self.flow_figure, self.closeup_figure, flow_sources = flow_views()
        self.stall_figure, stall_sources = stall_view()
        self.operating_figure, operating_sources = operating_view()
        self.energy_figure, energy_sources = energy_view()
        self.mechanisms = Mechanisms(slider)
        self.sources = {
            **speed_sources,
            **flow_sources,
            **stall_sources,
            **operating_sources,
            **energy_sources,
            **self.mechanisms.sources,
        }
        for name, source in self.sources.items():
            source.name = name  # so a browser can find it: Bokeh.documents[0].get_model_by_name
        self.readouts = {
            name: pn.pane.HTML("", stylesheets=[READOUT_CSS])
            for name in ("mean_flow", "volume", "tau", "margin", "peak_to_mean", "ripple", "energy")
        }
        self.status = pn.pane.Alert("", alert_type="success", stylesheets=LARGE_TEXT)
        self.error = pn.pane.Alert("", alert_type="danger", visible=False, stylesheets=LARGE_TEXT)
        self.lab_note = pn.pane.Markdown("", visible=False)
        self.seen: windpump.Exploration | None = None
        self._suspended = False
        for widget in self.sliders.values():
            widget.param.watch(self._on_change, "value")
        self.reset_button.on_click(lambda _event: self.reset())
        self.lab_data.param.watch(self._on_lab_data, "value")
        self.update()

    # -- inputs ------------------------------------------------------------------------------

    def value(self, name: str) -> float:
        return self.sliders[name].value

    def design(self) -> windpump.Design:
        """The design the sliders describe: the paper's example with its radii R and R0 kept."""
        return SEED.replace(
            L=SEED.R * self.value("L_over_R"),
            R1=SEED.R0 * self.value("R_dagger"),
            h=self.value("h"),
            T_m=self.value("T_m"),
            omega_m=self.value("omega_m"),
            I0=self.value("I0"),
            I1=self.value("I1"),
        )

    def set_values(self, **values: float) -> None:
        """Set several sliders, widening a range if needed, then update once."""
        self._suspended = True
        try:
            for name, value in values.items():
                widget = self.sliders[name]
                widget.start, widget.end = min(widget.start, value), max(widget.end, value)
                widget.value = value
        finally:
            self._suspended = False
        self.update()

    def reset(self) -> None:
        self.set_values(
            **{name: spec[4] for name, spec in {**MAIN_SLIDERS, **MORE_SLIDERS}.items()}
        )
        self.sources["data"].data = {"omega": [], "power": []}
        self.lab_note.visible = False

    def _on_change(self, *_events) -> None:
        # Panel gathers the changes that arrive while an update runs and applies the latest, so a
        # dragged slider redraws as fast as the machine can and always ends on its final value.
        if not self._suspended:
            self.update()

    # -- the one path from inputs to screen --------------------------------------------------

    def update(self) -> None:
        """Run the core on the current inputs and redraw; a rejected input shows its message."""
        try:
            seen = windpump.explore(
                self.design(), self.value("t_end"), self.value("theta0"), self.value("theta_dot0")
            )
            with pn.io.hold():
                self._draw(seen)
        except ValueError as error:  # the core's verdict on an input: say so, keep the last plots
            self._show_error(f"{self._culprit(error)}cannot be run: {error}")
        except Exception as error:  # a bug: say so, log it, keep the session alive
            log.exception("update failed")
            self._show_error(
                f"Something went wrong ({type(error).__name__}: {error}); it has been logged."
            )
        else:
            self.seen = seen
            self.error.visible = False
            self.mechanisms.set_design(seen.design)

    def _culprit(self, error: ValueError) -> str:
        """The slider behind a rejected parameter, as the student sees it: "L/R, rod / crank = 1 "."""
        name = SLIDER_OF_PARAMETER.get(getattr(error, "name", None))
        return f"{self.sliders[name].label} = {self.value(name):g} " if name else "This design "

    def _show_error(self, message: str) -> None:
        self.error.object = message
        self.error.visible = True

    def _draw(self, seen: windpump.Exploration) -> None:
        run, d = seen.run, seen.design
        t_end = float(run.t[-1])
        s = self.sources
        s["speed"].data = self._band(run.t, run.theta_dot)
        s["spinup"].data = {"t": seen.spinup_t, "speed": seen.spinup_speed}
        cycle_t, lower, upper = band(seen.cycle_t, seen.cycle_speed, self.bins)
        s["cycle_mean"].data = {"t": cycle_t, "speed": 0.5 * (lower + upper)}
        s["alpha_plus"].data = self._level(seen.alpha_plus, t_end)
        near_alpha_minus = (
            seen.alpha_minus is not None and run.theta_dot.min() < 2 * seen.alpha_minus
        )
        s["alpha_minus"].data = self._level(seen.alpha_minus if near_alpha_minus else None, t_end)

        litres = 1e3 * run.flow
        s["flow"].data = self._band(run.t, litres)
        s["mean_flow"].data = {"t": [0.0, t_end], "flow": [1e3 * seen.mean_flow] * 2}
        window = self._closeup_window(run)
        s["closeup"].data = {"t": run.t[window], "flow": litres[window]}

        self._draw_stall(seen)
        omega = np.linspace(0.0, 2.1 * d.omega_m, 211)
        s["curve"].data = {"omega": omega, "power": windpump.windmill_power(d, omega)}
        s["load_line"].data = {"omega": omega, "power": windpump.load_power(d, omega)}
        op = seen.operating_point
        s["stable"].data = {"omega": [op.omega] if op else [], "power": [op.power] if op else []}
        s["unstable"].data = {
            "omega": [op.omega_unstable] if op else [],
            "power": [op.power_unstable] if op else [],
        }

        self._draw_energy(seen)
        self._readouts(seen)
        self.status.object, self.status.alert_type = (
            self._status_text(seen),
            STATUS_STYLE[seen.status],
        )

    def _draw_stall(self, seen: windpump.Exploration) -> None:
        """Eq. (22)'s two sides in a unit that reads (x 10^k), with the margin in the title."""
        d = seen.design
        sides = np.array([d.Tm_dagger, d.R_dagger * d.L_dagger / math.pi])
        power = math.floor(math.log10(sides.max()))
        self.sources["stall"].data = {**self.sources["stall"].data, "value": sides / 10.0**power}
        self.stall_figure.xaxis.axis_label = f"dimensionless torque, Eqs. (14, 15) [× 10^{power}]"
        verdict = "runs" if seen.margin > 1 else "stalls"
        self.stall_figure.title.text = (
            f"Stall criterion, Eq. (22): margin {seen.margin:.3f}, it {verdict}"
        )

    def _draw_energy(self, seen: windpump.Exploration) -> None:
        """The ski lift's lesson on this run: per revolution, power to spin up and to lift water."""
        budget = windpump.power_budget(seen.design, seen.run)
        means = budget.cycle_means()
        self.sources["power_split"].data = bin_means(
            means.t,
            {"hydraulic": means.hydraulic, "shaft": means.shaft, "kinetic": means.kinetic},
            self.bins,
        )
        work, kinetic, lift = (
            float(e[-1]) for e in (budget.shaft_work, budget.kinetic_energy, budget.lift_work)
        )
        self.readouts["energy"].object = readout(
            "Windmill's work = gained speed + lifted water",
            f"{work:,.0f} J = {kinetic:,.0f} J + {lift:,.0f} J",
            "energy",
        )

    def _band(self, t, values) -> dict:
        return dict(zip(("t", "lower", "upper"), band(t, values, self.bins), strict=True))

    @staticmethod
    def _level(speed: float | None, t_end: float) -> dict:
        return (
            {"t": [0.0, t_end], "speed": [speed, speed]}
            if speed is not None
            else {"t": [], "speed": []}
        )

    @staticmethod
    def _closeup_window(run: windpump.SimulationResult) -> np.ndarray:
        """Samples of the last few complete revolutions (or of the whole run, if shorter)."""
        start, end = run.revolutions()
        if len(start) == 0:
            return np.ones(run.t.shape, dtype=bool)
        first = start[-min(CLOSEUP_REVOLUTIONS, len(start))]
        return (run.t >= first) & (run.t <= end[-1])

    def _readouts(self, seen: windpump.Exploration) -> None:
        figures = seen.intermittency
        values = {
            "mean_flow": ("Mean flow", f"{1e3 * seen.mean_flow:.4f} L/s"),
            "volume": ("Volume pumped", f"{1e3 * seen.pumped_volume:.1f} L"),
            "tau": ("Spin-up time τ, Eq. (25)", f"{seen.tau:.1f} s" if seen.tau else "none"),
            "margin": ("Stall margin, Eq. (22)", f"{seen.margin:.3f}"),
            "peak_to_mean": ("Peak / mean flow", f"{figures.peak_to_mean:.2f}" if figures else "–"),
            "ripple": ("Speed ripple", f"{100 * figures.speed_ripple:.3f} %" if figures else "–"),
        }
        for name, (label, value) in values.items():
            self.readouts[name].object = readout(label, value, name)

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
        need = (
            f"α₋ = {seen.alpha_minus:.2f} rad/s"
            if seen.alpha_minus is not None
            else "a running margin"
        )
        return (
            f"**Never started.** The kick θ̇₀ = {seen.theta_dot0:.2f} rad/s is below {need}: "
            f"it came to rest at t = {run.t_stall:.2f} s."
        )

    # -- files -------------------------------------------------------------------------------

    def _csv(self) -> io.StringIO:
        return io.StringIO(self.seen.run.to_csv() if self.seen else "")

    def _on_lab_data(self, event) -> None:
        """A CSV of windmill speed [rad/s] and torque [N m]: fit Eq. (11) and use T_m, omega_m."""
        try:
            table = np.genfromtxt(io.BytesIO(event.new), delimiter=",", comments="#")
            table = table[~np.isnan(table).any(axis=1)] if table.ndim == 2 else np.empty((0, 2))
            if table.shape[1] < 2 or len(table) < 2:
                raise ValueError(
                    "the file needs two columns, windmill speed [rad/s] and torque [N m]"
                )
            fit = windpump.fit_torque_curve(table[:, 0], table[:, 1])
        except Exception as error:
            self._show_error(f"Could not use that file: {error}")
            return
        self.sources["data"].data = {"omega": table[:, 0], "power": table[:, 0] * table[:, 1]}
        self.lab_note.object = (
            f"Fitted Eq. (11) to {len(table)} points: Tₘ = {fit.T_m:.3f} N·m, "
            f"ωₘ = {fit.omega_m:.1f} rad/s (rms residual {fit.rms_residual:.3g} N·m)."
        )
        self.lab_note.visible = True
        self.set_values(T_m=fit.T_m, omega_m=fit.omega_m)

    # -- layout ------------------------------------------------------------------------------

    def controls(self) -> pn.Column:
        more = pn.Card(
            *(self.sliders[name] for name in MORE_SLIDERS), title="More parameters", collapsed=True
        )
        return pn.Column(
            *(self.sliders[name] for name in MAIN_SLIDERS),
            more,
            self.reset_button,
            pn.pane.Markdown("**Lab data**: a CSV of windmill speed [rad/s], torque [N·m]"),
            self.lab_data,
            self.lab_note,
            self.download,
        )

    def main(self) -> pn.Tabs:
        return pn.Tabs(("Wind pump", self.pump()), ("Mechanisms", self.mechanisms.layout()))

    def pump(self) -> pn.Column:
        views = dict(sizing_mode="fixed")
        return pn.Column(
            pn.Row(*(self.readouts[name] for name in ("mean_flow", "volume", "tau", "margin"))),
            self.error,
            self.status,
            pn.pane.Bokeh(self.speed_figure, **views),
            self.readouts["energy"],
            pn.pane.Bokeh(self.energy_figure, **views),
            pn.pane.Bokeh(self.flow_figure, **views),
            pn.Row(self.readouts["peak_to_mean"], self.readouts["ripple"]),
            pn.pane.Bokeh(self.closeup_figure, **views),
            pn.pane.Bokeh(self.stall_figure, **views),
            pn.pane.Bokeh(self.operating_figure, **views),
        )

    def template(self) -> pn.template.BootstrapTemplate:
        return pn.template.BootstrapTemplate(
            title="Wind pump explorer — M. Louge, A simple wind-pump analysis (2010)",
            sidebar=[self.controls()],
            main=[self.main()],
            sidebar_width=380,
            header_background="#0b4f8a",
        )
