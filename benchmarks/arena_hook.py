"""Where a served process's pymalloc arenas go: on SIGUSR1 it writes them, and what is in them.

Investigation only, never imported by the app: ``benchmarks/bench_arenas.py`` starts ``panel
serve app/`` with ``ARENA_DUMP=<folder>`` and a ``sitecustomize`` that calls ``install()``. Each
signal writes ``snapN-*`` in the folder, after a full collection: ``-arenas.json`` (pymalloc's
table of arenas, read from the interpreter's own ``arenas`` array: each arena's address, free
and total pools, and each pool in use with its size class and blocks; glibc's ``mallinfo2``; the
arenas' and their free pools' resident memory by ``mincore``), ``-blocks.json`` (every live
object reachable from the collector's objects, and the blocks of its dict's keys and values, a
list's items, a set's table, placed in their arena) and, after the first, ``-owners.txt`` (each
object in an arena new since the first, with its chain of referrers up to a module or class).

It reads CPython 3.11's allocator by its private layout (``struct arena_object``, the pool
header) through the symbols of an unstripped ``libpython3.11.so``: another build or version
needs its own offsets.
"""

import os

ARENA_SIZE = 1 << 20  # [bytes] CPython 3.11 on 64 bits (USE_LARGE_ARENAS)
POOL_SIZE = 1 << 14  # [bytes]


def install() -> None:
    """Write a dump on each SIGUSR1 when ``ARENA_DUMP`` names a folder."""
    if not os.environ.get("ARENA_DUMP"):
        return
    import signal

    count = [0]

    def handler(signum, frame):
        count[0] += 1
        try:
            _dump(os.path.join(os.environ["ARENA_DUMP"], f"snap{count[0]}"))
        except Exception:
            import traceback

            traceback.print_exc()

    signal.signal(signal.SIGUSR1, handler)


def _libpython_base():
    with open("/proc/self/maps") as maps:
        for line in maps:
            parts = line.split()
            if len(parts) >= 6 and "libpython3.11" in parts[5] and int(parts[2], 16) == 0:
                return int(parts[0].split("-")[0], 16), parts[5]
    raise RuntimeError("no libpython")


def _symbol(path, name):
    import subprocess

    out = subprocess.run(["nm", path], capture_output=True, text=True).stdout
    for line in out.splitlines():
        p = line.split()
        if len(p) == 3 and p[2] == name:
            return int(p[0], 16)
    raise RuntimeError(name)


def arenas():
    """[(index, address, nfreepools, ntotalpools, [(pool, szidx, count)])] of allocated arenas,
    read into an array first (no object made per pool while the pools are read)."""
    import array
    import ctypes

    base, path = _libpython_base()
    arenas_p = ctypes.c_void_p.from_address(base + _symbol(path, "arenas")).value
    maxarenas = ctypes.c_uint.from_address(base + _symbol(path, "maxarenas")).value
    flat = array.array("Q")
    flat.extend(range(100_000))  # room made beforehand
    del flat[:]
    for i in range(maxarenas):
        ao = arenas_p + 48 * i
        address = ctypes.c_size_t.from_address(ao).value
        if address == 0:
            continue
        pool_address = ctypes.c_size_t.from_address(ao + 8).value
        flat.append(1 << 63)
        flat.extend(
            (
                i,
                address,
                ctypes.c_uint.from_address(ao + 16).value,
                ctypes.c_uint.from_address(ao + 20).value,
            )
        )
        first = (address + POOL_SIZE - 1) & ~(POOL_SIZE - 1)
        for pool in range(first, pool_address, POOL_SIZE):
            count = ctypes.c_uint.from_address(pool).value
            if count:
                flat.extend((pool, ctypes.c_uint.from_address(pool + 36).value, count))
    out = []
    k = 0
    while k < len(flat):
        assert flat[k] == 1 << 63
        i, address, nfree, ntotal = flat[k + 1 : k + 5]
        k += 5
        pools = []
        while k < len(flat) and flat[k] != 1 << 63:
            pools.append(tuple(flat[k : k + 3]))
            k += 3
        out.append((i, address, nfree, ntotal, pools))
    return out


def _dump(prefix):
    import ctypes
    import gc
    import json
    import sys
    import time
    import tracemalloc

    import numpy as np

    t0 = time.time()
    gc.unfreeze()
    gc.collect()
    gc.collect()
    # glibc's view, for comparison
    with open("/proc/self/status") as status:
        rss = next(int(line.split()[1]) * 1024 for line in status if line.startswith("VmRSS"))
    found = arenas()
    info = accounting(found)
    with open(prefix + "-arenas.json", "w") as out:
        out.write(json.dumps({"rss": rss, "arenas": found, "info": info}))
    fd = os.open(prefix + "-mallocstats.txt", os.O_WRONLY | os.O_CREAT | os.O_TRUNC)
    saved = os.dup(2)
    os.dup2(fd, 2)
    try:
        sys._debugmallocstats()
    finally:
        os.dup2(saved, 2)
        os.close(saved)
        os.close(fd)
    if tracemalloc.is_tracing():
        tracemalloc.take_snapshot().dump(prefix + ".tracemalloc")
    starts = np.array(sorted(a[1] for a in found), dtype=np.uint64)

    import bisect

    starts_l = starts.tolist()
    index_of = {a[1]: a[0] for a in found}

    def arena_of(addr):
        k = bisect.bisect_right(starts_l, addr) - 1
        return index_of[starts_l[k]] if k >= 0 and addr < starts_l[k] + ARENA_SIZE else -1

    objects = gc.get_objects()
    everything = {id(o): o for o in objects}
    stack = list(objects)
    while stack:
        for r in gc.get_referents(stack.pop()):
            if id(r) not in everything and not gc.is_tracked(r):
                everything[id(r)] = r
                stack.append(r)
    del stack, objects
    mine = {id(found), id(info)}
    for a in found:
        mine.add(id(a))
        mine.update(id(x) for x in a)
        mine.update(id(x) for x in a[4])
        mine.update(id(y) for x in a[4] for y in x)
    for v in info.values():
        mine.add(id(v))
    for i in mine:
        everything.pop(i, None)
    before_ids = None
    if os.path.exists(os.environ["ARENA_DUMP"] + "/snap1-ids.npy") and not prefix.endswith("snap1"):
        before_ids = set(np.load(os.environ["ARENA_DUMP"] + "/snap1-ids.npy").tolist())
    np.save(prefix + "-ids.npy", np.fromiter(everything.keys(), dtype=np.uint64))
    rows = []  # (block address, arena index, what, type, traceback, new)
    traces = {}
    types = {}
    managed = 1 << 4
    for address, o in everything.items():
        tp = type(o)
        pre = (16 if tp.__flags__ & (1 << 14) else 0) + (16 if tp.__flags__ & managed else 0)
        blocks = [("object", address - pre)]
        if tp is dict:
            blocks.append(("dict keys", ctypes.c_size_t.from_address(address + 32).value))
            values = ctypes.c_size_t.from_address(address + 40).value
            if values:
                blocks.append(("dict values", values))
        elif tp is list:
            items = ctypes.c_size_t.from_address(address + 24).value
            if items:
                blocks.append(("list items", items))
        elif tp in (set, frozenset):
            blocks.append(("set table", ctypes.c_size_t.from_address(address + 48).value))
        new = before_ids is None or address not in before_ids
        name = types.setdefault(f"{tp.__module__}.{tp.__qualname__}", len(types))
        where = -1
        for what, block in blocks:
            k = arena_of(block)
            if k < 0:
                continue
            if where == -1 and new and before_ids is not None:
                tb = tracemalloc.get_object_traceback(o)
                key = tb._frames if tb is not None else ()
                where = traces.setdefault(key, len(traces))
            rows.append((block, k, what, name, where, new))
    if before_ids is not None:
        before_arenas = json.load(open(os.environ["ARENA_DUMP"] + "/snap1-arenas.json"))
        old = {a[1] for a in before_arenas["arenas"]}
        newk = {a[0] for a in found if a[1] not in old}
        targets = []
        seen_kind = {}
        for block, k, what, name, _where, _new in rows:
            if k in newk and what == "object":
                seen_kind[name] = seen_kind.get(name, 0) + 1
                if seen_kind[name] <= 4000:
                    targets.append(block)
        # the block is the object's address less its pre-header: map back by the rows
        pre_of = {}
        for address, o in everything.items():
            tp = type(o)
            pre = (16 if tp.__flags__ & (1 << 14) else 0) + (16 if tp.__flags__ & managed else 0)
            pre_of[address - pre] = address
        ids = [pre_of[b] for b in targets if b in pre_of]
        chains = owners(
            ids,
            exclude={
                id(everything),
                id(rows),
                id(pre_of),
                id(found),
                id(targets),
                id(ids),
                id(before_ids),
                id(types),
                id(traces),
                id(mine),
            },
        )
        with open(prefix + "-owners.txt", "w") as out:
            for i in ids:
                o = everything[i]
                try:
                    text = repr(o)[:120]
                except Exception:
                    text = "?"
                out.write(f"{type(o).__name__}\t{text}\t{' <- '.join(chains[i])}\n")
    with open(prefix + "-blocks.json", "w") as out:
        out.write(
            json.dumps(
                {
                    "rows": rows,
                    "types": sorted(types, key=types.get),
                    "traces": [list(t) for t in sorted(traces, key=traces.get)],
                    "starts": starts.tolist(),
                }
            )
        )
    del everything, rows
    gc.collect()
    gc.freeze()
    with open(prefix + "-done", "w") as out:
        out.write(f"{time.time() - t0:.1f} s\n")


_LIBC = []  # libc, loaded once (each load makes objects of its own)


def _libc():
    import ctypes

    if not _LIBC:
        _LIBC.append(ctypes.CDLL(None))
    return _LIBC[0]


def resident(address, length):
    """Bytes of [address, address+length) resident (mincore)."""
    import ctypes

    libc = _libc()
    page = 4096
    start = address & ~(page - 1)
    n = (address + length - start + page - 1) // page
    vec = (ctypes.c_ubyte * n)()
    if libc.mincore(ctypes.c_void_p(start), ctypes.c_size_t(n * page), vec) != 0:
        return -1
    return sum(v & 1 for v in vec) * page


class _Mallinfo2(__import__("ctypes").Structure):
    _fields_ = [
        (n, __import__("ctypes").c_size_t)
        for n in (
            "arena",
            "ordblks",
            "smblks",
            "hblks",
            "hblkhd",
            "usmblks",
            "fsmblks",
            "uordblks",
            "fordblks",
            "keepcost",
        )
    ]


def accounting(found):

    libc = _libc()
    libc.mallinfo2.restype = _Mallinfo2
    m = libc.mallinfo2()
    info = {f: getattr(m, f) for f, _ in _Mallinfo2._fields_}
    info["arenas_resident"] = sum(resident(a[1], ARENA_SIZE) for a in found)
    info["arenas_used"] = sum(c * (s + 1) * 16 for a in found for _, s, c in a[4])
    info["free_pools_resident"] = 0
    for a in found:
        used = {p for p, _, _ in a[4]}
        first = (a[1] + POOL_SIZE - 1) & ~(POOL_SIZE - 1)
        for pool in range(first, a[1] + ARENA_SIZE - POOL_SIZE + 1, POOL_SIZE):
            if pool not in used:
                info["free_pools_resident"] += resident(pool, POOL_SIZE)
    with open("/proc/self/smaps_rollup") as f:
        info["smaps_rollup"] = f.read()
    return info


def owners(targets, depth=6, exclude=()):
    """Chains of referrers of ``targets`` (ids) up to modules, classes and named functions:
    {id: [(type name, label)...]} for a sample."""
    import gc
    import sys

    modules = {id(vars(m)): name for name, m in list(sys.modules.items()) if m is not None}
    objs = gc.get_objects()
    frontier = set(targets)
    parent_of = {}
    for _ in range(depth):
        found = {}
        for o in objs:
            if id(o) in exclude:
                continue
            for r in gc.get_referents(o):
                if id(r) in frontier and id(r) not in found:
                    found[id(r)] = o
        parent_of.update({k: v for k, v in found.items()})
        frontier = {id(v) for v in found.values()} - set(parent_of)
        if not frontier:
            break
    out = {}
    for t in targets:
        chain, cur = [], t
        for _ in range(depth):
            p = parent_of.get(cur)
            if p is None:
                break
            label = modules.get(id(p), "")
            if not label and hasattr(p, "__qualname__"):
                label = str(getattr(p, "__qualname__", ""))
            if not label and isinstance(p, dict):
                label = "keys: " + ",".join(str(k)[:20] for k in list(p)[:4])
            chain.append(f"{type(p).__name__}[{label[:60]}]")
            if id(p) in modules:
                break
            cur = id(p)
        out[t] = chain
    return out
