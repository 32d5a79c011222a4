"""The solver compiled in parts, in the order a page needs them, on a first start after an
install (an empty numba cache): the first page's kernels in the server itself, the rest in worker
processes that write numba's on-disk cache, from which the server loads each part once it is
ready. A page that needs a part still compiling waits for it (``COMPILE.wait``) rather than
compiling it a second time, and says so (``COMPILE.progress``).

Measured on a fresh cache (benchmarks/bench_app.py first-start; docs/measured.rst and
docs/known-issues.rst, "The first start after an install"): the first page's part takes 13.5-14.5
s of CPU, its readout 20-23 s after the launch at load 2-4; while the server compiles it,
the first worker compiles its last kernels (``AHEAD``), which the server then loads from the
cache (1.5 s of CPU less at load 3.5, nothing at load 6). The presets' real machine, the Wind
tab's and the real machine in wind are each a compile of their own of the driver, of 17-26 s of
CPU; the Site tab's year ~2 s. A part compiled in a worker is written to the cache when it is
done: a server stopped meanwhile keeps every part done, and the next start compiles only the
others.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import logging
import os
import threading
import time
from collections.abc import Callable
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from multiprocessing import get_context
from pathlib import Path

log = logging.getLogger("windpump.app")

COMPILING = "compiling the solver (once after an install)"


# -- the parts, each run in a worker process (module-level functions: spawned workers import them)


def first_page() -> None:
    """What a first page runs: the paper's example, its energy budget and its animation."""
    import windpump

    seen = windpump.explore(windpump.Design.seed_example(), 600.0)
    windpump.power_budget(seen.run).cycle_means()
    windpump.playback_frames(seen.run)


def real_machine() -> None:
    """What the presets with a real machine run (a deep well's rod and rising main, a leak
    hole): the driver compiled for the real machine, and the leak hole's flow."""
    import windpump

    for inputs in real_presets():
        seen = windpump.explore(inputs.design(), inputs.t_end, inputs.theta0, inputs.theta_dot0)
        seen.volumetric_efficiency  # noqa: B018 (the leak hole's flow, worked out on reading)
        windpump.power_budget(seen.run).cycle_means()
        windpump.playback_frames(seen.run)


def first_page_ahead() -> None:
    """The first page's last kernels (``driver.compile_ahead``), compiled in a worker while the
    server compiles the first page's part: numba compiles in one thread at a time, and the
    server loads these from the cache when it comes to them (its first page's compile was
    1.5-3 s shorter, of ~13.5 s of CPU). No page waits for them: not a part."""
    import windpump
    from windpump._kernels.driver import compile_ahead
    from windpump.run.dynamics import kernel_machine

    compile_ahead(kernel_machine(windpump.Design.seed_example()))


def real_presets() -> list:
    """The inputs of every preset with a real machine, found by their designs (not by name: a
    preset renamed left the worker's part a KeyError, and the pages compiled it themselves)."""
    from .inputs import PRESETS, PumpInputs

    found = []
    for values, *_ in PRESETS.values():
        inputs = PumpInputs()
        inputs.param.update(**values)
        if not inputs.design().is_ideal:
            found.append(inputs)
    return found


def wind_tab() -> None:
    """What a first Wind tab runs (``wind_tab.warm_up``): a gusty day in full."""
    from .inputs import PumpInputs
    from .wind_tab import warm_up

    warm_up(PumpInputs())


def real_in_wind() -> None:
    """What the Wind tab runs for a preset with a real machine (its own compile of the driver,
    as long as the real machine's): the first such preset's gusty day (the driver is compiled
    by the machine's types, the same for every real machine)."""
    from .wind_tab import warm_up

    warm_up(real_presets()[0])


def wheel() -> None:
    """What a page choosing a wheel runs (the multiblade wheel, an Aermotor, their preset): the
    driver compiled for a rotor's C_Q table (a specialisation of its own), ideal and in a wind
    record (the Wind tab's gusty day), and with the real machine's losses (the sliders under
    "Real machine"), alone and in wind."""
    import windpump

    from .inputs import PumpInputs
    from .wind_tab import warm_up

    for real in (False, True):
        inputs = PumpInputs(windmill="multiblade")
        if real:
            inputs.param.update(eta_t=0.9)
        seen = windpump.explore(inputs.design(), inputs.t_end, inputs.theta0, inputs.theta_dot0)
        windpump.power_budget(seen.run).cycle_means()
        windpump.playback_frames(seen.run)
        warm_up(inputs)


def site_tab() -> None:
    """What a first Site tab runs: the year at the sample site, its tank for 5 % and its
    loss-of-load curve (``site_year.run_year``)."""
    import numpy as np

    import windpump

    from .inputs import PumpInputs
    from .site_figures import LOLP_TARGET
    from .site_inputs import SiteInputs
    from .site_year import TANKS

    design, site = PumpInputs().design_at_v_ref(), SiteInputs()
    record = windpump.sample_site(site.site).at_height(site.hub)
    rule = dict(restart=site.restart)
    windpump.tank_for(design, record, site.demand, LOLP_TARGET, **rule)
    tanks = np.linspace(0.0, 20.0, TANKS)
    windpump.supply_map(design, record, site.demand, [design.R_dagger], tanks, **rule)
    windpump.supply(design, record, site.demand, site.tank, **rule)


@dataclasses.dataclass(frozen=True)
class Part:
    name: str  # as the page and the terminal say it
    run: Callable[[], None]


FIRST_PAGE, REAL_MACHINE = "the first page", "the real machine"
WIND_TAB, SITE_TAB, REAL_IN_WIND = "the Wind tab", "the Site tab", "the real machine in wind"
WHEEL = "the wheel"
# In the order a page needs them: the first page (in the server, alone on its core), then, in
# workers, the presets' real machine (the deep-well and leak-hole presets: with it third, after
# the Wind tab's, the deep-well preset waited 39.7 s after the first page), the Wind tab, the
# Site tab, and the Wind tab's day of a preset with a real machine (a fourth compile of the
# driver, the least likely to be needed first). The wheel's (a rotor's runs, ideal and in wind)
# after the Wind tab's: a class opens the Wind tab before it chooses a windmill.
PARTS = (
    Part(FIRST_PAGE, first_page),
    Part(REAL_MACHINE, real_machine),
    Part(WIND_TAB, wind_tab),
    Part(WHEEL, wheel),
    Part(SITE_TAB, site_tab),
    Part(REAL_IN_WIND, real_in_wind),
)

# The README's compile step (every part before the server starts: no page waits for one) runs
# them longest first, so that neither worker is left alone with a long one at the end. Each
# part's seconds in its worker (a CI run, load 6-8): the wheel 96, the real machine 79, the
# first page 62, the real machine in wind 33, the Wind tab 20, the Site tab 3; in PARTS' order
# the step took 178 s on 2 cores (the wheel started last), longest first ~150 s.
LONGEST_FIRST = (WHEEL, REAL_MACHINE, FIRST_PAGE, REAL_IN_WIND, WIND_TAB, SITE_TAB)

# Compiled ahead in the first worker while the server compiles the first page's part
AHEAD = "the first page's last kernels"


def run_part(name: str, parent: int) -> float:
    """Run part ``name`` (or AHEAD) in this worker process (numba writes what it compiles to its
    cache); the seconds it took. The worker ends with the server (``parent``), whatever stops
    it, and gives way to it (``WORKER_NICENESS``): the server's first page and its pages' moves
    come first."""
    watch_parent(parent)
    started = time.perf_counter()
    if name == AHEAD:
        first_page_ahead()
        return time.perf_counter() - started
    next(part for part in PARTS if part.name == name).run()
    record_compiled(name)  # in this process's cache (the server's, by its NUMBA_CACHE_DIR)
    return time.perf_counter() - started


def watch_parent(parent: int) -> None:
    """End this process (``os._exit``) once ``parent`` is gone: a server killed mid-compile
    leaves no worker behind."""

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(0)

    if not any(thread.name == "watch the server" for thread in threading.enumerate()):
        threading.Thread(target=watch, name="watch the server", daemon=True).start()
        os.nice(WORKER_NICENESS)


# A worker's nice value over the server's: on two cores, one compiling the first page's part in
# the server, it takes the other core, but not from the server's pages.
WORKER_NICENESS = 10


def installed_run_part() -> Callable[[str, int], float]:
    """``run_part`` as a spawned worker imports it: from the installed ``windpump_app`` (served,
    Bokeh runs this folder as a package of a made-up name no other process can import), which
    must be this very file (an editable install, or ``pip install .`` of this checkout)."""
    from windpump_app import compiling

    if os.path.realpath(compiling.__file__) != os.path.realpath(__file__):
        raise RuntimeError(f"windpump_app is installed from {compiling.__file__}, not {__file__}")
    return compiling.run_part


# -- which parts a worker has compiled into numba's cache, for the source it compiled

PARTS_FILE = "windpump-parts-compiled.json"


def source_stamp() -> str:
    """A digest of the solver's source files (path, size, modification time, as numba stamps a
    cached kernel's source) and numba's version: a part recorded under another stamp is stale."""
    import numba

    import windpump

    digest = hashlib.sha256(numba.__version__.encode())
    for path in sorted(Path(windpump.__file__).parent.rglob("*.py")):
        stat = path.stat()
        digest.update(f"{path}:{stat.st_size}:{stat.st_mtime_ns}".encode())
    return digest.hexdigest()


def parts_file() -> Path | None:
    """Where the parts compiled are recorded: beside the driver's cache (numba's private cache
    API; None when it has changed or caching is off, and then every start runs the workers)."""
    try:
        from windpump._kernels import driver

        return Path(driver.integrate._cache._cache_path) / PARTS_FILE
    except Exception:
        return None


def compiled_parts() -> set[str]:
    """The parts a worker compiled into the cache for this very source (``record_compiled``)."""
    where = parts_file()
    try:
        recorded = json.loads(where.read_text()) if where else {}
    except (OSError, ValueError):
        return set()
    stamp = source_stamp()
    return (
        {name for name, its in recorded.items() if its == stamp}
        if isinstance(recorded, dict)
        else set()
    )


def record_compiled(name: str) -> None:
    """Record that part ``name`` is in numba's cache for this source, so a later start runs no
    worker for it (a worker only loading a part cost every start seconds of CPU)."""
    where = parts_file()
    if where is None:
        return
    try:
        recorded = json.loads(where.read_text())
    except (OSError, ValueError):
        recorded = {}
    recorded = recorded if isinstance(recorded, dict) else {}
    recorded[name] = source_stamp()
    try:
        temporary = where.with_suffix(f".{os.getpid()}.tmp")
        temporary.write_text(json.dumps(recorded))
        temporary.replace(where)  # whole or not at all
    except OSError:
        pass  # not recorded: the next start's worker loads it from the cache


class Compile:
    """Which parts of the solver are ready: all of them unless a first start compiles them
    (``begin``). ``wait(name)`` blocks until part ``name`` is ready; ``progress()`` says how far
    the compile is ("compiling the solver (once after an install): 2 of 6 parts ready"), or ""
    once every part is ready."""

    def __init__(self, parts=PARTS):
        self.names = [part.name for part in parts]
        self.ready = {name: threading.Event() for name in self.names}
        for event in self.ready.values():
            event.set()

    def begin(self, names=None) -> None:
        """Parts ``names`` (all of them by default) are being compiled."""
        for name in self.names if names is None else names:
            self.ready[name].clear()

    def done(self, name: str, seconds: float | None = None) -> None:
        self.ready[name].set()
        took = "" if seconds is None else f" in {seconds:.1f} s"
        log.info("%s: %s ready%s", self.progress() or COMPILING, name, took)

    def count(self) -> int:
        return sum(event.is_set() for event in self.ready.values())

    def progress(self) -> str:
        if self.count() == len(self.names):
            return ""
        return f"{COMPILING}: {self.count()} of {len(self.names)} parts ready"

    def wait(self, name: str) -> None:
        self.ready[name].wait()

    def waiting(self, name: str) -> str:
        """What a page says while part ``name`` is compiling (Markdown), or "" once it is ready:
        "**Compiling the solver (once after an install): 1 of 6 parts ready.** These numbers
        follow once its part (the Wind tab) is ready." """
        return "" if self.ready[name].is_set() else self.saying(name)

    def saying(self, name: str, numbers: str = "These numbers") -> str:
        """What ``waiting(name)`` says while part ``name`` compiles, whether or not it does;
        ``numbers``: what follows once it is ready."""
        progress = self.progress() or COMPILING
        return (
            f"**{progress[0].upper()}{progress[1:]}.** {numbers} follow once its part "
            f"({name}) is ready."
        )


COMPILE = Compile()


class Workers:
    """Parts compiled in worker processes (spawned: a fresh interpreter each, with the server's
    environment and its NUMBA_CACHE_DIR), in order, one at a time while the server compiles the
    first page on one core, two at a time once it is done (two cores)."""

    def __init__(self, first_done: threading.Event, processes: int = 2):
        self.first_done = first_done
        self.processes = processes
        self.pool: ProcessPoolExecutor | None = None
        self.stopped = False

    def run(self, names: list[str]) -> None:
        """Compile parts ``names`` (marked not ready by COMPILE.begin), each marked ready when
        its worker is done; a part whose worker failed is marked ready too (a page then compiles
        what it needs itself)."""
        if not names:
            return
        run = installed_run_part()
        self.pool = ProcessPoolExecutor(self.processes, mp_context=get_context("spawn"))
        # the first page's last kernels first while the server compiles the first page's part
        ahead = [] if self.first_done.is_set() else [AHEAD]
        pending, running = ahead + list(names), {}
        try:
            while (pending or running) and not self.stopped:
                limit = self.processes if self.first_done.is_set() else 1
                while pending and len(running) < limit:
                    name = pending.pop(0)
                    running[self.pool.submit(run, name, os.getpid())] = name
                finished, _ = wait(list(running), timeout=0.5, return_when=FIRST_COMPLETED)
                for future in finished:
                    self.finished(running.pop(future), future)
        finally:
            for name in pending + list(running.values()):
                if name != AHEAD:
                    COMPILE.ready[name].set()  # never leave a page waiting
            self.pool.shutdown(wait=False, cancel_futures=True)

    def finished(self, name: str, future: Future) -> None:
        try:
            seconds = future.result()
        except Exception:
            log.exception("compiling %s in a worker failed", name)
            seconds = None
        if name == AHEAD:  # no page waits for it
            log.info("%s: %s compiled ahead", COMPILING, name)
            return
        COMPILE.done(name, seconds)

    def stop(self) -> None:
        """End the workers now (the server stops): a part under way is compiled again next time."""
        self.stopped = True
        if self.pool is not None:
            for process in list((getattr(self.pool, "_processes", None) or {}).values()):
                process.terminate()
            self.pool.shutdown(wait=False, cancel_futures=True)


# -- every part compiled before the server starts (the README's serve command)

BEFORE_SERVING = 2  # worker processes: one a core of the 2-core machines it is made for


def compile_every_part(processes: int = BEFORE_SERVING, say: Callable[[str], None] = print) -> int:
    """Compile every part not yet in numba's cache for this source, longest first
    (``LONGEST_FIRST``), in ``processes`` worker processes, saying each as it is ready and, while
    none is, how long it has been every ``HEARTBEAT`` seconds; the number of parts that failed (a
    server then compiles what a page needs itself). After it, ``panel serve app/`` loads the
    solver from the cache (its first page's readout in ~3-4 s) and runs no worker: the README's
    serve command runs it once before serving (``python -m windpump_app.compiling``)."""
    todo = [name for name in LONGEST_FIRST if name not in compiled_parts()]
    if not todo:
        say("The solver is compiled (numba's cache): nothing to do.")
        return 0
    which = (
        f"{len(todo)} of its {len(PARTS)} parts" if len(todo) < len(PARTS) else f"{len(todo)} parts"
    )
    say(
        f"{COMPILING[0].upper()}{COMPILING[1:]}: {which}, {processes} at a time, "
        f"1.5-4 minutes on 2 cores; later starts load them from numba's cache."
    )
    run, started, failed = installed_run_part(), time.perf_counter(), 0
    ready = len(PARTS) - len(todo)
    with ProcessPoolExecutor(processes, mp_context=get_context("spawn")) as pool:
        running = {pool.submit(run, name, os.getpid()): name for name in todo}
        while running:
            finished, _ = wait(list(running), timeout=HEARTBEAT, return_when=FIRST_COMPLETED)
            if not finished:  # a newcomer's terminal silent for minutes looked hung
                elapsed = time.perf_counter() - started
                # the pool queues one part ahead and calls it running: the first ``processes``
                # in the order sent are the ones its workers run
                busy = [name for future, name in running.items() if future.running()]
                now = ", ".join(busy[:processes])
                say(
                    f"{COMPILING}: {ready} of {len(PARTS)} parts ready, {elapsed:.0f} s (now {now})"
                )
            for future in finished:
                name = running.pop(future)
                try:
                    seconds = future.result()
                except Exception as error:  # the server compiles it on a page's first use instead
                    failed += 1
                    say(
                        f"Compiling {name} failed ({type(error).__name__}: {error}); the server will."
                    )
                    continue
                ready += 1
                said = f"{name}, {seconds:.1f} s in its worker"
                say(f"{COMPILING}: {ready} of {len(PARTS)} parts ready ({said})")
    say(f"Compiled in {time.perf_counter() - started:.0f} s.")
    return failed


# [s] the README's compile step says how long it has been after this long without a part ready
# (its longest part took 96-233 s in its worker: 150 s of silence on a busy machine)
HEARTBEAT = 30.0


if __name__ == "__main__":
    compile_every_part()
