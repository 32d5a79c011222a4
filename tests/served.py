"""The explorer served by a real `panel serve app/` on a free loopback port, and Debian's chromium.

Shared by the browser test, the load test and benchmarks/bench_app.py.
"""

from __future__ import annotations

import contextlib
import os
import socket
import subprocess
import sys
import time
import urllib.request
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


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@contextlib.contextmanager
def served_app(*extra_args: str, timeout: float = 90.0) -> Iterator[tuple[str, subprocess.Popen]]:
    """Start `panel serve app/` on 127.0.0.1; yield (page URL, process); stop it afterwards."""
    port = free_port()
    command = [
        sys.executable,
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
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    url = f"http://127.0.0.1:{port}/app"
    try:
        deadline = time.monotonic() + timeout
        while True:
            try:
                with urllib.request.urlopen(url, timeout=5) as response:
                    if response.status == 200:
                        break
            except OSError:
                if process.poll() is not None or time.monotonic() > deadline:
                    raise RuntimeError(
                        f"panel serve did not come up:\n{process.stdout.read()}"
                    ) from None
                time.sleep(0.25)
        yield url, process
    finally:
        process.terminate()
        try:
            process.wait(timeout=15)
        except subprocess.TimeoutExpired:
            process.kill()


def require_chromium() -> None:
    """Skip on a user's machine without Debian's chromium; in CI its absence is a failure."""
    import pytest

    if Path(CHROMIUM).exists():
        return
    if os.environ.get("CI"):
        pytest.fail(f"CI must run the browser tests, but {CHROMIUM} is missing")
    pytest.skip(f"{CHROMIUM} is not installed (apt-get install -y chromium)")


def resident_memory(pid: int) -> int:
    """Resident set size of a process [bytes], from /proc."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) * 1024
    raise RuntimeError(f"no VmRSS for process {pid}")
