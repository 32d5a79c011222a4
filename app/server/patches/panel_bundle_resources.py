"""Bokeh's WebGL bundle left out of the page Panel's server renders
(``panel.io.server.bundle_resources``).

Made for panel 1.9.4 (bokeh 3.9.2): it wraps ``bundle_resources(roots, resources, notebook=False,
reloading=False, enable_mathjax='auto')`` and drops ``/bokeh-gl`` from the bundle's ``js_files``;
``tests/app/test_app_patches.py`` fails when that function's signature changes.
"""

from __future__ import annotations


def without_webgl() -> None:
    """No figure here asks for WebGL, but Bokeh's resources list bokeh-gl (190 KB of script a
    browser must parse) for every page. Leave it out of the page Panel's server renders."""
    from panel.io import server

    if getattr(server.bundle_resources, "without_webgl", False):
        return
    bundle_resources = server.bundle_resources

    def bundle_without_webgl(roots, resources, *args, **kwargs):
        bundle = bundle_resources(roots, resources, *args, **kwargs)
        bundle.js_files = [url for url in bundle.js_files if "/bokeh-gl" not in str(url)]
        return bundle

    bundle_without_webgl.without_webgl = True
    bundle_without_webgl.panel = bundle_resources  # type: ignore[attr-defined]
    server.bundle_resources = bundle_without_webgl
