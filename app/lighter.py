"""Panel's components, lighter for a page kept in the server's memory while its student idles.

A page here is ~120 Panel components; a hall of 100 keeps 100 pages. Each text pane (HTML,
Markdown, Alert: ~40 a page, the readouts, captions, placeholders, notes) built a ``Row`` of its
own at once (``PaneBase.layout``, Panel 1.9), which Panel uses only to show the pane on its own as
a page's root or to index into it (``pane[0]``), never for a pane placed in a layout as every pane
here is; and it watched all ~25 of the pane's layout parameters to keep that ``Row`` in step. A
Panel component is ~10 kB of a session's memory, most of it param's watchers (a dict and a list for
each parameter watched): the ``Row`` and its watchers were ~0.4 MB of a page
(``benchmarks/bench_page_memory.py``). Here a text pane's ``Row`` is built, and kept in step, the
first time something asks for it: what a page shows and sends is the same.

What param keeps for each parameter watched on a component (``{"value": [watcher, ...]}``: a
dict of one key and a list, ~260 bytes; ~2,000 a page, ~0.5 MB) is kept as the list alone,
which answers as that dict too (``ValueWatchers``): the same watchers, called in the same order.
"""

from __future__ import annotations


def lighter_components() -> None:
    """Text panes' layouts built when first asked for, and param's watchers of a parameter kept
    in a list alone (see the module); a second call does nothing, and neither is done on a Panel
    or a param other than the one it was checked against."""
    import panel
    import param

    if panel.__version__.startswith("1.9."):
        lazy_pane_layouts()
    if param.__version__.startswith("2.4."):
        watchers_in_lists()


def lazy_pane_layouts() -> None:
    """A text pane (``HTMLBasePane``: HTML, Markdown, Alert, Str, ...) builds its ``layout`` and
    its watcher of the layout parameters the first time ``layout`` is read."""
    from panel.pane.base import PaneBase
    from panel.pane.markup import HTMLBasePane
    from panel.viewable import Layoutable

    if getattr(PaneBase.__init__, "lazy_layout", False):
        return
    eager_init = PaneBase.__init__

    def __init__(self, object=None, **params):
        if not isinstance(self, HTMLBasePane):
            eager_init(self, object, **params)
            return
        # PaneBase.__init__ of Panel 1.9.4, but for its last three statements (the layout)
        self._object_changing = False
        super(PaneBase, self).__init__(object=object, **params)
        if not hasattr(self, "_internal_callbacks"):
            self._internal_callbacks = []
        applies = self.applies(self.object, **(params if self._applies_kw else {}))
        if (isinstance(applies, bool) and not applies) and self.object is not None:
            self._type_error(self.object)
        # which layout parameters were given: the layout is built with them, as Panel does
        self._layout_keys = tuple(
            k for k in params if k in Layoutable.param and k not in self._skip_layoutable
        )

    def layout(self):
        built = self.__dict__.get("_built_layout")
        if built is None:
            kwargs = {k: getattr(self, k) for k in self.__dict__.get("_layout_keys", ())}
            built = self.__dict__["_built_layout"] = self.default_layout(self, **kwargs)
            self._internal_callbacks.append(
                self.param.watch(self._sync_layoutable, list(Layoutable.param))
            )
            self._sync_layoutable()
        return built

    __init__.lazy_layout = True  # type: ignore[attr-defined]
    __init__.panel = eager_init  # type: ignore[attr-defined]
    PaneBase.__init__ = __init__  # type: ignore[method-assign]
    HTMLBasePane.layout = property(layout)  # type: ignore[attr-defined]


class ValueWatchers(list):
    """The watchers of one parameter's value on one object, in the order param calls them: the
    list of param's ``{"value": [watcher, ...]}``, which answers as that dict too (``["value"]``,
    ``.get("value")``, ``.values()``, ``.items()``, ``"value" in``) and is changed in place
    through it as param and Panel change that list."""

    __slots__ = ()

    def __getitem__(self, key):
        if type(key) is str:
            if key == "value":
                return self
            raise KeyError(key)
        return list.__getitem__(self, key)

    def __setitem__(self, key, value) -> None:
        if type(key) is str:
            if key != "value":
                raise KeyError(key)
            key = slice(None)
        list.__setitem__(self, key, value)

    def __contains__(self, item) -> bool:
        return item == "value" or list.__contains__(self, item)

    def get(self, key, default=None):
        return self if key == "value" else default

    def keys(self) -> tuple[str, ...]:
        return ("value",)

    def values(self) -> tuple[list, ...]:
        return (self,)

    def items(self) -> tuple[tuple[str, list], ...]:
        return (("value", self),)


class Watchers(dict):
    """An object's watchers by parameter, as param keeps them, each parameter's a
    ``ValueWatchers``: the empty dict param puts in for a parameter watched first becomes one."""

    __slots__ = ()

    def __setitem__(self, name, entry) -> None:
        if type(entry) is dict and entry.keys() <= {"value"}:
            entry = ValueWatchers(entry.get("value", ()))
        dict.__setitem__(self, name, entry)


def watchers_in_lists() -> None:
    """Each Parameterized object's watchers kept in ``Watchers`` (see the module)."""
    from param.parameterized import _InstancePrivate

    if getattr(_InstancePrivate.__init__, "lists", False):
        return
    params_own = _InstancePrivate.__init__

    def __init__(self, *args, **kwargs) -> None:
        params_own(self, *args, **kwargs)
        if type(self.watchers) is dict:
            self.watchers = Watchers(self.watchers)

    __init__.lists = True  # type: ignore[attr-defined]
    __init__.param = params_own  # type: ignore[attr-defined]
    _InstancePrivate.__init__ = __init__  # type: ignore[method-assign]
