"""The documentation (docs/): its examples run, and it still tells a user what the README used to.

CI builds the site with ``sphinx -W -b doctest``, which runs every example on its pages; these tests
run the same examples under pytest, so ``python -m pytest`` alone still checks them, and check
that the pages keep what moved there from the README.
"""

from __future__ import annotations

import doctest
import importlib
import inspect
import pkgutil
import re
import runpy
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
EXAMPLES = DOCS / "examples"
PAGES = sorted(DOCS.glob("*.rst"))
# Sphinx's doctest defaults, so a page passes here exactly when it passes in the docs build.
FLAGS = doctest.ELLIPSIS | doctest.IGNORE_EXCEPTION_DETAIL | doctest.DONT_ACCEPT_TRUE_FOR_1


def page(name: str) -> str:
    return (DOCS / f"{name}.rst").read_text(encoding="utf-8")


@pytest.mark.parametrize("path", PAGES, ids=lambda p: p.name)
def test_a_pages_examples_run(path, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    globs = {"EXAMPLES": str(EXAMPLES), "Path": Path}
    failed, _ = doctest.testfile(str(path), module_relative=False, globs=globs, optionflags=FLAGS)
    assert failed == 0, f"{path.name}: {failed} example(s) failed (printed above)"


def test_the_pages_have_examples():
    examples = [
        re.findall(r"^\s+>>> ", (DOCS / f"{p}.rst").read_text("utf-8"), flags=re.M)
        for p in ("designers", "model", "instructors", "index")
    ]
    assert all(len(found) > 0 for found in examples)
    assert len(examples[0]) > 40  # the designers' guide carries the README's old examples


def test_the_cluster_example_runs_as_a_script():
    runpy.run_path(str(EXAMPLES / "sweep_on_a_cluster.py"), run_name="__main__")


def test_the_instructors_guide_names_every_link_parameter_and_preset():
    text = page("instructors")
    parameters = (
        "L_over_R R_dagger h T_m omega_m cylinders double_acting t_end theta_dot0 theta0 I0 I1 T_0"
    )
    wind = "V mean_wind k time_scale seed"
    for name in (parameters + " " + wind).split():
        assert f"``{name}``" in text, name
    for mode in ("presentation=true", "theme=dark", "resolution=full", "embed=true"):
        assert mode in text
    presets = (
        "The paper's example",
        "Near the stall boundary",
        "Kicked below α₋",
        "A light rotor, large ripple",
        "2 cylinders, torque at rest",
        "A double-acting pump",
        "A stalled pump",
    )
    for preset in presets:
        assert f"**{preset}**" in text, preset
    for needed in (
        "--allow-websocket-origin",
        "Copy link to this state",
        "Presentation mode",
        "Lab data uploads",
        "1 MB",
        "Pin this run",
        "Download this run",
    ):
        assert needed in text, needed


def test_the_designers_guide_covers_the_command_line_and_clusters():
    text = page("designers")
    for command in ("windpump simulate", "windpump map", "windpump sweep", "windpump serve"):
        assert command in text
    for needed in (
        "--scheduler",
        "MALLOC_TRIM_THRESHOLD_",
        "Design.to_json",
        "DesignFileError",
        "ParameterError",
        "samples_per_stroke",
        "sample_dt",
        "numeric=True",
    ):
        assert needed in text, needed
    assert ".. literalinclude:: examples/sweep_on_a_cluster.py" in text


def test_the_model_page_cites_its_sources_by_title():
    text = page("model")
    for source in (
        "Louge",
        "A simple wind-pump analysis",
        "2010",
        "Work of a Ski Lift",
        "Newton-Raphson Method: Application",
    ):
        assert source in text
    assert "∂F₂/∂θ₃ = −r₃ cos θ₃" in text and "2.778 m/s" in text  # the seed's slips, corrected
    assert "h = 3 m and θ̇₀ = 3 rad/s" in text  # how the paper's example is read
    assert "seeds/" not in text and ".txt" not in text  # no file outside the repository


def sections(text: str) -> set[str]:
    """The section titles of a reStructuredText page (a line underlined by -, = or ~)."""
    lines = text.splitlines()
    return {
        lines[i].strip()
        for i in range(len(lines) - 1)
        if lines[i].strip() and re.fullmatch(r"([-=~])\1{2,}", lines[i + 1].strip())
    }


def test_citations_of_the_model_page_name_its_sections():
    titles = sections(page("model"))
    cited = []
    for path in [
        *(ROOT / "core").rglob("*.py"),
        *(ROOT / "tests").glob("*.py"),
        *(ROOT / "app").rglob("*.py"),
    ]:
        text = path.read_text(encoding="utf-8")
        assert "model-notes.md" not in text or path.name == "test_docs.py", path
        cited += re.findall(r'docs/model\.rst, "([^"]+)"', text)
    assert cited and set(cited) <= titles, set(cited) - titles


def test_the_measured_page_names_benchmarks_that_exist():
    scripts = set(re.findall(r"benchmarks/(\w+\.py)", page("measured")))
    assert len(scripts) >= 5
    assert {s for s in scripts if not (ROOT / "benchmarks" / s).is_file()} == set()
    assert not re.search(r"\bissue \d", page("measured"))  # what it does now, not a history


def test_the_known_issues_say_what_to_do():
    text = page("known-issues")
    assert "PYTHONMALLOC=malloc" in text and text.count("*What to do*") >= 2


def test_the_api_reference_lists_every_public_name():
    """Every function and class ``windpump`` exposes is on the API reference's topic lists, and
    nothing else is (its modules and constants are under Modules): a name added to one and not the
    other fails."""
    import windpump

    page = (DOCS / "api" / "index.rst").read_text()
    listed = set(re.findall(r"^   (\w+)$", page, flags=re.M)) - {"modules"}  # the toctree
    public = {
        name
        for name in windpump.__all__
        if inspect.isclass(getattr(windpump, name)) or inspect.isfunction(getattr(windpump, name))
    }
    assert public - listed == set()
    assert listed - set(windpump.__all__) == set()


def public_modules() -> list:
    """``windpump`` and every module of it whose dotted name has no part starting with "_"."""
    import windpump

    found = pkgutil.walk_packages(windpump.__path__, "windpump.")
    names = [m.name for m in found if not any(p.startswith("_") for p in m.name.split("."))]
    return [windpump, *(importlib.import_module(name) for name in names)]


def public_objects() -> dict[int, str]:
    """Every function and class a public ``__all__`` names (the package's or a public module's),
    by ``id``, with one name for it."""
    named = {}
    for module in public_modules():
        for name in getattr(module, "__all__", ()):
            obj = getattr(module, name)
            if inspect.isclass(obj) or inspect.isfunction(obj):
                named[id(obj)] = f"{module.__name__}.{name}"
    return named


def test_api_summaries_are_whole_first_sentences():
    """The API tables show a docstring's first sentence as autosummary takes it, with the docs'
    configuration: a number of the paper's ("Eq. 12", "(Eqs. 18-25)", "Fig. 3") does not end it
    (23 read like "Integrate the wind pump's equation of motion, Eq."), nor does one stop inside
    its parentheses (issue 37)."""
    from docutils.frontend import get_default_settings
    from docutils.parsers.rst import Parser
    from sphinx.ext.autosummary import extract_summary

    runpy.run_path(str(DOCS / "conf.py"))  # what the build configures before it takes summaries
    settings = get_default_settings(Parser)
    import windpump

    objects = [windpump.simulate, windpump.explore]  # one cut at "Eq.", one at "Fig."
    objects += [m for m in public_modules()]
    objects += [
        obj for m in public_modules() for obj in map(m.__dict__.get, getattr(m, "__all__", ()))
    ]
    cut = {}
    for obj in objects:
        if not (inspect.isclass(obj) or inspect.isfunction(obj) or inspect.ismodule(obj)):
            continue
        summary = extract_summary((inspect.getdoc(obj) or "").splitlines(), settings)
        whole = summary.endswith(".") and not re.search(r"\b(Eqs?|Figs?)\.$", summary)
        if not whole or summary.count("(") != summary.count(")"):
            cut[obj.__name__] = summary
    assert cut == {}
    assert extract_summary(inspect.getdoc(windpump.simulate).splitlines(), settings) == (
        "Integrate the wind pump's equation of motion, Eq. (12), in full, from a start angle and kick."
    )


def test_only_the_public_api_gets_pages(tmp_path):
    """autosummary writes a page for each function and class a public ``__all__`` names (the
    package's, or a public module's such as ``windpump.model.wind``'s) and for each module, and for no
    other name: the command line's helpers (``windpump.command.cli.TimeLeft``) get none (issue 37).
    Built from a copy of docs/, so that no earlier build's pages count."""
    site = tmp_path / "site"
    shutil.copytree(DOCS, site / "docs", ignore=shutil.ignore_patterns("_build", "generated"))
    (site / "core").symlink_to(ROOT / "core")
    subprocess.run(
        [
            sys.executable,
            "-m",
            "sphinx",
            "-q",
            "-b",
            "dummy",
            str(site / "docs"),
            str(tmp_path / "out"),
        ],
        check=True,
        timeout=900,  # ~10 s on a quiet machine
    )
    pages = {page.stem for page in (site / "docs" / "api" / "generated").glob("*.rst")}
    modules = {module.__name__ for module in public_modules()}
    public = public_objects()
    private = set()
    for page in pages - modules:
        where, name = page.rsplit(".", 1)
        if id(getattr(importlib.import_module(where), name)) not in public:
            private.add(page)
    assert private == set()
    assert "windpump.command.cli.TimeLeft" not in pages
    expected = {
        "windpump.simulate",
        "windpump.model.wind.gusty",
        "windpump.linkage.grashof.grashof_class",
    }
    assert expected <= pages and "windpump.command.cli" in pages
