"""The explorer's Bokeh figures: built once, with named data sources that updates refill in place."""

from __future__ import annotations

from bokeh.models import ColumnDataSource, Legend, LegendItem
from bokeh.plotting import figure

WIDTH, HEIGHT = 900, 330  # WIDTH: the widest a view is drawn, so bins of 2 px: WIDTH // 2
ZOOM = "pan,box_zoom,wheel_zoom,reset,save"
TITLE, LABEL, TICKS = "16px", "15px", "14px"  # nothing a student must read below 14 px
# Each theme's colours: every drawn line, marker and label stands out from its plot's background
# by at least 3:1 (WCAG's non-text contrast; tests/test_app_colours.py), white in the light theme,
# the dark theme's #2b3035. Views pick theirs with palette(dark).
LIGHT = {
    "integrated": "#1f77b4",
    "averaged": "#2ca02c",
    "mean": "#d62728",
    "alpha_plus": "#555555",
    "alpha_minus": "#d95f02",
    "flow": "#1f77b4",
    "windmill": "#2ca02c",
    "load": "#d62728",
    "data": "#9467bd",
    "wind": "#8c564b",
    "best": "#d95f02",
    "ghost": "#8f8f8f",  # a pinned run: quieter than the run, still 3:1
    "site": "#808080",  # the site's Weibull wind
    "ink": "#000000",  # outlines, text and the windmill's power
    "structure": "#444444",  # the machine's chain, cylinders, tank; fixed pivots
    "cursor": "#444444",
    "blade": "#6b6b6b",
    "crank": "#d62728",
    "rod": "#1f77b4",
    "piston": "#9ecae1",
    "sprocket": "#dddddd",
    "joint": "#ffffff",
    "path": "#808080",
    "star": "#ffffff",
}
DARK = {
    **LIGHT,
    "integrated": "#5aa9e6",
    "averaged": "#4cc24c",
    "mean": "#ff6b6b",
    "alpha_plus": "#c8c8c8",
    "alpha_minus": "#ffa64d",
    "flow": "#5aa9e6",
    "windmill": "#4cc24c",
    "load": "#ff6b6b",
    "data": "#c4a5f0",
    "wind": "#d4a373",
    "best": "#ffa64d",
    "site": "#aaaaaa",
    "ink": "#e0e0e0",
    "structure": "#b8b8b8",
    "cursor": "#e0e0e0",
    "blade": "#a0a0a0",
    "crank": "#ff6b6b",
    "rod": "#5aa9e6",
    "joint": "#2b3035",  # a ring, as the light theme's white joint in a black outline
    "sprocket": "#454b52",  # dark, so that the crank drawn on it stands out
    "path": "#a0a0a0",
}
COLORS = LIGHT  # the light theme's
# Several faces' pulses, and the links of a drawn mechanism, one colour each.
FACES = {
    False: ("#d95f02", "#2ca02c", "#9467bd", "#8c564b", "#c2449f", "#0f8b96"),
    True: ("#ffa64d", "#4cc24c", "#c4a5f0", "#d4a373", "#f28cc7", "#4fd6e3"),
}
LINKS = {
    False: ("#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#d95f02"),
    True: ("#ff6b6b", "#5aa9e6", "#4cc24c", "#c4a5f0", "#ffa64d"),
}


def palette(dark: bool = False) -> dict[str, str]:
    """The colours of the light or the dark theme."""
    return DARK if dark else LIGHT


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


def legend(fig, items: dict, location="top_left", place="below", columns: int | None = None):
    """A legend of {label: renderer, or a list of renderers drawn as one swatch} beside the plot
    (``place``; below by default, so it never covers data), in two rows, or in rows of at most
    ``columns`` items (a legend of long labels, which would be cut at the plot's edge). Returns
    {label: LegendItem}, so an update can hide the items of what is not drawn."""
    entries = {
        label: LegendItem(
            label=label, renderers=list(drawn) if isinstance(drawn, list | tuple) else [drawn]
        )
        for label, drawn in items.items()
    }
    rows = 2 if columns is None else max(2, -(-len(entries) // columns))
    fig.add_layout(
        Legend(
            items=list(entries.values()),
            location=location,
            orientation="horizontal" if place in ("below", "above") else "vertical",
            nrows=rows if place in ("below", "above") and len(entries) > 2 else "auto",
            label_text_font_size=TICKS,
            click_policy="hide",
            background_fill_alpha=0.7,
        ),
        place,
    )
    return entries


def draw_band(fig, source, color):
    """A min-to-max band with its edges drawn, so a band thinner than a pixel still shows (and
    the faint fill has an outline that stands out). Returns [area, edge]: a legend's swatch."""
    area = fig.varea("t", "lower", "upper", source=source, color=color, alpha=0.35)
    edge = line(fig, "t", "lower", source, color, width=1.5)
    line(fig, "t", "upper", source, color, width=1.5)
    return [area, edge]


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


def draw_links(fig, prefix: str, joint_size: int = 12, dark: bool = False):
    """Links as thick coloured bars between joints, fixed pivots as triangles, a traced path."""
    c = palette(dark)
    s = {
        f"{prefix}_links": empty("xs", "ys", "color"),
        f"{prefix}_joints": empty("x", "y"),
        f"{prefix}_pivots": empty("x", "y"),
        f"{prefix}_path": empty("x", "y"),
    }
    fig.line(
        "x", "y", source=s[f"{prefix}_path"], color=c["path"], line_dash="dotted", line_width=2
    )
    fig.multi_line("xs", "ys", source=s[f"{prefix}_links"], color="color", line_width=7)
    fig.scatter(
        "x", "y", source=s[f"{prefix}_pivots"], marker="triangle", size=22, color=c["structure"]
    )
    fig.scatter(
        "x",
        "y",
        source=s[f"{prefix}_joints"],
        size=joint_size,
        fill_color=c["joint"],
        line_color=c["ink"],
        line_width=2,
    )
    return s


def slider_crank_views(dark: bool = False):
    """The pump's slider-crank at a chosen crank angle, and its piston travel over a revolution."""
    c = palette(dark)
    drawing = mechanism_figure("The pump's slider-crank (Newton-Raphson)")
    s = draw_links(drawing, "crank", dark=dark)
    s["cylinder"] = empty("xs", "ys")
    s["piston"] = empty("x", "y", "width", "height")
    drawing.multi_line("xs", "ys", source=s["cylinder"], color=c["structure"], line_width=3)
    drawing.rect(
        "x", "y", "width", "height", source=s["piston"], fill_color=c["piston"], line_color=c["ink"]
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
        "Eq. (1)": line(travel, "angle", "x", s["travel"], c["integrated"], 3),
        "Newton-Raphson": travel.scatter(
            "angle", "x", source=s["travel_point"], size=14, color=c["mean"]
        ),
    }
    legend(travel, items, place="below")
    return drawing, travel, s


def linkage_view(dark: bool = False):
    """A four-bar or Watt six-bar drawn from its Newton-Raphson solution, with its joint's path."""
    fig = mechanism_figure("Four-bar / double loop (Newton-Raphson)")
    return fig, draw_links(fig, "linkage", dark=dark)
