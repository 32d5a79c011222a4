"""The Site tab's figures: the water and the demand month by month, the tank's level over the
year, and the loss-of-load probability against tank size."""

from __future__ import annotations

import math

from bokeh.models import CustomJS, FactorRange, HoverTool, Span

from .figures import HEIGHT, draw_band, empty, legend, line, new_figure

MONTHS = ("Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec")
LOLP_TARGET = 0.05  # the readout's "smallest tank for 5 %"
SITE_HEIGHT = HEIGHT + 40  # [px] each keeps a frame to read under its legend in presentation mode

# On a narrow figure (a phone) the months' names are tilted, so that they do not run together.
TILT_JS = """
const tilt = plot.outer_width < 520 ? angle : 0
for (const axis of plot.below) {  // the axis (a legend lies below too)
  if (axis.major_label_orientation === undefined || axis.major_label_orientation === tilt) continue
  axis.setv({major_label_orientation: tilt}, {sync: false})
}
"""


def monthly_figure(s: dict, c: dict):
    """Water pumped (bars) and demanded (a line) each calendar month [m³]."""
    s["monthly"] = empty("month", "pumped", "demand", "delivered")
    fig = new_figure(
        "Water each month", "month", "water [m³]", SITE_HEIGHT, x_range=FactorRange(*MONTHS)
    )
    fig.js_on_change("outer_width", CustomJS(args=dict(plot=fig, angle=math.pi / 3), code=TILT_JS))
    fig.y_range.start = 0
    bars = fig.vbar(
        x="month", top="pumped", width=0.7, source=s["monthly"], color=c["flow"], alpha=0.8
    )
    demand = fig.scatter(
        "month", "demand", source=s["monthly"], marker="dash", size=30, line_width=4,
        color=c["load"],
    )  # fmt: skip
    delivered = fig.scatter(
        "month", "delivered", source=s["monthly"], marker="circle", size=9, color=c["ink"]
    )
    fig.add_tools(
        HoverTool(
            renderers=[bars],
            tooltips=[
                ("month", "@month"),
                ("pumped", "@pumped{0.0} m³"),
                ("delivered", "@delivered{0.0} m³"),
                ("demand", "@demand{0.0} m³"),
            ],
        )
    )
    legend(fig, {"pumped": bars, "demand": demand, "delivered": delivered})
    return fig


def level_figure(s: dict, c: dict):
    """The water in the tank over the year [m³], each day's lowest to highest, under the tank's
    size: (figure, the tank's line)."""
    s["level"] = empty("t", "lower", "upper")
    fig = new_figure(
        "The tank over the year", "day of the year", "water in the tank [m³]", SITE_HEIGHT
    )
    fig.y_range.start = 0
    band = draw_band(fig, s["level"], c["integrated"])
    size = Span(
        location=0, dimension="width", line_color=c["ink"], line_width=2, line_dash="dashed"
    )
    fig.add_layout(size)
    fig.add_tools(
        HoverTool(
            renderers=[band[1]],
            tooltips=[("day", "@t{0}"), ("level", "@lower{0.0} to @upper{0.0} m³")],
            mode="vline",
        )
    )
    legend(fig, {"lowest to highest each day": band})
    return fig, size


def lolp_figure(s: dict, c: dict):
    """The loss-of-load probability [%] against tank size [m³], this tank marked, the 5 % line:
    (figure, the 5 % line)."""
    s["lolp"] = empty("tank", "lolp")
    s["lolp_here"] = empty("tank", "lolp")
    fig = new_figure(
        "Loss-of-load probability against tank size",
        "tank [m³]",
        "loss of load [%]",
        SITE_HEIGHT,
    )
    fig.y_range.start = 0
    curve = line(fig, "tank", "lolp", s["lolp"], c["flow"], 3)
    here = fig.scatter(
        "tank", "lolp", source=s["lolp_here"], marker="circle", size=14, color=c["mean"],
        line_color=c["ink"],
    )  # fmt: skip
    target = Span(
        location=100 * LOLP_TARGET, dimension="width", line_color=c["best"], line_width=2,
        line_dash="dashed",
    )  # fmt: skip
    fig.add_layout(target)
    fig.add_tools(
        HoverTool(
            renderers=[curve],
            tooltips=[("tank", "@tank{0.0} m³"), ("LOLP", "@lolp{0.0} %")],
            mode="vline",
        )
    )
    legend(fig, {"loss-of-load probability": curve, "this tank": here})
    return fig, target
