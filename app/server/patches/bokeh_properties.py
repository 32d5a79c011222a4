"""Bokeh's property machinery, lighter for a page of ~350 models built and sent per student.

A page here is ~350 Bokeh models (its controls, template and first views), and every property of
every model that is not set is read through its default several times while the page is built
and sent: when it is set (the old value), when the document walks its models, when it is
serialised. Bokeh (3.9) works the default out again at each read (``Property.themed_default``:
the class's overrides, a copy of the default, ``prepare_value``'s validation), ~17,000 times a
page. Profiled while pages opened one after another on a served app, that was 37 % of the
server's CPU for a page. A default that is a plain immutable value (None, a number, a string, a
tuple of them) is the same each time for a class and property: here it is worked out once per
class and property (and per theme value) and kept. Mutable defaults (lists, dicts, models) are
worked out as before, a fresh one each time, so no model shares one with another.

Whether a default is "unstable" (made anew for each model: a list, a model) is known per class
and property, and was worked out again at each read too (importing two names each time: 12 %).
Each list or dict a model holds as a property value (most of them its defaults: its tags, its
stylesheets, its callbacks, ~6,000 a page) keeps the models that own it, to tell them of a change
made in place: in a set of its own, 216 bytes for one owner, 1.1 MB a page of a session's memory
(tracemalloc, a served page). Here in a tuple (48 bytes), the same owners.

Three more of its costs are cut the same way, with the same results: a model's theme values were
looked up by raising and catching an ``AttributeError`` twice when it has none (most models, at
each read of a default: 9 % of a page's build), and the name of a container property (``Dict(String,
Any)``) was written out at each validation of a value, for an error message not raised (6 %).

And Bokeh made every such container a model's class gives it by default as the model was made
(``HasProps.__init__``) and kept it, ~7 a model, almost all never used: an empty list, dict or
set is made here when first read, as Bokeh makes any default it has not made yet, and the walks
that read every property (the document's walk of what its models refer to, the serialiser)
pass over those not made: empty, they refer to nothing, and the serialiser leaves an unchanged
container default out anyway. A page with its first screen's views is the same document with
~2,000 fewer containers (``benchmarks/bench_page_memory.py``: 0.9 MB fewer a page).

Made for bokeh 3.9.2 (applied on bokeh 3.9 only): it replaces ``Property.themed_default(self, cls,
name, theme_overrides, *, no_eval=False)``, ``PropertyDescriptor.has_unstable_default(self, obj)``,
``HasProps.themed_values(self)``, ``ParameterizedProperty.__str__(self)``,
``PropertyValueContainer.__init__`` and its ``_register_owner``/``_unregister_owner(self, owner,
descriptor)``, ``HasProps.__init__(self, **properties)`` (with Bokeh 3.9's body),
``HasProps.query_properties_with_values(self, query, *, include_defaults=True,
include_undefined=False)`` and ``bokeh.model.util.visit_immediate_value_references(value,
visitor)`` (and Panel 1.9's copy of it); ``tests/app/test_app_patches.py`` fails when any of them
changes shape.
"""

from __future__ import annotations

from typing import Any

# Values whose default is kept: what a property cannot change in place.
IMMUTABLE = (type(None), bool, int, float, str)


def immutable(value: Any) -> bool:
    """Whether ``value`` is a plain immutable value, or a tuple of them."""
    if type(value) is tuple:
        return all(immutable(item) for item in value)
    return type(value) in IMMUTABLE


def lighter_properties() -> None:
    """Bokeh's property machinery with its defaults kept, its theme values read directly and its
    container properties' names written once (see the module); a second call does nothing."""
    import bokeh

    # It replaces methods of Bokeh's property machinery: only on the Bokeh it was checked against.
    if not bokeh.__version__.startswith("3.9."):
        return
    kept_defaults()
    stable_defaults_known()
    themed_values_read_directly()
    names_written_once()
    owners_in_tuples()
    empty_defaults_made_when_read()


def kept_defaults() -> None:
    """Keep the immutable defaults of Bokeh's properties once worked out (see the module)."""
    from bokeh.core.property.bases import Property

    if getattr(Property.themed_default, "kept", False):
        return
    themed_default = Property.themed_default
    kept: dict = {}

    def default(self, cls, name, theme_overrides, *, no_eval=False):
        themed = theme_overrides is not None and name in theme_overrides
        override = theme_overrides[name] if themed else None
        if themed and not immutable(override):
            return themed_default(self, cls, name, theme_overrides, no_eval=no_eval)
        # A property is not hashable: its id, kept with it (an id is unique while it lives)
        key = (id(self), cls, name, no_eval, themed, type(override), override)
        entry = kept.get(key)
        if entry is not None and entry[0] is self:
            return entry[1]
        value = themed_default(self, cls, name, theme_overrides, no_eval=no_eval)
        if immutable(value):
            kept[key] = (self, value)
        return value

    default.kept = True  # type: ignore[attr-defined]
    default.bokeh = themed_default  # type: ignore[attr-defined]
    Property.themed_default = default  # type: ignore[method-assign]


def stable_defaults_known() -> None:
    """Whether a property's default is made anew for each model (``has_unstable_default``: its
    type, and its class's overridden default) kept per class and property once known."""
    from bokeh.core.property.descriptors import PropertyDescriptor

    if getattr(PropertyDescriptor.has_unstable_default, "kept", False):
        return
    has_unstable_default = PropertyDescriptor.has_unstable_default
    known: dict = {}

    def unstable(self, obj) -> bool:
        key = (id(self), type(obj))  # a descriptor lives as long as its class
        entry = known.get(key)
        if entry is not None and entry[0] is self:
            return entry[1]
        answer = has_unstable_default(self, obj)
        known[key] = (self, answer)
        return answer

    unstable.kept = True  # type: ignore[attr-defined]
    unstable.__wrapped__ = has_unstable_default  # type: ignore[attr-defined]
    PropertyDescriptor.has_unstable_default = unstable  # type: ignore[method-assign]


def themed_values_read_directly() -> None:
    """A model's theme values (``HasProps.themed_values``) read from its ``__dict__``, where
    ``apply_theme`` sets them, not through ``getattr``: Bokeh's ``__getattr__`` raises for a model
    without any, and ``getattr`` catches it."""
    from bokeh.core.has_props import HasProps

    if getattr(HasProps.themed_values, "direct", False):
        return

    def themed_values(self):
        return self.__dict__.get("__themed_values__")

    themed_values.direct = True  # type: ignore[attr-defined]
    themed_values.__doc__ = HasProps.themed_values.__doc__
    HasProps.themed_values = themed_values  # type: ignore[method-assign]


def names_written_once() -> None:
    """A container property's name (``Dict(String, Any)``: its class and its type parameters,
    fixed once it is made) written once and kept, not at each validation of a value."""
    from bokeh.core.property.bases import ParameterizedProperty

    if getattr(ParameterizedProperty.__str__, "once", False):
        return
    written = ParameterizedProperty.__str__

    def name(self) -> str:
        try:
            return self.__dict__["_windpump_name"]
        except KeyError:
            self.__dict__["_windpump_name"] = text = written(self)
            return text

    name.once = True  # type: ignore[attr-defined]
    ParameterizedProperty.__str__ = name  # type: ignore[method-assign]


def owners_in_tuples() -> None:
    """The owners of a property's list or dict (``PropertyValueContainer._owners``: almost always
    one model) kept in a tuple, not a set of their own; told of a change in place as before."""
    from bokeh.core.property.wrappers import PropertyValueContainer

    if getattr(PropertyValueContainer._register_owner, "tuples", False):
        return

    def __init__(self, *args, **kwargs) -> None:
        self._owners = ()
        super(PropertyValueContainer, self).__init__(*args, **kwargs)

    def register(self, owner, descriptor) -> None:
        pair = (owner, descriptor)
        if pair not in self._owners:
            self._owners = (*self._owners, pair)

    def unregister(self, owner, descriptor) -> None:
        pair = (owner, descriptor)
        self._owners = tuple(owned for owned in self._owners if owned != pair)

    register.tuples = True  # type: ignore[attr-defined]
    PropertyValueContainer.__init__ = __init__  # type: ignore[method-assign]
    PropertyValueContainer._register_owner = register  # type: ignore[method-assign]
    PropertyValueContainer._unregister_owner = unregister  # type: ignore[method-assign]


def empty_defaults_made_when_read() -> None:
    """A model's empty list, dict and set defaults made when first read (see the module), not each
    made and kept as the model is made; the document's walk of its models' references and the
    serialiser pass over those not made yet (empty, they refer to nothing and send nothing)."""
    from bokeh.core.has_props import HasProps
    from bokeh.model import util

    if getattr(HasProps.__init__, "lazy", False):
        return
    init = _init_without_empty_defaults(HasProps)
    init.bokeh = HasProps.__init__  # type: ignore[attr-defined]
    HasProps.__init__ = init  # type: ignore[method-assign]
    HasProps.query_properties_with_values = _query_without_unmade(  # type: ignore[method-assign]
        HasProps.query_properties_with_values
    )
    visit = _visit_without_unmade(util.visit_immediate_value_references)
    util.visit_immediate_value_references = visit
    try:  # Panel's copy of the name, where it checks what a change refers to
        from panel.io import document as panel_document

        panel_document.visit_immediate_value_references = visit  # type: ignore[attr-defined]
    except ImportError:
        pass


_EMPTY = (list, dict, set)
_MADE_AT_INIT: dict = {}  # class -> the names of its properties made as a model is made


def _made_at_init(model) -> tuple[str, ...]:
    """The properties of ``model``'s class whose default is made anew for each model (Bokeh's
    ``has_unstable_default``), but for those whose default is an empty list, dict or set."""
    cls = type(model)
    names = _MADE_AT_INIT.get(cls)
    if names is None:
        names = _MADE_AT_INIT[cls] = tuple(
            name
            for name in cls.properties(_with_props=True)
            if model.lookup(name).has_unstable_default(model) and not _empty_default(cls, name)
        )
    return names


_EMPTY_DEFAULT: dict = {}  # (class, name) -> whether its default is a plain empty container


def _empty_default(cls, name: str) -> bool:
    key = (cls, name)
    answer = _EMPTY_DEFAULT.get(key)
    if answer is None:
        from bokeh.core.property.descriptors import PropertyDescriptor
        from bokeh.core.property.wrappers import PropertyValueContainer

        descriptor = cls.lookup(name)
        prop = descriptor.property
        default = getattr(prop, "_default", None)
        answer = _EMPTY_DEFAULT[key] = (
            type(descriptor) is PropertyDescriptor
            and name not in cls.__overridden_defaults__
            and type(default) in _EMPTY
            and len(default) == 0
            # one the serialiser leaves out as a default (a Seq's plain list it sends)
            and isinstance(prop.wrap(type(default)()), PropertyValueContainer)
        )
    return answer


def unmade(model, name: str) -> bool:
    """Whether ``model``'s property ``name`` is an empty default not made yet (not set, not read,
    not given by a theme)."""
    themed = model.themed_values()
    return (
        _empty_default(type(model), name)
        and name not in model._property_values
        and name not in model._unstable_default_values
        and (themed is None or name not in themed)
    )


def _init_without_empty_defaults(HasProps):
    """``HasProps.__init__`` of Bokeh 3.9, but for the empty defaults."""
    from bokeh.core.property.singletons import Intrinsic, Undefined

    def __init__(self, **properties) -> None:
        super(HasProps, self).__init__()
        self._property_values = {}
        self._unstable_default_values = {}
        self._unstable_themed_values = {}
        for name, value in properties.items():
            if value is Undefined or value is Intrinsic:
                continue
            setattr(self, name, value)
        for name in _made_at_init(self):
            if name not in properties:
                self.lookup(name)._get(self)  # fills in _unstable_*_values
        self._initialized = True

    __init__.lazy = True  # type: ignore[attr-defined]
    return __init__


def _query_without_unmade(query_properties_with_values):
    """Bokeh's, passing over the empty defaults not made yet when defaults are left out."""

    def query(self, query, *, include_defaults: bool = True, include_undefined: bool = False):
        if include_defaults:
            return query_properties_with_values(
                self, query, include_defaults=True, include_undefined=include_undefined
            )

        def asked(descriptor) -> bool:
            return not unmade(self, descriptor.name) and query(descriptor)

        return query_properties_with_values(
            self, asked, include_defaults=False, include_undefined=include_undefined
        )

    query.lazy = True  # type: ignore[attr-defined]
    query.bokeh = query_properties_with_values  # type: ignore[attr-defined]
    return query


def _visit_without_unmade(visit_immediate_value_references):
    """Bokeh's walk of what a model refers to, passing over its empty defaults not made yet."""
    from bokeh.core.has_props import HasProps
    from bokeh.model.util import visit_value_and_its_immediate_references

    def visit(value, visitor) -> None:
        if not isinstance(value, HasProps):
            visit_value_and_its_immediate_references(value, visitor)
            return
        for name in value.properties_with_refs():
            if not unmade(value, name):
                visit_value_and_its_immediate_references(getattr(value, name), visitor)

    visit.lazy = True  # type: ignore[attr-defined]
    visit.bokeh = visit_immediate_value_references  # type: ignore[attr-defined]
    return visit
