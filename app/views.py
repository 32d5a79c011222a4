"""The explorer's views: each owns its figure, its named data sources and ``update(seen)``.

Sources are refilled in place, and only when their data changed, so a slider move sends what it
changed and nothing else. Every number drawn comes from ``windpump``.
"""

from __future__ import annotations

import math

import numpy as np
import panel as pn
from bokeh.models import (
    ColumnDataSource,
    CustomJS,
    FactorRange,
    HoverTool,
    NumeralTickFormatter,
    Range1d,
)

import windpump
from windpump.units import LITRES_PER_M3

from .envelope import band
from .figures import (
    FACES,
    HEIGHT,
    LABEL,
    PHONE_FRAME,
    draw_band,
    empty,
    legend,
    line,
    new_figure,
    palette,
)
from .readouts import TextOnlyUpdates, running_tsr, shown_totals
from .styles import CAPTION_CSS

BINS = 450  # min/max bands of 2-pixel bins on the widest a view is drawn: fewer points than pixels
CLOSEUP_REVOLUTIONS = 3


def same(old, new) -> bool:
    """True when two column dicts hold the same columns and values."""
    if old.keys() != new.keys():
        return False
    for key, value in new.items():
        try:
            a, b = np.asarray(old[key]), np.asarray(value)
        except ValueError:  # ragged (lists of lists of several lengths): compare as lists
            if list(old[key]) != list(value):
                return False
            continue  # and the other columns
        if a.shape != b.shape or a.dtype.kind != b.dtype.kind:
            return False
        if a.dtype.kind == "f" and not np.array_equal(a, b, equal_nan=True):
            return False
        if a.dtype.kind != "f" and not np.array_equal(a, b):
            return False
    return True


def refill(source: ColumnDataSource, data: dict) -> None:
    """Replace a source's data, unless it already holds exactly that (then nothing is sent)."""
    if not same(source.data, data):
        source.data = data


def band_data(t, values, bins) -> dict:
    return dict(zip(("t", "lower", "upper"), band(t, values, bins), strict=True))


def level(value: float | None, t_end: float) -> dict:
    return (
        {"t": [0.0, t_end], "speed": [value, value]}
        if value is not None
        else {"t": [], "speed": []}
    )


def caption_pane(caption: str) -> pn.pane.HTML:
    """A view's caption, under it on the page."""
    return pn.pane.HTML(f"<p>{caption}</p>", stylesheets=CAPTION_CSS)


class Caption(TextOnlyUpdates, pn.pane.HTML):
    """A view's caption that says what the view draws now: a change sends its text alone."""

    def __init__(self, caption: str, **params):
        super().__init__(f"<p>{caption}</p>", stylesheets=CAPTION_CSS, **params)


class View:
    """A figure with a one-line caption naming its equation; subclasses fill ``sources``."""

    caption = ""
    height = HEIGHT  # [px] the figure's, before presentation mode

    def __init__(self, dark: bool = False):
        self.sources: dict[str, ColumnDataSource] = {}
        self.dark = dark
        self.colors = palette(dark)  # the theme's: every drawn colour stands out of its background

    def drawing(self) -> pn.pane.Bokeh:
        """The figure as the page shows it, above its caption."""
        return pn.pane.Bokeh(self.figure, sizing_mode="stretch_width")

    def caption_panel(self) -> pn.pane.HTML:
        """The caption under the figure: ``caption``, or (a view whose figure draws one thing or
        another) what it draws now."""
        return caption_pane(self.caption)

    def panel(self, **options) -> pn.Column:
        return pn.Column(
            self.drawing(), self.caption_panel(), sizing_mode="stretch_width", **options
        )

    def update(self, seen: windpump.Exploration, bins: int | None) -> None:
        raise NotImplementedError


class TimeView(View):
    """A view against the run's time, on the axis shared by every time view, with the player's
    time cursor."""

    def __init__(self, time_range: Range1d, cursor: ColumnDataSource, dark: bool = False):
        super().__init__(dark)
        self.time_range, self.cursor = time_range, cursor

    def time_figure(self, title: str, y_label: str, tooltips: list, **options):
        fig = new_figure(title, "time t [s]", y_label, x_range=self.time_range, **options)
        fig.vspan(
            x="t", source=self.cursor, line_color=self.colors["cursor"], line_width=2, alpha=0.6
        )
        fig.add_tools(HoverTool(tooltips=tooltips, mode="vline", renderers=[]))
        return fig

    def hover_on(self, *renderers) -> None:
        hover = self.figure.select_one(HoverTool)
        hover.renderers = list(renderers)

    # A view with a band named ``traced`` keeps a pinned run as ``<traced>_ghost``.
    traced = ""

    def band(self, seen: windpump.Exploration, bins: int | None) -> dict:
        """The band drawn for ``seen``: its ``t``, ``lower`` and ``upper``."""
        raise NotImplementedError

    def pin(self) -> None:
        """Keep the current band as a faint ghost to compare the next run with."""
        self.sources[f"{self.traced}_ghost"].data = dict(self.sources[self.traced].data)
        self.items["pinned run"].visible = True

    def pin_run(self, seen: windpump.Exploration, bins: int | None) -> None:
        """Keep ``seen``'s band as the ghost (a run pinned before this view was built)."""
        self.sources[f"{self.traced}_ghost"].data = self.band(seen, bins)
        self.items["pinned run"].visible = True

    def clear(self) -> None:
        self.sources[f"{self.traced}_ghost"].data = {"t": [], "lower": [], "upper": []}
        self.items["pinned run"].visible = False

    def show_ghost(self) -> None:
        self.items["pinned run"].visible = len(self.sources[f"{self.traced}_ghost"].data["t"]) > 0


class SpeedView(TimeView):
    traced = "speed"
    caption = (
        "Crank speed θ̇: the full Eq. (12) as a min–max band, its mean per revolution, the "
        "averaged spin-up of Eq. (24) and the steady speeds α± of Eq. (21)."
    )

    def __init__(self, time_range, cursor, dark: bool = False):
        super().__init__(time_range, cursor, dark)
        s, c = self.sources, self.colors
        s.update({name: empty("t", "speed") for name in ("spinup", "cycle_mean", "alpha_plus")})
        s["alpha_minus"] = empty("t", "speed")
        s["speed"] = empty("t", "lower", "upper")
        s["speed_ghost"] = empty("t", "lower", "upper")
        self.figure = fig = self.time_figure(
            "Crank speed",
            "θ̇ [rad/s]",
            [("t", "@t{0.00} s"), ("θ̇", "@lower{0.000} to @upper{0.000} rad/s")],
        )
        fig.tags = [
            {"phone_frame": PHONE_FRAME}
        ]  # figures.FIT_TEXT_JS: whole in a phone's first screen
        ghost = draw_band(fig, s["speed_ghost"], c["ghost"])
        integrated = draw_band(fig, s["speed"], c["integrated"])
        averaged = line(fig, "t", "speed", s["spinup"], c["averaged"], 3, "dashed")
        mean = line(fig, "t", "speed", s["cycle_mean"], c["mean"])
        self.items = legend(
            fig,
            {
                "full, Eq. (12)": integrated,
                "averaged, Eq. (24)": averaged,
                "cycle mean": mean,
                "α₊, Eq. (21)": line(
                    fig, "t", "speed", s["alpha_plus"], c["alpha_plus"], 2, "dotted"
                ),
                "α₋, Eq. (21)": line(
                    fig, "t", "speed", s["alpha_minus"], c["alpha_minus"], 2, "dotted"
                ),
                "pinned run": ghost,
            },
        )
        self.hover_on(integrated[0])

    def band(self, seen, bins):
        return band_data(seen.run.t, seen.run.theta_dot, bins)

    def update(self, seen, bins):
        run, s = seen.run, self.sources
        t_end = float(run.t[-1])
        refill(s["speed"], self.band(seen, bins))
        refill(s["spinup"], {"t": seen.spinup_t, "speed": seen.spinup_speed})
        cycle_t, lower, upper = band(seen.cycle_t, seen.cycle_speed, bins)
        refill(s["cycle_mean"], {"t": cycle_t, "speed": 0.5 * (lower + upper)})
        refill(s["alpha_plus"], level(seen.alpha_plus, t_end))
        near = seen.alpha_minus is not None and run.theta_dot.min() < 2 * seen.alpha_minus
        refill(s["alpha_minus"], level(seen.alpha_minus if near else None, t_end))
        for label, name in (("α₊, Eq. (21)", "alpha_plus"), ("α₋, Eq. (21)", "alpha_minus")):
            self.items[label].visible = len(s[name].data["t"]) > 0
        self.items["cycle mean"].visible = len(cycle_t) > 0
        self.show_ghost()


class FlowView(TimeView):
    traced = "flow"
    caption = (
        "Flow Q = A ẋ (Eq. 16) over the whole run as a min–max band (the pulses are too fast to "
        "draw one by one) and its mean."
    )

    def __init__(self, time_range, cursor, dark: bool = False):
        super().__init__(time_range, cursor, dark)
        s, c = self.sources, self.colors
        s["flow"] = empty("t", "lower", "upper")
        s["flow_ghost"] = empty("t", "lower", "upper")
        s["mean_flow"] = empty("t", "flow")
        self.figure = fig = self.time_figure(
            "Flow rate over the run",
            "Q [L/s]",
            [("t", "@t{0.00} s"), ("Q", "@lower{0.0000} to @upper{0.0000} L/s")],
        )
        ghost = draw_band(fig, s["flow_ghost"], c["ghost"])
        instantaneous = draw_band(fig, s["flow"], c["flow"])
        self.items = legend(
            fig,
            {
                "Q, min to max": instantaneous,
                "mean over the run": line(fig, "t", "flow", s["mean_flow"], c["mean"], 3, "dashed"),
                "pinned run": ghost,
            },
        )
        self.hover_on(instantaneous[0])

    def band(self, seen, bins):
        return band_data(seen.run.t, LITRES_PER_M3 * seen.run.flow, bins)

    def update(self, seen, bins):
        run, s = seen.run, self.sources
        refill(s["flow"], self.band(seen, bins))
        refill(
            s["mean_flow"],
            {"t": [0.0, float(run.t[-1])], "flow": [LITRES_PER_M3 * seen.mean_flow] * 2},
        )
        self.show_ghost()


class CloseupView(View):
    caption = (
        "The last revolutions (or the last turns before a stall), every sample: one delivery "
        "pulse per revolution and face while it delivers, none while it takes water in; with "
        "several faces, each face's pulses (thin) and their sum (thick)."
    )

    def __init__(self, dark: bool = False):
        super().__init__(dark)
        self.sources["closeup"] = empty("t", "flow")
        self.sources["closeup_faces"] = empty("xs", "ys", "color")
        self.figure = fig = new_figure(
            "Close-up: the last revolutions",
            "time t [s]",
            "Q [L/s]",
            tools="pan,box_zoom,reset,save",
        )
        fig.multi_line(
            "xs", "ys", source=self.sources["closeup_faces"], line_color="color", line_width=1.5
        )
        flow = self.colors["flow"]
        drawn = line(fig, "t", "flow", self.sources["closeup"], flow, width=3)
        fig.scatter("t", "flow", source=self.sources["closeup"], color=flow, size=4)
        fig.add_tools(
            HoverTool(
                tooltips=[("t", "@t{0.000} s"), ("Q", "@flow{0.0000} L/s")],
                mode="vline",
                renderers=[drawn],
            )
        )

    def update(self, seen, bins):
        run = seen.run
        window = run.last_revolutions(CLOSEUP_REVOLUTIONS)
        t = run.t[window]
        refill(self.sources["closeup"], {"t": t, "flow": LITRES_PER_M3 * run.flow[window]})
        faces = run.face_flows()[:, window] if run.design.deliveries > 1 else np.empty((0, 0))
        delivering = [k for k in range(len(faces)) if faces[k].any()]
        faces_colors = FACES[self.dark]
        refill(
            self.sources["closeup_faces"],
            {
                "xs": [t] * len(delivering),
                "ys": [LITRES_PER_M3 * faces[k] for k in delivering],
                "color": [faces_colors[(k // 2) % len(faces_colors)] for k in delivering],
            },
        )


# The waterfall's x range in the browser, where the frame's width and the labels' are known: to
# the right of each bar its label (at ``offset`` px), so the range ends where the farthest label
# ends, and no further (the bars as long as the labels leave room for).
FIT_BARS_JS = """
const right = source.data.right, labels = source.data.label, width = plot.inner_width
if (!right || right.length === 0 || !(width > 0)) return
const ctx = document.createElement('canvas').getContext('2d')
const size = glyph.text_font_size  // a glyph's: a value spec, {value: '15px'}
ctx.font = `${size?.value ?? size} helvetica`
let end = 1.02 * Math.max(...right, 1e-9)
for (let i = 0; i < right.length; i++) {
  const share = (ctx.measureText(String(labels[i])).width + offset + 6) / width
  end = Math.max(end, right[i] / Math.max(1 - share, 0.25))  // its label ends at the range's end
}
if (plot.x_range.end !== end) plot.x_range.end = end
"""


class EnergyView(View):
    caption = (
        "Over the run, the windmill's work W = ∫ T ω dt, and where it went: the chain (1 − η_t) W, "
        "the rising main's friction ∫ ρ_w g h_f Q dt, the leak hole, the spinning up "
        "Δ(½ J θ̇²) and the rod's weight, and the lifted water ρ_w g h V (a slowing rotor gives "
        "energy back: its bar goes up). Each share is of the energy that came in: W and what "
        "the rotor gave back."
    )
    STEPS = ("windmill's work", "chain", "rising main", "leak hole", "spinning up", "lifted water")
    COLORS = ("windmill", "structure", "wind", "data", "alpha_minus", "flow")

    def __init__(self, dark: bool = False):
        super().__init__(dark)
        self.sources["losses"] = empty("step", "left", "right", "label", "color", "at")
        self.figure = fig = new_figure(
            "Where the windmill's work goes",
            "work over the run [J]",
            "",
            tools="save",
            y_range=FactorRange(*reversed(self.STEPS)),
        )
        source = self.sources["losses"]
        fig.hbar(y="step", left="left", right="right", height=0.6, color="color", source=source)
        labels = fig.text(
            x="at", y="step", text="label", source=source, text_baseline="middle",
            text_font_size=LABEL, x_offset=6, color=self.colors["ink"],
        )  # fmt: skip
        fig.x_range.start = 0
        fig.xaxis.ticker.desired_num_ticks = 3  # "10000 15000 20000" ran together at 300 px
        fig.xaxis.formatter = NumeralTickFormatter(format="0,0")  # 150,000, not 1.500e+5
        fit = CustomJS(
            args=dict(plot=fig, source=source, glyph=labels.glyph, offset=6), code=FIT_BARS_JS
        )
        source.js_on_change("data", fit)
        fig.js_on_change("inner_width", fit)
        fig.x_range.js_on_change("end", fit)  # the server's, set with new bars
        labels.glyph.js_on_change("text_font_size", fit)  # presentation mode

    def update(self, seen, bins):
        refill(self.sources["losses"], self.waterfall(seen.energy_totals))

    def waterfall(self, totals: windpump.EnergyTotals) -> dict:
        """The bars: W from 0, each loss hanging from what is left, the water from 0; each
        labelled with its joules and its share of the energy that came in (W, and what a
        slowing rotor gave back)."""
        spin = totals.kinetic + totals.potential
        W = totals.shaft
        left, right, running = [0.0], [W], W
        for loss in (totals.transmission, totals.friction, totals.leak, spin):
            left.append(min(running, running - loss))
            right.append(max(running, running - loss))
            running -= loss
        left.append(0.0)
        right.append(totals.water)
        values = (W, totals.transmission, totals.friction, totals.leak, spin, totals.water)
        # Shares of the energy that came in: the windmill's work, and what a slowing rotor gave
        # back (of W alone, a stalling pump's water was "156 J, 456 %")
        came_in = W + max(-spin, 0.0)
        share = [100.0 * abs(v) / came_in if came_in > 0 else 0.0 for v in values]
        joules = list(shown_totals(totals).values())  # as the readout shows them, adding up
        labels = [f"{v:,} J, {p:.0f} %" for v, p in zip(joules, share, strict=True)]
        if spin < 0:
            labels[4] = f"{-joules[4]:,} J given back, {share[4]:.0f} %"
        # the bars; the page makes room for their labels (FIT_BARS_JS)
        self.figure.x_range.end = 1.02 * max(max(right), 1e-9)
        return {
            "step": list(self.STEPS),
            "left": left,
            "right": right,
            "label": labels,
            "color": [self.colors[c] for c in self.COLORS],
            "at": right,
        }


SUPERSCRIPTS = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def superscript(power: int) -> str:
    """An exponent as a reader writes it: 10⁻⁴, not 10^-4."""
    return str(power).translate(SUPERSCRIPTS)


class StallView(View):
    caption = (
        "Eq. (22): it can run while the windmill's characteristic torque Tₘ† (Eq. 14) exceeds the "
        "mean load m R† L†/π (Eq. 15; m deliveries per revolution: 1 in the paper, cylinders × 2 "
        "when double-acting)."
    )
    NAMES = ("windmill: Tₘ†", "load: m R† L†/π")
    height = HEIGHT * 3 // 4

    def __init__(self, dark: bool = False):
        super().__init__(dark)
        self.sources["stall"] = ColumnDataSource(
            {
                "name": list(self.NAMES),
                "value": [0.0, 0.0],
                "color": [self.colors["windmill"], self.colors["load"]],
            }
        )
        self.figure = fig = new_figure(
            "Stall criterion, Eq. (22)",
            "dimensionless torque",
            "",
            height=self.height,
            tools="save",
            y_range=FactorRange(*self.NAMES),
        )
        fig.hbar(y="name", right="value", height=0.6, color="color", source=self.sources["stall"])
        fig.x_range.start = 0
        fig.xaxis.ticker.desired_num_ticks = 5

    def update(self, seen, bins):
        sides = np.array(windpump.stall_sides(seen.design))
        power = math.floor(math.log10(sides.max()))
        data = {**self.sources["stall"].data, "value": sides / 10.0**power}
        refill(self.sources["stall"], data)
        self.figure.xaxis.axis_label = f"Eqs. (14, 15) [×10{superscript(power)}]"
        verdict = "runs" if seen.margin > 1 else "stalls"
        margin = "∞" if math.isinf(seen.margin) else f"{seen.margin:.3f}"  # a leak hole, h = 0
        # two short lines: one long line was cut on a phone and in presentation mode
        self.figure.title.text = f"Stall criterion, Eq. (22)\nmargin {margin}: it {verdict}"


class OperatingView(View):
    """The windmill against the pump: for the paper's curve (Eq. 11) its power T(ω) ω and the
    pump's load line with the operating points; for a rotor (a wheel of a C_Q table) its torque
    and power coefficients C_Q(λ) and C_P(λ) against the tip-speed ratio, with where it runs."""

    caption = (
        "Eq. (5): the windmill's power T(ω) ω (Eq. 11) against the pump's load line; they meet at "
        "the operating point (filled: stable) and an unstable one (open). A wheel: its torque "
        "and power coefficients C_Q(λ) and C_P(λ) = λ C_Q against the tip-speed ratio "
        "λ = ω r / V, and where it runs (ω = R† α₊)."
    )  # until the first run is drawn (the view's placeholder); then what it draws (``said``)
    CURVE_CAPTION = (
        "Eq. (5): the windmill's power T(ω) ω (Eq. 11, solid) against the pump's load line (its "
        "power at each speed); they meet at the operating point (filled: stable) and an unstable "
        "one (open)."
    )
    ROTOR_CAPTION = (
        "The wheel's coefficients against the tip-speed ratio λ = ω r / V: solid, its torque "
        "coefficient C_Q(λ) (its torque T = ½ ρ π r³ V² C_Q, largest at rest); dashed, its power "
        "coefficient C_P(λ) = λ C_Q (the share it takes of the wind's power through its disc, "
        "½ ρ π r² V³). {where}"
    )
    TITLES = {
        False: ("Operating point, Eq. (5)", "windmill speed ω [rad/s]", "power [W]"),
        True: ("The wheel's coefficients", "tip-speed ratio λ = ω r / V", "C_Q, C_P [–]"),
    }
    ROTOR_ITEMS = ("torque coefficient C_Q", "power coefficient C_P", "where it runs")
    CURVE_ITEMS = ("windmill, Eq. (11)", "pump load, Eq. (5)", "operating point", "unstable")

    def __init__(self, dark: bool = False):
        super().__init__(dark)
        s, c = self.sources, self.colors
        s.update(
            {
                name: empty("omega", "power")
                for name in ("curve", "load_line", "stable", "unstable", "data")
            }
        )
        s.update({name: empty("tsr", "cq", "cp") for name in ("coefficients", "running")})
        self.rotor = False  # what is drawn: a rotor's coefficients, or the paper's curve
        self.figure = fig = new_figure(*self.TITLES[False], tools="pan,box_zoom,reset,save")
        point = dict(x="omega", y="power", size=14)
        curve = line(fig, "omega", "power", s["curve"], c["windmill"], 3)
        cq = line(fig, "tsr", "cq", s["coefficients"], c["windmill"], 3)
        cp = line(fig, "tsr", "cp", s["coefficients"], c["flow"], 3, "dashed")
        running = dict(source=s["running"], size=14, color=c["ink"])
        self.items = legend(
            fig,
            {
                "windmill, Eq. (11)": curve,
                "pump load, Eq. (5)": line(fig, "omega", "power", s["load_line"], c["load"], 3),
                "operating point": fig.scatter(source=s["stable"], color=c["ink"], **point),
                "unstable": fig.scatter(
                    source=s["unstable"],
                    fill_color=c["joint"],
                    line_color=c["ink"],
                    line_width=2,
                    **point,
                ),
                "lab data": fig.scatter(
                    "omega",
                    "power",
                    source=s["data"],
                    size=8,
                    marker="triangle",
                    color=c["data"],
                ),
                "torque coefficient C_Q": cq,
                "power coefficient C_P": cp,
                "where it runs": [
                    fig.scatter("tsr", "cq", **running),
                    fig.scatter("tsr", "cp", **running),
                ],
            },
        )
        fig.add_tools(
            HoverTool(
                tooltips=[("ω", "@omega{0.0} rad/s"), ("power", "@power{0.00} W")],
                renderers=[curve],
                mode="vline",
            ),
            HoverTool(
                tooltips=[("λ", "@tsr{0.00}"), ("C_Q", "@cq{0.000}"), ("C_P", "@cp{0.000}")],
                renderers=[cq],
                mode="vline",
            ),
        )
        self._show_items(False)
        self.caption_shown = Caption(self.caption)

    def caption_panel(self) -> Caption:
        return self.caption_shown

    @classmethod
    def said(cls, seen) -> str:
        """What the figure draws for ``seen``, in words (its caption): the paper's curve and the
        load line, or a wheel's C_Q and C_P, which is which and where it runs."""
        design = seen.design
        if design.rotor is None:
            return cls.CURVE_CAPTION
        op = seen.operating_point
        tsr = running_tsr(design, op.omega if op is not None else None)
        if not math.isfinite(tsr):
            where = "It does not run in this wind: no point is marked."
        else:
            cq, cp = float(design.rotor.cq(tsr)), float(design.rotor.cp(tsr))
            where = (
                f"Dots: where it runs (ω = R† α₊), λ = {tsr:.2f}, C_Q = {cq:.3f}, C_P = {cp:.3f}."
            )
        return cls.ROTOR_CAPTION.format(where=where)

    def update(self, seen, bins):
        d = seen.design
        rotor = d.rotor is not None
        if rotor:
            self._draw_rotor(seen)
        else:
            self._draw_curve(seen)
        if rotor != self.rotor:
            self.rotor = rotor
            title, x_label, y_label = self.TITLES[rotor]
            self.figure.title.text = title
            self.figure.xaxis.axis_label, self.figure.yaxis.axis_label = x_label, y_label
        self._show_items(rotor, seen.operating_point is not None)
        said = f"<p>{self.said(seen)}</p>"
        if said != self.caption_shown.object:
            self.caption_shown.object = said

    def _draw_curve(self, seen) -> None:
        """Eq. (11)'s power curve, the load line and the operating points; no coefficients."""
        d, s, op = seen.design, self.sources, seen.operating_point
        omega = np.linspace(0.0, 1.05 * d.runaway_speed, 211)  # to where T is 0, and a little
        refill(s["curve"], {"omega": omega, "power": windpump.windmill_power(d, omega)})
        refill(s["load_line"], {"omega": omega, "power": windpump.load_power(d, omega)})
        refill(s["stable"], {"omega": [op.omega] if op else [], "power": [op.power] if op else []})
        refill(
            s["unstable"],
            {
                "omega": [op.omega_unstable] if op else [],
                "power": [op.power_unstable] if op else [],
            },
        )
        for name in ("coefficients", "running"):
            refill(s[name], {"tsr": [], "cq": [], "cp": []})

    def _draw_rotor(self, seen) -> None:
        """The rotor's C_Q(λ) and C_P(λ) to a little past its runaway, and where it runs."""
        d, s, op = seen.design, self.sources, seen.operating_point
        rotor = d.rotor
        tsr = np.linspace(0.0, 1.05 * rotor.runaway_tsr, 211)
        refill(s["coefficients"], {"tsr": tsr, "cq": rotor.cq(tsr), "cp": rotor.cp(tsr)})
        here = running_tsr(d, op.omega if op is not None else None)
        at = [here] if math.isfinite(here) else []
        refill(
            s["running"],
            {"tsr": at, "cq": list(rotor.cq(np.array(at))), "cp": list(rotor.cp(np.array(at)))},
        )
        for name in ("curve", "load_line", "stable", "unstable"):
            refill(s[name], {"omega": [], "power": []})

    def _show_items(self, rotor: bool, running: bool = False) -> None:
        """The legend's items of what is drawn (and the lab points only over ω)."""
        for label in self.CURVE_ITEMS:
            self.items[label].visible = not rotor and (
                running or label.startswith(("wind", "pump"))
            )
        for label in self.ROTOR_ITEMS:
            self.items[label].visible = rotor and (running or label != "where it runs")
        lab = self.items["lab data"]
        lab.renderers[0].visible = not rotor
        lab.visible = not rotor and len(self.sources["data"].data["omega"]) > 0

    def show_lab_data(self, omega, power) -> None:
        """Measured speeds [rad/s] and shaft powers [W] (``windpump.TorqueTable.power``)."""
        self.sources["data"].data = {"omega": np.asarray(omega), "power": np.asarray(power)}
        self.items["lab data"].visible = len(omega) > 0 and not self.rotor
