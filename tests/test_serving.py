"""The server-wide order of a class opening the page at once (app/serving.py: ReadoutsFirst)."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "app"))
from serving import ReadoutsFirst  # noqa: E402


class Document:
    """Stands in for a Bokeh document: keeps the timeout callbacks to run them on demand."""

    def __init__(self):
        self.pending = []

    def add_timeout_callback(self, callback, _milliseconds):
        self.pending.append(callback)

    def run_pending(self):
        pending, self.pending = self.pending, []
        for callback in pending:
            callback()


def test_a_page_alone_gets_its_views_at_once():
    order, shown = ReadoutsFirst(), []
    order.opened("a")
    order.loaded("a", Document(), lambda: shown.append("a"))
    assert shown == ["a"]


def test_views_wait_until_every_page_opened_meanwhile_has_loaded():
    order, document, shown = ReadoutsFirst(), Document(), []
    for page in "abc":
        order.opened(page)
    order.loaded("a", document, lambda: shown.append("a"))
    order.loaded("b", document, lambda: shown.append("b"))
    document.run_pending()
    assert shown == [] and order.loading == {"c": order.loading["c"]}
    order.closed("c")  # its page closed before it loaded: it holds nobody back
    document.run_pending()
    assert sorted(shown) == ["a", "b"] and document.pending == []


def test_a_page_waits_no_longer_than_its_patience_nor_for_a_page_that_never_loads():
    impatient, document, shown = ReadoutsFirst(patience=0.0), Document(), []
    impatient.opened("slow")
    impatient.loaded("a", document, lambda: shown.append("a"))
    assert shown == ["a"] and "slow" in impatient.loading
    forgetful = ReadoutsFirst(forget_after=0.0)
    forgetful.opened("never")
    forgetful.loaded("b", document, lambda: shown.append("b"))
    assert shown == ["a", "b"] and forgetful.loading == {}
