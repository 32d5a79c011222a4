"""The Wind tab's figures: the pump against steady wind, and a day of wind run in full."""

from __future__ import annotations

import math

from bokeh.models import HoverTool, LinearAxis, NumeralTickFormatter, Range1d, Span

from windpump.units import SECONDS_PER_DAY, SECONDS_PER_HOUR

from .figures import HEIGHT, TICKS, draw_band, empty, grow_in_presentation, legend, line, new_figure


def curve_figure(s: dict, c: dict):
    """Water against steady wind, the site's Weibull density on a second axis and the V_stop
    and V_start lines: (figure, stop line, start line). ``s`` gets its sources, ``c`` the colours."""
    s["curve"] = empty("V", "flow")
    s["density"] = empty("V", "density")
    s["here"] = empty("V", "flow")
    fig = new_figure("Water against steady wind", "wind speed V [m/s]", "mean flow [L/s]")
    fig.extra_y_ranges = {"density": Range1d(0, 1)}
    axis = LinearAxis(y_range_name="density", axis_label="Weibull density [s/m]")
    axis.axis_label_text_font_size = axis.major_label_text_font_size = TICKS
    # as few labels as the flow's axis: six asked for gave nine (0 to 0.16 by 0.02), stacked on
    # each other in a frame ~140 px high (presentation mode, a phone)
    axis.ticker.desired_num_ticks = 3
    fig.add_layout(axis, "right")
    curve = line(fig, "V", "flow", s["curve"], c["flow"], 3)
    density = fig.varea(
        "V", 0, "density", source=s["density"], y_range_name="density", color=c["site"],
        alpha=0.3,
    )  # fmt: skip
    # The faint area's outline, so that it stands out of the background.
    density_edge = fig.line(
        "V",
        "density",
        source=s["density"],
        y_range_name="density",
        color=c["site"],
        line_width=1.5,
    )
    here = fig.scatter("V", "flow", source=s["here"], size=12, color=c["mean"])
    stop_span = Span(location=0, dimension="height", line_color=c["load"], line_width=2)
    start_span = Span(
        location=0,
        dimension="height",
        line_color=c["windmill"],
        line_width=2,
        line_dash="dashed",
    )
    fig.add_layout(stop_span)
    fig.add_layout(start_span)
    fig.add_tools(
        HoverTool(
            renderers=[curve],
            tooltips=[("V", "@V{0.0} m/s"), ("flow", "@flow{0.000} L/s")],
            mode="vline",
        )
    )
    legend(
        fig,
        {
            "averaged flow (α₊)": curve,
            "site's wind (Weibull)": [density, density_edge],
            "steady wind V": here,
        },
    )
    # In presentation mode its legend (three items, 18 px) takes three rows below a plot ~440 px
    # wide: at HEIGHT the plot kept 90-140 px. The plot keeps ~240 px, the legend below the fold
    # of a 1280×720 projector.
    grow_in_presentation(fig, round(1.3 * HEIGHT))
    return fig, stop_span, start_span


def day_figures(s: dict, c: dict):
    """The day's wind, crank speed and water lifted on one time axis, stops and starts marked:
    (wind, speed, litres, the markers' legend items). ``s`` gets its sources, ``c`` the colours."""
    s["wind"] = empty("t", "lower", "upper")
    s["speed"] = empty("t", "lower", "upper")
    s["litres"] = empty("t", "litres")
    for kind in ("stops", "starts"):
        s[f"{kind}_wind"] = empty("t", "y")
        s[f"{kind}_litres"] = empty("t", "y")
    shared = Range1d(0, 24)
    wind = new_figure("The day's wind", "time [h]", "wind speed V [m/s]", x_range=shared)
    draw_band(wind, s["wind"], c["wind"])
    speed = new_figure("Crank speed", "time [h]", "crank speed θ̇ [rad/s]", x_range=shared)
    draw_band(speed, s["speed"], c["integrated"])
    litres = new_figure("Water lifted", "time [h]", "water since dawn [L]", x_range=shared)
    # 100,000 L, not Bokeh's 1.000e+5 (a record of days lifts that much); 0.5 L, not "1" beside
    # "1" (a stalling pump's half-litre ticks on a phone): decimals where a tick has them
    litres.yaxis.formatter = NumeralTickFormatter(format="0,0.[00]")
    lifted = line(litres, "t", "litres", s["litres"], c["flow"], 3)
    markers = {}
    for fig, suffix in ((wind, "wind"), (litres, "litres")):
        markers[suffix] = (
            fig.scatter("t", "y", source=s[f"stops_{suffix}"], marker="inverted_triangle",
                        size=11, color=c["load"]),
            fig.scatter("t", "y", source=s[f"starts_{suffix}"], marker="triangle", size=11,
                        color=c["windmill"]),
        )  # fmt: skip
    # Items only for what the day has: no empty swatches on a day without stops.
    marker_items = legend(wind, {"stops": markers["wind"][0], "starts": markers["wind"][1]})
    for item in marker_items.values():
        item.visible = False
    litres.add_tools(
        HoverTool(
            renderers=[lifted],
            tooltips=[("t", "@t{0.00} h"), ("water", "@litres{0,0} L")],
            mode="vline",
        )
    )
    for fig, what in ((wind, "V"), (speed, "θ̇")):
        fig.add_tools(
            HoverTool(
                tooltips=[("t", "@t{0.00} h"), (what, "@lower{0.00} to @upper{0.00}")],
                mode="vline",
                renderers=[fig.renderers[0]],
            )
        )
    return wind, speed, litres, marker_items


def time_unit(duration: float) -> tuple[float, str]:
    """The day figures' time axis for a record of ``duration`` [s]: (seconds a unit, its
    symbol), hours up to two days, days beyond (a week is 7 days, not 168 h)."""
    return (SECONDS_PER_DAY, "days") if duration > 2 * SECONDS_PER_DAY else (SECONDS_PER_HOUR, "h")


def a_day(duration: float) -> bool:
    """Whether a record [s] is a day long (to the minute): its words are then a day's."""
    return math.isclose(duration, SECONDS_PER_DAY, abs_tol=60.0)


def label_day(wind, speed, litres, duration: float) -> None:
    """The day figures' words for a record of ``duration`` [s]: "The day's wind" and "water since
    dawn" for a day, the record's for any other span; the time axis and its hover in its unit."""
    day = a_day(duration)
    _unit, symbol = time_unit(duration)
    wind.title.text = "The day's wind" if day else "The record's wind"
    litres.yaxis.axis_label = (
        "water since dawn [L]" if day else "water since the record's start [L]"
    )
    for fig in (wind, speed, litres):
        fig.xaxis.axis_label = f"time [{symbol}]"
        for hover in fig.select(type=HoverTool):
            hover.tooltips = [
                (name, f"@t{{0.00}} {symbol}") if name == "t" else (name, field)
                for name, field in hover.tooltips
            ]
