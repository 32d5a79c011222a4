"""What the server writes in its terminal when a page closes mid-write (server.watch)."""

from __future__ import annotations

import asyncio
import gc
import logging

import pytest
from tornado.websocket import WebSocketClosedError

from windpump_app.server.watch import quiet_closed_pages


def unretrieved_task_fails_with(error: Exception, caplog, quiet: bool) -> list[logging.LogRecord]:
    """A task on a fresh loop that fails with ``error`` and that nothing awaits (as tornado's
    write to a closed page), collected: what asyncio and the app logged meanwhile."""

    async def write() -> None:
        raise error

    loop = asyncio.new_event_loop()
    try:
        if quiet:
            quiet_closed_pages(loop)
        task = loop.create_task(write())
        loop.run_until_complete(asyncio.sleep(0.01))
        assert task.done()
        caplog.clear()
        # the app's logger has its own level (INFO, server.hooks): DEBUG asked of it too
        with caplog.at_level(logging.DEBUG), caplog.at_level(logging.DEBUG, logger="windpump.app"):
            del task
            gc.collect()  # asyncio reports a failed task nobody asked at its collection
        return list(caplog.records)
    finally:
        loop.close()


def test_a_page_closed_mid_write_is_one_debug_line_not_a_traceback(caplog):
    records = unretrieved_task_fails_with(WebSocketClosedError(), caplog, quiet=True)
    assert [(r.name, r.levelno) for r in records] == [("windpump.app", logging.DEBUG)]
    # without it, asyncio's own handler: an error with the traceback (the terminal a user saw)
    records = unretrieved_task_fails_with(WebSocketClosedError(), caplog, quiet=False)
    assert any(
        r.name == "asyncio" and r.levelno == logging.ERROR and r.exc_info for r in records
    ), records


@pytest.mark.parametrize("error", [RuntimeError("a bug"), ConnectionResetError()])
def test_every_other_failure_still_reaches_asyncios_handler(error, caplog):
    records = unretrieved_task_fails_with(error, caplog, quiet=True)
    assert any(r.name == "asyncio" and r.levelno == logging.ERROR for r in records), records
