"""Text from a link or a file is shown as text, never run nor read as markup (in-process: what
the panes hold, rendered as the browser gets it; tests/browser/test_browser_text.py opens the pages)."""

from __future__ import annotations

import math
from html.parser import HTMLParser
from pathlib import Path

import panel as pn
import pytest
from hypothesis import given
from hypothesis import strategies as st

from windpump_app.escape import CONTROLS, as_text
from windpump_app.explorer import Explorer
from windpump_app.inputs import FORMATS, SWITCHES
from windpump_app.site_inputs import SiteInputs

from panes import collapsed, rendered, shown

# Each payload is short enough to be echoed whole (notices cut at 40 characters).
PAYLOADS = (
    "<script>window.ran=1</script>",
    '<img src=x onerror="window.ran=1">',
    "<svg onload=window.ran=1>",
    '<iframe srcdoc="<b>x</b>">',
    "javascript:window.ran=1",
    "[go](javascript:alert(1))",
    "\"'><b>bold</b>",
    "&lt;script&gt; &amp; &#60;",
    "**strong** _em_ `code`",
    "# heading\n- list\n1. item",
    "www.example.org",
)
# What none of the pages' messages hold of their own: a payload's elements (its list shows in
# the text: a list's bullets would be gone).
FOREIGN_TAGS = {"script", "img", "svg", "iframe", "b", "a", "h1", "code"}


class Markup(HTMLParser):
    """An HTML fragment's foreign elements, event or source attributes, and text."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.foreign, self.text = [], []

    def handle_starttag(self, tag, attrs):
        if tag in FOREIGN_TAGS:
            self.foreign.append(tag)
        for name, value in attrs:
            if name.startswith("on") or name in ("srcdoc", "href", "src"):
                self.foreign.append(f"{tag} {name}={value!r}")

    def handle_data(self, data):
        self.text.append(data)


def read(fragment: str) -> Markup:
    markup = Markup()
    markup.feed(fragment)
    markup.close()
    return markup


def every_pane(root, seen=None) -> list:
    """Every Markdown and HTML pane reachable from ``root``'s attributes (the whole page)."""
    seen = set() if seen is None else seen
    found = []
    if id(root) in seen:
        return found
    seen.add(id(root))
    if isinstance(root, pn.pane.Markdown | pn.pane.HTML):
        found.append(root)
    children = (
        list(root.values())
        if isinstance(root, dict)
        else list(root)
        if isinstance(root, list | tuple)
        else list(vars(root).values())
        if hasattr(root, "__dict__") and type(root).__module__.startswith(("windpump_app", "panel"))
        else []
    )
    for child in children:
        found += every_pane(child, seen)
    return found


def foreign_markup(app) -> list[tuple[str, list[str]]]:
    """Each pane of ``app`` holding a payload's markup, with what it holds."""
    return [
        (str(pane.object)[:120], found)
        for pane in every_pane(app)
        for found in [read(rendered(pane)).foreign]
        if found
    ]


def as_typed(payload: str) -> str:
    """``payload`` as a page shows it: blanks collapsed, control characters replaced."""
    controls = {code: "\ufffd" for code in CONTROLS if chr(code) not in "\t\n\r"}
    return collapsed(payload.translate(controls))


@given(st.text(max_size=200))
def test_any_text_renders_as_itself_in_a_markdown_and_an_html_pane(raw):
    """The property behind every message: ``as_text`` of any text, rendered as the page renders
    its Markdown or its HTML, is one paragraph of that very text (blanks collapsed), and no
    element."""
    for pane in (pn.pane.Markdown(as_text(raw)), pn.pane.HTML(f"<p>{as_text(raw)}</p>")):
        markup = read(rendered(pane))
        assert markup.foreign == []
        assert collapsed("".join(markup.text)) == as_typed(raw)


LINK_KEYS = sorted({*FORMATS, *SWITCHES, *SiteInputs.keys(), "tab", "presentation", "theme"})


@pytest.mark.parametrize("payload", PAYLOADS)
def test_a_link_key_or_value_is_shown_as_typed_in_every_place(payload):
    """The payload as a key, and as the value of every key the page reads (one page for all:
    each value is refused and named in a notice)."""
    raw = payload.encode()
    query = {payload: [b"1"], **{key: [raw] for key in LINK_KEYS}}
    app = Explorer(query=query)
    assert foreign_markup(app) == []
    notices = shown(app.notices)
    assert as_typed(payload) in notices
    assert app.readouts.status.alert_type != "danger"  # the page runs on the defaults


def test_a_value_given_twice_is_shown_as_typed():
    payload = PAYLOADS[1]
    app = Explorer(query={"h": [payload.encode(), b"3"]})
    assert foreign_markup(app) == [] and payload in shown(app.notices)


@pytest.fixture
def app():
    return Explorer()


@pytest.mark.parametrize("payload", PAYLOADS)
def test_a_lab_file_echoed_in_its_refusal_is_text(app, payload):
    line = payload.replace("\n", " ")
    app.sidebar.lab.upload.param.update(value=f"{line},0.5\n".encode(), filename=f"{line}.csv")
    assert app.sidebar.lab.message.visible
    assert foreign_markup(app) == []


@pytest.mark.parametrize("payload", PAYLOADS)
def test_a_wind_file_its_name_and_cells_are_text(app, payload):
    line = payload.replace("\n", " ")
    app.main().active = 2
    app.wind_tab.upload.filename = f"{line}.csv"
    app.load_wind_data(f"t,V\n0,5\n60,{line}\n".encode())
    assert app.wind_tab.upload_message.visible
    assert foreign_markup(app) == []
    rows = "".join(f"{60 * i},{5 + math.sin(i / 5):.3f}\n" for i in range(121))
    app.load_wind_data(f"t [s],V [m/s]\n{rows}".encode())  # a good file under that name
    assert not app.wind_tab.upload_message.visible
    assert foreign_markup(app) == []
    assert as_typed(line) in shown(app.wind_tab.day_note)


def greensboro() -> bytes:
    import pvlib

    return (Path(pvlib.__file__).parent / "data" / "723170TYA.CSV").read_bytes()


@pytest.mark.parametrize("payload", [p for p in PAYLOADS if "," not in p and '"' not in p])
def test_a_weather_file_its_name_cells_and_station_are_text(app, payload):
    line = payload.replace("\n", " ")
    app.main().active = 4
    site = app.site_tab
    site.upload.param.update(value=f"t,V\n0,5\n3600,{line}\n".encode(), filename=f"{line}.csv")
    assert site.upload_message.visible
    assert foreign_markup(app) == []
    header, rest = greensboro().split(b"\n", 1)
    fields = header.split(b",")
    fields[1] = f'"{line}"'.encode()  # the station's name
    site.upload.param.update(value=b",".join(fields) + b"\n" + rest, filename=f"{line}.csv")
    assert not site.upload_message.visible, site.upload_message.object
    assert foreign_markup(app) == []
    assert as_typed(line) in shown(site.note)


def test_a_link_value_of_any_length_is_read_by_panels_location_as_text():
    """Panel's Location read ``?h=9…9`` (5,000 digits) with int() and the page died; a deep
    bracketed value went to ast.literal_eval. Patched, both stay text, and others read as
    Panel reads them."""
    from panel.io import location
    from panel.util import parse_query

    from windpump_app.link_values import link_values_read_safely

    link_values_read_safely()
    assert getattr(location.parse_query, "safe", False)  # Panel still reads the link there
    digits, deep = "9" * 5_000, "[" * 100_000
    page = location.Location(search=f"?h={digits}&x={deep}&a=1&b=2.5&c=[1,2]&d=true&a=3")
    assert page.query_params == {"h": digits, "x": deep, "a": 3, "b": 2.5, "c": "[1,2]", "d": True}
    assert parse_query("?a=1&b=2.5&d=true&e=x") == location.parse_query("?a=1&b=2.5&d=true&e=x")


@pytest.mark.parametrize("value", ["9" * 5_000, "-" + "1" * 5_000, "1e" + "9" * 400, "[" * 5_000])
def test_a_link_value_of_any_length_is_named_in_a_notice(value):
    app = Explorer(query={"h": [value.encode()], value: [b"1"]})
    notices = shown(app.notices)
    assert "Head h [m] (h) =" in notices and "is not a parameter of this page" in notices
    assert app.inputs.h == 3.0 and app.readouts.status.alert_type != "danger"


@pytest.mark.parametrize(
    "module", ["escape", "link", "server.policy", "readouts", "site_figures", "map_tab"]
)
def test_the_examples_in_the_docstrings_hold(module):
    """The app's folder is not collected for doctests (its main.py is the page's script)."""
    import doctest
    import importlib

    failed, tried = doctest.testmod(importlib.import_module(f"windpump_app.{module}"))
    assert tried > 0 and failed == 0


def test_a_unicode_link_key_is_named_as_typed():
    """Tornado gives a query's keys decoded as Latin-1 (``cafÃ©``); the page reads them as UTF-8."""
    from windpump_app.link import utf8_keys

    tornado = {"café".encode().decode("latin-1"): [b"1"], "h": [b"3"]}
    app = Explorer(query=utf8_keys(tornado))
    assert "“café” is not a parameter of this page" in shown(app.notices)


# Unicode's bidirectional formatting characters (embeddings, overrides, isolates, marks): in an
# echoed value, U+202E reversed the rest of the notice's line on screen ("?h=%E2%80%AEfdp.exe"
# showed "“exe.pdf” ignored: ..." as ".03 ot 0 morf rebmun a eb tsum ti :derongi ”exe.pdf").
BIDI = "\u061c\u200e\u200f\u202a\u202b\u202c\u202d\u202e\u2066\u2067\u2068\u2069"


@pytest.mark.parametrize("mark", BIDI)
def test_a_bidi_control_in_a_value_cannot_reorder_the_notice_around_it(mark):
    app = Explorer(query={"h": [f"{mark}fdp.exe".encode()]})
    notices = shown(app.notices)
    assert "“\ufffdfdp.exe” ignored" in notices
    assert not set(BIDI) & set(app.notices.object)
