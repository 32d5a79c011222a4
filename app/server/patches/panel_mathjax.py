"""Panel's MathJax left out of every page (``panel.io.resources._panel_use_mathjax``).

Made for panel 1.9.4 (bokeh 3.9.2, param 2.4.2): it replaces a private function of Panel's
resource bundler, ``_panel_use_mathjax(roots)``; ``tests/app/test_app_patches.py`` fails when it is
gone or takes other arguments.
"""

from __future__ import annotations


def without_mathjax() -> None:
    """No page here writes LaTeX, but Panel ships MathJax (1.8 MB, a third of the page) to every
    page that has an HTML pane. Tell Panel's resource bundler this app needs none."""
    from panel.io import resources

    resources._panel_use_mathjax = lambda roots: False
