"""The Design map tab: mean flow over sprocket ratio and head, the stall boundary, the best gear.

The map is ``windpump.design_map`` (the averaged theory) over the sliders' own ranges of R₁/R₀
and h, for every other input as set: it is recomputed only when one of those changes, while the
marker of the current design follows the R₁/R₀ and h sliders. A tap on the map moves the design
there. Every number comes from ``windpump``.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import panel as pn
from bokeh.events import Tap
from bokeh.models import ColorBar, ColumnDataSource, HoverTool, LogColorMapper
from bokeh.palettes import Viridis256
from bokeh.plotting.contour import contour_data
from figures import TICKS, empty, legend, new_figure
from styles import CAPTION_CSS, TEXT
from views import refill

import windpump

GRID = 160  # ratios x heads: under the figure's pixels, ~2 ms to compute
PER_DAY = 86_400.0  # m^3/s to m^3/day
DECADES = 2


def colour_range(flow: np.ndarray) -> tuple[float, float]:
    """The log colour scale's ends [m^3/day]: the map's top and at most DECADES below it (the
    flow at no head grows as 1/R+, so a linear scale would leave the rest of the map dark)."""
    finite = flow[np.isfinite(flow) & (flow > 0.0)]
    if finite.size == 0:
        return 0.1, 1.0
    top = float(finite.max())
    return max(float(finite.min()), top / 10**DECADES), top


def contour_levels(flow: np.ndarray) -> np.ndarray:
    """The round levels 1, 2, 5 x 10^k [m^3/day] within the map's colour range; none when
    nothing runs."""
    if not (np.isfinite(flow) & (flow > 0.0)).any():
        return np.array([])
    low, top = colour_range(flow)
    decades = 10.0 ** np.arange(np.floor(np.log10(low)), np.ceil(np.log10(top)) + 1)
    levels = np.outer(decades, [1.0, 2.0, 5.0]).ravel()
    return levels[(levels > low) & (levels < top)]


class MapTab:
    """The Design map's figure, readout and ``update(design)``; a tap calls ``on_tap(ratio, h)``."""

    def __init__(
        self,
        ratio_bounds: tuple[float, float],
        head_bounds: tuple[float, float],
        on_tap: Callable[[float, float], None],
    ):
        self.ratios = np.linspace(*ratio_bounds, GRID)
        self.heads = np.linspace(*head_bounds, GRID)
        self.sources: dict[str, ColumnDataSource] = {
            "flow": ColumnDataSource({"image": [np.full((2, 2), np.nan)]}),
            "stall": empty("ratio", "h"),
            "best": empty("ratio", "h"),
            "here": empty("ratio", "h", "flow"),
        }
        for name, source in self.sources.items():
            source.name = f"maptab_{name}"  # for a browser: get_model_by_name
        self.figure = self._figure()
        self.figure.name = "map_figure"  # a browser test finds it by name
        self.figure.on_event(Tap, lambda event: on_tap(event.x, event.y))
        self.readout = pn.pane.Markdown("", stylesheets=TEXT, sizing_mode="stretch_width")
        self.mapped: windpump.DesignMap | None = None
        self._mapped_key: windpump.Design | None = None

    def _figure(self):
        s = self.sources
        x0, x1, y0, y1 = self.ratios[0], self.ratios[-1], self.heads[0], self.heads[-1]
        fig = new_figure(
            "Water a day over sprocket ratio and head",
            "sprocket ratio R₁/R₀",
            "head h [m]",
            height=520,
            tools="tap,pan,wheel_zoom,reset,save",
            x_range=(x0, x1),
            y_range=(y0, y1),
        )
        self.mapper = LogColorMapper(palette=Viridis256, low=0.1, high=1, nan_color=(0, 0, 0, 0))
        image = fig.image(
            image="image", x=x0, y=y0, dw=x1 - x0, dh=y1 - y0, source=s["flow"],
            color_mapper=self.mapper,
        )  # fmt: skip
        bar = ColorBar(color_mapper=self.mapper, title="mean flow [m³/day]", width=14)
        bar.title_text_font_size = bar.major_label_text_font_size = TICKS
        fig.add_layout(bar, "right")
        self.contours = fig.contour(
            self.ratios, self.heads, np.zeros((GRID, GRID)), [0.5], fill_color=None,
            line_color="white", line_alpha=0.8, line_width=1.5,
        )  # fmt: skip
        stall = fig.line("ratio", "h", source=s["stall"], color="#d62728", line_width=3)
        best = fig.line(
            "ratio", "h", source=s["best"], color="#ff7f0e", line_width=3, line_dash="dashed"
        )
        here = fig.scatter(
            "ratio", "h", source=s["here"], marker="star", size=24, color="white",
            line_color="black", line_width=1.5,
        )  # fmt: skip
        fig.add_tools(
            HoverTool(
                renderers=[image],
                tooltips=[
                    ("R₁/R₀", "$x{0.00}"),
                    ("h", "$y{0.0} m"),
                    ("flow", "@image{0.0} m³/day"),
                ],
            )
        )
        legend(
            fig,
            {
                "stall boundary (margin 1)": stall,
                "best sprocket ratio": best,
                "this design": here,
            },
        )
        return fig

    def update(self, design: windpump.Design) -> None:
        """Map the design (when anything but R₁ and h changed) and mark it."""
        key = design.replace(R1=design.R0, h=0.0)  # the map depends on everything else
        if key != self._mapped_key:
            self._draw_map(design)
            self._mapped_key = key
        self._mark(design)

    def _draw_map(self, design: windpump.Design) -> None:
        mapped = windpump.design_map(design, self.ratios, self.heads)
        flow = mapped.mean_flow * PER_DAY
        refill(self.sources["flow"], {"image": [flow]})
        self.mapper.low, self.mapper.high = colour_range(flow)
        levels = contour_levels(flow)
        data = contour_data(self.ratios, self.heads, flow, levels, want_fill=False)
        self.contours.set_data(data)
        self.contours.levels = list(levels)
        refill(self.sources["stall"], {"ratio": mapped.stall_gear_ratio, "h": self.heads})
        refill(self.sources["best"], {"ratio": mapped.best_gear_ratio, "h": self.heads})
        self.mapped = mapped

    def _mark(self, design: windpump.Design) -> None:
        here = float(windpump.steady_flow(design, design.V_ref)) * PER_DAY
        refill(self.sources["here"], {"ratio": [design.R_dagger], "h": [design.h], "flow": [here]})
        row = windpump.design_map(design, self.ratios, [design.h])
        best_ratio, best_flow = row.best_gear_ratio[0], row.best_flow[0] * PER_DAY
        if np.isnan(best_ratio):
            self.readout.object = (
                f"At h = {design.h:.1f} m no sprocket ratio on this map carries the load: "
                "lower the head or strengthen the windmill."
            )
            return
        now = f"{here:.1f} m³/day" if here > 0 else "it stalls"
        self.readout.object = (
            f"At h = {design.h:.1f} m the best sprocket ratio is **R₁/R₀ = {best_ratio:.2f}**, "
            f"lifting **{best_flow:.1f} m³/day** (averaged theory); this design, "
            f"R₁/R₀ = {design.R_dagger:.2f}: {now}."
        )

    def figures(self) -> list:
        return [self.figure]

    def layout(self) -> pn.Column:
        return pn.Column(
            self.readout,
            pn.pane.Bokeh(self.figure, sizing_mode="stretch_width"),
            pn.pane.HTML(
                "<p>Colour (a log scale) and white contours (1, 2, 5 × 10ᵏ m³/day): mean flow "
                "m A R α₊/π of the averaged theory (Eq. 21) for every other input as set. Left of the red line the stall margin "
                "(Eq. 22) is below 1 and the pump cannot run; the dashed line is the best ratio "
                "at each head (stall margin 9/8 without torque at rest). Tap the map to move the "
                "design there.</p>",
                stylesheets=CAPTION_CSS,
            ),
            sizing_mode="stretch_width",
        )
