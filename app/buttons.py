"""Buttons whose clicks change the page's Bokeh models safely, whatever else is queued."""

from __future__ import annotations

import panel as pn


class ActionButton(pn.widgets.Button):
    """Panel's button, its click handled under the page's document lock.

    A click that arrives while a slider's move is still queued (three arrow keys, then Pin and
    Reset at once) is run by Panel (1.9.4, ``Syncable._server_event``) as a coroutine without the
    lock; a Bokeh model changed there (the pinned run's data) raised Bokeh's "_pending_writes
    should be non-None" and the rest of the action (Reset's inputs) was lost. Panel's
    ``async_execute`` keeps the lock for a callback marked ``lock``.
    """

    async def _event_coroutine(self, doc, event) -> None:
        await super()._event_coroutine(doc, event)

    _event_coroutine.lock = True  # type: ignore[attr-defined]
