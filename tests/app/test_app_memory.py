"""What a closed page leaves behind in the server: nothing of its own.

A served page's components are dropped with its session; anything a class-level or module-level
registry keeps of them is kept for every page a server ever served (a hall of 100, then the next
class...). Here pages are built in-process and dropped, as a closed session drops them, and what
still lives is counted.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import gc
import os
import subprocess
import sys
import weakref

import panel as pn
import pytest
from panel.links import Callback
from panel.reactive import Reactive

from windpump_app.explorer import Explorer


def components_alive() -> int:
    """Panel's components anywhere in the process, once the garbage is collected."""
    gc.collect()
    return sum(isinstance(o, Reactive) for o in gc.get_objects())


def a_page_dropped() -> None:
    explorer = Explorer(defer_views=True, lazy_views=True)
    explorer.show_views()
    explorer.template()


def in_a_process_of_its_own(check: str) -> None:
    """Run this module's function ``check`` in a fresh interpreter, and fail as it fails. For the
    checks that count what lives in the whole process: there no other test's pages or threads
    are alive, or let go meanwhile (under pytest-xdist a worker's earlier tests vary)."""
    from pathlib import Path

    here = Path(__file__).resolve()
    script = (
        f"import sys; sys.path.insert(0, {str(here.parent)!r})\n"
        f"import {here.stem}\n{here.stem}.{check}()"
    )
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stderr[-3000:]


def dropped_pages_leave_no_component_alive() -> None:
    a_page_dropped()  # what the first page imports and caches is not the page's
    before = components_alive()
    for _ in range(2):
        a_page_dropped()
    assert components_alive() == before


def test_a_dropped_page_leaves_none_of_its_components_alive():
    in_a_process_of_its_own("dropped_pages_leave_no_component_alive")


def buttons_of_a_dropped_page() -> list[weakref.ref]:
    """The buttons with JavaScript callbacks of a page built and dropped here, weakly (other
    tests' pages, still alive, have theirs in the registry too)."""
    known = weakref.WeakSet(Callback.registry.keys())
    explorer = Explorer(defer_views=True, lazy_views=True)
    explorer.show_views()
    explorer.template()
    return [
        weakref.ref(source)
        for source in Callback.registry.keys()
        if isinstance(source, pn.widgets.Button) and source not in known
    ]


def test_panels_link_registry_forgets_a_dropped_pages_buttons():
    in_a_process_of_its_own("link_registry_forgets_a_dropped_pages_buttons")


def link_registry_forgets_a_dropped_pages_buttons() -> None:
    """Panel's ``Callback.registry`` holds a component weakly and its JavaScript callbacks
    strongly: a callback whose ``args`` hold the component keeps it (and its page's design).
    Only this page's buttons are looked at: other tests' pages, alive, keep theirs. (Built
    without a document, as here, the page before the fix let its buttons go too: the leak
    showed in a served hall, ``benchmarks/bench_hall.py``, where each session left one.)"""
    buttons = buttons_of_a_dropped_page()
    assert len(buttons) >= 2  # Copy link and the theme's
    gc.collect()
    assert [button() for button in buttons if button() is not None] == []


# In a process of its own (glibc's thresholds are the process's): an upload's block (16 MB)
# freed, then twenty 6 MB blocks each beside a small block that lives on, and the twenty freed.
BLOCKS = """
import sys
import numpy as np
from windpump_app.server.memory import large_blocks_mapped

def resident():
    with open("/proc/self/status") as status:
        return next(int(line.split()[1]) * 1024 for line in status if line.startswith("VmRSS"))

if sys.argv[1] == "mapped" and not large_blocks_mapped():
    raise SystemExit(3)
upload = np.ones(16 * 2**20 // 8)
del upload
before = resident()
blocks, small = [], []
for i in range(20):
    blocks.append(np.ones(6 * 2**20 // 8))
    small.append(bytes(2000 + i))
del blocks
print((resident() - before) / 1e6)
"""


def kept_after_blocks(how: str) -> float:
    """The memory [MB] a process keeps of 120 MB of blocks it freed, after an upload's block."""
    # glibc's own rule: any MALLOC_*_ setting turns its dynamic threshold off, and dask's nanny
    # leaves MALLOC_TRIM_THRESHOLD_ in this process's environment once a test has started one
    env = {k: v for k, v in os.environ.items() if not k.startswith("MALLOC_")}
    env.pop("GLIBC_TUNABLES", None)
    done = subprocess.run(
        [sys.executable, "-c", BLOCKS, how], capture_output=True, text=True, timeout=120, env=env
    )
    assert done.returncode == 0, done.stderr or "large_blocks_mapped() did not map them"
    return float(done.stdout)


def glibc() -> bool:
    name = ctypes.util.find_library("c")
    return (
        sys.platform.startswith("linux")
        and name is not None
        and hasattr(ctypes.CDLL(name), "mallopt")
    )


@pytest.mark.skipif(not glibc(), reason="glibc's malloc")
def test_blocks_freed_after_an_uploads_go_back_to_the_system():
    assert kept_after_blocks("mapped") < 10.0
    # glibc's own rule, for comparison: the freed upload's block raised its threshold, and the
    # blocks came from its heap, where the small blocks beside them keep them resident
    assert kept_after_blocks("default") > 60.0


# In a fresh process: what opening a first page's Wind tab imports and makes, with the server's
# warm-up (app_hooks.warm_the_wind_tab) or without it.
WIND_TAB = """
import sys
from windpump_app.explorer import Explorer
from windpump_app.inputs import PumpInputs
from windpump_app.wind_tab import gusty_day, warm_up

explorer = Explorer()
if sys.argv[1] == "warm":
    warm_up(PumpInputs())
modules = set(sys.modules)
days = gusty_day.cache_info().misses
explorer.main().active = 2  # the Wind tab
new = sorted(name for name in set(sys.modules) - modules if name.startswith(("scipy", "windpump")))
print(len(new), gusty_day.cache_info().misses - days, " ".join(new[:5]))
"""


def opening_the_wind_tab(how: str) -> tuple[int, int]:
    """The modules of scipy and windpump a first Wind tab imports, and the gusty days it makes."""
    done = subprocess.run(
        [sys.executable, "-c", WIND_TAB, how], capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr
    modules, days, _ = done.stdout.split(" ", 2)
    return int(modules), int(days)


def test_the_servers_warm_up_leaves_a_first_wind_tab_nothing_to_import_or_make():
    assert opening_the_wind_tab("warm") == (0, 0)
    assert opening_the_wind_tab("cold") != (0, 0)  # what the warm-up spares it


def test_a_closed_pages_template_root_leaves_panels_fake_roots():
    """Panel 1.9 lists each page's template root in ``state._fake_roots`` and never dropped it
    when the page's session ended: one string a page, kept for good (a served hall of 30 left
    30), each made among its page's objects and keeping their memory after the page had gone.
    ``serving.fake_roots_forgotten`` has Panel drop it, as Bokeh ends a session."""
    from types import SimpleNamespace

    from bokeh.document import Document
    from panel.io.state import state

    from windpump_app.server.patches import fake_roots_forgotten

    fake_roots_forgotten()
    before = list(state._fake_roots)
    template = Explorer(defer_views=True, lazy_views=True).template()
    document = Document()
    template.server_doc(document)
    assert len(state._fake_roots) == len(before) + 1
    template._server_destroy(SimpleNamespace(_document=document))  # what Bokeh calls
    assert state._fake_roots == before


def test_a_class_gone_its_designs_are_forgotten(monkeypatch):
    """Once every page has closed the designs the class moved to are forgotten: made among the
    pages' objects, kept, they kept those pages' memory (``serving.forget_the_class``)."""
    import windpump
    from windpump.run.dynamics import ideal_of
    from windpump_app.server import memory as serving

    monkeypatch.setattr(serving, "_LIBC", None)
    ideal_of(windpump.Design.seed_example().replace(m_r=3.0))
    tidy = serving.Tidy()
    tidy.opened()
    tidy.run()  # a page still open: kept
    assert ideal_of.cache_info().currsize >= 1
    tidy.open = 0
    tidy.run()
    assert ideal_of.cache_info().currsize == 0


def test_the_servers_threads_are_started_before_a_class():
    """Every thread of a pool started at once (``serving.every_thread_started``), not when a
    class's work first needs it, in the middle of the class."""
    from concurrent.futures import ThreadPoolExecutor

    from windpump_app.server.threads import every_thread_started

    pool = ThreadPoolExecutor(max_workers=3)
    try:
        assert every_thread_started(pool) == 3
    finally:
        pool.shutdown()
