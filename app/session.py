"""One page's state: its inputs, the exploration they gave, and whether the page shows an earlier
one (``stale``: the last input was refused)."""

from __future__ import annotations

import logging
import re
import threading
import weakref
from typing import Protocol

import panel as pn
import param

import windpump

from .compiling import COMPILE, REAL_MACHINE, WHEEL
from .escape import as_text
from .inputs import FORMATS, SEED, PumpInputs, link_text
from .server import api as serving
from .styles import TEXT

log = logging.getLogger("windpump.app")


class Screen(Protocol):
    """What a session draws on: the page (``explorer.Explorer``)."""

    def _draw(self, seen: windpump.Exploration) -> None:
        """Show ``seen``."""

    def _mark_stale(self, stale: bool) -> None:
        """Show that the screen holds an earlier run than the inputs (or no longer)."""

    def _followed(self, seen: windpump.Exploration) -> None:
        """``seen`` is on the screen: what follows it (the tabs) may follow too."""

    def _working(self, working: bool) -> None:
        """Say that a move's run is taking long (``working``), or no longer."""


class Session(param.Parameterized):
    """The inputs → exploration half of a page, drawn on its ``screen`` (the page,
    ``explorer.Explorer``, holds one): a move's whole path, from an input changed to its run drawn
    or refused, reads here (``move``, ``update``).

    >>> from windpump_app.session import Session
    >>> class Blank:  # a screen that draws nothing
    ...     def _draw(self, seen): self.drawn = seen
    ...     def _mark_stale(self, stale): pass
    ...     def _followed(self, seen): pass
    ...     def _working(self, working): pass
    >>> session = Session(screen=Blank())
    >>> session.inputs.h = 5.0
    >>> session.move()  # not served: run at once
    >>> session.screen.drawn.design.h, session.stale
    (5.0, False)
    """

    inputs = param.ClassSelector(class_=PumpInputs)
    stale = param.Boolean(
        False, doc="The plots show an earlier design: the last input was rejected."
    )

    def __init__(self, screen: Screen, **params):
        super().__init__(inputs=PumpInputs(), **params)
        self.screen = screen  # what it draws on; read at each call (a test may replace its methods)
        self.seen: windpump.Exploration | None = None  # the run on the screen
        self._asked = 0  # moves asked for (``move``)
        self._running = False  # a move's run is under way off the event loop
        self._runs = 0  # moves' runs started
        self._working_shown = False  # the page says it is working (``screen._working``)
        self.error = pn.pane.Alert(
            "", alert_type="danger", visible=False, stylesheets=TEXT, sizing_mode="stretch_width"
        )

    # -- the one path from inputs to screen --------------------------------------------------

    def move(self) -> None:
        """An input changed: run the core on the inputs and redraw (``update``).

        Served, the run goes off the event loop (``serving.MOVE_RUNS``; the kernels release the
        GIL), so the loop answers other pages meanwhile and 30 moves at once use both cores;
        its readouts are drawn on the loop, under the page's lock. One run of a page at a time,
        in order: a move made while one runs waits, and only the latest waiting runs, so the
        page ends on its latest inputs and never shows an older run after a newer. A run still
        under way after ``WORKING_AFTER`` says so on the page (``_working``). Not served (a
        notebook, the tests): at once.
        """
        document = serving.served_document()
        if document is None:
            self.update()
            return
        self._asked += 1
        if not self._running:
            self._run_latest(document)

    def _run_latest(self, document) -> None:
        asked, self._running = self._asked, True
        self._runs += 1
        i = self.inputs
        try:
            run = (i.design(), i.t_end, i.theta0, i.theta_dot0)
        except Exception as error:  # refused on reading the inputs: said at once
            self._ran(document, asked, error)
            return
        serving.MOVE_RUNS.submit(
            document,
            lambda: ready(shared_explore(*run)),
            lambda seen: self._ran(document, asked, seen),
        )
        number = self._runs
        document.add_timeout_callback(lambda: self._still_running(number), WORKING_AFTER)

    def _ran(self, document, asked: int, outcome) -> None:
        """The run of move ``asked`` is back (an Exploration or the exception it raised), on the
        loop: drawn if no move was made since, else the latest move runs."""
        self._running = False
        if asked != self._asked:  # superseded: its inputs are no longer the page's
            self._run_latest(document)
            return
        if self._working_shown:
            self._working_shown = False
            self.screen._working(False)
        self.update(outcome)

    def _still_running(self, number: int) -> None:
        """``WORKING_AFTER`` after run ``number`` started: say so if it is still under way."""
        if self._running and self._runs == number and not self._working_shown:
            self._working_shown = True
            self.screen._working(True)

    def update(self, seen: windpump.Exploration | Exception | None = None) -> None:
        """Run the core on the current inputs (``seen``: that run, done already, or the exception
        it raised) and redraw; a rejected input shows its message."""
        try:
            seen = self.explore() if seen is None else seen
            if isinstance(seen, Exception):
                raise seen
            with pn.io.hold():
                self.screen._draw(seen)
        except ValueError as error:  # the core's verdict on an input: say so, mark the plots stale
            self.show_error(f"{self.culprit(error)}cannot be run: {page_symbols(str(error))}")
        except Exception as error:  # a bug: say so, log it, keep the session alive
            log.exception("update failed")
            self.show_error(
                f"Something went wrong ({type(error).__name__}: {error}); it has been logged."
            )
        else:
            self.seen = seen
            self.error.visible = False
            self.stale = False
            self.screen._mark_stale(False)
            self.screen._followed(seen)

    def show_error(self, message: str) -> None:
        """Say ``message`` above the plots, and mark what they show as not current."""
        self.error.object = message
        self.error.visible = True
        if self.seen is None:  # nothing drawn yet (a link's design was rejected): show the paper's
            self.seen = shared_explore(SEED, 600.0)  # example behind it, marked not current
            with pn.io.hold():
                self.screen._draw(self.seen)
        self.stale = True
        self.screen._mark_stale(True)

    def explore(self) -> windpump.Exploration:
        i = self.inputs
        return shared_explore(i.design(), i.t_end, i.theta0, i.theta_dot0)

    def run_link(self, values: dict, notices: list[str]) -> windpump.Exploration | None:
        """The run of the link's values. A value the core refuses with the others (``T_0=0.9``
        with the default T_m = 0.6) is ignored with the core's reason, as a value refused on
        reading is, and the page opens on the rest. None: nothing ran (update() says why)."""
        values = dict(values)
        while True:
            try:
                return self.explore()
            except ValueError as error:
                name = input_name(error)
                if name not in values:
                    return None
                label = self.inputs.param[name].label
                notices.append(
                    f"{label} ({name}) = “{link_text(name, values.pop(name))}” ignored: "
                    f"{sentence(error)}"
                )
                setattr(self.inputs, name, self.inputs.param[name].default)
            except Exception:  # a bug: update() shows and logs it
                return None

    def culprit(self, error: ValueError) -> str:
        """The control behind a rejected parameter, as the student sees it: "L/R, rod / crank = 1 "."""
        name = input_name(error)
        if name in FORMATS:
            return f"{self.inputs.param[name].label} = {getattr(self.inputs, name):g} "
        return "This design "


# [ms] a move's run under way this long says so on its page (``Session.move``): a run of the
# paper's example takes 2-4 ms, its readouts are back in ~60 ms while a class moves at its own pace
WORKING_AFTER = 400


def ready(seen: windpump.Exploration) -> windpump.Exploration:
    """``seen`` with what its readouts compute once (its energy balance) computed, off the loop."""
    _ = seen.energy_totals
    return seen


# The runs pages hold, by what they ran: a page asking a run another page holds (a class opening the
# default page asks the same one thirty times) gets that one, computed once and kept once (~2.8 MB
# for the paper's example) instead of once a page; the run goes with the last page holding it.
SHARED_RUNS: weakref.WeakValueDictionary = weakref.WeakValueDictionary()


def shared_explore(design: windpump.Design, t_end: float, *start: float) -> windpump.Exploration:
    """``windpump.explore(design, t_end, *start)`` (``start``: θ₀ [rad], θ̇₀ [rad/s]), shared with
    every page holding the same run (the core's results are frozen: no page changes what another
    draws)."""
    key = (design, float(t_end), *map(float, start))
    with SHARING:
        seen = SHARED_RUNS.get(key)
    if seen is None:
        serving.mark("run: worked out")
        if not design.is_ideal:  # a first start compiles it in a worker: not a second time here
            COMPILE.wait(REAL_MACHINE)
        if design.rotor is not None:  # a wheel's runs: likewise
            COMPILE.wait(WHEEL)
        seen = windpump.explore(design, t_end, *start)
        serving.mark("run: done")
        with SHARING:
            seen = SHARED_RUNS.setdefault(key, seen)
    else:
        serving.mark("run: shared")
    return seen


SHARING = threading.Lock()  # the moves' runs share SHARED_RUNS from their threads


def input_name(error: Exception) -> str | None:
    """The input behind a parameter the core refused (the core names R1 and L, the page R† and
    L/R)."""
    name = getattr(error, "name", None)
    return CORE_TO_INPUT.get(name, name)


# The core's field -> the input that sets it, where the page shows another quantity (a ratio, mm).
CORE_TO_INPUT = {"L": "L_over_R", "R1": "R_dagger", "D_main": "D_main_mm", "d_leak": "d_leak_mm"}


def sentence(error: Exception) -> str:
    """The error's message as a sentence, in the page's symbols (``page_symbols``): capitalised,
    unless it starts with a parameter's name (``d_leak = ...`` stays as the core spells it), and
    ending in a full stop; shown as text (``escape.as_text``: a message may echo a link's value
    or a file's line)."""
    text = str(error)
    name = getattr(error, "name", None)
    if not (name and text.startswith(f"{name} ")):
        text = text[0].upper() + text[1:]
    return as_text(page_symbols(text + ("" if text.endswith(".") else ".")))


# The core's plain-text names of the quantities the page writes with its symbols (its labels: "Torque
# at rest T₀ [N·m]"), and its unit N m, which the page writes N·m.
PAGE_SYMBOLS = {"T_0": "T₀", "T_m": "Tₘ", "omega_m": "ωₘ", "eta_t": "ηₜ", "m_r": "mᵣ"}
CORE_SYMBOL = re.compile(rf"\b({'|'.join(PAGE_SYMBOLS)})\b")


def page_symbols(text: str) -> str:
    """The core's message ``text`` in the page's symbols and units.

    >>> page_symbols("T_0 = 0.9 N m is not allowed: T_0 must be < T_m = 0.6 N m")
    'T₀ = 0.9 N·m is not allowed: T₀ must be < Tₘ = 0.6 N·m'
    """
    text = CORE_SYMBOL.sub(lambda found: PAGE_SYMBOLS[found.group()], text)
    return re.sub(r"(\d) N m\b", "\\1 N·m", text)
