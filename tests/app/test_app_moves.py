"""A served page's moves: each run off the event loop, one at a time, in order, the latest winning
(app/session.py: ``Session.move``, the session an ``Explorer`` holds), with the loop
answering other pages meanwhile.

In-process: the page believes it is served (``server.api.served_document`` gives a stand-in whose
next-tick and timeout callbacks run on the test's event loop), and a run can be held in its thread
(``Held``) while the test moves other sliders or other pages. Every wait is bounded; nothing is
timed. Without the runs off the loop, the first held run blocks the test itself until its gate
gives up, and the test fails.
"""

from __future__ import annotations

import asyncio
import math
import threading
import time

import windpump
from windpump_app import session
from windpump_app.explorer import WORKING, Explorer
from windpump_app.server import api
from windpump_app.server import threads as serving

WAIT = 60.0  # [s] the longest any condition is waited for
SEED = windpump.Design.seed_example()


class LoopDocument:
    """A served page's document as a move sees it: callbacks run on the test's event loop. Each
    next-tick callback records the thread that added it: Bokeh's document loses one added from
    another thread while the loop holds the document (``serving.in_thread``)."""

    added_from: list[int] = []  # threading.get_ident() of each add_next_tick_callback's caller

    def __init__(self):
        from tornado.ioloop import IOLoop

        self.loop = IOLoop.current()
        self.loop_thread = threading.get_ident()  # made on the loop, as a page's document is

    def add_next_tick_callback(self, callback):
        LoopDocument.added_from.append(threading.get_ident() == self.loop_thread)
        self.loop.add_callback(callback)

    def add_timeout_callback(self, callback, milliseconds):
        self.loop.call_later(milliseconds / 1e3, callback)


class Held:
    """``session.shared_explore`` whose runs of a head ``h`` in ``held`` wait until released (or
    until WAIT passes: then it raises, and the test fails on what the page shows); every head run
    is recorded, in order."""

    def __init__(self, monkeypatch, *held: float):
        self.held = set(held)
        self.gate = threading.Event()
        self.ran: list[float] = []
        self.started = threading.Event()
        real = session.shared_explore

        def explore(design, t_end, *start):
            self.ran.append(design.h)
            if design.h in self.held:
                self.started.set()
                if not self.gate.wait(WAIT):
                    raise RuntimeError("held for ever: the test's own loop was blocked")
            return real(design, t_end, *start)

        monkeypatch.setattr(session, "shared_explore", explore)

    def release(self) -> None:
        self.gate.set()


async def until(condition, what: str) -> None:
    deadline = time.monotonic() + WAIT
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError(f"not within {WAIT:.0f} s: {what}")
        await asyncio.sleep(0.005)


def served(monkeypatch, document_of) -> None:
    """Pages served: ``document_of()`` is the document of the page being changed."""
    monkeypatch.setattr(api, "served_document", document_of)


def flow_text(h: float) -> str:
    """The mean-flow readout of the paper's example at head ``h``, run here."""
    seen = windpump.explore(SEED.replace(h=h), 600.0, math.pi / 2, 3.0)
    return f"{1e3 * seen.mean_flow:.4f} L/s"


def shows(app: Explorer, h: float) -> bool:
    return app.seen is not None and app.seen.design.h == h and flow_text(h) in flow_of(app)


def flow_of(app: Explorer) -> str:
    return app.readouts["mean_flow"].object


def test_two_moves_in_quick_succession_end_with_the_newer_run_and_never_an_older_after_it(
    monkeypatch,
):
    app = Explorer()
    drawn: list[float] = []
    draw = app._draw
    monkeypatch.setattr(app, "_draw", lambda seen: (drawn.append(seen.design.h), draw(seen)))

    async def moves() -> None:
        served(monkeypatch, LoopDocument)
        held = Held(monkeypatch, 2.0)
        app.inputs.h = 2.0
        await until(held.started.is_set, "the first move's run started")
        app.inputs.h = 3.0  # both made while the first runs: only the latest will run
        app.inputs.h = 5.0
        await asyncio.sleep(0.05)  # the loop turns meanwhile
        assert drawn == [] and held.ran == [2.0]
        held.release()
        await until(lambda: shows(app, 5.0), "the latest move's readouts")
        assert held.ran == [2.0, 5.0] and drawn == [5.0]

    asyncio.run(moves())
    assert not app.error.visible and not app.stale


def test_a_move_is_answered_while_another_pages_long_run_holds_a_thread(monkeypatch):
    slow, quick = Explorer(), Explorer()
    documents = {slow: LoopDocument, quick: LoopDocument}
    changing: list[Explorer] = []

    async def moves() -> None:
        served(monkeypatch, lambda: documents[changing[-1]]())
        held = Held(monkeypatch, 2.0)
        changing.append(slow)
        slow.inputs.h = 2.0
        await until(held.started.is_set, "the slow page's run started")
        changing.append(quick)
        quick.inputs.h = 5.0
        await until(lambda: shows(quick, 5.0), "the other page's readouts")
        assert slow.seen.design.h == SEED.h  # still held: its page shows its earlier run
        held.release()
        await until(lambda: shows(slow, 2.0), "the slow page's readouts, once released")

    asyncio.run(moves())


def test_a_refused_run_is_said_and_the_page_goes_on(monkeypatch):
    app = Explorer()

    async def moves() -> None:
        served(monkeypatch, LoopDocument)
        # refused by the run itself (its samples), in its thread
        app.set_values(R_dagger=0.5, omega_m=150.0, t_end=3000.0)
        await until(lambda: app.error.visible, "the refusal shown")
        assert "t_end" in app.error.object and app.stale
        assert app.readouts.row.styles["opacity"] == "0.35"
        app.inputs.L_over_R = 1.0  # refused on reading the inputs, before any run
        await until(lambda: "L/R, rod / crank = 1" in app.error.object, "the next refusal")
        app.set_values(**app.inputs.defaults())
        app.inputs.h = 5.0
        await until(lambda: shows(app, 5.0), "the next move's readouts")

    asyncio.run(moves())
    assert not app.error.visible and not app.stale
    assert app.readouts.row.styles["opacity"] == "1"


def test_a_long_run_says_the_page_is_working_until_it_is_drawn(monkeypatch):
    app = Explorer()
    monkeypatch.setattr(session, "WORKING_AFTER", 0)

    async def moves() -> None:
        served(monkeypatch, LoopDocument)
        held = Held(monkeypatch, 2.0)
        app.inputs.h = 2.0
        await until(lambda: app.readouts.status.object == WORKING, "the page saying it works")
        assert app.readouts.row.styles["opacity"] == "0.35"  # the readouts not current
        held.release()
        await until(lambda: shows(app, 2.0), "the run's readouts")

    asyncio.run(moves())
    assert "Running" in app.readouts.status.object and app.readouts.status.alert_type == "success"
    assert app.readouts.row.styles["opacity"] == "1"


def test_runs_under_way_hold_the_plots_back_and_are_counted_once_handed_back(monkeypatch):
    """serving.MOVE_RUNS: a run under way is a move pending (DrawAfterMoves waits for its
    readouts); its answer runs on the document's loop, with an exception handed over."""
    runs, answers = serving.Runs(threads=1), []
    monkeypatch.setattr(serving, "MOVE_RUNS", runs)
    gate = threading.Event()

    def fails():
        raise ValueError("refused")

    async def submitted() -> None:
        document = LoopDocument()
        runs.submit(document, lambda: gate.wait(WAIT) and "ran", answers.append)
        runs.submit(document, fails, answers.append)
        assert serving.moves_pending() and runs.under_way == 2
        gate.set()
        await until(lambda: len(answers) == 2, "both answers")

    LoopDocument.added_from.clear()
    asyncio.run(submitted())
    assert answers[0] == "ran" and isinstance(answers[1], ValueError)
    assert runs.under_way == 0 and not serving.moves_pending()
    assert LoopDocument.added_from == [True, True]  # each answer queued from the loop's thread


def test_a_thread_hands_its_answer_to_the_loop_and_a_closed_page_is_passed_over(monkeypatch):
    """serving.in_thread: the answer is queued on the document from the event loop's thread,
    never the work's (there, an ``unhold`` of the page on the loop could drop it); a page closed
    meanwhile (Bokeh refuses its callbacks) is passed over, and ``queued`` runs either way."""
    pool, answers, queued = serving.ThreadPoolExecutor(max_workers=1), [], []

    class Closed(LoopDocument):
        def add_next_tick_callback(self, callback):
            raise RuntimeError("Attempting to add session callback to already-destroyed Document")

    async def handed() -> None:
        serving.in_thread(pool, Closed(), lambda: "lost", answers.append, lambda: queued.append(1))
        serving.in_thread(
            pool, LoopDocument(), lambda: "ran", answers.append, lambda: queued.append(2)
        )
        await until(lambda: answers == ["ran"] and queued == [1, 2], "the open page's answer")

    LoopDocument.added_from.clear()
    asyncio.run(handed())
    pool.shutdown()
    assert LoopDocument.added_from == [True]


def test_not_served_a_move_runs_at_once():
    app = Explorer()
    app.inputs.h = 2.0
    assert shows(app, 2.0)  # a notebook, the tests: no loop to come back to
