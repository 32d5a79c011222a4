"""Panel's ``Location`` for a link of any length: what it reads of a page's address.

``pn.state.location`` parses the address's query when the page opens (``panel.util.parse_query``,
Panel 1.4 to 1.9 at least): a value of digits with ``int()``, which refuses one of more than 4,300
digits (``?h=999…``: the page died with no readout), and a value starting with ``[`` or ``{`` with
``json.loads`` or ``ast.literal_eval``, which a deep one drives out of the stack. The explorer reads
its link itself (``Explorer``, from the session's arguments) and only writes the address through
``Location``; so here such a value stays the text it was, and every other value is read as Panel
reads it.
"""

from __future__ import annotations

from typing import Any
from urllib.parse import parse_qsl, urlencode

LONGEST_PARSED = 300  # [characters] a longer value stays text


def link_values_read_safely() -> None:
    """Panel's ``Location`` parses a link's query with ``safe_parse_query`` (a second call does
    nothing). Raises ``AttributeError`` if Panel no longer reads the query through
    ``panel.io.location.parse_query`` (tests/app/test_text_is_text.py holds it)."""
    from panel.io import location

    if getattr(location.parse_query, "safe", False):
        return
    panels = location.parse_query  # AttributeError: the patched name is gone

    def safe_parse_query(query: str) -> dict[str, Any]:
        """Panel's ``parse_query``, but a long value or a bracketed one stays text."""
        last = dict(parse_qsl(query[1:]))  # a key's last value wins, as in Panel's
        rest = {key: value for key, value in last.items() if not _kept_as_text(value)}
        parsed = panels("?" + urlencode(rest)) if rest else {}
        return {
            key: value if _kept_as_text(value) else parsed[key]
            for key, value in last.items()
            if _kept_as_text(value) or key in parsed
        }

    safe_parse_query.safe = True  # type: ignore[attr-defined]
    location.parse_query = safe_parse_query


def _kept_as_text(value: str) -> bool:
    return len(value) > LONGEST_PARSED or value.startswith(("[", "{"))
