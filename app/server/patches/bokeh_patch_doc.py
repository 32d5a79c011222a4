"""Bokeh's PATCH-DOC message made without listing every model of its document first
(``bokeh.protocol.messages.patch_doc.patch_doc.create``, with ``SyncedSerializer``, a
``bokeh.core.serialization.Serializer``).

Made for bokeh 3.9.2 (applied on bokeh 3.9 only): it replaces the classmethod ``create(events,
**metadata)`` and relies on ``Serializer.__init__(*, references=..., deferred=...)``,
``DocumentModelManager.flush_synced(is_still_new)``, ``_models`` and ``_new_models``;
``tests/app/test_app_patches.py`` fails when those change shape.
"""

from __future__ import annotations

from typing import Any


def lighter_patches() -> None:
    """Bokeh (3.9) starts every PATCH-DOC message by listing every model of its document and
    making each one's reference (``Serializer(references=doc.models.synced_references)``): ~600
    models a page here, for a message that changes one readout. Measured with py-spy while 30
    students moved at once, it was a fifth of the server's event loop. Here a model's reference
    is made when the message meets it (``SyncedSerializer``); the message is the same."""
    import bokeh
    from bokeh.document.json import PatchJson
    from bokeh.protocol.messages.patch_doc import patch_doc

    # It reaches into Bokeh's document internals: only on the Bokeh it was checked against.
    if getattr(patch_doc.create, "lighter", False) or not bokeh.__version__.startswith("3.9."):
        return

    def create(cls, events, **metadata):
        if not events:
            raise ValueError("PATCH-DOC message requires at least one event")
        docs = {event.document for event in events}
        if len(docs) != 1:
            raise ValueError("PATCH-DOC message configured with events for more than one document")
        [doc] = docs
        serializer = SyncedSerializer(doc.models)
        patch_json = PatchJson(events=serializer.encode(events))
        doc.models.flush_synced(lambda model: not serializer.has_ref(model))
        message = cls(cls.create_header(), metadata, patch_json)
        message.add_buffers(*serializer.buffers)
        return message

    create.lighter = True  # type: ignore[attr-defined]
    create.bokeh = patch_doc.create  # type: ignore[attr-defined]
    patch_doc.create = classmethod(create)  # type: ignore[method-assign,assignment]


def _serializer_class():
    from bokeh.core.serialization import Serializer
    from bokeh.model import Model

    class SyncedSerializer(Serializer):
        """Bokeh's serializer, knowing the synced models of a document (those the browser has)
        as it meets them rather than all of them beforehand."""

        def __init__(self, models) -> None:
            super().__init__()
            self._models = models  # the document's DocumentModelManager

        def _synced(self, obj: Any) -> bool:
            if id(obj) in self._references:
                return True
            models = self._models
            if (
                isinstance(obj, Model)
                and models._models.get(obj.id) is obj
                and obj not in models._new_models
            ):
                self._references[id(obj)] = obj.ref
                return True
            return False

        def has_ref(self, obj: Any) -> bool:
            return self._synced(obj)

        def get_ref(self, obj: Any):
            return self._references[id(obj)] if self._synced(obj) else None

    return SyncedSerializer


SyncedSerializer = _serializer_class()
