"""The explorer served by a real `panel serve app/` on a free loopback port, and Debian's chromium.

Shared by the browser test, the load test and benchmarks/bench_app.py.
"""

from __future__ import annotations

import contextlib
import os
import socket
import subprocess
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path

APP = Path(__file__).resolve().parents[1] / "app"
CHROMIUM = "/usr/bin/chromium"
CHROMIUM_FLAGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking"]

# Finds an element through open shadow roots (Panel renders each component in one) and returns its
# text; playwright's locators pierce shadow DOM, but code run in the page has to walk it.
DEEP_TEXT = """(selector) => {
  const walk = (root) => {
    const hit = root.querySelector(selector);
    if (hit) return hit;
    for (const el of root.querySelectorAll('*')) {
      if (el.shadowRoot) { const found = walk(el.shadowRoot); if (found) return found; }
    }
    return null;
  };
  const el = walk(document);
  return el ? el.textContent : null;
}"""

# Every page a browser test opened (test_browser.open_page), with the requests each made to
# another host than its server (``page.elsewhere``): tests/conftest.py fails a test whose
# pages asked the internet for anything (a font, a stylesheet, a script).
OPENED_PAGES: list = []

# How often a class's pages are checked [ms]: playwright's default checks on every animation
# frame, and 30 pages walking their DOM 60 times a second cost chromium more than the pages do.
POLL_MS = 250

# True once a page's views are drawn: the crank-speed band holds data (a served page gets its views
# after its readouts, Explorer.show_views).
VIEWS_DRAWN = (
    "() => { const s = window.Bokeh.documents[0].get_model_by_name('speed');"
    " return s !== null && s.data.upper.length > 0 }"
)

# The pump's views are built when the page first shows them (app/viewport.js): a test that needs
# one below the first screen scrolls to it, as a person would, and waits for it (``show_view``).
# Scrolls the placeholder of view ``name`` into the middle of the screen, unless it is drawn.
# The element of view ``name`` (``.view-<name>``: its placeholder or the view), through the
# template's shadow roots: ``const el = walk(document)`` in a script taking ``name``.
FIND_VIEW = """
  const walk = (root) => {
    const hit = root.querySelector('.view-' + name);
    if (hit) return hit;
    for (const el of root.querySelectorAll('*')) {
      if (el.shadowRoot) { const found = walk(el.shadowRoot); if (found) return found; }
    }
    return null;
  };
  const el = walk(document);"""
SCROLL_TO_VIEW = (
    """(name) => {
  const model = window.Bokeh.documents[0].get_model_by_name(name + '_figure');
  if (model !== null && window.Bokeh.index.find_one(model)) return 'drawn';"""
    + FIND_VIEW
    + """
  if (el !== null) el.scrollIntoView({block: 'center'});
  return el !== null ? 'scrolled' : 'missing';
}"""
)
VIEW_DRAWN = """(name) => {
  const model = window.Bokeh.documents[0].get_model_by_name(name + '_figure');
  const view = model && window.Bokeh.index.find_one(model);
  return view != null && view.el.isConnected && view.el.getBoundingClientRect().height > 0;
}"""


def show_view(page, name: str, timeout: float = 60_000) -> None:
    """Scroll to the pump's view ``name`` (``speed``, ``flow``...) unless it is drawn already, and
    wait until it is, at most ``timeout`` [ms]."""
    page.evaluate(SCROLL_TO_VIEW, name)
    page.wait_for_function(VIEW_DRAWN, arg=name, timeout=timeout, polling=POLL_MS)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@contextlib.contextmanager
def served_app(
    *extra_args: str,
    timeout: float = 180.0,
    python: str = sys.executable,
    env: dict[str, str] | None = None,
) -> Iterator[tuple[str, subprocess.Popen]]:
    """Start `panel serve app/` on 127.0.0.1 (with the interpreter ``python``: another
    environment's; ``env``: its environment, else this one's); yield (page URL, process); stop
    it afterwards.

    The server's output goes to a temporary file, never a pipe: a pipe nobody reads fills up and
    stops a chatty server (``server_log(process)`` reads it). Waiting for it is bounded by
    ``timeout`` [s]; the log is shown if it does not come up.
    """
    port = free_port()
    command = [
        python,
        "-m",
        "panel",
        "serve",
        str(APP),
        "--port",
        str(port),
        "--address",
        "127.0.0.1",
        "--allow-websocket-origin",
        f"127.0.0.1:{port}",
        *extra_args,
    ]
    url = f"http://127.0.0.1:{port}/app"
    with tempfile.TemporaryFile("w+") as log:
        process = subprocess.Popen(
            command, stdout=log, stderr=subprocess.STDOUT, text=True, env=env
        )
        process.log = log  # type: ignore[attr-defined]
        try:
            # A static file, not the page: asking for the page would open the server's first session
            wait_until_up(f"http://127.0.0.1:{port}/static/js/bokeh.min.js", process, log, timeout)
            yield url, process
        finally:
            process.terminate()
            try:
                process.wait(timeout=15)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait(timeout=15)


def server_log(process: subprocess.Popen) -> str:
    """Everything a server started by ``served_app`` has written so far (stdout and stderr)."""
    fd = process.log.fileno()  # type: ignore[attr-defined]
    # pread: the server writes through the same file offset, which a seek would move
    return os.pread(fd, os.fstat(fd).st_size, 0).decode("utf-8", "replace")


def wait_until_up(url: str, process: subprocess.Popen, log, timeout: float) -> None:
    """The proxy's wait (:func:`windpump_app.server.proxy.wait_until_up`), with the server's log when
    it does not come up."""
    from windpump_app.server import proxy

    try:
        proxy.wait_until_up(url, process, timeout)
    except RuntimeError:
        log.seek(0)
        raise RuntimeError(
            f"panel serve did not come up within {timeout:.0f} s:\n{log.read()}"
        ) from None


def require_chromium() -> None:
    """Skip on a user's machine without Debian's chromium; in CI its absence is a failure."""
    import pytest

    if Path(CHROMIUM).exists():
        return
    if os.environ.get("CI"):
        pytest.fail(f"CI must run the browser tests, but {CHROMIUM} is missing")
    pytest.skip(f"{CHROMIUM} is not installed (apt-get install -y chromium)")


def require_nginx() -> None:
    """Skip on a user's machine without Debian's nginx; in CI its absence is a failure."""
    import pytest

    from windpump_app.server import proxy

    if Path(proxy.NGINX).exists():
        return
    if os.environ.get("CI"):
        pytest.fail(f"CI must run the proxy tests, but {proxy.NGINX} is missing")
    pytest.skip(f"{proxy.NGINX} is not installed (apt-get install -y nginx)")


def require_jemalloc() -> str:
    """jemalloc's library, which the proxy's processes start on; skip on a user's machine
    without it (they fall back to Python's allocator); in CI its absence is a failure."""
    import pytest

    from windpump_app.server import proxy

    library = proxy.jemalloc_library()
    if library is not None:
        return library
    if os.environ.get("CI"):
        pytest.fail(f"CI must run the proxy on jemalloc, but {proxy.JEMALLOC} is missing")
    pytest.skip(f"{proxy.JEMALLOC} is not installed (apt-get install -y libjemalloc2)")


def resident_memory(pid: int) -> int:
    """Resident set size of a process [bytes], from /proc."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) * 1024
    raise RuntimeError(f"no VmRSS for process {pid}")


def cpu_seconds(pid: int) -> float:
    """CPU time a process has used so far, user and system [s], from /proc."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def watched_env(path: Path, env: dict[str, str] | None = None) -> dict[str, str]:
    """The environment (``env``, else this one's) for a server whose loop watch
    (``windpump_app.server.watch.LoopWatch``) writes its full collections to ``path``; a late
    loop is written down only past a minute: these tests read its collections, not its lags."""
    return {
        **(os.environ if env is None else env),
        "WINDPUMP_LOOP_WATCH": str(path),
        "WINDPUMP_LOOP_WATCH_SLOW": "60",
    }


def tidied_since(path: Path, since: float) -> bool:
    """Has a server started with ``watched_env(path)`` handed back what its closed sessions held
    (``windpump_app.server.memory.Tidy.run``) after ``since`` [``time.time()``]?

    ``Tidy.run`` unfreezes every object and collects them all, so its collection tracks at least
    what the server held at its first full collection (at start, before any page); a page's
    ``settle`` and Python's own collections walk only what is not frozen (measured: 10k-60k
    objects, against 180k at start and 320k in a run after three pages)."""
    import json

    try:
        lines = [json.loads(line) for line in path.read_text().splitlines() if line]
    except FileNotFoundError:
        return False
    full = [line for line in lines if line["kind"] == "gc" and line.get("generation") == 2]
    return bool(full) and any(
        line["t"] > since and line["tracked"] >= full[0]["tracked"] for line in full[1:]
    )
