"""The pump's views on the first tab: the crank speed, the machine playing the run, the flow,
the close-up, the energy, the stall and the operating point, built once the page has loaded."""

from __future__ import annotations

import panel as pn
from bokeh.models import ColumnDataSource, Range1d

import windpump

from .machine import MachineView
from .sidebar import closed_card
from .styles import TEXT
from .views import CloseupView, EnergyView, FlowView, OperatingView, SpeedView, StallView

VIEW_FLEX = {"flex": "1 1 460px", "min-width": "300px"}  # two or more columns from ~1600 px
VIEW_FLEX_ROW = {"gap": "8px"}
PRESENTATION_GROWTH = 1.3  # the height of a view below the first screen in presentation mode
NAMED = ("speed", "flow", "energy", "closeup", "stall", "operating", "machine")


class PumpViews:
    """The views (``views``, none until ``build()``), their data ``sources`` and the ``results``
    box that holds them on the page."""

    def __init__(self, dark: bool, bins: int | None):
        self.dark = dark
        self.bins = bins  # None: every sample of every trace (the benchmark's baseline)
        self.views: list = []
        self.sources: dict[str, ColumnDataSource] = {}
        self._drawn_linkage: tuple | None = None
        self.results = pn.FlexBox(
            pn.pane.Markdown("Drawing the plots and the machine…", stylesheets=TEXT),
            flex_wrap="wrap",
            sizing_mode="stretch_width",
            styles=VIEW_FLEX_ROW,
        )

    def build(self) -> None:
        self.time_range = Range1d(0.0, 600.0, name="speed_range")
        self.cursor = ColumnDataSource({"t": [0.0]}, name="cursor")
        dark = self.dark  # each view draws in its theme's colours
        self.speed = SpeedView(self.time_range, self.cursor, dark)
        self.flow = FlowView(self.time_range, self.cursor, dark)
        self.energy = EnergyView(dark)
        self.closeup = CloseupView(dark)
        self.stall = StallView(dark)
        self.operating = OperatingView(dark)
        self.machine = MachineView(self.cursor, dark)
        # The crank speed and the machine playing it first: side by side in a projector's first screen.
        self.views = [
            self.speed,
            self.machine,
            self.flow,
            self.closeup,
            self.energy,
            self.stall,
            self.operating,
        ]
        self.sources.update(cursor=self.cursor)
        self.base_heights = {view: view.figure.height for view in self.views}
        for view in self.views:
            self.sources.update(view.sources)
        name_sources(self.sources)
        for name in NAMED:
            getattr(self, name).figure.name = f"{name}_figure"
        self.results.objects = self._panels()

    def _panels(self) -> list:
        panels = [view.panel(styles=VIEW_FLEX) for view in self.views]
        # After the views, across the page: beside the machine it made the first row of views
        # taller than its neighbours, and a band of blank space under them.
        about = closed_card(
            "What is this machine?",
            lambda: [pn.pane.Markdown(ABOUT, stylesheets=TEXT, sizing_mode="stretch_width")],
        )
        return [*panels, about]

    def plot(self, seen: windpump.Exploration, t_end: float) -> None:
        """Draw ``seen`` in every view (``t_end`` [s]: the time axis of a run of no length)."""
        if not self.views:  # not on the page yet: show_views() draws the latest run
            return
        run = seen.run
        span = float(run.t[-1]) if run.t[-1] > 0 else float(t_end)
        self.time_range.update(start=0.0, end=span)
        if self._drawn_linkage != _linkage_of(
            seen.design
        ):  # R, L, A, the sprockets or the cylinders changed
            self._drawn_linkage = _linkage_of(seen.design)
            self.machine.set_design(seen.design)
        for view in self.views:
            view.update(seen, self.bins)

    def restyle(self, large: bool) -> None:
        """Larger text leaves a plot less room: the views below the first screen grow with it
        (the crank speed and the machine keep a projector's first screen)."""
        for view in self.views:
            if view not in (self.speed, self.machine):
                growth = PRESENTATION_GROWTH if large else 1
                view.figure.height = round(self.base_heights[view] * growth)

    def pin(self) -> None:
        """Keep the current traces as a faint ghost to compare the next change with."""
        self.speed.pin()
        self.flow.pin()

    def clear(self) -> None:
        if self.views:
            self.speed.clear()
            self.flow.clear()

    def mark_stale(self, styles: dict) -> None:
        self.results.styles = {**VIEW_FLEX_ROW, **styles}


def name_sources(sources: dict[str, ColumnDataSource]) -> None:
    for name, source in sources.items():
        source.name = name  # so a browser can find it: Bokeh.documents[0].get_model_by_name


def _linkage_of(design: windpump.Design) -> tuple[float, ...]:
    """What the machine's fixed drawing depends on."""
    return (
        design.R,
        design.L,
        design.A,
        design.R0,
        design.R1,
        design.cylinders,
        design.L_main,  # the rising main and the leak hole are drawn, and labelled
        design.D_main,
        design.d_leak,
        design.double_acting,
    )


ABOUT = """
A windmill turns a small sprocket of radius R₀; a chain drives a large sprocket of radius R₁ on the
crankshaft, so the windmill turns R† = R₁/R₀ times faster than the crank (Eq. 4). A crank of radius R
and a rod of length L drive a single-acting piston of cross-section A: while it moves up it lifts the
water above it by a head h (the *exhaust* half of a revolution); while it moves down it takes water in.

The windmill's torque T = Tₘ x(2 − x), x = ω/ωₘ (Eq. 11), is zero at rest and at 2ωₘ: the pump must
be *kicked* into motion. It then spins up over a time constant τ (Eq. 25) to a steady speed α₊
(Eq. 21), pulsing once per revolution, unless the load is more than the windmill can carry: the
stall criterion, Eq. (22). Press ▶ Play to watch the computed run; the time cursor on the plots
follows it, and the scrubber moves through it. The model is M. Louge, *A simple wind-pump analysis*, Cornell University (2010).
"""
