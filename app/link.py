"""The page's link: the URL query it opens from, and the query it keeps in step with its state."""

from __future__ import annotations

from urllib.parse import urlencode

from .inputs import clipped

MAX_NOTICES = 5  # the link's ignored values listed; the rest counted
MAX_QUERY = 64 * 1024  # [characters] a longer link's parameters are ignored (app_hooks.py)


def readable(query: dict) -> tuple[dict, list[str]]:
    """``query``, or nothing and a notice if it is longer than MAX_QUERY characters (a link of
    this page is a few hundred)."""
    size = sum(len(key) + sum(len(v) + 2 for v in _listed(raw)) for key, raw in query.items())
    if size <= MAX_QUERY:
        return query, []
    return {}, [
        f"The link was too long ({size / 1024:.0f} KB; at most {MAX_QUERY // 1024} KB): "
        "its parameters were ignored."
    ]


def utf8_keys(query: dict) -> dict:
    """Tornado's query arguments (``pn.state.session_args``) with their keys read as UTF-8:
    Tornado decodes a key's bytes as Latin-1 (its values stay bytes), so ``?café=1`` came as
    ``cafÃ©``. A key that is not UTF-8 stays as Tornado gave it.

    >>> utf8_keys({"cafÃ©": [b"1"], "h": [b"3"]})
    {'café': [b'1'], 'h': [b'3']}
    """
    return {_utf8(key): raw for key, raw in query.items()}


def _utf8(key: str) -> str:
    try:
        return key.encode("latin-1").decode("utf-8")
    except UnicodeError:
        return key


def _listed(raw) -> list:
    return list(raw) if isinstance(raw, list | tuple) else [raw]


def text(raw) -> str:
    """A query value as text (the last one, if it is given several times)."""
    raw = raw[-1] if isinstance(raw, list | tuple) and raw else raw
    return raw.decode("utf-8", "replace") if isinstance(raw, bytes) else str(raw or "")


def flag_from(query: dict, key: str, name: str, notices: list[str]) -> bool | None:
    """A flag of the page, ``?key=true`` or ``false``; None: not given, or ignored with a notice
    naming it (``name``, as the page calls it) and what it takes."""
    raw = text(query.get(key, [b""]))
    if raw in ("true", "false"):
        return raw == "true"
    if raw:
        notices.append(f"{name} ({key}) = “{clipped(raw)}” ignored: true or false.")
    return None


def presentation_from(query: dict, notices: list[str]) -> bool | None:
    """``?presentation=true`` opens the page in presentation mode (kept in the link, so the
    theme switch, which reloads the page, keeps it too); None: not given, or ignored."""
    return flag_from(query, "presentation", "Presentation mode", notices)


def embed_from(query: dict, notices: list[str]) -> bool:
    """``?embed=true`` opens the page for an iframe in a course page: the controls and the tabs
    without the page's header (``page.EMBED_CSS``); kept in the link, as presentation mode."""
    return bool(flag_from(query, "embed", "Embedded page", notices))


def dark_from(query: dict, notices: list[str]) -> bool:
    """``?theme=dark`` opens the page in the dark theme; ``light`` (or nothing) in the light one;
    any other value is ignored with a notice."""
    raw = text(query.get("theme", [b""]))
    if raw and raw not in ("light", "dark"):
        notices.append(f"Theme (theme) = “{clipped(raw)}” ignored: light or dark.")
    return raw == "dark"


UNITS = ("si", "us")  # ``units=``: the readouts in SI (the default) or US customary units


def units_from(query: dict, notices: list[str]) -> str:
    """``?units=us`` shows the readouts in US customary units (ft, gal/h, gal); ``si`` (or
    nothing) in SI; any other value is ignored with a notice."""
    raw = text(query.get("units", [b""]))
    if raw in UNITS:
        return raw
    if raw:
        notices.append(f"Units (units) = “{clipped(raw)}” ignored: si or us.")
    return "si"


def units_query(units: str) -> str:
    """The link's part for the units shown (none for SI, the default)."""
    return "units=us" if units == "us" else ""


TABS = ("mechanisms", "wind", "map", "site")  # ``tab=``: the tabs after the pump's, in order


def tab_from(query: dict, notices: list[str]) -> int:
    """``?tab=site`` (``mechanisms``, ``wind``, ``map``) opens the page on that tab: its index
    in the tab strip; 0, the pump's tab, when not given or ignored."""
    raw = text(query.get("tab", [b""]))
    if raw in TABS:
        return TABS.index(raw) + 1
    if raw:
        notices.append(f"Tab (tab) = “{clipped(raw)}” ignored: one of {', '.join(TABS)}.")
    return 0


def tab_query(active: int) -> str:
    """The link's part for the tab shown (none for the pump's, the default)."""
    return f"tab={TABS[active - 1]}" if 1 <= active <= len(TABS) else ""


# A page whose connection was lost reopens itself from its link once the server answers again
# (serving.reopen_when_reconnected), with ?restored=true, which this says and the link drops.
RESTORED = (
    "**The connection to the server was lost and is back.** This page was reopened from its "
    "link, which holds its design: nothing to retype."
)


def restored_from(query: dict) -> bool:
    """``?restored=true``: the page was reopened after its connection was lost."""
    return text(query.get("restored", [b""])) == "true"


def notices_text(notices: list[str]) -> str:
    """The link's ignored values, MAX_NOTICES at most (a link may carry thousands)."""
    listed = [f"- {notice}" for notice in notices[:MAX_NOTICES]]
    if len(notices) > MAX_NOTICES:
        listed.append(f"- … and {len(notices) - MAX_NOTICES} more ignored.")
    # a phone shows two lines of the list (styles.NOTICE): more than one notice scrolls
    hint = f' <span class="scroll-hint">({len(listed)}: scroll the list)</span>'
    title = "**Some values in the link were ignored:**" + (hint if len(listed) > 1 else "")
    return title + "\n\n" + "\n".join(listed)


def page_query(
    inputs, presentation: bool, dark: bool, full: bool, *more: str, embed: bool = False
) -> str:
    """The page's query as its link carries it: the inputs that differ from the defaults, each
    as its slider shows it, then ``more`` (a tab's own inputs' query), then presentation mode,
    the dark theme, full resolution and the embedded page if on. Nothing else: a key the page
    ignored is not carried on."""
    page = {"presentation": "true"} if presentation else {}
    if dark:
        page["theme"] = "dark"
    if full:
        page["resolution"] = "full"
    if embed:
        page["embed"] = "true"
    return "&".join(part for part in (inputs.query(), *more, urlencode(page)) if part)


class PageLink:
    """Keeps a served page's address (``pn.state.location``) on ``query()``: written on every
    change (``write``), and written again when the browser reports the address it opened."""

    def __init__(self, location, query):
        self.location = location
        self.query = query
        location.param.watch(self.write, "search")
        self.write()

    def write(self, *_events) -> None:
        query = self.query()
        search = f"?{query}" if query else ""
        if self.location.search != search:
            self.location.search = search

    def write_later(self, *_events) -> None:
        """``write``, served: after the readouts of the moves pending (``DRAW_AFTER_MOVES``), as
        the plots are; a move's answer does not wait for its link (~1 ms of the event loop a
        move, a message of its own). Asked for twice before it runs, it runs once."""
        from .server.api import DRAW_AFTER_MOVES, served_document

        document = served_document()
        if document is None:
            self.write()
        else:
            DRAW_AFTER_MOVES.later(document, self.write)
