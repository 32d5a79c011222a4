"""What the README promises: its example runs, its commands are CI's, its links and picture exist.

Everything else the README used to carry lives in the documentation (docs/); tests/project/test_docs.py
runs the pages' examples and checks that they still say what a user needs.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")
CI = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
BLOCKS = re.findall(r"```python\n(.*?)```", README, flags=re.S)
BASH = [block.strip() for block in re.findall(r"```bash\n(.*?)```", README, flags=re.S)]

TEST_COMMAND = 'pip install -e ".[app,test,browser]" && python -m pytest'


@pytest.mark.parametrize("number", range(len(BLOCKS)))
def test_a_readme_example_runs(number, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # an example that writes a file writes it here
    code = compile(BLOCKS[number], f"README.md python block {number + 1}", "exec")
    exec(code, {"__name__": "__main__"})  # as a script runs it


def test_the_readme_is_short_with_a_ten_line_example():
    assert len(README.splitlines()) <= 150
    (example,) = BLOCKS
    assert len(example.strip().splitlines()) <= 10


def test_the_test_command_is_the_readmes_and_cis_verbatim():
    assert TEST_COMMAND in BASH
    assert CI.rstrip().splitlines()[-1] == TEST_COMMAND  # CI ends with it, as written


def test_the_docs_command_builds_what_ci_builds():
    (command,) = [block for block in BASH if "sphinx" in block]
    install, build = command.split(" && ")
    assert install == 'pip install -e ".[docs]"'
    assert build in CI.splitlines()  # CI runs the same build, warnings as errors
    assert "-W --keep-going" in build
    assert re.search(r"^python -m sphinx -W --keep-going -b doctest docs \S+$", CI, flags=re.M)
    docs_step, tests_step = CI.index(build), CI.index(TEST_COMMAND)
    assert docs_step < tests_step


def test_the_serve_command_serves_the_app():
    assert 'pip install -e ".[app]" && python -m windpump_app.compiling && panel serve app/' in BASH
    assert (ROOT / "app" / "main.py").is_file()


def test_every_local_link_and_picture_exists():
    targets = re.findall(r"\]\(([^)#\s]+)\)", README)
    local = [target for target in targets if "://" not in target]
    assert "docs/explorer.png" in local and "docs/model.rst" in local
    assert [target for target in local if not (ROOT / target).is_file()] == []
    for page in ("instructors", "designers", "model", "measured", "known-issues", "architecture"):
        assert f"docs/{page}.rst" in local


def test_ci_runs_the_test_command_in_a_fresh_environment_of_its_own():
    """A dependency no extra of the README's install declares fails CI (mpmath did not): the
    tests' environment is made fresh, and nothing goes into it but the README's own install
    (made ahead, in the background, then the README's command verbatim)."""
    lines = CI.rstrip().splitlines()
    assert lines[-2:] == ['source "$ENVS/test/bin/activate"', TEST_COMMAND]
    made = [line for line in lines if 'venv "$ENVS/test"' in line]
    assert len(made) == 1 and made[0].lstrip("(").startswith('python -m venv "$ENVS/test"')
    readme_install = TEST_COMMAND.split(" && ")[0].removeprefix("pip ")
    after = CI[CI.index('python -m venv "$ENVS/test"') :].splitlines()
    code = "\n".join(line for line in after if not line.lstrip().startswith("#"))
    installs = re.findall(r"pip\"? (install[^\n&)]*)", code)
    assert installs and all(i.replace("-q ", "").strip() == readme_install for i in installs)


def test_every_package_the_tests_import_is_declared_by_the_test_command():
    """The tests' and benchmarks' third-party imports, each in a dependency of the README's
    install (by import name; a few differ from their distribution's)."""
    import sys

    tomllib = pytest.importorskip("tomllib")  # Python 3.11 on

    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    extras = project["optional-dependencies"]
    declared = project["dependencies"] + extras["app"] + extras["test"] + extras["browser"]
    names = {re.split(r"[\[<>=!~ ]", d)[0].lower().replace("-", "_") for d in declared}
    imported_as = {"pil": "pillow", "distributed": "dask", "yaml": "pyyaml"}
    # installed with the declared ones (panel brings param, bokeh tornado, sphinx docutils)
    brought = {"param", "tornado", "jinja2", "docutils"}
    ours = {
        "windpump",
        "windpump_app",
        "conftest",
        "panes",
        "reference",
        "served",
        "real_reference",
    }
    found = set()
    for path in [*(ROOT / "tests").glob("*.py"), *(ROOT / "benchmarks").glob("*.py")]:
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                found |= {alias.name.split(".")[0].lower() for alias in node.names}
            elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
                found.add(node.module.split(".")[0].lower())
    local = {p.stem.lower() for p in (ROOT / "tests").glob("*.py")}
    local |= {p.stem.lower() for p in (ROOT / "benchmarks").glob("*.py")}
    third_party = found - set(sys.stdlib_module_names) - ours - local - {"__future__"}
    missing = {m for m in third_party if imported_as.get(m, m) not in names | brought}
    assert missing == set()
