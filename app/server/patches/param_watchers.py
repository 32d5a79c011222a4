"""param's watchers of a parameter kept in a list alone
(``param.parameterized._InstancePrivate.__init__``), lighter for a page kept in memory.

What param keeps for each parameter watched on a component (``{"value": [watcher, ...]}``: a
dict of one key and a list, ~260 bytes; ~2,000 a page, ~0.5 MB) is kept as the list alone,
which answers as that dict too (``ValueWatchers``): the same watchers, called in the same order.

Made for param 2.4.2 (applied on param 2.4 only): it wraps ``_InstancePrivate.__init__(self,
initialized=False, parameters_state=None, dynamic_watchers=None, refs=None, params=None,
watchers=None, values=None, explicit_no_refs=None)`` and replaces the ``watchers`` dict it made; ``tests/app/test_app_patches.py`` fails when that changes.
"""

from __future__ import annotations


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
