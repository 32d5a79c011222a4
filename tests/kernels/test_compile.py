"""What a first start compiles: the seed example's kernels once each, in a fresh numba cache.

A first start after an install spends its time compiling (README, "Measured"); these tests count
what is compiled, not how long it takes (the machine is noisy).
"""

from __future__ import annotations

import json
import logging
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import windpump

PARTS_FILE = "windpump-parts-compiled.json"  # compiling.PARTS_FILE

# Run in a process of its own with an empty cache: with a warm one numba loads the driver from
# disk and compiles nothing, so there would be nothing to count.
COMPILE_SEED = """
import json, sys
import numba
from numba.core import event
import windpump
from windpump.run.dynamics import solver_is_cached

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
    core = Path(__file__).resolve().parents[2] / "core"
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
    assert signatures["windpump._kernels.samples.record"] == 1
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


# The first page's last kernels compiled ahead (as a worker does on a first start), then the first
# page: each compiled for the types integrate's calls have, or integrate compiles it a second time.
COMPILE_AHEAD = """
import json, sys
import windpump
from windpump._kernels import driver, stepping
from windpump.run.dynamics import kernel_machine

ahead = driver.compile_ahead(kernel_machine(windpump.Design.seed_example()))
seen = windpump.explore(windpump.Design.seed_example(), 600.0)
kernels = {name: getattr(driver, name, None) or getattr(stepping, name) for name in ahead}
json.dump({name: len(kernel.signatures) for name, kernel in kernels.items()}, sys.stdout)
"""


def test_the_first_pages_last_kernels_compiled_ahead_are_the_ones_it_runs(tmp_path):
    """driver.compile_ahead's signatures are integrate's (a worker compiling other types while
    the server compiles the first page would save it nothing); an ideal machine's only. On an
    empty cache, as on a first start: with integrate in the cache its callees are not typed at
    all (dp5_step then has compile_ahead's one signature, not two)."""
    from windpump import Design
    from windpump._kernels import driver
    from windpump.run.dynamics import kernel_machine

    done = subprocess.run(
        [sys.executable, "-c", COMPILE_AHEAD],
        env=dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path)),
        capture_output=True,
        text=True,
        check=True,
        timeout=600,
    )
    signatures = json.loads(done.stdout)
    assert set(signatures) >= {"advance_in_time", "step_to_kink", "tabulate_segment"}
    assert signatures == {name: 2 if name == "dp5_step" else 1 for name in signatures}
    deep_well = Design.seed_example().replace(m_r=20.0)
    assert driver.compile_ahead(kernel_machine(deep_well)) == []


def test_the_server_says_when_it_compiles(monkeypatch, caplog):
    """`panel serve app/` says it is compiling, and for about how long, before it does; and how
    long it took once done (an empty cache is told by solver_is_cached, forced here)."""
    from windpump_app.server import hooks as app_hooks

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


# -- a first start in parts (app/compiling.py) ---------------------------------------------------


@pytest.fixture
def compiling():
    """The app's record of which parts of the solver are ready, every part ready again after."""
    from windpump_app.compiling import COMPILE

    yield COMPILE
    for name in COMPILE.names:
        COMPILE.ready[name].set()


def test_the_terminal_says_how_many_parts_are_ready(compiling, caplog):
    """Each part done is said with how far the compile is: "2 of 5 parts ready"."""
    from windpump_app.compiling import FIRST_PAGE, PARTS, SITE_TAB, WIND_TAB

    compiling.begin()
    assert (
        compiling.progress()
        == f"compiling the solver (once after an install): 0 of {len(PARTS)} parts ready"
    )
    with caplog.at_level(logging.INFO, logger="windpump.app"):
        compiling.done(FIRST_PAGE, 7.5)
        compiling.done(WIND_TAB)
    lines = [record.getMessage() for record in caplog.records]
    assert lines == [
        f"compiling the solver (once after an install): 1 of {len(PARTS)} parts ready: "
        "the first page ready in 7.5 s",
        f"compiling the solver (once after an install): 2 of {len(PARTS)} parts ready: "
        "the Wind tab ready",
    ]
    assert compiling.waiting(WIND_TAB) == ""
    assert compiling.waiting(SITE_TAB).startswith(
        f"**Compiling the solver (once after an install): 2 of {len(PARTS)} parts ready.**"
    )


def test_a_waiting_page_says_how_far_the_compile_is(compiling):
    """A first start's page (start=False) says "compiling the solver" with its progress, again as
    parts get ready (serving.first_run_when_ready calls say_compiling), until its first run."""
    from windpump_app.compiling import FIRST_PAGE, PARTS, REAL_MACHINE
    from windpump_app.explorer import Explorer

    compiling.begin()
    page = Explorer(start=False)
    status = page.readouts.status
    assert f"once after an install): 0 of {len(PARTS)} parts ready" in status.object
    compiling.done(REAL_MACHINE)
    page.say_compiling()
    assert f"once after an install): 1 of {len(PARTS)} parts ready" in status.object
    compiling.done(FIRST_PAGE)
    page.start()
    assert "Compiling" not in status.object and page.seen is not None


@pytest.mark.parametrize(
    "preset", ["The paper's example", "A deep well, a heavy rod", "A stalled pump"]
)
def test_a_waiting_page_shows_the_averaged_theory_meanwhile(compiling, preset):
    """While a first start compiles, the page shows what needs no compiled code: the averaged
    theory's τ (Eq. 25) and stall margin (Eq. 22) in their readouts and α₊ (Eq. 21) in the
    status, each as the core computes them for the page's design; the full run's readouts (the
    mean flow, the page's sign that it has run) stay empty until its part is ready."""
    import re

    import windpump
    from windpump_app.explorer import Explorer
    from windpump_app.inputs import PRESETS

    compiling.begin()
    page = Explorer(start=False)
    page.inputs.param.update(**PRESETS[preset][0])
    page.say_compiling()
    design = page.inputs.design()

    def shown(name):
        return re.sub(r"<[^>]+>", "", page.readouts[name].object)

    margin = windpump.stall_margin(design)
    assert f"{margin:.3f}" in shown("margin")
    status = page.readouts.status.object
    assert "Compiling the solver" in status and "The averaged theory meanwhile" in status
    if margin > 1.0:
        assert f"{windpump.time_constant(design):.1f} s" in shown("tau")
        assert f"{windpump.steady_speeds(design)[0]:.2f}" in status
    else:
        assert "–" in shown("tau") and "cannot carry the load" in status
    assert page.readouts["mean_flow"].object == "" and page.seen is None
    assert "The full run's numbers follow once its part (the first page) is ready" in status


@pytest.mark.parametrize("tab, part", [(2, "the Wind tab"), (4, "the Site tab")])
def test_a_tab_whose_part_compiles_says_so_and_waits_for_it(compiling, tab, part):
    """The Wind and Site tabs opened while their part compiles in a worker say so instead of a bare
    "…", and run once it is ready, not compiling it a second time meanwhile."""
    import threading

    import windpump
    from windpump_app.explorer import Explorer

    page = Explorer()
    compiling.begin([part])
    opened = threading.Thread(target=lambda: setattr(page.main(), "active", tab), daemon=True)
    opened.start()
    tab_of, name = (page.wind_tab, "day_note") if tab == 2 else (page.site_tab, "computing")

    def said() -> str:  # the tab's word while its day or year runs (built by the thread)
        return str(getattr(getattr(tab_of, name, None), "object", ""))

    deadline = time.monotonic() + 120
    while "Compiling the solver" not in said() and time.monotonic() < deadline:
        time.sleep(0.05)
    assert "Compiling the solver (once after an install): " in said()
    assert f"once its part ({part}) is ready" in said()
    time.sleep(0.5)
    assert opened.is_alive()  # waiting for the part
    compiling.done(part)
    opened.join(timeout=300)
    assert not opened.is_alive()
    if tab == 2:
        assert "Integrated in full over a gusty day" in page.wind_tab.day_note.object
    else:
        record = windpump.sample_site("greensboro").at_height(10.0)
        year = windpump.supply(
            windpump.Design.seed_example(), record, 10.0, 5.0, restart="attended"
        )
        assert page.site_tab.supplied.lolp == year.lolp and not page.site_tab.computing.visible


def test_a_worker_process_writes_its_part_to_numbas_cache(compiling, monkeypatch, tmp_path):
    """A part compiled in a worker process (spawned, with the server's NUMBA_CACHE_DIR) is in the
    cache once it is marked ready, where the server loads it from."""
    import threading

    from windpump_app.compiling import SITE_TAB, Workers

    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))  # the worker inherits it
    compiling.begin([SITE_TAB])
    first_done = threading.Event()
    first_done.set()
    workers = Workers(first_done, processes=1)
    workers.run([SITE_TAB])
    assert compiling.ready[SITE_TAB].is_set()
    workers.stop()  # the server stops after its workers are done: no AttributeError at its end
    indexes = {path.name.split(".")[1].split("-")[0] for path in tmp_path.rglob("supply.*.nbi")}
    assert {"shortfall_map", "balance"} <= indexes
    (recorded,) = tmp_path.rglob(PARTS_FILE)  # beside the driver's cache, by the worker
    assert SITE_TAB in json.loads(recorded.read_text())


class SubmittedInOrder:
    """A process pool that runs nothing: each part submitted is done at once (0 s)."""

    def __init__(self, *args, **kwargs):
        self.sent = []

    def submit(self, run, name, parent):
        from concurrent.futures import Future

        self.sent.append(name)
        done = Future()
        done.set_result(0.0)
        return done

    def shutdown(self, **kwargs):
        pass


@pytest.mark.parametrize("first_done", [False, True])
def test_the_workers_compile_the_first_pages_last_kernels_first_while_it_compiles(
    compiling, monkeypatch, first_done
):
    """While the server compiles the first page, the first worker compiles its last kernels
    (compiling.AHEAD), then the parts in order; AHEAD is no part: no page waits for it, and
    "k of 5 parts ready" counts the parts alone."""
    import threading

    from windpump_app import compiling as parts

    pool = SubmittedInOrder()
    monkeypatch.setattr(parts, "ProcessPoolExecutor", lambda *args, **kwargs: pool)
    monkeypatch.setattr(parts, "installed_run_part", lambda: parts.run_part)
    first = threading.Event()
    if first_done:
        first.set()
    rest = [part.name for part in parts.PARTS if part.name != parts.FIRST_PAGE]
    compiling.begin(rest)
    parts.Workers(first).run(rest)
    assert pool.sent == ([] if first_done else [parts.AHEAD]) + rest
    assert rest[0] == parts.REAL_MACHINE  # the presets' real machine next, then the Wind tab
    assert compiling.count() == len(parts.PARTS)
    assert parts.AHEAD not in compiling.names


def test_a_later_start_runs_no_worker_for_a_part_compiled_for_this_source(
    compiling, monkeypatch, tmp_path
):
    """A part a worker recorded for this very source is ready at once on a later start and runs
    in no worker (loading it cost every start seconds of CPU); recorded for other source (numba
    recompiles then), it runs again."""
    from windpump_app import compiling as parts
    from windpump_app.server import hooks as app_hooks

    monkeypatch.setattr(parts, "parts_file", lambda: tmp_path / PARTS_FILE)
    sent = []
    monkeypatch.setattr(app_hooks.WORKERS, "run", sent.extend)
    monkeypatch.setattr(app_hooks, "WARM_UPS", [])  # the page's warm-ups (app/app_hooks.py)
    for name in (parts.WIND_TAB, parts.SITE_TAB):
        parts.record_compiled(name)
    rest = [part.name for part in parts.PARTS if part.name != parts.FIRST_PAGE]
    compiling.begin(rest)
    app_hooks.compile_the_rest()
    assert sent == [name for name in rest if name not in (parts.WIND_TAB, parts.SITE_TAB)]
    assert compiling.ready[parts.WIND_TAB].is_set() and compiling.ready[parts.SITE_TAB].is_set()
    monkeypatch.setattr(parts, "source_stamp", lambda: "another source")
    assert parts.compiled_parts() == set()


class FailingFor(SubmittedInOrder):
    """A pool as SubmittedInOrder, as a context manager, whose part ``failing`` raises."""

    def __init__(self, failing: str):
        super().__init__()
        self.failing = failing

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def submit(self, run, name, parent):
        from concurrent.futures import Future

        if name != self.failing:
            return super().submit(run, name, parent)
        self.sent.append(name)
        failed = Future()
        failed.set_exception(RuntimeError("no such kernel"))
        return failed


def test_the_readmes_compile_step_compiles_every_part_not_yet_compiled(monkeypatch, tmp_path):
    """``python -m windpump_app.compiling`` (the README's serve command, before the server):
    every part not recorded for this source, longest first (no page waits for one), each said
    as it is ready; a part that fails is said, counted, and left to the server; run again with every part
    recorded, it does nothing."""
    from windpump_app import compiling as parts

    monkeypatch.setattr(parts, "parts_file", lambda: tmp_path / PARTS_FILE)
    monkeypatch.setattr(parts, "installed_run_part", lambda: parts.run_part)
    parts.record_compiled(parts.SITE_TAB)
    pool = FailingFor(parts.WIND_TAB)
    monkeypatch.setattr(parts, "ProcessPoolExecutor", lambda *args, **kwargs: pool)
    said: list[str] = []
    assert parts.compile_every_part(say=said.append) == 1
    assert sorted(parts.LONGEST_FIRST) == sorted(part.name for part in parts.PARTS)
    todo = [name for name in parts.LONGEST_FIRST if name != parts.SITE_TAB]
    assert pool.sent == todo  # the wheel first, the recorded Site tab's part not again
    total = len(parts.PARTS)
    assert f"{total - 1} of its {total} parts, 2 at a time" in said[0]
    assert any(f"Compiling {parts.WIND_TAB} failed (RuntimeError" in line for line in said)
    # 2 of 6 ... 5 of 6: neither the recorded part nor the failed one
    assert sum("parts ready" in line for line in said) == total - 2
    assert said[-1].startswith("Compiled in")
    monkeypatch.setattr(parts, "compiled_parts", lambda: {part.name for part in parts.PARTS})
    said.clear()
    assert parts.compile_every_part(say=said.append) == 0
    assert said == ["The solver is compiled (numba's cache): nothing to do."]


def test_the_readmes_compile_step_says_how_long_while_no_part_is_ready(monkeypatch, tmp_path):
    """While no part gets ready the step says how long it has been and which parts it compiles
    (a newcomer's terminal was silent 150 s after its first line and looked hung): the two
    its workers run, not the one a process pool queues ahead."""
    from concurrent.futures import ThreadPoolExecutor

    from windpump_app import compiling as parts

    class Slow(ThreadPoolExecutor):
        def submit(self, run, name, parent):
            return super().submit(lambda: time.sleep(0.4) or 0.4)

    monkeypatch.setattr(parts, "parts_file", lambda: tmp_path / PARTS_FILE)
    monkeypatch.setattr(parts, "installed_run_part", lambda: parts.run_part)
    # three at once, as a process pool of two runs two and marks a third queued ahead running
    monkeypatch.setattr(parts, "ProcessPoolExecutor", lambda *args, **kwargs: Slow(3))
    monkeypatch.setattr(parts, "HEARTBEAT", 0.05)
    said: list[str] = []
    assert parts.compile_every_part(say=said.append) == 0
    first, second = parts.LONGEST_FIRST[:2]
    waiting = [line for line in said if line.endswith(f"(now {first}, {second})")]
    assert waiting and all(f"0 of {len(parts.PARTS)} parts ready, " in line for line in waiting)
    assert sum("parts ready (" in line for line in said) == len(parts.PARTS)


CALLER = """
from windpump._kernels.jit import kernel
from windpump._kernels.zz_callee import step

@kernel
def twice(x):
    return 2.0 * step(x)
"""

RUN_CALLER = "from windpump._kernels.zz_caller import twice; print(twice(1.0))"


def test_a_change_to_a_callees_module_alone_recompiles_its_caller(tmp_path):
    """A kernel loaded from numba's cache holds its callees' code: with numba's own stamp (its
    source file alone) a change to the callee's module left the caller's old code in use. In a
    copy of the package, a caller and a callee in two kernel modules: the callee changed, the
    caller's answer changes with it, on the same cache."""
    core = tmp_path / "core"
    shutil.copytree(
        Path(__file__).resolve().parents[2] / "core" / "windpump",
        core / "windpump",
        ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc"),
    )
    kernels = core / "windpump" / "_kernels"
    (kernels / "zz_caller.py").write_text(CALLER)
    callee = kernels / "zz_callee.py"
    environment = dict(os.environ, PYTHONPATH=str(core))
    environment.pop("NUMBA_CACHE_DIR", None)  # beside the copied source

    def answer(step: str) -> float:
        callee.write_text(
            f"from windpump._kernels.jit import kernel\n\n@kernel\ndef step(x):\n    return {step}\n"
        )
        done = subprocess.run(
            [sys.executable, "-c", RUN_CALLER],
            env=environment,
            capture_output=True,
            text=True,
            check=True,
            timeout=600,
        )
        return float(done.stdout)

    assert answer("x + 1.0") == 4.0
    assert list(kernels.glob("__pycache__/zz_caller.*.nbi"))  # cached, so the next run loads it
    assert answer("x + 10.0") == 22.0  # a new size: numba's stamp of zz_callee.py changes


def test_the_real_machines_part_runs_every_preset_with_a_real_machine():
    """The worker's real-machine part runs the presets whose designs are a real machine, found by
    their designs: by name, a renamed preset made the part a KeyError (the pages then compiled
    the real machine themselves, on the event loop)."""
    from windpump_app.compiling import real_presets
    from windpump_app.inputs import PRESETS, PumpInputs, preset_of

    def design_of(values):
        inputs = PumpInputs()
        inputs.param.update(**values)
        return inputs.design()

    real = {name for name, (values, _) in PRESETS.items() if not design_of(values).is_ideal}
    assert len(real) >= 2  # a deep well, a leak hole
    assert {preset_of(inputs) for inputs in real_presets()} == real


def test_a_page_whose_link_opens_a_real_machine_waits_for_its_part_off_the_loop(compiling):
    """A first start's page whose design is a real machine (a deep well's link) waits off the
    event loop for the real machine's part, saying so, then runs: it waited on the loop, and
    every page stood still meanwhile."""
    import asyncio
    import threading

    from windpump_app.compiling import REAL_MACHINE, real_presets
    from windpump_app.explorer import Explorer
    from windpump_app.server import sessions as serving

    compiling.begin([REAL_MACHINE])
    page = Explorer(start=False)
    page.inputs.param.update(**real_presets()[0].values())
    assert page.part_awaited() == REAL_MACHINE
    page.say_compiling()
    assert "(the real machine)" in page.readouts.status.object

    class Document:
        pending: list = []

        def add_next_tick_callback(self, callback):
            self.pending.append(callback)

    document = Document()
    onload = serving.first_run_when_ready("page", document, page)
    threading.Timer(0.3, compiling.ready[REAL_MACHINE].set).start()
    # in a thread of its own: a browser test's playwright may hold this thread's event loop
    waited = threading.Thread(target=asyncio.run, args=(asyncio.wait_for(onload(), timeout=60),))
    waited.start()
    waited.join(timeout=90)
    assert not waited.is_alive()
    assert page.part_awaited() is None and page.seen is None  # nothing ran on the way
    assert document.pending  # the first run, on the document's next tick


def test_a_page_choosing_a_wheel_waits_for_the_wheels_part_which_runs_a_rotor(compiling):
    """A first start's page whose link opens a wheel (the multiblade, an Aermotor) waits for the
    wheel's part, saying so, rather than compile a rotor's run itself; the part runs a rotor's
    design, ideal and in a day of wind (loaded from this worktree's cache: quick)."""
    import windpump
    from windpump_app.compiling import WHEEL, wheel
    from windpump_app.explorer import Explorer
    from windpump_app.inputs import PumpInputs

    compiling.begin([WHEEL])
    page = Explorer(start=False)
    page.inputs.param.update(windmill="aermotor")
    assert page.part_awaited() == WHEEL
    page.say_compiling()
    assert "(the wheel)" in page.readouts.status.object
    page.inputs.param.update(windmill="eq11")
    assert page.part_awaited() is None  # the paper's curve: nothing of the wheel's
    compiling.ready[WHEEL].set()
    wheel()  # the part: a wheel's design, as a page's inputs make it
    assert PumpInputs(windmill="multiblade").design().rotor == windpump.Rotor.multiblade(2.4)


@pytest.mark.parametrize("samples", [1, 2, 48])
def test_a_records_kernel_arrays_are_typed_as_every_records(samples):
    """The wind record as the kernels take it has numba's type of any other record's: a record
    of one sample handed the driver its own read-only times, and a run compiled the driver anew
    for them (~20-30 s)."""
    import numba

    from windpump.run.machine import kernel_wind

    record = windpump.WindRecord(np.arange(samples) * 600.0, 5.0 + np.arange(samples) % 3)
    reference = kernel_wind(windpump.WindRecord([0.0, 600.0, 1200.0], [4.0, 6.0, 5.0]), 5.0)
    assert numba.typeof(kernel_wind(record, 5.0)) == numba.typeof(reference)
