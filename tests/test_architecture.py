"""The layers' import rules (docs/architecture.rst, "What each may import"), read from the source.

The core never imports the app or its libraries; the compiled kernels import nothing of the package
but themselves; the study extras are imported only where a study needs them, so the core installs
and imports without them.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest

CORE = Path(__file__).resolve().parents[1] / "core" / "windpump"
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
def test_the_kernels_import_nothing_of_the_package(path):
    allowed = KERNEL_LIBRARIES | set(sys.stdlib_module_names)
    # Inside _kernels/__init__.py a level-1 import is a kernel module; a deeper one leaves _kernels.
    bad = [
        (level, name, line)
        for level, name, line in imports(parsed(path))
        if level > 1 or (level == 0 and root(name) not in allowed)
    ]
    assert bad == [], f"_kernels/{path.name} imports outside the kernels: {bad}"


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
