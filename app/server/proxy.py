"""Several `panel serve app/` processes behind nginx with sticky sessions: one command for a
class larger than one process carries.

    python -m windpump_app.server.proxy --processes 4 --port 8080 [--address 0.0.0.0] [--host NAME:PORT]

starts ``--processes`` servers on free loopback ports and nginx (Debian's ``/usr/sbin/nginx``, as
a child process, its configuration ``app/server/nginx.conf`` filled in and written to a temporary
directory) listening on ``--address:--port``; students open ``http://NAME:PORT/app``. Ctrl-C (or a
SIGTERM: ``kill``, systemd, docker) stops them all. See docs/instructors.rst, "More students
than one process carries".

Each server starts with jemalloc as its allocator (``--allocator jemalloc``, the default; see
``allocator_env``): after a class it hands back what the class took. Without the library (not
Debian: ``apt-get install -y libjemalloc2``) they start as ``panel serve`` does, and say so.
"""

from __future__ import annotations

import argparse
import contextlib
import logging
import os
import signal
import socket
import subprocess
import sys
import sysconfig
import tempfile
import time
import urllib.request
from collections.abc import Iterator
from pathlib import Path

APP = Path(__file__).resolve().parent.parent  # app/, what `panel serve` serves
NGINX = "/usr/sbin/nginx"
CONFIG = Path(__file__).resolve().parent / "nginx.conf"

log = logging.getLogger("windpump.app")

# jemalloc, where Debian's libjemalloc2 (and other distributions) put it
JEMALLOC = "libjemalloc.so.2"
LIBRARY_DIRS = (
    f"/usr/lib/{sysconfig.get_config_var('MULTIARCH') or ''}",
    "/usr/lib64",
    "/usr/lib",
    "/usr/local/lib",
)
# Freed pages handed back by jemalloc's own thread within about a second (its default: ten
# seconds, and only when the process next allocates); none kept "muzzy" (advised but mapped).
JEMALLOC_CONF = "background_thread:true,dirty_decay_ms:1000,muzzy_decay_ms:0"
ALLOCATORS = ("jemalloc", "malloc", "python")


def jemalloc_library(dirs: tuple[str, ...] | None = None) -> str | None:
    """The path of jemalloc's shared library in ``dirs`` (``LIBRARY_DIRS``), or None."""
    dirs = LIBRARY_DIRS if dirs is None else dirs
    return next((str(Path(d) / JEMALLOC) for d in dirs if (Path(d) / JEMALLOC).is_file()), None)


def allocator_env(
    allocator: str = "jemalloc", env: dict | None = None, library: str | None = None
) -> dict[str, str]:
    """The environment a server process starts with, its memory allocator chosen.

    ``"jemalloc"``: Python's small objects handed to malloc (``PYTHONMALLOC=malloc``) and malloc
    taken from jemalloc (``LD_PRELOAD``), which packs small blocks without a header each and
    hands freed pages back to the system (``JEMALLOC_CONF``, unless ``MALLOC_CONF`` is set):
    after a hall of 100 the server holds within 10 % of its memory before it, where Python's
    own allocator keeps 1 MiB arenas pinned by a few survivors (docs/known-issues.rst). If the
    library is missing (``library`` None and none in ``LIBRARY_DIRS``), Python's allocator, and
    a line logged saying so. ``"malloc"``: glibc's malloc; ``"python"``: as ``panel serve``
    starts. ``PYTHONMALLOC`` and ``LD_PRELOAD`` are read when a process starts: set for the
    servers, not in them. Figures: docs/measured.rst, "the allocator"."""
    if allocator not in ALLOCATORS:
        raise ValueError(f"allocator {allocator!r}: one of {', '.join(ALLOCATORS)}")
    env = dict(os.environ if env is None else env)
    if allocator == "jemalloc":
        library = library or jemalloc_library()
        if library is None:
            log.warning(
                "jemalloc (%s) not found in %s: the servers use Python's allocator and keep "
                "more memory after a class (apt-get install -y libjemalloc2)",
                JEMALLOC,
                ", ".join(LIBRARY_DIRS),
            )
            return env
        preload = env.get("LD_PRELOAD", "")
        env["LD_PRELOAD"] = f"{library} {preload}".strip() if library not in preload else preload
        env.setdefault("MALLOC_CONF", JEMALLOC_CONF)
    if allocator in ("jemalloc", "malloc"):
        env["PYTHONMALLOC"] = "malloc"
    return env


def free_port(address: str = "127.0.0.1") -> int:
    with socket.socket() as s:
        s.bind((address, 0))
        return s.getsockname()[1]


def nginx_config(listen: str, ports: list[int], prefix: str) -> str:
    """``app/server/nginx.conf`` for nginx listening on ``listen`` (address:port) in front of the
    servers on 127.0.0.1 at ``ports``, its files under ``prefix``."""
    backends = [f"127.0.0.1:{port}" for port in ports]
    servers = "\n".join(f"    server {b} max_fails=1 fail_timeout=10s;" for b in backends)
    sticky = "\n".join(f'    "{b}" {b};' for b in backends)
    text = CONFIG.read_text(encoding="utf-8")
    for field, value in (("@PREFIX@", prefix), ("@SERVERS@", servers), ("@STICKY@", sticky)):
        text = text.replace(field, value)
    return text.replace("@LISTEN@", listen)


def panel_command(port: int, origins: list[str], *extra: str) -> list[str]:
    command = [sys.executable, "-m", "panel", "serve", str(APP), "--port", str(port)]
    command += ["--address", "127.0.0.1", "--use-xheaders"]
    for origin in origins:
        command += ["--allow-websocket-origin", origin]
    return [*command, *extra]


@contextlib.contextmanager
def hall(
    processes: int,
    listen: str,
    origins: list[str],
    *extra: str,
    log_to=None,
    timeout: float = 180.0,
    allocator: str = "jemalloc",
) -> Iterator[tuple[list[subprocess.Popen], subprocess.Popen, list[int]]]:
    """Start ``processes`` servers and nginx in front of them; yield (servers, nginx, ports);
    stop them all afterwards. Waits, at most ``timeout`` s, until each server answers. The
    servers' memory allocator: ``allocator_env``."""
    if not Path(NGINX).exists():
        raise RuntimeError(f"{NGINX} is missing: apt-get install -y nginx")
    ports = [free_port() for _ in range(processes)]
    started: list[subprocess.Popen] = []
    env = allocator_env(allocator)
    with tempfile.TemporaryDirectory(prefix="windpump-nginx-") as prefix:
        try:
            for port in ports:
                command = panel_command(port, origins, *extra)
                started.append(subprocess.Popen(command, env=env, stdout=log_to, stderr=log_to))
            for port, server in zip(ports, started, strict=True):
                wait_until_up(f"http://127.0.0.1:{port}/static/js/bokeh.min.js", server, timeout)
            config = Path(prefix) / "nginx.conf"
            config.write_text(nginx_config(listen, ports, prefix), encoding="utf-8")
            proxy = subprocess.Popen(
                [NGINX, "-p", prefix, "-c", str(config), "-e", f"{prefix}/error.log"],
                stdout=log_to,
                stderr=log_to,
            )
            started.append(proxy)
            host, port = listen.rsplit(":", 1)
            wait_until_up(f"http://{_local(host)}:{port}/static/js/bokeh.min.js", proxy, 30)
            yield started[:-1], proxy, ports
        finally:
            for process in reversed(started):
                stop(process)


def _local(host: str) -> str:
    return "127.0.0.1" if host in ("0.0.0.0", "", "*") else host


def wait_until_up(url: str, process: subprocess.Popen, timeout: float) -> None:
    deadline = time.monotonic() + timeout
    while True:
        try:
            with urllib.request.urlopen(url, timeout=5) as response:
                if response.status == 200:
                    return
        except OSError:
            pass
        if process.poll() is not None or time.monotonic() > deadline:
            raise RuntimeError(f"{url} did not answer within {timeout:.0f} s")
        time.sleep(0.25)


def stop(process: subprocess.Popen) -> None:
    if process.poll() is None:
        process.send_signal(signal.SIGTERM)
        try:
            process.wait(timeout=15)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(timeout=15)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--processes", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--port", type=int, default=8080)
    parser.add_argument("--address", default="0.0.0.0", help="nginx listens here")
    parser.add_argument(
        "--host",
        action="append",
        default=[],
        help="NAME:PORT students type (repeatable; default: this machine's names)",
    )
    parser.add_argument(
        "--allocator",
        choices=ALLOCATORS,
        default="jemalloc",
        help="the servers' memory allocator (default jemalloc, if installed)",
    )
    args, extra = parser.parse_known_args(argv)
    # `kill`, systemd and docker stop it with SIGTERM: stop the servers and nginx as Ctrl-C does
    # (Python's default ended this process at once, and they ran on, orphaned, on their ports)
    signal.signal(signal.SIGTERM, _interrupted)
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    origins = args.host or [f"{name}:{args.port}" for name in _names()]
    listen = f"{args.address}:{args.port}"
    with hall(args.processes, listen, origins, *extra, allocator=args.allocator) as started:
        servers, proxy, ports = started
        print(f"{len(servers)} servers on 127.0.0.1:{','.join(map(str, ports))}; nginx on {listen}")
        print(f"students open http://{origins[0]}/app  (Ctrl-C stops them all)", flush=True)
        with contextlib.suppress(KeyboardInterrupt):
            while all(p.poll() is None for p in (*servers, proxy)):
                time.sleep(1.0)
    return 0


def _interrupted(signum: int, _frame) -> None:
    raise KeyboardInterrupt(f"signal {signum}")


def _names() -> list[str]:
    names = ["localhost", "127.0.0.1", socket.gethostname()]
    with contextlib.suppress(OSError):
        names.append(socket.gethostbyname(socket.gethostname()))
    return list(dict.fromkeys(names))


if __name__ == "__main__":
    raise SystemExit(main())
