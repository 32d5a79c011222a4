"""Panel's text panes (``panel.pane.base.PaneBase.__init__``), lighter for a page kept in the server's memory while its student idles.

A page here is ~120 Panel components; a hall of 100 keeps 100 pages. Each text pane (HTML,
Markdown, Alert: ~40 a page, the readouts, captions, placeholders, notes) built a ``Row`` of its
own at once (``PaneBase.layout``, Panel 1.9), which Panel uses only to show the pane on its own as
a page's root or to index into it (``pane[0]``), never for a pane placed in a layout as every pane
here is; and it watched all ~25 of the pane's layout parameters to keep that ``Row`` in step. A
Panel component is ~10 kB of a session's memory, most of it param's watchers (a dict and a list for
each parameter watched): the ``Row`` and its watchers were ~0.4 MB of a page
(``benchmarks/bench_page_memory.py``). Here a text pane's ``Row`` is built, and kept in step, the
first time something asks for it: what a page shows and sends is the same.

Made for panel 1.9.4 (applied on panel 1.9 only): it replaces ``PaneBase.__init__(self,
object=None, **params)`` with Panel 1.9.4's body but for the layout, and gives ``HTMLBasePane``
a lazy ``layout`` property; ``tests/app/test_app_patches.py`` fails when that signature changes.
"""

from __future__ import annotations


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
