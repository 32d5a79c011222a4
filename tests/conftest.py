"""Shared designs and the reference runs, computed once per test session."""

from __future__ import annotations

import math
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

import windpump

from reference import reference_run
from served import CHROMIUM, CHROMIUM_FLAGS, OPENED_PAGES, require_chromium, served_app

SEED = windpump.Design.seed_example()
SEED_MARGIN = windpump.stall_margin(SEED)

# name: (design, t_end [s], theta0 [rad], theta_dot0 [rad/s])
ACCURACY_CASES = {
    "seed example": (SEED, 600.0, math.pi / 2, 3.0),
    "short rod L/R = 1.5": (SEED.replace(L=0.06), 300.0, math.pi / 2, 3.0),
    "near stall, margin 1.05": (SEED.replace(h=3.0 * SEED_MARGIN / 1.05), 600.0, math.pi / 2, 12.0),
    "overload, margin 0.95": (SEED.replace(h=3.0 * SEED_MARGIN / 0.95), 1200.0, math.pi / 2, 12.0),
    "kick below alpha-": (SEED, 600.0, math.pi / 2, 1.0),
    "light rotor, large ripple": (
        SEED.replace(I0=SEED.I0 / 100, I1=SEED.I1 / 100, h=6.0),
        60.0,
        0.3,
        5.0,
    ),
}


# Under pytest-xdist the workers share numba's on-disk cache (beside the kernels' source), and
# numba writes a cache's index unlocked: two processes compiling one kernel at once may each
# give its code the same data file. So the controller compiles what the app compiles (every
# part of windpump_app.compiling, one after another) before any worker starts; the workers then
# load, not write. In its own process: the controller itself stays without numba.
WARM_UP = "from windpump_app import compiling\nfor part in compiling.PARTS:\n    part.run()"


def pytest_configure(config):
    if hasattr(config, "workerinput") or not config.getoption("numprocesses", None):
        return  # a worker, or no workers
    subprocess.run([sys.executable, "-c", WARM_UP], check=True)


# The test modules that take longest, longest first (their seconds in a --durations=0 log
# under two workers on a busy machine, rounded). pytest-xdist's --dist loadscope gives a worker a whole module at a
# time, and with --no-loadscope-reorder in the order collected: these first, the many short ones
# after them fill the gaps, so that neither worker is left running a long module alone at the end
# (longest processing time first). Every other module keeps its place after them.
SLOW_FIRST = (
    "tests/browser/test_accessibility.py",  # 580 at load 7-8, 200 quiet (one process; 44 states)
    "tests/browser/test_layout.py",  # 317 s
    "tests/browser/test_browser.py",  # 314
    "tests/run/test_real_machine.py",  # 237
    "tests/browser/test_browser_text.py",  # 192
    "tests/server/test_serving.py",  # 188, mostly the server's clocks
    "tests/server/test_upload_route.py",  # 176
    "tests/kernels/test_compile.py",  # 162
    "tests/app/test_app.py",  # 152
    "tests/server/test_load.py",  # 131
    "tests/app/test_app_map.py",  # 108
    "tests/app/test_text_is_text.py",  # 105
    "tests/app/test_app_site.py",  # 103
    "tests/model/test_wind.py",  # 102
    "tests/app/test_app_wind.py",  # 85
    "tests/browser/test_browser_site.py",  # 78
    "tests/browser/test_browser_views.py",  # 61
)


def pytest_collection_modifyitems(config, items):
    """The modules of SLOW_FIRST first, in its order; the rest as collected (a stable sort)."""
    rank = {path: k for k, path in enumerate(SLOW_FIRST)}
    items.sort(key=lambda item: rank.get(item.nodeid.split("::")[0], len(rank)))


@pytest.fixture
def short_tmp_path():
    """A fresh empty folder with a short path (``/tmp/wp-xxxxxxxx``), removed after the test.

    For tests whose error messages show a file's path in full: messages cut what they echo to
    ~80 characters (``windpump.errors.SHOWN``), and ``tmp_path`` (~60 characters) grows by the
    worker's folder under pytest-xdist (``popen-gw0/``), which cut the file's name off them."""
    with tempfile.TemporaryDirectory(prefix="wp-") as folder:
        yield Path(folder)


@pytest.fixture(scope="session")
def runs():
    """name -> (case, windpump.simulate result, reference) for every accuracy case."""
    return {
        name: (case, windpump.simulate(*case), reference_run(*case))
        for name, case in ACCURACY_CASES.items()
    }


# No test may fail because the machine is busy: no deadline on an example, and no "too slow"
# health check (the one check that times the data generation; the others count or measure the
# data and stay on). Every profile builds on this one.
settings.register_profile(
    "patient", deadline=None, suppress_health_check=[HealthCheck.too_slow], print_blob=True
)
# CI runs a fixed set of examples, so a landing never depends on a newly drawn one.
# A longer hunt for counter-examples: pytest --hypothesis-profile=thorough
settings.register_profile("ci", settings.get_profile("patient"), derandomize=True)
settings.register_profile("thorough", settings.get_profile("patient"), max_examples=1000)
settings.load_profile("ci" if os.environ.get("CI") else "patient")


# The app served for a test module's pages, and one headless chromium for them (browser tests).
@pytest.fixture(scope="module")
def server():
    require_chromium()
    with served_app() as (address, process):
        yield address, process


@pytest.fixture(scope="module")
def url(server):
    return server[0]


@pytest.fixture(scope="module")
def browser():
    require_chromium()
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        chromium = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_FLAGS)
        yield chromium
        chromium.close()


@pytest.fixture(autouse=True)
def nothing_from_another_host():
    """Every browser test: the pages it opened asked no host but their server for anything (a
    CDN's font, stylesheet or script), checked once it has run, so a module need not remember to
    (``test_browser.record_elsewhere``; a page the test closed counts too). Here, not in
    tests/browser/conftest.py: a second module named ``conftest`` would shadow this one's names
    (``from conftest import SEED``). Other tests open no page: nothing to check."""
    OPENED_PAGES.clear()
    yield
    leaving = {page.opened: list(page.elsewhere) for page in OPENED_PAGES if page.elsewhere}
    OPENED_PAGES.clear()
    assert leaving == {}, "pages asked another host than their server"
