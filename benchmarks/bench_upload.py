"""What one 10 MB wind upload costs the server's event loop, as another page's moves see it.

Run: python benchmarks/bench_upload.py [ROUNDS] [--app DIR]   (ROUNDS = 5 by default)

An otherwise idle `panel serve app/` (``--app``: another checkout's ``app/``, e.g. main's, with
that checkout's ``windpump`` importable): a witness page (a protocol-level student of
``bench_hall.py``, in this process) moves a slider one move after another, while a loader page in
a process of its own (as a student's browser is) sends a 10 MB record as the page does: by HTTP
POST and its reference over the websocket when the server has the upload route
(``app/server/upload_route.py``), else as the FileInput's base64 value in one websocket message. Printed:
the witness's round trips with no upload against those sent within 0.6 s of the upload's first
byte (the same witness, the same server), their ratio, and how long the upload took until the
server said it read the file. Bounded: ROUNDS <= 20, every wait has a timeout; loopback only.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import random
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
import bench_hall  # noqa: E402

import served  # noqa: E402

WAIT = 120.0  # [s] the longest any step is waited for
CALM = 2.0  # [s] of the witness's moves with no upload, each round
DURING = 0.6  # [s] after the upload's first byte: the witness's moves sent then


async def loader(url: str, size: int = bench_hall.UPLOAD_BYTES) -> None:
    """The loader's process (``bench_hall.py --upload``'s too): open a page and its Wind tab,
    make a record of ``size`` bytes, print "ready"; on a line of stdin, send the record; print
    "read" and the seconds until the server says it reads it."""
    bench_hall.AsyncHTTPClient.configure(None, max_clients=4)
    student = bench_hall.Student(url, random.Random(0))
    await student.open()
    upload = await bench_hall.wind_tab(student)
    route = await bench_hall.has_upload_route(student)
    record = bench_hall.wind_record(size)
    shown = asyncio.Event()
    name = bench_hall.UPLOAD_NAME
    reading = lambda new: name in new and "Sending" not in new  # noqa: E731
    student.watchers.append(lambda e: reading(str(e.get("new"))) and shown.set())
    print("ready", route, flush=True)
    await asyncio.get_running_loop().run_in_executor(None, sys.stdin.readline)
    sent = time.perf_counter()
    if route:
        await bench_hall.post_upload(student, record)
    else:
        await bench_hall.in_base64(student, upload, record)
    await asyncio.wait_for(shown.wait(), WAIT)
    print("read", time.perf_counter() - sent, flush=True)
    await asyncio.sleep(3.0)  # its reading and its day, before the next round
    student.close()


async def moves_for(witness: bench_hall.Student, seconds: float, pause: float) -> list[float]:
    """The witness's round trips [s], one move after another for ``seconds``."""
    first = len(witness.moves)
    end = time.perf_counter() + seconds
    while time.perf_counter() < end:
        await witness.move()
        await asyncio.sleep(pause)
    return [trip for _, trip in witness.moves[first:]]


async def rounds(url: str, n: int) -> tuple[bool, list[float], list[float], list[float]]:
    bench_hall.AsyncHTTPClient.configure(None, max_clients=4)
    witness = bench_hall.Student(url, random.Random(5))
    await asyncio.wait_for(witness.open(), WAIT)
    calm: list[float] = []
    during: list[float] = []
    took: list[float] = []
    route = False
    for _ in range(n):
        child = await asyncio.create_subprocess_exec(
            sys.executable,
            __file__,
            "--loader",
            url,
            stdin=asyncio.subprocess.PIPE,
            stdout=asyncio.subprocess.PIPE,
        )
        assert child.stdin is not None and child.stdout is not None
        ready = (await asyncio.wait_for(child.stdout.readline(), WAIT)).decode().split()
        route = ready[1:] == ["True"]
        calm += await moves_for(witness, CALM, 0.02)
        child.stdin.write(b"go\n")
        await child.stdin.drain()
        during += await moves_for(witness, DURING, 0.005)
        read = (await asyncio.wait_for(child.stdout.readline(), WAIT)).decode().split()
        took.append(float(read[1]))
        await asyncio.wait_for(child.wait(), WAIT)
    witness.close()
    return route, calm, during, took


def summary(trips: list[float]) -> str:
    ordered = sorted(trips)
    p90 = ordered[min(len(ordered) - 1, int(0.9 * len(ordered)))]
    return (
        f"median {1e3 * statistics.median(trips):.0f} ms, 90th percentile {1e3 * p90:.0f} ms, "
        f"max {1e3 * ordered[-1]:.0f} ms ({len(trips)})"
    )


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("rounds", nargs="?", type=int, default=5)
    parser.add_argument("--app", default=str(served.APP), help="the app/ directory served")
    args = parser.parse_args(argv)
    if not 1 <= args.rounds <= 20:
        raise SystemExit("1 <= ROUNDS <= 20")
    served.APP = Path(args.app).resolve()
    print(f"bench_upload of {served.APP} on {os.cpu_count()} cores, load {os.getloadavg()}")
    with served.served_app() as (url, _server):
        bench_hall.loopback(url)
        route, calm, during, took = asyncio.run(rounds(url, args.rounds))
    way = "HTTP POST + reference" if route else "base64 over the websocket (no upload route)"
    print(f"  a 10 MB record sent {args.rounds} times, {way}")
    print(f"  the witness's moves, no upload: {summary(calm)}")
    print(f"  the witness's moves sent within {DURING} s of its first byte: {summary(during)}")
    print(
        f"  ratio during / no upload: median "
        f"{statistics.median(during) / statistics.median(calm):.2f}, max "
        f"{max(during) / max(calm):.2f}"
    )
    print(f"  the upload until the server reads it: median {statistics.median(took):.2f} s")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--loader"]:  # --loader URL [BYTES]
        asyncio.run(loader(sys.argv[2], *map(int, sys.argv[3:4])))
    else:
        main()
