"""The app's patches to Panel, Bokeh and param internals (app/server/patches/): each internal a
patch replaces or reads is still there with the shape it was made for, the versions installed
are those ``pyproject.toml`` allows, and a served app has every patch in place.

These fail, not skip: a patch switched off quietly by an upgrade made pages slow with no test
saying so (issue 38). The signatures below are written out from the libraries' sources the
patches were made for (panel 1.9.4, bokeh 3.9.2, param 2.4.2), not read from the patches.
"""

from __future__ import annotations

import inspect
import re
import urllib.request
from pathlib import Path

import pytest
import tomllib

from served import served_app, server_log

ROOT = Path(__file__).resolve().parents[2]


def _internal(path: str):
    """The object at ``path``: a module, then attributes ("panel.reactive:Reactive._update_properties")."""
    import importlib

    module, _, attributes = path.partition(":")
    thing = importlib.import_module(module)
    for name in attributes.split(".") if attributes else ():
        thing = (
            inspect.getattr_static(thing, name) if inspect.isclass(thing) else getattr(thing, name)
        )
        if isinstance(thing, classmethod | staticmethod):
            thing = thing.__func__
    return thing


def _unpatched(thing):
    """What a patch replaced, when ``thing`` is a patch (each keeps the original it wraps)."""
    for mark in ("bokeh", "panel", "param", "__wrapped__"):
        original = getattr(thing, mark, None)
        if callable(original):
            if isinstance(original, classmethod) or inspect.ismethod(original):
                original = original.__func__  # a classmethod's function: (cls, ...)
            return _unpatched(original)
    return thing


# The internal each patch replaces or calls (module:attribute), and its parameters as the patch
# calls or mimics them: (name, kind) in order; annotations and defaults aside.
P, K, V, KW = "POSITIONAL_OR_KEYWORD", "KEYWORD_ONLY", "VAR_POSITIONAL", "VAR_KEYWORD"
SIGNATURES = {
    # panel_mathjax
    "panel.io.resources:_panel_use_mathjax": [("roots", P)],
    # panel_bundle_resources
    "panel.io.server:bundle_resources": [
        ("roots", P), ("resources", P), ("notebook", P), ("reloading", P), ("enable_mathjax", P),
    ],
    # bokeh_patch_doc
    "bokeh.protocol.messages.patch_doc:patch_doc.create": [("cls", P), ("events", P), ("metadata", KW)],
    "bokeh.core.serialization:Serializer.__init__": [
        ("self", P), ("references", K), ("deferred", K), ("check_circular", K),
    ],
    "bokeh.document.json:PatchJson": None,  # a TypedDict the patch builds: it must exist
    "bokeh.document.models:DocumentModelManager.flush_synced": [("self", P), ("is_still_new", P)],
    # panel_reactive_update
    "panel.reactive:Reactive._update_properties": [("self", P), ("events", V), ("doc", K)],
    "panel.reactive:Reactive._process_param_change": [("self", P), ("params", P)],
    # panel_dispatch_msgs
    "panel.io.document:_dispatch_msgs": [("doc", P)],
    "panel.io.document:_dispatch_write_task": [("doc", P), ("func", P), ("args", V), ("kwargs", KW)],
    # panel_template_init_doc
    "panel.template.base:BaseTemplate._init_doc": [
        ("self", P), ("doc", P), ("comm", P), ("title", P), ("notebook", P), ("location", P),
    ],
    # bokeh_properties
    "bokeh.core.property.bases:Property.themed_default": [
        ("self", P), ("cls", P), ("name", P), ("theme_overrides", P), ("no_eval", K),
    ],
    "bokeh.core.property.descriptors:PropertyDescriptor.has_unstable_default": [
        ("self", P), ("obj", P),
    ],
    "bokeh.core.has_props:HasProps.themed_values": [("self", P)],
    "bokeh.core.property.bases:ParameterizedProperty.__str__": [("self", P)],
    "bokeh.core.property.wrappers:PropertyValueContainer.__init__": [
        ("self", P), ("args", V), ("kwargs", KW),
    ],
    "bokeh.core.property.wrappers:PropertyValueContainer._register_owner": [
        ("self", P), ("owner", P), ("descriptor", P),
    ],
    "bokeh.core.property.wrappers:PropertyValueContainer._unregister_owner": [
        ("self", P), ("owner", P), ("descriptor", P),
    ],
    "bokeh.core.has_props:HasProps.__init__": [("self", P), ("properties", KW)],
    "bokeh.core.has_props:HasProps.query_properties_with_values": [
        ("self", P), ("query", P), ("include_defaults", K), ("include_undefined", K),
    ],
    "bokeh.model.util:visit_immediate_value_references": [("value", P), ("visitor", P)],
    "bokeh.model.util:visit_value_and_its_immediate_references": [("obj", P), ("visitor", P)],
    "panel.io.document:visit_immediate_value_references": [("value", P), ("visitor", P)],
    # panel_pane_layout
    "panel.pane.base:PaneBase.__init__": [("self", P), ("object", P), ("params", KW)],
    "panel.pane.base:PaneBase._sync_layoutable": [("self", P), ("events", V)],
    "panel.pane.markup:HTMLBasePane": None,
    # param_watchers
    "param.parameterized:_InstancePrivate.__init__": [
        ("self", P), ("initialized", P), ("parameters_state", P), ("dynamic_watchers", P),
        ("refs", P), ("params", P), ("watchers", P), ("values", P), ("explicit_no_refs", P),
    ],
}  # fmt: skip

# The private state the patches read, by name: (module:object, attribute)
STATE = [
    ("panel.io.document:", "_WRITE_MSGS"),
    ("panel.io.document:", "_WRITE_BLOCK"),
    ("panel.io.state:state", "_fake_roots"),
    ("bokeh.document.models:DocumentModelManager", "flush_synced"),
    ("param.parameterized:_InstancePrivate", "__slots__"),
]


@pytest.mark.parametrize("path", sorted(SIGNATURES))
def test_each_patched_internal_keeps_the_shape_its_patch_was_made_for(path):
    """Each internal a patch replaces or calls exists and takes the parameters the patch gives it
    (the original, when the patch is applied already)."""
    thing = _unpatched(_internal(path))
    expected = SIGNATURES[path]
    if expected is None:
        return
    parameters = inspect.signature(thing).parameters.values()
    assert [(p.name, p.kind.name) for p in parameters] == expected, path


def test_the_private_state_the_patches_read_is_there():
    for path, name in STATE:
        holder = _internal(path.rstrip(":")) if not path.endswith(":") else _internal(path[:-1])
        assert hasattr(holder, name), f"{path}{name}"
    from param.parameterized import _InstancePrivate

    assert "watchers" in _InstancePrivate.__slots__  # param_watchers sets it


def _release(version: str) -> tuple[int, ...]:
    """A version's release numbers: "1.9.4" -> (1, 9, 4)."""
    return tuple(int(part) for part in re.match(r"\d+(?:\.\d+)*", version).group().split("."))


def test_the_installed_versions_are_those_pyproject_allows():
    """panel, bokeh and param are bounded above to the versions the patches are tested on, and
    these are installed (an upgrade past a bound fails here, not quietly in a slow page)."""
    import bokeh
    import panel
    import param

    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"][
        "optional-dependencies"
    ]
    for module in (panel, bokeh, param):
        [requirement] = [r for r in extras["app"] if re.match(rf"{module.__name__}\b", r)]
        bounds = dict(re.findall(r"(>=|<)\s*([\d.]+)", requirement))
        assert set(bounds) == {">=", "<"}, requirement  # bounded from below and above
        installed = _release(module.__version__)
        assert _release(bounds[">="]) <= installed < _release(bounds["<"]), (
            requirement,
            module.__version__,
        )


def test_every_patch_applies_on_the_installed_versions():
    """In this process (as a page's ``main.py`` applies them): each patch in place."""
    from windpump_app.server import patches

    patches.apply_all()
    assert patches.applied() == dict.fromkeys(patches.applied(), True)


def test_every_patch_module_says_the_versions_it_was_made_for():
    for path in sorted((ROOT / "app" / "server" / "patches").glob("[!_]*.py")):
        doc = path.read_text().split('"""')[1]
        assert re.search(r"Made for (panel|bokeh|param) \d+\.\d+\.\d+", doc), path.name


def test_a_served_app_has_every_patch_in_place():
    """``panel serve app/`` applies the patches as it starts (server.hooks.framework_patches) and
    says so; a page served from it is built with them (it opens)."""
    from windpump_app.server import patches

    with served_app(timeout=300) as (url, process):
        with urllib.request.urlopen(url, timeout=120) as response:  # a page: main.py ran
            assert response.status == 200
        log = server_log(process)
    count = len(patches.applied())
    assert f"framework patches: all {count} applied" in log, log[-3000:]
    assert "framework patches not applied" not in log
