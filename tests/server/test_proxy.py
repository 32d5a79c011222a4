"""Two `panel serve app/` processes behind nginx (app/server/proxy.py, app/server/nginx.conf), on loopback:
students spread over both, each page's websocket reaches the process that built it, and with one
process killed its pages reopen on the other from their link, saying so.

Talks only to 127.0.0.1; a handful of protocol-level students (benchmarks/bench_hall.py)."""

from __future__ import annotations

import asyncio
import html
import logging
import random
import subprocess
import sys
from pathlib import Path
from urllib.parse import urlparse

import pytest

from windpump_app.server import proxy

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
import bench_hall  # noqa: E402

STUDENTS = 6
COOKIE = "windpump_process"


def test_the_config_names_every_process_and_listens_where_asked(tmp_path):
    text = proxy.nginx_config("127.0.0.1:8081", [5001, 5002], str(tmp_path))
    assert "listen 127.0.0.1:8081;" in text
    assert text.count("server 127.0.0.1:5001") == 1 and text.count("server 127.0.0.1:5002") == 1
    assert '"127.0.0.1:5002" 127.0.0.1:5002;' in text
    assert "@" not in text.replace("@pool", "")  # every field filled in


def test_the_servers_start_with_jemalloc_and_python_hands_it_its_small_objects(tmp_path):
    library = tmp_path / "lib" / proxy.JEMALLOC
    library.parent.mkdir()
    library.write_bytes(b"")
    assert proxy.jemalloc_library((str(tmp_path / "none"), str(library.parent))) == str(library)
    env = proxy.allocator_env("jemalloc", {"PATH": "/bin", "LD_PRELOAD": "x.so"}, str(library))
    assert env["LD_PRELOAD"] == f"{library} x.so" and env["PYTHONMALLOC"] == "malloc"
    assert env["MALLOC_CONF"] == proxy.JEMALLOC_CONF and env["PATH"] == "/bin"
    mine = proxy.allocator_env("jemalloc", {"MALLOC_CONF": "narenas:1"}, str(library))
    assert mine["MALLOC_CONF"] == "narenas:1"  # an instructor's own setting is kept
    assert proxy.allocator_env("malloc", {})["PYTHONMALLOC"] == "malloc"
    assert proxy.allocator_env("python", {"A": "1"}) == {"A": "1"}
    with pytest.raises(ValueError, match="tcmalloc"):
        proxy.allocator_env("tcmalloc", {})


def test_without_jemalloc_the_servers_start_as_panel_serve_does_and_say_so(monkeypatch, caplog):
    monkeypatch.setattr(proxy, "LIBRARY_DIRS", ("/nonexistent",))
    with caplog.at_level(logging.WARNING, logger="windpump.app"):
        env = proxy.allocator_env("jemalloc", {"A": "1"})
    assert env == {"A": "1"}
    assert "jemalloc" in caplog.text and "apt-get install -y libjemalloc2" in caplog.text


def test_each_process_of_the_hall_gets_the_allocator(monkeypatch):
    """hall() hands each server the environment allocator_env builds (nginx is not reached)."""
    started = []

    class Started(Exception):
        pass

    def popen(command, env=None, **_):
        started.append((command, env))
        raise Started

    monkeypatch.setattr(proxy.subprocess, "Popen", popen)
    monkeypatch.setattr(proxy, "NGINX", sys.executable)  # present: the check passes
    monkeypatch.setattr(proxy, "jemalloc_library", lambda: "/opt/libjemalloc.so.2")
    with pytest.raises(Started), proxy.hall(2, "127.0.0.1:1", ["127.0.0.1:1"]):
        pass
    ((command, env),) = started
    assert command[1:4] == ["-m", "panel", "serve"]
    assert env["LD_PRELOAD"].startswith("/opt/libjemalloc.so.2")
    assert env["PYTHONMALLOC"] == "malloc" and env["MALLOC_CONF"] == proxy.JEMALLOC_CONF


# The proxy's main() with hall() replaced by one that says when it stops its processes; its wait
# sends the proxy itself a SIGTERM, as `kill`, systemd or docker stop it.
STOPPED_BY_SIGTERM = """
import contextlib, os, signal, sys
from windpump_app.server import proxy

class Running:
    def poll(self):
        return None

@contextlib.contextmanager
def hall(*args, **kwargs):
    try:
        yield [Running()], Running(), [1]
    finally:
        print("servers and nginx stopped", flush=True)

proxy.hall = hall
proxy._names = lambda: ["localhost"]
proxy.time.sleep = lambda seconds: os.kill(os.getpid(), signal.SIGTERM)
sys.exit(proxy.main(["--processes", "1", "--port", "1"]))
"""


def test_a_sigterm_stops_the_servers_and_nginx_as_ctrl_c_does():
    """Python's default for SIGTERM ended the proxy at once: its panel servers and nginx
    ran on, orphaned, holding their ports."""
    done = subprocess.run(
        [sys.executable, "-c", STOPPED_BY_SIGTERM], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    assert "servers and nginx stopped" in done.stdout


def test_a_process_started_so_runs_on_jemalloc():
    from served import require_jemalloc

    library = require_jemalloc()
    code = "print(open('/proc/self/maps').read())"
    env = proxy.allocator_env("jemalloc")
    assert env["LD_PRELOAD"].split()[0] == library
    maps = subprocess.run(
        [sys.executable, "-c", code],
        env=env,
        capture_output=True,
        text=True,
        timeout=60,
        check=True,
    ).stdout
    assert "libjemalloc" in maps


def shown_text(student, needle: str) -> bool:
    return any(needle in html.unescape(str(m.get("text", ""))) for m in student.models.values())


async def a_class_behind_the_proxy(url: str, servers, ports):
    students = [bench_hall.Student(url, random.Random(k)) for k in range(STUDENTS)]
    for student in students:  # one after the other: round robin alternates
        await asyncio.wait_for(student.open(), 300)
    for student in students:
        await student.move()
    seen = {"built on": [s.ws_cookies[COOKIE] for s in students]}
    seen["connected to"] = [s.cookies[COOKIE] for s in students]
    seen["moves"] = [len(s.moves) for s in students]
    # A wind file posted by HTTP (app/server/upload_route.py) reaches the process of its page's session,
    # by the same cookie; sent to the other process, it is refused (no such session there).
    record = bench_hall.wind_record(200_000)
    seen["posted"] = [await bench_hall.post_upload(s, record) for s in students]
    elsewhere = bench_hall.Student(url, random.Random(0))
    elsewhere.token, elsewhere.models = students[0].token, students[0].models
    other = next(b for b in seen["built on"] if b != seen["built on"][0])
    elsewhere.cookies, elsewhere.ws = {COOKIE: other}, students[0].ws
    seen["elsewhere"] = await bench_hall.post_upload(elsewhere, record)
    # One process dies: its pages lose their websocket and reopen from their link, as the page's
    # script does (serving.RECONNECT_JS), with ?restored=true.
    victim = f"127.0.0.1:{ports[0]}"
    servers[0].kill()
    servers[0].wait(timeout=30)
    lost = [s for s in students if s.cookies[COOKIE] == victim]
    reopened = []
    for student in lost:
        student.close()
        head = student.models[student.sliders["Head h [m]"][0]]["value"]
        again = bench_hall.Student(f"{url}?h={head:g}&restored=true", random.Random(0))
        again.cookies = dict(student.cookies)  # the browser still names the dead process
        await asyncio.wait_for(again.open(), 300)
        value = again.models[again.sliders["Head h [m]"][0]]["value"]
        reopened.append((head, value, again.cookies[COOKIE], shown_text(again, "was lost")))
        again.close()
    for student in students:
        student.close()
    return seen, victim, reopened


@pytest.mark.timeout(900)
def test_sessions_spread_stick_and_reopen_on_the_other_process():
    from served import require_nginx

    require_nginx()
    port = proxy.free_port()
    origin = f"127.0.0.1:{port}"
    with proxy.hall(2, origin, [origin]) as (servers, _nginx, ports):
        url = f"http://{origin}/app"
        assert urlparse(url).hostname == "127.0.0.1"
        seen, victim, reopened = asyncio.run(a_class_behind_the_proxy(url, servers, ports))
    backends = {f"127.0.0.1:{p}" for p in ports}
    assert set(seen["built on"]) == backends  # spread over both
    assert seen["connected to"] == seen["built on"]  # each websocket reached its page's process
    assert seen["moves"] == [1] * STUDENTS  # each move answered (by its own process)
    assert seen["posted"] == [200] * STUDENTS and seen["elsewhere"] == 403
    assert reopened, "no page was on the killed process"
    for head, value, now_on, notice in reopened:
        assert value == pytest.approx(head)  # the state from the link
        assert now_on != victim and now_on in backends
        assert notice  # "The connection to the server was lost and is back"


@pytest.mark.browser
@pytest.mark.timeout(600)
def test_a_page_that_loses_its_server_says_so_and_reopens_from_its_link(tmp_path):
    """Wi-Fi drops, or the server restarts: the page says it lost the connection, and once the
    server answers again it reopens from its link (its design kept) and says it was restored."""
    from playwright.sync_api import sync_playwright

    from served import CHROMIUM, CHROMIUM_FLAGS, DEEP_TEXT, require_chromium

    require_chromium()
    port = proxy.free_port()
    origin = f"127.0.0.1:{port}"
    log = (tmp_path / "server.log").open("w")

    def serve():
        server = proxy.subprocess.Popen(proxy.panel_command(port, [origin]), stdout=log, stderr=log)
        proxy.wait_until_up(f"http://{origin}/static/js/bokeh.min.js", server, 180)
        return server

    server = serve()
    try:
        with sync_playwright() as playwright:
            browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_FLAGS)
            page = browser.new_page()
            page.set_default_timeout(120_000)
            page.goto(f"http://{origin}/app?h=4.2")
            page.wait_for_function(f"() => ({DEEP_TEXT})('[data-name=mean_flow]') !== null")
            proxy.stop(server)
            page.wait_for_selector("#windpump-offline")
            assert "lost" in page.inner_text("#windpump-offline")
            server = serve()
            page.wait_for_url("**restored=true**")
            page.get_by_text("The connection to the server was lost and is back").filter(
                visible=True
            ).wait_for()
            page.wait_for_function("() => !window.location.search.includes('restored')")
            assert "h=4.2" in page.url  # the design, from the link, and the notice not kept in it
            assert page.locator(".bk-slider-title", has_text="Head h [m]: 4.2").count() == 1
            browser.close()
    finally:
        proxy.stop(server)


async def a_page_with_a_long_link(url: str) -> tuple[int, bool]:
    student = bench_hall.Student(url, random.Random(0))
    await asyncio.wait_for(student.open(), 300)
    said = shown_text(student, "The link was too long")
    student.close()
    return len(url), said


@pytest.mark.timeout(600)
def test_behind_the_proxy_a_link_too_long_gets_the_pages_notice_not_nginxs_414():
    """A 100 KB link reaches the app, which opens the page and says it ignored the link."""
    from served import require_nginx

    require_nginx()
    port = proxy.free_port()
    origin = f"127.0.0.1:{port}"
    with proxy.hall(1, origin, [origin]):
        long_link = f"http://{origin}/app?h=3&note={'x' * 100_000}"
        length, said = asyncio.run(a_page_with_a_long_link(long_link))
    assert length > 100_000 and said
