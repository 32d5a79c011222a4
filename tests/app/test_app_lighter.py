"""Panel's components made lighter for a page kept in memory (app/server/patches/: panel_pane_layout.py, param_watchers.py): what a page shows
and sends is the same, with fewer objects kept. Each test compares with Panel's own behaviour,
restored for the comparison (``panels_own``)."""

from __future__ import annotations

import sys
from pathlib import Path

import panel as pn
import param
import pytest
from panel.pane.base import PaneBase
from panel.pane.markup import HTMLBasePane
from panel.viewable import Layoutable
from param.parameterized import _InstancePrivate

from windpump_app.server.patches import lighter_components
from windpump_app.server.patches.param_watchers import ValueWatchers

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
import bench_page_memory  # noqa: E402

pytestmark = pytest.mark.skipif(
    not pn.__version__.startswith("1.9."), reason="patched only on the Panel it was checked on"
)


@pytest.fixture(autouse=True)
def lighter():
    lighter_components()


@pytest.fixture
def panels_own(monkeypatch):
    """Panel's and param's own components while the test asks (``panels_own.undo()`` ends it)."""
    monkeypatch.setattr(PaneBase, "__init__", PaneBase.__init__.panel)  # type: ignore[attr-defined]
    monkeypatch.delattr(HTMLBasePane, "layout")
    monkeypatch.setattr(_InstancePrivate, "__init__", _InstancePrivate.__init__.param)  # type: ignore[attr-defined]
    return monkeypatch


def built(pane) -> bool:
    """Whether ``pane`` has built its layout (Panel's own keeps it in ``layout``)."""
    return "layout" in pane.__dict__ or "_built_layout" in pane.__dict__


def layout_values(layout) -> dict:
    return {name: getattr(layout, name) for name in Layoutable.param if name != "name"}


PANES = [
    (pn.pane.HTML, "<b>x</b>", dict(width=100, margin=5, sizing_mode="fixed")),
    (pn.pane.Markdown, "**x**", dict(margin=(2, 4), sizing_mode="stretch_width")),
    (pn.pane.Alert, "x", dict(alert_type="info", height=40, styles={"color": "red"})),
    (pn.pane.Str, "x", dict(min_width=50, visible=False)),
]


@pytest.mark.parametrize("cls, text, options", PANES, ids=lambda p: getattr(p, "__name__", ""))
def test_a_text_panes_layout_is_panels_own_once_asked_for_and_follows_it(
    cls, text, options, panels_own
):
    own = cls(text, **options)
    own.param.update(width=120, visible=True)
    expected = layout_values(own.layout)
    panels_own.undo()
    pane = cls(text, **options)
    assert not built(pane)
    pane.param.update(width=120, visible=True)  # changes before the layout is asked for
    layout = pane.layout
    assert isinstance(layout, pn.Row) and layout.objects == [pane] and pane.layout is layout
    assert layout_values(layout) == expected
    pane.param.update(width=200, margin=(1, 2, 3, 4))  # and after: kept in step, as Panel does
    assert layout.width == 200 + 2 + 4 and pane[0] is pane


def test_a_pane_shown_on_its_own_renders_as_panels_own(panels_own):
    own = pn.panel("**x**").get_root()
    panels_own.undo()
    assert type(pn.panel("**x**").get_root()) is type(own)
    assert pn.pane.HTML("x").get_root().text == pn.pane.HTML("x", name="y").get_root().text


@pytest.mark.parametrize("views", [False, True], ids=["page", "with its first screen"])
def test_a_page_sends_the_same_document_and_builds_no_panes_layout(views, panels_own):
    bench_page_memory.setup(lighter=False)
    own, _, _ = bench_page_memory.page(views)
    panels_own.undo()
    document, _, template = bench_page_memory.page(views)
    assert bench_page_memory.normalised(document) == bench_page_memory.normalised(own)
    panes = template.select(HTMLBasePane)
    assert len(panes) > 20 and not any(built(pane) for pane in panes)


class Knobs(param.Parameterized):
    a = param.Number(1.0)
    b = param.Number(2.0)


def watched(calls: list) -> Knobs:
    """Knobs watched as a page watches its inputs: several watchers, precedences, both values,
    one watcher removed."""
    knobs = Knobs()
    knobs.param.watch(
        lambda *e: calls.append(("ab", [x.name for x in e])), ["a", "b"], precedence=3
    )
    knobs.param.watch(lambda e: calls.append(("second", e.new)), "a", precedence=1)
    gone = knobs.param.watch(lambda e: calls.append(("gone", e.new)), "a")
    knobs.param.watch(lambda e: calls.append(("b", e.old, e.new)), "b", onlychanged=False)
    knobs.a = 5.0
    knobs.param.unwatch(gone)
    knobs.param.unwatch(gone)  # a second time does nothing, as param's
    knobs.param.update(a=6.0, b=2.0)
    knobs.param.trigger("b")
    return knobs


def kind(watcher) -> tuple:
    return watcher.precedence, watcher.parameter_names, watcher.onlychanged


def test_watchers_are_called_as_params_own_and_read_as_its_dicts(panels_own):
    own_calls: list = []
    own = watched(own_calls)
    panels_own.undo()
    calls: list = []
    knobs = watched(calls)
    assert calls == own_calls
    mine, theirs = knobs.param.watchers, own.param.watchers
    assert type(mine["a"]) is ValueWatchers and type(theirs["a"]) is dict
    assert mine.keys() == theirs.keys()
    for name in theirs:
        entry = mine[name]
        assert entry["value"] is entry and entry.get("value") is entry and "value" in entry
        assert entry.get("other") is None and "other" not in entry
        assert [kind(w) for w in entry["value"]] == [kind(w) for w in theirs[name]["value"]]
        assert [(k, len(v)) for k, v in entry.items()] == [
            (k, len(v)) for k, v in theirs[name].items()
        ]
        assert [len(v) for v in entry.values()] == [len(v) for v in theirs[name].values()]
        with pytest.raises(KeyError):
            entry["other"]


def test_a_layout_updates_its_names_first_as_panel_has_it(panels_own):
    own = pn.Tabs(("a", pn.pane.Markdown("a")))
    own_order = [w.fn.__name__ for w in own.param.watchers["objects"]["value"]]
    panels_own.undo()
    tabs = pn.Tabs(("a", pn.pane.Markdown("a")))  # Panel reverses that list in place
    assert [w.fn.__name__ for w in tabs.param.watchers["objects"]["value"]] == own_order
    assert "_update_names" in own_order and len(own_order) > 1
    tabs.append(("b", pn.pane.Markdown("b")))
    assert tabs.objects[1].object == "b" and tabs._names == ["a", "b"]
