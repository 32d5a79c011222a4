"""Every browser test: the pages it opened asked no host but their server for anything (issue 40).

``test_browser.open_page`` records each request a page makes to another host (``page.elsewhere``:
a CDN's font, stylesheet or script); here every test's pages are checked once it has run, so a
module need not remember to. A page the test closed counts too.
"""

from __future__ import annotations

import pytest

from served import OPENED_PAGES


@pytest.fixture(autouse=True)
def nothing_from_another_host():
    OPENED_PAGES.clear()
    yield
    leaving = {page.opened: list(page.elsewhere) for page in OPENED_PAGES if page.elsewhere}
    OPENED_PAGES.clear()
    assert leaving == {}, "pages asked another host than their server"
