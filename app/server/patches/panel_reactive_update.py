"""A component's design worked out only when its stylesheets change
(``panel.reactive.Reactive._update_properties``).

Made for panel 1.9.4 (applied on panel 1.9 only): it replaces ``Reactive._update_properties(self,
*events, doc)``; ``tests/app/test_app_patches.py`` fails when its signature changes.
"""

from __future__ import annotations


def lighter_updates() -> None:
    """Panel (1.9) works out a component's design, its theme's stylesheets read through
    ``param.Path`` parameters that look up the file system, on every change of every component
    (``Reactive._update_properties``), and uses it only when the change is of its stylesheets:
    ~10 % of the event loop while 30 students moved at once (py-spy). Here it is worked out
    only then; what the change sends is the same."""
    import panel
    from panel.reactive import Reactive

    if getattr(Reactive._update_properties, "lighter", False) or not panel.__version__.startswith(
        "1.9."
    ):
        return

    def _update_properties(self, *events, doc):
        changes = {event.name: event.new for event in events}
        if "stylesheets" in changes and self._design:
            params, _ = self._design.params(self, doc)
            if "stylesheets" in params:
                changes["stylesheets"] = params["stylesheets"] + changes["stylesheets"]
        return self._process_param_change(changes)

    _update_properties.lighter = True  # type: ignore[attr-defined]
    _update_properties.panel = Reactive._update_properties  # type: ignore[attr-defined]
    Reactive._update_properties = _update_properties  # type: ignore[method-assign]
