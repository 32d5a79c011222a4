"""The explorer's Bokeh figures: built once, with named data sources that updates refill in place."""

from __future__ import annotations

from bokeh.models import ColumnDataSource, FactorRange, Legend, LegendItem
from bokeh.plotting import figure

WIDTH, HEIGHT = 900, 380
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


def styled(fig, x_label: str, y_label: str):
    """Fonts and lines a projector can carry."""
    fig.title.text_font_size = "16pt"
    for axis, label in ((fig.xaxis, x_label), (fig.yaxis, y_label)):
        axis.axis_label = label
        axis.axis_label_text_font_size = "14pt"
        axis.major_label_text_font_size = "12pt"
    fig.toolbar.autohide = True
    return fig


def legend(fig, items, location="top_left", place="center"):
    """A legend inside the plot at ``location``, or beside it with ``place="right"``."""
    fig.add_layout(
        Legend(
            items=[LegendItem(label=label, renderers=[renderer]) for label, renderer in items],
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
    fig.line("t", "lower", source=source, color=color, line_width=1.5)
    fig.line("t", "upper", source=source, color=color, line_width=1.5)
    return area


def speed_view():
    """View 1: crank speed, integrated and averaged, with the steady speeds."""
    sources = {
        "speed": empty("t", "lower", "upper"),
        "spinup": empty("t", "speed"),
        "cycle_mean": empty("t", "speed"),
        "alpha_plus": empty("t", "speed"),
        "alpha_minus": empty("t", "speed"),
    }
    fig = styled(
        figure(
            title="Crank speed",
            width=WIDTH,
            height=HEIGHT,
            tools="pan,box_zoom,wheel_zoom,reset,save",
        ),
        "time t [s]",
        "crank speed θ̇ [rad/s]",
    )
    items = [
        (
            "integrated, Eq. (12)",
            draw_band(fig, sources["speed"], COLORS["integrated"]),
        ),
        (
            "averaged spin-up, Eq. (24)",
            fig.line(
                "t",
                "speed",
                source=sources["spinup"],
                color=COLORS["averaged"],
                line_width=3,
                line_dash="dashed",
            ),
        ),
        (
            "cycle mean of the integration",
            fig.line(
                "t", "speed", source=sources["cycle_mean"], color=COLORS["mean"], line_width=2
            ),
        ),
        (
            "α₊, Eq. (21)",
            fig.line(
                "t",
                "speed",
                source=sources["alpha_plus"],
                color=COLORS["alpha_plus"],
                line_width=2,
                line_dash="dotted",
            ),
        ),
        (
            "α₋, Eq. (21)",
            fig.line(
                "t",
                "speed",
                source=sources["alpha_minus"],
                color=COLORS["alpha_minus"],
                line_width=2,
                line_dash="dotted",
            ),
        ),
    ]
    legend(fig, items, location="bottom_right")
    return fig, sources


def flow_views():
    """View 2: the flow over the whole run (envelope) and a close-up of its last revolutions."""
    sources = {
        "flow": empty("t", "lower", "upper"),
        "mean_flow": empty("t", "flow"),
        "closeup": empty("t", "flow"),
    }
    whole = styled(
        figure(
            title="Flow rate over the run",
            width=WIDTH,
            height=HEIGHT,
            tools="pan,box_zoom,wheel_zoom,reset,save",
        ),
        "time t [s]",
        "flow [L/s]",
    )
    items = [
        (
            "instantaneous (band: min to max)",
            draw_band(whole, sources["flow"], COLORS["flow"]),
        ),
        (
            "mean over the run",
            whole.line(
                "t",
                "flow",
                source=sources["mean_flow"],
                color=COLORS["mean"],
                line_width=3,
                line_dash="dashed",
            ),
        ),
    ]
    legend(whole, items)
    closeup = styled(
        figure(
            title="Close-up: the last revolutions, every sample",
            width=WIDTH,
            height=HEIGHT,
            tools="pan,box_zoom,reset,save",
        ),
        "time t [s]",
        "flow [L/s]",
    )
    closeup.line("t", "flow", source=sources["closeup"], color=COLORS["flow"], line_width=2)
    closeup.scatter("t", "flow", source=sources["closeup"], color=COLORS["flow"], size=4)
    return whole, closeup, sources


def stall_view():
    """View 3: Eq. (22), the windmill's characteristic torque against the load's."""
    names = ["windmill: T_m†", "load: R† L†/π"]
    source = ColumnDataSource(
        {"name": names, "value": [0.0, 0.0], "color": [COLORS["windmill"], COLORS["load"]]}
    )
    fig = styled(
        figure(
            title="Stall criterion, Eq. (22)",
            y_range=FactorRange(*names),
            width=WIDTH,
            height=HEIGHT * 2 // 3,
            tools="save",
        ),
        "dimensionless torque (Eqs. 14, 15)",
        "",
    )
    fig.hbar(y="name", right="value", height=0.6, color="color", source=source)
    fig.x_range.start = 0
    fig.xaxis.ticker.desired_num_ticks = 5
    return fig, {"stall": source}


def operating_view():
    """View 4: Eq. (5) against the windmill's power curve, with their intersections."""
    sources = {
        "curve": empty("omega", "power"),
        "load_line": empty("omega", "power"),
        "stable": empty("omega", "power"),
        "unstable": empty("omega", "power"),
        "data": empty("omega", "power"),
    }
    fig = styled(
        figure(
            title="Operating point, Eq. (5)",
            width=WIDTH,
            height=HEIGHT,
            tools="pan,box_zoom,reset,save",
        ),
        "windmill speed ω [rad/s]",
        "power [W]",
    )
    items = [
        (
            "windmill T(ω) ω, Eq. (11)",
            fig.line(
                "omega", "power", source=sources["curve"], color=COLORS["windmill"], line_width=3
            ),
        ),
        (
            "pump load, Eq. (5)",
            fig.line(
                "omega", "power", source=sources["load_line"], color=COLORS["load"], line_width=3
            ),
        ),
        (
            "operating point (stable)",
            fig.scatter("omega", "power", source=sources["stable"], size=14, color="black"),
        ),
        (
            "unstable intersection",
            fig.scatter(
                "omega",
                "power",
                source=sources["unstable"],
                size=14,
                fill_color="white",
                line_color="black",
                line_width=2,
            ),
        ),
        (
            "measured T ω (lab data)",
            fig.scatter(
                "omega",
                "power",
                source=sources["data"],
                size=8,
                marker="triangle",
                color=COLORS["data"],
            ),
        ),
    ]
    legend(fig, items, location="top_left", place="right")
    return fig, sources
