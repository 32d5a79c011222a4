"""The machine, animated: rotor, chain, sprockets, crank, rod, piston and the water it delivers.

Drawn to the design's proportions (the rotor's blades excepted: they would dwarf the pump). The
server sends the run's frames once per run (``windpump.playback_frames``: angles, volume, tank
level) with every crank pin and piston over a revolution (``windpump.crank_table``); ``player.js``
interpolates in them and draws, in the browser.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import panel as pn
from bokeh.layouts import column, row
from bokeh.models import (
    Button,
    ColumnDataSource,
    CustomJS,
    InlineStyleSheet,
    Range1d,
    Select,
    Slider,
)
from bokeh.plotting import figure

import windpump
from windpump.units import LITRES_PER_M3, MM_PER_M

from .figures import LABEL, empty, palette
from .keyboard import FOCUS_CSS, LABEL_FOR_SCREEN_READERS_CSS
from .styles import px
from .views import View, refill

PLAYER_JS = (Path(__file__).parent / "player.js").read_text(encoding="utf-8")
MAX_FRAMES = 3000  # ~84 kB a run: 7 float32 columns
FRAME_COLUMNS = ("t", "theta", "theta_dot", "rotor_angle", "rotor_speed", "tank_level")
SPEEDS = [
    ("0.1", "0.1× slow motion"),
    ("0.25", "0.25×"),
    ("1", "1× real time"),
    ("5", "5×"),
    ("20", "20× fast"),
]
ASPECT = (
    1.9  # the drawing's width / height: wide, so the drawing and its controls fit beside a plot
)
WIDGET_CSS = f":host {{ font-size: {px(15)}; }} .bk-btn, select {{ font-size: {px(15)}; }}"
# Bokeh's primary button is white on #428bca, 3.6:1 (WCAG AA asks 4.5:1 of its 15 px label): the
# Play button is white on the page's blue, darker when pressed (6.3:1 and more, in both themes).
PRIMARY_BUTTON_CSS = (
    ":host { --primary: #2a6496; --primary-border: #245580; --primary-hover: #1f5580; "
    "--primary-hover-border: #1b4a70; --primary-active: #1b4a70; --primary-active-border: #163d5c; }"
)
# The share of the drawing's width right of the cylinders when it has a rising main: its label,
# "rising main / 30 m × 25 mm", ~130 px in presentation mode, fits there on a phone's ~370 px.
MAIN_LABEL_ROOM = 0.4
# Three blades and the sprocket's mark, then each cylinder's crank and rod (the player draws
# as many as the design has cylinders, in the colours it is given: ``moving_colors``).
MOVING = ("blade", "crank", "rod")


def moving_colors(dark: bool = False) -> dict[str, str]:
    """The theme's colours of what the player moves: blades, cranks and rods."""
    return {part: palette(dark)[part] for part in MOVING}


def fit_aspect(left, right, bottom, top, aspect):
    """The smallest box of width / height ``aspect`` around a drawing, centred on it."""
    width, height = right - left, top - bottom
    if width < aspect * height:
        grow = (aspect * height - width) / 2
        left, right = left - grow, right + grow
    else:
        grow = (width / aspect - height) / 2
        bottom, top = bottom - grow, top + grow
    return left, right, bottom, top


def crank_columns(table: windpump.CrankTable) -> dict:
    """The table's columns as the player reads them: ``theta``, then cylinder k's ``pin_xk``,
    ``pin_yk`` and ``piston_yk``; and ``x``, the first piston's travel (Eq. 1)."""
    columns = {"theta": table.theta, "x": table.piston[0]}
    for k in range(len(table.piston)):
        for name in ("pin_x", "pin_y", "piston_y"):
            columns[f"{name}{k}"] = getattr(table, name)[k]
    return columns


def tangents(c0, r0, c1, r1):
    """The two outer tangent segments of two circles: the chain's straight runs."""
    (x0, y0), (x1, y1) = c0, c1
    d = math.hypot(x1 - x0, y1 - y0)
    base = math.atan2(y1 - y0, x1 - x0)
    spread = math.acos((r0 - r1) / d)
    segments = []
    for sign in (1, -1):
        a = base + sign * spread
        segments.append(
            (
                [x0 + r0 * math.cos(a), x1 + r1 * math.cos(a)],
                [y0 + r0 * math.sin(a), y1 + r1 * math.sin(a)],
            )
        )
    return segments


class MachineView(View):
    caption = (
        "The machine playing the computed run: the windmill turns R₁/R₀ times faster than the "
        "crank (Eq. 4); each piston follows Eq. (1), cylinder k 2πk/n behind the first; the tank "
        "fills with the volume pumped (Eq. 16). Blades not to scale."
    )

    def __init__(self, cursor: ColumnDataSource, dark: bool = False):
        super().__init__(dark)
        s = self.sources
        moving = moving_colors(dark)
        link_colors = [moving["blade"]] * 4 + [moving["crank"], moving["rod"]]
        s["frames"] = empty(*FRAME_COLUMNS, "litres")
        s["piston_table"] = empty("theta", "x")  # and each cylinder's parts: crank_columns
        s["machine_geometry"] = ColumnDataSource({})
        s["machine_static"] = empty("xs", "ys")
        s["machine_circles"] = empty("x", "y", "radius")
        s["machine_links"] = ColumnDataSource(
            {"xs": [[]] * len(link_colors), "ys": [[]] * len(link_colors), "color": link_colors}
        )
        s["machine_joints"] = empty("x", "y")
        s["machine_piston"] = empty("x", "y", "width", "height")
        s["machine_water"] = empty("x", "y", "width", "height")
        s["machine_label"] = ColumnDataSource({"x": [0.0], "y": [0.0], "text": [""]})
        s["machine_main"] = empty("xs", "ys")  # the rising main, when the design has one
        s["machine_notes"] = empty("x", "y", "text", "align")  # the main's and the hole's size
        # Ranges set from the design (set_design) to the figure's own aspect, with no border: equal
        # scales on both axes whatever width the page gives it.
        self.figure = fig = figure(
            width=640,
            height=int(640 / ASPECT),
            sizing_mode="scale_width",
            max_width=900,
            tools="save",
            toolbar_location=None,
            x_range=Range1d(0.0, 1.0),
            y_range=Range1d(0.0, 1.0),
            min_border=0,
        )
        self._draw_machine(fig)
        self._controls(cursor)

    def _draw_machine(self, fig) -> None:
        """The machine's glyphs, drawn from the sources ``set_design`` and the player fill."""
        s, c = self.sources, self.colors
        fig.axis.visible = False
        fig.grid.visible = False
        fig.outline_line_color = None
        fig.multi_line("xs", "ys", source=s["machine_static"], color=c["structure"], line_width=3)
        fig.circle(
            "x",
            "y",
            radius="radius",
            source=s["machine_circles"],
            fill_color=c["sprocket"],
            line_color=c["structure"],
            line_width=2,
        )
        fig.rect(
            "x",
            "y",
            "width",
            "height",
            source=s["machine_water"],
            fill_color=c["flow"],
            line_color=None,
        )
        fig.multi_line(
            "xs", "ys", source=s["machine_links"], color="color", line_width=6, alpha=0.9
        )
        fig.rect(
            "x",
            "y",
            "width",
            "height",
            source=s["machine_piston"],
            fill_color=c["piston"],
            line_color=c["ink"],
            line_width=2,
        )
        fig.scatter(
            "x",
            "y",
            source=s["machine_joints"],
            size=10,
            fill_color=c["joint"],
            line_color=c["ink"],
            line_width=2,
        )
        fig.multi_line("xs", "ys", source=s["machine_main"], color=c["flow"], line_width=7)
        fig.text(
            "x", "y", "text", source=s["machine_notes"], text_font_size=LABEL,
            text_baseline="middle", text_align="align", text_color=c["ink"],
        )  # fmt: skip
        fig.text(
            "x",
            "y",
            "text",
            source=s["machine_label"],
            text_font_size=LABEL,
            text_baseline="top",
            text_color=c["ink"],
        )

    def _controls(self, cursor) -> None:
        s = self.sources
        # A model: one per document, never shared.
        css = InlineStyleSheet(
            css=f"{WIDGET_CSS} {FOCUS_CSS} {PRIMARY_BUTTON_CSS} {LABEL_FOR_SCREEN_READERS_CSS}"
        )
        self.button = Button(
            label="▶ Play", button_type="primary", width=120, stylesheets=[css], name="play"
        )
        # wide enough for "0.1× slow motion" whole in presentation mode's text (cut at 170 px);
        # its options say what it sets, its title says it to a screen reader
        self.speed = Select(
            value="1",
            options=SPEEDS,
            width=210,
            stylesheets=[css],
            name="playback_speed",
            title="Playback speed",
        )
        self.scrubber = Slider(
            start=0.0,
            end=1.0,
            value=0.0,
            step=0.01,
            title="time t [s]",
            sizing_mode="stretch_width",
            stylesheets=[css],
            name="scrubber",
        )
        args = dict(
            frames=s["frames"],
            table=s["piston_table"],
            geometry=s["machine_geometry"],
            links=s["machine_links"],
            joints=s["machine_joints"],
            piston=s["machine_piston"],
            water=s["machine_water"],
            label=s["machine_label"],
            cursor=cursor,
            palette=moving_colors(self.dark),
            scrubber=self.scrubber,
            button=self.button,
            speed_select=self.speed,
            plot=self.figure,
        )
        callback = CustomJS(args=args, code=PLAYER_JS)
        self.button.js_on_event("button_click", callback)
        self.scrubber.js_on_change("value", callback)
        s["frames"].js_on_change("data", callback)
        self.figure.js_on_change("inner_width", callback)
        # The scrubber under the drawing takes the whole width (~1 s a pixel for a 600 s run).
        self.layout = column(
            self.figure,
            self.scrubber,
            row(self.button, self.speed),
            sizing_mode="stretch_width",
        )

    def drawing(self) -> pn.pane.Bokeh:
        """The drawing with its scrubber and Play button under it."""
        return pn.pane.Bokeh(self.layout, sizing_mode="stretch_width")

    def set_design(self, d: windpump.Design) -> None:
        """The drawing's fixed parts, for a new design (nothing is sent when they are unchanged)."""
        refill(self.sources["piston_table"], crank_columns(windpump.crank_table(d)))
        blade = d.L + d.R
        c0 = (-(d.R1 + 1.15 * blade), 0.55 * blade)
        # Cylinder k stands pitch * k to the right, on its own throw of the one crankshaft.
        pitch = max(2.6 * d.R, 1.6 * d.bore)
        last = pitch * (d.cylinders - 1)
        tank_w = tank_h = 0.45 * d.L
        tank_x, tank_y = last + 1.5 * d.bore + 0.2 * d.L, d.L + d.R + 1.2 * d.bore
        top = d.L + d.R + d.bore  # the cylinders' heads
        walls = [
            ([x + side * d.bore / 2] * 2, [d.L - d.R - 0.3 * d.bore, top])
            for x in np.arange(d.cylinders) * pitch
            for side in (-1, 1)
        ]
        static = [
            *tangents(c0, d.R0, (0.0, 0.0), d.R1),  # chain
            *walls,
            ([-d.bore / 2, last + d.bore / 2], [top, top]),  # heads, and the manifold above them
            ([0.0, last], [top + 0.6 * d.bore] * 2),
            *[([x, x], [top, top + 0.6 * d.bore]) for x in np.arange(d.cylinders) * pitch],
            (
                [last, tank_x + 0.3 * tank_w, tank_x + 0.3 * tank_w],
                [top + 0.6 * d.bore, top + 0.6 * d.bore, tank_y + tank_h],
            ),  # riser
            (
                [tank_x, tank_x, tank_x + tank_w, tank_x + tank_w],
                [tank_y + tank_h, tank_y, tank_y, tank_y + tank_h],
            ),  # tank
            ([0.0, last], [0.0, 0.0]),  # the crankshaft (a point for one cylinder)
        ]
        refill(
            self.sources["machine_static"],
            {"xs": [a for a, _ in static], "ys": [b for _, b in static]},
        )
        riser = static[-3]
        refill(
            self.sources["machine_circles"],
            {"x": [c0[0], 0.0], "y": [c0[1], 0.0], "radius": [d.R0, d.R1]},
        )
        self.geometry = dict(
            R0=d.R0,
            bore=d.bore,
            blade=blade,
            c0x=c0[0],
            c0y=c0[1],
            tank_x=tank_x,
            tank_y=tank_y,
            tank_w=tank_w,
            tank_h=tank_h,
            cylinders=d.cylinders,
            pitch=pitch,
        )
        self._frame(d)
        self._real_parts(d, riser, (-d.bore / 2, 0.5 * (d.L - d.R + top)))

    def _real_parts(self, d: windpump.Design, riser, cylinder_side) -> None:
        """The real machine's rising main (over the riser, drawn when L_main > 0, labelled with
        its length and bore) and its leak hole's size beside the first cylinder. The main's label
        ends at the frame's right edge (``_frame`` first): it extends leftwards from there, never
        out of the figure, however narrow the figure or large its text (presentation mode)."""
        main = d.L_main > 0.0
        refill(
            self.sources["machine_main"],
            {"xs": [riser[0]] if main else [], "ys": [riser[1]] if main else []},
        )
        notes = {"x": [], "y": [], "text": [], "align": []}
        if main:
            x_range = self.figure.x_range  # under the pipe, right of the cylinders
            notes["x"].append(x_range.end - 0.02 * (x_range.end - x_range.start))
            notes["y"].append(riser[1][0] - 1.7 * d.bore)
            notes["text"].append(f"rising main\n{d.L_main:g} m × {d.D_main * MM_PER_M:g} mm")
            notes["align"].append("right")
        if d.d_leak > 0.0:
            notes["x"].append(cylinder_side[0] - 0.3 * d.bore)
            notes["y"].append(cylinder_side[1])
            notes["text"].append(f"leak hole\n{d.d_leak * MM_PER_M:g} mm")
            notes["align"].append("right")
        refill(self.sources["machine_notes"], notes)

    def _frame(self, d: windpump.Design) -> None:
        """The figure's ranges around the whole machine, at the figure's aspect."""
        g = self.geometry
        blade, c0y = g["blade"], g["c0y"]
        left, right = g["c0x"] - blade * 1.05, g["tank_x"] + g["tank_w"] + 0.1 * blade
        if d.L_main > 0.0:  # room right of the cylinders for the main's label (_real_parts)
            wall = g["pitch"] * (d.cylinders - 1) + d.bore / 2
            right = max(right, (wall - MAIN_LABEL_ROOM * left) / (1.0 - MAIN_LABEL_ROOM))
        bottom, high = (
            min(-d.R1, c0y - blade) - 0.05 * blade,
            max(c0y + blade, g["tank_y"] + g["tank_h"]) + 0.4 * blade,  # room for the label
        )
        left, right, bottom, high = fit_aspect(left, right, bottom, high, ASPECT)
        self.figure.x_range.update(start=left, end=right)
        self.figure.y_range.update(start=bottom, end=high)
        self.label_at = (left, high)

    def update(self, seen, bins) -> None:
        """A new run: its frames (the tank full at the run's volume). The player stops."""
        run = seen.run
        frames = windpump.playback_frames(run, max_frames=MAX_FRAMES)
        self.sources["machine_geometry"].data = {k: [float(v)] for k, v in self.geometry.items()}
        self.sources["machine_label"].data = {
            "x": [self.label_at[0]],
            "y": [self.label_at[1]],
            "text": [""],
        }
        self.scrubber.update(end=max(float(run.t[-1]), 1e-6), value=0.0)
        self.sources["frames"].data = {
            name: np.asarray(getattr(frames, name), dtype=np.float32) for name in FRAME_COLUMNS
        } | {"litres": np.asarray(LITRES_PER_M3 * frames.volume, dtype=np.float32)}
