"""The server-wide order of a class opening the page at once (app/server/sessions.py: ReadoutsFirst),
and what a served page nobody connects costs (app/server/hooks.py)."""

from __future__ import annotations

import re
import time
import urllib.request

import pytest
from bokeh import __version__ as bokeh_version
from hypothesis import given
from hypothesis import strategies as st

from windpump_app.server.sessions import ReadoutsFirst
from windpump_app.server.threads import Newest

from served import require_jemalloc, resident_memory, served_app, tidied_since, watched_env


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


def test_a_page_opened_while_the_solver_compiles_runs_once_it_is_ready(monkeypatch):
    """The page's onload waits off the event loop for the compile, then, on the document's next
    tick, runs its first design and goes on as any page (its views through ReadoutsFirst, drawn
    on a later tick)."""
    import asyncio
    import threading

    from windpump_app.server import sessions as serving

    monkeypatch.setattr(serving.READOUTS_FIRST, "settled", lambda: None)
    monkeypatch.setattr(
        serving.READOUTS_FIRST, "draw", lambda document, show: document.add_next_tick_callback(show)
    )

    started, shown = [], []

    class Page:
        def part_awaited(self):  # Explorer's: the first page's part until the solver is ready
            return None if serving.SOLVER_READY.is_set() else "the first page"

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
        assert started == [True] and shown == []
        document.run_pending()
        assert shown == [True]
    finally:
        serving.SOLVER_READY.set()


def test_a_page_closed_while_the_solver_compiles_runs_nothing(monkeypatch):
    """A page opened during a first start's compile and closed before it ended: its session is
    destroyed, and its document takes no callback (Bokeh deletes its callbacks' store, and
    adding one raised AttributeError, a traceback in the log for every such page)."""
    import asyncio
    import threading

    from windpump_app.server import sessions as serving

    class Context:
        destroyed = False

    class Gone(TickDocument):
        session_context = Context()

        def add_next_tick_callback(self, callback):
            raise AttributeError("'DocumentCallbackManager' object has no attribute")

    class Page:
        def part_awaited(self):
            return None if serving.SOLVER_READY.is_set() else "the first page"

        def start(self):
            raise AssertionError("a closed page's design was run")

    document = Gone()
    serving.SOLVER_READY.clear()
    try:
        onload = serving.first_run_when_ready("page", document, Page())
        document.session_context.destroyed = True  # the student left during the compile

        threading.Timer(0.2, serving.SOLVER_READY.set).start()
        asyncio.run(asyncio.wait_for(onload(), timeout=60))  # no AttributeError
    finally:
        serving.SOLVER_READY.set()


def test_closing_sessions_tidy_once_after_the_last_closes(monkeypatch):
    """A class leaving: one full collection after the last page closes, not one per page (each
    blocks every other page for a second or more), and the next at least ``every`` after it.

    Timed by the collections' own clock readings and polled with a bounded wait, not by fixed
    sleeps: on a busy machine a 0.2 s sleep ran long enough to let the second collection in
    before the check (CI at load 6-8)."""
    import asyncio
    import time

    from windpump_app.server import memory as serving

    runs = []  # each run's start, as the tidier's clock reads it
    tidy = serving.Tidy(quiet=0.2, every=2.0)
    monkeypatch.setattr(serving.gc, "collect", lambda: runs.append(tidy.last))

    async def until(count, limit=30.0):
        deadline = time.monotonic() + limit
        while len(runs) < count and time.monotonic() < deadline:
            await asyncio.sleep(0.05)

    async def leave():
        for _ in range(20):
            tidy.closed()
            await asyncio.sleep(0.01)
        last_closed = time.monotonic()
        await until(1)
        await asyncio.sleep(0.3)
        assert len(runs) == 1  # one for the twenty
        assert runs[0] >= last_closed + 0.2 - 0.02  # `quiet` after the last one closed
        tidy.closed()  # another leaves soon after: it waits for `every` since the last run
        await until(2)
        assert len(runs) == 2 and runs[1] - runs[0] >= 2.0 - 0.02

    asyncio.run(leave())


# -- garbage collections: never a walk of every open page while students move ------------------


def test_a_built_page_is_frozen_out_of_later_collections_until_sessions_close():
    """Once a page is built, ``settle`` freezes it: a full collection during a move walks what
    the move made, not the page; ``run`` (sessions closed) unfreezes, collects and freezes again."""
    import gc

    from windpump_app.explorer import Explorer
    from windpump_app.server.memory import Tidy

    tidy, walked = Tidy(), []

    def count(phase, info):  # the objects a collection is about to walk
        if phase == "start":
            walked.append(sum(len(gc.get_objects(g)) for g in range(info["generation"] + 1)))

    try:
        page = Explorer()
        tidy.settle()
        frozen = gc.get_freeze_count()
        assert not any(o is page.readouts for o in gc.get_objects())  # out of every walk
        gc.callbacks.append(count)
        page.set_values(h=4.0)  # a move
        gc.collect()  # even a full collection during it
        gc.callbacks.remove(count)
        assert page.seen.design.h == 4.0
        assert walked and max(walked) < frozen / 4
        tidy.run()  # sessions closed: all walked once, what lives frozen again
        assert gc.get_freeze_count() > 0
        assert not any(o is page.readouts for o in gc.get_objects())
    finally:
        if count in gc.callbacks:
            gc.callbacks.remove(count)
        gc.unfreeze()


def test_closed_sessions_are_collected_once_they_are_a_quarter_of_those_open(monkeypatch):
    """Frozen pages are freed only by a full walk: it waits until the dead pages are a quarter
    of the live ones (or none is open), as Python's own rule for full collections does."""
    import asyncio

    from windpump_app.server import memory as serving

    runs = []
    for name in ("collect", "freeze", "unfreeze"):
        monkeypatch.setattr(serving.gc, name, lambda name=name: runs.append(name))

    async def a_class() -> None:
        tidy = serving.Tidy(quiet=0.05, every=0.0)
        for _ in range(9):
            tidy.opened()
        tidy.closed()  # 1 dead, 8 open
        await asyncio.sleep(0.2)
        assert runs == []
        tidy.closed()  # 2 dead, 7 open: 2 >= 7/4
        await asyncio.sleep(0.2)
        assert runs == ["unfreeze", "collect", "freeze"] and tidy.dead == 0
        for _ in range(7):  # the rest leave: collected once after the last
            tidy.closed()
        await asyncio.sleep(0.2)
        assert runs[3:] == ["unfreeze", "collect", "freeze"] and tidy.open == 0

    asyncio.run(a_class())


def test_the_loop_watch_writes_full_collections_and_a_stalled_loop(tmp_path):
    import asyncio
    import gc
    import json
    import time

    from windpump_app.server.watch import LoopWatch

    path = tmp_path / "watch.jsonl"
    watch = LoopWatch(str(path), slow=0.2, every=0.02)

    async def stall() -> None:
        watch.start(asyncio.get_running_loop())
        await asyncio.sleep(0.05)
        time.sleep(0.3)  # a callback holding the loop
        await asyncio.sleep(0.05)
        gc.collect()
        watch.stop()

    try:
        asyncio.run(stall())
    finally:
        watch.stop()
    lines = [json.loads(line) for line in path.read_text().splitlines()]
    lags = [line["seconds"] for line in lines if line["kind"] == "lag"]
    full = [line for line in lines if line["kind"] == "gc" and line["generation"] == 2]
    assert lags and max(lags) >= 0.25
    assert full and full[-1]["tracked"] is not None
    assert watch.on_gc not in gc.callbacks


# -- the server's order of drawing: readouts of every pending move, then plots -------------------


class LoopDocument:
    """A Bokeh document's next-tick callbacks, run by the event loop."""

    def add_next_tick_callback(self, callback):
        from tornado.ioloop import IOLoop

        IOLoop.current().add_callback(callback)


def test_readouts_of_queued_moves_go_out_before_any_plots():
    """Two pages' moves queue: A's run is done (its readouts sent, its plots asked for), B's is
    read by Panel and waits for its turn. B's readouts go out before A's plots are drawn; a
    page's plots asked for twice before they are drawn are drawn once."""
    import asyncio

    from panel.io.state import state
    from tornado.ioloop import IOLoop

    from windpump_app.server.threads import DrawAfterMoves

    drawing, order = DrawAfterMoves(retry=0.001), []
    a, b = LoopDocument(), LoopDocument()

    def plots(page):
        return lambda: order.append(f"plots {page}")

    plots_a, plots_b = plots("A"), plots("B")

    def move_b() -> None:  # Panel applies B's change: its run, its readouts
        del state._change_callbacks[b]
        order.append("readouts B")
        drawing.later(b, plots_b)

    async def moves() -> None:
        state._change_callbacks[b] = {"b": move_b}  # read, not applied yet
        order.append("readouts A")
        drawing.later(a, plots_a)
        drawing.later(a, plots_a)
        await asyncio.sleep(0.01)  # the turns a page's next tick would take
        IOLoop.current().call_later(0.0, move_b)  # Panel's own timer (Syncable._debounce = 0)
        await asyncio.sleep(0.1)

    try:
        asyncio.run(moves())
    finally:
        state._change_callbacks.pop(b, None)
    assert order == ["readouts A", "readouts B", "plots A", "plots B"]


def test_a_patch_message_is_bokehs_own_with_references_made_when_met():
    """serving.lighter_patches: the PATCH-DOC of a changed text, a new model and a column of
    numbers is the message Bokeh makes, and the same models are left new."""
    import json

    import numpy as np
    from bokeh.document import Document
    from bokeh.models import Column, ColumnDataSource, Div
    from bokeh.protocol.messages.patch_doc import patch_doc

    from windpump_app.server.patches import lighter_patches

    if not bokeh_version.startswith("3.9."):
        pytest.skip(f"lighter_patches applies to Bokeh 3.9 only, not {bokeh_version}")
    lighter_patches()
    ours = patch_doc.create
    bokeh = ours.__func__.bokeh

    document, events = Document(), []
    source = ColumnDataSource({"y": np.arange(5.0)})
    text, other = Div(text="before"), Div(text="other")
    document.add_root(Column(text, other))
    document.add_root(source)
    document.models.flush_synced()  # the browser has them
    document.on_change(events.append)
    text.text = "after"
    source.data = {"y": np.arange(7.0)}
    new = Div(text="new")
    document.roots[0].children.append(new)
    document.add_root(Div(text="added, then left out of the events"))
    events = [e for e in events if "left out" not in str(getattr(e, "model", ""))][:3]
    before = set(document.models._new_models)
    messages, still_new = [], []
    for create in (bokeh, ours):
        document.models._new_models = set(before)
        messages.append(create(events))
        still_new.append(document.models._new_models)

    def content(message) -> str:  # a buffer's id is new in every message: named by its place
        place = {id(buffer): k for k, buffer in enumerate(message.buffers)}
        return json.dumps(message.content, default=lambda b: f"buffer {place[id(b)]}")

    assert content(messages[0]) == content(messages[1])
    assert [bytes(b.data) for b in messages[0].buffers] == [
        bytes(b.data) for b in messages[1].buffers
    ]
    assert still_new[0] == still_new[1] and len(still_new[0]) == len(before) - 1
    assert new.id in str(messages[1].content) and '"text": "other"' not in str(messages[1].content)


def test_plots_wait_for_moves_no_longer_than_their_patience():
    """A change Panel never applies (its page closed meanwhile) holds no page's plots for ever."""
    import asyncio

    from panel.io.state import state

    from windpump_app.server.threads import DrawAfterMoves

    drawing, order, gone = DrawAfterMoves(retry=0.001, patience=0.05), [], LoopDocument()

    async def stuck() -> None:
        state._change_callbacks[gone] = {"never": lambda: None}
        drawing.later(LoopDocument(), lambda: order.append("plots"))
        await asyncio.sleep(0.01)
        assert order == []  # waits for the move...
        await asyncio.sleep(0.2)  # ...for its patience

    try:
        asyncio.run(stuck())
    finally:
        state._change_callbacks.pop(gone, None)
    assert order == ["plots"]


class ClosedDocument:
    """A document whose page has closed: Bokeh refuses its callbacks."""

    def add_next_tick_callback(self, callback):
        raise RuntimeError("this document's session is gone")


def test_a_closed_pages_drawing_holds_up_no_other_pages():
    """A page closed while its plots were queued: the plots queued behind it are still drawn."""
    import asyncio

    from windpump_app.server.threads import DrawAfterMoves

    drawing, order = DrawAfterMoves(retry=0.001, patience=0.05), []

    async def queued() -> None:
        drawing.later(ClosedDocument(), lambda: order.append("closed"))
        drawing.later(LoopDocument(), lambda: order.append("plots"))
        await asyncio.sleep(0.2)

    asyncio.run(queued())
    assert order == ["plots"]


def test_a_change_sends_what_panels_own_update_sends_with_the_design_worked_out_only_for_styles():
    """serving.lighter_updates: Panel's ``Reactive._update_properties`` gives the same properties
    for a change of a value and of the stylesheets (the design's sheets before the component's)."""
    import panel as pn
    from panel.reactive import Reactive

    from windpump_app.server.patches import lighter_updates

    lighter_updates()
    ours = Reactive._update_properties
    if not getattr(ours, "lighter", False):
        pytest.skip(f"lighter_updates applies to Panel 1.9 only, not {pn.__version__}")
    panels = ours.panel
    slider = pn.widgets.FloatSlider(start=0.0, end=10.0, value=1.0, design=pn.theme.Bootstrap)
    events = []
    slider.param.watch(events.append, ["value", "stylesheets"])
    slider.value = 2.5
    slider.stylesheets = [":host { margin: 3px; }"]
    assert [e.name for e in events] == ["value", "stylesheets"]

    def plain(properties: dict) -> dict:  # a stylesheet model by its address (a new id each time)
        sheets = [getattr(s, "url", s) for s in properties.get("stylesheets", [])]
        return {**properties, **({"stylesheets": sheets} if sheets else {})}

    for event in events:
        theirs, mine = panels(slider, event, doc=None), ours(slider, event, doc=None)
        assert plain(mine) == plain(theirs)
    styles = plain(ours(slider, events[1], doc=None))["stylesheets"]
    assert len(styles) > 1 and styles[-1] == ":host { margin: 3px; }"


def test_an_upload_is_read_in_a_process_of_its_own_as_the_core_reads_it():
    """serving.FILE_READERS, started as the server starts it: the core's reader runs in another
    process (a 10 MB CSV is ~2 s of pure Python, which in a thread held the GIL from every
    page's moves), its record comes back read-only and equal to the core's own read here, a
    refusal comes back with the core's message, a reader that dies is replaced, and the reader
    runs below the server's CPU priority."""
    import os

    import numpy as np

    import windpump
    from windpump.model.wind import read_csv
    from windpump_app.server import threads as serving

    data = b"time,speed\n0,4.5\n10,6\n20,5.25\n"
    readers = serving.FileReaders()
    assert readers.read(os.getpid) == os.getpid()  # not started: read where asked
    readers.start()
    try:
        assert readers.read(os.getpid) != os.getpid()
        if hasattr(os, "nice"):  # the reader yields the CPU to the server's moves
            assert readers.read(os.nice, 0) == min(19, os.nice(0) + readers.NICENESS)
        record, here = readers.read(read_csv, data), read_csv(data)
        assert np.array_equal(record.t, here.t) and np.array_equal(record.V, here.V)
        assert not record.t.flags.writeable and not record.V.flags.writeable
        weather = readers.read(windpump.read_weather, data)
        assert np.array_equal(weather.V, windpump.read_weather(data).V)
        with pytest.raises(ValueError) as refused:
            readers.read(read_csv, b"time,speed\n0,4.5\n10,-6\n")
        with pytest.raises(ValueError) as here_refused:
            read_csv(b"time,speed\n0,4.5\n10,-6\n")
        assert str(refused.value) == str(here_refused.value)
        with pytest.raises(RuntimeError, match="stopped"):
            readers.read(os._exit, 1)  # the reader dies
        assert readers.read(os.getpid) != os.getpid()  # and a new one reads the next file
    finally:
        readers.stop()


def test_files_read_at_once_by_several_pages_are_all_read():
    """Four pages' uploads read at the same moment each get their record, each in a process
    of its own, none waiting for ever."""
    import concurrent.futures

    import numpy as np

    from windpump.model.wind import read_csv
    from windpump_app.server import threads as serving

    files = [f"time,speed\n0,{v}\n10,6\n".encode() for v in (1.5, 2.5, 3.5, 4.5)]
    readers = serving.FileReaders()
    readers.start()
    pages = concurrent.futures.ThreadPoolExecutor(max_workers=len(files))
    try:
        reads = [pages.submit(readers.read, read_csv, data) for data in files]
        done, waiting = concurrent.futures.wait(reads, timeout=120)
        assert not waiting, f"{len(waiting)} of {len(files)} reads never came back"
        assert [read.result().V[0] for read in reads] == [1.5, 2.5, 3.5, 4.5]
        assert all(np.array_equal(r.result().t, [0.0, 10.0]) for r in reads)
    finally:
        readers.stop()
        pages.shutdown(wait=False, cancel_futures=True)


def test_changes_queued_while_a_page_sends_are_sent_when_its_sending_ends(monkeypatch):
    """serving.writes_not_stranded: a page's changes that meet its socket busy are queued
    (Panel's ``schedule_write_events``); those queued while an earlier batch is being sent go
    out too, not only at the page's next change (the Design map's mark after a tap did not)."""
    import asyncio

    import panel as pn
    from bokeh.document import Document
    from bokeh.document.events import ModelChangedEvent
    from bokeh.models import Div
    from bokeh.protocol import Protocol
    from panel.io import document as documents
    from tornado.locks import Lock

    from windpump_app.server.patches import writes_not_stranded

    monkeypatch.setattr(documents, "_dispatch_msgs", documents._dispatch_msgs)  # put back after
    writes_not_stranded()
    if not getattr(documents._dispatch_msgs, "not_stranded", False):
        pytest.skip(f"writes_not_stranded applies to Panel 1.9 only, not {pn.__version__}")

    class Socket:  # a page's websocket: the first message's frames written when the test says
        def __init__(self):
            self.write_lock = Lock()
            self.sent: list[str] = []  # the text of each message sent
            self.first: asyncio.Future | None = None

        def send(self, _connection, msg) -> list:
            self.sent.append(msg.content["events"][0]["new"])
            done = asyncio.get_running_loop().create_future()
            if self.first is None:
                self.first = done
            else:
                done.set_result(None)
            return [done]

    class Connection:
        def __init__(self):
            self._socket, self.protocol = Socket(), Protocol()

    monkeypatch.setitem(
        documents.extra_socket_handlers, Socket, lambda c, msg: c._socket.send(c, msg)
    )
    document, text, page = Document(), Div(text="before"), Connection()
    document.add_root(text)

    def change(new: str) -> None:
        documents.schedule_write_events(
            document, [page], [ModelChangedEvent(document, text, "text", new)]
        )

    async def sending() -> None:
        change("the move's readouts")
        for _ in range(1000):
            if page._socket.first is not None:
                break
            await asyncio.sleep(0.001)
        page._socket.first.set_result(None)  # its frames written: its task ends next
        change("the map's mark")  # queued meanwhile, its own task after that one
        for _ in range(1000):
            if len(page._socket.sent) == 2:
                return
            await asyncio.sleep(0.001)

    asyncio.run(sending())
    assert page._socket.sent == ["the move's readouts", "the map's mark"]


@given(
    asks=st.lists(st.integers(0, 3), min_size=1, max_size=8),
    order=st.randoms(use_true_random=False),
)
def test_only_the_newest_request_is_drawn_and_none_superseded_is_worked_out(asks, order):
    """Requests held in a pool and run in any order, each asked for when the one before was
    held: the outcome drawn is the last request's (and only once it is run), and a request's
    work is done only while it is the one last asked for (repeats of it count as it)."""
    held: list = []  # (work, then) as the pool holds them
    worked: list = []
    drawn: list = []
    newest = Newest()
    for i, asked in enumerate(asks):
        newest.ask(
            asked,
            lambda a=asked, i=i: worked.append(i) or a,
            drawn.append,
            lambda w, t: held.append((w, t)),
        )
    order.shuffle(held)
    for work, then in held:
        then(work())
    last = asks[-1]
    assert set(drawn) <= {last} and len(drawn) == asks.count(last)
    assert all(asks[i] == last for i in worked)  # nothing else was worked out


@given(
    sent_at=st.integers(0, 4),
    files=st.integers(1, 4),
    order=st.randoms(use_true_random=False),
)
def test_a_file_on_its_way_supersedes_every_file_chosen_before_it(sent_at, files, order):
    """A tab's files (each a request of its own), one of them posted by HTTP: while it is on its
    way (``supersede``), no file chosen before it is read or drawn, in whatever order the pool
    runs them; of those chosen after it, only the last is drawn."""
    sent_at %= files + 1  # before the first file, between two, or after the last
    held: list = []
    worked: list = []
    drawn: list = []
    files_of_tab = Newest()
    for i in range(files + 1):
        if i == sent_at:
            files_of_tab.supersede()
        if i < files:
            files_of_tab.ask(
                object(),
                lambda i=i: worked.append(i) or i,
                drawn.append,
                lambda w, t: held.append((w, t)),
            )
    order.shuffle(held)
    for work, then in held:
        then(work())
    expected = [files - 1] if sent_at < files else []
    assert drawn == expected
    assert set(worked) <= set(expected)


# -- a served page nobody connects ------------------------------------------------------------

BARE_VISITS = 100
# [s] the longest the first visits are waited for: a bare session lives 30-35 s (server/hooks.py),
# then is collected 5 s after (server/memory.py: Tidy), which the test waits for (``tidied_since``)
SETTLED = 120.0
SETTLE = 300.0  # [s] the longest the server's memory is waited for after the visits
HELD = 20e6  # [bytes] what the visits may leave: 100 kept pages held +90 to +480 MB
POLL = 0.5  # [s] how often the server's memory and collections are read


def bare_visit(url: str) -> None:
    """A GET of the page, as a script or a link checker sends it: its websocket never connects."""
    with urllib.request.urlopen(url, timeout=300) as page:
        page.read()


@pytest.mark.timeout(1200)
def test_served_a_hundred_bare_visits_hold_no_memory_a_minute_later(tmp_path):
    """Each GET builds a page's session, which the server drops within seconds when no browser
    connects it. The server runs on jemalloc (as the proxy's processes do), which hands back
    what is freed: with Python's allocator a few dropped pages' objects pin arenas and the
    figure wanders by tens of MB either way (docs/known-issues.rst).

    Most of its time is the server's own clocks, which are the scenario: a bare session's
    lifetime (30-35 s), then the collection of what it held, at most once a minute (Tidy)."""
    from windpump_app.server import proxy

    watch = tmp_path / "watch.jsonl"
    env = watched_env(watch, proxy.allocator_env("jemalloc", library=require_jemalloc()))
    with served_app(env=env) as (url, process):
        visited = time.time()
        for _ in range(3):  # what a first page imports and keeps for good
            bare_visit(url)
        # the first visits dropped and what they held collected (a full collection of everything)
        deadline = time.monotonic() + SETTLED
        while not tidied_since(watch, visited) and time.monotonic() < deadline:
            time.sleep(POLL)
        time.sleep(POLL)  # the collection's memory handed back (malloc_trim, right after it)
        before = resident_memory(process.pid)
        for _ in range(BARE_VISITS):
            bare_visit(url)
        held = resident_memory(process.pid)
        deadline = time.monotonic() + SETTLE
        while held - before >= HELD and time.monotonic() < deadline:
            time.sleep(POLL)
            held = resident_memory(process.pid)
    assert held - before < HELD, f"{before / 1e6:.0f} MB before, {held / 1e6:.0f} MB after"


# -- a page whose browser connects late -------------------------------------------------------

LIFETIME_MS = 2_000  # a short unconnected lifetime, so "late" is seconds here, not 30 s
LATE = 8.0  # [s] the browser connects this long after its page was served: past the lifetime


def page_visit(url: str, browser: bool) -> tuple[str, str]:
    """GET the page, as a browser's navigation (``Sec-Fetch-Dest: document``) or as a script;
    return its session's id and its HTML."""
    from bokeh.util.token import get_session_id

    headers = {"Sec-Fetch-Dest": "document", "Sec-Fetch-Mode": "navigate"} if browser else {}
    with urllib.request.urlopen(urllib.request.Request(url, headers=headers), timeout=300) as page:
        html = page.read().decode()
    token = re.search(r'"token": ?"([^"]+)"', html).group(1)
    return get_session_id(token), html


def connected_root_ids(url: str, session_id: str) -> set[str]:
    """Connect the session's websocket, as the page's scripts do; the ids of its document's roots."""
    import panel.models  # noqa: F401  (the page's models, to read its document)
    import panel.models.location  # noqa: F401
    from bokeh.client import pull_session

    with pull_session(session_id=session_id, url=url) as session:
        return {root.id for root in session.document.roots}


@pytest.mark.timeout(600)
def test_served_a_page_whose_browser_connects_late_is_built_once_and_works():
    """A page connected after its session's unconnected lifetime (30 s; 2 s here) was built a
    second time as it connected, on a busy server: the browser's page is kept until it connects
    (serving.wait_for_the_browser); a script's bare GET still goes after the lifetime (issue 37)."""
    args = ("--unused-session-lifetime", str(LIFETIME_MS), "--check-unused-sessions", "500")
    with served_app(*args) as (url, _process):
        browsers, script = page_visit(url, browser=True), page_visit(url, browser=False)
        time.sleep(LATE)
        for (session_id, html), kept in ((browsers, True), (script, False)):
            page_roots = set(re.findall(r'data-root-id="([^"]+)"', html))
            assert page_roots, html[:2000]  # the roots the served HTML places
            roots = connected_root_ids(url, session_id)
            # the same document: the one built when the page was served (a rebuilt one has new ids)
            assert (page_roots <= roots) is kept, (kept, page_roots, roots)


@pytest.mark.timeout(600)
def test_served_a_browser_s_page_once_connected_and_closed_goes_after_the_lifetime():
    """The hold on a browser's page ends as it connects: closed, it goes after Bokeh's lifetime
    (2 s here), as any closed page does, not 180 s after it was served (the hold kept a class's
    closed pages, and their memory, for three minutes)."""
    args = ("--unused-session-lifetime", str(LIFETIME_MS), "--check-unused-sessions", "500")
    with served_app(*args) as (url, _process):
        session_id, html = page_visit(url, browser=True)
        page_roots = set(re.findall(r'data-root-id="([^"]+)"', html))
        assert page_roots <= connected_root_ids(url, session_id)  # connects, then closes
        time.sleep(LATE)  # past the lifetime and a check after the close
        roots = connected_root_ids(url, session_id)
        assert not page_roots & roots, (page_roots, roots)  # a new document: the old one went


def test_forged_navigations_hold_at_most_max_held_pages_and_each_goes_when_it_may(monkeypatch):
    """A script can send ``Sec-Fetch-Dest: document`` with every GET: each held its page for
    BROWSER_CONNECT_WINDOW (180 s) instead of the 30 s of a bare GET. At most MAX_HELD are held
    at once; a held page frees its place when it connects or its window ends."""
    import asyncio
    from types import SimpleNamespace

    from windpump_app.server import sessions

    monkeypatch.setattr(sessions, "MAX_HELD", 3)
    monkeypatch.setattr(sessions, "HELD", set())

    class Session:
        def __init__(self, k):
            self.id, self.destroyed, self.connection_count = f"s{k}", False, 0
            self.milliseconds_since_last_unsubscribe = 1e12  # never connected
            self.blocked = False

        def block_expiration(self):
            self.blocked = True

        def unblock_expiration(self):
            self.blocked = False

    def navigation(k):
        context = SimpleNamespace(
            request=SimpleNamespace(headers={"Sec-Fetch-Dest": "document"}), _session=Session(k)
        )
        return SimpleNamespace(session_context=context), context._session

    async def visits():
        pages = [navigation(k) for k in range(5)]
        for document, _ in pages:
            sessions.wait_for_the_browser(document, window=1.0, poll=0.02)
        await asyncio.sleep(0.2)
        held = [session.blocked for _, session in pages]
        pages[0][1].connection_count = 1  # its browser connects: its place is free
        await asyncio.sleep(0.2)
        late, _ = navigation(5)
        sessions.wait_for_the_browser(late, window=1.0, poll=0.02)
        await asyncio.sleep(0.2)
        after_connect = (pages[0][1].blocked, late.session_context._session.blocked)
        await asyncio.sleep(1.5)  # every window over
        return held, after_connect, [s.blocked for _, s in pages], set(sessions.HELD)

    held, after_connect, at_the_end, still = asyncio.run(visits())
    assert held == [True, True, True, False, False]
    assert after_connect == (False, True)
    assert at_the_end == [False] * 5 and still == set()
