"""Sphinx configuration: the windpump documentation, built from this checkout.

Build (from the repository root; ``-W`` turns every warning into an error, as CI does)::

    python -m sphinx -W --keep-going -b doctest docs docs/_build/doctest
    python -m sphinx -W --keep-going -b html docs docs/_build/html
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import sys
from pathlib import Path

from sphinx.ext import autosummary

ROOT = Path(__file__).resolve().parents[1]
# Document this checkout's core, whichever windpump happens to be installed.
sys.path.insert(0, str(ROOT / "core"))
sys.path.insert(0, str(Path(__file__).resolve().parent / "_ext"))  # layers: the layers' picture

import windpump  # noqa: E402

project = "windpump"
author = "the windpump engineers"
copyright = "2024, the windpump engineers"
release = windpump.__version__ if hasattr(windpump, "__version__") else "0.1.0"

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.doctest",
    "sphinx.ext.mathjax",
    "numpydoc",
    "layers",
    "offline_math",
]

templates_path = ["_templates"]
exclude_patterns = ["_build"]
html_theme = "alabaster"
html_static_path: list[str] = []
# MathJax from the site itself, not a CDN: offline the equations still render (docs/_ext/offline_math.py
# copies it there from the PyPI package django-static-mathjax). Relative to the build's _static.
mathjax_path = "mathjax/tex-mml-chtml.js"
html_theme_options = {
    "description": "A wind-driven piston pump: a checked solver and a live explorer"
}

# The API reference: one page per public name, generated from the docstrings at build time.
autosummary_generate = True
# autosummary's tables show a docstring's first sentence, which it ends at the first ". " after
# anything but its few known abbreviations (e.g., i.e.): the paper's equations and figures ("Eq. 12",
# "(Eqs. 18-25)", "Fig. 3") are abbreviations too, or a summary reads "Integrate ... motion, Eq.".
# Sphinx has no setting for the list; it is read when a summary is taken, so it is extended here.
PAPER_ABBREVIATIONS = ("Eq.", "Eqs.", "Fig.", "Figs.")
autosummary.WELL_KNOWN_ABBREVIATIONS = tuple(
    dict.fromkeys((*autosummary.WELL_KNOWN_ABBREVIATIONS, *PAPER_ABBREVIATIONS))
)
autosummary_imported_members = False
# ``python -m windpump`` runs the command line on import: not a module to document.
autosummary_mock_imports = ["windpump.__main__"]
autodoc_typehints = "none"  # the numpydoc Parameters sections give the types, with units
autodoc_member_order = "bysource"

# numpydoc renders the docstrings; it does not list every attribute of a class as a second table.
numpydoc_show_class_members = False
numpydoc_xref_param_type = False

# numpydoc's validation, as errors under -W: every check of the docstrings' *format* (sections
# known and in order, parameters that exist and in order, types given, descriptions punctuated),
# but none that asks for more *content* than a docstring needs: an Examples, See Also or extended
# summary on every object (EX01, SA01, ES01), a Parameters section on a dataclass that documents its
# fields as attributes or a Returns section under a one-line "X of the run [unit]" (PR01, RT01), a
# sentence for a self-explaining ``design : Design`` (PR07, RT03), a docstring on the command
# line's private option helpers (GL08), and the summary's wording and length (SS05, SS06) or where
# the closing quotes sit (GL02), which render the same.
numpydoc_validation_checks = {
    "all",
    "EX01",
    "SA01",
    "ES01",
    "PR01",
    "RT01",
    "PR07",
    "RT03",
    "GL08",
    "SS05",
    "SS06",
    "GL02",
}
# A NamedTuple's fields carry Python's own docstring ("Alias for field number 0").
numpydoc_validation_exclude = {r"\.WindRecord\.(t|V)$"}

# Examples on the pages run in `-b doctest`; the docstrings' own examples run under pytest
# (--doctest-modules), so they are not run a second time here.
doctest_test_doctest_blocks = ""
# The examples' files (a script, a designs CSV) by absolute path, wherever the build runs from.
doctest_global_setup = f"""
from pathlib import Path
EXAMPLES = {str(ROOT / "docs" / "examples")!r}
"""


def _top_level_names() -> dict[str, str]:
    """Each name ``windpump`` exposes, with the module that defines it (for the module pages)."""
    names = {}
    for name in windpump.__all__:
        obj = getattr(windpump, name)
        module = getattr(obj, "__module__", None)
        if module and not isinstance(obj, type(windpump)):
            names[name] = module
    return names


def _public_names() -> dict[str, list[str]]:
    """The functions and classes each module's page lists with pages of their own: those a public
    ``__all__`` names (the package's, or one of its public modules'), under the module that defines
    them. A module without ``__all__`` gets a page of its docstring and no pages for its helpers."""
    modules = [windpump]
    for found in pkgutil.walk_packages(windpump.__path__, "windpump."):
        if not any(part.startswith("_") for part in found.name.split(".")):  # _kernels, __main__
            modules.append(importlib.import_module(found.name))
    names: dict[str, list[str]] = {}
    for module in modules:
        for name in getattr(module, "__all__", ()):
            obj = getattr(module, name)
            if inspect.isclass(obj) or inspect.isfunction(obj):
                names.setdefault(obj.__module__, []).append(obj.__name__)
    return names


def _remove_stale_pages(generated: Path, public: dict[str, list[str]]) -> None:
    """Remove the pages an earlier build wrote for names no longer public (autosummary writes pages
    but never removes one; left in place, each fails ``-W`` as a page in no table of contents)."""
    pages = {f"windpump.{name}" for name in windpump.__all__}
    pages |= {f"{module}.{name}" for module, names in public.items() for name in names}
    pages |= {"windpump"} | {
        found.name for found in pkgutil.walk_packages(windpump.__path__, "windpump.")
    }
    for page in generated.glob("*.rst"):
        if page.stem not in pages:
            page.unlink()


autosummary_context = {"toplevel": _top_level_names(), "public": _public_names()}


def setup(app) -> None:
    """Sphinx runs this on reading the configuration (not on importing this file)."""
    _remove_stale_pages(ROOT / "docs" / "api" / "generated", autosummary_context["public"])
