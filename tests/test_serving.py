"""The server-wide order of a class opening the page at once (app/serving.py: ReadoutsFirst)."""

from __future__ import annotations

from windpump_app.serving import ReadoutsFirst


class Document:
    """Stands in for a Bokeh document: keeps the timeout callbacks to run them on demand."""

    def __init__(self):
        self.pending = []

    def add_timeout_callback(self, callback, _milliseconds):
        self.pending.append(callback)

    def run_pending(self):
        pending, self.pending = self.pending, []
        for callback in pending:
            callback()


def test_a_page_alone_gets_its_views_at_once():
    order, shown = ReadoutsFirst(), []
    order.opened("a")
    order.loaded("a", Document(), lambda: shown.append("a"))
    assert shown == ["a"]


def test_views_wait_until_every_page_opened_meanwhile_has_loaded():
    order, document, shown = ReadoutsFirst(), Document(), []
    for page in "abc":
        order.opened(page)
    order.loaded("a", document, lambda: shown.append("a"))
    order.loaded("b", document, lambda: shown.append("b"))
    document.run_pending()
    assert shown == [] and order.loading == {"c": order.loading["c"]}
    order.closed("c")  # its page closed before it loaded: it holds nobody back
    document.run_pending()
    assert sorted(shown) == ["a", "b"] and document.pending == []


def test_a_page_waits_no_longer_than_its_patience_nor_for_a_page_that_never_loads():
    impatient, document, shown = ReadoutsFirst(patience=0.0), Document(), []
    impatient.opened("slow")
    impatient.loaded("a", document, lambda: shown.append("a"))
    assert shown == ["a"] and "slow" in impatient.loading
    forgetful = ReadoutsFirst(forget_after=0.0)
    forgetful.opened("never")
    forgetful.loaded("b", document, lambda: shown.append("b"))
    assert shown == ["a", "b"] and forgetful.loading == {}


# -- a first start: pages open while the solver compiles ------------------------------------------


class TickDocument(Document):
    """Also keeps next-tick callbacks (run under the document's lock in a real server)."""

    def add_next_tick_callback(self, callback):
        self.pending.append(callback)


def test_a_page_opened_while_the_solver_compiles_runs_once_it_is_ready():
    """The page's onload waits off the event loop for the compile, then, on the document's next
    tick, runs its first design and goes on as any page (its views through ReadoutsFirst)."""
    import asyncio
    import threading

    from windpump_app import serving

    started, shown = [], []

    class Page:
        def start(self):
            started.append(serving.SOLVER_READY.is_set())

        def show_views(self):
            shown.append(True)

    document = TickDocument()
    serving.SOLVER_READY.clear()
    try:
        onload = serving.first_run_when_ready("page", document, Page())
        threading.Timer(0.2, serving.SOLVER_READY.set).start()  # the compile ends
        asyncio.run(asyncio.wait_for(onload(), timeout=60))
        assert started == [] and len(document.pending) == 1  # nothing ran off the lock
        document.run_pending()
        assert started == [True] and shown == [True]
    finally:
        serving.SOLVER_READY.set()


def test_closing_sessions_tidy_once_after_the_last_closes(monkeypatch):
    """A class leaving: one full collection after the last page closes, not one per page (each
    blocks every other page for a second or more)."""
    import asyncio

    from windpump_app import serving

    runs = []
    monkeypatch.setattr(serving.gc, "collect", lambda: runs.append("collect"))

    async def leave():
        tidy = serving.Tidy(quiet=0.2, every=0.5)
        for _ in range(20):
            tidy.closed()
            await asyncio.sleep(0.01)
        await asyncio.sleep(0.4)
        assert runs == ["collect"]
        tidy.closed()  # another leaves soon after: it waits for `every` since the last run
        await asyncio.sleep(0.2)
        assert runs == ["collect"]
        await asyncio.sleep(0.5)
        assert runs == ["collect", "collect"]

    asyncio.run(leave())
