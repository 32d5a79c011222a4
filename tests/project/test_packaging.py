"""How the project installs: the solver's packages and the explorer's, and how the command line
finds the explorer."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

from windpump.command.cli import explorer_folder

tomllib = pytest.importorskip("tomllib")  # Python 3.11+

ROOT = Path(__file__).resolve().parents[2]


def test_every_package_of_the_checkout_is_installed():
    """pyproject lists its packages (setuptools finds them under one folder only): a package
    added under core/windpump or app/ must be listed too, or a wheel leaves it out."""
    setuptools = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    folders = {name: ROOT / "core" / name.replace(".", "/") for name in setuptools["packages"]}
    for name, folder in setuptools["package-dir"].items():
        if (
            name
        ):  # a mapped package's sub-packages are in its folder (windpump_app.server: app/server)
            for package in setuptools["packages"]:
                if package == name or package.startswith(f"{name}."):
                    folders[package] = ROOT / folder / package[len(name) + 1 :].replace(".", "/")
    on_disk = {
        ".".join(init.parent.relative_to(ROOT / "core").parts)
        for init in (ROOT / "core").rglob("__init__.py")
    } | {
        ".".join(("windpump_app", *init.parent.relative_to(ROOT / "app").parts))
        for init in (ROOT / "app").rglob("__init__.py")
    }
    assert set(setuptools["packages"]) == on_disk
    assert all((folder / "__init__.py").is_file() for folder in folders.values())


def test_the_explorer_is_the_package_windpump_app_served_from_its_folder():
    """Tests import the explorer by its package name, and ``windpump serve`` serves that
    package's folder (a checkout's app/), not a path beside the core."""
    from windpump_app.explorer import Explorer

    folder = explorer_folder()
    assert Path(importlib.util.find_spec("windpump_app").origin).parent.resolve() == folder
    assert Explorer.__module__ == "windpump_app.explorer"
    assert (folder / "main.py").is_file() and (folder / "app_hooks.py").is_file()
