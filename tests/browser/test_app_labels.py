"""What the figures say: no label reads as code, and every legend's labels fit its figure."""

from __future__ import annotations

import math

from bokeh.models import Axis, ColorBar, Legend

import windpump
from windpump_app.explorer import Explorer


def every_figure(app: Explorer) -> list:
    app.main().active = 2  # the Wind tab runs its day once opened
    wind, design_map, mechanisms, site = app.wind, app.design_map, app.mechanisms, app.site
    design_map.update(app.seen)
    return [
        site.monthly,
        site.level,
        site.lolp,
        *(view.figure for view in app.pump.views),
        wind.curve,
        wind.day_wind,
        wind.day_speed,
        wind.day_litres,
        design_map.figure,
        mechanisms.slider_crank.crank_figure,
        mechanisms.slider_crank.travel_figure,
        mechanisms.linkage_figure,
    ]


def texts(fig) -> list[str]:
    """A figure's title, axis labels, colour bar titles and legend labels."""
    found = [fig.title.text]
    found += [axis.axis_label or "" for axis in fig.select(type=Axis)]
    found += [bar.title or "" for bar in fig.select(type=ColorBar)]
    found += [item.label.value for legend in fig.select(type=Legend) for item in legend.items]
    return found


def test_no_label_shows_a_caret():
    """Powers of ten are written as superscripts (× 10⁻⁴), never as code (× 10^-4)."""
    app = Explorer()
    for design in ({"h": 3.0}, {"h": 30.0, "T_m": 0.05}, {"T_m": 5.0, "h": 0.5}):
        app.set_values(**design)
        figures = every_figure(app)
        labels = [text for fig in figures for text in texts(fig)]
        assert len(labels) > 40
        assert [label for label in labels if "^" in label] == []
    power = math.floor(math.log10(max(windpump.stall_sides(app.inputs.design()))))
    written = "".join(dict(zip("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹", strict=True))[c] for c in str(power))
    assert app.pump.stall.figure.xaxis[0].axis_label.endswith(f"×10{written}]")


def test_the_theme_button_offers_the_other_theme():
    assert Explorer(query={"theme": [b"dark"]}).sidebar.dark_toggle.label == "Light theme"
    assert Explorer().sidebar.dark_toggle.label == "Dark theme"


def dejavu(size: float, bold: bool = False):
    """DejaVu Sans, the page's font on Debian, at ``size`` px (a test skips without it)."""
    import subprocess

    import pytest
    from PIL import ImageFont

    name = "DejaVu Sans:bold" if bold else "DejaVu Sans"
    found = subprocess.run(["fc-match", "-f", "%{file}", name], capture_output=True, text=True)
    if "DejaVuSans" not in found.stdout:
        pytest.skip("no DejaVu Sans")
    return ImageFont.truetype(found.stdout, size)


def test_every_sidebar_slider_keeps_its_value_on_its_titles_line():
    """At 1280 x 720 a slider's title and value, "Rod and piston mass mᵣ [kg]: 50.0" at its
    widest, stay on one line: 15 px, the value bold, in the 294 px of a slider's title in the
    sidebar and 284 px in a card (chromium's layout of a 330 px sidebar); the main sliders' in
    presentation mode too."""
    from windpump_app.inputs import FORMATS, PumpInputs
    from windpump_app.styles import PRESENTATION_ZOOM

    inputs = PumpInputs()
    too_long = {}
    # presentation mode: the text a quarter larger in the same sidebar (a wider one pushed the
    # machine under the crank speed at 1280 px); the main sliders' titles still fit, the cards'
    # may wrap (tests/browser/test_layout.py)
    for zoom, places in ((1.0, ("main", "more", "real")), (PRESENTATION_ZOOM, ("main",))):
        font, bold = dejavu(15 * zoom), dejavu(15 * zoom, bold=True)
        for name, (fmt, place) in FORMATS.items():
            if place not in places:
                continue
            decimals = len(fmt.split(".")[1]) if "." in fmt else 0
            widest = f"{inputs.param[name].bounds[1]:.{decimals}f}"
            width = font.getlength(f"{inputs.param[name].label}: ") + bold.getlength(widest)
            if width > (294 if place == "main" else 284):
                too_long[name, zoom] = width
    assert too_long == {}


def test_a_legends_items_stand_apart():
    """Bokeh's 3 px between a legend's items put a swatch against the label before it
    ("(12)▬▬ averaged"): every legend leaves at least 10 px between its columns (a CSS grid's
    column-gap, its rows as close as they were)."""
    import re

    figures = every_figure(Explorer())
    legends = [legend for fig in figures for legend in fig.select(type=Legend)]
    assert len(legends) >= 8
    for legend in legends:
        css = " ".join(str(sheet) for sheet in legend.stylesheets)
        gap = re.search(r"\.bk-grid \{ column-gap: (\d+)px !important; \}", css)
        assert gap and int(gap.group(1)) >= 10, css
