"""The app's patches to Panel, Bokeh and param internals, one module per thing patched, each
named for it and saying the versions it was made for (``pyproject.toml`` bounds panel, bokeh and
param to them; ``tests/app/test_app_patches.py`` fails when a patched internal changes shape).

Each patch is applied by a function that does nothing a second time, nor on a version other than
the one it was checked against: ``apply_all`` applies every one, and ``applied`` says which are
in place (the server logs it at its start: ``server.hooks.on_server_loaded``).
"""

from __future__ import annotations

from .bokeh_patch_doc import lighter_patches
from .bokeh_properties import lighter_properties
from .panel_bundle_resources import without_webgl
from .panel_dispatch_msgs import writes_not_stranded
from .panel_mathjax import without_mathjax
from .panel_pane_layout import lazy_pane_layouts
from .panel_reactive_update import lighter_updates
from .panel_template_init_doc import fake_roots_forgotten
from .param_watchers import watchers_in_lists

__all__ = [
    "applied",
    "apply_all",
    "fake_roots_forgotten",
    "lighter_components",
    "lighter_patches",
    "lighter_properties",
    "lighter_updates",
    "without_mathjax",
    "without_webgl",
    "writes_not_stranded",
]


def lighter_components() -> None:
    """Text panes' layouts built when first asked for (``panel_pane_layout``), and param's
    watchers of a parameter kept in a list alone (``param_watchers``); a second call does
    nothing, and neither is done on a Panel or a param other than the one it was checked
    against."""
    import panel
    import param

    if panel.__version__.startswith("1.9."):
        lazy_pane_layouts()
    if param.__version__.startswith("2.4."):
        watchers_in_lists()


def apply_all() -> None:
    """Apply every patch (each does nothing a second time); ``main.py`` applies them in the
    order a page needs them, the server at its start."""
    without_mathjax()
    without_webgl()
    lighter_patches()
    lighter_updates()
    writes_not_stranded()
    fake_roots_forgotten()
    lighter_properties()
    lighter_components()


def applied() -> dict[str, bool]:
    """Whether each patch is in place, by the mark it leaves on what it patched (the internal's
    path -> True once patched)."""
    from bokeh.core.has_props import HasProps
    from bokeh.core.property.bases import ParameterizedProperty, Property
    from bokeh.core.property.descriptors import PropertyDescriptor
    from bokeh.core.property.wrappers import PropertyValueContainer
    from bokeh.model import util
    from bokeh.protocol.messages.patch_doc import patch_doc
    from panel.io import document, resources, server
    from panel.pane.base import PaneBase
    from panel.reactive import Reactive
    from panel.template.base import BaseTemplate
    from param.parameterized import _InstancePrivate

    def marked(thing, mark: str) -> bool:
        return bool(getattr(thing, mark, False))

    return {
        "panel.io.resources._panel_use_mathjax": resources._panel_use_mathjax.__name__
        == "<lambda>",
        "panel.io.server.bundle_resources": marked(server.bundle_resources, "without_webgl"),
        "bokeh patch_doc.create": marked(patch_doc.create, "lighter"),
        "panel.reactive.Reactive._update_properties": marked(
            Reactive._update_properties, "lighter"
        ),
        "panel.io.document._dispatch_msgs": marked(document._dispatch_msgs, "not_stranded"),
        "panel.template.base.BaseTemplate._init_doc": marked(BaseTemplate._init_doc, "forgets"),
        "bokeh Property.themed_default": marked(Property.themed_default, "kept"),
        "bokeh PropertyDescriptor.has_unstable_default": marked(
            PropertyDescriptor.has_unstable_default, "kept"
        ),
        "bokeh HasProps.themed_values": marked(HasProps.themed_values, "direct"),
        "bokeh ParameterizedProperty.__str__": marked(ParameterizedProperty.__str__, "once"),
        "bokeh PropertyValueContainer._register_owner": marked(
            PropertyValueContainer._register_owner, "tuples"
        ),
        "bokeh HasProps.__init__": marked(HasProps.__init__, "lazy"),
        "bokeh model.util.visit_immediate_value_references": marked(
            util.visit_immediate_value_references, "lazy"
        ),
        "panel.pane.base.PaneBase.__init__": marked(PaneBase.__init__, "lazy_layout"),
        "param _InstancePrivate.__init__": marked(_InstancePrivate.__init__, "lists"),
    }
