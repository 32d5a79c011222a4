"""Every drawn element of every figure of the explorer is visible in both themes.

WCAG's non-text contrast (1.4.11): a line, marker, bar, text or legend swatch needs a contrast of
at least 3:1 against what it is drawn on. The colours are read from the figures' models, with the
dark theme's Bokeh theme applied as the page applies it, and the contrast is computed here from
WCAG's definition (not from the app's code). What is drawn on what:

- glyphs against the plot's background (the Design map's contours and their labels against the
  colour the map shows at their level, which is what lies under them);
- titles, axis labels and ticks against the border around the plot;
- legend labels and swatches against the legend's background (over the border);
- the colour bar's labels against the colour bar's background.

A glyph with both a fill and an outline is visible when either reaches 3:1 (its boundary is then
seen); a translucent area counts with its colour composited over the background, or through the
edge lines of its colour drawn from the same data (a min–max band's edges).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest
from bokeh.colors import named
from bokeh.models import (
    ColorBar,
    ContourRenderer,
    CustomJS,
    GlyphRenderer,
    Image,
    Legend,
    Span,
)
from bokeh.models.glyphs import HArea, Line, Patch, Patches, VArea
from panel.theme.bootstrap import BootstrapDarkTheme

from windpump_app.explorer import Explorer
from windpump_app.figures import present
from windpump_app.mechanisms import SIX_BAR

APP = Path(__file__).resolve().parents[2] / "app"
MINIMUM = 3.0
AREAS = (VArea, HArea, Patch, Patches)


# -- WCAG 2.x relative luminance and contrast -----------------------------------------------------


def rgba(colour) -> tuple[float, float, float, float]:
    """(r, g, b, a) in 0..1 from '#rgb', '#rrggbb', '#rrggbbaa', a CSS name or an (r, g, b[, a])."""
    if isinstance(colour, tuple | list):
        r, g, b, *a = colour
        return r / 255, g / 255, b / 255, (a[0] if a else 1.0)
    text = str(colour).strip().lower()
    if not text.startswith("#"):
        text = getattr(named, text).to_hex()
    digits = text[1:]
    if len(digits) in (3, 4):
        digits = "".join(c * 2 for c in digits)
    channels = [int(digits[i : i + 2], 16) / 255 for i in range(0, len(digits), 2)]
    return (*channels[:3], channels[3] if len(channels) == 4 else 1.0)  # type: ignore[return-value]


def over(colour, alpha: float, background) -> str:
    """``colour`` at ``alpha`` (times its own) composited over an opaque ``background``, as hex."""
    r, g, b, a = rgba(colour)
    a *= alpha
    mixed = [a * c + (1 - a) * d for c, d in zip((r, g, b), rgba(background)[:3], strict=True)]
    return "#" + "".join(f"{round(255 * c):02x}" for c in mixed)


def luminance(colour) -> float:
    rgb = rgba(colour)
    linear = [c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4 for c in rgb[:3]]
    return 0.2126 * linear[0] + 0.7152 * linear[1] + 0.0722 * linear[2]


def contrast(a, b) -> float:
    la, lb = sorted((luminance(a), luminance(b)), reverse=True)
    return (la + 0.05) / (lb + 0.05)


def test_contrast_is_wcags():
    assert contrast("black", "white") == pytest.approx(21.0)
    assert contrast("#777777", "#ffffff") == pytest.approx(4.48, abs=0.01)
    assert contrast("#2b3035", "#2b3035") == 1.0


# -- reading the figures --------------------------------------------------------------------------


def themed(app: Explorer, dark: bool) -> list:
    """Every figure of the app, its tabs opened and a run pinned, with the page's Bokeh theme."""
    app.main().active = 2  # the Wind tab runs its day once opened
    app.pin()
    app.set_values(h=3.5, cylinders=6, double_acting=True)  # every face's colour drawn
    app.mechanisms.kind.value = SIX_BAR  # every link's colour drawn
    figures = [view.figure for view in app.pump.views]
    wind, design_map, mechanisms = app.wind, app.design_map, app.mechanisms
    figures += [wind.curve, wind.day_wind, wind.day_speed, wind.day_litres]
    design_map.update(app.seen)
    figures += [design_map.figure]
    site = app.site  # its year runs once opened
    figures += [site.monthly, site.level, site.lolp]
    figures += [
        mechanisms.slider_crank.crank_figure,
        mechanisms.slider_crank.travel_figure,
        mechanisms.linkage_figure,
    ]
    if dark:
        theme = BootstrapDarkTheme.bokeh_theme
        for fig in figures:
            for model in fig.references():
                theme.apply_to_model(model)
    return figures


def opaque(colour, alpha) -> bool:
    return colour is not None and colour != "none" and alpha > 0


def values_of(glyph, renderer, name: str) -> list:
    """The values of a glyph's property: its one value, or its data column's values."""
    value = getattr(glyph, name)
    if isinstance(value, dict):
        value = value.get("value", value.get("field"))
    source = getattr(renderer, "data_source", None)
    if isinstance(value, str) and source is not None and value in source.column_names:
        return list(source.data[value])
    return [value]


def paints(glyph, renderer) -> dict[str, list]:
    """{'line'|'fill'|'text': [(colour, alpha), ...]} of what a glyph draws visibly."""
    drawn: dict[str, list] = {}
    for kind in ("line", "fill", "text"):
        if not hasattr(glyph, f"{kind}_color"):
            continue
        if kind == "line" and isinstance(glyph, AREAS):
            continue
        if kind == "line" and not any(w > 0 for w in values_of(glyph, renderer, "line_width")):
            continue
        colours = values_of(glyph, renderer, f"{kind}_color")
        alphas = values_of(glyph, renderer, f"{kind}_alpha")
        if len(alphas) == 1:
            alphas = alphas * len(colours)
        pairs = [(c, a) for c, a in zip(colours, alphas, strict=True) if opaque(c, a)]
        if pairs:
            drawn[kind] = pairs
    return drawn


def edges_of(area_renderer, fig) -> list:
    """Lines drawn from the area's data in its colour (a band's edges)."""
    colour = area_renderer.glyph.fill_color
    return [
        r
        for r in fig.renderers
        if isinstance(r, GlyphRenderer)
        and isinstance(r.glyph, Line)
        and r.data_source is area_renderer.data_source
        and r.glyph.line_color == colour
    ]


def failures_of_renderer(
    renderer, background, where: str, fig, extra_edges=(), in_legend=False
) -> list[str]:
    """What of a renderer falls under 3:1 against ``background``; a legend's swatch of a
    translucent area is outlined only by the lines its item draws with it (``extra_edges``)."""
    glyph, failures = renderer.glyph, []
    drawn = paints(glyph, renderer)
    if isinstance(glyph, AREAS) and "fill" in drawn:
        fills = drawn["fill"]
        seen = all(contrast(over(c, a, background), background) >= MINIMUM for c, a in fills)
        edged = [*extra_edges] if in_legend else edges_of(renderer, fig)
        if not seen and not edged:
            failures.append(f"{where}: translucent area {drawn['fill']} without edges")
        return failures
    worst = {
        kind: min(contrast(over(c, a, background), background) for c, a in pairs)
        for kind, pairs in drawn.items()
    }
    if "text" in worst and worst["text"] < MINIMUM:
        failures.append(f"{where}: text {drawn['text']} at {worst['text']:.2f}:1")
    shape = {k: v for k, v in worst.items() if k != "text"}
    if shape and max(shape.values()) < MINIMUM:
        failures.append(f"{where}: {type(glyph).__name__} {drawn} at {max(shape.values()):.2f}:1")
    return failures


def level_colour(mapper, level: float):
    """The colour the map shows at a value (its log colour mapper)."""
    low, high = math.log(mapper.low), math.log(mapper.high)
    index = int((math.log(level) - low) / (high - low) * len(mapper.palette))
    return mapper.palette[min(max(index, 0), len(mapper.palette) - 1)]


def failures_of(fig) -> list[str]:
    title = fig.title.text or "untitled"
    plot = over(fig.background_fill_color, fig.background_fill_alpha, "white")
    border = over(fig.border_fill_color, fig.border_fill_alpha, "white")
    failures = []

    def need(colour, alpha, background, what):
        seen = over(colour, alpha, background)
        if opaque(colour, alpha) and contrast(seen, background) < MINIMUM:
            failures.append(f"{title}: {what} {colour} on {background}")

    if fig.title.text:
        need(fig.title.text_color, fig.title.text_alpha, border, "title")
    for axis in [*fig.left, *fig.right, *fig.below, *fig.above]:
        if hasattr(axis, "major_label_text_color") and not isinstance(axis, ColorBar | Legend):
            if axis.visible:
                if axis.axis_label:
                    need(axis.axis_label_text_color, axis.axis_label_text_alpha, border, "label")
                need(axis.major_label_text_color, axis.major_label_text_alpha, border, "ticks")
    for bar in fig.select(type=ColorBar):
        behind = over(bar.background_fill_color, bar.background_fill_alpha, border)
        need(bar.major_label_text_color, bar.major_label_text_alpha, behind, "colour bar labels")
        need(bar.title_text_color, bar.title_text_alpha, behind, "colour bar title")
    for legend in fig.select(type=Legend):
        inside = legend in fig.center
        under = plot if inside else border
        behind = over(legend.background_fill_color, legend.background_fill_alpha, under)
        need(legend.label_text_color, legend.label_text_alpha, behind, "legend labels")
        for item in legend.items:
            lines = [r for r in item.renderers if isinstance(r.glyph, Line)]
            for renderer in item.renderers:
                failures += failures_of_renderer(
                    renderer,
                    behind,
                    f"{title}: legend swatch '{item.label.value}'",
                    fig,
                    lines,
                    in_legend=True,
                )
    for span in fig.select(type=Span):
        need(span.line_color, span.line_alpha, plot, "span")
    images = [r for r in fig.renderers if isinstance(getattr(r, "glyph", None), Image)]
    mapper = images[0].glyph.color_mapper if images else None
    for renderer in fig.renderers:
        if not renderer.visible:
            continue
        if isinstance(renderer, ContourRenderer):
            lines = renderer.line_renderer
            colours = values_of(lines.glyph, lines, "line_color")
            alphas = values_of(lines.glyph, lines, "line_alpha")
            for i, level in enumerate(lines.data_source.data["levels"]):
                under = over(level_colour(mapper, level), 1.0, "white")
                colour, alpha = colours[i % len(colours)], alphas[i % len(alphas)]
                need(colour, alpha, under, f"contour {level:g}")
            continue
        if not isinstance(renderer, GlyphRenderer) or isinstance(renderer.glyph, Image):
            continue
        source = renderer.data_source
        if mapper is not None and "level" in source.column_names:  # labels on the map's colours
            for level, colour in zip(source.data["level"], source.data["color"], strict=True):
                under = over(level_colour(mapper, level), 1.0, "white")
                need(colour, renderer.glyph.text_alpha, under, f"contour label {level:g}")
            continue
        failures += failures_of_renderer(
            renderer, plot, f"{title}: {type(renderer.glyph).__name__}", fig
        )
    return failures


@pytest.mark.parametrize("dark", [False, True], ids=["light", "dark"])
def test_every_drawn_element_stands_out_from_its_background(dark):
    app = Explorer(query={"theme": [b"dark"]} if dark else {})
    figures = themed(app, dark)
    background = figures[0].background_fill_color
    assert (luminance(background) < 0.1) == dark  # the theme is the one meant
    failures = [failure for fig in figures for failure in failures_of(fig)]
    assert failures == []


@pytest.mark.parametrize("dark", [False, True], ids=["light", "dark"])
def test_the_machines_player_draws_in_the_themes_colours(dark):
    """player.js draws the moving links: it takes their colours from the view (checked above and
    here), never from colours of its own."""
    code = (APP / "player.js").read_text(encoding="utf-8")
    assert re.findall(r"#[0-9a-fA-F]{3,8}\b|\"(?:black|white|gr[ae]y)\"", code) == []
    app = Explorer(query={"theme": [b"dark"]} if dark else {})
    themed(app, dark)
    fig = app.pump.machine.figure
    plot = fig.background_fill_color
    callback = next(iter(app.pump.machine.button.js_event_callbacks["button_click"]))
    assert isinstance(callback, CustomJS)
    palette = callback.args["palette"]
    assert set(palette) == {"blade", "crank", "rod"}
    for name, colour in palette.items():
        assert contrast(colour, plot) >= MINIMUM, name
    sprocket = next(r.glyph.fill_color for r in fig.renderers if type(r.glyph).__name__ == "Circle")
    for part in ("crank", "rod"):  # each drawn over the crank's sprocket
        assert contrast(palette[part], sprocket) >= MINIMUM, part


def test_the_dotted_alpha_plus_line_is_visible():
    for dark in (False, True):
        app = Explorer(query={"theme": [b"dark"]} if dark else {})
        figures = themed(app, dark)
        plot = figures[0].background_fill_color
        line = app.pump.speed.items["α₊, Eq. (21)"].renderers[0].glyph
        dash = list(line.line_dash)  # Bokeh's "dotted": [2, 4], on and off [px]
        assert len(dash) == 2 and dash[0] / sum(dash) >= 1 / 3  # dots, not a faint scatter
        assert line.line_width >= 2
        assert contrast(line.line_color, plot) >= MINIMUM


def test_the_check_sees_a_faint_line():
    """The check itself: a light grey line on white, or black on the dark theme, fails it."""
    from bokeh.plotting import figure

    fig = figure(title="probe")
    fig.line([0, 1], [0, 1], color="#cccccc", line_width=2)
    assert len(failures_of(fig)) == 1
    fig = figure(title="probe", background_fill_color="#2b3035", border_fill_color="#212529")
    fig.scatter([0], [0], color="black")
    fig.title.text_color = "#e0e0e0"
    for axis in (*fig.xaxis, *fig.yaxis):
        axis.major_label_text_color = "#e0e0e0"
    assert len(failures_of(fig)) == 1


@pytest.mark.parametrize("dark", [False, True], ids=["light", "dark"])
def test_the_design_maps_star_reads_in_its_legend(dark):
    """Bokeh draws a legend's marker at 0.4 of its swatch's box whatever its size on the plot: the
    map's star in its legend is at least 12 px across, its outline thin beside it (so its fill is
    seen, not a black blot) and standing out from the legend's background by 3:1; presentation
    mode makes it larger, never smaller."""
    app = Explorer(query={"theme": [b"dark"]} if dark else {})
    themed(app, dark)
    fig = app.design_map.figure
    (legend,) = fig.select(type=Legend)
    border = over(fig.border_fill_color, fig.border_fill_alpha, "white")
    behind = over(legend.background_fill_color, legend.background_fill_alpha, border)
    sizes = []
    for large in (False, True, False):
        present(fig, large)
        sizes.append(0.4 * min(legend.glyph_width, legend.glyph_height))  # Bokeh's MarkerView's
    size = sizes[0]
    assert size >= 12 and sizes[1] > size and sizes[2] == size
    item = next(i for i in legend.items if i.label.value == "this design")
    (star,) = [r.glyph for r in item.renderers]
    assert star.marker == "star"
    assert star.line_width <= 0.1 * size
    assert contrast(star.line_color, behind) >= MINIMUM
    assert contrast(star.fill_color, behind) >= MINIMUM or not dark  # the light theme's: outlined
