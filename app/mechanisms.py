"""The mechanisms tab: the pump's slider-crank at a dragged crank angle, and a four-bar / Watt six-bar
explorer, both drawn from windpump.linkage's Newton-Raphson solutions. The core decides every
position (assembly on a branch, branch following, the coupler's path, Grashof's class); this
module only draws them."""

from __future__ import annotations

import math
import re

import numpy as np
import panel as pn
from bokeh.models import CustomJS

import windpump
from windpump import linkage
from windpump.linkage import NoClosure
from windpump.units import MM_PER_M

from .figures import LINKS, MECHANISM_SIZE, linkage_view, show_box, slider_crank_views
from .styles import TEXT
from .tab import Tab

LINKED = ("r1", "r2", "r3", "r4", "r5")  # the links drawn in a colour of their own
FOUR_BAR = "Four-bar"
SIX_BAR = "Watt six-bar (double loop)"
# name: (label, start, end, step, value); lengths [m], angles [°]
FIRST_LOOP = {
    "r1": ("Input link r₁ [m]", 0.2, 5.0, 0.05, 1.0),
    "r2": ("Coupler r₂ [m]", 0.2, 5.0, 0.05, 3.0),
    "r3": ("Output link r₃ [m]", 0.2, 5.0, 0.05, 2.5),
    "r6": ("Ground r₆ [m]", 0.2, 5.0, 0.05, 3.0),
}
SECOND_LOOP = {
    "r3p": ("Second arm of link 3, r₃′ [m]", 0.2, 5.0, 0.05, 1.5),
    "r4": ("Coupler r₄ [m]", 0.2, 5.0, 0.05, 2.5),
    "r5": ("Output link r₅ [m]", 0.2, 5.0, 0.05, 2.0),
    "r6p": ("Ground D→E, r₆′ [m]", 0.2, 5.0, 0.05, 2.5),
    "beta": ("Angle between link 3's arms β [°]", -180.0, 180.0, 1.0, 25.0),
}
BRANCHES = {"+1: B left of A→D": 1, "−1: B right of A→D": -1}
NOTE_CSS = TEXT[:1]
# [px] a part's (the slider-crank's, the linkage's) flex basis: two figures of 320 px or more side
# by side, and the two parts beside each other only where both get that (a pane of ~1,590 px at
# 1920×1080; at 1366×768 its ~1,000 px hold one)
PART_BASIS = 700
LINKAGE_MAX_WIDTH = 920  # [px] the linkage's drawing, under its controls: its part's width
# Where the two parts stand side by side (1920×1080), each figure takes the screen's height below
# its top (a bottom margin of FILL_MARGIN px), MECHANISM_SIZE px at least and twice that at most:
# at 440 px the tab left ~30 % of the screen blank below them. One above the other (1366 px and
# narrower, a phone) the page scrolls anyway: they keep MECHANISM_SIZE. The drawings keep equal
# scales in any frame (figures.show_box).
FILL_MARGIN = 24
FILL_TAG = "fills_the_height"  # the figures' tag: the slider-crank's, its travel's, the linkage's
FILL_HEIGHT_JS = """
// after the layout pass that called it (a new height set within it left the legend's swatches
// blank, "Eq. (1)" with no line, until the next paint)
setTimeout(() => {
  // found by their tag (FILL_TAG), in the order the tag gives them
  const tagged = [...cb_obj.document.all_models].filter(m => (m.tags ?? []).some(t => t?.[tag] != null))
  const figures = tagged.sort((a, b) => a.tags.find(t => t?.[tag] != null)[tag] - b.tags.find(t => t?.[tag] != null)[tag])
  if (figures.length !== 3) return
  const views = figures.map(f => window.Bokeh?.index?.find_one?.(f))
  if (views.some(v => v == null)) return
  const boxes = views.map(v => v.el.getBoundingClientRect())
  if (boxes.some(b => b.width === 0)) return  // a hidden tab: laid out when shown
  const beside = boxes[2].top < boxes[0].bottom  // the linkage's part beside the slider-crank's
  const pane = document.querySelector('#main')
  const scrolled = pane != null ? pane.scrollTop : 0
  figures.forEach((fig, i) => {
    const room = window.innerHeight - margin - (boxes[i].top + scrolled)
    const want = beside ? Math.round(Math.min(2 * least, Math.max(least, room))) : least
    if (Math.abs(fig.height - want) > 1) fig.setv({height: want}, {sync: false})
  })
}, 0)
"""
SUBSCRIPT = str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉")  # θ₂, as the sliders write θ₁


def degrees(angle: float) -> str:
    return f"{round(math.degrees(angle), 1) + 0.0:.1f}°"  # + 0.0: never "-0.0°"


def vertical(points: np.ndarray) -> np.ndarray:
    """Turn the slider-crank's drawing a quarter turn, so the cylinder stands up like a pump's."""
    return np.column_stack([-points[:, 1], points[:, 0]])


def segments(points, pairs, colors) -> dict:
    return {
        "xs": [[points[a][0], points[b][0]] for a, b in pairs],
        "ys": [[points[a][1], points[b][1]] for a, b in pairs],
        "color": colors,
    }


def xy(points) -> dict:
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    return {"x": points[:, 0], "y": points[:, 1]}


class SliderCrank:
    """The pump's slider-crank at a dragged crank angle; ``set_design`` follows the pump's sliders."""

    def __init__(self, slider, dark: bool = False):
        self.link_colors = dict(zip(LINKED, LINKS[dark], strict=True))
        self.crank_angle = slider("Crank angle θ [°]", 0.0, 360.0, 1.0, 90.0, "0")
        self.crank_note = pn.pane.HTML("", stylesheets=NOTE_CSS)
        self.crank_figure, self.travel_figure, self.sources = slider_crank_views(dark)
        self.design: windpump.Design | None = None

    def set_design(self, design: windpump.Design) -> None:
        self.design = design
        theta = np.linspace(0.0, 2 * math.pi, 181)
        self.sources["travel"].data = {
            "angle": np.degrees(theta),
            "x": MM_PER_M * windpump.piston_position(theta, design.R, design.L),
        }
        span = design.L + 4 * design.R  # the crank's circle, the rod and the cylinder above
        show_box(self.crank_figure, -span / 2, span / 2, -1.6 * design.R, span - 1.6 * design.R)
        self.draw()

    def draw(self) -> None:
        d, theta = self.design, math.radians(self.crank_angle.value)
        pose = linkage.slider_crank_pose(theta, d.R, d.L)
        x, theta_c = pose.x, pose.theta_c
        centre, pin, piston = vertical(pose.joints)
        bore = d.bore
        s = self.sources
        s["crank_links"].data = segments(
            [centre, pin, piston],
            [(0, 1), (1, 2)],
            [self.link_colors["r1"], self.link_colors["r2"]],
        )
        s["crank_joints"].data = xy([pin, piston])
        s["crank_pivots"].data = xy([centre])
        circle = np.linspace(0.0, 2 * math.pi, 73)
        s["crank_path"].data = {"x": d.R * np.cos(circle), "y": d.R * np.sin(circle)}
        s["piston"].data = {
            "x": [piston[0]],
            "y": [piston[1]],
            "width": [bore],
            "height": [0.8 * bore],
        }
        bottom, top = d.L - d.R - 0.4 * bore, d.L + d.R + 1.2 * bore
        s["cylinder"].data = {"xs": [[-bore / 2] * 2, [bore / 2] * 2], "ys": [[bottom, top]] * 2}
        s["travel_point"].data = {"angle": [self.crank_angle.value], "x": [MM_PER_M * x]}
        stroke = (
            "exhausting (lifting water)"
            if windpump.f2(theta, d.L_over_R) > 0
            else "taking water in"
        )
        self.crank_note.object = (
            f'<span data-name="slider_crank">x = {MM_PER_M * x:.2f} mm from TDC, '
            f"θc = {degrees(theta_c)}</span> · {stroke} · Newton-Raphson: "
            f"{pose.closure.iterations} iterations"
        )


class Mechanisms(Tab):
    """The Mechanisms tab: the pump's slider-crank (``slider_crank``), following the pump's
    design, and a four-bar / Watt six-bar explorer of its own."""

    title, waiting = "Mechanisms", "Loading the mechanisms…"

    def __init__(self, slider, dark: bool = False):
        super().__init__(dark)
        self.slider = slider  # makes a slider: (label, start, end, step, value, format)
        self.drawn_linkage: tuple | None = None  # the pump's links the slider-crank shows

    def build(self) -> None:
        slider, dark = self.slider, self.dark
        self.slider_crank = SliderCrank(slider, dark)
        self.link_colors = self.slider_crank.link_colors
        self.kind = pn.widgets.RadioButtonGroup(
            options=[FOUR_BAR, SIX_BAR], value=FOUR_BAR, stylesheets=TEXT
        )
        self.links = {name: slider(*spec, "0.00") for name, spec in FIRST_LOOP.items()}
        self.links.update({name: slider(*spec, "0.00") for name, spec in SECOND_LOOP.items()})
        self.links["beta"].format = "0"
        self.input_angle = slider("Input angle θ₁ [°]", -360.0, 360.0, 1.0, 60.0, "0")
        self.branch = pn.widgets.RadioButtonGroup(options=BRANCHES, value=1, stylesheets=TEXT)
        self.second_branch = pn.widgets.RadioButtonGroup(
            options={"loop 2: +1": 1, "loop 2: −1": -1}, value=1, stylesheets=TEXT
        )
        # The second loop's controls, shown for the Watt six-bar: in two halves, one under each
        # column of the first loop's (``layout``)
        self.second_loop = pn.Column(
            *(self.links[name] for name in ("r3p", "r4", "r5")),
            visible=False,
            sizing_mode="stretch_width",
        )
        self.second_loop_rest = pn.Column(
            *(self.links[name] for name in SECOND_LOOP if name not in ("r3p", "r4", "r5")),
            self.second_branch,
            visible=False,
            sizing_mode="stretch_width",
        )
        self.linkage_note = pn.pane.HTML("", stylesheets=NOTE_CSS)
        self.linkage_error = pn.pane.Alert(
            "", alert_type="warning", visible=False, stylesheets=NOTE_CSS
        )
        self.linkage_figure, linkage_sources = linkage_view(dark)
        self.linkage_figure.name = "linkage_figure"  # a browser test finds it by name
        self.linkage_figure.max_width = LINKAGE_MAX_WIDTH  # under its controls: its part's width
        self.sources = {**self.slider_crank.sources, **linkage_sources}

        self.position: dict | None = None  # the linkage's last closed position (rad, m)
        self._quiet = False  # True while reset() sets many controls: one redraw at the end
        crank_angle = self.slider_crank.crank_angle
        crank_angle.param.watch(lambda _e: self._quiet or self.slider_crank.draw(), "value")
        self.input_angle.param.watch(lambda _e: self._quiet or self.follow(), "value")
        for widget in (self.kind, self.branch, self.second_branch, *self.links.values()):
            widget.param.watch(lambda _e: self._quiet or self.assemble(), "value")
        self.assemble()

    def draw(self, seen: windpump.Exploration) -> None:
        """The pump's slider-crank, redrawn when its links (R, L, A, R₀, R₁) moved."""
        d = seen.design
        if self.drawn_linkage != (d.R, d.L, d.A, d.R0, d.R1):
            self.drawn_linkage = (d.R, d.L, d.A, d.R0, d.R1)
            self.slider_crank.set_design(d)

    def failed(self, message: str) -> None:
        self.slider_crank.crank_note.object = message

    # -- the four-bar / Watt six-bar explorer ------------------------------------------------

    def loops(self) -> list:
        v = {name: widget.value for name, widget in self.links.items()}
        if self.kind.value == FOUR_BAR:
            return [linkage.four_bar_loop(v["r1"], v["r2"], v["r3"], v["r6"])]
        return linkage.watt_six_bar_loops(
            *(v[name] for name in ("r1", "r2", "r3", "r6", "r3p", "r4", "r5", "r6p")),
            beta=math.radians(v["beta"]),
        )

    def assemble(self) -> None:
        """New links or branch: close the loops from the compass construction on that branch."""
        self.second_loop.visible = self.second_loop_rest.visible = self.kind.value == SIX_BAR
        theta1 = math.radians(self.input_angle.value)
        loops = self.loops()
        branches = (self.branch.value, self.second_branch.value)[: len(loops)]
        try:
            closures = linkage.assemble(loops, {"theta1": theta1}, branches)
        except NoClosure as error:
            self.position = None
            self._cannot_close(error, theta1)
            return
        self.position = closures[-1].values
        self._trace_path()
        self._draw_linkage(closures)

    def follow(self) -> None:
        """A dragged input: follow the branch from the last position, step by step."""
        if self.position is None:  # the links did not close last time: start afresh
            self.assemble()
            return
        target = math.radians(self.input_angle.value)
        moved = linkage.follow_branch(self.loops(), self.position, target)
        self.position = moved.closures[-1].values
        self._draw_linkage(moved.closures)
        if moved.stop is not None:
            self._cannot_close(moved.stop, target, ends=self.position["theta1"])

    def _trace_path(self) -> None:
        """The path of the traced joint over the branch's reach: all the way round, or to its ends."""
        self.sources["linkage_path"].data = xy(linkage.coupler_path(self.loops(), self.position))

    def _draw_linkage(self, closures) -> None:
        loops, values = self.loops(), closures[-1].values
        p = linkage.mechanism_joints(loops, values)
        bars = [("O", "A", "r1"), ("A", "B", "r2"), ("B", "D", "r3")]
        if len(loops) > 1:
            bars += [("D", "C", "r3"), ("C", "F", "r4"), ("F", "E", "r5")]
        s = self.sources
        s["linkage_links"].data = segments(
            p, [(a, b) for a, b, _ in bars], [self.link_colors[link] for *_, link in bars]
        )
        s["linkage_pivots"].data = xy([p[name] for name in "ODE" if name in p])
        s["linkage_joints"].data = xy([p[name] for name in "ABCF" if name in p])
        self._frame(list(p.values()))
        self.linkage_error.visible = False
        self.linkage_note.object = self._describe(closures)

    def _frame(self, points) -> None:
        """Equal, steady scales: a square around every pivot with room for the longest reach."""
        v = {name: widget.value for name, widget in self.links.items()}
        reach = max(v["r1"], v["r2"] + v["r3"]) + (
            v["r3p"] + v["r4"] if self.kind.value == SIX_BAR else 0.0
        )
        centre = np.mean(points, axis=0)
        x, y = centre
        show_box(self.linkage_figure, x - reach, x + reach, y - reach, y + reach)

    def _describe(self, closures) -> str:
        values = closures[-1].values
        names = ["theta2", "theta3"] + (["theta4", "theta5"] if len(closures) > 1 else [])
        angles = ", ".join(
            f"θ{name[-1].translate(SUBSCRIPT)} = {degrees(values[name] % (2 * math.pi))}"
            for name in names
        )
        branch = linkage.four_bar_branch(values["theta2"], values["theta3"])
        v = [self.links[name].value for name in FIRST_LOOP]
        turns = linkage.input_turns_fully(*v)
        histories = " · ".join(
            "|F|: " + " → ".join(f"{r:.0e}" for r in closure.residuals) for closure in closures
        )
        return (
            f'<span data-name="linkage">θ₁ = {degrees(values["theta1"])}: {angles}</span><br>'
            f"Branch {branch:+d} ({'B left' if branch > 0 else 'B right'} of the line A→D) · "
            f"{'Grashof: the input turns fully' if turns else 'the input rocks between limits'}<br>"
            f"Newton-Raphson: {sum(c.iterations for c in closures)} iterations, {histories}"
        )

    def _cannot_close(self, error: NoClosure, theta1: float, ends: float | None = None) -> None:
        at = error.where.get("theta1", theta1)
        where = (
            f" The branch ends between θ₁ = {degrees(ends)} and {degrees(at)}: drawn at its end."
            if ends is not None
            else " The drawing stays at the last position that closed."
        )
        detail = str(error).split(": ", 1)[-1]  # the core's why, in the labels the student sees
        labels = {
            name: spec[0].split(" [")[0] for name, spec in {**FIRST_LOOP, **SECOND_LOOP}.items()
        }
        why = re.sub(r"\b(r\d+p?|beta) = ", lambda m: f"{labels.get(m[1], m[1])} = ", detail)
        self.linkage_error.object = f"**Cannot close at θ₁ = {degrees(at)}**: {why}.{where}"
        self.linkage_error.visible = True
        if ends is None:
            self.linkage_note.object = ""

    def reset(self) -> None:
        """Every control of the tab back to its default."""
        self._quiet = True
        try:
            self.slider_crank.crank_angle.value = 90.0
            self.input_angle.value = 60.0
            self.kind.value = FOUR_BAR
            self.branch.value = self.second_branch.value = 1
            for name, spec in {**FIRST_LOOP, **SECOND_LOOP}.items():
                self.links[name].value = spec[-1]
        finally:
            self._quiet = False
        self.assemble()
        if self.slider_crank.design is not None:
            self.slider_crank.draw()

    # -- layout ------------------------------------------------------------------------------

    def figures(self) -> list:
        crank = self.slider_crank
        return [crank.crank_figure, crank.travel_figure, self.linkage_figure]

    def fill_the_height(self) -> None:
        """The figures as high as the screen has room for where the parts stand side by side
        (``FILL_HEIGHT_JS``), whenever the page lays them out."""
        figures = self.figures()
        fill = CustomJS(
            args=dict(least=MECHANISM_SIZE, margin=FILL_MARGIN, tag=FILL_TAG),
            code=FILL_HEIGHT_JS,
        )
        for order, fig in enumerate(figures):
            fig.tags = [*fig.tags, {FILL_TAG: order}]
            fig.js_on_change("outer_width", fill)

    def layout(self) -> pn.Column:
        """The slider-crank and the linkage, each a part with its figures side by side; the two
        parts side by side where both fit (1920 px: one part left ~40 % of the screen blank),
        else one above the other (1366 px and narrower)."""
        crank = self.slider_crank
        self.fill_the_height()
        figure = dict(sizing_mode="stretch_width", max_width=460, min_width=300)
        flex = {"flex": "1 1 320px"}
        part = dict(styles={"flex": f"1 1 {PART_BASIS}px"}, sizing_mode="stretch_width")
        # A Bokeh pane puts its figure itself in the flex box (a pane's styles reach nothing): the
        # figure's own flex lets the two share a part's width (at their 440 px they wrapped).
        for fig in (crank.crank_figure, crank.travel_figure):
            fig.styles = flex
        slider_crank = pn.Column(
            pn.pane.Markdown(
                "### The pump's slider-crank, closed as a vector loop", stylesheets=NOTE_CSS
            ),
            crank.crank_angle,
            crank.crank_note,
            pn.FlexBox(
                pn.pane.Bokeh(crank.crank_figure, **figure),
                pn.pane.Bokeh(crank.travel_figure, **figure),
                sizing_mode="stretch_width",
            ),
            **part,
        )
        linkages = pn.Column(
            pn.pane.Markdown(
                "### Four-bar and double loop, by Newton-Raphson", stylesheets=NOTE_CSS
            ),
            self.kind,
            # The controls above the drawing, in columns side by side where they fit: beside it,
            # at 1920×1080, they left a block ~270 × 420 px blank under them, the drawing
            # taking the screen's height.
            pn.FlexBox(
                pn.Column(
                    self.input_angle,
                    self.links["r1"],
                    self.links["r2"],
                    self.second_loop,
                    styles=flex,
                    sizing_mode="stretch_width",
                ),
                pn.Column(
                    *(self.links[name] for name in ("r3", "r6")),
                    self.branch,
                    self.second_loop_rest,
                    styles=flex,
                    sizing_mode="stretch_width",
                ),
                sizing_mode="stretch_width",
            ),
            self.linkage_error,
            self.linkage_note,
            pn.pane.Bokeh(self.linkage_figure, **{**figure, "max_width": LINKAGE_MAX_WIDTH}),
            **part,
        )
        return pn.Column(
            pn.FlexBox(slider_crank, linkages, gap="0 24px", sizing_mode="stretch_width"),
            sizing_mode="stretch_width",
        )
