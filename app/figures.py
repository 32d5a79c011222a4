"""The explorer's Bokeh figures: built once, with named data sources that updates refill in place."""

from __future__ import annotations

from bokeh.models import ColumnDataSource, FactorRange, Legend, LegendItem
from bokeh.plotting import figure

WIDTH, HEIGHT = 900, 380
ZOOM = "pan,box_zoom,wheel_zoom,reset,save"
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
    """A figure with the fonts and lines a projector can carry."""
    fig = figure(title=title, width=WIDTH, height=height, tools=tools, **options)
    fig.title.text_font_size = "16pt"
    for axis, label in ((fig.xaxis, x_label), (fig.yaxis, y_label)):
        axis.axis_label = label
        axis.axis_label_text_font_size = "14pt"
        axis.major_label_text_font_size = "12pt"
    fig.toolbar.autohide = True
    return fig


def line(fig, x: str, y: str, source, color: str, width: float = 2, dash: str = "solid"):
    return fig.line(x, y, source=source, color=color, line_width=width, line_dash=dash)


def legend(fig, items: dict, location="top_left", place="center"):
    """A legend of {label: renderer} inside the plot at ``location``, or beside it (``place``)."""
    fig.add_layout(
        Legend(
            items=[
                LegendItem(label=label, renderers=[renderer]) for label, renderer in items.items()
            ],
            location=location,
            label_text_font_size="12pt",
            click_policy="hide",
            background_fill_alpha=0.7,
        ),
        place,
    )


def draw_band(fig, source, color):
    """A min-to-max band with its edges drawn, so a band thinner than a pixel still shows."""
    area = fig.varea("t", "lower", "upper", source=source, color=color, alpha=0.35)
    line(fig, "t", "lower", source, color, width=1.5)
    line(fig, "t", "upper", source, color, width=1.5)
    return area


def speed_view():
    """View 1: crank speed, integrated and averaged, with the steady speeds."""
    s = {
        name: empty("t", "speed") for name in ("spinup", "cycle_mean", "alpha_plus", "alpha_minus")
    }
    s["speed"] = empty("t", "lower", "upper")
    fig = new_figure("Crank speed", "time t [s]", "crank speed θ̇ [rad/s]")
    items = {
        "integrated, Eq. (12)": draw_band(fig, s["speed"], COLORS["integrated"]),
        "averaged spin-up, Eq. (24)": line(
            fig, "t", "speed", s["spinup"], COLORS["averaged"], 3, "dashed"
        ),
        "cycle mean of the integration": line(fig, "t", "speed", s["cycle_mean"], COLORS["mean"]),
        "α₊, Eq. (21)": line(fig, "t", "speed", s["alpha_plus"], COLORS["alpha_plus"], 2, "dotted"),
        "α₋, Eq. (21)": line(
            fig, "t", "speed", s["alpha_minus"], COLORS["alpha_minus"], 2, "dotted"
        ),
    }
    legend(fig, items, location="bottom_right")
    return fig, s


def flow_views():
    """View 2: the flow over the whole run (envelope) and a close-up of its last revolutions."""
    s = {
        "flow": empty("t", "lower", "upper"),
        "mean_flow": empty("t", "flow"),
        "closeup": empty("t", "flow"),
    }
    whole = new_figure("Flow rate over the run", "time t [s]", "flow [L/s]")
    legend(
        whole,
        {
            "instantaneous (band: min to max)": draw_band(whole, s["flow"], COLORS["flow"]),
            "mean over the run": line(
                whole, "t", "flow", s["mean_flow"], COLORS["mean"], 3, "dashed"
            ),
        },
    )
    closeup = new_figure(
        "Close-up: the last revolutions, every sample",
        "time t [s]",
        "flow [L/s]",
        tools="pan,box_zoom,reset,save",
    )
    line(closeup, "t", "flow", s["closeup"], COLORS["flow"])
    closeup.scatter("t", "flow", source=s["closeup"], color=COLORS["flow"], size=4)
    return whole, closeup, s


def stall_view():
    """View 3: Eq. (22), the windmill's characteristic torque against the load's."""
    names = ["windmill: T_m†", "load: R† L†/π"]
    source = ColumnDataSource(
        {"name": names, "value": [0.0, 0.0], "color": [COLORS["windmill"], COLORS["load"]]}
    )
    fig = new_figure(
        "Stall criterion, Eq. (22)",
        "dimensionless torque (Eqs. 14, 15)",
        "",
        height=HEIGHT * 2 // 3,
        tools="save",
        y_range=FactorRange(*names),
    )
    fig.hbar(y="name", right="value", height=0.6, color="color", source=source)
    fig.x_range.start = 0
    fig.xaxis.ticker.desired_num_ticks = 5
    return fig, {"stall": source}


def operating_view():
    """View 4: Eq. (5) against the windmill's power curve, with their intersections."""
    s = {
        name: empty("omega", "power")
        for name in ("curve", "load_line", "stable", "unstable", "data")
    }
    fig = new_figure(
        "Operating point, Eq. (5)",
        "windmill speed ω [rad/s]",
        "power [W]",
        tools="pan,box_zoom,reset,save",
    )
    point = dict(x="omega", y="power", size=14)
    items = {
        "windmill T(ω) ω, Eq. (11)": line(fig, "omega", "power", s["curve"], COLORS["windmill"], 3),
        "pump load, Eq. (5)": line(fig, "omega", "power", s["load_line"], COLORS["load"], 3),
        "operating point (stable)": fig.scatter(source=s["stable"], color="black", **point),
        "unstable intersection": fig.scatter(
            source=s["unstable"], fill_color="white", line_color="black", line_width=2, **point
        ),
        "measured T ω (lab data)": fig.scatter(
            "omega", "power", source=s["data"], size=8, marker="triangle", color=COLORS["data"]
        ),
    }
    legend(fig, items, location="top_left", place="right")
    return fig, s


def energy_view():
    """View 5: the windmill's power split between spinning up and lifting water, per revolution."""
    s = {"power_split": empty("t", "hydraulic", "shaft", "kinetic")}
    fig = new_figure(
        "Where the windmill's power goes (per revolution)",
        "time t [s]",
        "power [W]",
        tools="pan,box_zoom,reset,save",
    )
    source = s["power_split"]
    items = {
        "lifting water, ρ_w g h Q": fig.varea(
            "t", 0.0, "hydraulic", source=source, color=COLORS["flow"], alpha=0.5
        ),
        "spinning up, d(½ I_eff θ̇²)/dt": fig.varea(
            "t", "hydraulic", "shaft", source=source, color=COLORS["averaged"], alpha=0.5
        ),
        "windmill T ω": line(fig, "t", "shaft", source, "black", 2, "dashed"),
    }
    legend(fig, items, location="bottom_right")
    return fig, s


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
    )
    fig.width = MECHANISM_SIZE
    fig.title.text_font_size = "13pt"
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
    )
    travel.width = MECHANISM_SIZE
    travel.title.text_font_size = "13pt"
    s["travel"] = empty("angle", "x")
    s["travel_point"] = empty("angle", "x")
    items = {
        "Eq. (1)": line(travel, "angle", "x", s["travel"], COLORS["integrated"], 3),
        "Newton-Raphson": travel.scatter(
            "angle", "x", source=s["travel_point"], size=14, color=COLORS["mean"]
        ),
    }
    legend(travel, items, location="top_left")
    return drawing, travel, s


def linkage_view():
    """A four-bar or Watt six-bar drawn from its Newton-Raphson solution, with its joint's path."""
    fig = mechanism_figure("Four-bar / double loop (Newton-Raphson)")
    return fig, draw_links(fig, "linkage")
