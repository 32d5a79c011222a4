"""The Site tab's figures: the demand month by month (delivered and short) before the water
pumped, the tank's level over the record, and the loss-of-load probability against tank size."""

from __future__ import annotations

import math

import numpy as np
from bokeh.models import CustomJS, FactorRange, HoverTool, NumeralTickFormatter, Range1d, Span

from windpump.readers.quantities import display_unit

from .figures import HEIGHT, LABEL, empty, legend, line, new_figure
from .site_record import LOLP_TARGET, span
from .views import refill

MONTHS = ("Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec")
SITE_HEIGHT = HEIGHT + 40  # [px] each keeps a frame to read under its legend in presentation mode

# On a narrow figure (a phone) the months' names are tilted, so that they do not run together.
TILT_JS = """
const tilt = plot.outer_width < 520 ? angle : 0
for (const axis of plot.below) {  // the axis (a legend lies below too)
  if (axis.major_label_orientation === undefined || axis.major_label_orientation === tilt) continue
  axis.setv({major_label_orientation: tilt}, {sync: false})
}
"""


# The water's ticks in whole numbers with thousands separated (gallons: "150,000", not "1.5e+5")
WATER_TICKS = "0,0.[00]"
SI_WATER = "m³"  # the figures' unit of water as built (the core's): ``say_water_in`` rewrites it


def page_unit(unit: str) -> str:
    """A unit in pint's spelling (``windpump.readers.quantities``) as the page writes it.

    >>> page_unit("m^3/day"), page_unit("gal")
    ('m³/day', 'gal')
    """
    return unit.replace("^3", "³").replace("^2", "²")


def shown_in(kind: str, system: str) -> tuple[float, str]:
    """[shown unit / core unit] and the unit the Site tab shows a quantity of ``kind`` in, as
    the command line does (``windpump supply --units``): the core's m³ and m³/day, or US
    gallons and gallons a day (``windpump.readers.quantities.display_unit``: pint's factors).

    >>> shown_in("tank", "si"), shown_in("daily flow", "us")[1]
    ((1.0, 'm³'), 'gal/day')
    """
    factor, unit = display_unit(kind, system)
    return factor, page_unit(unit)


def water_texts(figures) -> list[tuple]:
    """The texts of ``figures`` that name the water's unit (axis labels, hover tooltips) as
    built, in m³: (model, attribute, text), for ``say_water_in``."""
    texts: list[tuple] = []
    for fig in figures:
        for axis in (*fig.xaxis, *fig.yaxis):
            if SI_WATER in (axis.axis_label or ""):
                texts.append((axis, "axis_label", axis.axis_label))
        for hover in fig.select(HoverTool):
            if any(SI_WATER in text for _, text in hover.tooltips):
                texts.append((hover, "tooltips", list(hover.tooltips)))
    return texts


def say_water_in(texts: list[tuple], unit: str) -> None:
    """The figures' texts (``water_texts``) naming ``unit`` for the water (m³ or gal)."""
    for model, attribute, built in texts:
        if attribute == "tooltips":
            setattr(model, attribute, [(n, t.replace(SI_WATER, unit)) for n, t in built])
        else:
            setattr(model, attribute, built.replace(SI_WATER, unit))


DRY = "days short of water"  # the level figure's rug, in its legend when there are any
CUT = 2.5  # pumped water above CUT times the largest month's demand is cut, its number written


def monthly_figure(s: dict, c: dict):
    """Each calendar month's demand [m³] as a stacked bar, delivered and short (in a warning
    colour), in front of the water pumped (an outlined bar, cut at the figure's top with its
    number written when it dwarfs the demand: ``water_range``)."""
    s["monthly"] = empty(
        "month", "pumped", "demand", "delivered", "shortfall", "short_top", "cut", "cut_at"
    )
    fig = new_figure(
        "Water each month",
        "month",
        "water [m³]",
        SITE_HEIGHT,
        x_range=FactorRange(*MONTHS),
        y_range=Range1d(0, 1),
    )
    fig.js_on_change("outer_width", CustomJS(args=dict(plot=fig, angle=math.pi / 3), code=TILT_JS))
    fig.yaxis.formatter = NumeralTickFormatter(format=WATER_TICKS)
    source = s["monthly"]
    pumped = fig.vbar(
        x="month", top="pumped", width=0.85, source=source, fill_color=c["ghost"],
        fill_alpha=0.25, line_color=c["ghost"], line_width=2,
    )  # fmt: skip
    # filled without an outline: a bar of no height draws nothing (an outline drew a line)
    delivered = fig.vbar(
        x="month", top="delivered", width=0.5, source=source, fill_color=c["flow"],
        line_color=None,
    )  # fmt: skip
    short = fig.vbar(
        x="month", bottom="delivered", top="short_top", width=0.5, source=source,
        fill_color=c["best"], line_color=None,
    )  # fmt: skip
    fig.text(
        x="month", y="cut_at", text="cut", source=source, angle=math.pi / 2, text_align="right",
        text_baseline="middle", text_font_size=LABEL, text_color=c["ink"],
    )  # fmt: skip
    fig.add_tools(
        HoverTool(
            renderers=[pumped],
            tooltips=[
                ("month", "@month"),
                ("pumped", "@pumped{0,0.0} m³"),
                ("demand", "@demand{0,0.0} m³"),
                ("delivered", "@delivered{0,0.0} m³"),
                ("short", "@shortfall{0,0.0} m³"),
            ],
        )
    )
    legend(fig, {"delivered": delivered, "short of the demand": short, "pumped": pumped})
    return fig


def water_range(pumped, demand) -> tuple[float, list[str]]:
    """The monthly figure's top [m³] and each month's written number: every bar in view, unless
    the water pumped would crush the demand's bars (more than CUT times the largest month's
    demand): then the figure stops at CUT times it and a month pumped beyond shows its number."""
    most_asked = max(demand, default=0.0)
    most_pumped = max(pumped, default=0.0)
    if most_asked <= 0.0 or most_pumped <= CUT * most_asked:
        return 1.08 * max(most_pumped, most_asked, 1e-9), ["" for _ in pumped]
    top = CUT * most_asked
    return top, [f"{p:,.0f} " if p > top else "" for p in pumped]


def short_tops(delivered, shortfall) -> np.ndarray:
    """The top [m³] of each month's short bar, on its delivered one: delivered + shortfall (the
    demand), or NaN (no bar at all) for a month with no shortfall."""
    delivered, shortfall = np.asarray(delivered, float), np.asarray(shortfall, float)
    return np.where(shortfall > 0.0, delivered + shortfall, np.nan)


def show_monthly(source, fig, monthly, water: float = 1.0) -> None:
    """A year's months (``windpump.MonthTable``, m³) in the monthly figure, cut at
    ``water_range``, in the unit ``water`` m³ make [shown unit / m³] (1: m³)."""
    drawn = {
        name: water * np.asarray(getattr(monthly, name))
        for name in ("pumped", "demand", "delivered", "shortfall")
    }
    top, cut = water_range(drawn["pumped"], drawn["demand"])
    refill(
        source,
        {
            "month": [MONTHS[m - 1] for m in monthly.month],
            **drawn,
            "short_top": short_tops(drawn["delivered"], drawn["shortfall"]),
            "cut": cut,
            "cut_at": np.full(len(cut), 0.98 * top),
        },
    )
    fig.y_range.end = top


def level_figure(s: dict, c: dict):
    """The water in the tank each day [m³]: its mean, filled from the bottom as water in a tank
    (opaque enough to read without an outline, so a tank that fills and empties every few days
    is a comb of water, not a scribble of lines), and the days short of water (a rug along the
    bottom), under the tank's size: (figure, the tank's line). Each day's range is in the hover.
    """
    s["level"] = empty("t", "lower", "upper", "mean")
    s["dry"] = empty("t", "top")
    fig = new_figure(
        "The tank over the year", "day of the year", "water in the tank [m³]", SITE_HEIGHT
    )
    fig.y_range.start = 0
    fig.yaxis.formatter = NumeralTickFormatter(format=WATER_TICKS)
    mean = fig.varea(x="t", y1=0.0, y2="mean", source=s["level"], color=c["integrated"], alpha=0.8)
    dry = fig.vbar(x="t", top="top", width=0.9, source=s["dry"], color=c["load"])
    size = Span(
        location=0, dimension="width", line_color=c["ink"], line_width=2, line_dash="dashed"
    )
    fig.add_layout(size)
    edge = fig.line("t", "mean", source=s["level"], line_alpha=0.0)  # for the hover alone
    fig.add_tools(
        HoverTool(
            renderers=[edge],
            tooltips=[
                ("day", "@t{0}"),
                ("mean", "@mean{0,0.0} m³"),
                ("range", "@lower{0,0.0} to @upper{0,0.0} m³"),
            ],
            mode="vline",
        )
    )
    legend(fig, {"water in the tank": mean, DRY: dry})
    return fig, size


def show_level(sources: dict, fig, supplied, tank: float, water: float = 1.0) -> None:
    """A year's tank (``windpump.Supply``; ``tank`` [m³]) in the level figure: each day's mean
    (its range for the hover), the days short of water, the title and axis by the record's
    span; in the unit ``water`` m³ make [shown unit / m³] (1: m³)."""
    days = np.arange(supplied.hours) / 24.0
    tank = water * tank
    x, lower, upper, mean = daily_band(days, water * np.asarray(supplied.level))
    refill(sources["level"], {"t": x, "lower": lower, "upper": upper, "mean": mean})
    dry = np.flatnonzero(supplied.dry) + 0.5
    rug = 0.05 * max(tank, float(np.max(upper, initial=0.0)), 1e-3 * water)  # the rug's height
    refill(sources["dry"], {"t": dry, "top": np.full(dry.size, rug)})
    for item in fig.legend[0].items:  # an empty rug draws a blank swatch: left out
        if item.label.value == DRY:
            item.visible = bool(dry.size)
    over = span(supplied.hours)
    fig.title.text = f"The tank over {over}"
    fig.xaxis.axis_label = "day of the year" if over == "the year" else "day"


def placeholder_year(sources: dict, largest_tank: float) -> None:
    """Flat, empty bars and lines over a year and the tanks up to ``largest_tank`` (in the unit
    shown), so that the figures have ranges before the first year comes (Bokeh cannot set the
    ranges of figures with no data) and their legends their swatches."""
    months = {name: np.zeros(len(MONTHS)) for name in sources["monthly"].data}
    refill(sources["monthly"], {**months, "month": list(MONTHS), "cut": [""] * len(MONTHS)})
    zeros = [0.0, 0.0]
    refill(sources["level"], {"t": [0.5, 364.5], "lower": zeros, "upper": zeros, "mean": zeros})
    refill(sources["lolp"], {"tank": [0.0, largest_tank], "lolp": zeros})


def daily_band(days: np.ndarray, values: np.ndarray):
    """Each day's lowest, highest and mean value (a year of hours: 365 points, under the
    figure's pixels): (day's middle, lower, upper, mean)."""
    whole = int(np.ceil(days[-1] + 1e-9)) if len(days) else 0
    edges = np.searchsorted(days, np.arange(whole))
    edges = np.unique(edges[edges < len(days)])
    return (
        days[edges] + 0.5,
        np.minimum.reduceat(values, edges),
        np.maximum.reduceat(values, edges),
        np.add.reduceat(values, edges) / np.diff(np.append(edges, len(values))),
    )


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
    fig.xaxis.formatter = NumeralTickFormatter(format=WATER_TICKS)
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
            tooltips=[("tank", "@tank{0,0.0} m³"), ("LOLP", "@lolp{0.0} %")],
            mode="vline",
        )
    )
    legend(fig, {"loss-of-load probability": curve, "this tank": here})
    return fig, target
