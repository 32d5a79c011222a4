"""The explorer in a real browser: first page after a fresh start, slider move to new readout, bytes
on the wire, and a class of 30 pages opening at once.

Run: python benchmarks/bench_app.py [first] [slider] [class] [first-start] [readme-start]
(the first three by default; needs Debian's chromium at /usr/bin/chromium)

1. First page: a fresh `panel serve app/`, then the time from opening the page to the mean-flow
   readout showing, for the first page and for a second one (the goal: the same).
2. Page weight: the bytes the first page transfers (compressed as sent) against the same files
   uncompressed.
3. Slider to readout: the head slider moved with the keyboard 30 times; each move is timed in the
   page from the key's keydown event to the readout showing the value windpump computes for the
   new head, and to the plots holding windpump's values; the websocket bytes the server sent
   meanwhile are added up. The baseline, timed in the same run, is the same
   page with display decimation off (`?resolution=full`: every sample of every trace sent).
4. A class: 30 pages opened at once on one server, each in its own browser context made before
   the clock starts; each page's time to its readout and to its views, checked every 250 ms, and
   the CPU the server and each kind of chromium process used until the last readout.
5. First start after an install (`first-start`): `panel serve app/` launched with an empty numba
   cache (NUMBA_CACHE_DIR a fresh directory), timed from the launch to the first page's checked
   readout; then, in that page, each tab's first use (chosen, to its checked readout or its data
   drawn) and each preset's first use (chosen, to the mean-flow readout windpump gives for it);
   then launched again on the cache it left (a later start). Then the seed example's
   first run alone, cold, in a process of its own (import, then explore + power_budget +
   playback_frames as the first page runs them): for this checkout and, with BENCH_BASELINE=<git
   revision>, for that revision's core (extracted with git archive).
6. The README's serve command (`readme-start`): its compile step (`python -m
   windpump_app.compiling`) on an empty numba cache, timed (wall and CPU), then `panel serve app/`
   on that cache, its first page's readout and each tab's and preset's first use as in 5.
Every readout is checked against windpump, so a fast wrong page cannot pass.
"""

from __future__ import annotations

import asyncio
import contextlib
import math
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
import windpump  # noqa: E402
from windpump.units import LITRES_PER_M3  # noqa: E402

from served import (  # noqa: E402
    CHROMIUM,
    CHROMIUM_FLAGS,
    DEEP_TEXT,
    POLL_MS,
    VIEWS_DRAWN,
    cpu_seconds,
    served_app,
)

MOVES = 30
CLASS = 30
SEED = windpump.Design.seed_example()
READOUT = f"() => ({DEEP_TEXT})('[data-name=mean_flow]')"


def readout_text(seen: windpump.Exploration) -> str:
    return f"{LITRES_PER_M3 * seen.mean_flow:.4f} L/s"


def expected_readout(head: float) -> str:
    return readout_text(windpump.explore(SEED.replace(h=head), 600.0, math.pi / 2, 3.0))


def open_timed(browser, url):
    """Open the page; return (seconds to the right readout, bytes on the wire, bytes unpacked)."""
    page = browser.new_page(viewport={"width": 1400, "height": 1000})
    finished = []
    page.on("requestfinished", lambda request: finished.append(request))
    start = time.perf_counter()
    page.goto(url)
    page.wait_for_function(
        f"(e) => ({READOUT})() === e", arg=expected_readout(SEED.h), timeout=300_000
    )
    seconds = time.perf_counter() - start
    wire = sum(r.sizes()["responseBodySize"] + r.sizes()["responseHeadersSize"] for r in finished)
    unpacked = 0
    for request in finished:
        try:
            unpacked += len(request.response().body())
        except Exception:  # a body already released: count what went over the wire
            unpacked += request.sizes()["responseBodySize"]
    page.close()
    return seconds, wire, unpacked


# Timed inside the page, from the key's keydown event: the readout when its text first shows the
# value windpump computes, the plots when the flow view's mean-flow source holds windpump's value
# (Bokeh draws a changed source in the next animation frame). Both checked on each frame.
KEY_TIMES = (
    "window.addEventListener('keydown', () => { window.__keyAt = performance.now(); }, true);"
)
ARRIVED = f"""([text, flow]) => {{
  const now = performance.now();
  if (window.__readoutAt === undefined && ({READOUT})() === text) window.__readoutAt = now;
  const mean = Bokeh.documents[0].get_model_by_name('mean_flow').data.flow[0];
  if (window.__plotsAt === undefined && Math.abs(mean - flow) <= 1e-9 * flow) window.__plotsAt = now;
  return window.__readoutAt !== undefined && window.__plotsAt !== undefined;
}}"""
ELAPSED = "() => [window.__readoutAt - window.__keyAt, window.__plotsAt - window.__keyAt]"
RESET = "() => { window.__keyAt = window.__readoutAt = window.__plotsAt = undefined; }"


def slider_moves(browser, url):
    """MOVES key presses on the head slider: (key-to-readout [s], key-to-plots [s], bytes) each."""
    page = browser.new_page(viewport={"width": 1400, "height": 1000})
    page.add_init_script(KEY_TIMES)
    received = []
    page.on(
        "websocket", lambda ws: ws.on("framereceived", lambda frame: received.append(len(frame)))
    )
    page.goto(url)
    page.wait_for_function(f"() => ({READOUT})() !== null", timeout=300_000)
    title = page.locator(".bk-slider-title", has_text="Head h [m]")
    page.locator(".bk-input-group", has=title).locator(".noUi-handle").focus()
    time.sleep(1)
    readouts, plots, sizes, head = [], [], [], SEED.h
    for move in range(MOVES):
        key, head = ("ArrowRight", head + 0.1) if move % 2 == 0 else ("ArrowLeft", head - 0.1)
        seen = windpump.explore(SEED.replace(h=round(head, 1)), 600.0, math.pi / 2, 3.0)
        page.evaluate(RESET)
        received.clear()
        page.keyboard.press(key)
        page.wait_for_function(
            ARRIVED,
            arg=[readout_text(seen), LITRES_PER_M3 * seen.mean_flow],
            polling="raf",
            timeout=60_000,
        )
        to_readout, to_plots = page.evaluate(ELAPSED)
        readouts.append(to_readout / 1e3)
        plots.append(to_plots / 1e3)
        time.sleep(0.3)  # let the rest of the update arrive before counting its bytes
        sizes.append(sum(received))
    page.close()
    return readouts, plots, sizes


async def a_class(url, server_pid):
    """CLASS pages opened at once: each one's seconds from opening to its correct readout, and
    to its views drawn; and the CPU each kind of process had used when the last readout showed.

    Each student has a browser of their own (a browser context: its own cache and connections),
    open before the lecture: the 30 blank pages are made first, then all go to the URL at once.
    """
    from playwright.async_api import async_playwright

    target = expected_readout(SEED.h)
    at_last_readout = {}
    shown = []

    async def student(page):
        start = time.perf_counter()
        await page.goto(url, timeout=600_000)
        await page.wait_for_function(
            f"(e) => ({READOUT})() === e", arg=target, timeout=600_000, polling=POLL_MS
        )
        readout = time.perf_counter() - start
        shown.append(readout)
        if len(shown) == CLASS:
            at_last_readout.update(cpu_by_process(server_pid))
        await page.wait_for_function(VIEWS_DRAWN, timeout=600_000, polling=POLL_MS)
        views = time.perf_counter() - start
        await page.close()
        return readout, views

    async with async_playwright() as playwright:
        browser = await playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_FLAGS)
        try:
            pages = await asyncio.gather(*(browser.new_page() for _ in range(CLASS)))
            await asyncio.sleep(2.0)  # the blank pages settle
            start_cpu = cpu_by_process(server_pid)
            times = await asyncio.gather(*(student(page) for page in pages))
        finally:
            await browser.close()
    used = {kind: at_last_readout[kind] - start_cpu.get(kind, 0.0) for kind in at_last_readout}
    return times, used


def cpu_by_process(server_pid: int) -> dict[str, float]:
    """CPU seconds used so far by this process's descendants, by kind: the server, and chromium's
    processes by their --type (browser, renderer, gpu-process, ...), from /proc."""
    parents, kinds = {}, {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        pid = int(stat.parent.name)
        try:
            parents[pid] = int(stat.read_text().rsplit(")", 1)[1].split()[1])
            # chromium rewrites its children's command lines as one space-separated string
            arguments = (stat.parent / "cmdline").read_bytes().replace(b"\0", b" ").split()
        except (OSError, IndexError, ValueError):
            continue
        types = [a[7:].decode() for a in arguments if a.startswith(b"--type=")]
        program = arguments[0] if arguments else b""  # none for a kernel thread
        kinds[pid] = types[0] if types else "browser" if b"chrom" in program else "other"
    used: dict[str, float] = {}
    for pid in kinds:
        ancestor = pid
        while ancestor in parents and ancestor not in (os.getpid(), 0, 1):
            ancestor = parents[ancestor]
        if ancestor != os.getpid():
            continue
        kind = "server" if pid == server_pid else kinds[pid]
        try:
            used[kind] = used.get(kind, 0.0) + cpu_seconds(pid)
        except OSError:  # it ended meanwhile
            pass
    return used


@contextlib.contextmanager
def a_browser():
    """Chromium driven by playwright's sync API (the class uses its async API instead)."""
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_FLAGS)
        try:
            yield browser
        finally:
            browser.close()


def first_pages():
    with a_browser() as browser, served_app() as (url, _server):
        first, wire, unpacked = open_timed(browser, url)
        second, *_ = open_timed(browser, url)
    print("1. after a fresh `panel serve app/` (readout checked against windpump)")
    print(f"   first page {first:6.2f} s, second page {second:6.2f} s, ratio {first / second:.2f}")
    print("2. first page's weight")
    print(
        f"   {wire / 1e6:.2f} MB on the wire, {unpacked / 1e6:.2f} MB unpacked "
        f"({unpacked / wire:.1f}x)"
    )


def slider():
    rows = {}
    for name, query in [
        ("explorer (min/max bands)", ""),
        ("baseline: every sample sent", "?resolution=full"),
    ]:
        with a_browser() as browser, served_app() as (url, _server):
            slider_moves(browser, url + query)  # warm-up
            rows[name] = slider_moves(browser, url + query)
    print(f"3. seed example, {MOVES} moves of the head slider, timed in the page from the key's")
    print("   keydown; readout and plotted mean flow both checked against windpump")
    print(f"   {'':30s}{'readout median':>15s}{'90th pct':>10s}{'plots median':>14s}{'bytes':>12s}")
    for name, (readouts, plots, sizes) in rows.items():
        p90 = statistics.quantiles(readouts, n=10)[-1]
        print(
            f"   {name:30s}{statistics.median(readouts) * 1e3:12.0f} ms{p90 * 1e3:7.0f} ms"
            f"{statistics.median(plots) * 1e3:11.0f} ms{statistics.median(sizes) / 1e3:9.1f} KB"
        )
    (fast, fast_plots, fast_bytes), (slow, slow_plots, slow_bytes) = rows.values()
    ratio = lambda a, b: statistics.median(a) / statistics.median(b)  # noqa: E731
    print(
        f"   baseline / explorer: readout {ratio(slow, fast):.1f}x, plots "
        f"{ratio(slow_plots, fast_plots):.1f}x, bytes {ratio(slow_bytes, fast_bytes):.0f}x"
    )


def classroom():
    with served_app() as (url, server):
        before = cpu_seconds(server.pid)
        times, used = asyncio.run(a_class(url, server.pid))
        server_cpu = cpu_seconds(server.pid) - before
    readouts, views = (sorted(column) for column in zip(*times, strict=True))
    print(
        f"4. {CLASS} pages opened at once on one server, the {CLASS} pages in one chromium on the"
    )
    print("   same 2 cores (a class brings its own browsers: the server's CPU is its share)")
    print(
        f"   checked readout: median {statistics.median(readouts):.1f} s, slowest "
        f"{readouts[-1]:.1f} s (goal: every page within 30 s)"
    )
    print(f"   views drawn:     median {statistics.median(views):.1f} s, slowest {views[-1]:.1f} s")
    print(f"   server CPU: {server_cpu:.0f} s for the class, {server_cpu / CLASS:.2f} s a page")
    shares = ", ".join(f"{kind} {seconds:.0f} s" for kind, seconds in sorted(used.items()))
    print(f"   CPU used until the last readout showed: {shares} ({sum(used.values()):.0f} s")
    print(f"   on 2 cores in {readouts[-1]:.0f} s)")


def launch_to_readout(
    browser, cache: str, uses: dict | None = None
) -> tuple[float, float, float, float, list]:
    """Seconds from launching `panel serve app/` (numba caching to ``cache``) to its answering,
    to the first page's averaged τ (shown while the solver compiles) and to its checked readout
    (the full run's mean flow); and the server's CPU seconds by then (a measure a
    busy machine disturbs less). With ``uses`` (``expected_first_uses()``), then each tab's and
    each preset's first use in that page: (name, seconds from choosing it to its checked
    readout, seconds from the launch)."""
    before = os.environ.get("NUMBA_CACHE_DIR")
    os.environ["NUMBA_CACHE_DIR"] = cache  # the server inherits it
    used = []
    try:
        start = time.perf_counter()
        with served_app(timeout=600) as (url, server):
            up, up_cpu = time.perf_counter() - start, cpu_seconds(server.pid)
            # a browser context of its own: nothing cached from the other start
            context = browser.new_context(viewport={"width": 1400, "height": 1000})
            page = context.new_page()
            page.goto(url, timeout=600_000)
            # the averaged theory's τ, shown while the solver compiles (or with the full run's)
            page.wait_for_function(TAU_SHOWN, arg=AVERAGED_TAU, timeout=600_000)
            averaged = time.perf_counter() - start
            page.wait_for_function(
                f"(e) => ({READOUT})() === e", arg=expected_readout(SEED.h), timeout=600_000
            )
            readout, readout_cpu = time.perf_counter() - start, cpu_seconds(server.pid)
            for name, (choose, check, expected) in (uses or {}).items():
                chosen = time.perf_counter()
                choose(page)
                page.wait_for_function(check, arg=expected, timeout=600_000, polling=POLL_MS)
                done = time.perf_counter()
                used.append((name, done - chosen, done - start))
            context.close()
    finally:
        if before is None:
            del os.environ["NUMBA_CACHE_DIR"]
        else:
            os.environ["NUMBA_CACHE_DIR"] = before
    return up, averaged, readout, up_cpu, readout_cpu, used


# The paper's example's τ (Eq. 25, from the core) in its readout, shown while the solver compiles
AVERAGED_TAU = f"{windpump.time_constant(SEED):.1f}"
TAU_SHOWN = f"(e) => (({DEEP_TEXT})('[data-name=tau]') || '').startsWith(e)"
# A readout's text, by its data-name, equal to the expected one (the argument)
SHOWS = "(([name, e]) => ({DEEP_TEXT})(`[data-name=${{name}}]`) === e)"
# A readout, by its data-name, shown (the Mechanisms tab's depends on the animation's angle)
PRESENT = "((name) => ({DEEP_TEXT})(`[data-name=${{name}}]`) !== null)"
# A named Bokeh data source with rows
HOLDS = (
    "(name) => {{ const m = window.Bokeh.documents[0].get_model_by_name(name);"
    " return m !== null && Object.values(m.data).some((c) => c.length > 0) }}"
)


def tab(name: str):
    return lambda page: page.get_by_role("tab", name=name, exact=True).click()


def preset(name: str):
    def choose(page):
        page.get_by_role("tab", name="Wind pump", exact=True).click()
        page.locator("select").filter(has_text="Choose a preset").select_option(name)

    return choose


def expected_first_uses() -> dict:
    """name -> (what the page does, the check run in it, its argument): each tab chosen, to its
    readout as windpump gives it (the Design map: its map drawn), then each preset chosen, to
    its mean-flow readout as windpump gives it. Worked out here before any server starts, so
    this process's own compiling does not share the cores with the server's."""
    from windpump.units import LITRES_PER_M3 as LITRES
    from windpump_app.inputs import PRESETS, PumpInputs
    from windpump_app.wind_tab import kick_in_wind, run_day, wind_of

    shows = SHOWS.format(DEEP_TEXT=DEEP_TEXT)
    inputs = PumpInputs()
    design = inputs.design_at_v_ref()
    wind = (inputs.mean_wind, inputs.k, inputs.time_scale, int(round(inputs.seed)))
    day, _low, _high = run_day(
        design, wind_of(wind), inputs.theta0, kick_in_wind(design, inputs.theta_dot0)
    )
    record = windpump.sample_site("greensboro").at_height(10.0)
    year = windpump.supply(SEED, record, 10.0, 5.0, restart="attended")
    uses = {
        "Mechanisms tab": (tab("Mechanisms"), PRESENT.format(DEEP_TEXT=DEEP_TEXT), "slider_crank"),
        "Wind tab": (tab("Wind"), shows, ["day_litres", f"{LITRES * day.volume:,.0f}"]),
        "Design map tab": (tab("Design map"), HOLDS.format(), "maptab_here"),
        "Site tab": (tab("Site"), shows, ["site_lolp", f"{100 * year.lolp:.1f} %"]),
    }
    for name, (values, _sentence) in PRESETS.items():
        chosen = PumpInputs()
        chosen.param.update(**values)
        seen = windpump.explore(chosen.design(), chosen.t_end, chosen.theta0, chosen.theta_dot0)
        uses[f"preset: {name}"] = (preset(name), shows, ["mean_flow", readout_text(seen)])
    return uses


# The first page's runs, alone, timed in a process of its own (wall and CPU seconds).
FIRST_RUN = """
import time
started = time.perf_counter()
import windpump
imported = time.perf_counter()
cpu = time.process_time()
seen = windpump.explore(windpump.Design.seed_example(), 600.0)
windpump.power_budget(seen.run).cycle_means()
windpump.playback_frames(seen.run)
print(imported - started, time.perf_counter() - imported, time.process_time() - cpu)
"""


def cold_first_run(core: Path) -> tuple[float, float, float]:
    """(import, first page's runs, their CPU) [s] with ``core`` on the path and an empty cache."""
    with tempfile.TemporaryDirectory() as cache:
        environment = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPATH=str(core))
        done = subprocess.run(
            [sys.executable, "-c", FIRST_RUN],
            env=environment,
            capture_output=True,
            text=True,
            check=True,
            timeout=900,
        )
    imported, runs, cpu = (float(word) for word in done.stdout.split())
    return imported, runs, cpu


def baseline_core(revision: str, into: Path) -> Path:
    """The core of a git revision of this repository, extracted under ``into``."""
    root = Path(__file__).resolve().parents[1]
    archive = subprocess.run(
        ["git", "-C", str(root), "archive", revision, "core"], capture_output=True, check=True
    )
    subprocess.run(["tar", "-x", "-C", str(into)], input=archive.stdout, check=True)
    return into / "core"


def first_start():
    # A browser's first page after its launch costs it ~1 s more than later pages; an instructor's
    # browser is usually open already: both are timed, each with an empty numba cache.
    uses = expected_first_uses()
    with a_browser() as browser, tempfile.TemporaryDirectory() as cache:
        starts = {"first start, browser just launched": launch_to_readout(browser, cache)}
        with tempfile.TemporaryDirectory() as fresh:
            starts["first start, browser already open"] = launch_to_readout(browser, fresh, uses)
            # on the cache the first uses filled (the first start's, stopped after its first page,
            # has only the parts done by then: its next start compiles the rest)
            starts["later start"] = launch_to_readout(browser, fresh, uses)
    print("5. first start after an install: `panel serve app/` launched with an empty numba cache")
    print(
        "   from the launch: answering, the averaged τ, first page's checked readout (server CPU)"
    )
    for name, (up, averaged, readout, up_cpu, readout_cpu, _used) in starts.items():
        print(
            f"   {name:34s} answering {up:5.1f} s ({up_cpu:4.1f} s of CPU), averaged τ"
            f" {averaged:5.1f} s, readout {readout:5.1f} s ({readout_cpu:4.1f} s of CPU)"
        )
    for name in ("first start, browser already open", "later start"):
        print(f"   {name}: each first use after the first page, in order (readouts checked)")
        print(f"   {'':40s}{'chosen to shown':>16s}{'from launch':>13s}")
        for use, took, since_launch in starts[name][5]:
            print(f"   {use:40s}{took:14.1f} s{since_launch:11.1f} s")
    print("   the first page's runs alone, cold, in a process of their own:")
    cores = {"this checkout": Path(__file__).resolve().parents[1] / "core"}
    with tempfile.TemporaryDirectory() as extracted:
        if os.environ.get("BENCH_BASELINE"):
            revision = os.environ["BENCH_BASELINE"]
            cores[f"BENCH_BASELINE={revision}"] = baseline_core(revision, Path(extracted))
        for name, core in cores.items():
            imported, runs, cpu = cold_first_run(core)
            print(
                f"   {name:28s} import {imported:4.1f} s, runs {runs:5.1f} s ({cpu:4.1f} s of CPU)"
            )


def compile_step(cache: str) -> tuple[float, float]:
    """The README's compile step, ``python -m windpump_app.compiling``, on ``cache``: its wall
    seconds and the CPU seconds of it and its worker processes."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    subprocess.run(
        [sys.executable, "-m", "windpump_app.compiling"],
        env=dict(os.environ, NUMBA_CACHE_DIR=cache),
        check=True,
        timeout=1800,
    )
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    return time.perf_counter() - started, cpu


def readme_start():
    """The README's serve command after an install: the compile step on an empty numba cache,
    then `panel serve app/`, its first page and each tab's and preset's first use."""
    uses = expected_first_uses()
    with a_browser() as browser, tempfile.TemporaryDirectory() as cache:
        wall, cpu = compile_step(cache)
        up, _averaged, readout, up_cpu, readout_cpu, used = launch_to_readout(browser, cache, uses)
    print("6. the README's serve command: the compile step, then `panel serve app/`")
    print(f"   compile step on an empty cache {wall:5.1f} s ({cpu:5.1f} s of CPU, its workers')")
    print(f"   then from the launch: answering {up:5.1f} s ({up_cpu:4.1f} s of CPU), readout")
    print(f"   {readout:5.1f} s ({readout_cpu:4.1f} s of CPU); each first use after it:")
    print(f"   {'':40s}{'chosen to shown':>16s}{'from launch':>13s}")
    for use, took, since_launch in used:
        print(f"   {use:40s}{took:14.1f} s{since_launch:11.1f} s")


PARTS = {
    "first": first_pages,
    "slider": slider,
    "class": classroom,
    "first-start": first_start,
    "readme-start": readme_start,
}
DEFAULT_PARTS = ("first", "slider", "class")


def main(parts=DEFAULT_PARTS):
    for part in parts:
        PARTS[part]()


if __name__ == "__main__":
    main(sys.argv[1:] or DEFAULT_PARTS)
