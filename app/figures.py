"""The explorer's Bokeh figures: built once, with named data sources that updates refill in place."""

from __future__ import annotations

from bokeh.core.property.descriptors import UnsetValueError
from bokeh.models import ColumnDataSource, CustomJS, GlyphRenderer, Legend, LegendItem
from bokeh.plotting import figure

WIDTH, HEIGHT = 900, 330  # WIDTH: the widest a view is drawn, so bins of 2 px: WIDTH // 2
ZOOM = "pan,box_zoom,wheel_zoom,reset,save"
TITLE, LABEL, TICKS = "16px", "15px", "14px"  # nothing a student must read below 14 px
# Each theme's colours: every drawn line, marker and label stands out from its plot's background
# by at least 3:1 (WCAG's non-text contrast; tests/app/test_app_colours.py), white in the light theme,
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


# Canvas-drawn text, normal and in presentation mode (the page's HTML follows styles.px)
PRESENTATION_SIZES = {TITLE: "22px", LABEL: "19px", TICKS: "18px"}  # text glyphs are LABEL
LINE_SCALE = 1.5  # lines in presentation mode
SWATCH = 20  # a legend's swatch [px], Bokeh's default; SWATCH_GROWTH larger in presentation mode
SWATCH_GROWTH = 1.4
NARROW = 700  # [px] a phone: the page's narrow layout (page.NARROW_CSS), where text keeps its size


def present(fig, large: bool) -> None:
    """Presentation mode on (``large``) or back off for one figure: every text it draws on its
    canvas (title, axes, legends, colour bars, text glyphs) and its lines. Idempotent."""
    if getattr(fig, "_presented", False) == large:
        return
    fig._presented = large
    heights = getattr(fig, "_heights", None)  # grow_in_presentation
    if heights is not None:
        fig.height = heights[large]
    size = PRESENTATION_SIZES if large else {v: k for k, v in PRESENTATION_SIZES.items()}
    fig.title.text_font_size = size.get(fig.title.text_font_size, fig.title.text_font_size)
    for axis in (*fig.xaxis, *fig.yaxis):
        for prop in ("axis_label_text_font_size", "major_label_text_font_size"):
            setattr(axis, prop, size.get(getattr(axis, prop), getattr(axis, prop)))
    for panel in fig.center + fig.below + fig.above + fig.left + fig.right:
        for prop in ("label_text_font_size", "title_text_font_size", "major_label_text_font_size"):
            value = getattr(panel, prop, None)
            if isinstance(value, str) and value in size:
                setattr(panel, prop, size[value])
        if isinstance(panel, Legend):
            swatch = getattr(panel, "_swatch", SWATCH)
            panel.glyph_width = panel.glyph_height = (
                round(swatch * SWATCH_GROWTH) if large else swatch
            )
    scale = LINE_SCALE if large else 1 / LINE_SCALE
    for renderer in fig.renderers:
        glyph = getattr(renderer, "glyph", None)
        if hasattr(glyph, "line_width") and isinstance(glyph.line_width, int | float):
            glyph.line_width = glyph.line_width * scale
        font = getattr(glyph, "text_font_size", None)
        if isinstance(font, str) and font in size:
            glyph.text_font_size = size[font]


def grow_in_presentation(fig, height: int) -> None:
    """Draw ``fig`` ``height`` px high in presentation mode (``present``), its own height else:
    for a figure whose larger text (a legend below in more rows) leaves its plot too little room."""
    fig._heights = {False: fig.height, True: height}


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
    fit_text_in_the_browser(fig)
    return fig


# A figure's canvas text in the browser, whenever its size, a text or a text's size changes: each
# title and axis label at the size the server set, or smaller down to 14 px if it would be cut
# (a phone, presentation mode); legends below a plot in two columns if two fit (from the frame's
# left edge to the figure's right), else one.
FIT_TEXT_JS = """
const P = plot.__fit_text ?? (plot.__fit_text = {asked: new Map(), busy: false})
if (P.busy) return
P.busy = true
try {
  const ctx = document.createElement('canvas').getContext('2d')
  const measure = (text, px, style) => {
    ctx.font = `${style} ${px}px helvetica`
    return Math.max(0, ...String(text ?? '').split('\\n').map(line => ctx.measureText(line).width))
  }
  // The size the server asked for: remembered, unless it has sent another since we fitted it.
  const asked = (model, attr) => {
    const key = model.id + attr, entry = P.asked.get(key)
    if (entry == null || model[attr] !== entry.fitted) P.asked.set(key, {size: model[attr], fitted: model[attr]})
    return P.asked.get(key)
  }
  // On a phone (the page's narrow layout) the text keeps its size in presentation mode, as the
  // page's HTML does (styles.zoom_css): a size the server asked for presentation mode is drawn
  // at its usual one (phone_sizes).
  const phone = window.matchMedia(`(max-width: ${narrow}px)`).matches
  const usual = (size) => (phone && phone_sizes[size] != null ? phone_sizes[size] : size)
  const keep = (model, attr) => {
    if (model == null || typeof model[attr] !== 'string') return
    const entry = asked(model, attr)
    entry.fitted = usual(entry.size)
    if (model[attr] !== entry.fitted) model.setv({[attr]: entry.fitted}, {sync: false})
  }
  for (const axis of [...plot.below, ...plot.left]) keep(axis, 'major_label_text_font_size')
  for (const panel of [...plot.below, ...plot.above, ...plot.left, ...plot.right, ...plot.center]) {
    if (panel.items !== undefined) {  // a legend: its labels, and its swatches back to their size
      const entry = asked(panel, 'label_text_font_size')
      keep(panel, 'label_text_font_size')
      const swatch = asked(panel, 'glyph_width')
      const size = entry.fitted !== entry.size ? Math.round(swatch.size / swatch_growth) : swatch.size
      swatch.fitted = size
      if (panel.glyph_width !== size) panel.setv({glyph_width: size, glyph_height: size}, {sync: false})
    } else if (panel.color_mapper !== undefined) {  // a colour bar
      keep(panel, 'title_text_font_size')
      keep(panel, 'major_label_text_font_size')
    }
  }
  for (const renderer of plot.renderers) {  // text glyphs: their size is a value spec
    const glyph = renderer.glyph, spec = glyph?.text_font_size
    if (spec == null || typeof spec.value !== 'string') continue
    const key = glyph.id + 'text_font_size', known = P.asked.get(key)
    if (known == null || spec.value !== known.fitted) P.asked.set(key, {size: spec.value, fitted: spec.value})
    const entry = P.asked.get(key)
    entry.fitted = usual(entry.size)
    if (spec.value !== entry.fitted) glyph.setv({text_font_size: {value: entry.fitted}}, {sync: false})
  }
  const fit = (model, attr, text, style, room) => {
    if (model == null || !text || room <= 0) return
    const entry = asked(model, attr)
    let px = parseFloat(usual(entry.size))
    while (px > 14 && measure(text, px, style) > room) px -= 1
    entry.fitted = `${px}px`
    if (model[attr] !== entry.fitted) model.setv({[attr]: entry.fitted}, {sync: false})
  }
  const width = plot.inner_width, height = plot.inner_height
  // A title starts at the frame's left edge: its room is the frame and the border to its right
  // (most of the border, ~4/5, is the y axis on the left).
  fit(plot.title, 'text_font_size', plot.title?.text, 'bold', plot.outer_width - (plot.outer_width - width) * 0.8)
  for (const axis of plot.below) if (axis.axis_label !== undefined) fit(axis, 'axis_label_text_font_size', axis.axis_label, 'italic', width)
  for (const axis of plot.left) if (axis.axis_label !== undefined) fit(axis, 'axis_label_text_font_size', axis.axis_label, 'italic', height)
  // Fewer ticks where their labels would crowd (a phone, presentation mode): a tick's label and
  // a gap of its size, across the frame; the server's number of ticks at most.
  const ticks = (axis, room, size) => {
    const ticker = axis.ticker
    if (ticker?.desired_num_ticks === undefined || !(size > 0) || room <= 0) return
    const entry = asked(ticker, 'desired_num_ticks')
    const n = Math.max(2, Math.min(entry.size, Math.floor(room / (2 * size))))
    entry.fitted = n
    if (ticker.desired_num_ticks !== n) ticker.setv({desired_num_ticks: n}, {sync: false})
  }
  const label = (axis) => parseFloat(axis.major_label_text_font_size) || 14
  // a tick label as long as the range's ends' (a time of day on a datetime axis)
  const shown = (v) => {
    const a = Math.abs(v ?? 0)
    return (v < 0 ? '-' : '') + (a >= 1e6 ? '00:00' : a >= 10 ? String(Math.round(a)) : a.toFixed(1))
  }
  const widestTick = (axis, range) =>
    range == null ? 0 : Math.max(...[range.start, range.end].map(v => measure(shown(v), label(axis), '')))
  for (const axis of plot.below) if (axis.ticker !== undefined) ticks(axis, width, Math.max(widestTick(axis, plot.x_range), label(axis)))
  for (const axis of plot.left) if (axis.ticker !== undefined) ticks(axis, height, label(axis))
  // A legend below (or above) starts at the frame's left edge, past the y axis: its room runs
  // from there to the figure's right edge (over a colour bar's border on the right).
  const frame = window.Bokeh?.index?.find_one?.(plot)?.frame?.bbox
  const room = plot.outer_width - (frame != null ? frame.left : (plot.outer_width - width) * 0.8)
  for (const legend of [...plot.below, ...plot.above]) {
    if (legend.orientation !== 'horizontal' || legend.items === undefined) continue
    // On a phone a label drops its equation's number (", Eq. (12)"): the caption under the
    // figure gives them, and the legend takes a row less. Back as the server sent it elsewhere.
    for (const item of legend.items) {
      const label = item.label
      if (label == null || typeof label.value !== 'string') continue
      const entry = P.asked.get(item.id + 'label')
      if (entry == null || label.value !== entry.fitted) P.asked.set(item.id + 'label', {size: label.value, fitted: label.value})
      const own = P.asked.get(item.id + 'label')
      own.fitted = phone ? own.size.replace(/,? ?Eqs?\\. \\([0-9]+\\)$/, '') : own.size
      if (label.value !== own.fitted) item.setv({label: {value: own.fitted}}, {sync: false})
    }
    ctx.font = `${legend.label_text_font_size} helvetica`
    // in n columns, row by row: the first column holds items 0, n, 2n..., the second 1, n + 1...
    // (two at most, three on a phone, whose labels are short)
    const shown = legend.items.filter(item => item.visible !== false)
    const widths = shown.map(item => ctx.measureText(item.label?.value ?? String(item.label ?? '')).width)
    const swatch = legend.glyph_width + legend.label_standoff
    const packed = phone ? phone_legend : wide_legend
    const box = (n) => {
      let sum = 0
      for (let j = 0; j < n; j++) sum += Math.max(0, ...widths.filter((_, i) => i % n === j))
      return sum + n * swatch + (n - 1) * column_gap + 2 * packed.padding + 2 * legend.border_line_width
    }
    let ncols = 1
    for (let n = 2; n <= (phone ? 3 : 2) && n <= shown.length; n++) if (box(n) <= room - packed.margin) ncols = n
    if (legend.ncols !== ncols) legend.setv({ncols}, {sync: false})
    // On a phone a legend below is packed (PHONE_LEGEND): its rows ~16 px, not ~23, and less
    // padding, so that a plot with five items (a deep well's crank speed, three rows) still fits
    // the first screen whole, its frame as high as elsewhere.
    const changed = Object.fromEntries(Object.entries(packed).filter(([k, v]) => legend[k] !== v))
    if (Object.keys(changed).length > 0) legend.setv(changed, {sync: false})
    if (phone && legend.glyph_height > phone_legend.label_height) {
      legend.setv({glyph_height: phone_legend.label_height}, {sync: false})
    }
  }
  // A figure the first screen of a phone shows whole (the crank speed, page.NARROW_CSS): its
  // height there is what its frame of ``phone_frame`` px needs with its title, axes and legend.
  const frame_px = (plot.tags ?? []).find(tag => tag?.phone_frame != null)?.phone_frame
  if (frame_px != null) {
    const entry = asked(plot, 'height')
    const around = plot.outer_height - plot.inner_height
    entry.fitted = phone && around > 0 ? Math.round(around + frame_px) : entry.size
    if (Math.abs(plot.height - entry.fitted) > 1) plot.setv({height: entry.fitted}, {sync: false})
  }
} finally {
  P.busy = false
}
"""


def fit_text_in_the_browser(fig) -> None:
    """Keep a figure's canvas text inside it at every width (``FIT_TEXT_JS``)."""
    fit = CustomJS(
        args=dict(
            plot=fig,
            column_gap=LEGEND_COLUMN_GAP,
            narrow=NARROW,
            phone_sizes={large: usual for usual, large in PRESENTATION_SIZES.items()},
            swatch_growth=SWATCH_GROWTH,
            phone_legend=PHONE_LEGEND,
            wide_legend=WIDE_LEGEND,
        ),
        code=FIT_TEXT_JS,
    )
    fig.js_on_change("outer_width", fit)
    fig.js_on_change("inner_height", fit)
    fig.title.js_on_change("text", fit)
    fig.title.js_on_change("text_font_size", fit)
    for axis in (*fig.xaxis, *fig.yaxis):
        axis.js_on_change("axis_label", fit)
        axis.js_on_change("axis_label_text_font_size", fit)
        axis.js_on_change("major_label_text_font_size", fit)  # presentation mode: fewer ticks
    fig._fit_text = fit


def lean(fig) -> None:
    """Drop the copies of each glyph Bokeh makes for a selection and a muted legend item (neither
    happens here: no tool selects, no legend mutes) and let the browser make them if ever asked:
    a page's views are ~80 models and 13 % of their message lighter."""
    for renderer in fig.renderers:
        if isinstance(renderer, GlyphRenderer):
            renderer.nonselection_glyph = "auto"
            renderer.muted_glyph = "auto"


def line(fig, x: str, y: str, source, color: str, width: float = 2, dash: str = "solid"):
    return fig.line(x, y, source=source, color=color, line_width=width, line_dash=dash)


# A legend below a plot on a phone (FIT_TEXT_JS): its rows, padding, margin and spacing [px]
# packed, its text at its size; Bokeh's own elsewhere. Three rows take ~60 px instead of ~96.
PHONE_LEGEND = {"label_height": 16, "padding": 4, "margin": 4, "spacing": 0}
WIDE_LEGEND = {"label_height": "auto", "padding": 10, "margin": 10, "spacing": 3}
# [px] the crank speed's frame on a phone (its figure as high as that, its title, axes and legend
# need): the readouts, a four-line status and the whole chart fit the first screen of 390×844.
PHONE_FRAME = 160
LEGEND_WIDTH = 340  # [px] a figure's width on a phone (390 px): a legend below fits in it
# [px] between a legend's columns (its ``spacing``, 3 px, ran a swatch into the label before it:
# "max▬ ▬ mean"); its rows keep theirs (Bokeh's legend is a CSS grid: ``gap`` sets both)
LEGEND_COLUMN_GAP = 14
LEGEND_GAP_CSS = f".bk-grid {{ column-gap: {LEGEND_COLUMN_GAP}px !important; }}"


def legend_columns(labels) -> int:
    """The server's first guess, before the browser measures them (``FIT_TEXT_JS``): two columns
    of labels below a plot when two fit in LEGEND_WIDTH at 14 px, else one."""
    longest = max((len(label) for label in labels), default=0)
    # a label: ~0.55 of the font size a character; a swatch and gaps (LEGEND_COLUMN_GAP) of ~5
    return 2 if 2 * 0.55 * 14 * (longest + 5) <= LEGEND_WIDTH else 1


def legend(fig, items: dict, location="top_left", place="below", swatch: int = SWATCH):
    """A legend of {label: renderer, or a list of renderers drawn as one swatch} beside the plot
    (``place``; below by default, so it never covers data), in as many columns as fit, each
    swatch ``swatch`` px square (Bokeh draws a marker in it 0.4 of that across, whatever its size
    on the plot). Returns {label: LegendItem}, so an update can hide the items of what is not
    drawn."""
    entries = {
        label: LegendItem(
            label=label, renderers=list(drawn) if isinstance(drawn, list | tuple) else [drawn]
        )
        for label, drawn in items.items()
    }
    across = place in ("below", "above")
    box = Legend(
        items=list(entries.values()),
        location=location,
        orientation="horizontal" if across else "vertical",
        ncols=legend_columns(items) if across else "auto",
        label_text_font_size=TICKS,
        click_policy="hide",
        background_fill_alpha=0.7,
        stylesheets=[LEGEND_GAP_CSS],
        glyph_width=swatch,
        glyph_height=swatch,
    )
    box._swatch = swatch  # present() scales it
    fig.add_layout(box, place)
    if across and hasattr(fig, "_fit_text"):
        box.js_on_change("label_text_font_size", fig._fit_text)
        for entry in entries.values():  # a label changed later (a leaky pump's map's red line)
            entry.js_on_change("label", fig._fit_text)
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
    """A drawing with equal scales on both axes, so a link looks as long as it is: its ranges
    are fixed ones, set by ``show_box`` for the frame's shape (Bokeh's data ranges, recomputed in
    the browser, kept the first ones it was sent)."""
    fig = new_figure(
        title,
        "x [m]",
        "y [m]",
        height=MECHANISM_SIZE,
        tools="pan,wheel_zoom,reset,save",
        x_range=(-1.0, 1.0),
        y_range=(-1.0, 1.0),
        max_width=MECHANISM_SIZE,
    )
    return fig


def show_box(fig, x0: float, x1: float, y0: float, y1: float) -> None:
    """Show at least the box [x0, x1] x [y0, y1] [m] on a mechanism's drawing, at equal scales
    across and up (a link looks as long as it is, a circle stays round): the span with room to
    spare widened about its middle to the frame's shape. The frame is taken as square until the
    page says its pixels (``inner_width`` and ``inner_height``), and the box is fitted again
    whenever the page lays the figure out anew (a drawing beside another at 1920 px, a phone)."""
    fig._box = (x0, x1, y0, y1)
    if not getattr(fig, "_follows_frame", False):
        fig._follows_frame = True
        for side in ("inner_width", "inner_height"):
            fig.on_change(side, lambda _attr, _old, _new: fit_box(fig))
    fit_box(fig)


def fit_box(fig) -> None:
    """``show_box``'s ranges for the frame's pixels as last said."""
    x0, x1, y0, y1 = fig._box
    try:
        width, height = fig.inner_width, fig.inner_height
    except UnsetValueError:  # not laid out yet, or one of the two said, not the other
        width = height = None
    if not width or not height:
        width = height = 1
    scale = max((x1 - x0) / width, (y1 - y0) / height)  # [m/px] the box's larger need
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    for axis, centre, pixels in ((fig.x_range, cx, width), (fig.y_range, cy, height)):
        start, end = centre - scale * pixels / 2, centre + scale * pixels / 2
        # the reset tool's too (a fixed range resets to the first one the browser was sent)
        axis.update(start=start, end=end, reset_start=start, reset_end=end)


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
