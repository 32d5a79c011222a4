"""The explorer's Bokeh figures: built once, with named data sources that updates refill in place."""

from __future__ import annotations

from bokeh.models import ColumnDataSource, Legend, LegendItem
from bokeh.plotting import figure

WIDTH, HEIGHT = 900, 330  # WIDTH: the widest a view is drawn, so bins of 2 px: WIDTH // 2
ZOOM = "pan,box_zoom,wheel_zoom,reset,save"
TITLE, LABEL, TICKS = "16px", "15px", "14px"  # nothing a student must read below 14 px
COLORS = {
    "integrated": "#1f77b4",
    "averaged": "#2ca02c",
    "mean": "#d62728",
    "alpha_plus": "#555555",
    "alpha_minus": "#ff7f0e",
    "flow": "#1f77b4",
    "windmill": "#2ca02c",
    "load": "#d62728",
    "data": "#9467bd",
}


def empty(*columns: str) -> ColumnDataSource:
    return ColumnDataSource({column: [] for column in columns})


def new_figure(
    title: str, x_label: str, y_label: str, height: int = HEIGHT, tools: str = ZOOM, **options
):
    """A figure that takes the width it is given, with fonts and lines a projector can carry."""
    options.setdefault("sizing_mode", "stretch_width")
    fig = figure(title=title, height=height, tools=tools, min_width=300, **options)
    fig.title.text_font_size = TITLE
    for axis, label in ((fig.xaxis, x_label), (fig.yaxis, y_label)):
        axis.axis_label = label
        axis.axis_label_text_font_size = LABEL
        axis.major_label_text_font_size = TICKS
    fig.toolbar.autohide = True
    return fig


def line(fig, x: str, y: str, source, color: str, width: float = 2, dash: str = "solid"):
    return fig.line(x, y, source=source, color=color, line_width=width, line_dash=dash)


def legend(fig, items: dict, location="top_left", place="below"):
    """A legend of {label: renderer} beside the plot (``place``; below by default, so it never
    covers data), in as many columns as fit. Returns {label: LegendItem}, so an update can hide
    the items of what is not drawn."""
    entries = {
        label: LegendItem(label=label, renderers=[renderer]) for label, renderer in items.items()
    }
    fig.add_layout(
        Legend(
            items=list(entries.values()),
            location=location,
            orientation="horizontal" if place in ("below", "above") else "vertical",
            nrows=2 if place in ("below", "above") and len(entries) > 2 else "auto",
            label_text_font_size=TICKS,
            click_policy="hide",
            background_fill_alpha=0.7,
        ),
        place,
    )
    return entries


def draw_band(fig, source, color):
    """A min-to-max band with its edges drawn, so a band thinner than a pixel still shows."""
    area = fig.varea("t", "lower", "upper", source=source, color=color, alpha=0.35)
    line(fig, "t", "lower", source, color, width=1.5)
    line(fig, "t", "upper", source, color, width=1.5)
    return area


MECHANISM_SIZE = 440


def mechanism_figure(title: str):
    """A square drawing with equal scales on both axes, so a link looks as long as it is."""
    fig = new_figure(
        title,
        "x [m]",
        "y [m]",
        height=MECHANISM_SIZE,
        tools="pan,wheel_zoom,reset,save",
        match_aspect=True,
        max_width=MECHANISM_SIZE,
    )
    return fig


def draw_links(fig, prefix: str, joint_size: int = 12):
    """Links as thick coloured bars between joints, fixed pivots as triangles, a traced path."""
    s = {
        f"{prefix}_links": empty("xs", "ys", "color"),
        f"{prefix}_joints": empty("x", "y"),
        f"{prefix}_pivots": empty("x", "y"),
        f"{prefix}_path": empty("x", "y"),
    }
    fig.line(
        "x", "y", source=s[f"{prefix}_path"], color="#999999", line_dash="dotted", line_width=2
    )
    fig.multi_line("xs", "ys", source=s[f"{prefix}_links"], color="color", line_width=7, alpha=0.85)
    fig.scatter("x", "y", source=s[f"{prefix}_pivots"], marker="triangle", size=22, color="#444444")
    fig.scatter(
        "x",
        "y",
        source=s[f"{prefix}_joints"],
        size=joint_size,
        fill_color="white",
        line_color="black",
        line_width=2,
    )
    return s


def slider_crank_views():
    """The pump's slider-crank at a chosen crank angle, and its piston travel over a revolution."""
    drawing = mechanism_figure("The pump's slider-crank (Newton-Raphson)")
    s = draw_links(drawing, "crank")
    s["cylinder"] = empty("xs", "ys")
    s["piston"] = empty("x", "y", "width", "height")
    drawing.multi_line("xs", "ys", source=s["cylinder"], color="#555555", line_width=3)
    drawing.rect(
        "x", "y", "width", "height", source=s["piston"], fill_color="#9ecae1", line_color="black"
    )
    travel = new_figure(
        "Piston position over a revolution",
        "crank angle θ [°]",
        "x [mm]",
        height=MECHANISM_SIZE,
        tools="save",
        max_width=MECHANISM_SIZE,
    )
    s["travel"] = empty("angle", "x")
    s["travel_point"] = empty("angle", "x")
    items = {
        "Eq. (1)": line(travel, "angle", "x", s["travel"], COLORS["integrated"], 3),
        "Newton-Raphson": travel.scatter(
            "angle", "x", source=s["travel_point"], size=14, color=COLORS["mean"]
        ),
    }
    legend(travel, items, place="below")
    return drawing, travel, s


def linkage_view():
    """A four-bar or Watt six-bar drawn from its Newton-Raphson solution, with its joint's path."""
    fig = mechanism_figure("Four-bar / double loop (Newton-Raphson)")
    return fig, draw_links(fig, "linkage")
