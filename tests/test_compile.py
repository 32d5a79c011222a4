"""What a first start compiles: the seed example's kernels once each, in a fresh numba cache.

A first start after an install spends its time compiling (README, "Measured"); these tests count
what is compiled, not how long it takes (the machine is noisy).
"""

from __future__ import annotations

import json
import logging
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

# Run in a process of its own with an empty cache: with a warm one numba loads the driver from
# disk and compiles nothing, so there would be nothing to count.
COMPILE_SEED = """
import json, sys
import numba
from numba.core import event
import windpump
from windpump.dynamics import solver_is_cached

cached_before = solver_is_cached(windpump.Design.seed_example())
compiled = []
class Listener(event.Listener):
    def on_start(self, e):
        compiled.append(e.data["dispatcher"].py_func.__module__)
    def on_end(self, e):
        pass
event.register("numba:compile", Listener())
seen = windpump.explore(windpump.Design.seed_example(), 600.0)
windpump.power_budget(seen.run).cycle_means()
windpump.playback_frames(seen.run)

from windpump._kernels import dopri5, driver, grid, model, stepping
signatures = {}
for module in (dopri5, driver, grid, model, stepping):
    for name, value in vars(module).items():
        if isinstance(value, numba.core.dispatcher.Dispatcher):  # named where it is defined
            signatures[f"{value.py_func.__module__}.{name}"] = len(value.signatures)
cached = [cached_before, solver_is_cached(windpump.Design.seed_example())]
json.dump({"signatures": signatures, "compiled": compiled, "cached": cached}, sys.stdout)
"""

# Compiled once per domain (ANGLE, TIME) on purpose: jit.by_value_kernel.
BY_DOMAIN = {"windpump._kernels.stepping.rates", "windpump._kernels.stepping.dp5_step"}


@pytest.fixture(scope="module")
def first_start(tmp_path_factory):
    """The seed example run as the first page runs it, in a fresh process and numba cache."""
    core = Path(__file__).resolve().parents[1] / "core"
    environment = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path_factory.mktemp("numba_cache")))
    environment["PYTHONPATH"] = os.pathsep.join(
        [str(core), *filter(None, [os.environ.get("PYTHONPATH")])]
    )
    done = subprocess.run(
        [sys.executable, "-c", COMPILE_SEED],
        env=environment,
        capture_output=True,
        text=True,
        check=True,
        timeout=600,
    )
    return json.loads(done.stdout)


def test_every_kernel_is_compiled_once(first_start):
    """A constant argument (record(out, 0, ...), final=True) compiles no copy of its own."""
    signatures = first_start["signatures"]
    assert signatures["windpump._kernels.driver.integrate"] == 1
    assert signatures["windpump._kernels.driver.record"] == 1
    assert signatures["windpump._kernels.grid.steady_runs"] == 0  # the Map tab's, not this page's
    twice = {name: count for name, count in signatures.items() if count > 1}
    assert set(twice) <= BY_DOMAIN
    assert all(count == 2 for count in twice.values())


def test_no_string_formatting_is_compiled(first_start):
    """numba's error messages of slice assignments (its unicode helpers) are not compiled."""
    modules = set(first_start["compiled"])
    assert "windpump._kernels.driver" in modules
    assert not {name for name in modules if "unicode" in name}


def test_the_cache_says_whether_a_first_run_compiles(first_start):
    """solver_is_cached (the server's "compiling the solver" line): not before the first run in an
    empty cache, and so after it."""
    assert first_start["cached"] == [False, True]


def test_the_server_says_when_it_compiles(monkeypatch, caplog):
    """`panel serve app/` says it is compiling, and for about how long, before it does; and how
    long it took once done (an empty cache is told by solver_is_cached, forced here)."""
    from windpump_app import app_hooks

    for cached, done in [(False, "solver compiled in"), (True, "loaded from numba's cache in")]:
        caplog.clear()
        monkeypatch.setattr(app_hooks, "solver_is_cached", lambda _design, c=cached: c)
        with caplog.at_level(logging.INFO, logger="windpump.app"):
            app_hooks.prepare_solver()
        lines = [record.getMessage() for record in caplog.records]
        assert done in lines[-1]
        compiling = [line for line in lines if line.startswith("compiling the solver")]
        assert len(compiling) == (0 if cached else 1)
        if not cached:
            assert f"about {app_hooks.FIRST_COMPILE_SECONDS} s" in compiling[0]


@pytest.mark.browser
def test_a_first_start_answers_while_it_compiles_and_its_first_page_gets_its_numbers(
    browser, monkeypatch, tmp_path
):
    """With an empty numba cache `panel serve app/` answers at once and compiles in the
    background; a page opened meanwhile loads, then shows the seed example's readout."""
    import windpump

    from served import DEEP_TEXT, served_app, server_log

    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))  # the server inherits it
    with served_app(timeout=600) as (url, server):
        assert "solver compiled" not in server_log(server)  # it answers before the compile ends
        # the background thread says so once it has looked at the cache (numba's import first)
        deadline = time.monotonic() + 120
        while "compiling the solver" not in server_log(server) and time.monotonic() < deadline:
            time.sleep(0.2)
        assert "compiling the solver" in server_log(server)
        page = browser.new_page(viewport={"width": 1280, "height": 720})
        try:
            page.goto(url, timeout=600_000)
            seen = windpump.explore(windpump.Design.seed_example(), 600.0)
            page.wait_for_function(
                f"(e) => ({DEEP_TEXT})('[data-name=mean_flow]') === e",
                arg=f"{1e3 * seen.mean_flow:.4f} L/s",
                timeout=600_000,
            )
        finally:
            page.close()
        assert "solver compiled in" in server_log(server)
        assert "Traceback" not in server_log(server)
