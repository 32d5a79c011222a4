"""The documentation offline: its equations' MathJax is the site's own copy, and no page of a
built site loads anything from another host (issue 40).

Nothing heavy is built here: MathJax is copied into a temporary folder as the build copies it
(docs/_ext/offline_math.py), and the built site (docs/_build/html, which CI builds before the
tests) is read when it is there. ``tests/browser/test_docs_offline.py`` opens it in chromium
offline and checks that its equations are typeset.
"""

from __future__ import annotations

import ast
import re
import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import urlsplit

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
BUILT = DOCS / "_build" / "html"

sys.path.insert(0, str(DOCS / "_ext"))
import offline_math  # noqa: E402


def conf_value(name: str):
    """A literal assigned in docs/conf.py, read without running it."""
    for node in ast.parse((DOCS / "conf.py").read_text(encoding="utf-8")).body:
        targets = node.targets if isinstance(node, ast.Assign) else [getattr(node, "target", None)]
        if any(isinstance(t, ast.Name) and t.id == name for t in targets):
            return ast.literal_eval(node.value)
    raise LookupError(name)


def off_site(address: str) -> bool:
    """Whether a browser loading ``address`` from a page of the site would ask another host."""
    parts = urlsplit(address.strip())
    return bool(parts.netloc) or parts.scheme not in ("", "file", "data")


def test_off_site_tells_a_host_from_a_path():
    assert off_site("https://cdn.jsdelivr.net/npm/mathjax@4/tex-mml-chtml.js")
    assert off_site("//fonts.googleapis.com/css?family=Georgia")
    assert off_site("http://localhost:8000/x.js")
    assert not off_site("_static/mathjax/tex-mml-chtml.js")
    assert not off_site("../_static/alabaster.css?v=27fed22d")
    assert not off_site("#kinematics")
    assert not off_site("data:image/png;base64,AAAA")


def test_mathjax_is_the_sites_own_copy(tmp_path):
    """conf.py loads the extension that copies MathJax and points ``mathjax_path`` into ``_static``
    (no host); the copy holds that script and the fonts it draws with (CommonHTML's woff)."""
    assert "offline_math" in conf_value("extensions")
    path = conf_value("mathjax_path")
    assert not off_site(path) and not path.startswith("/")
    script = offline_math.copy_mathjax(tmp_path, path)
    assert script == tmp_path / path and script.stat().st_size > 100_000
    fonts = list((script.parent / "output" / "chtml" / "fonts" / "woff-v2").glob("*.woff"))
    assert len(fonts) >= 20
    assert (script.parent / "input" / "tex" / "extensions" / "boldsymbol.js").is_file()
    assert not list(script.parent.rglob("*svg*"))  # the output the pages never load: left out


@pytest.mark.parametrize("bad", ["https://cdn.jsdelivr.net/npm/mathjax@3/es5/tex-mml-chtml.js",
                                 "/usr/share/mathjax/tex-mml-chtml.js", "mathjax/no-such.js"])  # fmt: skip
def test_a_mathjax_path_outside_the_copy_fails_the_build(tmp_path, bad):
    from sphinx.errors import ExtensionError

    with pytest.raises(ExtensionError, match="mathjax_path"):
        offline_math.copy_mathjax(tmp_path, bad)


class Loaded(HTMLParser):
    """The addresses a page makes the browser load (not its links, which a reader follows)."""

    ATTRIBUTES = {
        "script": ("src",),
        "img": ("src", "srcset"),
        "iframe": ("src",),
        "source": ("src", "srcset"),
        "video": ("src", "poster"),
        "audio": ("src",),
        "embed": ("src",),
        "track": ("src",),
        "object": ("data",),
        "input": ("src",),
    }

    def __init__(self):
        super().__init__()
        self.addresses: list[str] = []

    def handle_starttag(self, tag, attrs):
        values = dict(attrs)
        names: tuple[str, ...] = self.ATTRIBUTES.get(tag, ())
        if tag == "link" and values.get("rel", "") not in ("canonical", "alternate", "author"):
            names = ("href",)  # a stylesheet, an icon, a preload: loaded
        for name in names:
            for value in re.split(r",\s*", values.get(name) or ""):
                if value:
                    self.addresses.append(value.split()[0])
        style = values.get("style") or ""
        self.addresses += re.findall(r"url\(\s*['\"]?([^'\")]+)", style)


def built_pages() -> list[Path]:
    if not (BUILT / "index.html").is_file():
        pytest.skip("the site is not built (python -m sphinx -b html docs docs/_build/html)")
    return sorted(BUILT.rglob("*.html"))


def test_no_built_page_loads_from_another_host():
    pages = built_pages()
    leaving = {}
    for page in pages:
        parser = Loaded()
        parser.feed(page.read_text(encoding="utf-8"))
        assert parser.addresses, page  # every page loads at least its stylesheets
        found = [a for a in parser.addresses if off_site(a)]
        if found:
            leaving[str(page.relative_to(BUILT))] = found
    assert leaving == {}
    for sheet in (BUILT / "_static").rglob("*.css"):
        text = sheet.read_text(encoding="utf-8", errors="replace")
        imports = re.findall(r"@import\s+(?:url\()?\s*['\"]?([^'\")\s;]+)", text)
        urls = re.findall(r"url\(\s*['\"]?([^'\")]+)", text)
        assert [a for a in imports + urls if off_site(a)] == [], sheet


def test_the_built_pages_with_equations_load_the_sites_mathjax():
    pages = built_pages()
    script = BUILT / "_static" / conf_value("mathjax_path")
    assert script.is_file()
    with_math = [p for p in pages if 'class="math' in p.read_text(encoding="utf-8")]
    assert any(p.name == "model.html" for p in with_math)
    for page in with_math:
        parser = Loaded()
        parser.feed(page.read_text(encoding="utf-8"))
        loaded = {(page.parent / a.split("?")[0]).resolve() for a in parser.addresses}
        assert script.resolve() in loaded, page
