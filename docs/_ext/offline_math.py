"""MathJax served by the site itself, so that its equations render with no internet.

Sphinx's ``sphinx.ext.mathjax`` loads MathJax from a CDN by default; offline (a lab's network, a
laptop on a train) the pages then show raw LaTeX. The site carries its own copy instead: MathJax
3's browser components (``es5/``), as the PyPI package ``django-static-mathjax`` ships them (no
Django needed: it is MathJax's files in a package), copied into the build's ``_static`` once the
HTML is written. ``conf.py`` points ``mathjax_path`` at the copy, relative to ``_static``; the
build fails if the file it names is not in the copy.

Left out of the copy: the SVG output and the other combined components (the page loads
``tex-mml-chtml.js`` only), about 12 MB of the package's 24.
"""

from __future__ import annotations

import shutil
from pathlib import Path, PurePosixPath

from sphinx.errors import ExtensionError

# What the pages never load: the SVG output, the other combined components, node's entry point.
KEPT_OUT = ("*svg*", "mml-chtml.js", "tex-chtml*.js", "node-main.js")


def mathjax_source() -> Path:
    """MathJax 3's browser components (``es5/``) in the installed ``django-static-mathjax``."""
    try:
        import mathjax  # django-static-mathjax: the package's files, no code
    except ImportError as missing:
        raise ExtensionError(
            "MathJax for the offline site: pip install django-static-mathjax "
            "(in the docs extra: pip install -e '.[docs]')"
        ) from missing
    return Path(mathjax.__file__).resolve().parent / "static" / "mathjax" / "es5"


def copy_mathjax(static: Path, mathjax_path: str) -> Path:
    """Copy MathJax into ``static`` (a build's ``_static``) where ``mathjax_path`` (relative to
    ``_static``, as Sphinx reads it) names its entry script; that script's path in the copy."""
    relative = PurePosixPath(mathjax_path)
    if relative.is_absolute() or "://" in mathjax_path or mathjax_path.startswith("//"):
        raise ExtensionError(f"mathjax_path = {mathjax_path!r}: a path inside _static, not a URL")
    target = static / relative.parent
    shutil.copytree(
        mathjax_source(), target, ignore=shutil.ignore_patterns(*KEPT_OUT), dirs_exist_ok=True
    )
    script = static / relative
    if not script.is_file():
        raise ExtensionError(f"mathjax_path = {mathjax_path!r}: no such file in MathJax's copy")
    return script


def _copy_after_build(app, exception) -> None:
    if exception is None and app.builder.format == "html":
        copy_mathjax(Path(app.outdir) / "_static", app.config.mathjax_path)


def setup(app):
    app.connect("build-finished", _copy_after_build)
    return {"parallel_read_safe": True, "version": "1"}
