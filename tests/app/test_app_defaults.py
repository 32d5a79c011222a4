"""Bokeh's property machinery made lighter for a page (app/server/patches/bokeh_properties.py): the same values, fewer
workings-out. Each test compares with what Bokeh's own methods give, kept aside by the patch."""

from __future__ import annotations

import sys
from pathlib import Path

import bokeh
import pytest
from bokeh.core.has_props import HasProps
from bokeh.core.properties import Any, Dict, Int, List, String
from bokeh.core.property.bases import ParameterizedProperty, Property
from bokeh.document import Document
from bokeh.models import ColumnDataSource, Div, GlyphRenderer, Line, Slider
from bokeh.plotting import figure
from bokeh.themes import Theme

from windpump_app.server.patches.bokeh_properties import immutable, lighter_properties

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
import bench_page_memory  # noqa: E402

pytestmark = pytest.mark.skipif(
    not bokeh.__version__.startswith("3.9."), reason="patched only on the Bokeh it was checked on"
)


@pytest.fixture(autouse=True)
def lighter():
    lighter_properties()


def test_a_default_is_worked_out_once_per_class_and_property(monkeypatch):
    prepared = []
    prepare_value = Property.prepare_value

    def counted(self, owner, name, value, **kwargs):
        prepared.append((owner, name))
        return prepare_value(self, owner, name, value, **kwargs)

    monkeypatch.setattr(Property, "prepare_value", counted)
    for _ in range(5):
        assert Slider(start=0, end=1, value=0.5).bar_color == "#e6e6e6"
    assert prepared.count((Slider, "bar_color")) <= 1  # Bokeh's own: once per read


MODELS = [Slider, Div, Line, GlyphRenderer, ColumnDataSource]


@pytest.mark.parametrize("cls", MODELS, ids=lambda c: c.__name__)
def test_every_default_is_bokehs_own(cls):
    bokehs = Property.themed_default.bokeh  # type: ignore[attr-defined]
    model = cls()
    for name in model.properties():
        prop = model.lookup(name).property
        kept = model.lookup(name)._get(model)  # Undefined for a value a model must be given
        if immutable(kept):
            assert kept == bokehs(prop, cls, name, None), name


def test_figures_defaults_are_bokehs_own():
    bokehs = Property.themed_default.bokeh  # type: ignore[attr-defined]
    fig = figure()
    for model in [fig, fig.xaxis[0], fig.yaxis[0], fig.xgrid[0], fig.title, fig.toolbar]:
        for name in model.properties():
            kept = model.lookup(name)._get(model)
            if immutable(kept):
                expected = bokehs(model.lookup(name).property, type(model), name, None)
                assert kept == expected, (type(model).__name__, name)


def test_mutable_defaults_are_each_models_own():
    a, b = ColumnDataSource(), ColumnDataSource()
    assert a.data is not b.data
    a.data["x"] = [1, 2]
    assert "x" not in b.data
    c, d = Div(), Div()
    assert c.tags is not d.tags and c.stylesheets is not d.stylesheets
    c.tags.append("one")
    assert d.tags == []
    r, s = GlyphRenderer(), GlyphRenderer()
    assert r.view is not s.view  # a model made by its default: one each


def test_a_themes_values_still_apply_and_follow_the_theme():
    document = Document()
    themed, plain = Slider(start=0, end=1, value=0.5), Slider(start=0, end=1, value=0.5)
    assert themed.bar_color == "#e6e6e6"
    width = themed.width  # the class's own default
    document.theme = Theme(json={"attrs": {"Slider": {"bar_color": "red", "width": 222}}})
    document.add_root(themed)
    assert (themed.bar_color, themed.width) == ("red", 222)
    assert (plain.bar_color, plain.width) == ("#e6e6e6", width)
    document.theme = Theme(json={"attrs": {"Slider": {"bar_color": "blue"}}})
    assert (themed.bar_color, themed.width) == ("blue", width)
    themed.bar_color = "green"  # a value set outranks the theme
    assert themed.bar_color == "green"


def test_theme_values_are_read_as_bokeh_sets_them():
    model = Div()
    assert model.themed_values() is None
    values = {"width": 10}
    model.apply_theme(values)
    assert model.themed_values() is values and model.width == 10
    model.unapply_theme()
    assert model.themed_values() is None and model.width is None
    assert HasProps.themed_values.direct  # type: ignore[attr-defined]


def test_a_container_propertys_name_is_written_once_and_the_same():
    prop = Dict(String, List(Int))
    assert str(prop) == "Dict(String, List(Int))" == str(prop)
    assert ParameterizedProperty.__str__.once  # type: ignore[attr-defined]
    with pytest.raises(ValueError, match=r"expected a dict of type Dict\(String, Any\)"):
        Dict(String, Any).validate([1])


@pytest.mark.parametrize("cls", MODELS, ids=lambda c: c.__name__)
def test_whether_a_default_is_made_anew_is_bokehs_own_answer(cls, monkeypatch):
    from bokeh.core.property.descriptors import PropertyDescriptor

    kept = PropertyDescriptor.has_unstable_default
    assert kept.kept  # type: ignore[attr-defined]
    model = cls()
    answers = {name: kept(model.lookup(name), model) for name in model.properties()}
    for _ in range(2):  # kept, and asked again
        assert answers == {name: kept(model.lookup(name), model) for name in model.properties()}
    monkeypatch.setattr(PropertyDescriptor, "has_unstable_default", kept.__wrapped__)
    assert answers == {
        name: model.lookup(name).has_unstable_default(model) for name in model.properties()
    }
    assert answers["tags"] and not answers["name"]  # a list made anew, a string not


def test_a_property_lists_owners_are_kept_in_a_tuple_and_told_of_changes():
    source, other = ColumnDataSource(data={"x": [1]}), Div()
    owners = source.data._owners
    assert type(owners) is tuple and len(owners) == 1 and owners[0][0] is source
    changes = []
    other.on_change("tags", lambda attr, old, new: changes.append((old, new)))
    other.tags.append("a")  # a change in place reaches the model that owns the list
    assert other.tags == ["a"] and changes == [([], ["a"])]
    shared = other.tags
    twice = Div(tags=shared)  # a list set on a second model: both own it, once each
    twice.tags = shared
    assert [owner for owner, _ in shared._owners] == [other, twice]
    twice.tags = ["b"]  # and the one that let it go no more
    assert [owner for owner, _ in shared._owners] == [other]


@pytest.fixture
def bokehs_own(monkeypatch):
    """Bokeh's own making of a model's empty defaults, its walk and its serialiser while the
    test asks (``bokehs_own.undo()`` ends it)."""
    from bokeh.model import util
    from panel.io import document as panel_document

    visit = util.visit_immediate_value_references
    monkeypatch.setattr(HasProps, "__init__", HasProps.__init__.bokeh)  # type: ignore[attr-defined]
    query = HasProps.query_properties_with_values
    monkeypatch.setattr(HasProps, "query_properties_with_values", query.bokeh)  # type: ignore[attr-defined]
    monkeypatch.setattr(util, "visit_immediate_value_references", visit.bokeh)  # type: ignore[attr-defined]
    monkeypatch.setattr(panel_document, "visit_immediate_value_references", visit.bokeh)  # type: ignore[attr-defined]
    return monkeypatch


def page_of_models() -> Document:
    """A document of a figure with a line and models of the page's kinds."""
    fig = figure(title="t")
    fig.line([1, 2], [3, 4])
    document = Document()
    for root in (fig, Slider(start=0, end=1, value=0.5), Div(text="x"), ColumnDataSource()):
        document.add_root(root)
    return document


def read(document: Document) -> tuple:
    """What a document's models send (names of their values other than defaults, and the whole
    document as its JSON), what each refers to, and every value of a few empty defaults."""
    models = sorted(document.models, key=lambda m: (type(m).__name__, m.id))
    sent = [sorted(model.properties_with_values(include_defaults=False)) for model in models]
    refers = [sorted(type(ref).__name__ for ref in model.references()) for model in models]
    defaults = [
        [getattr(model, name) for name in ("tags", "js_event_callbacks", "subscribed_events")]
        for model in models
    ]
    return sent, bench_page_memory.normalised(document), refers, defaults


def test_a_models_empty_defaults_are_made_when_first_read():
    model = Div()
    assert "tags" not in model._unstable_default_values  # not made with the model
    tags = model.tags
    assert type(tags).__name__ == "PropertyValueList" and tags == [] and model.tags is tags
    assert tags._owners == ((model, model.lookup("tags")),)  # owned: told of a change in place
    changes = []
    model.on_change("tags", lambda attr, old, new: changes.append((old, new)))
    model.tags.append("a")
    assert changes == [([], ["a"])]
    assert Div().js_event_callbacks == {} and Div().stylesheets == []


def test_models_send_refer_to_and_read_as_with_bokehs_own_defaults(bokehs_own):
    own = read(page_of_models())
    bokehs_own.undo()
    assert read(page_of_models()) == own


def test_a_themes_container_default_still_applies():
    themed, plain = Div(), Div()
    document = Document()
    document.theme = Theme(json={"attrs": {"Div": {"css_classes": ["from-theme"]}}})
    document.add_root(themed)
    assert themed.css_classes == ["from-theme"] and plain.css_classes == []
    assert themed.properties_with_values(include_defaults=False)["css_classes"] == ["from-theme"]
    assert "css_classes" not in plain.properties_with_values(include_defaults=False)


@pytest.mark.parametrize("views", [False, True], ids=["page", "with its first screen"])
def test_a_page_sends_the_same_document_with_fewer_models_containers(views, bokehs_own):
    import gc

    from bokeh.core.property.wrappers import PropertyValueContainer

    def containers() -> int:
        gc.collect()
        # type(), not isinstance(): a weakref proxy another test left behind, its object gone,
        # raises ReferenceError when isinstance() asks it for its __class__
        return sum(issubclass(type(obj), PropertyValueContainer) for obj in gc.get_objects())

    before = containers()
    own, _, _ = bench_page_memory.page(views)
    made_own = containers() - before
    bokehs_own.undo()
    before = containers()
    document, _, _ = bench_page_memory.page(views)
    made = containers() - before
    assert bench_page_memory.normalised(document) == bench_page_memory.normalised(own)
    assert made < made_own / 2, (made, made_own)
