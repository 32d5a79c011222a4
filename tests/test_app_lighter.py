"""Panel's components made lighter for a page kept in memory (app/lighter.py): what a page shows
and sends is the same, with fewer objects kept. Each test compares with Panel's own behaviour,
restored for the comparison (``panels_own``)."""

from __future__ import annotations

import sys
from pathlib import Path

import panel as pn
import pytest
from panel.pane.base import PaneBase
from panel.pane.markup import HTMLBasePane
from panel.viewable import Layoutable

from windpump_app.lighter import lighter_components

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import bench_page_memory  # noqa: E402

pytestmark = pytest.mark.skipif(
    not pn.__version__.startswith("1.9."), reason="patched only on the Panel it was checked on"
)


@pytest.fixture(autouse=True)
def lighter():
    lighter_components()


@pytest.fixture
def panels_own(monkeypatch):
    """Panel's own components while the test asks (``panels_own.undo()`` ends it)."""
    monkeypatch.setattr(PaneBase, "__init__", PaneBase.__init__.panel)  # type: ignore[attr-defined]
    monkeypatch.delattr(HTMLBasePane, "layout")
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
