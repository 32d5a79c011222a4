"""A lecture hall at the protocol level: N students open the explorer within a few seconds and move
its sliders, each a websocket client that speaks Bokeh's protocol as the page does but draws nothing.

Run: python benchmarks/bench_hall.py [N ...] [--minutes M] [--upload] [--scroll FRACTION]
     (N = 30 100 200 by default; each hall on a fresh `panel serve app/` on loopback)

Each student: GETs the page (the server builds its session), opens the page's websocket with the
token the page carries, pulls the document (PULL-DOC-REQ -> PULL-DOC-REPLY), sends what a loaded
page sends (its browser's facts, then ``document_ready``), and then, every 5-20 s at random, moves
one slider to a random value on its step, as the page does (``value``, then ``value_throttled``).
Recorded per student: the time from its GET to its readouts (the mean-flow readout's text arriving)
and each move's round trip (the PATCH-DOC sent -> the PATCH-DOC that changes the readouts). For the
server: its CPU and resident memory, sampled every half second. Printed: percentiles, the server's
CPU per page (while the hall opens), memory per idle session and after the hall has closed.

The page builds each view when it first shows it (``app/viewport.js`` names the views seen in a
hidden input): each student, once loaded, names those of a first screen at 1280x720 (the crank
speed and the machine), as that page does; ``--scroll FRACTION``: that fraction of the students
then scroll to the bottom (1-3 s after their readouts), naming every view. A server without that
input (before it) builds every view anyway and is sent nothing.

``--upload``: while the hall moves, one more student loads a 10 MB wind record into the Wind tab,
as the page sends it (by HTTP POST, its reference over the websocket; a server without the upload
route, as a FileInput's base64 value), from a process of its own as a student's browser is
(``bench_upload.py``'s loader), and the others' round trips are split into before/while/after
(while: from the first byte sent until the server says it reads the file). Ten more students,
who move at no other time, move at once 2 s before the upload and again 10 ms after its first
byte, each time to a design no other page holds (its run worked out, not shared): the same work,
with and without a file arriving.

``--watch``: the server writes what holds up its event loop (``WINDPUMP_LOOP_WATCH``, see
``server.watch.LoopWatch``: its full garbage collections and the times its loop ran late), and the
report sets them beside the slow round trips: how many of those had a collection or a late loop
during their flight.

Bounded: N <= 400 sessions, at most ``--minutes`` of moves (default 1), every wait has a timeout,
and it talks only to 127.0.0.0/8.
"""

from __future__ import annotations

import argparse
import asyncio
import html
import json
import os
import random
import re
import sys
import time
import uuid
from dataclasses import dataclass, field
from pathlib import Path
from urllib.parse import urlparse

from tornado.httpclient import AsyncHTTPClient, HTTPRequest
from tornado.websocket import websocket_connect

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from windpump_app.inputs import PumpInputs  # noqa: E402
from windpump_app.uploads import SESSION_HEADER  # noqa: E402

from served import cpu_seconds, resident_memory, served_app  # noqa: E402

MAX_SESSIONS = 400
OPEN_WITHIN = 10.0  # [s] the students open the page within this
MOVE_EVERY = (5.0, 20.0)  # [s] a student's pause between two moves
WAIT = 300.0  # [s] the longest a page's opening is waited for
MOVE_WAIT = 60.0  # [s] the longest a move's readouts are waited for
SAMPLE_EVERY = 0.5  # [s] the server's CPU and memory
# The sliders a student moves, by their title on the page (the app's labels: a renamed slider was
# not found): (lowest, highest) value sent, inside the slider's range and where the paper's example
# still runs (a stalled design shows no new flow).
TITLE = {name: PumpInputs.param[name].label for name in ("h", "T_m", "t_end")}
MOVES = {
    TITLE["h"]: (1.0, 6.0),
    TITLE["T_m"]: (0.5, 1.5),
    TITLE["t_end"]: (200.0, 900.0),
}
TOKEN = re.compile(r'"token":"([^"]+)"')
READOUT = 'data-name="mean_flow"'
READOUTS = 'class="readout"'  # every readout of the row: a move changes at least one
VIEWS_SEEN = "views-seen"  # the hidden input where the page names the views it shows
FIRST_SCREEN = "speed machine"  # what a page at 1280x720 names once loaded
EVERY_VIEW = "speed machine flow closeup energy stall operating"  # scrolled to the bottom


def loopback(url: str) -> str:
    host = urlparse(url).hostname or ""
    if not host.startswith("127."):
        raise SystemExit(f"bench_hall talks only to loopback (127.0.0.0/8), not {host}")
    return url


# -- one student ---------------------------------------------------------------------------------


@dataclass
class Student:
    """One student's page at the protocol level, and what it measured."""

    url: str
    rng: random.Random
    opened: float = 0.0  # [s] perf_counter of the GET
    to_readout: float | None = None  # [s] GET -> the readout's text
    moves: list[tuple[float, float]] = field(default_factory=list)  # (sent at, round trip [s])
    errors: list[str] = field(default_factory=list)
    models: dict = field(default_factory=dict)  # id -> {"type", "name", attributes...} as received
    readout_id: str | None = None
    readout_ids: set = field(default_factory=set)
    waiting: dict = field(default_factory=dict)  # reqid -> future of the server's answer
    readout_changed: asyncio.Event = field(default_factory=asyncio.Event)
    sliders: dict = field(default_factory=dict)  # title -> (id, step)
    acknowledged: asyncio.Event = field(default_factory=asyncio.Event)
    watchers: list = field(default_factory=list)  # called with every ModelChanged received
    cookies: dict = field(default_factory=dict)  # as a browser keeps them (a proxy's stickiness)
    scrolls: bool = False  # scrolls to the bottom once its readouts are shown
    token: str = ""  # the page's session token (its session's id within)

    async def open(self) -> None:
        self.opened = time.perf_counter()
        request = HTTPRequest(
            self.url, connect_timeout=WAIT, request_timeout=WAIT, headers=self.cookie_header()
        )
        page = await AsyncHTTPClient().fetch(request)
        self.keep_cookies(page.headers)
        token = self.token = TOKEN.search(page.body.decode()).group(1)
        parsed = urlparse(self.url)
        ws_url = f"ws://{parsed.netloc}{parsed.path}/ws"
        headers = {"Origin": f"http://{parsed.netloc}", **self.cookie_header()}
        self.ws = await websocket_connect(
            HTTPRequest(ws_url, request_timeout=WAIT, headers=headers),
            subprotocols=["bokeh", token],
            max_message_size=64 * 1024 * 1024,
        )
        self.ws_cookies = dict(self.cookies)
        self.keep_cookies(self.ws.headers)  # the handshake's answer (behind a proxy)
        self.listening = asyncio.ensure_future(self.listen())
        # The server reads nothing before its ACK (its session is made meanwhile)
        await asyncio.wait_for(self.acknowledged.wait(), WAIT)
        reply = await self.request("PULL-DOC-REQ", {})
        self.read_document(reply["doc"])
        await self.loaded()
        if self.to_readout is None:  # the server was compiling: the readout follows in a patch
            await asyncio.wait_for(self.readout_changed.wait(), WAIT)
        if self.scrolls:
            await asyncio.sleep(self.rng.uniform(1.0, 3.0))
            await self.see_views(EVERY_VIEW)

    def cookie_header(self) -> dict:
        cookie = "; ".join(f"{name}={value}" for name, value in self.cookies.items())
        return {"Cookie": cookie} if cookie else {}

    def keep_cookies(self, headers) -> None:
        for line in headers.get_list("Set-Cookie"):
            name, _, value = line.split(";", 1)[0].partition("=")
            self.cookies[name.strip()] = value.strip()

    async def loaded(self) -> None:
        """What a page sends once BokehJS has rendered it: its browser's facts, document_ready."""
        browser = next(
            (i for i, m in self.models.items() if m["type"].endswith("BrowserInfo")), None
        )
        facts = {
            "dark_mode": False,
            "device_pixel_ratio": 1,
            "language": "en-US",
            "timezone": "UTC",
        }
        for attr, value in facts.items() if browser else ():
            await self.patch([changed(browser, attr, value)])
        ready = {"type": "event", "name": "document_ready", "values": {"type": "map"}}
        event = {"kind": "MessageSent", "msg_type": "bokeh_event", "msg_data": ready}
        await self.patch([event])
        await self.see_views(FIRST_SCREEN)

    async def see_views(self, names: str) -> None:
        """Name the views the page shows, as ``viewport.js`` does (if the page asks)."""
        seen = lambda m: VIEWS_SEEN in (m.get("css_classes") or [])  # noqa: E731
        channel = next((i for i, m in self.models.items() if seen(m)), None)
        if channel is not None:
            await self.patch([changed(channel, "value", names)])

    async def move(self) -> None:
        """Move one slider to a random value on its step; time until the readout changes."""
        title = self.rng.choice([t for t in MOVES if t in self.sliders])
        model, step = self.sliders[title]
        low, high = MOVES[title]
        current = self.models[model].get("value")
        value = current
        while value == current:
            value = round(low + step * self.rng.randrange(int((high - low) / step) + 1), 6)
        await self.move_to(title, value)

    async def move_to(self, title: str, value: float) -> None:
        """Move the slider ``title`` to ``value``; time until the readout changes."""
        model, _ = self.sliders[title]
        self.readout_changed.clear()
        sent = time.perf_counter()
        await self.patch([changed(model, "value", value)], wait=False)
        await self.patch([changed(model, "value_throttled", value)], wait=False)
        self.models[model]["value"] = value
        try:
            await asyncio.wait_for(self.readout_changed.wait(), MOVE_WAIT)
        except TimeoutError:
            self.errors.append(f"no readout within {MOVE_WAIT:.0f} s of moving {title} to {value}")
            return
        self.moves.append((sent, time.perf_counter() - sent))

    # -- Bokeh's protocol: a message is a header, metadata and content frame, then its buffers --

    async def send(self, msgtype: str, content: dict, msgid: str | None = None) -> str:
        msgid = msgid or uuid.uuid4().hex
        for part in ({"msgid": msgid, "msgtype": msgtype}, {}, content):
            await self.ws.write_message(json.dumps(part))
        return msgid

    async def request(self, msgtype: str, content: dict) -> dict:
        answer = asyncio.get_running_loop().create_future()
        msgid = uuid.uuid4().hex
        self.waiting[msgid] = answer
        await self.send(msgtype, content, msgid)
        return await asyncio.wait_for(answer, WAIT)

    async def patch(self, events: list, wait: bool = True) -> None:
        if wait:
            await self.request("PATCH-DOC", {"events": events})
        else:
            await self.send("PATCH-DOC", {"events": events})

    async def listen(self) -> None:
        while True:
            header = await self.ws.read_message()
            if header is None:
                return
            header = json.loads(header)
            await self.ws.read_message()  # metadata
            content = json.loads(await self.ws.read_message())
            for _ in range(2 * header.get("num_buffers", 0)):  # each: its id, then its bytes
                await self.ws.read_message()
            kind = header["msgtype"]
            if kind == "ACK":
                self.acknowledged.set()
            if kind == "ERROR":
                self.errors.append(content.get("text", "ERROR"))
            if "reqid" in header and header["reqid"] in self.waiting:
                self.waiting.pop(header["reqid"]).set_result(content)
            if kind == "PATCH-DOC":
                self.apply(content["events"])

    def register(self, value) -> None:
        """Every model defined in ``value`` (a document's roots, a patch's new value)."""
        if isinstance(value, dict):
            if value.get("type") == "object" and "id" in value and "name" in value:
                attributes = value.get("attributes", {})
                self.models[value["id"]] = {"type": value["name"], **attributes}
            for item in value.values():
                self.register(item)
        elif isinstance(value, list):
            for item in value:
                self.register(item)

    def read_document(self, doc: dict) -> None:
        """Every model of the document with its attributes; the readout and the sliders found."""
        self.register(doc["roots"])
        for model_id, model in self.models.items():
            self.saw_text(model_id, html.unescape(str(model.get("text"))))
            title = model.get("title")
            if model["type"].endswith("Slider") and title in MOVES:
                self.sliders[title] = (model_id, model.get("step", 0.1))

    def apply(self, events: list) -> None:
        for event in events:
            if event.get("kind") != "ModelChanged":
                continue
            model = event["model"]["id"]
            self.register(event["new"])
            for watcher in list(self.watchers):
                watcher(event)
            if model in self.models:
                self.models[model][event["attr"]] = event["new"]
            if event["attr"] == "text" and isinstance(event["new"], str):
                self.saw_text(model, html.unescape(event["new"]))

    def saw_text(self, model_id: str, text: str) -> None:
        """A model's text, as received: a readout's (a move's answer) or not."""
        if READOUTS in text:
            self.readout_ids.add(model_id)
        if READOUT in text:
            self.readout_id = model_id
        if model_id in self.readout_ids:
            self.saw_readout()

    def saw_readout(self) -> None:
        if self.readout_id is None or "L/s" not in html.unescape(
            str(self.models[self.readout_id].get("text"))
        ):
            return  # not a number yet (compiling)
        if self.to_readout is None:
            self.to_readout = time.perf_counter() - self.opened
        self.readout_changed.set()

    def close(self) -> None:
        if getattr(self, "ws", None) is not None:
            self.ws.close()
        if getattr(self, "listening", None) is not None:
            self.listening.cancel()


def changed(model: str, attr: str, new) -> dict:
    return {"kind": "ModelChanged", "model": {"id": model}, "attr": attr, "new": new}


# -- the server, watched -------------------------------------------------------------------------


class Watch:
    """The server's CPU seconds and resident memory, sampled every SAMPLE_EVERY seconds."""

    def __init__(self, pid: int):
        self.pid = pid
        self.samples: list[tuple[float, float, int]] = []  # (perf_counter, CPU [s], RSS [bytes])

    def sample(self) -> tuple[float, float, int]:
        now = (time.perf_counter(), cpu_seconds(self.pid), resident_memory(self.pid))
        self.samples.append(now)
        return now

    async def run(self) -> None:
        while True:
            self.sample()
            await asyncio.sleep(SAMPLE_EVERY)

    async def quiet(self, within: float = 120.0, busy: float = 0.1) -> None:
        """Wait until the server uses under ``busy`` of a core for two seconds (or ``within`` s)."""
        deadline = time.perf_counter() + within
        while time.perf_counter() < deadline:
            _, before, _ = self.sample()
            await asyncio.sleep(2.0)
            _, after, _ = self.sample()
            if after - before < 2.0 * busy:
                return

    def peak(self) -> int:
        return max(rss for _, _, rss in self.samples)


# -- a hall --------------------------------------------------------------------------------------


@dataclass
class Hall:
    """What one hall measured."""

    n: int
    to_readout: list[float]
    open_seconds: float  # [s] first GET -> last readout
    cpu_per_page: float  # [s] the server's CPU from the first GET until it was quiet, per page
    memory: dict[str, int]  # before, idle (all connected), peak, after (closed, settled)
    moves: list[float]  # [s] round trips while students move at their own pace
    burst: list[float]  # [s] round trips of BURST students moving at the same moment
    upload: dict[str, list[float]]  # round trips before/while/after one student's 10 MB upload
    errors: list[str]
    scrolled: int = 0  # students who scrolled to the bottom
    flights: list[tuple[float, float]] = field(default_factory=list)  # (sent, round trip) [s]
    # the sent times in time.time(); every move's, the hall's opening to its end


BURST = 30  # students who move at the same moment
BURSTS = 3  # times they do, BURST_PAUSE [s] apart
BURST_PAUSE = 2.0


async def a_hall(
    url: str, n: int, minutes: float, watch: Watch, upload: bool, scroll: float = 0.0
) -> Hall:
    rng = random.Random(n)
    students = [Student(url, random.Random(rng.random())) for _ in range(n)]
    for i in random.Random(n + 1).sample(range(n), round(scroll * n)):
        students[i].scrolls = True
    delays = sorted(rng.uniform(0.0, OPEN_WITHIN) for _ in range(n))
    sampling = asyncio.ensure_future(watch.run())
    await watch.quiet(within=30.0)
    _, cpu0, before = watch.sample()
    started = time.perf_counter()

    async def arrive(student: Student, delay: float) -> None:
        await asyncio.sleep(delay)
        try:
            await asyncio.wait_for(student.open(), WAIT)
        except Exception as error:  # noqa: BLE001 - recorded, the hall goes on
            student.errors.append(f"opening: {error!r}")

    await asyncio.gather(*(arrive(s, d) for s, d in zip(students, delays, strict=True)))
    opened = time.perf_counter() - started
    await watch.quiet()
    _, cpu1, idle = watch.sample()
    here = [s for s in students if s.to_readout is not None]
    burst: list[float] = []
    for _ in range(BURSTS):
        burst += await moving_at_once(here[:BURST])
        await asyncio.sleep(BURST_PAUSE)
    paced, around = await moving(here, minutes, url if upload else None)
    wall = time.time() - time.perf_counter()  # perf_counter -> time.time()
    flights = [(wall + sent, trip) for s in here for sent, trip in s.moves]
    for student in students:
        student.close()
    sampling.cancel()
    after = await settled(watch, before)
    return Hall(
        n=n,
        to_readout=[s.to_readout for s in here],
        open_seconds=opened,
        cpu_per_page=(cpu1 - cpu0) / n,
        memory={"before": before, "idle": idle, "peak": watch.peak(), "after": after},
        moves=paced,
        burst=burst,
        upload=around,
        errors=[e for s in students for e in s.errors],
        scrolled=sum(s.scrolls for s in students),
        flights=flights,
    )


async def moving_at_once(students: list[Student]) -> list[float]:
    """Every one of ``students`` moves a slider at the same moment: their round trips."""
    counts = [len(s.moves) for s in students]
    await asyncio.gather(*(s.move() for s in students))
    return [rt for s, k in zip(students, counts, strict=True) for _, rt in s.moves[k:]]


async def moving(students: list[Student], minutes: float, upload_to: str | None):
    """Each student moves a slider every 5-20 s for ``minutes``; with ``upload_to``, one more
    student loads a 10 MB wind record meanwhile. The round trips, and those before / while /
    after the upload (by when the move was sent)."""
    end = time.perf_counter() + 60.0 * minutes
    first = [len(s.moves) for s in students]

    async def pace(student: Student) -> None:
        while True:
            await asyncio.sleep(student.rng.uniform(*MOVE_EVERY))
            if time.perf_counter() >= end:
                return
            await student.move()

    tasks = [pace(s) for s in students]
    window: list[float] = []
    if upload_to is not None:
        witnessed: dict[str, list[float]] = {}
        tasks.append(one_upload(upload_to, end, window, witnessed))
    await asyncio.gather(*tasks)
    sent = [(t, rt) for s, k in zip(students, first, strict=True) for t, rt in s.moves[k:]]
    around: dict[str, list[float]] = {"before": [], "while": [], "after": []}
    if window:
        for t, rt in sent:
            phase = "before" if t < window[0] else "while" if t <= window[1] else "after"
            around[phase].append(rt)
        around["window"] = [window[1] - window[0]]  # [s] from its first byte to its reading
        around.update(witnessed)
    return [rt for _, rt in sent], around


SETTLE_WITHIN = 90.0  # [s] the longest the memory after a hall is waited for


async def settled(watch: Watch, target: int) -> int:
    """The server's memory once it falls within 10 % of ``target`` or SETTLE_WITHIN s pass."""
    deadline = time.perf_counter() + SETTLE_WITHIN
    while True:
        _, _, rss = watch.sample()
        if rss <= 1.1 * target or time.perf_counter() > deadline:
            return rss
        await asyncio.sleep(2.0)


# -- one student loads a 10 MB wind record -------------------------------------------------------

UPLOAD_NAME = "hall-wind-10MB.csv"
CHANNEL = "upload-refused"  # the CSS class of the page's upload channel (app/uploads.py)
UPLOAD_BYTES = 9_900_000  # the page takes up to 10 MB


def wind_record(size: int) -> bytes:
    """A wind CSV of ``size`` bytes at most (the page's limit is 10 MB): one sample a second."""
    rng = random.Random(24)
    lines, total, t = ["time_s,wind_m_s"], 0, 0
    while total < size - 40:
        line = f"{t},{5.0 + 3.0 * rng.random():.6f}"
        lines.append(line)
        total += len(line) + 1
        t += 1
    return "\n".join(lines).encode()


WITNESSES = 10  # students who move at once as the upload is sent, and 2 s before it
# Their moves: witness k sets the windmill's torque to CALM_TORQUE + k * TORQUE_APART 2 s before the
# upload and to that + TORQUE_APART / 2 just after it: designs no other page of the hall holds
# (MOVES keeps T_m <= 1.5), so both times each move's run is worked out, not shared with a page
# (``session.shared_explore``), and the two bursts do the same work. Random moves of the hall's
# kind were shared more often the first time than the second: the ten's round trips were half as
# long 2 s before the upload, with or without one.
WITNESS_SLIDER = TITLE["T_m"]
CALM_TORQUE, TORQUE_APART = 1.55, 0.1  # [N·m]


async def one_upload(
    url: str, end: float, window: list[float], witnessed: dict[str, list[float]]
) -> None:
    """A student who opens the Wind tab and loads a 10 MB record, in a process of its own as a
    student's browser is (``bench_upload.loader``: the bytes by HTTP POST, their reference over
    the websocket; to a server without the route, the FileInput's value in base64). ``window``
    gets (sent, the server reading it) [perf_counter]. WITNESSES more students (who move at no
    other time) move at once 2 s before the upload and again 10 ms after its first byte, each
    to a design no other page holds (WITNESS_SLIDER): ``witnessed`` gets their round trips [s],
    "calm" and "sending"."""
    witnesses = [Student(url, random.Random(100 + k)) for k in range(WITNESSES)]
    loader = Path(__file__).resolve().parent / "bench_upload.py"
    child = await asyncio.create_subprocess_exec(
        sys.executable,
        str(loader),
        "--loader",
        url,
        str(UPLOAD_BYTES),
        stdin=asyncio.subprocess.PIPE,
        stdout=asyncio.subprocess.PIPE,
    )
    assert child.stdin is not None and child.stdout is not None
    try:
        await asyncio.gather(*(w.open() for w in witnesses))
        ready = await asyncio.wait_for(child.stdout.readline(), WAIT)  # its page and Wind tab
        if not ready.startswith(b"ready"):
            raise RuntimeError(f"the uploading student's process did not start: {ready!r}")
        await asyncio.sleep(max(0.0, min(15.0, (end - time.perf_counter()) / 3)))
        torque = [CALM_TORQUE + k * TORQUE_APART for k in range(WITNESSES)]
        witnessed["calm"] = await moving_to(witnesses, torque)
        await asyncio.sleep(2.0)
        window.append(time.perf_counter())
        child.stdin.write(b"go\n")
        await child.stdin.drain()
        await asyncio.sleep(0.01)
        witnessed["sending"] = await moving_to(witnesses, [t + TORQUE_APART / 2 for t in torque])
        read = await asyncio.wait_for(child.stdout.readline(), WAIT)
        if not read.startswith(b"read"):
            raise RuntimeError(f"the uploading student's process: {read!r}")
        window.append(time.perf_counter())
        await asyncio.wait_for(child.wait(), WAIT)
    finally:
        if child.returncode is None:
            child.kill()
            await child.wait()
        for one in witnesses:
            one.close()


async def moving_to(students: list[Student], torques: list[float]) -> list[float]:
    """Each student sets the windmill's torque [N·m] at the same moment: their round trips."""
    counts = [len(s.moves) for s in students]
    await asyncio.gather(
        *(s.move_to(WITNESS_SLIDER, round(t, 6)) for s, t in zip(students, torques, strict=True))
    )
    return [rt for s, k in zip(students, counts, strict=True) for _, rt in s.moves[k:]]


async def has_upload_route(student: Student) -> bool:
    """Whether the server has the upload route (``app/server/upload_route.py``): an empty POST is
    refused there in words, and answered 404 by a server without it."""
    parsed = urlparse(student.url)
    request = HTTPRequest(
        f"http://{parsed.netloc}{parsed.path}/upload?kind=wind",
        method="POST",
        body=b"",
        headers=student.cookie_header(),
        request_timeout=WAIT,
    )
    response = await AsyncHTTPClient().fetch(request, raise_error=False)
    return response.code not in (404, 405)


async def in_base64(student: Student, upload: str, record: bytes) -> None:
    """The file as a page without the upload route sends it: the FileInput's value, in base64,
    in one message over the websocket."""
    import base64

    data = base64.b64encode(record).decode()
    await student.patch(
        [
            changed(upload, "mime_type", "text/csv"),
            changed(upload, "filename", UPLOAD_NAME),
            changed(upload, "value", data),
        ],
        wait=False,
    )


async def wind_tab(student: Student) -> str:
    """Open the student's Wind tab; its upload's model id, once the tab has arrived."""
    panels = [i for i, m in student.models.items() if m["type"] == "TabPanel"]
    wind = next(i for i in panels if student.models[i].get("title") == "Wind")
    tabs = next(
        (i, m)
        for i, m in student.models.items()
        if m["type"].endswith("Tabs") and wind in [t.get("id") for t in m.get("tabs", [])]
    )
    index = [t.get("id") for t in tabs[1]["tabs"]].index(wind)
    await student.patch([changed(tabs[0], "active", index)])
    deadline = time.perf_counter() + WAIT
    wind_input = lambda m: "wind-upload" in m.get("css_classes", [])  # noqa: E731
    while not any(wind_input(m) for m in student.models.values()):
        if time.perf_counter() > deadline:
            raise TimeoutError("the Wind tab's upload never arrived")
        await asyncio.sleep(0.2)
    return next(i for i, m in student.models.items() if wind_input(m))


async def post_upload(student: Student, data: bytes) -> int:
    """Send ``data`` as the page sends a wind file: "sending" on its upload channel, the bytes
    by HTTP POST (the session's id from its token in the page's header, the student's cookies:
    a proxy's stickiness), then "posted <id>" (or why not). The POST's HTTP status: 404 or 405,
    the server has no upload route (nothing more is sent)."""
    from urllib.parse import urlencode

    from bokeh.util.token import get_session_id

    channel = next(i for i, m in student.models.items() if CHANNEL in m.get("css_classes", []))

    async def tell(state: str) -> None:
        value = f"{len(data)}\t{int(1e3 * time.time())}\twind\t{UPLOAD_NAME}\t{state}"
        await student.patch([changed(channel, "value", value)], wait=False)

    parsed = urlparse(student.url)
    query = urlencode({"kind": "wind", "name": UPLOAD_NAME})
    await tell("sending")
    request = HTTPRequest(
        f"http://{parsed.netloc}{parsed.path}/upload?{query}",
        method="POST",
        body=data,
        headers={
            "Content-Type": "application/octet-stream",
            SESSION_HEADER: get_session_id(student.token),
            **student.cookie_header(),
        },
        request_timeout=WAIT,
    )
    response = await AsyncHTTPClient().fetch(request, raise_error=False)
    if response.code in (404, 405):
        return response.code
    answer = json.loads(response.body or b"{}")
    await tell(f"posted {answer['id']}" if response.code == 200 else f"failed {answer['refused']}")
    return response.code


# -- the report ----------------------------------------------------------------------------------


def percentiles(values: list[float], unit: float = 1.0, fmt: str = "{:.2f}") -> str:
    if not values:
        return "none"
    ordered = sorted(values)
    pick = lambda q: ordered[min(len(ordered) - 1, int(q * len(ordered)))]  # noqa: E731
    parts = [f"p{int(q * 100)} {fmt.format(pick(q) * unit)}" for q in (0.5, 0.9, 0.95)]
    return ", ".join(parts) + f", max {fmt.format(ordered[-1] * unit)} ({len(values)})"


def report(hall: Hall) -> None:
    mb = 1e6
    memory = hall.memory
    print(f"hall of {hall.n}: opened within {OPEN_WITHIN:.0f} s, load {os.getloadavg()[0]:.1f}")
    print(
        f"  views: each page names its first screen's ({FIRST_SCREEN}); {hall.scrolled} of "
        f"{hall.n} then scroll to the bottom (every view)"
    )
    print(
        f"  readouts [s]: {percentiles(hall.to_readout)}; all {len(hall.to_readout)} within "
        f"{hall.open_seconds:.1f} s of the first GET"
    )
    print(f"  server CPU per page: {hall.cpu_per_page:.3f} s (page, websocket, views, until quiet)")
    print(f"  moves at their own pace, round trip [ms]: {percentiles(hall.moves, 1e3, '{:.0f}')}")
    print(
        f"  {BURST} moving at once ({BURSTS} times), round trip [ms]: "
        f"{percentiles(hall.burst, 1e3, '{:.0f}')}"
    )
    for phase in ("before", "while", "after"):
        trips = hall.upload.get(phase, [])
        print(f"  others' moves {phase} a 10 MB upload [ms]: {percentiles(trips, 1e3, '{:.0f}')}")
    for phase, when in (("calm", "2 s before it"), ("sending", "10 ms after its first byte")):
        trips = hall.upload.get(phase, [])
        print(f"  {WITNESSES} more moving at once {when} [ms]: {percentiles(trips, 1e3, '{:.0f}')}")
    if hall.upload.get("window"):
        print(
            f"  the upload, from its first byte to the server reading it: {hall.upload['window'][0]:.2f} s"
        )
    per_session = (memory["idle"] - memory["before"]) / hall.n / mb
    print(
        f"  server memory [MB]: before {memory['before'] / mb:.0f}, {hall.n} idle "
        f"{memory['idle'] / mb:.0f} ({per_session:.2f} a session), peak "
        f"{memory['peak'] / mb:.0f}, after closing {memory['after'] / mb:.0f} "
        f"({memory['after'] / memory['before']:.2f}x before)"
    )
    if hall.errors:
        print(f"  errors ({len(hall.errors)}): {hall.errors[:3]}")


# -- what held up the server's loop (--watch) ---------------------------------------------------

SLOW_TRIP = 0.5  # [s] a round trip this long or longer is looked into


def read_watch(path: str) -> list[dict]:
    """The lines a server with WINDPUMP_LOOP_WATCH=path wrote (serving.LoopWatch)."""
    if not os.path.exists(path):
        return []
    with open(path) as lines:
        return [json.loads(line) for line in lines if line.strip()]


def stalls(events: list[dict], flights: list[tuple[float, float]]) -> list[str]:
    """What held up the loop beside the slow round trips: lines of the report."""
    start = min((sent for sent, _ in flights), default=0.0)
    end = max((sent + trip for sent, trip in flights), default=0.0)
    events = [e for e in events if start <= e["t"] - e["seconds"] and e["t"] <= end]
    full = [e["seconds"] for e in events if e["kind"] == "gc" and e["generation"] == 2]
    young = [e["seconds"] for e in events if e["kind"] == "gc" and e["generation"] < 2]
    lags = [e["seconds"] for e in events if e["kind"] == "lag"]
    slow = [(sent, trip) for sent, trip in flights if trip >= SLOW_TRIP]

    def during(kind: str, sent: float, trip: float) -> bool:
        return any(
            e["kind"] == kind and e["t"] - e["seconds"] < sent + trip and e["t"] > sent
            for e in events
            if e["kind"] != "gc" or e["generation"] == 2 or e["seconds"] >= 0.2
        )

    with_gc = sum(during("gc", sent, trip) for sent, trip in slow)
    with_lag = sum(during("lag", sent, trip) for sent, trip in slow)
    longest = lambda xs: f"{max(xs):.2f}" if xs else "-"  # noqa: E731
    return [
        f"  while moving: {len(full)} full collections ({sum(full):.1f} s, longest "
        f"{longest(full)} s), {len(young)} slow young ones; the loop late by >= 50 ms "
        f"{len(lags)} times ({sum(lags):.1f} s, longest {longest(lags)} s)",
        f"  round trips of {SLOW_TRIP} s or more: {len(slow)} of {len(flights)}; with a full "
        f"collection in flight {with_gc}, with the loop late in flight {with_lag}",
    ]


# Closed sessions are dropped 30 s after their last connection (checked every 2 s), so the
# memory after a hall can be read within a minute; `panel serve app/` alone keeps them 10 min.
SERVE = ["--unused-session-lifetime", "30000", "--check-unused-sessions", "2000"]


def run(n: int, minutes: float, upload: bool, watch: bool = False, scroll: float = 0.0) -> Hall:
    """One hall of ``n`` on a fresh `panel serve app/`; ``watch``: what held up its loop;
    ``scroll``: the fraction of students who scroll through every view."""
    # Each student's browser opens its own connections: not Tornado's default pool of 10
    AsyncHTTPClient.configure(None, max_clients=MAX_SESSIONS + 1)
    if not 1 <= n <= MAX_SESSIONS:
        raise SystemExit(f"1 <= N <= {MAX_SESSIONS}")
    watched = f"/tmp/bench_hall-watch-{os.getpid()}-{n}.jsonl" if watch else ""
    if watched and os.path.exists(watched):
        os.remove(watched)
    os.environ["WINDPUMP_LOOP_WATCH"] = watched  # the server inherits it; empty: not watched
    try:
        with served_app(*SERVE) as (address, server):
            loopback(address)
            warm = Student(address, random.Random(0))  # imports, caches: not the hall's cost
            asyncio.run(asyncio.wait_for(warm_up(warm), WAIT))
            hall = asyncio.run(a_hall(address, n, minutes, Watch(server.pid), upload, scroll))
    finally:
        del os.environ["WINDPUMP_LOOP_WATCH"]
    report(hall)
    if watched:
        print("\n".join(stalls(read_watch(watched), hall.flights)))
        print(f"  (the server's watch: {watched})")
    return hall


async def warm_up(student: Student) -> None:
    await student.open()
    await student.move()
    student.close()


def main(argv: list[str] | None = None) -> list[Hall]:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("n", nargs="*", type=int, default=[30, 100, 200])
    parser.add_argument("--minutes", type=float, default=1.0, help="of moves (default 1)")
    parser.add_argument("--upload", action="store_true", help="one student loads 10 MB")
    parser.add_argument("--watch", action="store_true", help="what holds up the server's loop")
    parser.add_argument(
        "--scroll", type=float, default=0.0, help="fraction of students scrolling (default 0)"
    )
    args = parser.parse_args(argv)
    if not 0.0 <= args.scroll <= 1.0:
        raise SystemExit("--scroll FRACTION: 0 <= FRACTION <= 1")
    print(f"bench_hall on {os.cpu_count()} cores, load {os.getloadavg()}, --scroll {args.scroll:g}")
    minutes = min(args.minutes, 10.0)
    return [run(n, minutes, args.upload, args.watch, args.scroll) for n in args.n]


if __name__ == "__main__":
    main()
