"""The layers' import rules (docs/architecture.rst, "What each may import"), read from the source.

The core never imports the app or its libraries; the compiled kernels import nothing of the package
but themselves; the study extras are imported only where a study needs them, so the core installs
and imports without them.
"""

from __future__ import annotations

import ast
import functools
import sys
from pathlib import Path

import pytest

CORE = Path(__file__).resolve().parents[2] / "core" / "windpump"
KERNELS = CORE / "_kernels"
APP_LIBRARIES = {"panel", "bokeh", "param", "app"}
STUDY_EXTRAS = {"pandas", "tqdm", "matplotlib", "dask", "distributed", "pvlib"}
KERNEL_LIBRARIES = {"numpy", "numba"}


def imports(tree: ast.AST) -> list[tuple[int, str, int]]:
    """Every import under ``tree``: (relative level, module name, line)."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [(0, alias.name, node.lineno) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            found.append((node.level, node.module or "", node.lineno))
    return found


def top_level_imports(tree: ast.Module) -> list[tuple[int, str, int]]:
    """The imports a module runs when it is imported (not those inside a function or class)."""
    found = []
    for statement in tree.body:
        if not isinstance(statement, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            found += imports(statement)
    return found


def parsed(path: Path) -> ast.Module:
    return ast.parse(path.read_text(encoding="utf-8"), filename=str(path))


def root(name: str) -> str:
    return name.split(".")[0]


CORE_FILES = sorted(CORE.rglob("*.py"))
KERNEL_FILES = sorted(KERNELS.rglob("*.py"))


@pytest.mark.parametrize("path", CORE_FILES, ids=lambda p: str(p.relative_to(CORE)))
def test_the_core_never_imports_the_app(path):
    bad = [
        (name, line)
        for level, name, line in imports(parsed(path))
        if level == 0 and root(name) in APP_LIBRARIES
    ]
    assert bad == [], f"{path.name} imports the app's layer: {bad}"


@pytest.mark.parametrize("path", KERNEL_FILES, ids=lambda p: p.name)
def test_the_kernels_import_of_the_package_only_the_model_s_equations(path):
    allowed = KERNEL_LIBRARIES | set(sys.stdlib_module_names)
    # A level-1 import is a kernel module; a deeper one leaves _kernels: only for the equations.
    bad = [
        (level, name, line)
        for level, name, line in imports(parsed(path))
        if (level > 1 and imported_modules(path, parsed_import(path, line)) != [EQUATIONS])
        or (level == 0 and root(name) not in allowed)
    ]
    assert bad == [], f"_kernels/{path.name} imports outside the kernels: {bad}"


EQUATIONS = "windpump.model.equations"


def parsed_import(path: Path, line: int) -> ast.ImportFrom:
    """The ``from ... import`` statement on ``line`` of ``path``."""
    [node] = [
        node
        for node in ast.walk(parsed(path))
        if isinstance(node, ast.ImportFrom) and node.lineno == line
    ]
    return node


@pytest.mark.parametrize("path", CORE_FILES, ids=lambda p: str(p.relative_to(CORE)))
def test_the_study_extras_are_imported_only_where_used(path):
    bad = [
        (name, line)
        for level, name, line in top_level_imports(parsed(path))
        if level == 0 and root(name) in STUDY_EXTRAS
    ]
    assert bad == [], f"{path.name} imports a study extra when it is imported: {bad}"


def test_the_rules_see_the_files():
    assert len(CORE_FILES) > 20 and len(KERNEL_FILES) > 5
    assert any(name == "numba" for _, name, _ in imports(parsed(KERNELS / "jit.py")))


# Import circles among the core's modules, counting imports inside functions (grimp reads them all).
# None is left (issue 38 broke the last four): any circle fails the test below.
CIRCLES_LEFT_FOR_LATER: dict[frozenset[str], str] = {}


def module_circles(depth: int | None = 2) -> list[frozenset[str]]:
    """The core's import circles: sets of sub-packages (``depth`` 2: ``windpump.model``, ...) or of
    modules (None) that each reach all the others."""
    grimp = pytest.importorskip("grimp")
    graph = grimp.build_graph("windpump")

    def top(name: str) -> str:
        return ".".join(name.split(".")[:depth])

    edges: dict[str, set[str]] = {}
    for module in graph.modules:
        for imported in graph.find_modules_directly_imported_by(module):
            if top(module) != top(imported):
                edges.setdefault(top(module), set()).add(top(imported))
    reach = {}
    for start in edges:
        seen, todo = set(), [start]
        while todo:
            for nxt in edges.get(todo.pop(), ()):
                if nxt not in seen:
                    seen.add(nxt)
                    todo.append(nxt)
        reach[start] = seen
    circles = {
        frozenset({a} | {b for b in reach[a] if a in reach.get(b, ())})
        for a in reach
        if a in reach[a]
    }
    return sorted(circles, key=sorted)


@pytest.mark.parametrize("depth", [2, None], ids=["sub-packages", "modules"])
def test_no_import_circles_but_those_left_for_later(depth):
    circles = module_circles(depth)
    unexpected = [sorted(c) for c in circles if c not in CIRCLES_LEFT_FOR_LATER]
    assert not unexpected, f"import circles in the core: {unexpected}"
    gone = [sorted(c) for c in CIRCLES_LEFT_FOR_LATER if c not in circles]
    assert not gone, f"these circles are broken now: take them off CIRCLES_LEFT_FOR_LATER: {gone}"


# -- the app in two rooms (issue 38): the page (app/'s top level) and the server (app/server/)

APP = CORE.parents[1] / "app"
APP_ENTRIES = {"main", "app_hooks", "compiling", "__init__"}  # wire both rooms (pyproject says why)


def _app_contract(name: str) -> dict:
    import tomllib

    config = tomllib.loads((CORE.parents[1] / "pyproject.toml").read_text())["tool"]
    [contract] = [c for c in config["importlinter"]["contracts"] if c["name"] == name]
    assert "windpump_app" in config["importlinter"]["root_packages"]
    return contract


def test_every_page_module_reaches_the_server_through_its_api_alone():
    """The import-linter contract (`lint-imports`) lists every page module of app/ as a source,
    and every module of app/server/ but ``api`` as forbidden: a page module or a server module
    added later is covered, not left out of the list."""
    contract = _app_contract("The page reaches the server through windpump_app.server.api alone")
    page = {path.stem for path in APP.glob("*.py")} - APP_ENTRIES
    assert set(contract["source_modules"]) == {f"windpump_app.{name}" for name in page}
    server = {path.stem for path in (APP / "server").glob("*.py")} - {"__init__", "api"}
    server |= {path.name for path in (APP / "server").iterdir() if (path / "__init__.py").is_file()}
    assert set(contract["forbidden_modules"]) == {f"windpump_app.server.{name}" for name in server}
    assert contract["type"] == "forbidden"


def test_the_server_imports_none_of_the_page_s_tabs():
    """The server may use of the page only its inputs' and uploads' checks (and the entries'
    compiling.py); every other page module is forbidden to it."""
    contract = _app_contract("The server imports none of the page's tabs")
    assert contract["source_modules"] == ["windpump_app.server"]
    page = {path.stem for path in APP.glob("*.py")} - {"compiling", "__init__", "inputs", "uploads"}
    assert set(contract["forbidden_modules"]) == {f"windpump_app.{name}" for name in page}


def module_name(path: Path) -> str:
    """``core/windpump/a/b.py`` -> ``windpump.a.b`` (a package's ``__init__`` is the package)."""
    parts = path.relative_to(CORE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imported_modules(path: Path, node: ast.Import | ast.ImportFrom) -> list[str]:
    """The absolute names of the modules an import statement in ``path`` imports: ``from . import
    x`` and ``from .pkg import x`` name ``pkg.x`` where x is a module, ``pkg`` where it is a
    name."""
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names]
    if node.level == 0:
        base = node.module or ""
    else:
        package = module_name(path).split(".")
        if path.name != "__init__.py":
            package = package[:-1]
        kept = package[: len(package) - node.level + 1]
        base = ".".join(kept + ([node.module] if node.module else []))
    if root(base) != "windpump":
        return [base]
    return [
        f"{base}.{alias.name}" if path_of(f"{base}.{alias.name}") else base for alias in node.names
    ]


def path_of(module: str) -> Path | None:
    """The source file of one of the core's modules (None: a name, not a module)."""
    relative = Path(*module.split(".")[1:]) if "." in module else None
    if relative is None:
        return CORE / "__init__.py" if module == "windpump" else None
    for candidate in (CORE / relative.with_suffix(".py"), CORE / relative / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


@functools.cache
def top_level_modules(module: str) -> tuple[str, ...]:
    """The modules ``module`` (one of the core's) imports when it is imported, TYPE_CHECKING's
    aside."""
    path = path_of(module)
    if path is None:
        return ()
    found: list[str] = []
    for statement in parsed(path).body:
        if isinstance(statement, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            continue
        if isinstance(statement, ast.If) and "TYPE_CHECKING" in ast.unparse(statement.test):
            continue
        for node in ast.walk(statement):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                found += imported_modules(path, node)
    return tuple(found)


def loads_numba(module: str) -> bool:
    """Whether importing ``module`` (one of the core's) imports numba: at its top, or through a
    module of the core it imports at its top."""
    seen, todo = {module}, [module]
    while todo:
        for name in top_level_modules(todo.pop()):
            if root(name) == "numba":
                return True
            if root(name) == "windpump" and name not in seen:
                seen.add(name)
                todo.append(name)
    return False


def lazy_imports_of_the_core(path: Path) -> list[tuple[str, int]]:
    """Imports of the core's own modules inside a function of ``path``: (module, line)."""
    found = []
    for function in ast.walk(parsed(path)):
        if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        for node in ast.walk(function):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                found += [
                    (name, node.lineno)
                    for name in imported_modules(path, node)
                    if root(name) == "windpump"
                ]
    return sorted(set(found))


@pytest.mark.parametrize("path", CORE_FILES, ids=lambda p: str(p.relative_to(CORE)))
def test_the_core_imports_its_own_modules_at_the_top(path):
    """No import of the core's own modules inside a function (a lazy import hid an import
    circle): ``import windpump`` stays free of numba because the package's public names are
    imported on first use (``windpump.PUBLIC``), not because a module hides its imports."""
    bad = lazy_imports_of_the_core(path)
    assert bad == [], f"{path.name} imports the core's own modules inside a function: {bad}"


def test_the_lazy_import_rule_sees_what_it_should():
    assert loads_numba("windpump._kernels.real") and loads_numba("windpump._kernels.supply")
    assert loads_numba("windpump._kernels") and loads_numba("windpump.run.dynamics")
    assert not loads_numba("windpump.model.equations") and not loads_numba("windpump")
    assert not any(
        loads_numba(f"windpump.{name}") for name in ("model.design", "averaging.averaged")
    )
    tree = ast.parse(
        "def f():\n    from ..sites.site import steady_flow\n    from .. import _kernels\n"
    )
    function = tree.body[0]
    assert isinstance(function, ast.FunctionDef)
    names = [
        name
        for node in function.body
        if isinstance(node, ast.ImportFrom)
        for name in imported_modules(CORE / "run" / "dynamics.py", node)
    ]
    assert names == ["windpump.sites.site", "windpump._kernels"]


# -- the folders show the layers (issue 38)

LADDER = [
    "command",
    "sites",
    "study",
    "run",
    "averaging",
    "_kernels",
    "catalogue",
    "model",
    "readers",
    "linkage",
]


def test_the_core_s_folders_are_its_ladder_and_few_modules_sit_beside_them():
    """``ls core/windpump`` shows the layers: the sub-packages of the import-linter contract and at
    most 12 modules directly in the package (issue 38)."""
    folders = {path.name for path in CORE.iterdir() if (path / "__init__.py").is_file()}
    assert folders == set(LADDER)
    modules = sorted(path.name for path in CORE.glob("*.py"))
    assert len(modules) <= 12, modules
    import tomllib

    config = tomllib.loads((CORE.parents[1] / "pyproject.toml").read_text())["tool"]
    [ladder] = [
        c
        for c in config["importlinter"]["contracts"]
        if c["name"] == "The core's sub-packages, from the command line down to errors and units"
    ]
    named = {
        part.strip().removeprefix("windpump.")
        for line in ladder["layers"]
        for part in line.split(":")
    }
    assert set(LADDER) <= named


def test_every_core_module_has_its_place_on_the_module_ladder():
    """The module-by-module import-linter contract names every module of the sub-packages (but the
    kernels and the linkage, each kept by its own rule), so a module added later is on it."""
    import tomllib

    config = tomllib.loads((CORE.parents[1] / "pyproject.toml").read_text())["tool"]
    [ladder] = [
        c
        for c in config["importlinter"]["contracts"]
        if c["name"] == "The core's modules, from the command line down to errors and units"
    ]
    named = {part.strip() for line in ladder["layers"] for part in line.split(":")}
    modules = {
        module_name(path)
        for path in CORE_FILES
        if path.name != "__init__.py" and path.parent.name not in {"_kernels", "linkage"}
    }
    modules -= {"windpump._old_paths"}  # the old paths' finder: imports nothing of the core
    assert modules <= named, sorted(modules - named)


LONGEST_MODULE = 800  # lines (issue 38)


@pytest.mark.parametrize(
    "path",
    sorted([*CORE.rglob("*.py"), *APP.rglob("*.py")]),
    ids=lambda p: str(p.relative_to(CORE.parents[1])),
)
def test_no_module_is_too_long_to_hold_in_the_head(path):
    assert len(path.read_text(encoding="utf-8").splitlines()) <= LONGEST_MODULE


def test_the_layers_picture_is_drawn_from_the_imports_and_follows_the_ladder():
    """docs/_ext/layers.py (the picture on docs/architecture.rst): every import it draws goes down
    the sub-packages' import-linter ladder, and it draws every sub-package."""
    sys.path.insert(0, str(CORE.parents[1] / "docs" / "_ext"))
    try:
        import layers
    finally:
        sys.path.pop(0)
    import tomllib

    config = tomllib.loads((CORE.parents[1] / "pyproject.toml").read_text())["tool"]
    [ladder] = [
        c
        for c in config["importlinter"]["contracts"]
        if c["name"] == "The core's sub-packages, from the command line down to errors and units"
    ]
    rung = {
        part.strip().removeprefix("windpump."): -level
        for level, line in enumerate(ladder["layers"])
        for part in line.split(":")
    }
    edges = layers.layer_edges()
    assert {node for edge in edges for node in edge} >= set(LADDER)
    assert all(rung[a] > rung[b] for a, b in edges), sorted(edges)
    assert "<svg" in layers.svg(edges) and all(f">{name}<" in layers.svg(edges) for name in LADDER)


TESTS = CORE.parents[1] / "tests"
TEST_FOLDERS_BEYOND_THE_CORE = {"whole_core", "app", "server", "browser", "project"}


def test_the_tests_are_grouped_by_the_same_layers():
    """A folder of tests per sub-package of the core (``tests/model`` for ``windpump.model``, ...),
    then the core as a whole, the app's page, its server, the browser and the project: no test
    file sits loose in ``tests/`` (only the references and helpers the folders share)."""
    loose = sorted(path.name for path in TESTS.glob("test_*.py"))
    assert loose == []
    folders = {
        path.name for path in TESTS.iterdir() if path.is_dir() and any(path.glob("test_*.py"))
    }
    core_layers = set(LADDER) - {"_kernels"} | {"kernels"}
    assert folders == core_layers | TEST_FOLDERS_BEYOND_THE_CORE


def test_the_modules_run_first_are_test_modules_that_exist():
    """tests/conftest.py's SLOW_FIRST names modules by path: a module moved or renamed would
    silently lose its place at the front of the workers' queue."""
    from conftest import SLOW_FIRST

    root = TESTS.parent
    assert len(set(SLOW_FIRST)) == len(SLOW_FIRST)
    assert [
        p for p in SLOW_FIRST if not (root / p).is_file() or not Path(p).name.startswith("test_")
    ] == []
