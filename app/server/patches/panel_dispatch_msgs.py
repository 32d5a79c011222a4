"""A page's changes queued while it sent are sent, not stranded
(``panel.io.document._dispatch_msgs``).

Made for panel 1.9.4 (applied on panel 1.9 only): it wraps the coroutine ``_dispatch_msgs(doc)``
and reads ``_WRITE_MSGS``, ``_WRITE_BLOCK`` and ``_dispatch_write_task(doc, func, *args, **kwargs)``;
``tests/app/test_app_patches.py`` fails when those change shape.
"""

from __future__ import annotations


def writes_not_stranded() -> None:
    """Panel (1.9) sends a page's changes made while its socket is busy a little later, from a
    task (``panel.io.document._dispatch_msgs``), the page's writes blocked meanwhile. A task
    that finishes sending unblocks the page even when more changes were queued while it sent;
    the task queued for those then finds the page unblocked and returns, and they wait for the
    page's next change. A thread's answer drawn on a page just after a move's (the Design
    map's mark and readout, its work back while the move's patch was being written) did not
    reach the browser (a browser test's tap, 1 run in 4 to 10). Here a task that leaves
    changes queued and the page unblocked sends them."""
    import panel
    from panel.io import document as documents

    dispatch = documents._dispatch_msgs
    if getattr(dispatch, "not_stranded", False) or not panel.__version__.startswith("1.9."):
        return

    async def _dispatch_msgs(doc) -> None:
        await dispatch(doc)
        if doc in documents._WRITE_MSGS and doc not in documents._WRITE_BLOCK:
            documents._WRITE_BLOCK[doc] = True  # queued while it sent: sent now
            documents._dispatch_write_task(doc, _dispatch_msgs, doc)

    _dispatch_msgs.not_stranded = True  # type: ignore[attr-defined]
    _dispatch_msgs.panel = dispatch  # type: ignore[attr-defined]
    documents._dispatch_msgs = _dispatch_msgs
