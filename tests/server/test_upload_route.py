"""A wind record or a site's weather file sent by HTTP (``app/server/upload_route.py``): the bounded
store, the page's channel read in-process, and the route of a real `panel serve app/` (bad input,
and a 10 MB record posted while another page moves)."""

from __future__ import annotations

import asyncio
import json
import math
import random
import sys
import urllib.parse
import urllib.request
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from windpump_app.explorer import Explorer
from windpump_app.server.upload_route import UPLOADS, Posted, Refused, Uploads, page_opened
from windpump_app.uploads import SESSION_HEADER, WIND_MAX_BYTES

from panes import shown
from served import served_app, server_log

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
import bench_hall  # noqa: E402

LIMIT = 10_000_000  # [bytes] the page's limit for a wind or weather file, as the docs say


class Clock:
    def __init__(self):
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def rows(n: int = 121) -> bytes:
    lines = "\n".join(f"{60 * i},{5 + 2 * math.sin(i / 5):.3f}" for i in range(n))
    return ("t [s],V [m/s]\n" + lines + "\n").encode()


# -- the store --------------------------------------------------------------------------------


def test_the_limit_is_the_pages():
    assert WIND_MAX_BYTES == LIMIT


def test_only_an_open_session_may_post_and_what_it_posted_is_taken_once():
    store = Uploads()
    with pytest.raises(Refused) as refused:
        store.put("nobody", "wind", "a.csv", b"0,5\n")
    assert refused.value.reason == "session" and refused.value.status == 403
    store.opened("s1")
    upload_id = store.put("s1", "wind", "a.csv", b"0,5\n")
    assert store.take("s2", upload_id) == "gone"  # another session's
    taken = store.take("s1", upload_id)
    assert isinstance(taken, Posted) and taken.data == b"0,5\n" and taken.name == "a.csv"
    assert store.take("s1", upload_id) == "gone" and store.held() == 0


def test_an_empty_file_a_file_too_large_and_an_unknown_kind_are_refused_in_words():
    store = Uploads()
    store.opened("s1")
    for kind, data, reason, status, said in [
        ("wind", b"", "empty", 400, "This wind file cannot be used: the file is empty"),
        (
            "wind",
            b"0" * (LIMIT + 1),
            "size",
            413,
            "This wind file cannot be used: it has 10,000,001 bytes; at most 10,000,000 are read",
        ),
        (
            "site",
            b"0" * (LIMIT + 1),
            "size",
            413,
            "This weather file cannot be used: it has 10,000,001 bytes",
        ),
        ("lab", b"1,2\n", "kind", 400, "kind must be one of"),
    ]:
        with pytest.raises(Refused) as refused:
            store.put("s1", kind, "a.csv", data)
        assert refused.value.reason == reason and refused.value.status == status
        assert said in str(refused.value)
    store.put("s1", "wind", "a.csv", b"0" * LIMIT)  # the limit itself is taken


def test_a_later_file_of_the_same_upload_replaces_one_not_taken():
    store = Uploads()
    store.opened("s1")
    first = store.put("s1", "wind", "a.csv", b"0,5\n")
    site = store.put("s1", "site", "year.epw", b"x")
    second = store.put("s1", "wind", "b.csv", b"0,6\n")
    assert store.take("s1", first) == "replaced"  # its reference is dropped quietly
    assert store.take("s1", second).name == "b.csv"
    assert store.take("s1", site).name == "year.epw"  # another upload's: kept


def test_a_file_expires_and_a_closed_session_leaves_nothing():
    clock = Clock()
    store = Uploads(lifetime=120.0, clock=clock)
    store.opened("s1")
    store.opened("s2")
    old = store.put("s1", "wind", "a.csv", b"0,5\n")
    clock.now = 121.0
    assert store.take("s1", old) == "expired"
    kept = store.put("s2", "wind", "b.csv", b"0,6\n")
    store.put("s2", "site", "c.csv", b"0,6\n")
    store.closed("s2")
    assert store.held() == 0 and store.take("s2", kept) == "lost"
    with pytest.raises(Refused):
        store.put("s2", "wind", "b.csv", b"0,6\n")  # closed: it posts no more


def test_a_full_store_makes_room_for_a_page_within_its_share_from_others_untaken_files():
    clock = Clock()
    store = Uploads(max_items=3, max_held=100, lifetime=10.0, clock=clock)
    for session in ("a", "b", "c", "d"):
        store.opened(session)
    first = store.put("a", "wind", "a.csv", b"1" * 10)
    clock.now = 1.0
    second = store.put("b", "wind", "b.csv", b"1" * 10)
    clock.now = 2.0
    store.put("c", "wind", "c.csv", b"1" * 10)
    store.put("d", "wind", "d.csv", b"1" * 10)  # three held: the oldest other's goes
    assert store.take("a", first) == "crowded" and store.held() == 3
    store.put("d", "site", "d.epw", b"1" * 75)  # 10 + 10 + 10 + 75 > 100: b's goes
    assert store.take("b", second) == "crowded"
    assert {item.session_id for item in store._items.values()} == {"c", "d"}
    clock.now = 13.0  # c's and d's expired: dropped as the next arrives
    store.put("a", "wind", "a.csv", b"1" * 90)
    assert store.held() == 1


def test_a_store_smaller_than_a_share_refuses_what_does_not_fit_in_words():
    store = Uploads(max_items=2, max_held=100)
    store.opened("a")
    store.put("a", "wind", "a.csv", b"1" * 60)
    with pytest.raises(Refused) as refused:
        store.put("a", "site", "a.epw", b"1" * 60)  # its own wind file is its share, not others'
    assert refused.value.reason == "busy" and refused.value.status == 503


def test_only_a_session_whose_page_is_connected_may_post_and_its_files_go_when_it_is_lost():
    connected: set[str] = set()
    store = Uploads(connected=connected.__contains__)
    for session in ("bare", "page"):
        store.opened(session)
    with pytest.raises(Refused) as refused:
        store.put("bare", "wind", "a.csv", b"0,5\n")  # built by a GET, never connected
    assert refused.value.reason == "session" and not store.is_open("bare")
    connected.add("page")
    kept = store.put("page", "wind", "a.csv", b"0,5\n")
    store.put("page", "site", "a.epw", b"0,5\n")
    store.lost("page")  # its websocket closed
    assert store.held() == 0 and store.take("page", kept) == "lost"


def test_a_post_in_flight_is_the_pages_share_of_its_upload_from_its_first_byte():
    """A page holds one file of each upload, arrived or arriving: a later post of the same
    upload cuts off an earlier one still arriving (its bytes let go at once) and drops its
    file not yet taken; the page's other upload is not touched."""
    store = Uploads()
    store.opened("s")
    held = store.put("s", "wind", "held.csv", b"0,5\n")
    site = store.put("s", "site", "year.epw", b"0,5\n")
    first = store.receiving("s", "wind")
    first.chunks.append(b"1" * 1000)
    assert store.take("s", held) == "replaced"  # the post that began is the share now
    second = store.receiving("s", "wind")
    assert first.cut == "replaced" and first.chunks == [] and second.cut == ""
    assert store.in_flight() == 1
    with pytest.raises(Refused) as refused:
        store.put("s", "wind", "first.csv", b"1" * 1000, first)  # it ended after all
    assert refused.value.reason == "replaced" and refused.value.status == 409
    store.done(first)  # its end does not free the later one's share
    assert store.in_flight() == 1
    upload_id = store.put("s", "wind", "second.csv", b"0,6\n", second)
    store.done(second)
    assert store.in_flight() == 0 and store.take("s", upload_id).name == "second.csv"
    assert store.take("s", site).name == "year.epw"


def test_a_page_that_goes_cuts_off_its_posts_in_flight():
    store = Uploads()
    store.opened("s")
    arriving = store.receiving("s", "site")
    arriving.chunks.append(b"1" * 1000)
    store.lost("s")
    assert arriving.cut == "lost" and arriving.chunks == [] and store.in_flight() == 0
    with pytest.raises(Refused) as refused:
        store.put("s", "site", "year.epw", b"1" * 1000, arriving)
    assert refused.value.reason == "session"


def test_a_file_not_taken_is_said_to_be_dropped_for_the_reason_it_was():
    from windpump_app.server.upload_route import LIFETIME, dropped_text

    expired = dropped_text("expired", "a.csv")
    assert f"{LIFETIME:.0f} s" in expired and "not taken by then" in expired
    for why in ("lost", "gone"):
        said = dropped_text(why, "a.csv")
        assert "did not reach the page" in said and "Choose it again" in said
        assert f"{LIFETIME:.0f}" not in said and " s " not in said  # no time: not the rule
    assert "connection to the server closed" in dropped_text("lost", "a.csv")


def test_a_post_still_arriving_when_a_later_one_is_kept_is_refused_and_the_later_kept():
    """Through the route, in-process: a page's post that stalls mid-body while a later post of
    the same upload arrives whole is cut off (409, "replaced") when it ends, and the later file
    stays the page's: it used to be kept last and replace the later one."""
    from tornado.httpclient import AsyncHTTPClient, HTTPRequest
    from tornado.httpserver import HTTPServer
    from tornado.netutil import bind_sockets
    from tornado.web import Application

    from windpump_app.server.upload_route import UploadHandler

    store = Uploads()
    store.opened("s")

    async def posts() -> tuple:
        sockets = bind_sockets(0, "127.0.0.1")
        port = sockets[0].getsockname()[1]
        server = HTTPServer(Application([(r"/upload", UploadHandler, {"uploads": store})]))
        server.add_sockets(sockets)
        stalled, go_on = asyncio.Event(), asyncio.Event()

        async def slowly(write) -> None:
            await write(b"0,5\n" * 1000)
            stalled.set()
            await go_on.wait()
            await write(b"60,6\n")

        def request(name: str, **body) -> HTTPRequest:
            return HTTPRequest(
                f"http://127.0.0.1:{port}/upload?kind=wind&name={name}",
                method="POST",
                headers={SESSION_HEADER: "s", "Content-Type": "application/octet-stream"},
                request_timeout=60,
                **body,
            )

        client = AsyncHTTPClient(force_instance=True)
        try:
            early = asyncio.ensure_future(
                client.fetch(request("early.csv", body_producer=slowly), raise_error=False)
            )
            await asyncio.wait_for(stalled.wait(), 30)
            while store.in_flight() == 0:  # its first piece read: it is the page's share
                await asyncio.sleep(0.01)
            late = await client.fetch(request("late.csv", body=b"0,7\n60,8\n"), raise_error=False)
            go_on.set()
            early = await asyncio.wait_for(early, 30)
            return early, late
        finally:
            client.close()
            server.stop()

    early, late = asyncio.run(posts())
    assert late.code == 200, late.body
    assert early.code == 409 and json.loads(early.body)["refused"] == "replaced"
    assert store.in_flight() == 0 and store.held() == 1
    assert store.take("s", json.loads(late.body)["id"]).name == "late.csv"


def test_a_post_still_arriving_past_its_deadline_is_cut_off_and_its_bytes_let_go(monkeypatch):
    """Through the route, in-process: a post whose body stalls (a page, or a script with a
    connected page's id) held its bytes as long as Tornado waits for a body, an hour; past
    POST_DEADLINE (0.5 s here) it is cut off, its share and bytes let go."""
    from tornado.httpclient import AsyncHTTPClient, HTTPRequest
    from tornado.httpserver import HTTPServer
    from tornado.netutil import bind_sockets
    from tornado.web import Application

    from windpump_app.server import upload_route

    monkeypatch.setattr(upload_route, "POST_DEADLINE", 0.5)
    store = Uploads()
    store.opened("s")

    async def stalled_post() -> tuple:
        sockets = bind_sockets(0, "127.0.0.1")
        port = sockets[0].getsockname()[1]
        app = Application([(r"/upload", upload_route.UploadHandler, {"uploads": store})])
        server = HTTPServer(app)
        server.add_sockets(sockets)
        never = asyncio.Event()

        async def stalls(write) -> None:
            await write(b"0,5\n" * 1000)
            await never.wait()

        client = AsyncHTTPClient(force_instance=True)
        try:
            post = asyncio.ensure_future(
                client.fetch(
                    HTTPRequest(
                        f"http://127.0.0.1:{port}/upload?kind=wind&name=slow.csv",
                        method="POST",
                        headers={SESSION_HEADER: "s"},
                        body_producer=stalls,
                        request_timeout=60,
                    ),
                    raise_error=False,
                )
            )
            while store.in_flight() == 0:  # its first piece read
                await asyncio.sleep(0.01)
            seen = store.in_flight()
            for _ in range(500):  # up to 5 s
                if store.in_flight() == 0:
                    break
                await asyncio.sleep(0.01)
            gone = store.in_flight()
            post.cancel()
            return seen, gone
        finally:
            client.close()
            server.stop()

    seen, gone = asyncio.run(stalled_post())
    assert (seen, gone) == (1, 0)
    assert store.held() == 0


@settings(max_examples=60, deadline=None)
@given(
    st.lists(
        st.tuples(
            st.sampled_from(["put", "take", "close", "tick"]),
            st.sampled_from(["a", "b", "c"]),
            st.sampled_from(["wind", "site"]),
            st.integers(0, 60),
        ),
        max_size=40,
    )
)
def test_the_store_never_holds_more_than_its_bounds_nor_a_closed_sessions_file(steps):
    clock = Clock()
    store = Uploads(max_items=3, max_held=100, lifetime=5.0, clock=clock)
    ids: list[str] = []
    for session in "abc":
        store.opened(session)
    for action, session, kind, size in steps:
        if action == "put":
            try:
                ids.append(store.put(session, kind, "f.csv", b"1" * size))
            except Refused as refused:
                assert refused.reason in ("empty", "busy", "session")
        elif action == "take" and ids:
            store.take(session, ids[size % len(ids)])
        elif action == "close":
            store.closed(session)
        else:
            clock.now += size / 10
        items = list(store._items.values())
        assert len(items) <= 3 and sum(len(i.data) for i in items) <= 100
        assert all(i.session_id in store._sessions for i in items)
        assert len({(i.session_id, i.kind) for i in items}) == len(items)  # the newest of each


def test_a_page_is_given_the_route_only_when_served_with_it(monkeypatch):
    """Without the route (``panel serve app/main.py``, a notebook) the page sends the file
    Bokeh's way; with it, a served page's session may post and its page is told where; what
    it posted goes when its websocket closes, and it posts no more once destroyed."""

    class Context:
        id = "a-session"

    class Document:
        session_context = Context()
        destroyed: list = []
        events: dict = {}

        def on_session_destroyed(self, callback):
            self.destroyed.append(callback)

        def on_event(self, event, callback):
            self.events[event] = callback

    store = Uploads()
    monkeypatch.setattr("windpump_app.server.upload_route.UPLOADS", store)
    assert page_opened(Document()) == {"url": "", "session": ""} and not store.is_open("a-session")
    store.url = "/app/upload"
    page = Document()
    assert page_opened(page) == {"url": "/app/upload", "session": "a-session"}
    assert store.is_open("a-session")
    store.put("a-session", "wind", "a.csv", b"0,5\n")
    page.events["connection_lost"](object())  # Bokeh's ConnectionLost, on the server
    assert store.held() == 0
    page.destroyed[0](Context())  # Bokeh destroys the session
    assert not store.is_open("a-session")


# -- the page's channel, in-process ----------------------------------------------------------


@pytest.fixture
def app():
    explorer = Explorer()
    explorer.main().active = 2  # open the Wind tab
    UPLOADS.opened("")  # not served: the session id is ""
    yield explorer
    UPLOADS.closed("")


def tell(app, size: int, kind: str, name: str, state: str) -> None:
    app.sidebar.refused_upload.value = f"{size}\t{random.random()}\t{kind}\t{name}\t{state}"


def test_a_posted_wind_file_is_taken_and_read_as_a_chosen_one_is(app):
    data = rows()
    tell(app, len(data), "wind", "mast.csv", "sending")
    message = app.wind.upload_message
    assert message.visible and message.alert_type == "info" and "Sending mast.csv" in shown(message)
    upload_id = UPLOADS.put("", "wind", "mast.csv", data)
    tell(app, len(data), "wind", "mast.csv", f"posted {upload_id}")
    assert app.wind.last_run.t[-1] == 7200.0 and "mast.csv" in shown(app.wind.day_note)
    assert not message.visible and UPLOADS.take("", upload_id) == "gone"  # taken


def test_a_posted_weather_file_becomes_the_site(app):
    import numpy as np

    hours = np.arange(3 * 24)
    data = ("t,V\n" + "".join(f"{3600 * h},{5 + (h % 7) / 3:.2f}\n" for h in hours)).encode()
    upload_id = UPLOADS.put("", "site", "three.csv", data)
    tell(app, len(data), "site", "three.csv", f"posted {upload_id}")
    assert app.site_inputs.site == "uploaded", app.site.upload_message.object


def test_what_could_not_be_sent_is_said_and_the_day_stays(app):
    day = app.wind.last_run
    message = app.wind.upload_message
    for state, said in [
        ("failed size", "it has 12,000,000 bytes; at most 10,000,000 are read"),
        ("failed session", "Reload the page"),
        ("failed busy", "The server is receiving other files"),
        ("failed network", "could not be sent to the server"),
        ("failed <b>tampered</b>", "could not be sent to the server"),
        ("posted nothing-of-that-id", "did not reach the page"),
        ("empty", "This wind file cannot be used: the file is empty"),
    ]:
        tell(app, 12_000_000 if "size" in state else 0, "wind", "year.csv", state)
        assert message.visible and said in shown(message), (state, message.object)
        assert message.alert_type == "danger" and app.wind.last_run is day
        assert app.sidebar.reveal.value.split("\t")[0] in message.css_classes


def test_a_file_dropped_for_another_pages_in_a_full_store_is_said(app, monkeypatch):
    store = Uploads(max_items=1)
    monkeypatch.setattr("windpump_app.server.upload_route.UPLOADS", store)
    store.opened("")
    store.opened("another page")
    upload_id = store.put("", "wind", "mast.csv", rows())
    store.put("another page", "wind", "theirs.csv", rows())
    day = app.wind.last_run
    tell(app, len(rows()), "wind", "mast.csv", f"posted {upload_id}")
    message = app.wind.upload_message
    assert message.visible and "was dropped before this page could take it" in shown(message)
    assert "Choose it again" in shown(message) and app.wind.last_run is day


def test_a_file_replaced_by_a_later_one_says_nothing_of_itself(app):
    first = UPLOADS.put("", "wind", "first.csv", rows())
    second = UPLOADS.put("", "wind", "second.csv", rows(61))
    tell(app, 1, "wind", "second.csv", "sending")
    tell(app, 1, "wind", "first.csv", f"posted {first}")  # came late
    assert "Sending second.csv" in shown(app.wind.upload_message)
    tell(app, 1, "wind", "second.csv", f"posted {second}")
    assert app.wind.last_run.t[-1] == 3600.0 and "second.csv" in shown(app.wind.day_note)


def test_served_of_two_wind_files_the_later_wins_though_the_earlier_is_read_last(monkeypatch):
    from windpump_app import wind_tab

    held: list = []
    monkeypatch.setattr(wind_tab, "off_the_loop", lambda work, then: held.append((work, then)))
    explorer = Explorer()
    explorer.main().active = 2
    while held:
        work, then = held.pop(0)
        then(work())
    explorer.wind.load_data(rows(), "early.csv")
    explorer.wind.sending("late.csv", 4000)
    explorer.wind.load_data(rows(61), "late.csv")
    (early, late) = held
    held.clear()
    late[1](late[0]())
    while held:  # the late file's day
        work, then = held.pop(0)
        then(work())
    early[1](early[0]())  # the earlier file, read last: not shown
    assert "late.csv" in shown(explorer.wind.day_note)
    assert explorer.wind.last_run.t[-1] == 3600.0


# -- the route of a real server ---------------------------------------------------------------


@pytest.fixture(scope="module")
def served():
    with served_app() as (url, process):
        yield url, process


def a_session(url: str) -> str:
    """A page's session, built by its GET (as a browser's): its id."""
    from bokeh.util.token import get_session_id

    with urllib.request.urlopen(url, timeout=180) as page:
        token = bench_hall.TOKEN.search(page.read().decode()).group(1)
    return get_session_id(token)


async def post_async(url: str, session: str, kind: str, name: str, data: bytes) -> tuple[int, dict]:
    """POST ``data`` to the upload route as a page does (its session's id in the header)."""
    query = urllib.parse.urlencode({"kind": kind, "name": name})
    request = bench_hall.HTTPRequest(
        f"{url}/upload?{query}",
        method="POST",
        body=data,
        headers={"Content-Type": "application/octet-stream", SESSION_HEADER: session},
        request_timeout=300,
    )
    response = await bench_hall.AsyncHTTPClient().fetch(request, raise_error=False)
    return response.code, json.loads(response.body or b"{}")


def session_of(student: bench_hall.Student) -> str:
    from bokeh.util.token import get_session_id

    return get_session_id(student.token)


async def connected_page(url: str, seed: int) -> bench_hall.Student:
    """A student's page, its websocket connected, on its Wind tab."""
    student = bench_hall.Student(url, random.Random(seed))
    await student.open()
    await bench_hall.wind_tab(student)
    return student


async def the_day_of(student: bench_hall.Student, record: bytes) -> str:
    """Post ``record`` as the student's page does; the day's note its Wind tab then shows."""
    said: list[str] = []
    watcher = lambda e: said.append(str(e.get("new")))  # noqa: E731
    student.watchers.append(watcher)
    try:
        assert await bench_hall.post_upload(student, record) == 200
        drawn = lambda s: "Integrated in full" in s and bench_hall.UPLOAD_NAME in s  # noqa: E731
        deadline = asyncio.get_running_loop().time() + 300
        while not any(drawn(s) for s in said):  # read in its process, its day run
            assert asyncio.get_running_loop().time() < deadline, said[-3:]
            await asyncio.sleep(0.2)
        return next(s for s in said if drawn(s))
    finally:
        student.watchers.remove(watcher)


@pytest.mark.timeout(600)
def test_served_bad_posts_are_refused_in_words_and_a_connected_pages_good_one_kept(served):
    url, _process = served
    bench_hall.AsyncHTTPClient.configure(None, max_clients=10)

    async def posts() -> None:
        status, answer = await post_async(url, "made-up", "wind", "a.csv", b"0,5\n")
        assert status == 403 and answer["refused"] == "session" and "Reload" in answer["message"]
        student = await connected_page(url, 5)
        try:
            session = session_of(student)
            status, answer = await post_async(url, session, "wind", "a.csv", b"")
            assert status == 400 and answer["refused"] == "empty"
            assert answer["message"] == "This wind file cannot be used: the file is empty"
            status, answer = await post_async(url, session, "lab", "a.csv", b"1,2\n")
            assert status == 400 and answer["refused"] == "kind"
            big = b"0" * (LIMIT + 1)
            status, answer = await post_async(url, session, "wind", "big.csv", big)
            assert status == 413 and answer["refused"] == "size"
            assert "it has 10,000,001 bytes; at most 10,000,000 are read" in answer["message"]
            status, answer = await post_async(url, session, "wind", "a.csv", b"0,5\n10,6\n")
            assert status == 200 and answer["size"] == len(b"0,5\n10,6\n") and answer["id"]
        finally:
            student.close()

    asyncio.run(posts())


@pytest.mark.timeout(900)
def test_served_bare_visits_post_nothing_and_a_connected_pages_upload_gets_the_same_day(served):
    """Three visitors GET the page and never connect its websocket (a script, not a browser),
    each posting 10 MB with its session's id: all are refused, and a connected page's wind
    record gets the same day as one uploaded before them."""
    url, _process = served
    bench_hall.AsyncHTTPClient.configure(None, max_clients=10)
    record = bench_hall.wind_record(300_000)  # ~7 h at a sample a second

    async def visits() -> tuple[str, str]:
        before = await connected_page(url, 6)
        try:
            day_before = await the_day_of(before, record)
        finally:
            before.close()
        bare = [a_session(url) for _ in range(3)]
        ten_mb = bench_hall.wind_record(LIMIT)
        answers = [await post_async(url, s, "wind", "x.csv", ten_mb) for s in bare]
        assert [(status, a["refused"]) for status, a in answers] == [(403, "session")] * 3
        after = await connected_page(url, 7)
        try:
            return day_before, await the_day_of(after, record)
        finally:
            after.close()

    day_before, day_after = asyncio.run(visits())
    assert day_after == day_before


async def reconnected(student: bench_hall.Student) -> bench_hall.Student:
    """A second websocket to the student's session (its token, as Bokeh's client reconnects),
    its document read again: the same page, its store as the server kept it."""
    again = bench_hall.Student(student.url, random.Random(0), token=student.token)
    parsed = urllib.parse.urlparse(student.url)
    again.ws = await bench_hall.websocket_connect(
        bench_hall.HTTPRequest(
            f"ws://{parsed.netloc}{parsed.path}/ws",
            request_timeout=300,
            headers={"Origin": f"http://{parsed.netloc}"},
        ),
        subprotocols=["bokeh", student.token],
        max_message_size=64 * 1024 * 1024,
    )
    again.listening = asyncio.ensure_future(again.listen())
    await asyncio.wait_for(again.acknowledged.wait(), 300)
    again.read_document((await again.request("PULL-DOC-REQ", {}))["doc"])
    return again


@pytest.mark.timeout(600)
def test_served_a_pages_files_are_gone_once_its_page_closes(served):
    """A file posted and not yet taken is dropped when the page's websocket closes: the same
    session connected again is told it did not reach the page."""
    url, _process = served
    bench_hall.AsyncHTTPClient.configure(None, max_clients=10)

    async def closing() -> list[str]:
        student = await connected_page(url, 8)
        status, answer = await post_async(url, session_of(student), "wind", "a.csv", rows())
        assert status == 200
        student.close()
        deadline = asyncio.get_running_loop().time() + 300
        # A site file as the probe: a wind file would replace the one posted, not drop it
        while (await post_async(url, session_of(student), "site", "b.csv", rows()))[0] != 403:
            assert asyncio.get_running_loop().time() < deadline, "the server kept the page open"
            await asyncio.sleep(0.2)
        again = await reconnected(student)
        said: list[str] = []
        again.watchers.append(lambda e: said.append(str(e.get("new"))))
        channel = next(
            i for i, m in again.models.items() if bench_hall.CHANNEL in m.get("css_classes", [])
        )
        value = f"{len(rows())}\t{random.random()}\twind\ta.csv\tposted {answer['id']}"
        await again.patch([bench_hall.changed(channel, "value", value)])
        # the posted file read: the Wind tab's day over it (its default gusty day, drawn late on
        # a busy machine, says "Integrated in full over a gusty day")
        read = lambda s: "Integrated in full over the measured record" in s  # noqa: E731
        dropped = lambda s: "did not reach the page" in s  # noqa: E731
        deadline = asyncio.get_running_loop().time() + 300
        while not any(read(s) or dropped(s) for s in said):
            assert asyncio.get_running_loop().time() < deadline, said[-3:]
            await asyncio.sleep(0.2)
        again.close()
        return said

    said = asyncio.run(closing())
    assert any("did not reach the page" in s for s in said), said[-3:]
    assert not any("Integrated in full over the measured record" in s for s in said)  # never read


@pytest.mark.timeout(600)
def test_served_no_session_id_goes_in_the_servers_log(served):
    """A page loaded, a file posted and taken, posts refused (Tornado logs those): the
    server's output names none of the sessions (a session's id is the upload's credential)."""
    url, process = served
    bench_hall.AsyncHTTPClient.configure(None, max_clients=10)

    async def a_visit() -> list[str]:
        bare = a_session(url)
        student = await connected_page(url, 9)
        try:
            await the_day_of(student, rows())
            session = session_of(student)
            assert (await post_async(url, session, "wind", "empty.csv", b""))[0] == 400
            assert (await post_async(url, bare, "wind", "a.csv", rows()))[0] == 403
        finally:
            student.close()
        return [bare, session, student.token]

    secrets = asyncio.run(a_visit())
    written = server_log(process)
    assert "POST /app/upload" in written  # the refusals' lines: the log was read
    for secret in secrets:
        assert secret not in written


@pytest.mark.timeout(600)
def test_served_a_10_mb_record_posted_while_another_page_moves_its_move_is_answered(served):
    url, _process = served
    bench_hall.AsyncHTTPClient.configure(None, max_clients=10)

    async def hall() -> tuple[bench_hall.Student, list[str]]:
        loader = bench_hall.Student(url, random.Random(1))
        mover = bench_hall.Student(url, random.Random(2))
        await asyncio.gather(loader.open(), mover.open())
        await bench_hall.wind_tab(loader)
        said: list[str] = []
        loader.watchers.append(lambda e: said.append(str(e.get("new"))))
        record = bench_hall.wind_record(9_900_000)
        moves = len(mover.moves)
        posting = asyncio.ensure_future(bench_hall.post_upload(loader, record))
        await asyncio.sleep(0.01)
        await mover.move()  # sent while the record is being posted
        assert await asyncio.wait_for(posting, 300) == 200  # the route kept it
        deadline = asyncio.get_running_loop().time() + 300
        drawn = lambda s: "Integrated in full" in s and bench_hall.UPLOAD_NAME in s  # noqa: E731
        while not any(drawn(s) for s in said):  # read in its process, its day run
            assert asyncio.get_running_loop().time() < deadline, said[-3:]
            await asyncio.sleep(0.2)
        await mover.move()
        loader.close()
        mover.close()
        assert len(mover.moves) == moves + 2, mover.errors  # both moves answered
        return loader, said

    loader, said = asyncio.run(hall())
    assert loader.errors == []
    assert any(f"Reading {bench_hall.UPLOAD_NAME}" in s for s in said)  # the tab said it worked


@pytest.mark.timeout(600)
def test_the_upload_benchmark_runs(capsys):
    """benchmarks/bench_upload.py keeps working (how fast is printed there, not asserted)."""
    import bench_upload

    bench_upload.main(["1"])
    printed = capsys.readouterr().out
    assert "HTTP POST + reference" in printed and "ratio during / no upload" in printed


def test_the_words_for_the_upload_rules_are_the_rules_numbers():
    """What the docs and the page say of the store's rules carries the numbers the code uses."""
    from windpump_app.server.hooks import CHECK_UNUSED_SESSIONS, UNCONNECTED_SESSION_LIFETIME
    from windpump_app.server.upload_route import LIFETIME, MAX_HELD, MAX_ITEMS, dropped_text

    docs = Path(__file__).resolve().parents[2] / "docs"
    issues = " ".join((docs / "known-issues.rst").read_text(encoding="utf-8").split())
    instructors = " ".join((docs / "instructors.rst").read_text(encoding="utf-8").split())
    assert f"The store holds {MAX_ITEMS} files or {MAX_HELD // 1_000_000} MB" in issues
    assert f"a file not taken within {LIFETIME:.0f} s is dropped" in instructors
    assert f"{LIMIT // 1_000_000} MB each" in instructors
    bare = UNCONNECTED_SESSION_LIFETIME // 1000
    most = (UNCONNECTED_SESSION_LIFETIME + CHECK_UNUSED_SESSIONS) // 1000
    assert f"dropped after {bare}–{most} s" in instructors
    assert f"within {bare}–{most} s" in issues
    assert f"{LIFETIME:.0f} s" in dropped_text("expired", "a")


def test_no_log_line_names_a_session_at_any_level():
    """Bokeh names sessions in its own lines (a WARNING when a session scheduled for discarding
    comes back, DEBUG on every page); the server's handlers write them without the id or token."""
    import io
    import logging

    from bokeh.util.token import generate_jwt_token, generate_session_id

    from windpump_app.server.watch import HIDDEN, hide_session_ids

    session = generate_session_id()
    token = generate_jwt_token(session)
    written = io.StringIO()
    handler = logging.StreamHandler(written)
    bokeh = logging.getLogger("bokeh")
    level = bokeh.level
    bokeh.addHandler(handler)
    bokeh.setLevel(logging.DEBUG)
    try:
        hide_session_ids(bokeh)
        hide_session_ids(bokeh)  # once only
        assert len(handler.filters) == 1
        contexts = logging.getLogger("bokeh.server.contexts")
        contexts.warning(f"Session {session!r} was scheduled to discard but came back to life")
        logging.getLogger("bokeh.server.session").debug(
            f"Sending pull-doc-reply from session {session!r}"
        )
        logging.getLogger("bokeh.server.views.ws").error(
            "Token for session %r had invalid signature", token
        )
        try:
            raise KeyError(session)
        except KeyError:
            contexts.exception("no session %s", session)
        logging.raiseExceptions, raised = False, logging.raiseExceptions
        try:
            contexts.warning("%d sessions", "many")  # a bad line raises nothing at its caller
        finally:
            logging.raiseExceptions = raised
    finally:
        bokeh.removeHandler(handler)
        bokeh.setLevel(level)
    lines = written.getvalue()
    assert session not in lines and token not in lines
    assert lines.count(HIDDEN) == 5 and "came back to life" in lines and "KeyError" in lines
