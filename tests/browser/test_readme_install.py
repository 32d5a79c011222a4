"""The README's serve command on a fresh environment: ``pip install -e ".[app]"`` brings what
every tab needs (the Site tab's sample site needs pvlib, which only ``.[site]`` brought: the tab
was a red "Something went wrong" and the server's log a traceback)."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import pytest
from test_browser import open_page

from served import DEEP_TEXT, served_app, server_log

pytestmark = pytest.mark.browser

ROOT = Path(__file__).resolve().parents[2]
INSTALL = 'pip install -e ".[app]"'  # the README's serve command's install
COMPILE = "python -m windpump_app.compiling"  # and its compile step


@pytest.fixture(scope="module")
def readme_python(tmp_path_factory) -> str:
    """A fresh virtual environment with the README's install alone, from the package index."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert f"{INSTALL} && {COMPILE} && panel serve app/" in readme
    env = tmp_path_factory.mktemp("readme") / "env"
    subprocess.run([sys.executable, "-m", "venv", str(env)], check=True, timeout=300)
    python = str(env / "bin" / "python")
    subprocess.run(
        [python, "-m", "pip", "install", "-q", "--disable-pip-version-check", "-e", ".[app]"],
        cwd=ROOT,
        check=True,
        timeout=1200,
    )
    compiled = subprocess.run(
        [python, "-m", "windpump_app.compiling"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
        timeout=1800,
    )
    said = compiled.stdout.strip().splitlines()
    # every part ready, or all of them in numba's cache already (the checkout's, shared)
    assert said[-1].startswith("Compiled in") or "nothing to do" in said[-1], said
    assert "failed" not in compiled.stdout and "Traceback" not in compiled.stderr, compiled
    return python


@pytest.mark.timeout(2400)
def test_every_tab_works_from_the_readmes_install(readme_python, browser):
    with served_app(python=readme_python, timeout=600) as (url, process):
        page = open_page(browser, url)
        try:
            for tab in ("Mechanisms", "Wind", "Design map", "Site"):
                page.get_by_text(tab, exact=True).first.click()
                time.sleep(1.0)
            page.wait_for_function(
                f"() => /%/.test(({DEEP_TEXT})('[data-name=site_lolp]') || '')", timeout=300_000
            )
            assert page.get_by_text("Something went wrong").count() == 0
            assert page.problems == []
        finally:
            page.close()
        assert "Traceback" not in server_log(process)
