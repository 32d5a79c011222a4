"""The Design map tab: mean flow over sprocket ratio and head, the stall boundary, the best gear.

The map is ``windpump.design_map`` (the averaged theory) over the R₁/R₀ slider's range and the
heads from 0 to 30 m (the paper's pump), or further for a deeper well (``map_heads``: a catalogue
mill's 53 m on a 0-100 m map), for every other input as set: it is recomputed only when one of
those changes (or the head crosses to another map's range), while the marker of the current
design follows the R₁/R₀ and h sliders. A tap on the map moves the design
there. Every number comes from ``windpump``.
"""

from __future__ import annotations

import functools
import logging
import math

import numpy as np
import panel as pn
from bokeh.core.properties import value as text_value
from bokeh.core.property.descriptors import UnsetValueError
from bokeh.events import Tap
from bokeh.models import (
    ColorBar,
    ColumnDataSource,
    CustomJS,
    CustomJSHover,
    FixedTicker,
    HoverTool,
    LogColorMapper,
    PrintfTickFormatter,
    TapTool,
)
from bokeh.palettes import Viridis256
from bokeh.plotting.contour import contour_data

import windpump
from windpump.study.resampling import COARSE, fine_map
from windpump.units import SECONDS_PER_DAY

from .escape import as_text
from .figures import TICKS, empty, legend, new_figure, palette
from .inputs import on_grid
from .page import pane_height_css
from .server.api import Newest, off_the_loop
from .styles import CAPTION_CSS, TEXT
from .tab import Tab
from .views import refill

log = logging.getLogger("windpump.app")

GRID = 160  # ratios x heads: under the figure's pixels, ~2 ms to compute
# [m] the map's heads: the paper's pump's (it stalls at 21 m; sidebar.PAPERS_HEADS), or for a
# deeper design (a catalogue mill's lift, inputs.PumpInputs.h to 300 m) from 0 to the first of
# HEAD_TOPS at least HEAD_ROOM times its head (``map_heads``)
MAP_HEADS = (0.0, 30.0)
HEAD_TOPS = (30.0, 60.0, 100.0, 150.0, 200.0, 300.0, 450.0)
HEAD_ROOM = 1.5
LEAKY_GRID = COARSE  # a leaky pump's map, interpolated onto GRID: ~1.7 s
STALE_ALPHA = (
    0.35  # the map drawn, dimmed while a newer design's is worked out (a leaky one ~1.7 s)
)
DECADES = 2
MAP_HEIGHT = 520  # [px] the figure: its frame ~335 px high on a projector, the legend below
# On a phone the figure is no higher than what the tabs' pane shows (page.pane_height_css, ~616
# of its ~632 px at 390×844, ~440 at 640 px high): a student sees it whole, colour bar and legend (at 520 px its top
# went under the header once scrolled to its foot). Not below 300 px (a frame of ~90 px). Its
# height and its flex basis: Panel lays it out in a column, where the basis (520 px) rules.
PHONE_HEIGHT = f"clamp(300px, {pane_height_css()}, {MAP_HEIGHT}px)"
# On a wide screen (WIDE_PX and wider: 1920×1080) the map took its 520 px and drew a frame ~4 times
# wider than high over half the screen, the lower half blank: there it takes the screen's height
# below its top (FILL_MARGIN px left under it), MAP_HEIGHT at least and twice that at most, as the
# Mechanisms tab's figures do. Narrower screens keep MAP_HEIGHT (a phone: PHONE_CSS).
WIDE_PX = 1600
FILL_MARGIN = 24
FILL_HEIGHT_JS = """
// after the layout pass that called it (a height set within it is laid out on the next one)
setTimeout(() => {
  const view = window.Bokeh?.index?.find_one?.(cb_obj)
  if (view == null) return
  const box = view.el.getBoundingClientRect()
  if (box.width === 0) return  // a hidden tab: laid out when shown
  const pane = document.querySelector('#main')
  const scrolled = pane != null ? pane.scrollTop : 0
  const room = window.innerHeight - margin - (box.top + scrolled)
  const want = window.innerWidth >= wide ? Math.round(Math.min(2 * least, Math.max(least, room))) : least
  if (Math.abs(cb_obj.height - want) > 1) cb_obj.setv({height: want}, {sync: false})
}, 0)
"""
PHONE_CSS = (
    f"@media (max-width: 700px) {{ :host {{ height: {PHONE_HEIGHT} !important; "
    f"flex-basis: {PHONE_HEIGHT} !important; }} }}"
)
# The hover's flow: the core's mean flow [m³/day], NaN where the pump cannot run (DesignMap: stall
# margin 1 or less, left of a tight pump's red line), said in words there (it said "NaN m³/day").
# Bokeh writes "NaN" for a NaN field before any formatter sees it: the formatter is given the
# hovered pixel's index ($image_index) and reads the flow there itself, as Bokeh reads @image.
STALLED = "0 m³/day: it stalls"
FLOW_HOVER_JS = """
const image = source.data.image[value.index]
const flow = Array.isArray(image[0]) ? image[value.j][value.i] : image[value.flat_index]
return Number.isFinite(flow) ? `${flow.toFixed(1)} m³/day` : stalled
"""


def map_heads(h: float) -> tuple[float, float]:
    """The map's heads [m] for a design of head ``h`` [m]: the paper's 0 to 30 m, or from 0 to
    the first of HEAD_TOPS at least HEAD_ROOM times ``h`` (the design's star inside, with the
    heads above it where a deeper well would be): a round top that changes only as the head
    crosses a step, each change a new map (a leaky pump's ~1.7 s), not one a move of h.

    >>> map_heads(3.0), map_heads(20.0), map_heads(175 * 0.3048), map_heads(300.0)
    ((0.0, 30.0), (0.0, 30.0), (0.0, 100.0), (0.0, 450.0))
    """
    wanted = HEAD_ROOM * h
    return MAP_HEADS[0], next((top for top in HEAD_TOPS if top >= wanted), HEAD_TOPS[-1])


def colour_range(flow: np.ndarray) -> tuple[float, float]:
    """The log colour scale's ends [m^3/day]: the map's top and at most DECADES below it (the
    flow at no head grows as 1/R+, so a linear scale would leave the rest of the map dark)."""
    finite = flow[np.isfinite(flow) & (flow > 0.0)]
    if finite.size == 0:
        return 0.1, 1.0
    top = float(finite.max())
    return max(float(finite.min()), top / 10**DECADES), top


def round_values(low: float, top: float, mantissas=(1.0, 2.0, 5.0)) -> np.ndarray:
    """The values m x 10^k (m in ``mantissas``) from ``low`` to ``top``, in order."""
    decades = 10.0 ** np.arange(np.floor(np.log10(low)), np.ceil(np.log10(top)) + 1)
    values = np.sort(np.outer(decades, mantissas).ravel())
    return values[(values >= low * (1 - 1e-12)) & (values <= top * (1 + 1e-12))]


def contour_levels(flow: np.ndarray) -> np.ndarray:
    """The round levels 1, 2, 5 x 10^k [m^3/day] within the map's colour range; none when
    nothing runs."""
    if not (np.isfinite(flow) & (flow > 0.0)).any():
        return np.array([])
    low, top = colour_range(flow)
    levels = round_values(low, top)
    return levels[(levels > low) & (levels < top)]


def colour_ticks(low: float, top: float) -> list[float]:
    """The colour bar's ticks: 1, 2, 5 x 10^k over the whole log scale (1 to 9 x 10^k on a
    scale too short for three of those), so its lower part is labelled as well as its top."""
    ticks = round_values(low, top)
    if len(ticks) < 3:
        ticks = round_values(low, top, mantissas=np.arange(1.0, 10.0))
    return [float(t) for t in ticks]


def relative_luminance(colour: str) -> float:
    """WCAG's relative luminance of a '#rrggbb' colour."""
    channels = np.array([int(colour[i : i + 2], 16) for i in (1, 3, 5)]) / 255.0
    linear = np.where(channels <= 0.04045, channels / 12.92, ((channels + 0.055) / 1.055) ** 2.4)
    return float(linear @ [0.2126, 0.7152, 0.0722])


def ink_on(colour: str) -> str:
    """Black or white, whichever stands out more on ``colour`` (a contour and its label on the
    map's colour at their level)."""
    return "#000000" if relative_luminance(colour) > 0.179 else "#ffffff"


def mapped_colour(mapper: LogColorMapper, value: float) -> str:
    """The colour the log colour mapper gives a value (as the browser's LogColorMapper does)."""
    span = math.log(mapper.high) - math.log(mapper.low)
    index = int((math.log(value) - math.log(mapper.low)) / span * len(mapper.palette))
    return mapper.palette[min(max(index, 0), len(mapper.palette) - 1)]


def label_place(
    xs: np.ndarray,
    ys: np.ndarray,
    x_range,
    y_range,
    stall: np.ndarray | None = None,
    taken: list[tuple[float, float, float, float]] | None = None,
    size: tuple[float, float] | None = None,
) -> tuple[float, float, str, str] | None:
    """Where a contour's label goes, (x, y, text_align, text_baseline, and its
    nudge right and up [px] off the frame's edges: ``edge_nudge``), clear of the labels
    already placed (``taken``: their boxes, ``label_box``): its middle vertex away from the
    map's edges (where a label would be cut) whose label, aligned as ``label_anchor`` says or
    else extending rightwards, keeps clear of the stall boundary (``stall``: its ratio at heads
    spanning ``y_range`` evenly; ``label_clearance``); else, while no more than LABELLED_ANYWAY
    box is ``taken`` (the star: the first line placed), the placement farthest from it.
    None where every place covers a label (the colour bar tells the line's level, as
    Matplotlib's ``clabel`` leaves a label out where it does not fit). ``size``: a label's
    width and height as shares of the map's (``LABEL_SIZE`` by default)."""
    size = size or LABEL_SIZE
    finite = np.isfinite(xs) & np.isfinite(ys)
    (x0, x1), (y0, y1) = x_range, y_range
    inner = (
        finite
        & (xs > x0 + 0.1 * (x1 - x0))
        & (xs < x1 - 0.15 * (x1 - x0))
        & (ys > y0 + 0.05 * (y1 - y0))
        & (ys < y1 - 0.05 * (y1 - y0))
    )
    anchors = [label_anchor(x, y, x_range, y_range, size) for x, y in zip(xs, ys, strict=True)]
    aligns = np.array([align for align, _ in anchors])
    baselines = np.array([baseline for _, baseline in anchors])
    boxes = label_box(xs, ys, aligns, baselines, x_range, y_range, size)
    clearance = label_clearance(boxes, x_range, y_range, stall)
    # not clear as anchored: extending rightwards instead, where the label still fits the map
    fits = xs < x1 - max(0.2, size[0]) * (x1 - x0)
    rightwards = (clearance <= LABEL_MARGIN) & (aligns != "left") & fits
    aligns = np.where(rightwards, "left", aligns)
    boxes = label_box(xs, ys, aligns, baselines, x_range, y_range, size)
    nudges = edge_nudge(boxes, size)  # [px] each box moved EDGE_PX inside the frame, as drawn
    shift = nudges * np.divide(size, LABEL_PX)
    boxes = boxes + np.column_stack([shift[:, 0], shift[:, 1], shift[:, 0], shift[:, 1]])
    clearance = label_clearance(boxes, x_range, y_range, stall)
    clear = finite & (clearance > LABEL_MARGIN)
    free = finite & ~np.any([overlap(boxes, box) for box in taken or []], axis=0)
    if not free.any():
        return None  # every place on the line covers a label placed before
    wishes = (inner & clear & free, clear & free)
    chosen = next((wish for wish in wishes if wish.any()), None)
    if chosen is not None:
        candidates = np.flatnonzero(chosen)
        at = candidates[len(candidates) // 2]
    elif len(taken or []) > LABELLED_ANYWAY:
        return None  # no place clear of the stall boundary, and lines enough labelled
    else:
        at = int(np.argmax(np.where(free, clearance, -np.inf)))
    right, up = (float(v) for v in nudges[at])
    return float(xs[at]), float(ys[at]), str(aligns[at]), str(baselines[at]), right, up


# A contour label's size as a share of the map's width and height ("100 m³/day" at 15 px on a
# map ~600 x 330 px: LABEL_PX) until the page says the map's size, and the gap it keeps from the
# stall boundary, a share of the width.
LABEL_PX = (96.0, 23.0)
STAR_PX = 28.0  # this design's star (24 px) and its outline: no label under it
LABEL_SIZE = (0.16, 0.07)
LABEL_MARGIN = 0.02
# Where a line has no place clear of the stall boundary its label is left out once this many boxes
# are taken (this design's star): a tight corner at ~600 x 330 px holds the
# 100 and 200 m³/day labels only one over the other, one of them across the red line.
LABELLED_ANYWAY = 1
EDGE_PX = 6.0  # [px] the least gap between a label's box and the frame's edge
# The red line's legend: a tight pump's stall boundary, where a leaky one starts lifting water.
STAR_SWATCH = 32  # the legend's swatches [px]: its star 0.4 of that, ~13 px (24 on the map)
STALL_LABEL, DELIVERY_LABEL = "stall boundary (margin 1)", "lifts water right of this"
SHIFT = {"left": 0.0, "center": 0.5, "right": 1.0}  # of its width, left of its anchor
RISE = {"bottom": 1.0, "middle": 0.5, "top": 0.0}  # of its height, above its anchor


def label_clearance(boxes: np.ndarray, x_range, y_range, stall: np.ndarray | None) -> np.ndarray:
    """How far right of the stall boundary labels (their ``label_box`` rows) start, as a share
    of the map's width, where the boundary is farthest right over each label's height (its
    ratio grows with the head: at the label's top). ``stall``: the boundary's ratio at heads
    spanning ``y_range`` evenly (non-finite: none at that head); +inf where it has none."""
    (x0, x1), (y0, y1) = x_range, y_range
    known = np.isfinite(stall) if stall is not None else np.array([False])
    if not known.any():
        return np.full(len(boxes), np.inf)
    heads = np.linspace(y0, y1, len(stall))
    left, top = boxes[:, 0], np.minimum(boxes[:, 3], 1.0)
    boundary = np.interp(y0 + top * (y1 - y0), heads[known], stall[known])
    return left - (boundary - x0) / (x1 - x0)


def label_box(
    xs: np.ndarray,
    ys: np.ndarray,
    aligns: np.ndarray,
    baselines: np.ndarray,
    x_range,
    y_range,
    size: tuple[float, float] | None = None,
) -> np.ndarray:
    """The boxes (left, bottom, right, top) of labels at (xs, ys), so aligned, as shares of
    the map's width and height (a label's: ``size``, ``LABEL_SIZE`` by default), one row a
    label."""
    (x0, x1), (y0, y1) = x_range, y_range
    width, height = size or LABEL_SIZE
    shift = np.array([SHIFT[align] for align in aligns], dtype=float)
    rise = np.array([RISE[baseline] for baseline in baselines], dtype=float)
    left = (np.asarray(xs, dtype=float) - x0) / (x1 - x0) - shift * width
    top = (np.asarray(ys, dtype=float) - y0) / (y1 - y0) + rise * height
    return np.column_stack([left, top - height, left + width, top])


def overlap(boxes: np.ndarray, box) -> np.ndarray:
    """Whether each of ``boxes`` (rows of left, bottom, right, top) overlaps ``box``."""
    left, bottom, right, top = box
    return (
        (boxes[:, 0] < right) & (boxes[:, 2] > left) & (boxes[:, 1] < top) & (boxes[:, 3] > bottom)
    )


def edge_nudge(boxes: np.ndarray, size: tuple[float, float]) -> np.ndarray:
    """How far [px] (right, up) each label's box (rows of left, bottom, right, top, as shares of
    the map: ``label_box``) moves to keep EDGE_PX from each of the frame's edges: a label placed
    on its line's vertex at the frame's foot or top had its background flush with the edge, and
    read as cut. ``size``: a label's width and height as shares of the map (LABEL_PX in pixels).

    >>> edge_nudge(np.array([[0.5, 0.0, 0.6, 0.07], [0.95, 0.5, 1.02, 0.57]]), (0.07, 0.07))
    array([[  0.     ,   6.     ],
           [-33.42857,   0.     ]])
    """
    per_x, per_y = size[0] / LABEL_PX[0], size[1] / LABEL_PX[1]  # a pixel, as a share
    edge_x, edge_y = EDGE_PX * per_x, EDGE_PX * per_y
    left, bottom, right, top = np.asarray(boxes, dtype=float).T
    dx = np.maximum(edge_x - left, 0.0) - np.maximum(right - (1.0 - edge_x), 0.0)
    dy = np.maximum(edge_y - bottom, 0.0) - np.maximum(top - (1.0 - edge_y), 0.0)
    return np.round(np.column_stack([dx / per_x, dy / per_y]), 5) + 0.0


def label_anchor(
    x: float, y: float, x_range, y_range, size: tuple[float, float] | None = None
) -> tuple[str, str]:
    """(text_align, text_baseline) that keep a label at (x, y) inside the map: a label near an
    edge extends away from it (nearer than a quarter of the map or half the label's width,
    ``size``)."""
    (x0, x1), (y0, y1) = x_range, y_range
    across, up = (x - x0) / (x1 - x0), (y - y0) / (y1 - y0)
    edge = max(0.25, 0.5 * (size or LABEL_SIZE)[0])
    align = "left" if across < edge else "right" if across > 1 - edge else "center"
    baseline = "bottom" if up < 0.1 else "top" if up > 0.9 else "middle"
    return align, baseline


@functools.lru_cache(maxsize=4)
def map_of(key: windpump.Design, ratios: tuple, heads: tuple) -> tuple:
    """(flow [m^3/s], stall (or, with a leak hole, delivery) and best gear ratios by head) of the
    design ``key`` (every input but R₁ and h) over the ``ratios`` and ``heads`` (the page's grid,
    as (low, high, points)): the core's map for drawing (``windpump.study.resampling``: a leaky
    pump's on a coarse grid, ~1.7 s, off the event loop). Kept: the pages of a class mapping one
    design share it."""
    drawn = fine_map(key, np.linspace(*ratios), np.linspace(*heads))
    return drawn.mean_flow, drawn.edge_gear_ratio, drawn.best_gear_ratio


def marks_of(design: windpump.Design, ratios: tuple) -> tuple[float, float, float]:
    """This design's flow [m^3/day], and the best sprocket ratio on the map's ``ratios`` at its
    head with the flow there [m^3/day] (NaN: none carries the load)."""
    here = float(windpump.steady_flow(design, design.V_ref)) * SECONDS_PER_DAY
    row = windpump.design_map(design, np.linspace(*ratios), [design.h])
    return here, float(row.best_gear_ratio[0]), float(row.best_flow[0]) * SECONDS_PER_DAY


def best_ratio_sentence(design: windpump.Design, best_ratio: str, best_flow: str, now: str) -> str:
    """The map's readout: at ``design``'s head the best sprocket ratio on the map lifting
    ``best_flow`` [m^3/day], and what this design lifts (``now``), all as text."""
    return (
        f"At h = {design.h:.1f} m the best sprocket ratio is **R₁/R₀ = {best_ratio}**, "
        f"lifting **{best_flow} m³/day** (averaged theory); this design, "
        f"R₁/R₀ = {design.R_dagger:.2f}: {now}."
    )


class MapTab(Tab):
    """The Design map over the sliders' ranges of sprocket ratio and head, with this design
    marked; a tap moves the design there (``inputs``: the page's)."""

    title, waiting = "Design map", "Mapping the design…"

    def __init__(self, inputs, dark: bool = False):
        super().__init__(dark)
        self.inputs = inputs

    def build(self) -> None:
        self.mapped: tuple | None = None  # the last map drawn: (flow, stall and best ratios)
        self._lines = None  # its contour lines (bokeh's contour_data), labelled by place_labels
        self.colors = palette(self.dark)
        self.grid = (  # (low, high, points) of the ratios and of the heads, as drawn (_place)
            (*self.inputs.param["R_dagger"].bounds, GRID),
            (*MAP_HEADS, GRID),
        )
        self.ratios, self.heads = (np.linspace(*axis) for axis in self.grid)
        self.sources: dict[str, ColumnDataSource] = {
            # no image until the first map comes (a blank one's hover said NaN, now "it stalls")
            "flow": ColumnDataSource({"image": []}),
            "stall": empty("ratio", "h"),
            "best": empty("ratio", "h"),
            "here": empty("ratio", "h", "flow"),
            "contour_labels": empty(
                "x",
                "y",
                "text",
                "level",
                "color",
                "background",
                "align",
                "baseline",
                "x_offset",
                "y_offset",
            ),  # fmt: skip
        }
        for name, source in self.sources.items():
            source.name = f"maptab_{name}"  # for a browser: get_model_by_name
        self.figure = self._figure()
        self.figure.name = "map_figure"  # a browser test finds it by name
        fill = CustomJS(
            args=dict(least=MAP_HEIGHT, margin=FILL_MARGIN, wide=WIDE_PX), code=FILL_HEIGHT_JS
        )
        self.figure.js_on_change("outer_width", fill)
        # A tap moves the design and selects nothing: Bokeh's tap tool selected what lay under it
        # (a contour label, a line) and drew the rest of that renderer at a tenth of its alpha
        # (the other labels faded to near invisible). Its Tap event comes all the same.
        self.figure.add_tools(TapTool(renderers=[]))
        self.figure.on_event(Tap, lambda event: self.move_to(event.x, event.y))
        self.label_size = LABEL_SIZE  # a contour label's, as shares of the map's (LABEL_PX)
        for side in ("inner_width", "inner_height"):
            self.figure.on_change(side, lambda _attr, _old, _new: self.resized())
        self.readout = pn.pane.Markdown("", stylesheets=TEXT, sizing_mode="stretch_width")
        self._mapped_key: windpump.Design | None = None  # what the map drawn is of (its grid)
        self.maps = Newest()  # the map and mark of the design last asked for

    def _figure(self):
        s = self.sources
        x0, x1, y0, y1 = self.ratios[0], self.ratios[-1], self.heads[0], self.heads[-1]
        fig = new_figure(
            "Water a day over sprocket ratio and head",
            "sprocket ratio R₁/R₀",
            "head h [m]",
            height=MAP_HEIGHT,
            tools="pan,wheel_zoom,reset,save",
            stylesheets=[PHONE_CSS],
            x_range=(x0, x1),
            y_range=(y0, y1),
        )
        self.mapper = LogColorMapper(palette=Viridis256, low=0.1, high=1, nan_color=(0, 0, 0, 0))
        self.image = image = fig.image(
            image="image", x=x0, y=y0, dw=x1 - x0, dh=y1 - y0, source=s["flow"],
            color_mapper=self.mapper,
        )  # fmt: skip
        self.ticker = FixedTicker(ticks=colour_ticks(0.1, 1.0), minor_ticks=[])
        bar = ColorBar(
            color_mapper=self.mapper,
            title="mean flow [m³/day]",
            width=14,
            ticker=self.ticker,
            formatter=PrintfTickFormatter(format="%g"),
        )
        bar.title_text_font_size = bar.major_label_text_font_size = TICKS
        fig.add_layout(bar, "right")
        self._add_contours(fig)
        self._add_lines(fig, image)
        return fig

    def _add_contours(self, fig) -> None:
        """Contours of the flow, their lines and labels filled in by ``_draw_contours``."""
        s = self.sources
        # Each contour and its label in black or white, whichever stands out on its level's colour.
        self.contours = fig.contour(
            self.ratios, self.heads, np.zeros((GRID, GRID)), [0.5], fill_color=None,
            line_color="#ffffff", line_width=1.5,
        )  # fmt: skip
        self.contours.line_renderer.glyph.line_color = "color"
        self.contours.line_renderer.data_source.data = {
            "xs": [],
            "ys": [],
            "levels": [],
            "color": [],
        }
        fig.text(
            "x", "y", "text", source=s["contour_labels"], text_color="color",
            text_font_size=TICKS, text_align="align", text_baseline="baseline",
            x_offset="x_offset", y_offset="y_offset",
            background_fill_color="background", background_fill_alpha=0.75,
        )  # fmt: skip

    def _add_lines(self, fig, image) -> None:
        """The stall boundary, the best ratio at each head, this design, and the map's hover."""
        s, c = self.sources, self.colors
        stall = fig.line("ratio", "h", source=s["stall"], color=c["load"], line_width=3)
        best = fig.line(
            "ratio", "h", source=s["best"], color=c["best"], line_width=3, line_dash="dashed"
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
                    ("flow", "$image_index{custom}"),
                ],
                formatters={
                    "$image_index": CustomJSHover(
                        args=dict(source=s["flow"], stalled=STALLED), code=FLOW_HOVER_JS
                    )
                },
            )
        )
        self.legend = legend(
            fig,
            {
                STALL_LABEL: stall,
                "best sprocket ratio": best,
                "this design": self._swatch(fig, here),
            },
            swatch=STAR_SWATCH,
        )

    def _swatch(self, fig, here):
        """The star the legend draws for ``here`` (which it would draw 0.4 of its swatch across,
        its black outline all that is seen): outlined thinly in the theme's ink, so it reads on
        either theme's legend; drawn nowhere on the map, hidden and shown with ``here``."""
        c = self.colors
        star = fig.scatter(
            [np.nan], [np.nan], marker="star", size=24, fill_color=c["star"],
            line_color=c["ink"], line_width=1.0,
        )  # fmt: skip
        star.js_link("visible", here, "visible")
        return star

    def move_to(self, ratio: float, h: float) -> None:
        """A tap on the map: the sprocket ratio and head there, on the sliders' steps."""
        values = {}
        for name, value in (("R_dagger", ratio), ("h", h)):
            low, high = self.inputs.param[name].bounds
            step = self.inputs.param[name].step
            values[name] = min(max(on_grid(value, step), low), high)
        self.inputs.param.update(**values)

    def draw(self, seen: windpump.Exploration) -> None:
        """Map the design (when anything but R₁ and h changed) and mark it: worked out off the
        event loop (``serving.Newest``: the newest design wins, and one superseded before its
        turn in the pool is not worked out; a leaky pump's map is ~1.7 s of quadrature)."""
        design = seen.design
        key = design.replace(R1=design.R0, h=0.0)  # the map depends on everything else
        grid = self.grid_for(design)  # and its heads on how deep the design's well is
        if self._mapped_key is None:  # the first map: later ones replace it when they come
            self.readout.object = self.placeholder(design)
        elif (key, grid) != self.drawn():  # the map drawn is another's until the new one comes
            self.image.glyph.global_alpha = STALE_ALPHA

        self.maps.ask(
            design,
            lambda: (map_of(key, *grid), marks_of(design, grid[0])),
            lambda outcome: self._show(design, (key, grid), outcome),
            off_the_loop,
        )

    def drawn(self) -> tuple:
        """What the map drawn is of: (the design but R₁ and h, the grid; ``grid_for``)."""
        return self._mapped_key, self.grid

    def grid_for(self, design: windpump.Design) -> tuple:
        """The map's (low, high, points) of the ratios (the R₁/R₀ slider's range) and of the
        heads (``map_heads``: to 30 m, or further for a deeper well) for ``design``."""
        return (
            (*self.inputs.param["R_dagger"].bounds, GRID),
            (*map_heads(design.h), GRID),
        )

    def _place(self, grid: tuple) -> None:
        """The map over ``grid`` (``grid_for``): its axes' ranges and its image's place, in the
        figure as built (a deeper well's heads: the same figure, its ranges moved)."""
        if grid == self.grid:
            return
        self.grid = grid
        self.ratios, self.heads = (np.linspace(*axis) for axis in grid)
        (x0, x1, _), (y0, y1, _) = grid
        glyph = self.image.glyph
        glyph.update(x=x0, y=y0, dw=x1 - x0, dh=y1 - y0)
        for axis, (start, end) in (
            (self.figure.x_range, (x0, x1)),
            (self.figure.y_range, (y0, y1)),
        ):
            axis.update(start=start, end=end, reset_start=start, reset_end=end)

    def _show(self, design: windpump.Design, mapped: tuple, outcome) -> None:
        """Draw the map and mark ``outcome`` of ``design`` (the newest asked for; ``mapped``:
        the design it maps and its grid); one that cannot be mapped says why."""
        if isinstance(outcome, Exception):
            said = as_text(outcome)
            if not isinstance(outcome, ValueError):  # a bug: say so, log it, keep the page alive
                log.error("mapping the design failed", exc_info=outcome)
                said = f"Something went wrong ({type(outcome).__name__}: {as_text(outcome)})."
            self.failed(said)
            return
        drawn, marks = outcome
        key, grid = mapped
        with pn.io.hold():
            if mapped != self.drawn():
                self._place(grid)
                self._draw_map(drawn)
                said = DELIVERY_LABEL if key.d_leak > 0.0 else STALL_LABEL
                self.legend[STALL_LABEL].label = text_value(said)  # a text, not a column's name
                self._mapped_key = key
            self._mark(design, *marks)

    def _draw_map(self, mapped: tuple) -> None:
        self.mapped = flow, stall, best = mapped
        self.image.glyph.global_alpha = 1.0
        flow = flow * SECONDS_PER_DAY
        refill(self.sources["flow"], {"image": [flow]})
        self.mapper.low, self.mapper.high = colour_range(flow)
        self.ticker.ticks = colour_ticks(self.mapper.low, self.mapper.high)
        self._draw_contours(flow, stall)
        refill(self.sources["stall"], {"ratio": stall, "h": self.heads})
        refill(self.sources["best"], {"ratio": best, "h": self.heads})

    def _draw_contours(self, flow: np.ndarray, stall: np.ndarray) -> None:
        """The round levels' lines, each in black or white for its level's colour, and their
        labels (``place_labels``)."""
        levels = contour_levels(flow)
        lines: dict[str, list] = {"xs": [], "ys": [], "levels": [], "color": []}
        self._lines = None
        if len(levels):
            drawn = contour_data(self.ratios, self.heads, flow, levels, want_fill=False).line_data
            lines = {**drawn.asdict(), "color": []}
            lines["color"] = [ink_on(mapped_colour(self.mapper, level)) for level in drawn.levels]
            self._lines = drawn
        self.contours.line_renderer.data_source.data = lines
        self.contours.levels = [float(level) for level in levels]
        self.place_labels()

    def place_labels(self) -> None:
        """Each line labelled with its value at a point of it clear of the other labels and of
        this design's star and, where it can be, of the red line: the shortest lines, with the
        fewest places, first; a line with no place clear goes without one. Sent only when the
        labels move (this is redone when the star moves or the page lays the map out anew)."""
        drawn, placed = self._lines, {}  # each labelled line's label, by its index in the lines
        if drawn is not None and self.mapped is not None:
            stall = self.mapped[1]
            places = [int(np.isfinite(xs).sum()) for xs in drawn.xs]
            taken: list = [self.star_box()]  # then the boxes of the labels placed (label_box)
            for i in sorted(np.flatnonzero(places), key=places.__getitem__):
                under = mapped_colour(self.mapper, drawn.levels[i])
                xs, ys = np.asarray(drawn.xs[i]), np.asarray(drawn.ys[i])
                label = self._contour_label(drawn.levels[i], xs, ys, under, stall, taken)
                if label is not None:
                    placed[i] = label
        labels: dict[str, list] = {name: [] for name in self.sources["contour_labels"].data}
        for i in sorted(placed):  # in the lines' order
            for name, value in placed[i].items():
                labels[name].append(value)
        if labels != dict(self.sources["contour_labels"].data):
            refill(self.sources["contour_labels"], labels)

    def star_box(self) -> tuple[float, float, float, float]:
        """This design's star's box (left, bottom, right, top) as shares of the map: STAR_PX
        square, in the label's pixels (``label_size``)."""
        here = self.sources["here"].data
        if not len(here["ratio"]):
            return (-1.0, -1.0, -1.0, -1.0)  # no star yet: a box outside the map
        x = (here["ratio"][0] - self.ratios[0]) / (self.ratios[-1] - self.ratios[0])
        y = (here["h"][0] - self.heads[0]) / (self.heads[-1] - self.heads[0])
        half_w = 0.5 * STAR_PX * self.label_size[0] / LABEL_PX[0]
        half_h = 0.5 * STAR_PX * self.label_size[1] / LABEL_PX[1]
        return (x - half_w, y - half_h, x + half_w, y + half_h)

    def _contour_label(
        self,
        level: float,
        xs: np.ndarray,
        ys: np.ndarray,
        under: str,
        stall: np.ndarray,
        taken: list,
    ) -> dict | None:
        """A level's label clear of the boxes ``taken``, its box added (None: none fits)."""
        bounds = (self.ratios[0], self.ratios[-1]), (self.heads[0], self.heads[-1])
        size = self.label_size
        at = label_place(xs, ys, *bounds, np.asarray(stall, dtype=float), taken, size)
        if at is None:
            return None
        x, y, align, baseline, right, up = at  # right, up: [px] off the frame's edges
        box = label_box([x], [y], [align], [baseline], *bounds, size)[0]
        per_x, per_y = size[0] / LABEL_PX[0], size[1] / LABEL_PX[1]
        taken.append(box + [right * per_x, up * per_y, right * per_x, up * per_y])  # as drawn
        return {
            "x": x,
            "y": y,
            "text": f"{level:g} m³/day",
            "level": float(level),
            "color": ink_on(under),
            "background": under,
            "align": align,
            "baseline": baseline,
            "x_offset": right,
            "y_offset": -up,  # the canvas's y grows downwards
        }

    def resized(self) -> None:
        """The page laid the map out (``inner_width`` and ``inner_height``: its frame's pixels):
        a label's share of it follows, and the labels are placed again when it changed (a
        phone's map is a third of a projector's width; its labels two or three times wider)."""
        try:
            width, height = self.figure.inner_width, self.figure.inner_height
        except UnsetValueError:  # the page has sent one of them, not yet the other
            return
        if not width or not height:
            return
        size = (LABEL_PX[0] / width, LABEL_PX[1] / height)
        if np.allclose(size, self.label_size, rtol=0.1):
            return
        self.label_size = size
        self.place_labels()

    def _mark(self, design: windpump.Design, here: float, best_ratio: float, best_flow: float):
        refill(self.sources["here"], {"ratio": [design.R_dagger], "h": [design.h], "flow": [here]})
        self.place_labels()  # clear of the star where it now is
        if np.isnan(best_ratio):
            self.readout.object = (
                f"At h = {design.h:.1f} m no sprocket ratio on this map carries the load: "
                "lower the head or strengthen the windmill."
            )
            return
        now = f"{here:.1f} m³/day" if here > 0 else "it stalls"
        self.readout.object = best_ratio_sentence(
            design, f"{best_ratio:.2f}", f"{best_flow:.1f}", now
        )

    @staticmethod
    def placeholder(design: windpump.Design) -> str:
        """The readout while the first map is worked out: its sentence with dashes for the
        numbers, about as wide as they will be (no line added when they come, on a phone too)."""
        return best_ratio_sentence(design, "–.––", "––.–", "––.– m³/day")

    def failed(self, message: str) -> None:
        self.readout.object = message
        self.image.glyph.global_alpha = 1.0  # the map drawn stays, and is said not to be this one

    def figures(self) -> list:
        return [self.figure]

    def layout(self) -> pn.Column:
        return pn.Column(
            self.readout,
            pn.pane.Bokeh(self.figure, sizing_mode="stretch_width"),
            pn.pane.HTML(
                "<p>Colour (a log scale) and contours labelled in m³/day (1, 2, 5 × 10ᵏ): mean flow "
                "m A R α₊/π of the averaged theory (Eq. 21) for every other input as set. Left of the red line the stall margin "
                "(Eq. 22) is below 1 and the pump cannot run (with a leak hole it turns, too "
                "slowly to lift water past the hole); the dashed line is the best ratio "
                "at each head (stall margin 9/8 without torque at rest). Tap the map to move the "
                "design there.</p>",
                stylesheets=CAPTION_CSS,
            ),
            sizing_mode="stretch_width",
        )
