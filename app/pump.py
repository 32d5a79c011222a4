"""The pump's views on the first tab: the crank speed, the machine playing the run, the flow,
the close-up, the energy, the stall and the operating point, each built when the page first shows
it (``viewport``): until then a placeholder of its height stands in its place."""

from __future__ import annotations

from collections.abc import Callable, Iterable

import panel as pn
from bokeh.models import ColumnDataSource, Range1d

import windpump

from .figures import lean, present
from .machine import ASPECT, MachineView
from .sidebar import closed_card
from .styles import TEXT
from .viewport import ViewsSeen, placeholder, placeholder_html
from .views import (
    CloseupView,
    EnergyView,
    FlowView,
    OperatingView,
    SpeedView,
    StallView,
    TimeView,
    View,
)

VIEW_FLEX = {"flex": "1 1 460px", "min-width": "300px"}  # two or more columns from ~1600 px
VIEW_FLEX_ROW = {"gap": "8px"}
PRESENTATION_GROWTH = 1.3  # the height of a view below the first screen in presentation mode
# In the page's order: the crank speed and the machine playing it first, side by side in a
# projector's first screen.
ORDER = ("speed", "machine", "flow", "closeup", "energy", "stall", "operating")
FIRST_SCREEN = ("speed", "machine")  # keep their height in presentation mode
MACHINE_CONTROLS = 93  # [px] the scrubber and the Play button under the machine's drawing
KINDS: dict[str, type[View]] = {
    "speed": SpeedView,
    "machine": MachineView,
    "flow": FlowView,
    "closeup": CloseupView,
    "energy": EnergyView,
    "stall": StallView,
    "operating": OperatingView,
}
TITLES = {
    "speed": "the crank speed",
    "machine": "the machine",
    "flow": "the flow rate",
    "closeup": "the close-up",
    "energy": "where the work goes",
    "stall": "the stall criterion",
    "operating": "the operating point",
}


class PumpViews:
    """The views built so far (``built``, by name; ``views`` in the page's order), their data
    ``sources`` and the ``results`` box that holds them, or their placeholders, on the page.

    What a view draws when it is built later is kept here: the run drawn (``drawn``), the pinned
    run (``pinned``), the lab points (``lab``) and presentation mode (``large``).
    """

    def __init__(self, dark: bool, bins: int | None):
        self.dark = dark
        self.bins = bins  # None: every sample of every trace (the benchmark's baseline)
        self.built: dict[str, View] = {}
        self.time_range = Range1d(0.0, 600.0, name="speed_range")  # shared by the time views
        self.cursor = ColumnDataSource({"t": [0.0]}, name="cursor")  # the player's time
        self.sources: dict[str, ColumnDataSource] = {"cursor": self.cursor}
        self.drawn: tuple[windpump.Exploration, float] | None = None  # (seen, t_end)
        self.pinned: windpump.Exploration | None = None
        self.lab: tuple = ([], [])  # the lab points' speeds [rad/s] and powers [W]
        self.large = False
        self._drawn_linkage: tuple | None = None
        self.channel = ViewsSeen()  # the page writes the views it has seen here
        self.slots: dict[str, pn.viewable.Viewable] = {name: self._slot(name) for name in ORDER}
        self.about: pn.Card | None = None  # with the first view built
        self.results = pn.FlexBox(
            *self.slots.values(),
            flex_wrap="wrap",
            sizing_mode="stretch_width",
            styles=VIEW_FLEX_ROW,
        )

    def _slot(self, name: str) -> pn.pane.HTML:
        """A view's place on the page until it is built: a placeholder of its height, with its
        caption under it."""
        return placeholder(name, self._placeholder_html(name), styles=VIEW_FLEX)

    def _placeholder_html(self, name: str) -> str:
        kind = KINDS[name]
        if name == "machine":
            return placeholder_html(TITLES[name], kind.caption, MACHINE_CONTROLS, aspect=ASPECT)
        return placeholder_html(TITLES[name], kind.caption, self._height(name, kind.height))

    def _height(self, name: str, base: int) -> int:
        """A view's height [px]: ``base``, larger below the first screen in presentation mode
        (larger text leaves a plot less room)."""
        grows = self.large and name not in FIRST_SCREEN
        return round(base * PRESENTATION_GROWTH) if grows else base

    @property
    def views(self) -> list[View]:
        """The views built so far, in the page's order."""
        return [self.built[name] for name in ORDER if name in self.built]

    def __getattr__(self, name: str) -> View:
        """A built view by its name: ``pump.speed``."""
        built = self.__dict__.get("built", {})
        if name in built:
            return built[name]
        raise AttributeError(f"no {name!r} view built")

    def build(self, names: Iterable[str]) -> list[str]:
        """Build the views ``names`` not built yet, each drawing what it would have drawn had it
        been built with the page, and put them on the page in their placeholders' place."""
        new = [name for name in ORDER if name in set(names) and name not in self.built]
        for name in new:
            view = self._make(name)
            lean(view.figure)
            view.figure.name = f"{name}_figure"
            self.built[name] = view
            self.sources.update(view.sources)
        name_sources(self.sources)
        for name in new:
            view = self.built[name]
            view.base_height = view.figure.height
            self._restyle_view(name, view)
            self._draw_new(name, view)
            self.slots[name] = pn.Column(
                view.drawing(),
                view.caption_panel(),
                sizing_mode="stretch_width",
                styles=VIEW_FLEX,
            )
        # One change of the box, not one per view: Panel walks the page's models for each change
        # (a page scrolled to its end cost 0.83 s of CPU with one per view, 0.58 s with one).
        # The page holds the box at its height meanwhile (viewport.js): it does not scroll up.
        if new:
            self.results.objects = [*self.slots.values(), self._about()]
        return new

    def _about(self) -> pn.Card:
        """After the views, across the page: beside the machine it made the first row of views
        taller than its neighbours, and a band of blank space under them."""
        if self.about is None:
            self.about = closed_card(
                "What is this machine?",
                lambda: [pn.pane.Markdown(ABOUT, stylesheets=TEXT, sizing_mode="stretch_width")],
            )
        return self.about

    def _make(self, name: str) -> View:
        makers: dict[str, Callable[[], View]] = {
            "speed": lambda: SpeedView(self.time_range, self.cursor, self.dark),
            "flow": lambda: FlowView(self.time_range, self.cursor, self.dark),
            "machine": lambda: MachineView(self.cursor, self.dark),
        }
        return makers.get(name, lambda: KINDS[name](self.dark))()  # type: ignore[call-arg]

    def _draw_new(self, name: str, view: View) -> None:
        """A view built after the page: the pinned run's ghost, the lab points, the run drawn."""
        if isinstance(view, TimeView) and self.pinned is not None:
            view.pin_run(self.pinned, self.bins)
        if isinstance(view, OperatingView):
            view.show_lab_data(*self.lab)
        if self.drawn is None:
            return
        seen, _t_end = self.drawn
        if isinstance(view, MachineView):
            self._drawn_linkage = _linkage_of(seen.design)
            view.set_design(seen.design)
        view.update(seen, self.bins)

    def plot(self, seen: windpump.Exploration, t_end: float) -> None:
        """Draw ``seen`` in every view built (``t_end`` [s]: the time axis of a run of no
        length); a view built later draws it then."""
        self.drawn = (seen, t_end)
        run = seen.run
        span = float(run.t[-1]) if run.t[-1] > 0 else float(t_end)
        self.time_range.update(start=0.0, end=span)
        machine = self.built.get("machine")
        # R, L, A, the sprockets or the cylinders changed
        if isinstance(machine, MachineView) and self._drawn_linkage != _linkage_of(seen.design):
            self._drawn_linkage = _linkage_of(seen.design)
            machine.set_design(seen.design)
        for view in self.views:
            view.update(seen, self.bins)

    def restyle(self, large: bool) -> None:
        """Presentation mode on (``large``) or off, in the views built and those to come: their
        canvas text and lines, and the height of those below the first screen (the crank speed
        and the machine keep a projector's first screen), placeholders included."""
        self.large = large
        for name, view in self.built.items():
            self._restyle_view(name, view)
        for name, slot in self.slots.items():
            if name not in self.built and name != "machine":
                slot.object = self._placeholder_html(name)

    def _restyle_view(self, name: str, view: View) -> None:
        present(view.figure, self.large)
        if name not in FIRST_SCREEN:
            view.figure.height = self._height(name, view.base_height)

    def pin(self) -> None:
        """Keep the run drawn as a faint ghost to compare the next change with, in the time
        views built and those to come."""
        self.pinned = self.drawn[0] if self.drawn is not None else None
        for view in self.views:
            if isinstance(view, TimeView):
                view.pin()

    def clear(self) -> None:
        self.pinned = None
        for view in self.views:
            if isinstance(view, TimeView):
                view.clear()

    def show_lab_data(self, omega, power) -> None:
        """Measured speeds [rad/s] and shaft powers [W] on the operating point's view, now or
        once it is built."""
        self.lab = (omega, power)
        operating = self.built.get("operating")
        if isinstance(operating, OperatingView):
            operating.show_lab_data(omega, power)

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
