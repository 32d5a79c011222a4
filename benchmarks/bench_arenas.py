"""What keeps the server's memory after a hall has closed: Python's arenas, and what is in them.

Run: python benchmarks/bench_arenas.py [N] [--upload] [--folder DIR]

A fresh ``panel serve app/`` with ``benchmarks/arena_hook.py`` loaded (``ARENA_DUMP``), one
student's warm-up as ``bench_hall.py`` does, a dump (the server's arenas and objects), a hall of
N (default 30, half a minute of moves) as ``bench_hall.py`` runs it, and a dump once it has
closed and the server has collected its garbage. Printed: the arenas before and after, the new
arenas' pools and blocks in use, their resident memory and its free pools', what the blocks in
the new arenas are and which module or class keeps each kind (the hook's own objects, made
while it writes, are among them: ``ctypes``, ``_dump``). CPython 3.11 with an unstripped
``libpython3.11.so`` only (see the hook); no timing is measured.
"""

from __future__ import annotations

import argparse
import asyncio
import collections
import json
import os
import random
import re
import signal
import sys
import tempfile
import time
from pathlib import Path

import bench_hall as hall

HERE = Path(__file__).resolve().parent
SITECUSTOMIZE = "import arena_hook\narena_hook.install()\n"


def dump(server, folder: str, k: int, within: float = 600.0) -> None:
    server.send_signal(signal.SIGUSR1)
    deadline = time.time() + within
    while not os.path.exists(f"{folder}/snap{k}-done"):
        if time.time() > deadline:
            raise TimeoutError(f"no dump {k} within {within:.0f} s")
        time.sleep(1.0)


def a_hall_dumped(n: int, upload: bool, folder: str, minutes: float = 0.5) -> None:
    hall.AsyncHTTPClient.configure(None, max_clients=hall.MAX_SESSIONS + 1)
    with tempfile.TemporaryDirectory() as site:
        Path(site, "sitecustomize.py").write_text(SITECUSTOMIZE)
        saved = dict(os.environ)
        os.environ.update(
            ARENA_DUMP=folder,
            PYTHONPATH=os.pathsep.join([site, str(HERE), os.environ.get("PYTHONPATH", "")]),
            WINDPUMP_LOOP_WATCH="",
        )
        try:
            with hall.served_app(*hall.SERVE) as (address, server):
                hall.loopback(address)
                warm = hall.Student(address, random.Random(0))
                asyncio.run(asyncio.wait_for(hall.warm_up(warm), hall.WAIT))
                time.sleep(40.0)  # the warm-up's session dropped (30 s) and collected
                dump(server, folder, 1)
                watch = hall.Watch(server.pid)
                hall.report(asyncio.run(hall.a_hall(address, n, minutes, watch, upload)))
                time.sleep(20.0)
                dump(server, folder, 2)
        finally:
            os.environ.clear()
            os.environ.update(saved)


def used(arenas: list) -> int:
    """Bytes in blocks in use in ``arenas`` (as the hook wrote them)."""
    return sum(count * (size + 1) * 16 for arena in arenas for _, size, count in arena[4])


def keeper(chain: str) -> str:
    """The outermost named holder of a chain of referrers (the hook's ``-owners.txt``)."""
    named = [p for p in chain.split(" <- ") if re.search(r"\[(?!keys:)[^\]]+\]", p)]
    return re.sub(r"0x[0-9a-f]+", "", named[-1] if named else "(unnamed)")[:80]


def summary(folder: str, top: int = 25) -> None:
    before = json.loads(Path(folder, "snap1-arenas.json").read_text())
    after = json.loads(Path(folder, "snap2-arenas.json").read_text())
    old = {arena[1] for arena in before["arenas"]}
    new = [arena for arena in after["arenas"] if arena[1] not in old]
    mb = 1e6
    print(
        f"arenas: {len(before['arenas'])} before, {len(after['arenas'])} after, holding "
        f"{used(before['arenas']) / mb:.1f} MB and {used(after['arenas']) / mb:.1f} MB"
    )
    print(
        f"  new arenas: {len(new)}, {used(new) / mb:.2f} MB in use, "
        f"{sum(len(a[4]) for a in new)} of their {sum(a[3] for a in new)} pools in use"
    )
    for label, snap in (("before", before), ("after", after)):
        info = snap["info"]
        print(
            f"  {label}: resident {snap['rss'] / mb:.0f} MB; arenas resident "
            f"{info['arenas_resident'] / mb:.1f} MB, of it free pools "
            f"{info['free_pools_resident'] / mb:.1f} MB; glibc in use {info['uordblks'] / mb:.1f}"
            f" MB, free {info['fordblks'] / mb:.1f} MB"
        )
    blocks = json.loads(Path(folder, "snap2-blocks.json").read_text())
    inside = {arena[0] for arena in new}
    kinds: collections.Counter = collections.Counter()
    for _, arena, what, kind, _, _ in blocks["rows"]:
        if arena in inside:
            kinds[(what, blocks["types"][kind])] += 1
    print("  in the new arenas, by kind:")
    for (what, kind), count in kinds.most_common(top):
        print(f"    {count:6d} {what} {kind}")
    keepers: collections.Counter = collections.Counter()
    for line in Path(folder, "snap2-owners.txt").read_text().splitlines():
        keepers[keeper(line.split("\t")[2])] += 1
    print("  in the new arenas, by what keeps them:")
    for name, count in keepers.most_common(top):
        print(f"    {count:6d} {name}")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("n", nargs="?", type=int, default=30)
    parser.add_argument("--upload", action="store_true", help="one student loads 10 MB")
    parser.add_argument("--folder", help="where the dumps go (default: a new temporary one)")
    args = parser.parse_args(argv)
    if sys.version_info[:2] != (3, 11):
        raise SystemExit("the hook reads CPython 3.11's allocator")
    folder = args.folder or tempfile.mkdtemp(prefix="bench_arenas-")
    os.makedirs(folder, exist_ok=True)
    print(f"bench_arenas: a hall of {args.n}, dumps in {folder}, load {os.getloadavg()[0]:.1f}")
    a_hall_dumped(args.n, args.upload, folder)
    summary(folder)


if __name__ == "__main__":
    main()
