"""The page's tabs: what every tab beside the pump's has in common (one contract for the page to
build and feed it), and the tab strip that opens each when it is first chosen."""

from __future__ import annotations

import logging
from collections.abc import Callable
from functools import partial

import panel as pn

import windpump

from .escape import as_text
from .keyboard import TAB_FOCUS_CSS
from .styles import TEXT, px

log = logging.getLogger("windpump.app")

# A tab's content arrives after its header is chosen (the Wind tab's after its day has run): its
# file input gets the page's size check (uploads.js) as soon as it is drawn.
GUARD_NEW_UPLOADS_JS = """
for (const delay of [300, 1000, 2500, 5000, 10000, 20000]) {
  setTimeout(() => window.__windpumpGuardAll && window.__windpumpGuardAll(), delay)
}
"""

TABS_CSS = [
    f":host {{ font-size: {px(16)}; }}",
    f".bk-tab {{ font-size: {px(16)}; }}",
    # five headers fit a phone's width (390 px)
    "@media (max-width: 500px) { .bk-tab { font-size: 14px; padding: 8px 4px !important; } }",
    TAB_FOCUS_CSS,
    # Panel keeps a hidden tab's content laid out (visibility: hidden), so the page
    # was as tall as the longest tab: a short tab scrolled into blank space.
    ':host > [aria-hidden="true"] { max-height: 0; overflow: hidden; }',
]


class Tab(pn.viewable.Viewer):
    """A tab of the page, built when it is first viewed (most pages never open it: its figures
    would cost every page) and from then on following every exploration while it is shown; a
    built tab hidden behind another (``hide``) draws the latest one when shown again.

    A subclass says what it builds (``build``), how it draws an exploration (``draw``), where it
    says that drawing failed (``failed``), its figures and its layout. The page calls
    ``open()`` when the tab is chosen, ``update(seen)`` after every run, and shows ``__panel__``.
    """

    title = ""  # the tab's header
    waiting = ""  # what the tab shows until it is first viewed

    def __init__(self, dark: bool = False, **params):
        super().__init__(**params)
        self.dark = dark
        self.built = False
        self.seen: windpump.Exploration | None = None  # the latest exploration
        self.hidden = False  # another tab is shown (``hide``): explorations wait to be drawn
        self.behind = False  # hidden, it holds an earlier exploration than ``seen``
        self._layout: pn.viewable.Viewable | None = None

    def open(self) -> Tab:
        """Build the tab (once) and draw the latest exploration in it."""
        if not self.built:
            self.build()
            self.built = True
            self.redraw()
        return self

    def update(self, seen: windpump.Exploration) -> None:
        """A new exploration: drawn at once if the tab is built and shown, else when it is next
        shown (``hide(False)``) or first opened."""
        self.seen = seen
        if self.built and self.hidden:
            self.behind = True
        elif self.built:
            self.redraw()

    def hide(self, hidden: bool) -> None:
        """Another tab is shown (``hidden``), or this one again: drawn then if an exploration
        came meanwhile. A hidden tab is still laid out by the browser (Panel's ``Tabs``), so a
        preset chosen with every tab built had all of them run and redraw a day, a year and a
        map nobody saw: ~4-6 s of the browser's CPU a choice, on top of the server's."""
        self.hidden = hidden
        if not hidden:
            self.catch_up()

    def catch_up(self) -> None:
        """Draw the latest exploration if the tab, hidden, was left behind it."""
        if self.behind:
            self.behind = False
            self.redraw()

    def redraw(self) -> None:
        """Draw the latest exploration again; a failure is said in the tab, the page goes on."""
        if self.seen is None:
            return
        try:
            with pn.io.hold():
                self.draw(self.seen)
        except Exception as error:  # a bug: say so, log it, keep the session alive
            log.exception("%s update failed", self.title)
            self.failed(f"Something went wrong ({type(error).__name__}: {as_text(error)}).")

    def when_ready(self, place: Callable[[], None]) -> None:
        """``place()`` puts the tab's content in the page: here at once; a tab whose first
        drawing runs off the loop may hold it until that is done (``SiteTab``), so that the
        browser lays the content out once, with its numbers."""
        place()

    def build(self) -> None:
        raise NotImplementedError

    def draw(self, seen: windpump.Exploration) -> None:
        raise NotImplementedError

    def failed(self, message: str) -> None:
        raise NotImplementedError

    def figures(self) -> list:
        """The tab's Bokeh figures (presentation mode restyles them)."""
        return []

    def layout(self) -> pn.viewable.Viewable:
        raise NotImplementedError

    def __panel__(self) -> pn.viewable.Viewable:
        if self._layout is None:
            self._layout = self.open().layout()
        return self._layout


class PageTabs:
    """The page's tab strip: the pump's tab first, then ``tabs``, each built and placed when first
    chosen (``open(tab)`` builds it; the page's own way, for what it adds)."""

    def __init__(self, tabs: list[Tab], open: Callable[[Tab], Tab]):
        self.tabs = tabs
        self.open = open

    def strip(self, first: pn.viewable.Viewable) -> pn.Tabs:
        waiting = [
            (tab.title, pn.pane.Markdown(tab.waiting, stylesheets=TEXT)) for tab in self.tabs
        ]
        strip = pn.Tabs(
            ("Wind pump", first),
            *waiting,
            dynamic=False,
            sizing_mode="stretch_width",
            stylesheets=TABS_CSS,
        )
        placed: set[int] = set()
        self.shown(strip.active)

        def place(index: int) -> None:
            tab = self.open(self.tabs[index - 1])  # data first: a figure sent empty warns
            tab.when_ready(lambda: strip.__setitem__(index, (tab.title, tab)))

        def chosen(event) -> None:
            self.shown(event.new)
            if event.new >= 1 and event.new not in placed:
                placed.add(event.new)
                later(partial(place, event.new))

        strip.param.watch(chosen, "active")
        strip.jscallback(active=GUARD_NEW_UPLOADS_JS)
        return strip

    def shown(self, index: int) -> None:
        """The strip shows its tab ``index`` (0: the pump's): every other tab is hidden."""
        for number, tab in enumerate(self.tabs, start=1):
            tab.hide(number != index)

    def update(self, seen: windpump.Exploration) -> None:
        for tab in self.tabs:
            tab.update(seen)

    def figures(self) -> list:
        """The figures of the tabs built so far."""
        return [figure for tab in self.tabs if tab.built for figure in tab.figures()]


def later(build: Callable[[], None]) -> None:
    """``build`` on a served page's next tick, after this change's other watchers have sent what
    they change (the link's ``tab=``: a tab's day or year takes seconds to run, and a link copied
    meanwhile named the tab before); at once in-process (a notebook, the tests)."""
    document = pn.state.curdoc
    if document is None or document.session_context is None:
        build()
        return

    def held() -> None:
        with pn.io.hold():
            build()

    document.add_next_tick_callback(held)
